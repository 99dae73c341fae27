//! The exact walls as the densify method's energy sees them: a penalty
//! ½·(r − s)² for each wall feature a disk of radius r reaches into, s the
//! distance from its centre to the feature.
//!
//! # Behavior
//! The energy is zero exactly when the disk lies inside the domain (its
//! centre at least r from the boundary), and continuously differentiable
//! while the centre stays inside, so the minimiser sees no kink at corners:
//! - a circle: one feature, s = R − |p − c| (a signed distance, right
//!   outside too);
//! - a convex polygon (rectangle, trapezoid, convex `polygon`): each edge is
//!   a half-plane, s the signed distance to its line. Inside a convex
//!   polygon the distance to the boundary is the least of these, and
//!   outside one of them is negative: exact everywhere;
//! - a concave polygon: each edge a strip (s the distance to its line while
//!   the centre projects onto the segment and lies on the domain's side),
//!   and each reflex corner a point obstacle over the wedge between its two
//!   edges' strips, where it is the nearest part of the boundary. Exact for
//!   a centre inside; one pushed outside (a deep overlap early in a run) is
//!   pulled back to the nearest boundary point with the penalty
//!   ½·(r + |p − q|)².

use nalgebra::Vector2;

use crate::geometry::{Domain, Point, Shape, Wall};

type V2 = Vector2<f64>;

/// A straight wall: from `a` along `d`, the domain on its left.
#[derive(Debug, Clone, Copy)]
pub(super) struct Edge {
    a: V2,
    d: V2,
    inv_len_2: f64,
    /// Unit normal into the domain.
    n: V2,
}

/// A reflex corner `v` between the edge arriving along `d_in` and the one
/// leaving along `d_out`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Corner {
    v: V2,
    d_in: V2,
    d_out: V2,
}

/// The walls of a domain, as features a disk may press on.
#[derive(Debug, Clone)]
pub(super) enum Boundary {
    /// A circular wall.
    Circle { c: V2, radius: f64 },
    /// Half-planes, one per edge of a convex polygon.
    Convex(Vec<Edge>),
    /// Strips along the edges (ids `0..edges.len()`) and reflex corners (the ids after).
    Concave {
        edges: Vec<Edge>,
        corners: Vec<Corner>,
    },
}

/// What a disk's walls add: the largest overlap relative to its radius,
/// the energy and the force on its centre.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct WallForce {
    pub worst: f64,
    pub energy: f64,
    pub force: V2,
}

impl WallForce {
    /// Add the penalty of an overlap `depth` > 0 of a disk of radius `r`, pushing along `dir`.
    #[inline]
    fn push(&mut self, depth: f64, r: f64, dir: V2) {
        self.worst = self.worst.max(depth / r);
        self.energy += 0.5 * depth * depth;
        self.force += dir * depth;
    }
}

impl Boundary {
    /// The features of `domain`'s walls.
    pub fn new(domain: &Domain) -> Self {
        if let Shape::Circle { center, radius } = *domain.shape() {
            return Boundary::Circle {
                c: center.coords,
                radius,
            };
        }
        let edges: Vec<Edge> = domain
            .walls()
            .iter()
            .filter_map(|w| match *w {
                Wall::Segment { a, b } => {
                    let d = b - a;
                    let len = d.norm();
                    Some(Edge {
                        a: a.coords,
                        d,
                        inv_len_2: 1.0 / (len * len),
                        n: V2::new(-d.y, d.x) / len,
                    })
                }
                Wall::Circle { .. } => None,
            })
            .collect();
        let reflex = domain.reflex_vertices();
        if reflex.is_empty() {
            return Boundary::Convex(edges);
        }
        let m = edges.len();
        let corners = (0..m)
            .filter(|&i| reflex.contains(&Point::from(edges[(i + 1) % m].a)))
            .map(|i| Corner {
                v: edges[(i + 1) % m].a,
                d_in: edges[i].d,
                d_out: edges[(i + 1) % m].d,
            })
            .collect();
        Boundary::Concave { edges, corners }
    }

    /// Whether a centre pushed out of the domain needs the outside rule (concave polygons only).
    pub fn needs_outside_rule(&self) -> bool {
        matches!(self, Boundary::Concave { .. })
    }

    /// Push into `out` the ids of the features within `reach` of `p`.
    pub fn near(&self, p: V2, reach: f64, out: &mut Vec<u32>) {
        match self {
            Boundary::Circle { c, radius } => {
                if radius - (p - c).norm() < reach {
                    out.push(0);
                }
            }
            Boundary::Convex(edges) => {
                for (id, e) in (0u32..).zip(edges) {
                    if e.n.dot(&(p - e.a)) < reach {
                        out.push(id);
                    }
                }
            }
            Boundary::Concave { edges, corners } => {
                for (id, e) in (0u32..).zip(edges) {
                    if segment_distance(p, e) < reach {
                        out.push(id);
                    }
                }
                for (id, c) in (edges.len() as u32..).zip(corners) {
                    if (p - c.v).norm() < reach {
                        out.push(id);
                    }
                }
            }
        }
    }

    /// The walls' penalty on a disk of radius `r` at `p`, over the features
    /// `ids` (those within reach). With `outside`, `p` is known to lie
    /// outside the domain (concave polygons only).
    pub fn force(&self, p: V2, r: f64, ids: &[u32], outside: bool) -> WallForce {
        let mut w = WallForce::default();
        match self {
            Boundary::Circle { c, radius } => {
                let out = p - c;
                let dist = out.norm();
                let depth = r - (radius - dist);
                if depth > 0.0 && dist > 0.0 {
                    w.push(depth, r, -out / dist);
                }
            }
            Boundary::Convex(edges) => {
                for &id in ids {
                    let e = &edges[id as usize];
                    let depth = r - e.n.dot(&(p - e.a));
                    if depth > 0.0 {
                        w.push(depth, r, e.n);
                    }
                }
            }
            Boundary::Concave { edges, corners } => {
                if outside {
                    let q = nearest_on_edges(p, edges);
                    let to = q - p;
                    let dist = to.norm();
                    if dist > 0.0 {
                        w.push(r + dist, r, to / dist);
                    }
                    return w;
                }
                for &id in ids {
                    let id = id as usize;
                    if let Some(e) = edges.get(id) {
                        let t = (p - e.a).dot(&e.d) * e.inv_len_2;
                        let s = e.n.dot(&(p - e.a));
                        // Off the segment's strip, or the far side of a thin wall.
                        if (0.0..=1.0).contains(&t) && s > 0.0 && s < r {
                            w.push(r - s, r, e.n);
                        }
                    } else {
                        let c = &corners[id - edges.len()];
                        let from = p - c.v;
                        let dist = from.norm();
                        if from.dot(&c.d_in) > 0.0
                            && from.dot(&c.d_out) < 0.0
                            && dist < r
                            && dist > 0.0
                        {
                            w.push(r - dist, r, from / dist);
                        }
                    }
                }
            }
        }
        w
    }
}

/// Distance from `p` to the segment `e`.
fn segment_distance(p: V2, e: &Edge) -> f64 {
    let t = ((p - e.a).dot(&e.d) * e.inv_len_2).clamp(0.0, 1.0);
    (e.a + e.d * t - p).norm()
}

/// The point of the boundary nearest to `p`.
fn nearest_on_edges(p: V2, edges: &[Edge]) -> V2 {
    let mut best = (f64::INFINITY, p);
    for e in edges {
        let t = ((p - e.a).dot(&e.d) * e.inv_len_2).clamp(0.0, 1.0);
        let q = e.a + e.d * t;
        let d2 = (q - p).norm_squared();
        if d2 < best.0 {
            best = (d2, q);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn l_shape() -> Domain {
        let v = [
            (0., 0.),
            (20., 0.),
            (20., 8.),
            (8., 8.),
            (8., 20.),
            (0., 20.),
        ];
        Domain::polygon(&v.map(|(x, y)| Point::new(x, y))).unwrap()
    }

    /// The energy over every feature: zero exactly when the disk is inside.
    fn energy(b: &Boundary, domain: &Domain, p: V2, r: f64) -> f64 {
        let mut ids = Vec::new();
        b.near(p, 2.0 * r + 1.0, &mut ids);
        let outside = b.needs_outside_rule() && domain.signed_distance(Point::from(p)) <= 0.0;
        b.force(p, r, &ids, outside).energy
    }

    #[test]
    fn the_energy_is_zero_exactly_where_the_disk_is_inside() {
        let domains = [
            Domain::rectangle(20.0, 12.0).unwrap(),
            Domain::circle(Point::new(3.0, 4.0), 9.0).unwrap(),
            Domain::trapezoid(20.0, 8.0, 12.0).unwrap(),
            l_shape(),
        ];
        for domain in &domains {
            let b = Boundary::new(domain);
            let (lo, hi) = domain.bounds();
            for i in 0..60 {
                for j in 0..60 {
                    let p = V2::new(
                        lo.x - 2.0 + (hi.x - lo.x + 4.0) * (i as f64 + 0.37) / 60.0,
                        lo.y - 2.0 + (hi.y - lo.y + 4.0) * (j as f64 + 0.61) / 60.0,
                    );
                    let r = 1.3;
                    let inside = domain.signed_distance(Point::from(p)) >= r;
                    let e = energy(&b, domain, p, r);
                    assert_eq!(
                        e == 0.0,
                        inside,
                        "{:?} at {p:?}: energy {e}",
                        domain.shape()
                    );
                }
            }
        }
    }

    #[test]
    fn a_disk_in_the_l_shapes_reflex_corner_is_pushed_away_from_it() {
        let domain = l_shape();
        let b = Boundary::new(&domain);
        // Below and left of the reflex corner (8, 8), 0.5 mm from it.
        let p = V2::new(8.0 - 0.3, 8.0 - 0.4);
        let mut ids = Vec::new();
        b.near(p, 3.0, &mut ids);
        let w = b.force(p, 1.0, &ids, false);
        assert!((w.worst - 0.5).abs() < 1e-12, "{w:?}");
        assert!((w.force - V2::new(-0.3, -0.4)).norm() < 1e-12, "{w:?}");
        // Pushed out across the top of the lower arm: pulled back in.
        let out = V2::new(14.0, 8.5);
        let w = b.force(out, 1.0, &ids, true);
        assert!((w.force - V2::new(0.0, -1.5)).norm() < 1e-12, "{w:?}");
    }
}
