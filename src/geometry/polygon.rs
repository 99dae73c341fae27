//! Simple-polygon routines behind [`Domain`](super::Domain): validation,
//! area and centroid, reflex corners, signed distance.
//!
//! Every decision about *which side* of a line a point lies on goes through
//! [`orient_2d`], an orientation test that is exact for finite inputs (fast
//! floating-point filter, exact expansion arithmetic when the filter cannot
//! decide, after Shewchuk's `orient2d`). Distances are plain floating point.
//! The routine is private to the geometry module; it belongs with the other
//! predicates in `predicates.rs` once that file exists.

use nalgebra::Vector2;

use super::{GeometryError, Point};

/// Two polygon vertices closer than this fraction of the bounding-box
/// diagonal count as repeated.
const REPEATED_VERTEX_REL: f64 = 1e-12;
/// A polygon whose |area| is at most this fraction of its bounding-box area
/// is degenerate.
const ZERO_AREA_REL: f64 = 1e-10;
/// Adjacent edges with |sin(angle between them)| at most this that turn back
/// on themselves form a spike.
const SPIKE_SIN: f64 = 1e-12;

/// Sign of the orientation of the triangle `(a, b, c)`: positive if
/// counter-clockwise (`c` left of `a → b`), negative if clockwise, zero if
/// collinear.
///
/// # Behavior
/// The sign is exact for finite inputs whose products neither overflow nor
/// underflow (|coordinates| between about 1e-140 and 1e140, or zero). The
/// magnitude is the floating-point determinant `(a−c)×(b−c)` when the
/// filter decides, and ±1 or 0 when the exact stage decides.
///
/// # Performance
/// One determinant and one comparison in the common case.
pub(crate) fn orient_2d(a: Point, b: Point, c: Point) -> f64 {
    /// Shewchuk's `ccwerrboundA = (3 + 16ε)ε` with ε = 2⁻⁵³.
    const ERR_BOUND_A: f64 = (3.0 + 16.0 * f64::EPSILON / 2.0) * f64::EPSILON / 2.0;
    let left = (a.x - c.x) * (b.y - c.y);
    let right = (a.y - c.y) * (b.x - c.x);
    let det = left - right;
    let bound = ERR_BOUND_A * (left.abs() + right.abs());
    if det > bound || -det > bound {
        return det;
    }
    orient_2d_exact(a, b, c)
}

/// Exact sign of `(a−c)×(b−c)`, expanded as
/// `ax·by − ax·cy − cx·by − ay·bx + ay·cx + cy·bx` (the `cx·cy` terms
/// cancel); each product is split exactly with a fused multiply-add and the
/// twelve parts are summed into a non-overlapping expansion.
fn orient_2d_exact(a: Point, b: Point, c: Point) -> f64 {
    let products = [
        (a.x, b.y),
        (-a.x, c.y),
        (-c.x, b.y),
        (-a.y, b.x),
        (a.y, c.x),
        (c.y, b.x),
    ];
    let mut expansion = [0.0_f64; 12];
    let mut len = 0;
    for (u, v) in products {
        let p = u * v;
        let e = u.mul_add(v, -p);
        for term in [e, p] {
            // Shewchuk's Grow-Expansion: add `term` into the expansion,
            // keeping the components non-overlapping and increasing.
            let mut q = term;
            for h in expansion.iter_mut().take(len) {
                let (s, err) = two_sum(q, *h);
                *h = err;
                q = s;
            }
            expansion[len] = q;
            len += 1;
        }
    }
    // The sign of a non-overlapping expansion is that of its largest
    // non-zero component, the last one.
    expansion[..len]
        .iter()
        .rev()
        .find(|h| **h != 0.0)
        .map_or(0.0, |h| h.signum())
}

/// `a + b` as a rounded sum and its exact rounding error (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bv = s - a;
    let av = s - bv;
    (s, (a - av) + (b - bv))
}

/// Whether the closed segments `p0-p1` and `q0-q1` share at least one point
/// (crossing, touching or overlapping), decided with exact orientations.
pub(crate) fn intersect_segment_segment(p0: Point, p1: Point, q0: Point, q1: Point) -> bool {
    let d1 = orient_2d(p0, p1, q0);
    let d2 = orient_2d(p0, p1, q1);
    let d3 = orient_2d(q0, q1, p0);
    let d4 = orient_2d(q0, q1, p1);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && in_box(p0, p1, q0))
        || (d2 == 0.0 && in_box(p0, p1, q1))
        || (d3 == 0.0 && in_box(q0, q1, p0))
        || (d4 == 0.0 && in_box(q0, q1, p1))
}

/// Whether `p` lies in the axis-aligned box spanned by `a` and `b` (closed);
/// for a `p` collinear with `a`, `b` this means `p` is on the segment.
fn in_box(a: Point, b: Point, p: Point) -> bool {
    a.x.min(b.x) <= p.x && p.x <= a.x.max(b.x) && a.y.min(b.y) <= p.y && p.y <= a.y.max(b.y)
}

/// Checks that `input` is a simple polygon and returns its vertices
/// counter-clockwise.
///
/// # Behavior
/// A last vertex exactly equal to the first (an explicitly closed ring) is
/// dropped. Refused, in this order: a non-finite coordinate, fewer than 3
/// vertices (counted after that drop), coordinates whose span overflows,
/// consecutive vertices closer than 1e-12 of the bounding-box diagonal, a
/// spike (adjacent edges folding back on each other within 1e-12 rad), two
/// non-adjacent edges that cross, touch or
/// overlap (exact test; edge `i` runs from vertex `i` to vertex `i + 1`,
/// indices of the input), and an area at most 1e-10 of the bounding-box area.
/// A vertex in the middle of a straight edge is kept.
///
/// More than [`Domain::MAX_POLYGON_VERTICES`](super::Domain::MAX_POLYGON_VERTICES)
/// vertices are refused first.
///
/// # Performance
/// O(n²) for the self-intersection test: at most 8·10⁶ segment pairs
/// under the vertex cap (0.2 s; 100,000 vertices took 74 s).
pub(crate) fn validate_polygon(input: &[Point]) -> Result<Vec<Point>, GeometryError> {
    let max = super::Domain::MAX_POLYGON_VERTICES;
    // A closing repeat of the first vertex is dropped below, so allow one more.
    if input.len() > max + 1 || (input.len() == max + 1 && input.first() != input.last()) {
        return Err(GeometryError::TooManyVertices {
            count: input.len(),
            max,
        });
    }
    if let Some(index) = input
        .iter()
        .position(|p| !p.x.is_finite() || !p.y.is_finite())
    {
        return Err(GeometryError::NonFiniteVertex { index });
    }
    let mut v = input.to_vec();
    if v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    let n = v.len();
    if n < 3 {
        return Err(GeometryError::TooFewVertices(n));
    }
    let (lo, hi) = bounds_of(&v);
    let extent = hi - lo;
    if !extent.x.is_finite() || !extent.y.is_finite() {
        return Err(GeometryError::Degenerate(
            "the vertices span a range too large for floating point".into(),
        ));
    }
    let diagonal = extent.x.hypot(extent.y);
    for i in 0..n {
        let j = (i + 1) % n;
        if (v[j] - v[i]).norm() <= REPEATED_VERTEX_REL * diagonal {
            return Err(GeometryError::Degenerate(format!(
                "vertices {i} and {j} coincide at ({}, {})",
                v[i].x, v[i].y
            )));
        }
    }
    for i in 0..n {
        let prev = v[(i + n - 1) % n];
        let next = v[(i + 1) % n];
        let e1 = v[i] - prev;
        let e2 = next - v[i];
        let collinear = orient_2d(prev, v[i], next) == 0.0
            || e1.perp(&e2).abs() <= SPIKE_SIN * e1.norm() * e2.norm();
        if collinear && e1.dot(&e2) < 0.0 {
            return Err(GeometryError::Degenerate(format!(
                "spike at vertex {i} ({}, {}): its two edges fold back on each other",
                v[i].x, v[i].y
            )));
        }
    }
    for i in 0..n {
        for j in (i + 2)..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            if intersect_segment_segment(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]) {
                return Err(GeometryError::SelfIntersecting {
                    first: i,
                    first_from: i,
                    first_to: (i + 1) % n,
                    second: j,
                });
            }
        }
    }
    let area = signed_area(&v);
    if area.abs() <= ZERO_AREA_REL * extent.x * extent.y || !area.is_finite() {
        return Err(GeometryError::Degenerate(format!(
            "area {} is (near) zero or not finite for a bounding box {} × {}",
            area.abs(),
            extent.x,
            extent.y
        )));
    }
    if area < 0.0 {
        v.reverse();
    }
    Ok(v)
}

/// Axis-aligned bounds `(min, max)` of a non-empty vertex list.
pub(crate) fn bounds_of(v: &[Point]) -> (Point, Point) {
    let first = v.first().copied().unwrap_or_else(Point::origin);
    v.iter().fold((first, first), |(lo, hi), p| {
        (
            Point::new(lo.x.min(p.x), lo.y.min(p.y)),
            Point::new(hi.x.max(p.x), hi.y.max(p.y)),
        )
    })
}

/// Signed area (shoelace, positive counter-clockwise), taken relative to the
/// first vertex to limit cancellation.
pub(crate) fn signed_area(v: &[Point]) -> f64 {
    let Some(&o) = v.first() else { return 0.0 };
    let twice: f64 = v.windows(2).map(|w| (w[0] - o).perp(&(w[1] - o))).sum();
    0.5 * twice
}

/// Area centroid of a polygon with non-zero area (either orientation).
pub(crate) fn centroid_of(v: &[Point]) -> Point {
    let Some(&o) = v.first() else {
        return Point::origin();
    };
    let mut twice_area = 0.0;
    let mut moment = Vector2::zeros();
    for w in v.windows(2) {
        let (a, b) = (w[0] - o, w[1] - o);
        let cross = a.perp(&b);
        twice_area += cross;
        moment += (a + b) * cross;
    }
    o + moment / (3.0 * twice_area)
}

/// Vertices of a counter-clockwise polygon whose interior angle exceeds 180°
/// (exact test; a vertex on a straight edge is not reflex).
pub(crate) fn reflex_vertices_of(v: &[Point]) -> Vec<Point> {
    let n = v.len();
    (0..n)
        .filter(|&i| orient_2d(v[(i + n - 1) % n], v[i], v[(i + 1) % n]) < 0.0)
        .map(|i| v[i])
        .collect()
}

/// One polygon edge with what the distance query needs precomputed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Edge {
    /// Start vertex.
    pub(crate) a: Point,
    /// End vertex.
    pub(crate) b: Point,
    /// `b − a`.
    pub(crate) d: Vector2<f64>,
    /// `1 / |b − a|²`.
    pub(crate) inv_len_2: f64,
}

/// The edges of a polygon, vertex `i` to vertex `i + 1`, closing edge last.
pub(crate) fn edges_of(v: &[Point]) -> Vec<Edge> {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            let d = b - a;
            Edge {
                a,
                b,
                d,
                inv_len_2: 1.0 / d.norm_squared(),
            }
        })
        .collect()
}

/// Squared distance from `p` to the edge's closed segment.
fn distance_point_segment_2(p: Point, e: &Edge) -> f64 {
    let t = ((p - e.a).dot(&e.d) * e.inv_len_2).clamp(0.0, 1.0);
    (p - (e.a + e.d * t)).norm_squared()
}

/// Signed distance from `p` to the boundary of a simple polygon given by its
/// edges: positive inside, negative outside.
///
/// # Behavior
/// The magnitude is the floating-point distance to the nearest edge (a few
/// ulps of the coordinates); the sign comes from a winding number computed
/// with exact orientations, so it is right for every point not on the
/// boundary. Points on the boundary give ±(rounding-size value), effectively
/// zero.
///
/// # Performance
/// O(n) in the number of edges, one pass.
pub(crate) fn signed_distance_point_polygon(p: Point, edges: &[Edge]) -> f64 {
    let mut best_2 = f64::INFINITY;
    let mut winding = 0_i32;
    for e in edges {
        best_2 = best_2.min(distance_point_segment_2(p, e));
        if e.a.y <= p.y {
            if e.b.y > p.y && orient_2d(e.a, e.b, p) > 0.0 {
                winding += 1;
            }
        } else if e.b.y <= p.y && orient_2d(e.a, e.b, p) < 0.0 {
            winding -= 1;
        }
    }
    let d = best_2.sqrt();
    if winding != 0 { d } else { -d }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn orient_2d_basic_signs() {
        assert!(orient_2d(p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0)) > 0.0);
        assert!(orient_2d(p(0.0, 0.0), p(0.0, 1.0), p(1.0, 0.0)) < 0.0);
        assert_eq!(orient_2d(p(0.0, 0.0), p(1.0, 1.0), p(3.0, 3.0)), 0.0);
    }

    /// Shewchuk's near-degenerate grid: points within a few ulps of the line
    /// through (12, 12) and (24, 24). Every coordinate is an integer multiple
    /// of 2⁻⁵³, so the exact determinant fits in an `i128`.
    #[test]
    fn orient_2d_matches_exact_integer_arithmetic_near_a_line() {
        let unit = 2f64.powi(-53);
        let to_int = |x: f64| (x / unit) as i128;
        let (b, c) = (p(12.0, 12.0), p(24.0, 24.0));
        let mut naive_wrong = 0;
        for i in 0..128 {
            for j in 0..128 {
                let a = p(0.5 + f64::from(i) * unit, 0.5 + f64::from(j) * unit);
                let det = (to_int(a.x) - to_int(c.x)) * (to_int(b.y) - to_int(c.y))
                    - (to_int(a.y) - to_int(c.y)) * (to_int(b.x) - to_int(c.x));
                let got = orient_2d(a, b, c);
                assert_eq!(got.partial_cmp(&0.0), Some(det.cmp(&0)), "i={i} j={j}");
                let naive = (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
                if naive.partial_cmp(&0.0) != Some(det.cmp(&0)) {
                    naive_wrong += 1;
                }
            }
        }
        // The grid is only a meaningful test if plain floating point fails on it.
        assert!(naive_wrong > 0);
    }

    #[test]
    fn segments_crossing_touching_overlapping_and_apart() {
        let s = |a: (f64, f64), b: (f64, f64), c: (f64, f64), d: (f64, f64)| {
            intersect_segment_segment(p(a.0, a.1), p(b.0, b.1), p(c.0, c.1), p(d.0, d.1))
        };
        assert!(s((0.0, 0.0), (2.0, 2.0), (0.0, 2.0), (2.0, 0.0)));
        assert!(s((0.0, 0.0), (2.0, 0.0), (1.0, 0.0), (1.0, 5.0)));
        assert!(s((0.0, 0.0), (2.0, 0.0), (2.0, 0.0), (3.0, 1.0)));
        assert!(s((0.0, 0.0), (2.0, 0.0), (1.0, 0.0), (3.0, 0.0)));
        assert!(!s((0.0, 0.0), (2.0, 0.0), (2.5, 0.0), (3.0, 0.0)));
        assert!(!s((0.0, 0.0), (2.0, 0.0), (1.0, 0.1), (1.0, 5.0)));
        assert!(!s((0.0, 0.0), (1.0, 1.0), (3.0, 0.0), (2.0, 1.0)));
    }

    #[test]
    fn explicit_closing_vertex_is_dropped() {
        let v = validate_polygon(&[p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0), p(0.0, 0.0)]);
        assert_eq!(v, Ok(vec![p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0)]));
    }

    #[test]
    fn centroid_and_area_of_a_unit_square_ccw_and_cw() {
        let sq = [p(1.0, 1.0), p(3.0, 1.0), p(3.0, 3.0), p(1.0, 3.0)];
        assert_eq!(signed_area(&sq), 4.0);
        let mut cw = sq;
        cw.reverse();
        assert_eq!(signed_area(&cw), -4.0);
        assert!((centroid_of(&cw) - p(2.0, 2.0)).norm() < 1e-15);
    }
}
