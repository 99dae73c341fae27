//! Where a particle that is not a disk may go: its distance to each
//! obstacle (another particle, a straight wall, a circular wall), the
//! centres at which it touches two obstacles (Newton on the two distances),
//! the centre at which it touches one (bisection along a line), and
//! whether a centre is clear of everything.
//!
//! # Two contacts
//! Superellipses with α = β ≤ 6 (ellipses among them) are solved on their
//! contact curves ([`two_contact_smooth`]): each is traced by support
//! points as the contact normal turns, and Newton on the two normals'
//! angles meets them in a few steps (the front solves only the crossings
//! its screen finds, `screen`). Other outlines (polygons, rhombi, α ≠ β,
//! flatter sides) are solved on distances, as follows.
//!
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
use super::screen::Sampled;
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
    /// Its way into the screen's tables (`None`: not screened).
    pub sampled: Option<Sampled>,
}

impl Newcomer<'_> {
    /// Support value, point (about the centre) and radius of curvature in
    /// the unit world direction `u`, for a smoothly turning outline.
    #[inline]
    pub fn curved(&self, u: Vector2<f64>) -> Option<(f64, Vector2<f64>, f64)> {
        let (h, p, rho) = curved_turned(self.outline, self.cos, self.sin, u)?;
        Some((h - self.slack, p, rho))
    }

    /// Support value and point (about the centre) in world direction `u`.
    #[inline]
    pub fn support(&self, u: Vector2<f64>) -> (f64, Vector2<f64>) {
        let (h, p) = support_turned(self.outline, self.cos, self.sin, u);
        (h - self.slack, p)
    }
}

/// Support value, point (world axes, about the centre) and radius of
/// curvature of `outline` turned by (cos, sin) in the unit world direction
/// `u`; `None` for outlines whose support point does not turn smoothly.
#[inline]
pub(super) fn curved_turned(
    outline: &Outline,
    cos: f64,
    sin: f64,
    u: Vector2<f64>,
) -> Option<(f64, Vector2<f64>, f64)> {
    let local = Vector2::new(cos * u.x + sin * u.y, -sin * u.x + cos * u.y);
    let (h, p, rho) = outline.support_curved(local)?;
    Some((
        h,
        Vector2::new(cos * p.x - sin * p.y, sin * p.x + cos * p.y),
        rho,
    ))
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

/// What [`two_contact_smooth`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Smooth {
    /// A centre touching both obstacles at a gap certified within
    /// [ε/2, 3ε/2].
    Found(Point),
    /// No crossing of the two contact curves near the start.
    Missing,
    /// An outline whose support point does not turn smoothly (a polygon,
    /// a rhombus, α ≠ β), or a contact at a straight wall's end: solve with
    /// [`two_contact`] instead.
    Unsuited,
}

/// Newton iterations of one smooth two-contact solve.
const SMOOTH_ITERATIONS: usize = 12;

/// Halvings of one damped Newton step before the solve gives up.
const BACKTRACKS: usize = 4;

/// The curve of centres at which the new particle touches an obstacle at
/// the gap ε, and its certificate. A curve's parameter is a vector: the
/// unit contact normal u for a particle or a circular wall (a step δ turns
/// it to (u + δ·u′)/|u + δ·u′|, no trigonometry), (t, 0) along a wall.
enum Curve<'a> {
    /// A placed particle at `c`: C(u) = c + s_A(u) − s_N(−u) + ε·u, moving
    /// by (ρ_A(u) + ρ_N(−u) + ε)·u′ as u turns.
    Body { c: Point, body: &'a Body },
    /// A straight wall through `a` along the unit `e`, the domain on the
    /// side `inward`: C(t) = a + t·e + (h_N(−inward) + ε)·inward.
    Line {
        a: Point,
        e: Vector2<f64>,
        len: f64,
        inward: Vector2<f64>,
        offset: f64,
    },
    /// A circular wall: C(u) = o + (R − ε)·u − s_N(u), moving by
    /// (R − ε − ρ_N(u))·u′.
    Circle { o: Point, radius: f64 },
}

/// Largest exponent the smooth solve takes: flatter sides turn the support
/// point so sharply with the normal that Newton on its angle backtracks
/// more than GJK costs (measured: α = β = 10 packs 1.8 times slower by the
/// smooth solve, α = 4 1.6 times faster, ellipses 7 times).
const SMOOTH_MAX_EXPONENT: f64 = 6.0;

/// Whether `outline` is solved by Newton on the contact normal's angle.
pub(super) fn newton_friendly(outline: &Outline) -> bool {
    matches!(*outline, Outline::Superellipse { alpha, beta, .. }
        if alpha == beta && alpha > 1.0 && alpha <= SMOOTH_MAX_EXPONENT)
}

/// The unit vector of `v` (the x axis for a zero vector).
#[inline]
fn unit(v: Vector2<f64>) -> Vector2<f64> {
    let n = v.norm();
    if n > 0.0 {
        v / n
    } else {
        Vector2::new(1.0, 0.0)
    }
}

impl<'a> Curve<'a> {
    /// The curve of `ob`, and the parameter of the point nearest `start`.
    fn of(
        bodies: &'a [Body],
        ob: &Obstacle,
        new: &Newcomer,
        start: Point,
    ) -> Option<(Self, Vector2<f64>)> {
        if !newton_friendly(new.outline) {
            return None;
        }
        Some(match *ob {
            Obstacle::Body(id, shift) => {
                let body = &bodies[id as usize];
                if !newton_friendly(&body.outline) {
                    return None;
                }
                let c = body.c + shift;
                (Curve::Body { c, body }, unit(start - c))
            }
            Obstacle::Segment(a, b) => {
                let len = (b - a).norm();
                if len == 0.0 {
                    return None;
                }
                let e = (b - a) / len;
                let inward = Vector2::new(-e.y, e.x);
                let (h, _, _) = new.curved(-inward)?;
                let offset = h + GAP_REL * new.reach;
                (
                    Curve::Line {
                        a,
                        e,
                        len,
                        inward,
                        offset,
                    },
                    Vector2::new((start - a).dot(&e), 0.0),
                )
            }
            Obstacle::Circle(o, radius) => (Curve::Circle { o, radius }, unit(start - o)),
        })
    }

    /// The parameter `t` moved by `step` (at most `max` for an angle).
    #[inline]
    fn advance(&self, t: Vector2<f64>, step: f64, reach: f64) -> Vector2<f64> {
        match self {
            Curve::Line { .. } => Vector2::new(t.x + step.clamp(-reach, reach), 0.0),
            _ => {
                let step = step.clamp(-0.5, 0.5);
                unit(t + Vector2::new(-t.y, t.x) * step)
            }
        }
    }

    /// The point at parameter `t` and its derivative there.
    #[inline]
    fn at(&self, new: &Newcomer, t: Vector2<f64>) -> Option<(Point, Vector2<f64>)> {
        let eps = GAP_REL * new.reach;
        let turn = Vector2::new(-t.y, t.x);
        match *self {
            Curve::Body { c, body } => {
                let (_, sa, ra) = curved_turned(&body.outline, body.cos, body.sin, t)?;
                let (_, sn, rn) = new.curved(-t)?;
                Some((c + sa - sn + t * eps, turn * (ra + rn + eps)))
            }
            Curve::Line {
                a,
                e,
                inward,
                offset,
                ..
            } => Some((a + e * t.x + inward * offset, e)),
            Curve::Circle { o, radius } => {
                let (_, sn, rn) = new.curved(t)?;
                Some((o + t * (radius - eps) - sn, turn * (radius - eps - rn)))
            }
        }
    }

    /// Whether the new particle at `p` is certainly apart from the obstacle
    /// by at least ε/2, `t` the parameter it was solved at: the gap along
    /// the contact normal with support values bounded from above.
    fn certify(
        &self,
        bodies: &[Body],
        ob: &Obstacle,
        new: &Newcomer,
        p: Point,
        t: Vector2<f64>,
    ) -> Certified {
        let half = 0.5 * GAP_REL * new.reach;
        match *self {
            Curve::Body { c, body } => {
                let (Some((ha, _, _)), Some((hn, _, _))) = (
                    curved_turned(&body.outline, body.cos, body.sin, t),
                    new.curved(-t),
                ) else {
                    return Certified::Unsuited;
                };
                Certified::from(t.dot(&(p - c)) - ha - hn >= half)
            }
            Curve::Line {
                a, e, len, inward, ..
            } => {
                let Some((hn, sn, _)) = new.curved(-inward) else {
                    return Certified::Unsuited;
                };
                // Touching the wall's line beyond its ends is not a contact.
                let along = (p + sn - a).dot(&e);
                if !(0.0..=len).contains(&along) {
                    return Certified::Unsuited;
                }
                Certified::from((p - a).dot(&inward) - hn >= half)
            }
            Curve::Circle { .. } => Certified::from(clear_of(bodies, ob, new, p)),
        }
    }
}

/// Whether `p` lies on the side of `start` of the line between the two
/// curves' obstacles (through the centre of `a`'s particle and `b`'s centre,
/// or square to `b`'s straight wall, or through `b`'s circle's centre).
fn same_side(a: &Curve, b: &Curve, start: Point, p: Point) -> bool {
    let Curve::Body { c, .. } = *a else {
        return true;
    };
    let (q, v) = match *b {
        Curve::Body { c: cb, .. } => (c, cb - c),
        Curve::Line { inward, .. } => (c, inward),
        Curve::Circle { o, .. } => (o, c - o),
    };
    let side = |x: Point| {
        let w = x - q;
        v.x * w.y - v.y * w.x
    };
    side(start) * side(p) >= 0.0
}

/// A certificate's answer.
enum Certified {
    Yes,
    No,
    Unsuited,
}

impl From<bool> for Certified {
    fn from(yes: bool) -> Self {
        if yes { Certified::Yes } else { Certified::No }
    }
}

/// The centre near `start` at which the new particle touches both `a` and
/// `b` at the gap ε = [`GAP_REL`]·reach, by Newton on the two contact
/// curves' parameters (seed 001's exact contact, eq. 1–3, solved on the
/// curves the support maps trace rather than by optimisation).
///
/// # Behavior
/// Each curve is the ε-offset of the Minkowski sum of the obstacle and the
/// reflected new particle, traced by support points: every point on it is
/// at distance ε from the obstacle, so a crossing touches both. Damped
/// Newton solves C_a(t₁) = C_b(t₂) from the parameters nearest `start`
/// (or, for two particles, from the contact `normals` given: the screen's
/// estimate) in a few steps (the curves' derivatives are exact); the
/// centre is then
/// certified clear of both by the gap along each contact normal, with
/// support values bounded from above, and kept only on `start`'s side of
/// the line between the obstacles (the other crossing is the other
/// start's). Counts its curve evaluations in `work`.
pub(super) fn two_contact_smooth(
    bodies: &[Body],
    a: &Obstacle,
    b: &Obstacle,
    new: &Newcomer,
    start: Point,
    normals: Option<(Vector2<f64>, Vector2<f64>)>,
    work: &mut u64,
) -> Smooth {
    if new.slack != 0.0 {
        return Smooth::Unsuited;
    }
    let (Some((ca, mut ta)), Some((cb, mut tb))) = (
        Curve::of(bodies, a, new, start),
        Curve::of(bodies, b, new, start),
    ) else {
        return Smooth::Unsuited;
    };
    // Known contact normals start closer than the directions to `start`.
    if let (Some((na, nb)), Curve::Body { .. }, Curve::Body { .. }) = (normals, &ca, &cb) {
        (ta, tb) = (na, nb);
    }
    let eps = GAP_REL * new.reach;
    let eval = |ta: Vector2<f64>, tb: Vector2<f64>| {
        let ((pa, da), (pb, db)) = (ca.at(new, ta)?, cb.at(new, tb)?);
        Some((pa, da, db, pa - pb))
    };
    let Some(mut now) = eval(ta, tb) else {
        return Smooth::Unsuited;
    };
    *work += 1;
    let cross = |x: Vector2<f64>, y: Vector2<f64>| x.x * y.y - x.y * y.x;
    for _ in 0..SMOOTH_ITERATIONS {
        let (pa, da, db, f) = now;
        let residual = f.norm();
        if residual <= 0.25 * eps {
            for (curve, ob, t) in [(&ca, a, ta), (&cb, b, tb)] {
                match curve.certify(bodies, ob, new, pa, t) {
                    Certified::Yes => {}
                    Certified::No => return Smooth::Missing,
                    Certified::Unsuited => return Smooth::Unsuited,
                }
            }
            if !same_side(&ca, &cb, start, pa) {
                return Smooth::Missing;
            }
            return Smooth::Found(pa);
        }
        // da·δa − db·δb = −f.
        let det = -cross(da, db);
        if !det.is_finite() || det.abs() <= 1e-12 * da.norm() * db.norm() {
            return Smooth::Missing;
        }
        let (step_a, step_b) = (cross(f, db) / det, -cross(da, f) / det);
        if !(step_a.is_finite() && step_b.is_finite()) {
            return Smooth::Missing;
        }
        // Damped: the step halved until the residual falls (the normal
        // maps of flat-sided outlines bend sharply; a full step overshoots).
        let mut lambda = 1.0;
        let mut next = None;
        for _ in 0..BACKTRACKS {
            *work += 1;
            let (ta2, tb2) = (
                ca.advance(ta, lambda * step_a, new.reach),
                cb.advance(tb, lambda * step_b, new.reach),
            );
            let Some(trial) = eval(ta2, tb2) else {
                return Smooth::Unsuited;
            };
            if trial.3.norm() < (1.0 - 0.25 * lambda) * residual {
                next = Some((ta2, tb2, trial));
                break;
            }
            lambda *= 0.5;
        }
        let Some((ta2, tb2, trial)) = next else {
            return Smooth::Missing;
        };
        (ta, tb, now) = (ta2, tb2, trial);
    }
    Smooth::Missing
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
