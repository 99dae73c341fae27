//! Every geometric test the packer relies on, under one tolerance policy.
//!
//! Candidate centres are intersections of halos; rounding puts them a few
//! ulps off the exact tangent point. The policy: a candidate may sit at most
//! [`FEASIBLE_REL`] (relative to the radii sum) inside another halo and still
//! count as tangent, which keeps every accepted overlap far below the
//! [`OVERLAP_REL`] that the metrics and tests treat as an overlap. Nearly
//! tangent halos (gap within [`TANGENT_REL`]) are treated as touching, so a
//! disk that exactly fits a gap is not lost to rounding.
//!
//! # Scale
//! The algorithm is scale-free, and so is every tolerance: none is an
//! absolute length. A scene scaled by a power of two packs to the same disks
//! scaled (bit for bit; `tests/integration/scales.rs` checks 2⁻²⁰ to 2²⁰), and one scaled
//! by a power of ten to the same packing up to rounding. Each tolerance is
//! relative to one of:
//! - **the radii**: [`OVERLAP_REL`], [`FEASIBLE_REL`], [`CONTACT_REL`],
//!   [`WITNESS_REL`] (× radii sum or radius); the packer's wall reach margin
//!   (`WALL_MARGIN_REL`, × the halo's reach); the deposition generator's
//!   contact margin (× the radius); the relaxation's gradient step
//!   (a millionth of the radius);
//! - **the domain**: polygon validation (repeated vertices within 1e-12 of
//!   the bounding-box diagonal, zero area within 1e-10 of the box's area);
//!   the end slack of a wall's tangent points (1e-12 of the wall's length);
//!   the metrics' hole search (steps of the smallest diameter or the extent);
//!   index buckets (in largest diameters);
//! - **nothing** (dimensionless): [`TANGENT_REL`] (a squared half-chord over
//!   the squared radius), parallel walls and spikes (sines of angles, 1e-12),
//!   the inradius' degenerate medial-axis vertices (of unit normals);
//! - **the coordinates' spacing** (ulps), for the rounding no relative
//!   tolerance can absorb: [`ROUNDING_ULPS`] in [`clear_disk_walls`].
//!
//! Orientation and self-intersection tests are exact (`polygon.rs`).
//!
//! # Far from the origin
//! An ulp of a coordinate grows with the coordinate, not with the disks
//! (1.2·10⁻¹⁰ mm at 10⁶ mm), so three rules keep the rounding at the scale
//! of the disks wherever it can be:
//! 1. A domain far from the origin is packed next to it
//!    ([`Domain::local_offset`], an exact move) and the packing moved back:
//!    the packing of a translated domain is that of the domain at the origin,
//!    translated, with one rounding of each centre.
//! 2. The advancing front computes candidates as offsets from the front's
//!    centre and tests them against its neighbours' offsets, so disk–disk
//!    decisions carry a rounding of the radii even in a domain 10⁶ diameters
//!    long; only the placed centre is rounded to its coordinates.
//! 3. A wall test forgives [`ROUNDING_ULPS`] ulps of the point's
//!    coordinates: a point's distance to a wall is computed from coordinates
//!    and cannot be better.
//!
//! What remains is up to half an ulp per coordinate in each placed centre
//! and again in each centre moved back, plus the wall slack: at most about
//! 6·10⁻¹⁶·X between two disks and 8·10⁻¹⁶·X at a wall, X the largest
//! |coordinate| (an ulp is at most 2.2·10⁻¹⁶·X). The config refuses scenes
//! whose smallest diameter is below [`RESOLUTION_REL`]·X, where that could
//! reach [`OVERLAP_REL`].

use super::{Domain, Point};

/// Largest overlap, relative to the sum of the radii, that counts as no overlap (metrics, tests).
pub const OVERLAP_REL: f64 = 1e-9;

/// Largest penetration, relative to the sum of the radii, a candidate may have and stay feasible.
pub const FEASIBLE_REL: f64 = 1e-11;

/// Relative gap under which two halos count as tangent (one intersection point).
pub const TANGENT_REL: f64 = 1e-12;

/// Rounding, in ulps of a point's largest coordinate, that a wall test
/// forgives a computed point (see [`clear_disk_walls`]).
///
/// Two ulps keep wall-tangent candidates up to 2·10⁶ diameters from the
/// origin, along axis-aligned and slanted walls (`tests/integration/scales.rs`). With
/// none, a pocket turned 30° at 10⁶ diameters packed 401 disks instead of
/// 429; with four, a disk stood out of it at 2·10⁶ diameters by 1.2·10⁻⁹ of
/// its diameter, over [`OVERLAP_REL`].
pub const ROUNDING_ULPS: f64 = 2.0;

/// Smallest ratio of the smallest diameter to the largest |coordinate| of a
/// scene that a config may give.
///
/// # Behavior
/// Below it the rounding of the coordinates alone (see the module's
/// "Far from the origin") could bring two disks within [`OVERLAP_REL`] of
/// their radii sum or a disk out of the domain: at this ratio the worst is
/// 8·10⁻¹⁰ of the diameter. Measured: at 10⁷ mm from the origin, disks of
/// 0.4–2 mm (a ratio of 4·10⁻⁸) overlapped by 1.3·10⁻⁹.
pub const RESOLUTION_REL: f64 = 1e-6;

/// Relative gap under which two disks count as in contact (coordination number).
pub const CONTACT_REL: f64 = 1e-6;

/// Relative slack when a front's remembered free spot is checked again: a spot
/// still counts as free unless it is blocked by more than this. Generous on
/// purpose (20 times the rounding of a stored direction), since a spot judged
/// free only costs a full, exact attempt.
pub const WITNESS_REL: f64 = 1e-3;

/// Intersections of the circles (`c1`, `r1`) and (`c2`, `r2`).
///
/// # Returns
/// `None` when the circles are apart, nested, or concentric. Near-tangent
/// circles (gap within [`TANGENT_REL`]) give the tangent point twice.
#[inline]
pub fn intersect_circle_circle(c1: Point, r1: f64, c2: Point, r2: f64) -> Option<[Point; 2]> {
    chord_circle_circle(c1, r1, c2, r2).map(|chord| chord.points(c1))
}

/// The common chord of two circles, as offsets from the first centre: what
/// [`intersect_circle_circle`] computes its points from.
///
/// # Behavior
/// With `d = c2 − c1`, the chord's midpoint is `c1 + a·d` and its ends lie
/// `±h` of `|d|` across the centre line. The offsets alone locate the
/// intersections to a rounding of the radii wherever the circles lie; the
/// points add the rounding of `c1`'s coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chord {
    /// `a·d`: the chord's midpoint relative to the first centre.
    pub mid: [f64; 2],
    /// `h·d`: the half-chord before its quarter turn; the ends lie at
    /// `mid ± (−half[1], half[0])`.
    pub half: [f64; 2],
}

impl Chord {
    /// The two intersections, the first on the left of `c1 → c2`.
    #[inline]
    pub fn points(&self, c1: Point) -> [Point; 2] {
        let (mx, my) = (c1.x + self.mid[0], c1.y + self.mid[1]);
        [
            Point::new(mx - self.half[1], my + self.half[0]),
            Point::new(mx + self.half[1], my - self.half[0]),
        ]
    }

    /// The two intersections relative to the first centre, in the order of [`Chord::points`].
    #[inline]
    pub fn offsets(&self) -> [Point; 2] {
        let [mx, my] = self.mid;
        [
            Point::new(mx - self.half[1], my + self.half[0]),
            Point::new(mx + self.half[1], my - self.half[0]),
        ]
    }
}

/// The common chord of the circles (`c1`, `r1`) and (`c2`, `r2`), or `None`
/// as for [`intersect_circle_circle`].
#[inline]
pub fn chord_circle_circle(c1: Point, r1: f64, c2: Point, r2: f64) -> Option<Chord> {
    chord_of_offset(c2.x - c1.x, c2.y - c1.y, r1, r2)
}

/// [`chord_circle_circle`] from the second centre's offset `(dx, dy)` from
/// the first, for a caller that already holds it (the advancing front keeps
/// each neighbour's offset from the front).
#[inline]
pub fn chord_of_offset(dx: f64, dy: f64, r1: f64, r2: f64) -> Option<Chord> {
    let d2 = dx * dx + dy * dy;
    if d2 == 0.0 {
        return None;
    }
    let a = (r1 * r1 - r2 * r2 + d2) / (2.0 * d2); // fraction of the centre line
    let h2 = r1 * r1 / d2 - a * a; // (half chord / d)²
    let h = if h2 >= 0.0 {
        h2.sqrt()
    } else if h2 > -TANGENT_REL * r1 * r1 / d2 {
        0.0
    } else {
        return None;
    };
    Some(Chord {
        mid: [a * dx, a * dy],
        half: [h * dx, h * dy],
    })
}

/// Intersections of the circle (`c`, `r`) with the line through `q` of unit direction `(ux, uy)`,
/// as parameters `t` along the line (`q + t·u`), smaller first.
///
/// A near-tangent line (gap within [`TANGENT_REL`]) gives the tangent point twice.
#[inline]
pub fn intersect_circle_line(c: Point, r: f64, q: Point, ux: f64, uy: f64) -> Option<[f64; 2]> {
    let wx = c.x - q.x;
    let wy = c.y - q.y;
    let t0 = wx * ux + wy * uy;
    // The distance to the line from the cross product: |w|² − t0² cancels
    // catastrophically far along a long wall (an 8 m fracture face put
    // 1e-8 mm overlaps into the candidates).
    let cross = wx * uy - wy * ux;
    let dist2 = cross * cross;
    let h2 = r * r - dist2;
    let h = if h2 >= 0.0 {
        h2.sqrt()
    } else if h2 > -TANGENT_REL * r * r {
        0.0
    } else {
        return None;
    };
    Some([t0 - h, t0 + h])
}

/// Whether a disk of radius `r` at `p` stays clear of the disk (`c`, `rc`), within [`FEASIBLE_REL`].
#[inline]
pub fn clear_disk_disk(p: Point, r: f64, c: Point, rc: f64) -> bool {
    let dx = p.x - c.x;
    let dy = p.y - c.y;
    let s = (r + rc) * (1.0 - FEASIBLE_REL);
    dx * dx + dy * dy >= s * s
}

/// Whether a disk of radius `r` at `p` stays inside `domain`: its centre at
/// least `r` from the boundary, within [`FEASIBLE_REL`] of `r` or
/// [`ROUNDING_ULPS`] of the spacing of `p`'s coordinates, whichever is larger.
///
/// # Behavior
/// A point tangent to a wall is computed from the wall's vertices and the
/// front's centre, so its distance to the wall carries a rounding of a few
/// ulps of its coordinates, whatever the radius: [`FEASIBLE_REL`] alone
/// refused wall-tangent candidates once the coordinates exceeded about 10⁵
/// radii. Where the coordinates are small the relative slack decides, as
/// before.
#[inline]
pub fn clear_disk_walls(domain: &Domain, p: Point, r: f64) -> bool {
    let rounding = ROUNDING_ULPS * f64::EPSILON * p.x.abs().max(p.y.abs());
    domain.signed_distance(p) >= (r * (1.0 - FEASIBLE_REL)).min(r - rounding)
}

/// Largest radius ρ of a disk centred at `t + ρ·u` (so touching the point `t`,
/// `u` a unit vector) that stays clear of the disk (`c`, `rc`).
///
/// # Returns
/// `f64::INFINITY` when no radius is blocked (the ray leaves the disk's side),
/// and 0 or less when `t` itself is inside the disk. Clearance is linear in ρ:
/// |t − c + ρu|² ≥ (rc + ρ)² ⇔ |t − c|² − rc² ≥ 2ρ(rc − (t − c)·u).
#[inline]
pub fn max_radius_ray_disk(t: Point, u: [f64; 2], c: Point, rc: f64) -> f64 {
    let (wx, wy) = (t.x - c.x, t.y - c.y);
    let toward = rc - (wx * u[0] + wy * u[1]);
    if toward <= 0.0 {
        return f64::INFINITY;
    }
    (wx * wx + wy * wy - rc * rc) / (2.0 * toward)
}

/// Overlap of two disks relative to the sum of their radii (negative when apart).
#[inline]
pub fn overlap_disk_disk(c1: Point, r1: f64, c2: Point, r2: f64) -> f64 {
    let d = (c1 - c2).norm();
    (r1 + r2 - d) / (r1 + r2)
}

/// Area of the intersection of the disks (`c1`, `r1`) and (`c2`, `r2`), exactly.
///
/// # Behavior
/// 0 when they are apart, the smaller disk's area when it lies inside the
/// larger, else the lens: the two circular segments cut by the common chord.
pub fn area_disk_disk(c1: Point, r1: f64, c2: Point, r2: f64) -> f64 {
    let d = (c1 - c2).norm();
    if d >= r1 + r2 {
        return 0.0;
    }
    let small = r1.min(r2);
    if d <= (r1 - r2).abs() {
        return std::f64::consts::PI * small * small;
    }
    // Half-angles of the chord seen from each centre.
    let a1 = ((d * d + r1 * r1 - r2 * r2) / (2.0 * d * r1))
        .clamp(-1.0, 1.0)
        .acos();
    let a2 = ((d * d + r2 * r2 - r1 * r1) / (2.0 * d * r2))
        .clamp(-1.0, 1.0)
        .acos();
    let segment = |r: f64, a: f64| r * r * (a - a.sin() * a.cos());
    segment(r1, a1) + segment(r2, a2)
}

/// Area of the disk (`c`, `r`) inside the axis-aligned box `[x0, x1] × [y0, y1]`, exactly.
///
/// # Behavior
/// Integrates the disk's vertical chord clipped to the box piece by piece
/// between the abscissae where the clipping changes, each piece in closed form.
pub fn area_disk_box(c: Point, r: f64, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let lo = x0.max(c.x - r);
    let hi = x1.min(c.x + r);
    if lo >= hi || y0 >= y1 || c.y - r >= y1 || c.y + r <= y0 {
        return 0.0;
    }
    // Breakpoints where the chord ends cross the box's horizontal sides.
    let mut xs = [lo, hi, lo, lo, lo, lo];
    let mut n = 2;
    for k in [y0 - c.y, y1 - c.y] {
        if k.abs() < r {
            let s = (r * r - k * k).sqrt();
            for x in [c.x - s, c.x + s] {
                if x > lo && x < hi {
                    xs[n] = x;
                    n += 1;
                }
            }
        }
    }
    let xs = &mut xs[..n];
    xs.sort_by(f64::total_cmp);
    // Antiderivative of the half chord h(t) = sqrt(r² − t²), t = x − c.x.
    let big_h = |t: f64| {
        let t = t.clamp(-r, r);
        0.5 * (t * (r * r - t * t).max(0.0).sqrt() + r * r * (t / r).asin())
    };
    let mut area = 0.0;
    for w in xs.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        let tm = 0.5 * (a + b) - c.x;
        let hm = (r * r - tm * tm).max(0.0).sqrt();
        // At or inside the box edge the chord bounds the piece (a box edge
        // tangent to the disk meets the chord at the midpoint only).
        let top_is_chord = c.y + hm <= y1;
        let bottom_is_chord = c.y - hm >= y0;
        let top = if top_is_chord { c.y + hm } else { y1 };
        let bottom = if bottom_is_chord { c.y - hm } else { y0 };
        if top <= bottom {
            continue;
        }
        let chord = big_h(b - c.x) - big_h(a - c.x); // ∫ h dx over the piece
        let width = b - a;
        let upper = if top_is_chord {
            c.y * width + chord
        } else {
            y1 * width
        };
        let lower = if bottom_is_chord {
            c.y * width - chord
        } else {
            y0 * width
        };
        area += upper - lower;
    }
    area
}

/// The part of the simple polygon `vertices` inside the axis-aligned box
/// `[x0, x1] × [y0, y1]`, as a ring in the input's orientation.
///
/// # Behavior
/// Clips the polygon to the box one side at a time (Sutherland–Hodgman).
/// The box is convex, so a concave polygon that the box cuts into several
/// pieces comes back as one ring whose extra edges run along the box's
/// sides and enclose no area: its area and its drawing (filled, without a
/// stroke) are those of the pieces. Empty when nothing is left, for an
/// empty box, or for fewer than three vertices.
///
/// # Performance
/// O(vertices) time, two scratch vectors.
pub fn clip_polygon_box(vertices: &[Point], x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<Point> {
    if vertices.len() < 3 || x0 >= x1 || y0 >= y1 {
        return Vec::new();
    }
    let mut ring = vertices.to_vec();
    let mut next = Vec::with_capacity(ring.len() + 4);
    // Each side of the box: along x or y, the bound, and the sign such
    // that the kept side is `coordinate(p) · sign >= bound · sign`.
    for (along_x, bound, sign) in [
        (true, x0, 1.0),
        (true, x1, -1.0),
        (false, y0, 1.0),
        (false, y1, -1.0),
    ] {
        let coordinate = |p: &Point| if along_x { p.x } else { p.y };
        next.clear();
        let inside = |p: &Point| (coordinate(p) - bound) * sign >= 0.0;
        for (i, b) in ring.iter().enumerate() {
            let a = ring[(i + ring.len() - 1) % ring.len()];
            let (a_in, b_in) = (inside(&a), inside(b));
            if a_in != b_in {
                // The edge crosses the side: its point at the bound.
                let t = (bound - coordinate(&a)) / (coordinate(b) - coordinate(&a));
                next.push(a + (b - a) * t);
            }
            if b_in {
                next.push(*b);
            }
        }
        std::mem::swap(&mut ring, &mut next);
        if ring.len() < 3 {
            return Vec::new();
        }
    }
    ring
}

/// Area of the simple polygon `vertices` inside the axis-aligned box `[x0, x1] × [y0, y1]`, exactly.
///
/// # Behavior
/// The area of [`clip_polygon_box`]'s ring: exact up to rounding (a few ulps
/// of the coordinates) for either orientation of `vertices`, concave ones
/// included. 0 for an empty box or fewer than three vertices.
///
/// # Performance
/// O(vertices) time, two scratch vectors.
pub fn area_polygon_box(vertices: &[Point], x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let ring = clip_polygon_box(vertices, x0, x1, y0, y1);
    let twice: f64 = ring
        .iter()
        .zip(ring.iter().cycle().skip(1))
        .map(|(a, b)| a.x * b.y - b.x * a.y)
        .sum();
    (0.5 * twice).abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;
    use std::f64::consts::PI;

    #[test]
    fn intersect_circle_circle_example() {
        let [p, q] =
            intersect_circle_circle(Point::new(0.0, 0.0), 1.0, Point::new(2.0, 0.0), 1.0).unwrap();
        assert!((p - Point::new(1.0, 0.0)).norm() < 1e-6 && (q - p).norm() < 1e-6);
    }

    #[test]
    fn clear_disk_walls_example() {
        let d = Domain::rectangle(4.0, 2.0).unwrap();
        assert!(clear_disk_walls(&d, Point::new(1.0, 1.0), 1.0));
        assert!(!clear_disk_walls(&d, Point::new(1.0, 1.0 - 1e-9), 1.0));
    }

    #[test]
    fn max_radius_ray_disk_example() {
        // From the origin along +x towards a unit disk centred at (3, 0): ρ = 1.
        let rho = max_radius_ray_disk(Point::new(0.0, 0.0), [1.0, 0.0], Point::new(3.0, 0.0), 1.0);
        assert!((rho - 1.0).abs() < 1e-12);
    }

    #[test]
    fn area_disk_disk_example() {
        let o = Point::new(0.0, 0.0);
        assert!((area_disk_disk(o, 1.0, o, 2.0) - std::f64::consts::PI).abs() < 1e-12);
        assert_eq!(area_disk_disk(o, 1.0, Point::new(3.0, 0.0), 1.0), 0.0);
    }

    #[test]
    fn area_polygon_box_example() {
        let triangle = [(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)].map(|(x, y)| Point::new(x, y));
        assert_eq!(area_polygon_box(&triangle, 0.0, 1.0, 0.0, 1.0), 1.0);
        assert_eq!(area_polygon_box(&triangle, 1.0, 2.0, 1.0, 2.0), 0.0);
    }

    #[test]
    fn circles_apart_nested_and_concentric_do_not_intersect() {
        let o = Point::new(0.0, 0.0);
        assert!(intersect_circle_circle(o, 1.0, Point::new(3.0, 0.0), 1.0).is_none());
        assert!(intersect_circle_circle(o, 3.0, Point::new(0.5, 0.0), 1.0).is_none());
        assert!(intersect_circle_circle(o, 1.0, o, 1.0).is_none());
    }

    #[test]
    fn intersections_lie_on_both_circles() {
        let (c1, r1, c2, r2) = (Point::new(1.0, 2.0), 1.3, Point::new(2.1, 2.7), 0.9);
        let pts = intersect_circle_circle(c1, r1, c2, r2).unwrap();
        for p in pts {
            assert!(((p - c1).norm() - r1).abs() < 1e-12);
            assert!(((p - c2).norm() - r2).abs() < 1e-12);
        }
        assert!((pts[0] - pts[1]).norm() > 0.1);
    }

    #[test]
    fn near_tangent_circles_give_the_tangent_point() {
        let c1 = Point::new(0.0, 0.0);
        let c2 = Point::new(2.0 * (1.0 + 1e-14), 0.0);
        let [p, q] = intersect_circle_circle(c1, 1.0, c2, 1.0).expect("tangent point kept");
        assert!((p - q).norm() < 1e-12 && (p.x - 1.0).abs() < 1e-12);
        // A real gap is not papered over.
        let c3 = Point::new(2.0 * (1.0 + 1e-9), 0.0);
        assert!(intersect_circle_circle(c1, 1.0, c3, 1.0).is_none());
    }

    /// The scales every scale test runs: 10⁻⁶ to 10⁶ and powers of two near them.
    const SCALES: [f64; 9] = [
        1e-6,
        1e-3,
        1.0,
        1e3,
        1e6,
        9.5367431640625e-7, // 2⁻²⁰
        0.0009765625,       // 2⁻¹⁰
        1024.0,
        1048576.0,
    ];

    #[test]
    fn near_tangent_circles_give_the_tangent_point_at_every_scale() {
        for s in SCALES {
            for (r1, r2) in [(1.0, 1.0), (0.3, 2.0), (5.0, 0.01)] {
                let (r1, r2) = (r1 * s, r2 * s);
                let c1 = Point::new(-0.7 * s, 0.4 * s);
                let dir = Vector2::new(0.6, 0.8);
                // Apart by 1e-14 of the radii sum: tangent, the point on both.
                let c2 = c1 + dir * ((r1 + r2) * (1.0 + 1e-14));
                let [p, q] = intersect_circle_circle(c1, r1, c2, r2)
                    .unwrap_or_else(|| panic!("scale {s}: tangent point lost"));
                // On both circles; near the tangent point to the square root of
                // the rounding (intersections of nearly tangent circles are
                // ill-conditioned along the tangent).
                let want = c1 + dir * r1;
                for x in [p, q] {
                    let (on1, on2) = ((x - c1).norm() - r1, (x - c2).norm() - r2);
                    let tol = 1e-12 * (r1 + r2);
                    assert!(
                        on1.abs() <= tol && on2.abs() <= tol,
                        "scale {s}: {on1} {on2}"
                    );
                    assert!(
                        (x - want).norm() <= 1e-6 * (r1 + r2),
                        "scale {s}: {x} vs {want}"
                    );
                }
                // Apart by 1e-9: a real gap at every scale.
                let c3 = c1 + dir * ((r1 + r2) * (1.0 + 1e-9));
                assert!(
                    intersect_circle_circle(c1, r1, c3, r2).is_none(),
                    "scale {s}"
                );
                // Internally tangent (the smaller inside the larger) likewise.
                let (big, small) = (r1.max(r2), r1.min(r2));
                if big > small {
                    let c4 = c1 + dir * ((big - small) * (1.0 - 1e-14));
                    assert!(intersect_circle_circle(c1, big, c4, small).is_some(), "{s}");
                }
            }
        }
    }

    #[test]
    fn coincident_centres_give_no_intersection_at_any_scale() {
        for s in SCALES {
            for c in [Point::origin(), Point::new(1e6 * s, -3e6 * s)] {
                assert!(intersect_circle_circle(c, s, c, s).is_none(), "scale {s}");
                assert!(intersect_circle_circle(c, s, c, 2.0 * s).is_none());
                assert!(chord_circle_circle(c, 0.0, c, 0.0).is_none());
            }
        }
    }

    #[test]
    fn chord_offsets_keep_the_radii_far_from_the_origin() {
        // Two unit circles 10⁶ from the origin: the points carry the
        // coordinates' rounding (an ulp is 1.2e-10 there), the offsets only
        // the radii's.
        for o in [0.0, 1e3, 1e6, -1e6] {
            let c1 = Point::new(o + 0.1, o - 0.3);
            let (c2, r1, r2) = (Point::new(o + 1.3, o + 0.2), 1.0, 0.7);
            let chord = chord_circle_circle(c1, r1, c2, r2).unwrap();
            let rel = c2 - c1; // exact: both within a factor two of each other
            for (v, p) in chord.offsets().iter().zip(chord.points(c1)) {
                assert!((v.coords.norm() - r1).abs() <= 1e-15, "{o}: {v}");
                assert!(((v.coords - rel).norm() - r2).abs() <= 1e-15, "{o}: {v}");
                let ulp = f64::EPSILON * o.abs().max(1.0);
                assert!(((p - c1).norm() - r1).abs() <= 4.0 * ulp, "{o}: {p}");
            }
            assert_eq!(
                chord.points(c1),
                intersect_circle_circle(c1, r1, c2, r2).unwrap()
            );
        }
    }

    #[test]
    fn lines_far_from_the_origin_keep_their_tangents() {
        // Coordinates up to 10⁶ radii from the origin (the resolution the
        // config allows, `RESOLUTION_REL`), at every scale.
        for s in SCALES {
            for o in [0.0, 1e3, 1e6, -1e6] {
                let o = o * s;
                let ulp = f64::EPSILON * o.abs().max(s);
                // A wall along x through (o, o) and a circle on it: its radius
                // is the centre's height above the wall, exactly.
                let c = Point::new(o + 3.0 * s, o + s);
                let r = c.y - o;
                let q = Point::new(o, o);
                let [t0, t1] = intersect_circle_line(c, r, q, 1.0, 0.0)
                    .unwrap_or_else(|| panic!("scale {s} offset {o}: tangent lost"));
                assert!(
                    (t0 - 3.0 * s).abs() <= 4.0 * ulp,
                    "scale {s} offset {o}: {t0}"
                );
                assert_eq!(t0, t1, "scale {s} offset {o}");
                // 1e-9 of the radius above the wall: a real gap.
                let up = Point::new(c.x, c.y + 1e-9 * r + 4.0 * ulp);
                assert!(intersect_circle_line(up, r, q, 1.0, 0.0).is_none());
                // A wall turned 30° through (o, o); circles 10³ radii along it,
                // 1e-6 of the radius nearer and farther than tangent.
                let (uy, ux) = 30f64.to_radians().sin_cos();
                let along = 1e3 * s;
                let at = |h: f64| Point::new(o + ux * along - uy * h, o + uy * along + ux * h);
                let [a, b] = intersect_circle_line(at(s * (1.0 - 1e-6)), s, q, ux, uy)
                    .unwrap_or_else(|| panic!("scale {s} offset {o}: turned tangent lost"));
                let mid = 0.5 * (a + b);
                assert!(
                    (mid - along).abs() <= 1e-9 * along,
                    "scale {s} offset {o}: {mid}"
                );
                assert!((b - a - 2.0 * s * 2e-6f64.sqrt()).abs() <= 1e-3 * (b - a));
                assert!(intersect_circle_line(at(s * (1.0 + 1e-6)), s, q, ux, uy).is_none());
            }
        }
    }

    #[test]
    fn wall_clearance_forgives_rounding_not_penetration() {
        for s in SCALES {
            let d = Domain::rectangle(4.0 * s, 2.0 * s).unwrap();
            let r = s;
            assert!(clear_disk_walls(&d, Point::new(r, r), r), "scale {s}");
            assert!(clear_disk_walls(&d, Point::new(r, r * (1.0 - 1e-12)), r));
            assert!(!clear_disk_walls(&d, Point::new(r, r * (1.0 - 1e-9)), r));
        }
        // 10⁶ from the origin, a disk of radius 1 tangent to the wall x = 10⁶:
        // a point rounded an ulp inside is still clear, 1e-9 inside is not.
        let o = 1e6;
        let square =
            [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)].map(|(x, y)| Point::new(o + x, o + y));
        let d = Domain::polygon(&square).unwrap();
        let at = Point::new(o + 1.0, o + 2.0);
        assert!(clear_disk_walls(&d, at, 1.0));
        let rounded = Point::new((o + 1.0).next_down(), o + 2.0);
        assert!(clear_disk_walls(&d, rounded, 1.0));
        assert!(!clear_disk_walls(
            &d,
            Point::new(o + 1.0 - 1e-9, o + 2.0),
            1.0
        ));
    }

    #[test]
    fn line_intersections_are_on_the_circle() {
        let c = Point::new(1.0, 1.0);
        let [t0, t1] = intersect_circle_line(c, 2.0, Point::new(0.0, 0.5), 1.0, 0.0).unwrap();
        for t in [t0, t1] {
            let p = Point::new(t, 0.5);
            assert!(((p - c).norm() - 2.0).abs() < 1e-12);
        }
        assert!(intersect_circle_line(c, 0.4, Point::new(0.0, 0.5), 1.0, 0.0).is_none());
    }

    #[test]
    fn ray_radius_is_the_tangent_radius() {
        let t = Point::new(0.5, -0.25);
        let (c, rc) = (Point::new(1.7, 1.1), 0.6);
        for u in [[0.6, 0.8], [1.0, 0.0], [0.0, 1.0]] {
            let rho = max_radius_ray_disk(t, u, c, rc);
            let p = Point::new(t.x + rho * u[0], t.y + rho * u[1]);
            assert!(((p - c).norm() - (rc + rho)).abs() < 1e-12, "{u:?}: {rho}");
        }
        // Pointing away from the disk: any radius fits.
        assert_eq!(max_radius_ray_disk(t, [-1.0, 0.0], c, rc), f64::INFINITY);
    }

    #[test]
    fn clearance_follows_the_tolerance_policy() {
        let o = Point::new(0.0, 0.0);
        assert!(clear_disk_disk(Point::new(2.0, 0.0), 1.0, o, 1.0));
        assert!(clear_disk_disk(Point::new(2.0 - 1e-13, 0.0), 1.0, o, 1.0));
        assert!(!clear_disk_disk(Point::new(2.0 - 1e-9, 0.0), 1.0, o, 1.0));
    }

    #[test]
    fn disk_box_area_with_a_tangent_edge_is_the_disk() {
        // Regression: the box's top edge tangent to the disk counted a rectangle.
        let c = Point::new(9.2, 9.2);
        let whole = area_disk_box(c, 0.8, 7.0, 11.0, 8.0, 10.0);
        assert!((whole - PI * 0.64).abs() < 1e-12, "{whole}");
        let below = area_disk_box(c, 0.8, 7.0, 11.0, 8.4, 10.0);
        assert!((below - PI * 0.64).abs() < 1e-12, "{below}");
    }

    #[test]
    fn disk_disk_area_matches_sampling() {
        let (c1, r1, c2, r2) = (Point::new(0.0, 0.0), 1.0, Point::new(1.2, 0.4), 0.8);
        let n = 2000;
        let mut hits = 0u64;
        for i in 0..n {
            for j in 0..n {
                let p = Point::new(
                    -1.0 + 2.0 * (i as f64 + 0.5) / n as f64,
                    -1.0 + 2.0 * (j as f64 + 0.5) / n as f64,
                );
                if (p - c1).norm() < r1 && (p - c2).norm() < r2 {
                    hits += 1;
                }
            }
        }
        let sampled = hits as f64 / (n * n) as f64 * 4.0;
        let exact = area_disk_disk(c1, r1, c2, r2);
        assert!((exact - sampled).abs() < 1e-4, "{exact} vs {sampled}");
        assert!((area_disk_disk(c1, r1, c2, r2) - area_disk_disk(c2, r2, c1, r1)).abs() < 1e-15);
    }

    #[test]
    fn disk_box_area_matches_cases_and_sampling() {
        let c = Point::new(0.0, 0.0);
        let full = area_disk_box(c, 1.0, -2.0, 2.0, -2.0, 2.0);
        assert!((full - PI).abs() < 1e-12);
        let half = area_disk_box(c, 1.0, 0.0, 2.0, -2.0, 2.0);
        assert!((half - PI / 2.0).abs() < 1e-12);
        let quarter = area_disk_box(c, 1.0, 0.0, 2.0, 0.0, 2.0);
        assert!((quarter - PI / 4.0).abs() < 1e-12);
        assert_eq!(area_disk_box(c, 1.0, 1.0, 2.0, 1.0, 2.0), 0.0);
        // Awkward box cutting the disk on all sides, against a fine midpoint grid.
        let (x0, x1, y0, y1) = (-0.7, 0.4, -0.9, 0.95);
        let n = 2000;
        let mut hits = 0u64;
        for i in 0..n {
            for j in 0..n {
                let x = x0 + (x1 - x0) * (i as f64 + 0.5) / n as f64;
                let y = y0 + (y1 - y0) * (j as f64 + 0.5) / n as f64;
                if x * x + y * y < 1.0 {
                    hits += 1;
                }
            }
        }
        let sampled = hits as f64 / (n * n) as f64 * (x1 - x0) * (y1 - y0);
        let exact = area_disk_box(c, 1.0, x0, x1, y0, y1);
        assert!((exact - sampled).abs() < 1e-4, "{exact} vs {sampled}");
    }

    #[test]
    fn polygon_box_area_matches_cases_and_sampling() {
        let pts = |v: &[(f64, f64)]| v.iter().map(|&(x, y)| Point::new(x, y)).collect::<Vec<_>>();
        let square = pts(&[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]);
        assert_eq!(area_polygon_box(&square, -1.0, 5.0, -1.0, 5.0), 16.0);
        assert_eq!(area_polygon_box(&square, 1.0, 2.0, 1.0, 3.0), 2.0);
        assert_eq!(area_polygon_box(&square, 3.0, 6.0, 3.0, 6.0), 1.0);
        assert_eq!(area_polygon_box(&square, 5.0, 6.0, 0.0, 1.0), 0.0);
        assert_eq!(area_polygon_box(&square, 1.0, 1.0, 0.0, 1.0), 0.0);
        // Clockwise input gives the same area.
        let clockwise: Vec<Point> = square.iter().rev().copied().collect();
        assert_eq!(area_polygon_box(&clockwise, 3.0, 6.0, 3.0, 6.0), 1.0);
        // A concave L: the box straddles the notch.
        let l = pts(&[
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 1.0),
            (1.0, 1.0),
            (1.0, 4.0),
            (0.0, 4.0),
        ]);
        assert!((area_polygon_box(&l, 0.5, 3.0, 0.5, 3.0) - (2.5 * 0.5 + 0.5 * 2.0)).abs() < 1e-12);
        // A concave comb with a spike, cut across its teeth: a strip under
        // the teeth (4.3 × 0.3), the two teeth (0.7 × 1.2 and 0.6 × 1.2) and
        // the spike's trapezoid (∫ (3 − y)/2 dy from 1 to 2.2 = 0.84).
        let comb = pts(&[
            (0.0, 0.0),
            (5.0, 0.0),
            (5.0, 3.0),
            (4.0, 3.0),
            (4.0, 1.0),
            (3.0, 1.0),
            (2.5, 3.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 3.0),
            (0.0, 3.0),
        ]);
        let exact = area_polygon_box(&comb, 0.3, 4.6, 0.7, 2.2);
        assert!(
            (exact - (1.29 + 0.84 + 0.72 + 0.84)).abs() < 1e-12,
            "{exact}"
        );
    }
}
