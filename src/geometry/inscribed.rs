//! Largest disk inside a simple polygon.
//!
//! The centre of a largest inscribed disk is a vertex of the polygon's medial
//! axis: a point equidistant from three *features*, each either the line of
//! an edge (touched inside that edge) or a reflex vertex. Convex corners
//! never touch a disk of positive radius, and where two parallel edges make
//! the maximum a flat ridge, the ridge ends at such a vertex with the same
//! value. [`max_inscribed_radius_polygon`] therefore solves every triple of
//! features for its equidistant points and keeps the best signed distance it
//! finds there. Every value it keeps is the signed distance of an actual
//! point, so the result never overestimates; it is exact up to rounding.
//! Above [`MAX_ENUMERATED_FEATURES`] features the O(F³) enumeration gives
//! way to a branch and bound on the signed distance.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;

use nalgebra::Vector2;

use super::Point;
use super::polygon::{Edge, bounds_of, signed_distance_point_polygon};

/// Most features (edges + reflex vertices) solved by enumeration of triples.
const MAX_ENUMERATED_FEATURES: usize = 200;
/// Work budget of the branch and bound, in point-to-edge distances.
const BRANCH_AND_BOUND_WORK: usize = 20_000_000;
/// The branch and bound stops once no cell can beat the best value found by
/// more than this fraction of it.
const BRANCH_AND_BOUND_REL: f64 = 1e-4;
/// Slack, as a fraction of the edge length, for a tangent point to count as
/// inside its edge.
const FOOT_TOL: f64 = 1e-9;
/// Cells per side of the grid that seeds the best value.
const SEED_GRID: u32 = 8;

/// Radius of the largest disk inside the simple counter-clockwise polygon
/// with these vertices, edges and reflex vertices.
///
/// # Behavior
/// With at most 200 features (edges + reflex vertices): exact up to rounding
/// (relative error ~1e-12), by enumeration of medial-axis vertices. Above:
/// a branch and bound with relative precision 1e-4 within a fixed work
/// budget (2·10⁷ point-edge distances); should the budget run out the best
/// value found so far is returned, a lower bound. Never negative.
///
/// # Performance
/// O(F³) for F ≤ 200 features (about 1.3·10⁶ triples at the limit, each O(1)
/// unless it could beat the best value so far), bounded work above.
pub(crate) fn max_inscribed_radius_polygon(
    vertices: &[Point],
    edges: &[Edge],
    reflex: &[Point],
) -> f64 {
    let (lo, hi) = bounds_of(vertices);
    let sdf = |p: Point| signed_distance_point_polygon(p, edges);
    let seed = seed_grid(lo, hi, &sdf);
    let best = if edges.len() + reflex.len() <= MAX_ENUMERATED_FEATURES {
        medial_axis_vertices(lo, hi, edges, reflex, seed)
    } else {
        let budget = BRANCH_AND_BOUND_WORK / edges.len().max(1);
        branch_and_bound(lo, hi, seed, budget, &sdf).0
    };
    best.max(0.0)
}

/// Best signed distance over the centres of a coarse grid on the bounds.
fn seed_grid(lo: Point, hi: Point, sdf: &impl Fn(Point) -> f64) -> f64 {
    let step = (hi - lo) / f64::from(SEED_GRID);
    let mut best = f64::NEG_INFINITY;
    for i in 0..SEED_GRID {
        for j in 0..SEED_GRID {
            let offset = Vector2::new((f64::from(i) + 0.5) * step.x, (f64::from(j) + 0.5) * step.y);
            best = best.max(sdf(lo + offset));
        }
    }
    best
}

/// The line through an edge, as seen from the polygon's inner side.
struct Line {
    /// Inward unit normal (left of the counter-clockwise edge).
    n: Vector2<f64>,
    /// `n · a`: the line is `n · p = k`.
    k: f64,
    /// The edge itself.
    edge: Edge,
}

impl Line {
    fn new(edge: &Edge) -> Self {
        let n = Vector2::new(-edge.d.y, edge.d.x) / edge.d.norm();
        Line {
            n,
            k: n.dot(&edge.a.coords),
            edge: *edge,
        }
    }

    /// Signed distance from `p` to the line, positive on the inner side.
    fn offset(&self, p: Point) -> f64 {
        self.n.dot(&p.coords) - self.k
    }

    /// Whether the foot of the perpendicular from `c` lies on the edge.
    fn foot_on_edge(&self, c: Point) -> bool {
        let t = (c - self.edge.a).dot(&self.edge.d) * self.edge.inv_len_2;
        (-FOOT_TOL..=1.0 + FOOT_TOL).contains(&t)
    }
}

/// The running maximum over candidate centres.
struct Search<'a> {
    edges: &'a [Edge],
    lo: Point,
    hi: Point,
    /// Half the smaller side of the bounds: no inscribed disk is larger.
    upper: f64,
    best: f64,
}

impl Search<'_> {
    /// Evaluates the candidate centre `c` (equidistant `r` from its features)
    /// unless it cannot be the centre of a larger inscribed disk.
    fn consider(&mut self, c: Point, r: f64, lines: &[&Line]) {
        let in_bounds =
            self.lo.x <= c.x && c.x <= self.hi.x && self.lo.y <= c.y && c.y <= self.hi.y;
        if r > self.best.max(0.0)
            && r <= self.upper
            && in_bounds
            && lines.iter().all(|l| l.foot_on_edge(c))
        {
            self.best = self.best.max(signed_distance_point_polygon(c, self.edges));
        }
    }
}

/// Best signed distance over all medial-axis vertex candidates.
fn medial_axis_vertices(lo: Point, hi: Point, edges: &[Edge], reflex: &[Point], seed: f64) -> f64 {
    let lines: Vec<Line> = edges.iter().map(Line::new).collect();
    let extent = hi - lo;
    let mut s = Search {
        edges,
        lo,
        hi,
        upper: 0.5 * extent.x.min(extent.y) * (1.0 + 1e-9),
        best: seed,
    };
    for (i, l1) in lines.iter().enumerate() {
        for (j, l2) in lines.iter().enumerate().skip(i + 1) {
            for l3 in &lines[j + 1..] {
                if let Some((c, r)) = equidistant_line_line_line(l1, l2, l3) {
                    s.consider(c, r, &[l1, l2, l3]);
                }
            }
            for &q in reflex {
                for (c, r) in equidistant_line_line_point(l1, l2, q).into_iter().flatten() {
                    s.consider(c, r, &[l1, l2]);
                }
            }
        }
        for (a, &q1) in reflex.iter().enumerate() {
            for &q2 in &reflex[a + 1..] {
                for (c, r) in equidistant_line_point_point(l1, q1, q2)
                    .into_iter()
                    .flatten()
                {
                    s.consider(c, r, &[l1]);
                }
            }
        }
    }
    for (a, &q1) in reflex.iter().enumerate() {
        for (b, &q2) in reflex.iter().enumerate().skip(a + 1) {
            for &q3 in &reflex[b + 1..] {
                if let Some((c, r)) = circumcircle_point_point_point(q1, q2, q3) {
                    s.consider(c, r, &[]);
                }
            }
        }
    }
    s.best
}

/// The point at equal inner distance `r` from three lines (`n_i · c − k_i = r`).
fn equidistant_line_line_line(l1: &Line, l2: &Line, l3: &Line) -> Option<(Point, f64)> {
    let (u, v) = (l1.n - l2.n, l1.n - l3.n);
    let det = u.perp(&v);
    if det.abs() <= 1e-12 {
        return None;
    }
    let (ku, kv) = (l1.k - l2.k, l1.k - l3.k);
    let c = Point::new((ku * v.y - kv * u.y) / det, (u.x * kv - v.x * ku) / det);
    Some((c, l1.offset(c)))
}

/// Points at equal inner distance `r` from two lines and distance `r` from `q`.
fn equidistant_line_line_point(l1: &Line, l2: &Line, q: Point) -> [Option<(Point, f64)>; 2] {
    let dn = l1.n - l2.n;
    let len_2 = dn.norm_squared();
    if len_2 <= 1e-24 {
        return [None, None];
    }
    // Centres equidistant from both lines: c0 + t·w.
    let c0 = Point::from(dn * ((l1.k - l2.k) / len_2));
    let w = Vector2::new(-dn.y, dn.x) / len_2.sqrt();
    let (alpha, beta) = (l1.offset(c0), l1.n.dot(&w));
    let d = c0 - q;
    // |c0 + t·w − q|² = (α + β·t)²
    roots_quadratic(
        1.0 - beta * beta,
        d.dot(&w) - alpha * beta,
        d.norm_squared() - alpha * alpha,
    )
    .map(|t| t.map(|t| (c0 + w * t, alpha + beta * t)))
}

/// Points at distance `r` from `q1` and `q2` and inner distance `r` from a line.
fn equidistant_line_point_point(l: &Line, q1: Point, q2: Point) -> [Option<(Point, f64)>; 2] {
    let e = q2 - q1;
    let len = e.norm();
    if len == 0.0 {
        return [None, None];
    }
    // Centres equidistant from both points: m + t·u, at distance √(a² + t²).
    let m = q1 + e * 0.5;
    let u = Vector2::new(-e.y, e.x) / len;
    let (alpha, beta) = (l.offset(m), l.n.dot(&u));
    // (α + β·t)² = a² + t²
    roots_quadratic(
        beta * beta - 1.0,
        alpha * beta,
        alpha * alpha - 0.25 * len * len,
    )
    .map(|t| t.map(|t| (m + u * t, alpha + beta * t)))
}

/// Centre and radius of the circle through three points, if not collinear.
fn circumcircle_point_point_point(q1: Point, q2: Point, q3: Point) -> Option<(Point, f64)> {
    let (b, c) = (q2 - q1, q3 - q1);
    let d = 2.0 * b.perp(&c);
    if d.abs() <= 1e-12 * b.norm() * c.norm() {
        return None;
    }
    let (b2, c2) = (b.norm_squared(), c.norm_squared());
    let u = Vector2::new(c.y * b2 - b.y * c2, b.x * c2 - c.x * b2) / d;
    Some((q1 + u, u.norm()))
}

/// Real roots of `a·t² + 2·b·t + c = 0` (numerically stable form). A
/// vanishing `a` yields one finite root and one non-finite value, which the
/// caller's bounds test discards; a slightly negative discriminant (a
/// tangency lost to rounding) counts as zero.
fn roots_quadratic(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    let mut disc = b * b - a * c;
    if disc < 0.0 {
        if disc < -1e-12 * (b * b + (a * c).abs()) {
            return [None, None];
        }
        disc = 0.0;
    }
    let q = -(b + disc.sqrt().copysign(b));
    if q == 0.0 {
        return [Some(0.0), None];
    }
    [Some(q / a), Some(c / q)]
}

/// A square cell of the branch and bound.
struct Cell {
    /// Centre.
    c: Point,
    /// Half the side.
    h: f64,
    /// Upper bound of the signed distance over the cell (it is 1-Lipschitz).
    bound: f64,
}

impl PartialEq for Cell {
    fn eq(&self, other: &Self) -> bool {
        self.bound.total_cmp(&other.bound) == Ordering::Equal
    }
}
impl Eq for Cell {}
impl PartialOrd for Cell {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Cell {
    fn cmp(&self, other: &Self) -> Ordering {
        self.bound.total_cmp(&other.bound)
    }
}

/// Maximum of a 1-Lipschitz `sdf` over the bounds, best cell first
/// (the polylabel scheme). Returns the best value and whether the search
/// completed — then the true maximum is at most `best·(1 + 1e-4)` (or
/// `best` if `best ≤ 0`) — rather than running out of `budget` evaluations.
fn branch_and_bound(
    lo: Point,
    hi: Point,
    seed: f64,
    budget: usize,
    sdf: &impl Fn(Point) -> f64,
) -> (f64, bool) {
    let extent = hi - lo;
    let long = extent.x.max(extent.y);
    // At most 64 initial cells along the longer side.
    let side = extent.x.min(extent.y).max(long / 64.0);
    let (nx, ny) = ((extent.x / side).ceil(), (extent.y / side).ceil());
    let mut best = seed;
    let mut evaluations = 0_usize;
    let mut heap = BinaryHeap::new();
    let add = |c: Point, h: f64, heap: &mut BinaryHeap<Cell>, best: &mut f64| {
        let d = sdf(c);
        *best = best.max(d);
        heap.push(Cell {
            c,
            h,
            bound: d + h * SQRT_2,
        });
    };
    let mut x = 0.0;
    while x < nx {
        let mut y = 0.0;
        while y < ny {
            let c = lo + Vector2::new((x + 0.5) * side, (y + 0.5) * side);
            add(c, 0.5 * side, &mut heap, &mut best);
            evaluations += 1;
            y += 1.0;
        }
        x += 1.0;
    }
    while let Some(cell) = heap.pop() {
        if cell.bound - best <= BRANCH_AND_BOUND_REL * best.max(0.0) {
            return (best, true);
        }
        if evaluations >= budget {
            return (best, false);
        }
        let h = 0.5 * cell.h;
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            add(
                cell.c + Vector2::new(sx * h, sy * h),
                h,
                &mut heap,
                &mut best,
            );
        }
        evaluations += 4;
    }
    (best, true)
}

#[cfg(test)]
mod tests {
    use super::super::polygon::{edges_of, reflex_vertices_of, validate_polygon};
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    fn parts(v: &[Point]) -> (Vec<Point>, Vec<Edge>, Vec<Point>) {
        let v = validate_polygon(v).expect("valid test polygon");
        let e = edges_of(&v);
        let r = reflex_vertices_of(&v);
        (v, e, r)
    }

    fn l_shape() -> Vec<Point> {
        [
            (0., 0.),
            (20., 0.),
            (20., 8.),
            (8., 8.),
            (8., 20.),
            (0., 20.),
        ]
        .map(|(x, y)| Point::new(x, y))
        .to_vec()
    }

    #[test]
    fn l_shape_by_enumeration_and_by_branch_and_bound() {
        let (v, e, r) = parts(&l_shape());
        let exact = 8.0 * (2.0 - SQRT_2);
        let got = max_inscribed_radius_polygon(&v, &e, &r);
        assert!((got - exact).abs() <= 1e-12 * exact, "{got} vs {exact}");
        let (lo, hi) = bounds_of(&v);
        let sdf = |p| signed_distance_point_polygon(p, &e);
        let (bb, done) = branch_and_bound(lo, hi, f64::NEG_INFINITY, 1_000_000, &sdf);
        assert!(done);
        assert!(bb <= exact * (1.0 + 1e-12) && bb * (1.0 + BRANCH_AND_BOUND_REL) >= exact);
    }

    #[test]
    fn long_strip_with_a_flat_ridge_is_exact() {
        let v = [(0., 0.), (1000., 0.), (1000., 1.), (500., 1.), (0., 1.)]
            .map(|(x, y)| Point::new(x, y));
        let (v, e, r) = parts(&v);
        assert!((max_inscribed_radius_polygon(&v, &e, &r) - 0.5).abs() <= 1e-12);
    }

    /// Random star-shaped polygons (simple by construction): the enumeration
    /// agrees with the branch and bound, whose completed result brackets the
    /// true maximum within 1e-4.
    #[test]
    fn enumeration_agrees_with_branch_and_bound_on_random_star_polygons() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(2009);
        for case in 0..25 {
            let n = rng.gen_range(3..=24);
            let mut angles: Vec<f64> = (0..n)
                .map(|_| rng.gen_range(0.0..std::f64::consts::TAU))
                .collect();
            angles.sort_by(f64::total_cmp);
            let v: Vec<Point> = angles
                .iter()
                .map(|a| {
                    let rho = rng.gen_range(3.0..10.0);
                    Point::new(50.0 + rho * a.cos(), -20.0 + rho * a.sin())
                })
                .collect();
            let Ok(valid) = validate_polygon(&v) else {
                continue;
            };
            let (v, e, r) = parts(&valid);
            let exact = max_inscribed_radius_polygon(&v, &e, &r);
            let (lo, hi) = bounds_of(&v);
            let sdf = |p| signed_distance_point_polygon(p, &e);
            let (bb, done) = branch_and_bound(lo, hi, f64::NEG_INFINITY, 2_000_000, &sdf);
            assert!(done, "case {case}");
            assert!(exact >= bb * (1.0 - 1e-12), "case {case}: {exact} < {bb}");
            assert!(
                exact <= bb * (1.0 + BRANCH_AND_BOUND_REL),
                "case {case}: {exact} > {bb}"
            );
        }
    }

    #[test]
    fn many_vertices_fall_back_to_branch_and_bound() {
        let n = 300;
        let radius = 7.0;
        let v: Vec<Point> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
                Point::new(radius * a.cos(), radius * a.sin())
            })
            .collect();
        let (v, e, r) = parts(&v);
        assert!(e.len() > MAX_ENUMERATED_FEATURES);
        let exact = radius * (std::f64::consts::PI / f64::from(n)).cos();
        let got = max_inscribed_radius_polygon(&v, &e, &r);
        assert!(got <= exact * (1.0 + 1e-12) && got * (1.0 + BRANCH_AND_BOUND_REL) >= exact);
    }

    #[test]
    fn quadratic_roots() {
        let mut r = roots_quadratic(1.0, -1.5, 2.0).map(Option::unwrap);
        r.sort_by(f64::total_cmp);
        assert_eq!(r, [1.0, 2.0]);
        assert_eq!(roots_quadratic(1.0, 0.0, 1.0), [None, None]);
        assert_eq!(roots_quadratic(0.0, 1.0, -4.0)[1], Some(2.0));
    }
}
