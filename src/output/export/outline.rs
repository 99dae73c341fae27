//! Particle outlines as the DEM exports write them: polygons inside the
//! particle, shrunk so that their rounded version stays inside too, and
//! the area moments a DEM code needs for mass and inertia.

use crate::geometry::{Grain, Outline, Point};
use crate::output::OutputError;

/// Points on a superellipse's outline in its DEM polygon.
pub(super) const DEM_SEGMENTS: usize = 48;

/// Rounding radius of an exported polygon whose particle has sharp (or
/// sharper) corners, as a fraction of the particle's least width.
pub(super) const ROUNDING_REL: f64 = 0.01;

/// A particle as a rounded polygon inside it, in its own axes: the core
/// polygon (counter-clockwise) and the corner radius; the core grown by the
/// radius lies inside the particle.
pub(super) struct Rounded {
    /// The core polygon's vertices (own axes, mm).
    pub(super) core: Vec<Point>,
    /// The corner radius (mm).
    pub(super) rounding: f64,
}

impl Rounded {
    /// The rounded polygon of `outline`: a rounded polygon keeps its
    /// vertices and radius when the radius is at least `ROUNDING_REL` of
    /// its least width, else its polygon is shrunk by the difference and
    /// rounded by that much; a superellipse's inscribed polygon of
    /// `DEM_SEGMENTS` points on its outline is shrunk by `ROUNDING_REL` of
    /// its least width and rounded by as much.
    pub(super) fn of(outline: &Outline) -> Self {
        let least = ROUNDING_REL * outline.least_width();
        match outline {
            Outline::Polygon {
                vertices, rounding, ..
            } => {
                if *rounding >= least {
                    Rounded {
                        core: vertices.to_vec(),
                        rounding: *rounding,
                    }
                } else {
                    Rounded {
                        core: shrink(vertices, least - rounding),
                        rounding: least,
                    }
                }
            }
            Outline::Superellipse { .. } => Rounded {
                core: shrink(&outline.boundary(DEM_SEGMENTS), least),
                rounding: least,
            },
        }
    }

    /// The rounded polygon drawn as a polygon of points on its outline
    /// (own axes), for its area moments.
    pub(super) fn fine(&self) -> Vec<Point> {
        match Outline::polygon(0, &self.core, self.rounding) {
            Ok(o @ Outline::Polygon { .. }) => {
                // The same vertices, moved onto their centroid: moved back.
                let shift = centroid(&self.core);
                o.boundary(8 * self.core.len().max(32))
                    .into_iter()
                    .map(|p| p + shift.coords)
                    .collect()
            }
            _ => self.core.clone(),
        }
    }
}

/// The convex counter-clockwise polygon `p` shrunk by `delta`: the
/// intersection of its edges' half-planes, each moved inwards by `delta`
/// (and a few ulps more), so that the result grown by a disk of radius
/// `delta` lies inside `p`. Vertices closer than 1e-9 of the polygon's
/// size are merged.
pub(super) fn shrink(p: &[Point], delta: f64) -> Vec<Point> {
    let n = p.len();
    let size = p.iter().map(|v| v.coords.norm()).fold(0.0, f64::max);
    let d = delta * (1.0 + 1e-12) + 1e-15 * size;
    let mut poly: Vec<Point> = p.to_vec();
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let e = b - a;
        let len = e.norm();
        if len == 0.0 {
            continue;
        }
        // Outward unit normal of a counter-clockwise edge.
        let normal = nalgebra::Vector2::new(e.y, -e.x) / len;
        let limit = normal.dot(&a.coords) - d;
        let inside = |q: &Point| normal.dot(&q.coords) <= limit;
        let m = poly.len();
        let mut next = Vec::with_capacity(m + 1);
        for j in 0..m {
            let (s, t) = (poly[j], poly[(j + 1) % m]);
            let (si, ti) = (inside(&s), inside(&t));
            if si {
                next.push(s);
            }
            if si != ti {
                let hs = normal.dot(&s.coords) - limit;
                let ht = normal.dot(&t.coords) - limit;
                let k = hs / (hs - ht);
                next.push(s + (t - s) * k);
            }
        }
        poly = next;
    }
    let mut out: Vec<Point> = Vec::with_capacity(poly.len());
    for q in poly {
        if out
            .last()
            .is_none_or(|l: &Point| (q - l).norm() > 1e-9 * size)
        {
            out.push(q);
        }
    }
    while out.len() > 1 && (out[0] - out[out.len() - 1]).norm() <= 1e-9 * size {
        out.pop();
    }
    out
}

/// Area centroid of a polygon (the mean of its vertices if it has no area).
fn centroid(p: &[Point]) -> Point {
    let m = Moments::of(p);
    if m.area == 0.0 {
        let k = p.len().max(1) as f64;
        return Point::new(
            p.iter().map(|q| q.x).sum::<f64>() / k,
            p.iter().map(|q| q.y).sum::<f64>() / k,
        );
    }
    Point::new(m.sx / m.area, m.sy / m.area)
}

/// Area moments of a counter-clockwise polygon about the origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Moments {
    /// ∫ dA.
    pub(super) area: f64,
    /// ∫ x dA.
    pub(super) sx: f64,
    /// ∫ y dA.
    pub(super) sy: f64,
    /// ∫ x² dA.
    pub(super) xx: f64,
    /// ∫ y² dA.
    pub(super) yy: f64,
    /// ∫ xy dA.
    pub(super) xy: f64,
}

impl Moments {
    /// The moments of polygon `p` (Green's theorem, edge by edge).
    pub(super) fn of(p: &[Point]) -> Self {
        let n = p.len();
        let mut m = Moments {
            area: 0.0,
            sx: 0.0,
            sy: 0.0,
            xx: 0.0,
            yy: 0.0,
            xy: 0.0,
        };
        for i in 0..n {
            let (a, b) = (p[i], p[(i + 1) % n]);
            let c = a.x * b.y - b.x * a.y;
            m.area += c / 2.0;
            m.sx += (a.x + b.x) * c / 6.0;
            m.sy += (a.y + b.y) * c / 6.0;
            m.xx += (a.x * a.x + a.x * b.x + b.x * b.x) * c / 12.0;
            m.yy += (a.y * a.y + a.y * b.y + b.y * b.y) * c / 12.0;
            m.xy += (a.x * b.y + 2.0 * a.x * a.y + 2.0 * b.x * b.y + b.x * a.y) * c / 24.0;
        }
        m
    }
}

/// The points `p` of a grain's own axes in world axes about its centre.
pub(super) fn turned(grain: &Grain, p: &[Point]) -> Vec<Point> {
    let t = grain.turned();
    p.iter().map(|&q| Point::from(t.to_world(q))).collect()
}

/// A particle as a superquadric's midplane: semi-axes `a`, `b` (mm, own
/// axes) and the one exponent `n` of |x'/a|^n + |y'/b|^n <= 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Superquadric {
    /// Semi-axis along the particle's own x axis (mm).
    pub(super) a: f64,
    /// Semi-axis along the particle's own y axis (mm).
    pub(super) b: f64,
    /// The exponent (blockiness), at least 2.
    pub(super) n: f64,
}

/// Every grain as a superquadric, for a format (`format`, its config name)
/// whose particles are superquadrics: superellipses with alpha = beta >= 2.
///
/// # Errors
/// [`OutputError::Unsupported`] at the first grain that is a rounded
/// polygon, or a superellipse with alpha != beta or an exponent below 2.
pub(super) fn superquadrics(
    grains: &[Grain],
    format: &'static str,
) -> Result<Vec<Superquadric>, OutputError> {
    grains
        .iter()
        .enumerate()
        .map(|(i, g)| match g.outline {
            Outline::Superellipse { a, b, alpha, beta } if alpha == beta && alpha >= 2.0 => {
                Ok(Superquadric { a, b, n: alpha })
            }
            Outline::Superellipse { alpha, beta, .. } => Err(OutputError::Unsupported {
                format,
                reason: format!(
                    "particle {i} has exponents alpha = {alpha}, beta = {beta}: a superquadric has one exponent (blockiness) in its plane, of at least 2; export it as lammps (rounded polygons) or vtk"
                ),
            }),
            Outline::Polygon { .. } => Err(OutputError::Unsupported {
                format,
                reason: format!(
                    "particle {i} is a rounded polygon, which is no superquadric; export it as lammps (body rounded/polygon) or vtk"
                ),
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_shrinks_by_its_offset_and_its_moments_are_exact() {
        let square = [
            Point::new(-1.0, -1.0),
            Point::new(1.0, -1.0),
            Point::new(1.0, 1.0),
            Point::new(-1.0, 1.0),
        ];
        let core = shrink(&square, 0.25);
        assert_eq!(core.len(), 4);
        for q in &core {
            assert!((q.x.abs() - 0.75).abs() < 1e-12 && (q.y.abs() - 0.75).abs() < 1e-12);
            assert!(q.x.abs() < 0.75 && q.y.abs() < 0.75, "strictly inside");
        }
        let m = Moments::of(&square);
        assert!((m.area - 4.0).abs() < 1e-12);
        assert!((m.xx - 4.0 / 3.0).abs() < 1e-12 && (m.yy - 4.0 / 3.0).abs() < 1e-12);
        assert!(m.xy.abs() < 1e-12 && m.sx.abs() < 1e-12);
    }

    #[test]
    fn rounded_cores_stay_inside_the_particle() {
        let outline = Outline::superellipse(1.5, 1.0, 4.0, 3.0).expect("valid");
        let r = Rounded::of(&outline);
        assert!(r.rounding > 0.0 && r.core.len() >= 8);
        // Every point of the rounded polygon's outline lies inside the
        // superellipse |x/a|^alpha + |y/b|^beta <= 1.
        for p in r.fine() {
            let v = (p.x / 1.5).abs().powf(4.0) + (p.y / 1.0).abs().powf(3.0);
            assert!(v < 1.0, "{p:?}: {v}");
        }
        // And it fills it to within a few percent.
        let a = Moments::of(&r.fine()).area;
        assert!(a > 0.95 * outline.area() && a < outline.area(), "{a}");
    }

    #[test]
    fn only_superellipses_with_one_exponent_of_2_or_more_are_superquadrics() {
        let se = |alpha, beta| {
            Grain::new(
                Outline::superellipse(2.0, 1.0, alpha, beta).expect("valid"),
                0.5,
            )
        };
        let q = superquadrics(&[se(4.0, 4.0)], "mercury").expect("a superquadric");
        assert_eq!(
            q,
            [Superquadric {
                a: 2.0,
                b: 1.0,
                n: 4.0
            }]
        );
        for bad in [se(4.0, 3.0), se(1.5, 1.5)] {
            let e = superquadrics(&[se(2.0, 2.0), bad], "mercury").expect_err("refused");
            assert!(
                e.to_string()
                    .starts_with("mercury: particle 1 has exponents"),
                "{e}"
            );
        }
        let square = [
            Point::new(-1.0, -1.0),
            Point::new(1.0, -1.0),
            Point::new(1.0, 1.0),
            Point::new(-1.0, 1.0),
        ];
        let poly = Grain::new(Outline::polygon(0, &square, 0.0).expect("valid"), 0.0);
        let e = superquadrics(&[poly], "liggghts-superquadric").expect_err("refused");
        assert!(
            e.to_string().contains("particle 0 is a rounded polygon"),
            "{e}"
        );
    }
}
