//! The geometry of a profile: the normalised coordinate s ∈ [0, 1] along an
//! axis of a domain, and the area fraction of each material as a function
//! of s. The packer's size-graded mode draws sizes by it; `layering`
//! measures and assigns materials by it.

use nalgebra::Vector2;

use crate::geometry::predicates::{area_disk_box, area_disk_disk};
use crate::geometry::{Disk, Domain, Point, Shape};
use crate::grading::Grading;
use crate::scene::ShapeSpec;

/// The direction along which the fractions change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Axis {
    /// Left (s = 0) to right (s = 1).
    X,
    /// Bottom (s = 0) to top (s = 1).
    #[default]
    Y,
    /// From the domain's centroid (s = 0) to its farthest boundary point (s = 1).
    Radial,
}

/// Where points of a domain lie along an axis: s ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    axis: Axis,
    /// s = 0: the lower bound along x or y, or the centroid.
    origin: Point,
    /// Length mapped to s = 1 (mm).
    length: f64,
}

impl Frame {
    /// The frame of `domain` along `axis`: its bounding box along x or y, or
    /// the centroid and the farthest boundary point.
    pub fn new(axis: Axis, domain: &Domain) -> Self {
        let (lo, hi) = domain.bounds();
        let (origin, length) = match axis {
            Axis::X => (lo, hi.x - lo.x),
            Axis::Y => (lo, hi.y - lo.y),
            Axis::Radial => {
                let c = domain.centroid();
                let far = match domain.shape() {
                    Shape::Circle { center, radius } => (center - c).norm() + radius,
                    _ => domain
                        .outline(0)
                        .iter()
                        .map(|p| (p - c).norm())
                        .fold(0.0, f64::max),
                };
                (c, far)
            }
        };
        Frame {
            axis,
            origin,
            length: length.max(f64::MIN_POSITIVE),
        }
    }

    /// The coordinate of `p` along the axis, clamped to [0, 1].
    pub fn s(&self, p: Point) -> f64 {
        let t = match self.axis {
            Axis::X => p.x - self.origin.x,
            Axis::Y => p.y - self.origin.y,
            Axis::Radial => (p - self.origin).norm(),
        };
        (t / self.length).clamp(0.0, 1.0)
    }

    /// The range of s a disk covers (unclamped).
    pub fn span(&self, d: &Disk) -> (f64, f64) {
        let centre = match self.axis {
            Axis::X => d.c.x - self.origin.x,
            Axis::Y => d.c.y - self.origin.y,
            Axis::Radial => (d.c - self.origin).norm(),
        };
        ((centre - d.r) / self.length, (centre + d.r) / self.length)
    }

    /// Area of the disk `d` between s = `a` and s = `b` (exact: a slab for
    /// x and y, an annulus for radial).
    pub fn area_between(&self, d: &Disk, a: f64, b: f64) -> f64 {
        let (ta, tb) = (a * self.length, b * self.length);
        let (c, r) = (d.c, d.r);
        match self.axis {
            Axis::X => {
                let x0 = self.origin.x;
                area_disk_box(c, r, x0 + ta, x0 + tb, c.y - 2.0 * r, c.y + 2.0 * r)
            }
            Axis::Y => {
                let y0 = self.origin.y;
                area_disk_box(c, r, c.x - 2.0 * r, c.x + 2.0 * r, y0 + ta, y0 + tb)
            }
            Axis::Radial => {
                let o = self.origin;
                let within = |radius: f64| {
                    if radius > 0.0 {
                        area_disk_disk(c, r, o, radius)
                    } else {
                        0.0
                    }
                };
                (within(tb) - within(ta)).max(0.0)
            }
        }
    }
}

impl Frame {
    /// The range of s a convex counter-clockwise polygon (world
    /// coordinates) covers (unclamped): its vertices' along x or y; for
    /// radial, from its nearest point to the origin (0 when it holds the
    /// origin) to its farthest vertex.
    pub fn polygon_span(&self, polygon: &[Point]) -> (f64, f64) {
        let (lo, hi) = polygon
            .iter()
            .map(|&p| self.t(p))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
                (lo.min(t), hi.max(t))
            });
        let lo = match self.axis {
            Axis::X | Axis::Y => lo,
            Axis::Radial => {
                let n = polygon.len();
                let (mut nearest, mut inside) = (lo, n > 2);
                for i in 0..n {
                    let a = polygon[i] - self.origin;
                    let e = polygon[(i + 1) % n] - polygon[i];
                    inside &= e.x * (-a.y) - e.y * (-a.x) >= 0.0;
                    let w = (-a.dot(&e) / e.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
                    nearest = nearest.min((a + e * w).norm());
                }
                if inside { 0.0 } else { nearest }
            }
        };
        (lo / self.length, hi / self.length)
    }

    /// Area of the counter-clockwise `polygon` (world coordinates) whose
    /// points lie at s ≤ `s` (unclamped): the polygon clipped by a
    /// half-plane for x and y, by a disk about the origin for radial.
    pub fn polygon_area_below(&self, polygon: &[Point], s: f64) -> f64 {
        let t = s * self.length;
        let n = polygon.len();
        let mut area = 0.0;
        match self.axis {
            Axis::X | Axis::Y => {
                // Sutherland–Hodgman against t(p) ≤ t, summed as it goes
                // (the shoelace over the clipped polygon's edges).
                let mut first: Option<Point> = None;
                let mut last: Option<Point> = None;
                let mut push = |p: Point| {
                    if let Some(q) = last {
                        area += q.x * p.y - p.x * q.y;
                    } else {
                        first = Some(p);
                    }
                    last = Some(p);
                };
                for i in 0..n {
                    let (a, b) = (polygon[i], polygon[(i + 1) % n]);
                    let (ta, tb) = (self.t(a), self.t(b));
                    if ta <= t {
                        push(a);
                    }
                    if (ta <= t) != (tb <= t) {
                        let w = (t - ta) / (tb - ta);
                        push(a + (b - a) * w);
                    }
                }
                if let (Some(f), Some(l)) = (first, last) {
                    area += l.x * f.y - f.x * l.y;
                }
                0.5 * area
            }
            Axis::Radial => {
                if t <= 0.0 {
                    return 0.0;
                }
                for i in 0..n {
                    let a = polygon[i] - self.origin;
                    let b = polygon[(i + 1) % n] - self.origin;
                    area += disk_triangle(a, b, t);
                }
                area
            }
        }
    }

    /// The coordinate of `p` along the axis (mm from the origin, unclamped).
    fn t(&self, p: Point) -> f64 {
        match self.axis {
            Axis::X => p.x - self.origin.x,
            Axis::Y => p.y - self.origin.y,
            Axis::Radial => (p - self.origin).norm(),
        }
    }
}

/// Signed area of the triangle (0, `a`, `b`) within the disk of radius `r`
/// about 0: the edge split where it crosses the circle, each piece inside
/// a triangle and each piece outside a circular sector.
fn disk_triangle(a: Vector2<f64>, b: Vector2<f64>, r: f64) -> f64 {
    let d = b - a;
    let (qa, qb, qc) = (d.dot(&d), a.dot(&d), a.dot(&a) - r * r);
    let mut ts = [0.0, 1.0, 1.0, 1.0];
    let mut n = 1;
    let disc = qb * qb - qa * qc;
    if qa > 0.0 && disc > 0.0 {
        let root = disc.sqrt();
        for t in [(-qb - root) / qa, (-qb + root) / qa] {
            if t > 0.0 && t < 1.0 {
                ts[n] = t;
                n += 1;
            }
        }
    }
    ts[n] = 1.0;
    let cross = |p: Vector2<f64>, q: Vector2<f64>| p.x * q.y - p.y * q.x;
    (0..n)
        .map(|k| {
            let (p, q) = (a + d * ts[k], a + d * ts[k + 1]);
            let m = a + d * (0.5 * (ts[k] + ts[k + 1]));
            if m.norm_squared() <= r * r {
                0.5 * cross(p, q)
            } else {
                0.5 * r * r * cross(p, q).atan2(p.dot(&q))
            }
        })
        .sum()
}

/// The target fractions of the materials along the axis.
#[derive(Debug, Clone, PartialEq)]
pub enum Profile {
    /// Layers from s = 0 up: (material index, thickness as a fraction of the
    /// axis); the thicknesses add up to 1. Any number of materials.
    Steps(Vec<(usize, f64)>),
    /// Two materials; the second's fraction is s.
    Linear,
    /// Two materials; the second's fraction is s^p.
    Power(f64),
    /// Two materials; the second's fraction is ½(2s)^p below s = ½ and
    /// 1 − ½(2(1 − s))^p above: two power-law halves meeting at ½.
    Sigmoid(f64),
    /// Rows of s and one fraction per material, s rising within [0, 1];
    /// linear between rows, constant beyond the first and last.
    Table(Vec<(f64, Vec<f64>)>),
}

impl Profile {
    /// The profile's name as written in configs.
    pub fn name(&self) -> &'static str {
        match self {
            Profile::Steps(_) => "steps",
            Profile::Linear => "linear",
            Profile::Power(_) => "power",
            Profile::Sigmoid(_) => "sigmoid",
            Profile::Table(_) => "table",
        }
    }

    /// The target fractions at `s` (clamped to [0, 1]) into `out`, one per
    /// material (`out.len()` of them); they add up to 1.
    pub fn fractions(&self, s: f64, out: &mut [f64]) {
        let s = s.clamp(0.0, 1.0);
        out.fill(0.0);
        let second = |out: &mut [f64], f: f64| {
            if let [a, b, ..] = out {
                (*a, *b) = (1.0 - f, f);
            }
        };
        match self {
            Profile::Linear => second(out, s),
            Profile::Power(p) => second(out, s.powf(*p)),
            Profile::Sigmoid(p) => {
                let f = if s <= 0.5 {
                    0.5 * (2.0 * s).powf(*p)
                } else {
                    1.0 - 0.5 * (2.0 * (1.0 - s)).powf(*p)
                };
                second(out, f);
            }
            Profile::Steps(layers) => {
                let mut top = 0.0;
                let last = layers.len().saturating_sub(1);
                for (i, &(m, t)) in layers.iter().enumerate() {
                    top += t;
                    if s < top || i == last {
                        if let Some(f) = out.get_mut(m) {
                            *f = 1.0;
                        }
                        return;
                    }
                }
            }
            Profile::Table(rows) => {
                let i = rows.partition_point(|(rs, _)| *rs <= s);
                let (lo, hi) = match i {
                    0 => (&rows[0], &rows[0]),
                    i if i == rows.len() => (&rows[i - 1], &rows[i - 1]),
                    i => (&rows[i - 1], &rows[i]),
                };
                let w = if hi.0 > lo.0 {
                    (s - lo.0) / (hi.0 - lo.0)
                } else {
                    0.0
                };
                for (f, (a, b)) in out.iter_mut().zip(lo.1.iter().zip(&hi.1)) {
                    *f = a + w * (b - a);
                }
            }
        }
    }
}

/// Size-graded packing: the grading blends from the scene's curve (the first
/// material) into a second curve (the second material) along an axis,
/// following a two-material profile; every disk is of the material whose
/// curve it was drawn from.
///
/// With particle shapes, the first material's shape is the scene's
/// ([`Scene::shape`](crate::Scene::shape)) and the second's is
/// `second_shape` when it has its own: each particle is drawn with the
/// shape of the material whose curve it was drawn from.
#[derive(Debug, Clone)]
pub struct SizeGradient {
    /// Where the blend runs.
    pub axis: Axis,
    /// The area fraction of the second material along the axis.
    pub profile: Profile,
    /// The second material's curve.
    pub second: Grading,
    /// The second material's shape, when it is not the scene's (`None`:
    /// the scene's shape, or disks in a scene without one). Read only in a
    /// scene with a shape: a scene of disks is packed by the disk packers.
    pub second_shape: Option<ShapeSpec>,
}

impl SizeGradient {
    /// A gradient into `second` along `axis` following `profile`, both
    /// materials of the scene's shape.
    pub fn new(axis: Axis, profile: Profile, second: Grading) -> Self {
        SizeGradient {
            axis,
            profile,
            second,
            second_shape: None,
        }
    }

    /// The same gradient with the second material of its own `shape`.
    #[must_use]
    pub fn with_second_shape(self, shape: ShapeSpec) -> Self {
        SizeGradient {
            second_shape: Some(shape),
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn second(p: &Profile, s: f64) -> f64 {
        let mut out = [0.0; 2];
        p.fractions(s, &mut out);
        assert!(
            (out[0] + out[1] - 1.0).abs() < 1e-12,
            "fractions add up to 1"
        );
        out[1]
    }

    #[test]
    fn continuous_profiles_follow_their_formulas() {
        for s in [0.0, 0.1, 0.25, 0.5, 0.7, 1.0] {
            assert!((second(&Profile::Linear, s) - s).abs() < 1e-12);
            assert!((second(&Profile::Power(2.0), s) - s * s).abs() < 1e-12);
            let sig = if s <= 0.5 {
                0.5 * (2.0 * s).powi(3)
            } else {
                1.0 - 0.5 * (2.0 * (1.0 - s)).powi(3)
            };
            assert!((second(&Profile::Sigmoid(3.0), s) - sig).abs() < 1e-12);
        }
        assert_eq!(second(&Profile::Sigmoid(3.0), 0.5), 0.5);
    }

    #[test]
    fn steps_and_tables_follow_their_definitions() {
        let steps = Profile::Steps(vec![(2, 0.25), (0, 0.5), (1, 0.25)]);
        let mut out = [0.0; 3];
        for (s, m) in [(0.0, 2), (0.2, 2), (0.3, 0), (0.74, 0), (0.76, 1), (1.0, 1)] {
            steps.fractions(s, &mut out);
            assert_eq!(out.iter().sum::<f64>(), 1.0);
            assert_eq!(out[m], 1.0, "s = {s}");
        }
        let table = Profile::Table(vec![(0.2, vec![1.0, 0.0]), (0.6, vec![0.2, 0.8])]);
        assert!((second(&table, 0.0)).abs() < 1e-12);
        assert!((second(&table, 0.4) - 0.4).abs() < 1e-12);
        assert!((second(&table, 0.9) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn polygon_areas_below_match_the_disk_slabs() {
        // A 720-gon about a disk: its clipped areas are the disk's within
        // the polygon's deficit (about 1.3e-5 of the area).
        let domain = Domain::rectangle(10.0, 6.0).unwrap();
        let disk = Disk::new(4.3, 2.1, 0.7);
        let polygon: Vec<Point> = (0..720)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 720.0;
                disk.c + Vector2::new(t.cos(), t.sin()) * disk.r
            })
            .collect();
        for axis in [Axis::X, Axis::Y, Axis::Radial] {
            let frame = Frame::new(axis, &domain);
            let (a, b) = frame.span(&disk);
            assert!((frame.polygon_span(&polygon).0 - a).abs() < 1e-5);
            for cut in [a + 0.1 * (b - a), 0.5 * (a + b), a + 0.8 * (b - a)] {
                let below = frame.polygon_area_below(&polygon, cut);
                let exact = frame.area_between(&disk, a - 1.0, cut);
                assert!(
                    (below - exact).abs() < 2e-5 * disk.area(),
                    "{axis:?} at {cut}: {below} vs {exact}"
                );
            }
            let whole = frame.polygon_area_below(&polygon, b + 1.0);
            assert!((whole - disk.area()).abs() < 2e-5 * disk.area(), "{axis:?}");
            assert!(frame.polygon_area_below(&polygon, a - 0.01).abs() < 1e-12);
        }
    }

    #[test]
    fn frame_areas_add_up_to_the_disk() {
        let domain = Domain::rectangle(10.0, 6.0).unwrap();
        let disk = Disk::new(4.3, 2.1, 0.7);
        for axis in [Axis::X, Axis::Y, Axis::Radial] {
            let frame = Frame::new(axis, &domain);
            let (a, b) = frame.span(&disk);
            let cut = 0.5 * (a + b) + 0.01;
            let total =
                frame.area_between(&disk, a - 0.1, cut) + frame.area_between(&disk, cut, b + 0.1);
            assert!((total - disk.area()).abs() < 1e-9, "{axis:?}: {total}");
            assert!(frame.area_between(&disk, a - 0.1, cut) > 0.0);
        }
    }
}
