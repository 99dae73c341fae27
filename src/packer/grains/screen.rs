//! A cheap first look at a front's candidates, on polygons.
//!
//! The centres at which the new particle N touches a placed particle X lie
//! on X's contact curve, the boundary of X ⊕ (−N). Sampled at [`SIDES`]
//! common normal directions u_k, the points c_X + s_X(u_k) − s_N(−u_k) are
//! points of X ⊕ (−N), so the polygon through them lies inside it: a centre
//! inside another particle's polygon is blocked by it (certainly when the
//! tables hold the particles' own shapes; nearly, when a range of shapes
//! shares tables rounded to a nearby one).
//!
//! The front's polygon is walked vertex by vertex, each vertex marked with
//! the obstacles that block it. Where two neighbouring vertices share no
//! blocker, the front's curve leaves one obstacle's shadow (or enters
//! another's) between them: a clear spot touching the front and that
//! obstacle may be there, its place estimated on the two polygons. Only
//! those candidates, lowest first, are solved exactly and checked
//! exactly; the rest of the curve, shadowed throughout, is never solved
//! for. A spot lost by the polygons (a clear arc shorter than one side
//! between two obstacles that share a vertex) costs density at most,
//! never an overlap: every placement is still solved and certified as
//! before.
//!
//! Support points come from tables of the unit outline (one per shape up
//! to scale, the aspect ratio and exponents rounded to a fine step: the
//! screen needs no exact outline), looked up at the nearest tabulated
//! direction.

use std::collections::HashMap;

use nalgebra::Vector2;

use super::Body;
use super::contact::{Newcomer, Obstacle, clear_of, newton_friendly};
use crate::geometry::{Outline, Point};

/// Sides of the sampled contact polygons.
pub(super) const SIDES: usize = 32;

/// A set of the polygons' vertices (bit k: vertex k).
type Ring = u32;

/// Every vertex.
const FULL: Ring = Ring::MAX >> (Ring::BITS as usize - SIDES);

/// The set turned back by one vertex: bit k set when vertex k + 1 is in.
#[inline]
fn next(c: Ring) -> Ring {
    (c >> 1 | c << (SIDES - 1)) & FULL
}

/// How deep (relative to the front's and the new particle's reaches) an
/// estimated spot must be in a third obstacle's polygon to be dropped
/// unsolved.
const MARGIN_REL: f64 = 0.01;

/// Directions tabulated per unit outline (a multiple of [`SIDES`]).
const TABLE: usize = 8 * SIDES;

/// Most tables kept; outlines past it are not screened (their fronts are
/// solved in full), which bounds the memory of scenes whose every particle
/// has its own shape.
const MOST_TABLES: usize = 2048;

/// Steps the aspect ratio and exponents are rounded to for a table.
const ASPECT_STEP: f64 = 1.0 / 256.0;
const EXPONENT_STEP: f64 = 1.0 / 64.0;

/// A placed or new particle's way into its table.
#[derive(Debug, Clone, Copy)]
pub(in crate::packer) struct Sampled {
    table: u32,
    /// The particle's angle in table steps.
    phase: u32,
    /// Its angle's cosine and sine times its scale (the table's unit
    /// outline so scaled and turned is the particle's).
    cos: f64,
    sin: f64,
}

/// What the neighbour search and the screen read of a placed particle,
/// kept apart from its body (one cache line, not two).
#[derive(Debug, Clone, Copy)]
pub(in crate::packer) struct Halo {
    pub c: Point,
    /// Radius of its bounding circle (circumradius).
    pub reach: f64,
    /// Radius of a disk about its centre inside it.
    pub inner: f64,
    /// Its way into the screen's tables (`None`: not screened).
    pub sampled: Option<Sampled>,
}

/// Support points of unit outlines at [`TABLE`] directions.
#[derive(Default)]
pub(super) struct Tables {
    known: HashMap<[u64; 3], u32>,
    points: Vec<Box<[Vector2<f64>; TABLE]>>,
}

impl Tables {
    /// The table of `outline` turned by (cos, sin), made on first use;
    /// `None` for outlines not screened (those not solved on their contact
    /// curves).
    pub fn sample(&mut self, outline: &Outline, cos: f64, sin: f64) -> Option<Sampled> {
        if !newton_friendly(outline) {
            return None;
        }
        let Outline::Superellipse { a, b, alpha, beta } = *outline else {
            return None;
        };
        let round = |x: f64, step: f64| (x / step).round() * step;
        let (aspect, alpha, beta) = (
            round(a / b, ASPECT_STEP),
            round(alpha, EXPONENT_STEP),
            round(beta, EXPONENT_STEP),
        );
        let key = [aspect.to_bits(), alpha.to_bits(), beta.to_bits()];
        let table = match self.known.get(&key) {
            Some(&t) => t,
            None => {
                if self.points.len() >= MOST_TABLES {
                    return None;
                }
                let unit = Outline::Superellipse {
                    a: aspect,
                    b: 1.0,
                    alpha,
                    beta,
                };
                let points = Box::new(std::array::from_fn(|i| {
                    let t = std::f64::consts::TAU * i as f64 / TABLE as f64;
                    unit.support_both(Vector2::new(t.cos(), t.sin())).1.coords
                }));
                let t = self.points.len() as u32;
                self.points.push(points);
                self.known.insert(key, t);
                t
            }
        };
        let turns = sin.atan2(cos) / std::f64::consts::TAU;
        let phase = ((turns * TABLE as f64).round() as i64).rem_euclid(TABLE as i64) as u32;
        Some(Sampled {
            table,
            phase,
            cos: b * cos,
            sin: b * sin,
        })
    }

    /// The support point (about the centre, world axes) of the particle
    /// `s` in the common direction `k` of [`SIDES`] (angle 2πk/SIDES).
    #[inline]
    pub fn point(&self, s: &Sampled, k: usize) -> Vector2<f64> {
        let i = (k * (TABLE / SIDES) + TABLE - s.phase as usize) % TABLE;
        let p = self.points[s.table as usize][i];
        Vector2::new(s.cos * p.x - s.sin * p.y, s.sin * p.x + s.cos * p.y)
    }

    /// `plus[k]` plus the support point of `s` in each common direction k.
    #[inline]
    pub fn points_plus(
        &self,
        s: &Sampled,
        plus: &[Vector2<f64>; SIDES],
        out: &mut [Vector2<f64>; SIDES],
    ) {
        let table = &self.points[s.table as usize];
        let start = TABLE - s.phase as usize;
        for k in 0..SIDES {
            let p = table[(k * (TABLE / SIDES) + start) % TABLE];
            out[k] = plus[k] + Vector2::new(s.cos * p.x - s.sin * p.y, s.sin * p.x + s.cos * p.y);
        }
    }
}

/// A contact polygon about a centre: its vertices (about the centre),
/// counter-clockwise.
#[derive(Clone, Copy)]
pub(super) struct Polygon {
    c: Point,
    v: [Vector2<f64>; SIDES],
}

/// What a polygon's vertices are computed from: the tables and the new
/// particle's reflected samples ([`reflected`]).
pub(super) struct Source<'t> {
    pub tables: &'t Tables,
    pub minus_n: [Vector2<f64>; SIDES],
}

impl Polygon {
    /// The contact polygon of particle `x` at `c` for the new particle.
    #[cfg(test)]
    fn of(c: Point, x: &Sampled, src: &Source) -> Polygon {
        let mut v = [Vector2::zeros(); SIDES];
        src.tables.points_plus(x, &src.minus_n, &mut v);
        Polygon { c, v }
    }

    /// The contact polygon of particle `x` at `c` for the new particle,
    /// made in slot `*used` of `polys` (slots are kept from one screen to
    /// the next); its slot.
    fn make(
        polys: &mut Vec<Polygon>,
        used: &mut usize,
        c: Point,
        x: &Sampled,
        src: &Source,
    ) -> usize {
        if *used == polys.len() {
            polys.push(Polygon {
                c,
                v: [Vector2::zeros(); SIDES],
            });
        }
        let slot = *used;
        *used += 1;
        let poly = &mut polys[slot];
        poly.c = c;
        src.tables.points_plus(x, &src.minus_n, &mut poly.v);
        slot
    }

    /// The side the ray from the centre along `w` crosses, by its first
    /// vertex, and the side's two ends; the walk starts at `hint` (else
    /// at the vertex whose normal is nearest w's direction).
    #[inline]
    fn side(&self, w: Vector2<f64>, hint: Option<usize>) -> (usize, Vector2<f64>, Vector2<f64>) {
        let mut k = hint
            .unwrap_or_else(|| ((pseudo_angle(w) * SIDES as f64 / 4.0) as usize).min(SIDES - 1));
        let mut a = self.v[k];
        for _ in 0..SIDES {
            if cross(a, w) >= 0.0 {
                break;
            }
            k = (k + SIDES - 1) % SIDES;
            a = self.v[k];
        }
        let mut b = self.v[(k + 1) % SIDES];
        for _ in 0..SIDES {
            if cross(b, w) < 0.0 {
                break;
            }
            k = (k + 1) % SIDES;
            a = b;
            b = self.v[(k + 1) % SIDES];
        }
        (k, a, b)
    }

    /// Whether `p` is inside the polygon, and the side its ray crosses
    /// (a hint for a point near it).
    #[inline]
    pub fn holds(&self, p: Vector2<f64>, hint: Option<usize>) -> (bool, usize) {
        let w = p - self.c.coords;
        let (k, a, b) = self.side(w, hint);
        (cross(b - a, w - a) > 0.0, k)
    }

    /// How deep `p` is inside the polygon: its distance inside the side
    /// its ray from the centre crosses (negative outside).
    pub fn depth(&self, p: Vector2<f64>) -> f64 {
        let w = p - self.c.coords;
        let (_, a, b) = self.side(w, None);
        let e = b - a;
        let len = e.norm();
        if len == 0.0 {
            return a.norm() - w.norm();
        }
        cross(e, w - a) / len
    }
}

/// The new particle's support points, reflected, in the common directions
/// turned half a turn: −s_N(−u_k).
pub(super) fn reflected(tables: &Tables, n: &Sampled) -> [Vector2<f64>; SIDES] {
    let mut v = [Vector2::zeros(); SIDES];
    for (k, vk) in v.iter_mut().enumerate() {
        *vk = -tables.point(n, (k + SIDES / 2) % SIDES);
    }
    v
}

#[inline]
fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// A place where a clear spot touching the front and obstacle `ob` (an
/// index into the front's obstacles) may be, estimated on the polygons.
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub ob: usize,
    pub p: Point,
    /// The contact normals there (the front's, the obstacle's) when the
    /// obstacle is a particle.
    pub normals: Option<(Vector2<f64>, Vector2<f64>)>,
}

/// The candidates of front `f` for the new particle `new` among
/// `obstacles` (at most 64), into `out`; `None` when the screen does not
/// apply (an outline without a table or not solved on its curve, too many
/// obstacles, or no obstacle shadowing any vertex: a front alone, solved
/// in full). `polys` is scratch.
#[allow(clippy::too_many_arguments)]
pub(super) fn candidates(
    tables: &Tables,
    bodies: &[Body],
    halos: &[Halo],
    f: &Halo,
    new: &Newcomer,
    obstacles: &[Obstacle],
    polys: &mut Vec<Polygon>,
    out: &mut Vec<Candidate>,
    work: &mut u64,
) -> Option<()> {
    out.clear();
    let mut used = 0;
    let sn = new.sampled?;
    let sf = f.sampled?;
    if obstacles.len() > 64 {
        return None;
    }
    let src = Source {
        tables,
        minus_n: reflected(tables, &sn),
    };
    let mut vf = [Vector2::zeros(); SIDES];
    tables.points_plus(&sf, &src.minus_n, &mut vf);
    for v in &mut vf {
        *v += f.c.coords;
    }
    let (xs, ys): ([f64; SIDES], [f64; SIDES]) = (
        std::array::from_fn(|k| vf[k].x),
        std::array::from_fn(|k| vf[k].y),
    );
    // Per obstacle, the vertices it shadows (bit k: vertex k).
    let mut cover = [0 as Ring; 64];
    // Per obstacle, its polygon's index in `polys` (built when needed).
    let mut poly_of = [u8::MAX; 64];
    // Nearest particles first: a front shadowed throughout is known as
    // soon as its neighbours' shadows overlap all round (the far ones can
    // add no candidate then).
    // Sorted on keys: the gap's bits made to sort as integers, its lowest
    // byte replaced by the obstacle's index.
    let mut order = [0u64; 64];
    for (j, ob) in obstacles.iter().enumerate() {
        let gap = match *ob {
            Obstacle::Body(id, shift) => {
                let g = &halos[id as usize];
                (g.c + shift - f.c).norm() - g.reach
            }
            _ => f64::INFINITY,
        };
        let bits = gap.to_bits();
        let key = if gap >= 0.0 { bits | 1 << 63 } else { !bits };
        order[j] = (key & !0xFF) | j as u64;
    }
    let order = &mut order[..obstacles.len()];
    order.sort_unstable();
    let mut shared: Ring = 0;
    for &key in order.iter() {
        let j = (key & 0xFF) as usize;
        let ob = &obstacles[j];
        *work += 1;
        match *ob {
            Obstacle::Body(id, shift) => {
                let g = &halos[id as usize];
                let sg = g.sampled?;
                let c = g.c + shift;
                let (far, near) = (g.reach + new.reach, g.inner + new.inner);
                let (far2, near2) = (far * far, near * near);
                let (mut inside, mut unsure): (Ring, Ring) = (0, 0);
                for k in 0..SIDES {
                    let (dx, dy) = (xs[k] - c.x, ys[k] - c.y);
                    let d2 = dx * dx + dy * dy;
                    inside |= Ring::from(d2 < near2) << k;
                    unsure |= Ring::from(d2 < far2 && d2 >= near2) << k;
                }
                if unsure != 0 {
                    let slot = Polygon::make(polys, &mut used, c, &sg, &src);
                    poly_of[j] = slot as u8;
                    let poly = &polys[slot];
                    // Neighbouring vertices of the front fall on
                    // neighbouring sides: each walk starts at the last.
                    let mut hint = None;
                    while unsure != 0 {
                        let k = unsure.trailing_zeros() as usize;
                        unsure &= unsure - 1;
                        let (held, side) = poly.holds(vf[k], hint);
                        hint = Some(side);
                        if held {
                            inside |= 1 << k;
                        }
                    }
                }
                cover[j] = inside;
            }
            Obstacle::Segment(..) | Obstacle::Circle(..) => {
                for (k, v) in vf.iter().enumerate() {
                    if !clear_of(bodies, ob, new, Point::from(*v)) {
                        cover[j] |= 1 << k;
                    }
                }
            }
        }
        shared |= cover[j] & next(cover[j]);
        if shared == FULL {
            return Some(());
        }
    }
    // Sides whose ends share a blocker, and sides with a blocked end; bit
    // k: the side from vertex k to k + 1.
    let cover = &cover[..obstacles.len()];
    let touched = cover.iter().fold(0, |acc, &c| acc | c | next(c));
    if touched == 0 {
        return None;
    }
    let margin = MARGIN_REL * (f.reach + new.reach);
    let mut sides = touched & !shared;
    while sides != 0 {
        let k = sides.trailing_zeros() as usize;
        sides &= sides - 1;
        let k1 = (k + 1) % SIDES;
        let (a, b) = (vf[k], vf[k1]);
        let mut at_side: u64 = 0;
        for (j, &c) in cover.iter().enumerate() {
            at_side |= (((c | next(c)) >> k & 1) as u64) << j;
        }
        for (j, &c) in cover.iter().enumerate() {
            if (c | next(c)) >> k & 1 == 0 {
                continue;
            }
            let (p, normals) = match obstacles[j] {
                Obstacle::Body(id, shift) => {
                    if poly_of[j] == u8::MAX {
                        let g = &halos[id as usize];
                        poly_of[j] =
                            Polygon::make(polys, &mut used, g.c + shift, &g.sampled?, &src) as u8;
                    }
                    let poly = &polys[poly_of[j] as usize];
                    let (d0, d1) = (poly.depth(a), poly.depth(b));
                    let t = if d0 != d1 {
                        (d0 / (d0 - d1)).clamp(0.0, 1.0)
                    } else {
                        0.5
                    };
                    let p = a + (b - a) * t;
                    // Deep in the shadow of another obstacle at this side:
                    // blocked (mostly a neighbour touching both).
                    let mut others = at_side & !(1 << j);
                    let mut blocked = false;
                    while others != 0 {
                        let j2 = others.trailing_zeros() as usize;
                        others &= others - 1;
                        if poly_of[j2] != u8::MAX && polys[poly_of[j2] as usize].depth(p) > margin {
                            blocked = true;
                            break;
                        }
                    }
                    if blocked {
                        continue;
                    }
                    let poly = &polys[poly_of[j] as usize];
                    // The normals of the two sides there.
                    let (i, _, _) = poly.side(p - poly.c.coords, None);
                    let normal = |x: f64| {
                        let angle = std::f64::consts::TAU * x / SIDES as f64;
                        Vector2::new(angle.cos(), angle.sin())
                    };
                    (p, Some((normal(k as f64 + t), normal(i as f64 + 0.5))))
                }
                _ => (a + (b - a) * 0.5, None),
            };
            out.push(Candidate {
                ob: j,
                p: Point::from(p),
                normals,
            });
        }
    }
    Some(())
}

/// A monotone stand-in for the angle of `w`, in [0, 4) for [0, 2π).
#[inline]
fn pseudo_angle(w: Vector2<f64>) -> f64 {
    let s = w.x.abs() + w.y.abs();
    if s == 0.0 {
        return 0.0;
    }
    let t = w.y / s;
    let r = if w.x >= 0.0 { t } else { 2.0 - t };
    if r < 0.0 { r + 4.0 } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygon_vertices_lie_inside_the_true_contact_set() {
        // Two ellipses: a vertex is inside X ⊕ (−N) when the two placed at
        // that centre distance overlap or touch.
        let mut tables = Tables::default();
        let x = Outline::Superellipse {
            a: 1.5,
            b: 1.0,
            alpha: 2.0,
            beta: 2.0,
        };
        let n = Outline::Superellipse {
            a: 2.0,
            b: 0.5,
            alpha: 4.0,
            beta: 4.0,
        };
        let (sx, cx) = (0.7f64.sin(), 0.7f64.cos());
        let (sn, cn) = (2.1f64.sin(), 2.1f64.cos());
        let xs = tables.sample(&x, cx, sx).unwrap();
        let ns = tables.sample(&n, cn, sn).unwrap();
        let src = Source {
            tables: &tables,
            minus_n: reflected(&tables, &ns),
        };
        let poly = Polygon::of(Point::origin(), &xs, &src);
        for (k, v) in poly.v.iter().enumerate() {
            // Vertex k is nearly the support point of X ⊕ (−N) in the
            // direction u_k (the tables' nearest directions), never beyond.
            let t = std::f64::consts::TAU * k as f64 / SIDES as f64;
            let u = Vector2::new(t.cos(), t.sin());
            let to_local = |c: f64, s: f64, u: Vector2<f64>| {
                Vector2::new(c * u.x + s * u.y, -s * u.x + c * u.y)
            };
            let h = x.support_both(to_local(cx, sx, u)).0 + n.support_both(to_local(cn, sn, -u)).0;
            let reach = v.dot(&u);
            assert!(
                reach <= h * (1.0 + 1e-12) && reach >= 0.97 * h,
                "{reach} vs {h}"
            );
        }
        // Depth: the centre is deep inside, a far point outside.
        assert!(poly.depth(Vector2::new(0.0, 0.01)) > 0.5);
        assert!(poly.depth(Vector2::new(10.0, -3.0)) < 0.0);
        // Each vertex is on the boundary (depth 0 up to rounding), and a
        // point just beyond is outside, from any hint.
        for v in &poly.v {
            assert!(poly.depth(*v).abs() < 1e-9);
            for hint in [None, Some(0), Some(SIDES / 2), Some(SIDES - 1)] {
                assert!(poly.depth(*v * 1.01) < 0.0 && !poly.holds(*v * 1.01, hint).0);
                assert!(poly.depth(*v * 0.99) > 0.0 && poly.holds(*v * 0.99, hint).0);
            }
        }
    }

    #[test]
    fn pseudo_angle_is_monotone() {
        let mut last = -1.0;
        for i in 0..360 {
            let t = (i as f64).to_radians();
            let p = pseudo_angle(Vector2::new(t.cos(), t.sin()));
            assert!(p > last && p < 4.0);
            last = p;
        }
    }
}
