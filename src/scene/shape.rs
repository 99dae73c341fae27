//! The shape of the particles (`[shape]` in a config): which outline each
//! size drawn from the grading becomes, how it is turned, and which of its
//! sizes the grading measures.
//!
//! Without a shape the particles are disks and nothing here is used. With
//! one, each diameter D drawn from the grading is given an outline (its
//! parameters drawn from their own seeded stream, so that the sizes are the
//! same draws as for disks) scaled so that its measured size is D:
//! - [`SizeMeasure::Sieve`]: its least width (the narrowest strip it fits
//!   in, [`Outline::least_width`]), what a sieve analysis measures;
//! - [`SizeMeasure::Equivalent`]: the diameter of the disk of the same area.
//!
//! For an ellipse of aspect A the two differ by √A (area-equivalent
//! diameter = least width·√A); every packing reports both.

use rand::Rng;
use rand_distr::{Distribution, Normal};

use crate::geometry::{Grain, Outline, Point};

/// Seed offset of the stream shape parameters and orientations are drawn
/// from (xor-ed with the scene's seed), apart from the sizes' stream.
pub const SHAPE_STREAM: u64 = 0x5348_4150_455f_3031;

/// Largest aspect ratio a particle may have (a superellipse's a/b, a
/// polygon template's greatest over least width): thinner particles make
/// the contact solving lose precision (the distance between two needles
/// turned almost parallel is found to too few digits to certify it).
pub const MAX_ASPECT: f64 = 20.0;

/// Largest superellipse exponent: blockier outlines make the contact
/// solving lose precision (their support points jump across the nearly
/// square corners as the direction turns).
pub const MAX_EXPONENT: f64 = 50.0;

/// Least area of a convex particle of least width w, over w² (Pál: the
/// equilateral triangle): 1/√3.
const PAL_AREA: f64 = 0.577_350_269_189_625_8;

/// Relative margin taken off every area ratio of [`ShapeSpec::least_area_ratio`]:
/// the measured sizes come from sampled widths, a few ulps off the exact ones.
const AREA_MARGIN: f64 = 1e-9;

/// Nodes per range in [`ShapeSpec::mean_area_ratio`]'s midpoint rule.
const RANGE_NODES: usize = 5;

/// A quantity of a shape: one value, a uniform range, or values with shares.
#[derive(Debug, Clone, PartialEq)]
pub enum Spread {
    /// Always this value.
    Fixed(f64),
    /// Uniform between the two (inclusive, low first).
    Range(f64, f64),
    /// Each value with its share (shares positive, summing to 1).
    Shares(Vec<(f64, f64)>),
}

impl Spread {
    /// A value drawn from `rng` (nothing drawn for a fixed value).
    pub fn draw(&self, rng: &mut impl Rng) -> f64 {
        match self {
            Spread::Fixed(v) => *v,
            Spread::Range(lo, hi) => lo + (hi - lo) * rng.r#gen::<f64>(),
            Spread::Shares(table) => {
                let u: f64 = rng.r#gen();
                let mut acc = 0.0;
                for &(v, share) in table {
                    acc += share;
                    if u < acc {
                        return v;
                    }
                }
                table.last().map_or(0.0, |&(v, _)| v)
            }
        }
    }

    /// The least and greatest value it can take.
    pub fn bounds(&self) -> (f64, f64) {
        match self {
            Spread::Fixed(v) => (*v, *v),
            Spread::Range(lo, hi) => (*lo, *hi),
            Spread::Shares(t) => t
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(v, _)| {
                    (lo.min(v), hi.max(v))
                }),
        }
    }
}

impl Spread {
    /// Values and weights (summing to 1) whose weighted mean approximates
    /// the mean of any smooth function of a draw: the value itself, a
    /// table's rows, or a range's [`RANGE_NODES`] midpoints.
    pub(crate) fn nodes(&self) -> Vec<(f64, f64)> {
        match self {
            Spread::Fixed(v) => vec![(*v, 1.0)],
            Spread::Range(lo, hi) => (0..RANGE_NODES)
                .map(|k| {
                    let t = (k as f64 + 0.5) / RANGE_NODES as f64;
                    (lo + (hi - lo) * t, 1.0 / RANGE_NODES as f64)
                })
                .collect(),
            Spread::Shares(table) => table.clone(),
        }
    }
}

/// Which outlines the particles have.
#[derive(Debug, Clone, PartialEq)]
pub enum Family {
    /// Superellipses |x/a|^α + |y/b|^β ≤ 1 with a/b = `aspect` (≥ 1: the
    /// long axis is the particle's own x axis).
    Superellipse {
        /// Aspect ratio a/b (≥ 1).
        aspect: Spread,
        /// Exponent α (≥ 1).
        alpha: Spread,
        /// Exponent β (≥ 1).
        beta: Spread,
    },
    /// Rounded convex polygons: each template (of any size: it is scaled)
    /// with its share of the particles.
    Polygons {
        /// The templates and their shares (summing to 1).
        templates: Vec<(Outline, f64)>,
    },
}

/// How the particles are turned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Orientation {
    /// Uniformly at random.
    Random,
    /// About a mean angle (radians, counter-clockwise from the x axis),
    /// normally distributed with standard deviation `spread` (radians; 0:
    /// all at the mean).
    Aligned {
        /// Mean angle (radians).
        mean: f64,
        /// Standard deviation (radians).
        spread: f64,
    },
}

/// Which size of a particle the grading curve gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SizeMeasure {
    /// The least width: the sieve a particle passes.
    #[default]
    Sieve,
    /// The diameter of the disk of the same area.
    Equivalent,
}

impl SizeMeasure {
    /// The name a config gives it.
    pub fn name(self) -> &'static str {
        match self {
            SizeMeasure::Sieve => "sieve",
            SizeMeasure::Equivalent => "equivalent",
        }
    }
}

/// The particles' shape: outlines, orientation and the size measured.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeSpec {
    /// The outlines.
    pub family: Family,
    /// The orientation.
    pub orientation: Orientation,
    /// Which size the grading measures.
    pub size: SizeMeasure,
}

impl ShapeSpec {
    /// Ellipses of aspect ratio `aspect`, turned at random, sized by sieve.
    pub fn ellipses(aspect: f64) -> ShapeSpec {
        ShapeSpec::superellipses(aspect, 2.0)
    }

    /// Superellipses of aspect ratio `aspect` and exponents α = β =
    /// `exponent`, turned at random, sized by sieve.
    pub fn superellipses(aspect: f64, exponent: f64) -> ShapeSpec {
        ShapeSpec {
            family: Family::Superellipse {
                aspect: Spread::Fixed(aspect),
                alpha: Spread::Fixed(exponent),
                beta: Spread::Fixed(exponent),
            },
            orientation: Orientation::Random,
            size: SizeMeasure::Sieve,
        }
    }

    /// The least ratio of a particle's area to that of the disk whose
    /// diameter is its measured size, a lower bound over every outline the
    /// shape can draw (less a relative 10⁻⁹ for the sampled widths):
    /// - sized by equivalent diameter, 1: the area is the disk's;
    /// - superellipses (α, β ≥ 1) sized by sieve, 1: their area is at
    ///   least the disk's of their least width;
    /// - polygons sized by sieve, (1/√3)/(π/4) ≈ 0.735: a convex shape of
    ///   least width w has area at least w²/√3 (Pál; the equilateral
    ///   triangle), less than the disk's πw²/4.
    ///
    /// The most particles a domain holds is its area over this ratio times
    /// the smallest disk's ([`crate::Scene::max_disks`]).
    pub fn least_area_ratio(&self) -> f64 {
        let ratio = match (&self.family, self.size) {
            (Family::Polygons { .. }, SizeMeasure::Sieve) => PAL_AREA / std::f64::consts::FRAC_PI_4,
            _ => 1.0,
        };
        ratio * (1.0 - AREA_MARGIN)
    }

    /// The mean ratio of a particle's area to that of the disk whose
    /// diameter is its measured size: exact for fixed parameters and for
    /// polygons (their shares), a midpoint rule over ranges. The outline is
    /// drawn apart from the size, so a particle's mean area is this times
    /// the grading's mean disk area (for [`crate::Scene::estimated_disks`]).
    pub fn mean_area_ratio(&self) -> f64 {
        let ratio = |o: &Outline| {
            let m = self.measure(o);
            o.area() / (std::f64::consts::FRAC_PI_4 * m * m)
        };
        match &self.family {
            Family::Polygons { templates } => templates.iter().map(|(t, s)| s * ratio(t)).sum(),
            Family::Superellipse {
                aspect,
                alpha,
                beta,
            } => {
                let mut sum = 0.0;
                for (a, wa) in aspect.nodes() {
                    for (al, wl) in alpha.nodes() {
                        for (be, wb) in beta.nodes() {
                            let o = Outline::Superellipse {
                                a,
                                b: 1.0,
                                alpha: al,
                                beta: be,
                            };
                            sum += wa * wl * wb * ratio(&o);
                        }
                    }
                }
                sum
            }
        }
    }

    /// A drawer of grains for this shape, with the measures of fixed
    /// outlines computed once.
    pub fn drawer(&self) -> Drawer<'_> {
        let fixed = match &self.family {
            Family::Superellipse {
                aspect: Spread::Fixed(a),
                alpha: Spread::Fixed(al),
                beta: Spread::Fixed(be),
            } => {
                let o = Outline::Superellipse {
                    a: *a,
                    b: 1.0,
                    alpha: *al,
                    beta: *be,
                };
                vec![(self.measure(&o), o)]
            }
            Family::Polygons { templates } => templates
                .iter()
                .map(|(t, _)| (self.measure(t), t.clone()))
                .collect(),
            Family::Superellipse { .. } => Vec::new(),
        };
        Drawer { spec: self, fixed }
    }

    /// The size of `outline` the grading measures.
    pub fn measure(&self, outline: &Outline) -> f64 {
        match self.size {
            SizeMeasure::Sieve => outline.least_width(),
            SizeMeasure::Equivalent => 2.0 * outline.equivalent_radius(),
        }
    }

    /// The largest ratio of a particle's circumradius to half its measured
    /// size: how much larger than a disk of the grading's diameter a
    /// particle's bounding circle may be (for the index and the estimates).
    pub fn reach_ratio(&self) -> f64 {
        let unit_ratio = |o: &Outline| 2.0 * o.circumradius() / self.measure(o);
        match &self.family {
            Family::Superellipse {
                aspect,
                alpha,
                beta,
            } => {
                let (a0, a1) = aspect.bounds();
                let (l0, l1) = alpha.bounds();
                let (b0, b1) = beta.bounds();
                if a0 == a1 && l0 == l1 && b0 == b1 {
                    return unit_ratio(&Outline::Superellipse {
                        a: a0,
                        b: 1.0,
                        alpha: l0,
                        beta: b0,
                    });
                }
                // Over ranges, a bound for any α, β ≥ 1: the circumradius is
                // at most the half diagonal √(a² + 1) of the bounding box,
                // the least width at least the rhombus' 2a/√(a² + 1), the
                // area at least the rhombus' 2a.
                let diagonal = (a1 * a1 + 1.0).sqrt();
                match self.size {
                    SizeMeasure::Sieve => diagonal * (a0 * a0 + 1.0).sqrt() / a0,
                    SizeMeasure::Equivalent => diagonal / (2.0 * a0 / std::f64::consts::PI).sqrt(),
                }
            }
            Family::Polygons { templates } => templates
                .iter()
                .map(|(t, _)| unit_ratio(t))
                .fold(1.0, f64::max),
        }
    }
}

/// Draws the grains of a [`ShapeSpec`] (see [`ShapeSpec::drawer`]).
#[derive(Debug, Clone)]
pub struct Drawer<'a> {
    spec: &'a ShapeSpec,
    /// Fixed unit outlines with their measures: the one superellipse of
    /// fixed parameters, or each polygon template.
    fixed: Vec<(f64, Outline)>,
}

impl Drawer<'_> {
    /// The grain of a particle whose measured size is `diameter`, its
    /// outline and angle drawn from `rng`.
    ///
    /// # Behavior
    /// The unit outline (b = 1, or the template as given) is drawn, then
    /// scaled so that its measure ([`SizeMeasure`]) is `diameter`. Fixed
    /// parameters draw nothing but the angle (and a template one number).
    pub fn draw(&self, diameter: f64, rng: &mut impl Rng) -> Grain {
        let spec = self.spec;
        let (measure, unit) = match &spec.family {
            Family::Superellipse {
                aspect,
                alpha,
                beta,
            } => {
                if let Some((m, o)) = self.fixed.first() {
                    (*m, o.clone())
                } else {
                    let o = Outline::Superellipse {
                        a: aspect.draw(rng),
                        b: 1.0,
                        alpha: alpha.draw(rng),
                        beta: beta.draw(rng),
                    };
                    (spec.measure(&o), o)
                }
            }
            Family::Polygons { templates } => {
                let u: f64 = rng.r#gen();
                let mut acc = 0.0;
                let mut pick = templates.len() - 1;
                for (i, (_, share)) in templates.iter().enumerate() {
                    acc += share;
                    if u < acc {
                        pick = i;
                        break;
                    }
                }
                let (m, o) = &self.fixed[pick];
                (*m, o.clone())
            }
        };
        let outline = unit.scaled(diameter / measure);
        let turn = match &spec.family {
            // A superellipse is symmetric under a half turn.
            Family::Superellipse { .. } => std::f64::consts::PI,
            Family::Polygons { .. } => std::f64::consts::TAU,
        };
        let angle = match spec.orientation {
            Orientation::Random => turn * rng.r#gen::<f64>(),
            Orientation::Aligned { mean, spread } => {
                if spread > 0.0 {
                    Normal::new(mean, spread).map_or(mean, |n| n.sample(rng))
                } else {
                    mean
                }
            }
        };
        Grain::new(outline, angle)
    }
}

/// A polygon template's vertices as a config gives them.
pub fn template_vertices(points: &[[f64; 2]]) -> Vec<Point> {
    points.iter().map(|p| Point::new(p[0], p[1])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// The area of `outline` over the disk of its measured size.
    fn area_ratio(spec: &ShapeSpec, outline: &Outline) -> f64 {
        let m = spec.measure(outline);
        outline.area() / (std::f64::consts::FRAC_PI_4 * m * m)
    }

    #[test]
    fn least_area_ratio_bounds_every_outline_and_is_tight_for_triangles() {
        let exponents = [1.0, 1.5, 2.0, 4.0, MAX_EXPONENT];
        for size in [SizeMeasure::Sieve, SizeMeasure::Equivalent] {
            for aspect in [1.0, 1.3, 2.0, MAX_ASPECT] {
                for alpha in exponents {
                    for beta in exponents {
                        let spec = ShapeSpec {
                            size,
                            ..ShapeSpec::superellipses(aspect, alpha)
                        };
                        let o = Outline::Superellipse {
                            a: aspect,
                            b: 1.0,
                            alpha,
                            beta,
                        };
                        let ratio = area_ratio(&spec, &o);
                        assert!(ratio >= spec.least_area_ratio(), "{aspect} {alpha} {beta}");
                    }
                }
            }
        }
        let h = 3f64.sqrt();
        let shapes: [&[[f64; 2]]; 3] = [
            &[[0.0, 0.0], [2.0, 0.0], [1.0, h]],
            &[[0.0, 0.0], [5.0, 0.0], [1.0, 1.0]],
            &[[0.0, 0.0], [1.0, 0.0], [1.5, 0.8], [0.5, 1.5], [-0.4, 0.9]],
        ];
        for (i, vertices) in shapes.into_iter().enumerate() {
            let o = Outline::polygon(0, &template_vertices(vertices), 0.0).expect("convex");
            let spec = ShapeSpec {
                family: Family::Polygons {
                    templates: vec![(o.clone(), 1.0)],
                },
                orientation: Orientation::Random,
                size: SizeMeasure::Sieve,
            };
            let (ratio, least) = (area_ratio(&spec, &o), spec.least_area_ratio());
            assert!(ratio >= least, "{i}: {ratio} < {least}");
            // Pál's bound is reached by the equilateral triangle, and a disk's is not a bound.
            if i == 0 {
                assert!(ratio < least * (1.0 + 1e-8) && ratio < 0.74, "{ratio}");
            }
            let equivalent = ShapeSpec {
                size: SizeMeasure::Equivalent,
                ..spec
            };
            assert!(area_ratio(&equivalent, &o) >= equivalent.least_area_ratio());
        }
    }

    #[test]
    fn mean_area_ratio_is_the_mean_over_the_draws() {
        // An ellipse of aspect A sized by sieve covers A times its disk.
        assert!((ShapeSpec::ellipses(3.0).mean_area_ratio() - 3.0).abs() < 1e-9);
        let spec = ShapeSpec {
            family: Family::Superellipse {
                aspect: Spread::Range(1.0, 3.0),
                alpha: Spread::Shares(vec![(2.0, 0.5), (4.0, 0.5)]),
                beta: Spread::Fixed(2.0),
            },
            orientation: Orientation::Random,
            size: SizeMeasure::Sieve,
        };
        // A fine midpoint grid over the same independent draws.
        let n = 100;
        let mut fine = 0.0;
        for k in 0..n {
            let a = 1.0 + 2.0 * (f64::from(k) + 0.5) / f64::from(n);
            for alpha in [2.0, 4.0] {
                let o = Outline::Superellipse {
                    a,
                    b: 1.0,
                    alpha,
                    beta: 2.0,
                };
                fine += 0.5 * area_ratio(&spec, &o) / f64::from(n);
            }
        }
        let rule = spec.mean_area_ratio();
        assert!((rule / fine - 1.0).abs() < 1e-3, "{rule} against {fine}");
        // Sized by equivalent diameter, every particle covers its disk.
        let equivalent = ShapeSpec {
            size: SizeMeasure::Equivalent,
            ..spec
        };
        assert!((equivalent.mean_area_ratio() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn drawn_grains_measure_the_drawn_size() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
        for size in [SizeMeasure::Sieve, SizeMeasure::Equivalent] {
            let spec = ShapeSpec {
                family: Family::Superellipse {
                    aspect: Spread::Range(1.0, 5.0),
                    alpha: Spread::Shares(vec![(2.0, 0.5), (6.0, 0.5)]),
                    beta: Spread::Range(1.0, 10.0),
                },
                orientation: Orientation::Random,
                size,
            };
            let ratio = spec.reach_ratio();
            let drawer = spec.drawer();
            for _ in 0..200 {
                let g = drawer.draw(3.0, &mut rng);
                let m = match size {
                    SizeMeasure::Sieve => g.outline.least_width(),
                    SizeMeasure::Equivalent => 2.0 * g.outline.equivalent_radius(),
                };
                assert!((m - 3.0).abs() < 1e-9, "{m}");
                assert!(2.0 * g.outline.circumradius() <= ratio * 3.0 * (1.0 + 1e-12));
                assert!((0.0..std::f64::consts::PI).contains(&g.angle));
            }
        }
    }
}
