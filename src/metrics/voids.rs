//! The space between particles that are not disks ([`Packing::grains`]):
//! each particle's solid area inside a window, for the local porosity, and
//! its distance from a point, for the largest hole.
//!
//! **Area in a window.** A particle K is bracketed by two polygons: P,
//! the [`HULL_POINTS`] points of [`Outline::boundary`], which lie on the
//! outline and so inside the convex particle; and Q, the polygon of the
//! outline's tangent lines at those points (a superellipse's, through
//! each point along its gradient's normal) or along the normals of P's
//! sides (a rounded polygon's, each at the support value, an upper
//! bound), which holds the particle. Clipped to a window W (Sutherland–
//! Hodgman against its box), they bound the particle's area in it:
//! |P ∩ W| ≤ |K ∩ W| ≤ |Q ∩ W|. The area taken is
//! |P ∩ W| + λ·(|Q ∩ W| − |P ∩ W|), with λ = (|K| − |P|) / (|Q| − |P|) the
//! share of the whole bracket the particle's exact area fills: it lies in
//! the bracket, so it is off the exact area in W by at most
//! |Q ∩ W| − |P ∩ W| ≤ |Q| − |P|, and windows that cover a particle's Q
//! share out exactly its area. With 1,024 points, |Q| − |P| is below 3·10⁻⁵ of
//! the particle's area for every outline a `[shape]` draws (ellipses to
//! aspect 20, superellipse exponents 1 to 50, rounded polygons; exactly 0
//! for a polygon with sharp corners, whose P and Q are the polygon itself),
//! and the error of the interpolated area is far smaller still: a window's
//! porosity is off by at most the sum of those brackets of the particles
//! its edges cut over its area. A particle whose bounding circle lies
//! wholly inside a window counts its exact area and one whose bounding
//! circle misses it nothing: only particles across a window's edge are
//! clipped. Both polygons are computed once per outline up to scale.
//!
//! **Distance from a point.** The GJK distance of the point to the
//! particle ([`separation`]) gives a certified lower bound and an upper
//! bound; the clearance at a point is the least *lower* bound over the
//! particles (and the walls): a disk of that radius there is certainly
//! empty, so the largest hole found is never larger than a real empty disk
//! (it is within 10⁻⁹ of a particle's size of the exact clearance at the
//! centre found). A sample is rejected early on *upper* bounds (its distance
//! to the nearest particle about that particle's centre, or the GJK upper
//! bound): rejecting never makes the hole larger.

use std::collections::HashMap;

use nalgebra::Vector2;

use super::near::ByRadius;
use super::shapes::{ShapeMemo, UnitKey, key_of};
use super::{Clearance, image, search_clearance};
use crate::geometry::predicates::area_polygon_box;
use crate::geometry::{Disk, Outline, Point, SUPPORT_REL, Turned, separation};
use crate::packer::Packing;
use crate::packer::index::{Grid, SpatialIndex};

/// Points of the polygon inside each particle, and tangent lines of the
/// polygon holding it.
const HULL_POINTS: usize = 1024;

/// Relative tolerance of the GJK distance from a sample to a particle, of
/// the particle's bounding radius.
const DISTANCE_TOL: f64 = 1e-9;

/// A particle's two bracketing polygons in its own axes, at unit scale
/// (see the module's notes).
#[derive(Debug)]
struct Hull {
    /// P: points on the outline, counter-clockwise.
    inner: Vec<Point>,
    /// Q: the corners of the tangent lines, counter-clockwise.
    outer: Vec<Point>,
    /// λ: the share of |Q| − |P| the exact area fills, in [0, 1].
    share: f64,
}

/// The two polygons bracketing `outline` and the share λ.
fn hull(outline: &Outline) -> Hull {
    let inner = outline.boundary(HULL_POINTS);
    let m = inner.len();
    // Each tangent line as (unit outward normal, offset): n·x ≤ offset
    // holds the whole outline.
    let lines: Vec<(Vector2<f64>, f64)> = match outline {
        Outline::Superellipse { a, b, alpha, beta } => {
            let margin = SUPPORT_REL * a.max(*b);
            let sign = |v: f64| {
                if v > 0.0 {
                    1.0
                } else if v < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            };
            inner
                .iter()
                .filter_map(|p| {
                    let g = Vector2::new(
                        alpha / a * (p.x.abs() / a).powf(alpha - 1.0) * sign(p.x),
                        beta / b * (p.y.abs() / b).powf(beta - 1.0) * sign(p.y),
                    );
                    let n = g.try_normalize(0.0)?;
                    Some((n, n.dot(&p.coords) + margin))
                })
                .collect()
        }
        Outline::Polygon { .. } => (0..m)
            .filter_map(|k| {
                let e = inner[(k + 1) % m] - inner[k];
                let n = Vector2::new(e.y, -e.x).try_normalize(0.0)?;
                Some((n, outline.support(n)))
            })
            .collect(),
    };
    // Lines all but parallel to the last one kept are left out: the
    // polygon of fewer lines still holds the outline, and their corner
    // would be found to too few digits.
    let mut kept: Vec<(Vector2<f64>, f64)> = Vec::with_capacity(lines.len());
    for line in lines {
        if let Some(last) = kept.last()
            && cross(last.0, line.0) <= 1e-12
        {
            continue;
        }
        kept.push(line);
    }
    while kept.len() > 3 && cross(kept[kept.len() - 1].0, kept[0].0) <= 1e-12 {
        kept.pop();
    }
    let k = kept.len();
    let outer: Vec<Point> = (0..k)
        .map(|i| {
            let ((n1, h1), (n2, h2)) = (kept[i], kept[(i + 1) % k]);
            let det = cross(n1, n2);
            Point::new((h1 * n2.y - h2 * n1.y) / det, (n1.x * h2 - n2.x * h1) / det)
        })
        .collect();
    let (p_area, q_area) = (shoelace(&inner), shoelace(&outer));
    let gap = q_area - p_area;
    let share = if gap > 0.0 {
        ((outline.area() - p_area) / gap).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Hull {
        inner,
        outer,
        share,
    }
}

/// The z component of a × b.
fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Area of a counter-clockwise polygon.
fn shoelace(v: &[Point]) -> f64 {
    let n = v.len();
    0.5 * (0..n)
        .map(|i| {
            let (p, q) = (v[i], v[(i + 1) % n]);
            p.x * q.y - q.x * p.y
        })
        .sum::<f64>()
}

/// The solid area of a packing's grains inside windows (see the module's
/// notes).
pub(super) struct GrainAreas<'a> {
    packing: &'a Packing,
    /// Wall disks, then each particle's bounding circle.
    bounds: Vec<Disk>,
    /// The bounding circles' centres.
    grid: Grid,
    /// The largest bounding radius.
    reach: f64,
    /// Each distinct outline's hull, with the index of each key.
    hulls: Vec<Hull>,
    keys: HashMap<UnitKey, usize>,
    /// Each particle's hull index and scale, once asked.
    slot: Vec<Option<(usize, f64)>>,
}

impl<'a> GrainAreas<'a> {
    /// The areas of `packing`'s grains, their bounding circles from `memo`.
    pub(super) fn new(packing: &'a Packing, memo: &mut ShapeMemo) -> Self {
        let bounds = bounding_circles(packing, memo);
        let reach = bounds.iter().fold(0.0f64, |m, d| m.max(d.r));
        let (lo, hi) = packing.domain.bounds();
        let bucket = (2.0 * reach).max(f64::MIN_POSITIVE);
        let margin = Vector2::new(2.0 * reach, 2.0 * reach);
        let mut grid = Grid::new(lo - margin, hi + margin, bucket);
        for (id, d) in bounds.iter().enumerate() {
            grid.insert(id as u32, d.c);
        }
        GrainAreas {
            packing,
            bounds,
            grid,
            reach,
            hulls: Vec::new(),
            keys: HashMap::new(),
            slot: vec![None; packing.grains.len()],
        }
    }

    /// The solid area of the packed particles inside the box
    /// [x0, x1] × [y0, y1] (in a periodic cell, their images' too).
    pub(super) fn in_box(&mut self, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
        let nb = self.packing.boundary.len();
        let (qlo, qhi) = (
            Point::new(x0 - self.reach, y0 - self.reach),
            Point::new(x1 + self.reach, y1 + self.reach),
        );
        let mut near = Vec::new();
        for v in self.packing.domain.image_shifts(qlo, qhi) {
            self.grid.visit_box(qlo - v, qhi - v, |j| {
                if j as usize >= nb {
                    near.push((j as usize, v));
                }
            });
        }
        let mut solid = 0.0;
        for (j, v) in near {
            solid += self.one_in_box(j - nb, image(self.bounds[j].c, v), (x0, x1, y0, y1));
        }
        solid
    }

    /// The area of particle `i`, centred at `c`, inside the box.
    fn one_in_box(&mut self, i: usize, c: Point, (x0, x1, y0, y1): (f64, f64, f64, f64)) -> f64 {
        let r = self.bounds[self.packing.boundary.len() + i].r;
        let dx = (x0 - c.x).max(c.x - x1).max(0.0);
        let dy = (y0 - c.y).max(c.y - y1).max(0.0);
        if dx * dx + dy * dy >= r * r {
            return 0.0;
        }
        if c.x - r >= x0 && c.x + r <= x1 && c.y - r >= y0 && c.y + r <= y1 {
            return self.packing.disks[i].area();
        }
        let grain = &self.packing.grains[i];
        let (h, scale) = match self.slot[i] {
            Some(s) => s,
            None => {
                let (key, scale) = key_of(&grain.outline);
                let next = self.hulls.len();
                let h = *self.keys.entry(key).or_insert(next);
                if h == next {
                    self.hulls.push(hull(&grain.outline.scaled(1.0 / scale)));
                }
                self.slot[i] = Some((h, scale));
                (h, scale)
            }
        };
        let hull = &self.hulls[h];
        let t = grain.turned();
        let place = |v: &[Point]| -> Vec<Point> {
            v.iter()
                .map(|p| c + t.to_world(Point::from(p.coords * scale)))
                .collect()
        };
        let inner = area_polygon_box(&place(&hull.inner), x0, x1, y0, y1);
        let outer = area_polygon_box(&place(&hull.outer), x0, x1, y0, y1);
        inner + hull.share * (outer - inner).max(0.0)
    }
}

/// The wall disks, then each packed particle's bounding circle (centre and
/// [`Outline::circumradius`], through `memo`).
fn bounding_circles(packing: &Packing, memo: &mut ShapeMemo) -> Vec<Disk> {
    let mut bounds = packing.boundary.clone();
    for (d, g) in packing.disks.iter().zip(&packing.grains) {
        let (unit, scale) = memo.unit(&g.outline);
        bounds.push(Disk::new(d.c.x, d.c.y, unit.circumradius * scale));
    }
    bounds
}

/// Radius of a disk about the outline's centre that lies inside it (mm),
/// in closed form: the largest for an ellipse and a rounded polygon.
///
/// # Behavior
/// A superellipse with both exponents 2 or more holds the ellipse of its
/// semi-axes, and so the disk of the smaller; any holds the rhombus of its
/// semi-axes, and so the disk of radius ab/√(a² + b²). A rounded polygon
/// holds the disk of its centre's least distance to a side, plus the
/// rounding.
fn centred_radius(outline: &Outline) -> f64 {
    match outline {
        Outline::Superellipse { a, b, alpha, beta } => {
            if *alpha >= 2.0 && *beta >= 2.0 {
                a.min(*b)
            } else {
                a * b / a.hypot(*b)
            }
        }
        Outline::Polygon {
            vertices, rounding, ..
        } => {
            let m = vertices.len();
            let side = (0..m)
                .filter_map(|k| {
                    let (p, q) = (vertices[k], vertices[(k + 1) % m]);
                    let n = Vector2::new(q.y - p.y, p.x - q.x).try_normalize(0.0)?;
                    Some(n.dot(&p.coords))
                })
                .fold(f64::INFINITY, f64::min);
            side.max(0.0) + rounding
        }
    }
}

/// The clearance among grains for the largest-hole search (see the
/// module's notes).
pub(super) struct GrainClearance<'a> {
    packing: &'a Packing,
    /// Wall disks, then each particle's bounding circle.
    bounds: Vec<Disk>,
    /// The bounding circles by size class.
    near: ByRadius,
    /// Each one's radius of a disk about its centre inside it.
    centred: Vec<f64>,
    /// Each packed particle turned.
    turned: Vec<Turned<'a>>,
    /// The largest bounding radius.
    reach: f64,
    /// The particle (and image shift) that settled the last sample.
    settler: (usize, Vector2<f64>),
}

impl<'a> GrainClearance<'a> {
    /// The clearance among `packing`'s grains, their bounding circles from `memo`.
    pub(super) fn new(packing: &'a Packing, memo: &mut ShapeMemo) -> Self {
        let bounds = bounding_circles(packing, memo);
        let near = ByRadius::new(&bounds, 0..bounds.len());
        let centred = packing
            .boundary
            .iter()
            .map(|d| d.r)
            .chain(packing.grains.iter().map(|g| centred_radius(&g.outline)))
            .collect();
        GrainClearance {
            packing,
            reach: bounds.iter().fold(0.0f64, |m, d| m.max(d.r)),
            bounds,
            near,
            centred,
            turned: packing.grains.iter().map(|g| g.turned()).collect(),
            settler: (usize::MAX, Vector2::zeros()),
        }
    }
}

impl Clearance for GrainClearance<'_> {
    fn settled_by_last(&self, p: Point, best: f64) -> bool {
        let (j, v) = self.settler;
        self.bounds
            .get(j)
            .is_some_and(|b| (p - image(b.c, v)).norm() - self.centred[j] <= best)
    }

    fn above(&mut self, p: Point, floor: f64) -> f64 {
        let nb = self.packing.boundary.len();
        let (bounds, centred, turned) = (&self.bounds, &self.centred, &self.turned);
        search_clearance(
            &self.packing.domain,
            &self.near,
            self.reach,
            p,
            floor,
            &mut self.settler,
            |j, v, bar| {
                let b = bounds[j];
                let off = p - image(b.c, v);
                let dist = off.norm();
                // No nearer than its bounding circle: it cannot lower the
                // clearance below what is found already.
                if dist - b.r >= bar {
                    return (f64::INFINITY, false);
                }
                // No farther than the disk about its centre inside it.
                let mut upper = dist - centred[j];
                let mut lower = upper;
                if upper > floor && j >= nb {
                    let s = separation(off, DISTANCE_TOL * b.r, |u| turned[j - nb].support_both(u));
                    (lower, upper) = (s.lower, s.upper);
                }
                (lower.min(upper), upper <= floor)
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::geometry::Grain;
    use crate::metrics::measure;
    use crate::{Domain, Scene, ShapeSpec};

    /// A scene of ellipses of aspect 1.5 sized by sieve, `uniform = [1, 2]`,
    /// in a `w` × `h` rectangle.
    fn scene(w: f64, h: f64) -> Scene {
        let text = format!(
            "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = {w}\nheight = {h}\n[grading]\nuniform = [1.0, 2.0]\n"
        );
        crate::config::parse_with(&text, "t", Default::default())
            .unwrap()
            .scene
            .with_shape(ShapeSpec::ellipses(1.5))
    }

    /// The square [−h, h]² as a polygon with sharp corners.
    fn square(h: f64) -> Outline {
        let v = [(-h, -h), (h, -h), (h, h), (-h, h)].map(|(x, y)| Point::new(x, y));
        Outline::polygon(0, &v, 0.0).unwrap()
    }

    #[test]
    fn windows_over_known_ellipses_and_squares_give_the_porosity_by_hand() {
        // Ellipses a = 2, b = 1 (equivalent radius √2): windows of side
        // w = 10√2, two of them side by side in a 2w × w rectangle.
        let ellipse = || Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
        let w = 10.0 * ellipse().equivalent_radius();
        let domain = Domain::rectangle(2.0 * w, w).unwrap();
        let p = Packing::of_grains(
            domain,
            vec![
                // Its tip 1 mm across x = w: the cap beyond x/a = 1/2.
                Grain::new(ellipse(), 0.0),
                // A 2 mm square turned 45° on x = w: half each side.
                Grain::new(square(1.0), PI / 4.0),
                // A 2 mm square 0.5 mm into the left window.
                Grain::new(square(1.0), 0.0),
                // Wholly in the right window.
                Grain::new(ellipse(), 0.7),
            ],
            &[
                Point::new(w - 1.0, w / 2.0),
                Point::new(w, w / 4.0),
                Point::new(w + 0.5, 0.75 * w),
                Point::new(1.5 * w, w / 2.0),
            ],
        );
        let e = 2.0 * PI;
        let cap = 2.0 * (PI / 3.0 - 3f64.sqrt() / 4.0);
        let (left, right) = (e - cap + 2.0 + 1.0, cap + 2.0 + 3.0 + e);
        let mut memo = ShapeMemo::default();
        let mut areas = GrainAreas::new(&p, &mut memo);
        let l = areas.in_box(0.0, w, 0.0, w);
        let r = areas.in_box(w, 2.0 * w, 0.0, w);
        // Within the ellipse's bracket (9.4·10⁻⁶ of its area), and in fact
        // far closer.
        assert!((l - left).abs() < 1e-8, "{l} vs {left}");
        assert!((r - right).abs() < 1e-8, "{r} vs {right}");
        assert!((l + r - (2.0 * e + 8.0)).abs() < 1e-12, "{}", l + r);
        let m = measure(&p, &scene(2.0 * w, w));
        assert_eq!((m.local_windows, m.local_windows_clipped), (2, false));
        let (pl, pr) = (1.0 - left / (w * w), 1.0 - right / (w * w));
        let sd = (pl - pr).abs() / 2f64.sqrt();
        assert!((m.local_porosity_std - sd).abs() < 1e-9, "{m:?} vs {sd}");
    }

    #[test]
    fn the_largest_hole_of_one_particle_in_a_periodic_cell() {
        // A square of half-diagonal 2 (turned 45°: a diamond) at the
        // centre of a 10 mm cell: the hole is centred on the cell's
        // corners, (10 − 2)/√2 from the diamond's sides.
        let cell = Domain::periodic_rectangle(10.0, 10.0).unwrap();
        let s = scene(10.0, 10.0);
        let diamond = Packing::of_grains(
            cell.clone(),
            vec![Grain::new(square(2f64.sqrt()), PI / 4.0)],
            &[Point::new(5.0, 5.0)],
        );
        let hole = measure(&diamond, &s).largest_hole;
        let exact = 2.0 * 8.0 / 2f64.sqrt();
        assert!(
            hole <= exact + 1e-12 && hole > exact - 1e-6,
            "{hole} vs {exact}"
        );
        // An ellipse a = 2, b = 1: the same corners, at the distance found
        // along a fine polygon of its outline (from above: points on it).
        let e = Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
        let far = e
            .boundary(200_000)
            .iter()
            .map(|q| (q.coords + Vector2::new(5.0, 5.0)).norm())
            .fold(f64::INFINITY, f64::min);
        let ellipse = Packing::of_grains(cell, vec![Grain::new(e, 0.0)], &[Point::new(5.0, 5.0)]);
        let hole = measure(&ellipse, &s).largest_hole;
        assert!(
            hole <= 2.0 * far + 1e-12 && hole > 2.0 * far - 1e-6,
            "{hole} vs {}",
            2.0 * far
        );
    }

    #[test]
    fn a_periodic_cell_shares_out_each_particle_once() {
        // A diamond on the cell's corner and an ellipse across its left
        // edge: 2 × 2 boxes tiling the cell hold their areas once.
        let cell = Domain::periodic_rectangle(10.0, 10.0).unwrap();
        let e = Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
        let p = Packing::of_grains(
            cell,
            vec![Grain::new(square(2.0), PI / 4.0), Grain::new(e, 0.3)],
            &[Point::new(0.0, 0.0), Point::new(0.5, 5.0)],
        );
        let mut memo = ShapeMemo::default();
        let mut areas = GrainAreas::new(&p, &mut memo);
        let total: f64 = [(0.0, 0.0), (5.0, 0.0), (0.0, 5.0), (5.0, 5.0)]
            .iter()
            .map(|&(x, y)| areas.in_box(x, x + 5.0, y, y + 5.0))
            .sum();
        assert!((total - (16.0 + 2.0 * PI)).abs() < 1e-12, "{total}");
    }

    #[test]
    fn a_packing_of_ellipses_shares_its_solid_out_among_windows() {
        let s = scene(25.0, 25.0);
        let p = crate::pack(&s).unwrap();
        assert!(!p.grains.is_empty());
        let m = measure(&p, &s);
        // Windows of 10 equivalent radii (about 12 mm): 2 × 2 inside.
        assert_eq!((m.local_windows, m.local_windows_clipped), (4, false));
        assert!(
            m.local_porosity_std > 0.0 && m.local_porosity_std < 0.1,
            "{m:?}"
        );
        // Boxes tiling the domain: their porosities average to the
        // packing's, within the brackets of the particles they cut (each
        // under 3·10⁻⁵ of its area).
        let mut memo = ShapeMemo::default();
        let mut areas = GrainAreas::new(&p, &mut memo);
        let tiles = |areas: &mut GrainAreas, lo: f64, hi: f64| {
            let k = 5;
            let side = (hi - lo) / k as f64;
            let mut solids = Vec::new();
            for iy in 0..k {
                for ix in 0..k {
                    let (x, y) = (lo + ix as f64 * side, lo + iy as f64 * side);
                    solids.push(areas.in_box(x, x + side, y, y + side));
                }
            }
            (solids, side * side)
        };
        let (solids, area) = tiles(&mut areas, 0.0, 25.0);
        let mean = solids
            .iter()
            .map(|&s| crate::metrics::porosity(s, area))
            .sum::<f64>()
            / solids.len() as f64;
        let error = (mean - m.porosity).abs();
        assert!(
            error < 3e-5 * (1.0 - m.porosity),
            "{mean} vs {}",
            m.porosity
        );
        // Boxes covering the particles' outer brackets too (those along
        // the walls reach past them) share out each particle's exact area.
        let (solids, _) = tiles(&mut areas, -1.0, 26.0);
        let total = solids.iter().sum::<f64>();
        assert!(
            (total / m.solid_area - 1.0).abs() < 1e-12,
            "{total} vs {}",
            m.solid_area
        );
        // The hole is a real empty disk, smaller than the largest particle.
        assert!(m.largest_hole > 0.0 && m.largest_hole < 2.0 * 1.5, "{m:?}");
    }

    #[test]
    fn the_brackets_hold_the_exact_area_closely() {
        let outlines = [
            Outline::superellipse(1.5, 1.0, 2.0, 2.0).unwrap(),
            Outline::superellipse(20.0, 1.0, 2.0, 2.0).unwrap(),
            Outline::superellipse(2.0, 1.0, 4.0, 4.0).unwrap(),
            Outline::superellipse(1.0, 1.0, 50.0, 50.0).unwrap(),
            Outline::superellipse(3.0, 1.0, 1.0, 1.0).unwrap(),
            Outline::superellipse(2.0, 1.0, 1.5, 7.0).unwrap(),
            Outline::superellipse(2.0, 1.0, 1.0, 50.0).unwrap(),
            Outline::polygon(
                0,
                &[
                    Point::new(0.0, 0.0),
                    Point::new(3.0, 0.0),
                    Point::new(1.0, 2.0),
                ],
                0.2,
            )
            .unwrap(),
        ];
        for o in &outlines {
            let h = hull(o);
            let (p, q, k) = (shoelace(&h.inner), shoelace(&h.outer), o.area());
            // Up to rounding: a rhombus's P is itself.
            let ulps = 1e-12 * k;
            assert!(p <= k + ulps && k <= q + ulps, "{o:?}: {p} {k} {q}");
            assert!((q - p) / k < 3e-5, "{o:?}: bracket {}", (q - p) / k);
            // Q holds the outline: every point of a finer polygonisation.
            let m = h.outer.len();
            for x in o.boundary(5000) {
                for i in 0..m {
                    let (a, b) = (h.outer[i], h.outer[(i + 1) % m]);
                    assert!(cross(b - a, x - a) >= -1e-12, "{o:?}: {x} outside Q");
                }
            }
        }
        // A polygon with sharp corners is its own bracket.
        let square = Outline::polygon(
            0,
            &[
                Point::new(0.0, 0.0),
                Point::new(2.0, 0.0),
                Point::new(2.0, 2.0),
                Point::new(0.0, 2.0),
            ],
            0.0,
        )
        .unwrap();
        let h = hull(&square);
        assert!((shoelace(&h.outer) - 4.0).abs() < 1e-11);
        assert!((shoelace(&h.inner) - 4.0).abs() < 1e-15);
    }
}
