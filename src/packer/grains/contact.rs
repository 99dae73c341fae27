//! Where a particle that is not a disk may go: its distance to each
//! obstacle (another particle, a straight wall, a circular wall), the
//! centres at which it touches two obstacles (Newton on the two distances),
//! the centre at which it touches one (bisection along a line), and
//! whether a centre is clear of everything.
//!
//! # Two contacts
//! With the orientations fixed, the distance from the new particle N at
//! centre p to a convex obstacle A is the distance from p to the convex set
//! A ⊕ (−N), a convex function of p whose gradient is the unit direction
//! GJK ends on ([`separation`]). The centres touching A and B at a gap ε
//! solve f_A(p) = f_B(p) = ε: Newton's step on the two linearised rows.
//! Started outside both sets (at the crossing of the bounding circles'
//! halos, which are clear of A and B), a convex function's linearisation
//! is below it, so no step enters a set: every iterate stays clear of A and
//! B and the converged centre is certified apart from both by the lower
//! bounds of its last evaluation (gap within [ε/2, 3ε/2]).

use nalgebra::Vector2;

use super::Body;
use crate::geometry::{Outline, Point, apart, separation_from};

/// Gap between touching particles, relative to the new particle's reach:
/// far below the contact tolerance of the metrics, far above rounding.
pub(super) const GAP_REL: f64 = 1e-9;

/// How near a coarse two-contact solve comes, relative to the reach.
pub(super) const COARSE_REL: f64 = 1e-4;

/// Newton iterations of one two-contact solve.
const NEWTON_ITERATIONS: usize = 30;

/// Bisection steps of a one-contact placement (or a slide to a wall).
const BISECTIONS: usize = 48;

/// The particle being placed: its outline turned, its reach (circumradius)
/// and the radius of a disk about its centre inside it.
pub(super) struct Newcomer<'a> {
    pub outline: &'a Outline,
    pub cos: f64,
    pub sin: f64,
    pub reach: f64,
    pub inner: f64,
    /// Taken off every support value: 0 for the particle itself; a small
    /// positive value gives a slightly eroded particle, for a test that
    /// forgives a coarse centre (never for a placement).
    pub slack: f64,
}

impl Newcomer<'_> {
    /// Support value and point (about the centre) in world direction `u`.
    #[inline]
    pub fn support(&self, u: Vector2<f64>) -> (f64, Vector2<f64>) {
        let (h, p) = support_turned(self.outline, self.cos, self.sin, u);
        (h - self.slack, p)
    }
}

/// Support of `outline` turned by (cos, sin), in world direction `u`.
#[inline]
pub(super) fn support_turned(
    outline: &Outline,
    cos: f64,
    sin: f64,
    u: Vector2<f64>,
) -> (f64, Vector2<f64>) {
    let local = Vector2::new(cos * u.x + sin * u.y, -sin * u.x + cos * u.y);
    let (h, p) = outline.support_both(local);
    (
        h,
        Vector2::new(cos * p.x - sin * p.y, sin * p.x + cos * p.y),
    )
}

/// An obstacle a particle may touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Obstacle {
    /// Placed particle `id`, met at its image shifted by the vector (a
    /// periodic cell's lattice shift; zero with walls).
    Body(u32, Vector2<f64>),
    /// Straight wall from `a` to `b` (the domain on its left).
    Segment(Point, Point),
    /// Circular wall: the domain is inside.
    Circle(Point, f64),
}

/// The new particle's signed clearance from `ob` at centre `p` (a certified
/// lower bound of the distance for particles and straight walls; positive
/// when apart) and its gradient in `p`. `tol` bounds the error of the value.
/// `guess` is the gradient of a nearby call (zero: none).
pub(super) fn clearance(
    bodies: &[Body],
    ob: &Obstacle,
    new: &Newcomer,
    p: Point,
    tol: f64,
    guess: Vector2<f64>,
) -> (f64, Vector2<f64>) {
    match *ob {
        Obstacle::Body(id, shift) => {
            let b = &bodies[id as usize];
            let d = p - (b.c + shift);
            let s = separation_from(d, guess, tol, |u| {
                let (hb, pb) = b.support(u);
                let (hn, pn) = new.support(-u);
                (hb + hn, pb - pn)
            });
            (s.lower, s.dir)
        }
        Obstacle::Segment(a, b) => {
            let s = separation_from(p.coords, guess, tol, |u| segment_minus(a, b, new, u));
            (s.lower, s.dir)
        }
        Obstacle::Circle(o, radius) => {
            let (far, u) = farthest(new, p - o);
            (radius - far, -u)
        }
    }
}

/// Support of the segment ab grown by −N, in direction `u`.
#[inline]
fn segment_minus(a: Point, b: Point, new: &Newcomer, u: Vector2<f64>) -> (f64, Vector2<f64>) {
    let (ha, hb) = (u.dot(&a.coords), u.dot(&b.coords));
    let (hs, ps) = if ha >= hb {
        (ha, a.coords)
    } else {
        (hb, b.coords)
    };
    let (hn, pn) = new.support(-u);
    (hs + hn, ps - pn)
}

/// Whether the new particle at `p` is certainly clear of `ob`.
pub(super) fn clear_of(bodies: &[Body], ob: &Obstacle, new: &Newcomer, p: Point) -> bool {
    match *ob {
        Obstacle::Body(id, shift) => {
            let b = &bodies[id as usize];
            let d = p - (b.c + shift);
            let n2 = d.norm_squared();
            let far = b.reach + new.reach;
            if n2 >= far * far {
                return true;
            }
            let near = b.inner + new.inner;
            if n2 < near * near {
                return false;
            }
            apart(d, |u| {
                let (hb, pb) = b.support(u);
                let (hn, pn) = new.support(-u);
                (hb + hn, pb - pn)
            })
        }
        Obstacle::Segment(a, b) => {
            let dist = point_segment_distance(p, a, b);
            if dist >= new.reach {
                return true;
            }
            if dist < new.inner {
                return false;
            }
            apart(p.coords, |u| segment_minus(a, b, new, u))
        }
        Obstacle::Circle(o, radius) => {
            let v = p - o;
            if v.norm() + new.reach <= radius {
                return true;
            }
            let (far, _) = farthest(new, v);
            // The fixed point is a local maximum: keep a margin for the
            // rounding of its direction (the check certifies containment
            // with a tangent polygon).
            far <= radius - GAP_REL * new.reach * 0.5
        }
    }
}

/// Distance from the origin to the farthest point of the new particle
/// centred at `v`, max over u of u·v + h(u), and the maximising direction.
///
/// # Behavior
/// A polygon's farthest point is a corner (plus the rounding): exact. A
/// superellipse's is a fixed point u = (v + s(u)) / |v + s(u)|, found from
/// five starts (towards `v` and along both own axes, both ways) and the
/// largest kept: the tips of an elongated particle are separate local
/// maxima, and the one a single start reaches may not be the farthest.
fn farthest(new: &Newcomer, v: Vector2<f64>) -> (f64, Vector2<f64>) {
    if let Outline::Polygon {
        vertices, rounding, ..
    } = new.outline
    {
        let mut best = (f64::NEG_INFINITY, Vector2::new(0.0, -1.0));
        for p in vertices.iter() {
            let w = v + Vector2::new(new.cos * p.x - new.sin * p.y, new.sin * p.x + new.cos * p.y);
            let n = w.norm();
            if n > best.0 {
                best = (n, if n > 0.0 { w / n } else { best.1 });
            }
        }
        return (best.0 + rounding - new.slack, best.1);
    }
    let n = v.norm();
    let (c, s) = (new.cos, new.sin);
    let starts = [
        if n > 0.0 {
            v / n
        } else {
            Vector2::new(0.0, -1.0)
        },
        Vector2::new(c, s),
        Vector2::new(-c, -s),
        Vector2::new(-s, c),
        Vector2::new(s, -c),
    ];
    let mut best = (f64::NEG_INFINITY, starts[0]);
    for start in starts {
        let mut u = start;
        for _ in 0..40 {
            let (h, sp) = new.support(u);
            let value = u.dot(&v) + h;
            if value > best.0 {
                best = (value, u);
            }
            let x = v + sp;
            let next = x / x.norm();
            if (next - u).norm_squared() < 1e-30 {
                break;
            }
            u = next;
        }
    }
    best
}

/// Distance from `p` to the segment ab.
pub(super) fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let e = b - a;
    let l2 = e.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + e * t)).norm()
}

/// Centres at which the new particle's bounding circle touches the
/// bounding circle of `front` (centre `cf`, reach `rf`) and `ob`: the
/// starts of the two-contact solve.
pub(super) fn starts(
    bodies: &[Body],
    cf: Point,
    rf: f64,
    ob: &Obstacle,
    new: &Newcomer,
    out: &mut Vec<Point>,
) {
    let r1 = rf + new.reach;
    match *ob {
        Obstacle::Body(id, shift) => {
            let b = &bodies[id as usize];
            circle_circle(cf, r1, b.c + shift, b.reach + new.reach, out);
        }
        Obstacle::Segment(a, b) => {
            let e = b - a;
            let len = e.norm();
            if len == 0.0 {
                return;
            }
            let u = e / len;
            let inward = Vector2::new(-u.y, u.x);
            let q = a + inward * new.reach;
            // The line q + t·u against the circle (cf, r1).
            let w = cf - q;
            let t0 = w.dot(&u);
            let cross = w.x * u.y - w.y * u.x;
            let h2 = r1 * r1 - cross * cross;
            if h2 < 0.0 {
                return;
            }
            let h = h2.sqrt();
            for t in [t0 - h, t0 + h] {
                if t >= -new.reach && t <= len + new.reach {
                    out.push(q + u * t);
                }
            }
        }
        Obstacle::Circle(o, radius) => {
            if radius > new.reach {
                circle_circle(cf, r1, o, radius - new.reach, out);
            }
        }
    }
}

/// The crossings of two circles (none when apart or nested).
fn circle_circle(c1: Point, r1: f64, c2: Point, r2: f64, out: &mut Vec<Point>) {
    let d = c2 - c1;
    let d2 = d.norm_squared();
    if d2 == 0.0 {
        return;
    }
    let a = (r1 * r1 - r2 * r2 + d2) / (2.0 * d2);
    let h2 = r1 * r1 / d2 - a * a;
    if h2 < 0.0 {
        return;
    }
    let h = h2.sqrt();
    let m = c1 + d * a;
    let perp = Vector2::new(-d.y, d.x) * h;
    out.push(m + perp);
    out.push(m - perp);
}

/// The centre near `start` at which the new particle touches both `a` and
/// `b` at the gap ε = [`GAP_REL`]·reach, or `None` when Newton does not
/// settle (the obstacles' contact curves do not cross near there, or cross
/// at a grazing angle). Counts its distance evaluations in `work`.
///
/// With `coarse`, it stops as soon as both gaps are within
/// [`COARSE_REL`]·reach of ε (a few iterations fewer): good enough to
/// rank a candidate and to reject it when another particle blocks it, and
/// a start from which the fine solve takes one or two steps.
#[allow(clippy::too_many_arguments)]
pub(super) fn two_contact(
    bodies: &[Body],
    a: &Obstacle,
    b: &Obstacle,
    new: &Newcomer,
    start: Point,
    coarse: bool,
    work: &mut u64,
) -> Option<Point> {
    let eps = GAP_REL * new.reach;
    let mut p = start;
    let (mut ga, mut gb) = (Vector2::zeros(), Vector2::zeros());
    // The distances need only be as accurate as the step they make.
    let mut tol = if coarse { 1e-3 } else { 1e-2 * COARSE_REL } * new.reach;
    let mut last = f64::INFINITY;
    for i in 0..NEWTON_ITERATIONS {
        let (fa, da) = clearance(bodies, a, new, p, tol, ga);
        let (fb, db) = clearance(bodies, b, new, p, tol, gb);
        (ga, gb) = (da, db);
        *work += 2;
        let (ra, rb) = (fa - eps, fb - eps);
        let residual = ra.abs().max(rb.abs());
        if coarse && residual <= COARSE_REL * new.reach {
            return Some(p);
        }
        if residual <= 0.5 * eps {
            if tol <= 0.05 * eps {
                return Some(p);
            }
            // Converged on rough distances: measure them finely here.
            tol = 0.05 * eps;
            continue;
        }
        // Newton halves the residual at least once it is near a crossing;
        // one that stalls is looking for a crossing that is not there.
        if i >= 3 && residual > 0.5 * last && residual > eps {
            return None;
        }
        last = residual;
        tol = (0.01 * residual).clamp(0.05 * eps, tol);
        let det = ga.x * gb.y - ga.y * gb.x;
        if det.abs() < 1e-6 {
            return None;
        }
        let mut step = Vector2::new(
            (-ra * gb.y + rb * ga.y) / det,
            (-rb * ga.x + ra * gb.x) / det,
        );
        let len = step.norm();
        if !len.is_finite() {
            return None;
        }
        if len > new.reach {
            step *= new.reach / len;
        }
        p += step;
    }
    None
}

/// The centre nearest `to` on the segment from `from` (clear of `a` and
/// `b`) towards `to` at which the new particle still clears both: it then
/// touches one of them (the one-contact construction, by bisection).
/// `None` when `from` itself is not clear.
pub(super) fn slide(
    bodies: &[Body],
    a: &Obstacle,
    b: Option<&Obstacle>,
    new: &Newcomer,
    from: Point,
    to: Point,
    work: &mut u64,
) -> Option<Point> {
    let clear = |p: Point, work: &mut u64| {
        *work += 2;
        clear_of(bodies, a, new, p) && b.is_none_or(|b| clear_of(bodies, b, new, p))
    };
    if !clear(from, work) {
        return None;
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let at = |t: f64| from + (to - from) * t;
    if clear(at(1.0), work) {
        return Some(at(1.0));
    }
    let resolution = GAP_REL * new.reach / (to - from).norm().max(f64::MIN_POSITIVE);
    for _ in 0..BISECTIONS {
        if hi - lo <= resolution {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if clear(at(mid), work) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(at(lo))
}
