//! Clumps of overlapping disks standing for non-disk particles, for the DEM
//! codes that model every particle shape as a rigid clump of disks.
//!
//! Each particle gets a set of disks that all lie **inside** it, so the
//! clumps of two particles never overlap (the particles do not). The disks
//! are chosen greedily: the largest inscribed disk first, then again and
//! again the disk that adds the most uncovered area, until the covered
//! share of the particle reaches `coverage` or there are `max_disks` disks.
//!
//! # How a disk is certified inside
//! A disk's radius is the clearance of its centre from the polygon of
//! [`Outline::boundary`]`(`[`BOUNDARY_POINTS`]`)`, whose corners lie on
//! the outline: the polygon lies inside the convex particle, so a disk
//! inside it is inside the particle. The radius is then reduced by
//! [`MARGIN`] (of the area-equivalent radius) against rounding.
//!
//! # Memoised on the outline up to scale
//! The clump depends only on the particle's outline divided by its
//! area-equivalent radius; it is computed once per such unit outline
//! (its parameters rounded to [`KEY_DIGITS`] significant digits), then
//! scaled, turned and moved onto each particle, so that a packing of one
//! shape at many sizes costs one clump.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use nalgebra::Vector2;

use crate::geometry::{Grain, Outline, Point};
use crate::output::format::ClumpOptions;
use crate::packer::Packing;

/// Corners of the inscribed polygon the disks are fitted in.
pub(super) const BOUNDARY_POINTS: usize = 512;

/// Safety margin taken off every disk's radius, as a share of the
/// particle's area-equivalent radius: far above the rounding of the
/// outline's points and of the moves onto each particle, and above the
/// difference between two unit outlines that share a key.
pub(super) const MARGIN: f64 = 1e-6;

/// Significant digits of a unit outline's parameters in the memo's key.
pub(super) const KEY_DIGITS: i32 = 10;

/// Points of the grid on which the covered area is counted, over the
/// outline's bounding box.
const SAMPLES: f64 = 20_000.0;

/// Candidate centres of the grid over the outline's bounding box (the
/// particle's own axes and its centre are added to them).
const CANDIDATES: f64 = 2_500.0;

/// Candidate centres along each of the particle's own axes, where the
/// medial axis of a shape symmetric about them lies.
const AXIS_CANDIDATES: usize = 256;

/// One particle's clump, in the packing's axes (mm).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Clump {
    /// The disks: centre and radius (mm).
    pub(super) disks: Vec<(Point, f64)>,
    /// Share of the particle's area the disks cover (estimated on a grid of
    /// [`SAMPLES`] points over its bounding box); 1 for a disk.
    pub(super) coverage: f64,
}

/// Every particle's clump, with what they achieved.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Clumps {
    /// One clump per packed particle, in placement order.
    pub(super) clumps: Vec<Clump>,
    /// Distinct unit outlines (clumps computed).
    pub(super) shapes: usize,
    /// Particles whose clump covers less than the target share.
    pub(super) short: usize,
    /// Smallest coverage of any particle (1 without particles).
    pub(super) min_coverage: f64,
    /// Mean coverage over the particles (1 without particles).
    pub(super) mean_coverage: f64,
}

impl Clumps {
    /// Total number of disks.
    pub(super) fn disks(&self) -> usize {
        self.clumps.iter().map(|c| c.disks.len()).sum()
    }

    /// One line saying what the clumps achieved, for file headers: the
    /// target, the cap, the coverage reached and how many fall short.
    pub(super) fn summary(&self, opts: &ClumpOptions) -> String {
        let mut s = format!(
            "{} clumps of {} disks, each inside its particle; coverage target {}, at most {} disks per clump: coverage reached min {:.4}, mean {:.4}",
            self.clumps.len(),
            self.disks(),
            opts.coverage,
            opts.max_disks,
            self.min_coverage,
            self.mean_coverage
        );
        if self.short > 0 {
            s.push_str(&format!(
                "; {} of {} particles fall short of the target (elongated or blocky shapes need more disks: raise clump_max_disks)",
                self.short,
                self.clumps.len()
            ));
        }
        s
    }
}

/// A clump in the particle's own axes for an area-equivalent radius of 1.
#[derive(Debug, Clone, PartialEq)]
struct Template {
    disks: Vec<(Point, f64)>,
    coverage: f64,
}

/// The clump of every packed particle: one disk each (the particle
/// itself) for a packing of disks, else as the module says.
pub(super) fn clumps(packing: &Packing, opts: &ClumpOptions) -> Clumps {
    if packing.grains.is_empty() {
        let n = packing.disks.len();
        return Clumps {
            clumps: packing
                .disks
                .iter()
                .map(|d| Clump {
                    disks: vec![(d.c, d.r)],
                    coverage: 1.0,
                })
                .collect(),
            shapes: usize::from(n > 0),
            short: 0,
            min_coverage: 1.0,
            mean_coverage: 1.0,
        };
    }
    let mut memo: HashMap<Vec<i64>, Template> = HashMap::new();
    let mut out = Vec::with_capacity(packing.grains.len());
    for (grain, disk) in packing.grains.iter().zip(&packing.disks) {
        let k = grain.outline.equivalent_radius();
        let unit = grain.outline.scaled(1.0 / k);
        let t = memo
            .entry(key(&unit))
            .or_insert_with(|| template(&unit, opts));
        out.push(place(t, grain, disk.c, k));
    }
    let n = out.len();
    let short = out.iter().filter(|c| c.coverage < opts.coverage).count();
    let min_coverage = out.iter().map(|c| c.coverage).fold(1.0, f64::min);
    let mean_coverage = if n == 0 {
        1.0
    } else {
        out.iter().map(|c| c.coverage).sum::<f64>() / n as f64
    };
    Clumps {
        clumps: out,
        shapes: memo.len(),
        short,
        min_coverage,
        mean_coverage,
    }
}

/// The template moved onto a particle: scaled by `k`, turned by the grain's
/// angle, centred on `c`.
fn place(t: &Template, grain: &Grain, c: Point, k: f64) -> Clump {
    let turned = grain.turned();
    Clump {
        disks: t
            .disks
            .iter()
            .map(|&(p, r)| {
                let w = turned.to_world(Point::from(p.coords * k));
                (c + w, r * k)
            })
            .collect(),
        coverage: t.coverage,
    }
}

/// `x` rounded to [`KEY_DIGITS`] significant digits, as an integer mantissa
/// and exponent.
fn rounded(x: f64, key: &mut Vec<i64>) {
    if x == 0.0 || !x.is_finite() {
        key.extend([0, 0]);
        return;
    }
    let e = x.abs().log10().floor() as i32;
    let m = (x / 10f64.powi(e - KEY_DIGITS + 1)).round() as i64;
    key.extend([m, i64::from(e)]);
}

/// The memo's key of a unit outline: its family and its parameters rounded.
fn key(unit: &Outline) -> Vec<i64> {
    let mut key = Vec::new();
    match unit {
        Outline::Superellipse { a, b, alpha, beta } => {
            key.push(0);
            for v in [*a, *b, *alpha, *beta] {
                rounded(v, &mut key);
            }
        }
        Outline::Polygon {
            template,
            vertices,
            rounding,
        } => {
            key.push(1 + i64::from(*template));
            rounded(*rounding, &mut key);
            for v in vertices.iter() {
                rounded(v.x, &mut key);
                rounded(v.y, &mut key);
            }
        }
    }
    key
}

/// Whether the point `p` (own axes) lies in the outline.
fn contains(outline: &Outline, p: Point) -> bool {
    match outline {
        Outline::Superellipse { a, b, alpha, beta } => {
            (p.x / a).abs().powf(*alpha) + (p.y / b).abs().powf(*beta) <= 1.0
        }
        Outline::Polygon {
            vertices, rounding, ..
        } => {
            let n = vertices.len();
            let mut inside = true;
            let mut nearest = f64::INFINITY;
            for i in 0..n {
                let (s, e) = (vertices[i], vertices[(i + 1) % n]);
                let d = e - s;
                if d.x * (p.y - s.y) - d.y * (p.x - s.x) < 0.0 {
                    inside = false;
                }
                let t = ((p - s).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                nearest = nearest.min((p - (s + d * t)).norm());
            }
            inside || nearest <= *rounding
        }
    }
}

/// The edges of a counter-clockwise convex polygon as (outward unit
/// normal, offset): a point x is inside when offset − normal·x ≥ 0 for all.
fn half_planes(poly: &[Point]) -> Vec<(Vector2<f64>, f64)> {
    let n = poly.len();
    (0..n)
        .filter_map(|i| {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            let e = q - p;
            let l = e.norm();
            (l > 0.0).then(|| {
                let normal = Vector2::new(e.y, -e.x) / l;
                (normal, normal.dot(&p.coords))
            })
        })
        .collect()
}

/// A regular grid over a box: `nx` × `ny` cells of side `h` from `lo`.
struct Grid {
    lo: Point,
    h: f64,
    nx: usize,
    ny: usize,
}

impl Grid {
    /// About `count` cells over the box `lo`–`hi`.
    fn over(lo: Point, hi: Point, count: f64) -> Grid {
        let (w, v) = (hi.x - lo.x, hi.y - lo.y);
        let h = (w * v / count).sqrt();
        Grid {
            lo,
            h,
            nx: ((w / h).ceil() as usize).max(1),
            ny: ((v / h).ceil() as usize).max(1),
        }
    }

    /// Centre of cell (i, j).
    fn at(&self, i: usize, j: usize) -> Point {
        Point::new(
            self.lo.x + (i as f64 + 0.5) * self.h,
            self.lo.y + (j as f64 + 0.5) * self.h,
        )
    }

    /// The cells whose centres may lie within `r` of `c`: column and row ranges.
    fn around(&self, c: Point, r: f64) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let cells = |x: f64, lo: f64, n: usize| {
            let a = ((x - r - lo) / self.h - 0.5).floor().max(0.0) as usize;
            let b = (((x + r - lo) / self.h - 0.5).ceil() + 1.0).max(0.0) as usize;
            a.min(n)..b.min(n)
        };
        (
            cells(c.x, self.lo.x, self.nx),
            cells(c.y, self.lo.y, self.ny),
        )
    }
}

/// The clump of a unit outline (area-equivalent radius 1), in its own axes.
fn template(unit: &Outline, opts: &ClumpOptions) -> Template {
    let poly = unit.boundary(BOUNDARY_POINTS);
    let planes = half_planes(&poly);
    let clearance = |x: Point| {
        planes
            .iter()
            .map(|(n, off)| off - n.dot(&x.coords))
            .fold(f64::INFINITY, f64::min)
            - MARGIN
    };
    let reach = unit.circumradius();
    let (lo, hi) = (Point::new(-reach, -reach), Point::new(reach, reach));

    // The sample points of the particle: the cells of the grid inside it.
    let grid = Grid::over(lo, hi, SAMPLES);
    let mut index = vec![usize::MAX; grid.nx * grid.ny];
    let mut total = 0usize;
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            if contains(unit, grid.at(i, j)) {
                index[j * grid.nx + i] = total;
                total += 1;
            }
        }
    }
    let mut covered = vec![false; total];
    let gain = |c: Point, r: f64, covered: &[bool], mark: bool, store: &mut Vec<usize>| {
        let (cols, rows) = grid.around(c, r);
        let mut count = 0u32;
        for j in rows {
            for i in cols.clone() {
                let s = index[j * grid.nx + i];
                if s != usize::MAX && !covered[s] && (grid.at(i, j) - c).norm() <= r {
                    count += 1;
                    if mark {
                        store.push(s);
                    }
                }
            }
        }
        count
    };

    // Candidate centres: the centre, the own axes, a grid; each with the
    // largest certified radius there.
    let mut points = vec![Point::origin()];
    for k in 0..AXIS_CANDIDATES {
        let t = -reach + 2.0 * reach * (k as f64 + 0.5) / AXIS_CANDIDATES as f64;
        points.push(Point::new(t, 0.0));
        points.push(Point::new(0.0, t));
    }
    let coarse = Grid::over(lo, hi, CANDIDATES);
    for j in 0..coarse.ny {
        for i in 0..coarse.nx {
            points.push(coarse.at(i, j));
        }
    }
    let candidates: Vec<(Point, f64)> = points
        .into_iter()
        .map(|p| (p, clearance(p)))
        .filter(|&(_, r)| r > 0.0)
        .collect();

    let mut disks: Vec<(Point, f64)> = Vec::new();
    let mut count = 0usize;
    let mut marked = Vec::new();
    let mut take = |(c, r): (Point, f64),
                    disks: &mut Vec<(Point, f64)>,
                    covered: &mut Vec<bool>,
                    count: &mut usize| {
        marked.clear();
        gain(c, r, covered, true, &mut marked);
        for &s in &marked {
            covered[s] = true;
        }
        *count += marked.len();
        disks.push((c, r));
    };
    let share = |count: usize| {
        if total == 0 {
            0.0
        } else {
            count as f64 / total as f64
        }
    };

    // The largest inscribed disk first (the first candidate of the largest
    // radius), then lazy greedy: a candidate's gain only falls as disks are
    // taken, so the heap holds upper bounds, refreshed when popped.
    let first = candidates
        .iter()
        .enumerate()
        .fold(None::<(usize, f64)>, |best, (i, &(_, r))| match best {
            Some((_, rb)) if rb >= r => best,
            _ => Some((i, r)),
        });
    if let Some((i, _)) = first
        && opts.max_disks > 0
    {
        take(candidates[i], &mut disks, &mut covered, &mut count);
    }
    let mut scratch = Vec::new();
    let mut heap: BinaryHeap<(u32, Reverse<usize>)> = candidates
        .iter()
        .enumerate()
        .map(|(i, &(c, r))| (gain(c, r, &covered, false, &mut scratch), Reverse(i)))
        .filter(|&(g, _)| g > 0)
        .collect();
    // Each pop takes a disk, drops a candidate or lowers its bound by at
    // least one sample: bounded by candidates × samples.
    let most_pops = candidates.len().saturating_mul(total.max(1));
    for _ in 0..most_pops {
        if disks.len() >= opts.max_disks || share(count) >= opts.coverage {
            break;
        }
        let Some((_, Reverse(i))) = heap.pop() else {
            break;
        };
        let (c, r) = candidates[i];
        let g = gain(c, r, &covered, false, &mut scratch);
        if g == 0 {
            continue;
        }
        if heap.peek().is_none_or(|&(next, _)| g >= next) {
            take((c, r), &mut disks, &mut covered, &mut count);
        } else {
            heap.push((g, Reverse(i)));
        }
    }
    Template {
        disks,
        coverage: share(count),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};

    /// `true` when the disk (c, r) in world axes is inside the grain at
    /// `centre`, certified on a fine inscribed polygon (its corners on the
    /// outline, so it lies inside the convex particle).
    fn certified_inside(grain: &Grain, centre: Point, (c, r): (Point, f64)) -> bool {
        let (s, co) = grain.angle.sin_cos();
        let d = c - centre;
        let local = Point::new(co * d.x + s * d.y, -s * d.x + co * d.y);
        let fine = grain.outline.boundary(8192);
        half_planes(&fine)
            .iter()
            .all(|(n, off)| off - n.dot(&local.coords) >= r)
    }

    /// The support-function test, necessary for the disk to be inside:
    /// h(u) ≥ u·c + r in every direction.
    fn within_support(grain: &Grain, centre: Point, (c, r): (Point, f64)) -> bool {
        let turned = grain.turned();
        (0..720).all(|k| {
            let t = std::f64::consts::TAU * k as f64 / 720.0;
            let u = Vector2::new(t.cos(), t.sin());
            turned.support_both(u).0 >= u.dot(&(c - centre)) + r
        })
    }

    /// Share of the grain's area covered by `disks`, counted on a 600 × 600
    /// grid over its circumscribed square.
    fn fine_coverage(grain: &Grain, centre: Point, disks: &[(Point, f64)]) -> f64 {
        let reach = grain.outline.circumradius();
        let (s, co) = grain.angle.sin_cos();
        let (mut inside, mut covered) = (0u32, 0u32);
        for i in 0..600 {
            for j in 0..600 {
                let x = -reach + 2.0 * reach * (i as f64 + 0.25) / 600.0;
                let y = -reach + 2.0 * reach * (j as f64 + 0.75) / 600.0;
                if !contains(&grain.outline, Point::new(x, y)) {
                    continue;
                }
                inside += 1;
                let w = centre + Vector2::new(co * x - s * y, s * x + co * y);
                if disks.iter().any(|&(c, r)| (w - c).norm() <= r) {
                    covered += 1;
                }
            }
        }
        f64::from(covered) / f64::from(inside)
    }

    fn ellipse(aspect: f64, r: f64) -> Outline {
        // a·b = r² keeps the area-equivalent radius r.
        let b = r / aspect.sqrt();
        Outline::superellipse(b * aspect, b, 2.0, 2.0).unwrap()
    }

    fn options(coverage: f64, max_disks: usize) -> ClumpOptions {
        ClumpOptions {
            coverage,
            max_disks,
        }
    }

    /// A grain packing of one particle per outline, in a big box.
    fn packing_of(grains: Vec<(Grain, Point)>) -> Packing {
        let domain = Domain::rectangle(400.0, 400.0).unwrap();
        let centres: Vec<Point> = grains
            .iter()
            .map(|(_, c)| Point::new(c.x + 200.0, c.y + 200.0))
            .collect();
        Packing::of_grains(
            domain,
            grains.into_iter().map(|(g, _)| g).collect(),
            &centres,
        )
    }

    #[test]
    fn every_disk_is_inside_its_particle() {
        let square = [
            Point::new(-1.0, -1.0),
            Point::new(1.0, -1.0),
            Point::new(1.2, 0.8),
            Point::new(-0.7, 1.1),
        ];
        let shapes = [
            ellipse(1.5, 2.0),
            ellipse(3.0, 0.7),
            Outline::superellipse(2.0, 1.0, 4.0, 4.0).unwrap(),
            Outline::superellipse(1.5, 1.0, 1.0, 1.0).unwrap(),
            Outline::superellipse(3.0, 1.0, 2.5, 6.0).unwrap(),
            Outline::polygon(0, &square, 0.0).unwrap(),
            Outline::polygon(1, &square, 0.3).unwrap(),
        ];
        let grains: Vec<(Grain, Point)> = shapes
            .iter()
            .enumerate()
            .map(|(i, o)| {
                (
                    Grain::new(o.clone(), 0.37 * i as f64 - 1.0),
                    Point::new(10.0 * i as f64 - 30.0, 5.0),
                )
            })
            .collect();
        let packing = packing_of(grains);
        let all = clumps(&packing, &options(0.95, 48));
        assert_eq!(all.clumps.len(), shapes.len());
        for ((clump, grain), disk) in all.clumps.iter().zip(&packing.grains).zip(&packing.disks) {
            assert!(!clump.disks.is_empty());
            for &d in &clump.disks {
                assert!(d.1 > 0.0);
                assert!(certified_inside(grain, disk.c, d), "{grain:?}: {d:?}");
                assert!(within_support(grain, disk.c, d), "{grain:?}: {d:?}");
            }
        }
    }

    #[test]
    fn a_disk_pushed_out_fails_the_certificate() {
        let grain = Grain::new(ellipse(2.0, 1.0), 0.3);
        let packing = packing_of(vec![(grain.clone(), Point::new(1.0, 2.0))]);
        let all = clumps(&packing, &options(0.9, 32));
        let (c, r) = all.clumps[0].disks[0];
        let centre = packing.disks[0].c;
        assert!(certified_inside(&grain, centre, (c, r)));
        assert!(!certified_inside(&grain, centre, (c, r * 1.01)));
        assert!(!within_support(&grain, centre, (c, r * 1.01)));
    }

    #[test]
    fn an_ellipse_reaches_the_coverage_within_the_cap() {
        let packing = packing_of(vec![(Grain::new(ellipse(1.5, 1.0), 0.0), Point::origin())]);
        let all = clumps(&packing, &options(0.9, 32));
        let c = &all.clumps[0];
        assert!(c.coverage >= 0.9, "{}", c.coverage);
        assert!(c.disks.len() <= 32);
        assert_eq!(all.short, 0);
        // Fewer disks allowed than needed: short, and said so.
        let few = clumps(&packing, &options(0.99, 2));
        assert_eq!(few.clumps[0].disks.len(), 2);
        assert!(few.clumps[0].coverage < 0.99);
        assert_eq!(few.short, 1);
        assert!(few.summary(&options(0.99, 2)).contains("fall short"));
    }

    /// The coverage reached with the defaults, quoted in docs/outputs.md.
    #[test]
    fn coverage_of_the_documented_shapes() {
        let cases = [
            ("ellipse aspect 1.5", ellipse(1.5, 1.0)),
            ("ellipse aspect 3", ellipse(3.0, 1.0)),
            (
                "superellipse 4 aspect 2",
                Outline::superellipse(2.0, 1.0, 4.0, 4.0).unwrap(),
            ),
        ];
        for (name, outline) in cases {
            let packing = packing_of(vec![(Grain::new(outline, 0.0), Point::origin())]);
            for (target, cap) in [(0.9, 32), (0.95, 64)] {
                let all = clumps(&packing, &options(target, cap));
                let c = &all.clumps[0];
                println!(
                    "{name}: target {target}, cap {cap}: {} disks, coverage {:.4}",
                    c.disks.len(),
                    c.coverage
                );
                assert!(c.coverage > 0.85, "{name}: {}", c.coverage);
                // The same share counted independently on a finer grid.
                let fine = fine_coverage(&packing.grains[0], packing.disks[0].c, &c.disks);
                assert!(
                    (fine - c.coverage).abs() < 0.01,
                    "{name}: {fine} {}",
                    c.coverage
                );
                assert!(c.coverage >= target || c.disks.len() == cap);
            }
        }
    }

    #[test]
    fn one_clump_per_shape_up_to_scale_and_placed_exactly() {
        let base = Outline::superellipse(2.0, 1.0, 4.0, 4.0).unwrap();
        let grains = (0..50)
            .map(|i| {
                let k = 0.5 + 0.031 * i as f64;
                (
                    Grain::new(base.scaled(k), 0.1 * i as f64),
                    Point::new(i as f64 - 25.0, 0.5 * i as f64 - 10.0),
                )
            })
            .collect();
        let packing = packing_of(grains);
        let opts = options(0.9, 32);
        let all = clumps(&packing, &opts);
        assert_eq!(all.shapes, 1);
        let n = all.clumps[0].disks.len();
        for ((clump, grain), disk) in all.clumps.iter().zip(&packing.grains).zip(&packing.disks) {
            assert_eq!(clump.disks.len(), n);
            for &d in &clump.disks {
                assert!(certified_inside(grain, disk.c, d));
            }
        }
        // Deterministic.
        assert_eq!(clumps(&packing, &opts), all);
    }

    #[test]
    fn clumps_of_touching_ellipses_do_not_overlap() {
        // Two rows of ellipses side by side, touching along their long sides,
        // and end to end: the gaps between particles are exactly zero.
        let (a, b) = (3.0, 1.0);
        let outline = Outline::superellipse(a, b, 2.0, 2.0).unwrap();
        let mut grains = Vec::new();
        for i in 0..4 {
            for j in 0..3 {
                grains.push((
                    Grain::new(outline.clone(), 0.0),
                    Point::new(2.0 * a * i as f64, 2.0 * b * j as f64),
                ));
            }
        }
        // And one turned upright, touching the last column's end.
        grains.push((
            Grain::new(outline.clone(), std::f64::consts::FRAC_PI_2),
            Point::new(2.0 * a * 3.0 + a + b, 2.0 * b),
        ));
        let packing = packing_of(grains);
        let all = clumps(&packing, &options(0.9, 32));
        for (i, p) in all.clumps.iter().enumerate() {
            for q in &all.clumps[i + 1..] {
                for &(c1, r1) in &p.disks {
                    for &(c2, r2) in &q.disks {
                        assert!((c1 - c2).norm() >= r1 + r2, "{c1} {r1} / {c2} {r2}");
                    }
                }
            }
        }
    }

    #[test]
    fn disks_are_their_own_clumps() {
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        let packing = Packing::of_disks(
            domain,
            vec![Disk::new(1.0, 1.0, 0.5), Disk::new(3.0, 1.0, 1.0)],
        );
        let all = clumps(&packing, &options(0.9, 32));
        assert_eq!(all.clumps[1].disks, [(Point::new(3.0, 1.0), 1.0)]);
        assert_eq!(all.short, 0);
    }

    #[test]
    fn many_particles_of_one_shape_are_fast() {
        let base = ellipse(2.0, 1.0);
        let grains: Vec<(Grain, Point)> = (0..100_000)
            .map(|i| {
                let k = 0.2 + (i % 97) as f64 * 0.01;
                (
                    Grain::new(base.scaled(k), i as f64 * 1e-3),
                    Point::new((i % 300) as f64 * 0.6 - 90.0, (i / 300) as f64 * 0.6 - 90.0),
                )
            })
            .collect();
        let packing = packing_of(grains);
        let start = std::time::Instant::now();
        let all = clumps(&packing, &options(0.9, 32));
        assert_eq!(all.shapes, 1);
        assert!(
            start.elapsed().as_secs_f64() < 20.0,
            "{:?}",
            start.elapsed()
        );
    }
}
