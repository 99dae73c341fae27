//! Shape genes: what the target-porosity search may move of the
//! particles' shape (superellipses), within the bounds a config sets
//! (`[optimise.shape]`).
//!
//! # Genes
//! [`SHAPE_GENES`] genes after the packing-rule genes, each in [0, 1]:
//! - the aspect ratios drawn are uniform over a range inside the bounds:
//!   gene 0 places it (0: at the low bound, 1: at the high one), gene 1 is
//!   its width as a share of the bounds' (0: one aspect for all);
//! - gene 2 is the exponent α = β, between its bounds;
//! - gene 3 the standard deviation of the orientation of aligned
//!   particles, between its bounds (unused when the orientation is fixed).
//!
//! Each genome's particles draw their outlines from the same stream of
//! random numbers (the scene's seed), so two genomes differ by their
//! shapes, not by luck.
//!
//! # Constraints
//! Beside the grading's KS, a genome must keep (each excess adds to the
//! score's violation):
//! - the mean Riley sphericity and mean Wadell roundness of the shape it
//!   asks for (a midpoint rule over its aspect range, five outlines) at
//!   least the bounds: proppant specifications bound these
//!   means;
//! - the packed particles' aspect ratios within `max_shape_ks` (KS
//!   distance) of the distribution asked: the search may not reach a
//!   porosity by leaving the awkward particles out.

use serde::Serialize;

use crate::geometry::{Grain, Outline};
use crate::metrics::{roundness, sphericity};
use crate::scene::{Family, Orientation, ShapeSpec, Spread};

/// Shape genes after the packing-rule genes (see the module documentation).
pub const SHAPE_GENES: usize = 4;

/// What the search may move of a superellipse shape, and the constraints
/// its shapes keep (`[optimise.shape]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeBounds {
    /// Least and greatest aspect ratio a/b (≥ 1).
    pub aspect: [f64; 2],
    /// Least and greatest exponent α = β (≥ 1).
    pub exponent: [f64; 2],
    /// Least and greatest standard deviation (radians) of aligned
    /// particles' orientation; `None`: the orientation `[shape]` gives.
    pub spread: Option<[f64; 2]>,
    /// Least mean Riley sphericity of the shape asked (0: none).
    pub min_sphericity: f64,
    /// Least mean Wadell roundness of the shape asked (0: none).
    pub min_roundness: f64,
    /// Largest KS distance of the packed aspect ratios to the distribution asked.
    pub max_shape_ks: f64,
}

/// `max_shape_ks` when not given: a few hundred particles drawn from a
/// range lie within about 0.05 of it; the search may not bend it further.
pub const DEFAULT_MAX_SHAPE_KS: f64 = 0.1;

impl ShapeBounds {
    /// Bounds of one aspect range and one exponent range, the orientation
    /// fixed, no bound on sphericity or roundness.
    pub fn new(aspect: [f64; 2], exponent: [f64; 2]) -> Self {
        ShapeBounds {
            aspect,
            exponent,
            spread: None,
            min_sphericity: 0.0,
            min_roundness: 0.0,
            max_shape_ks: DEFAULT_MAX_SHAPE_KS,
        }
    }

    /// The shape genes of the roundest shape the bounds allow: the least
    /// aspect alone, the exponent nearest 2 (an ellipse), the least spread.
    /// Generation 0 starts its pinned genomes there, where the sphericity
    /// and roundness bounds are most likely kept.
    pub fn roundest(&self) -> [f64; SHAPE_GENES] {
        let [lo, hi] = self.exponent;
        let two = if hi > lo {
            ((2.0 - lo) / (hi - lo)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        [0.0, 0.0, two, 0.0]
    }

    /// The shape asked by `genes` (the [`SHAPE_GENES`] shape genes; missing
    /// ones read as 0).
    pub fn asked(&self, genes: &[f64]) -> AskedShape {
        let gene = |i: usize| genes.get(i).copied().unwrap_or(0.0).clamp(0.0, 1.0);
        let [lo, hi] = self.aspect;
        let width = gene(1) * (hi - lo);
        let start = lo + gene(0) * (hi - lo - width);
        let [e_lo, e_hi] = self.exponent;
        AskedShape {
            aspect: [start, (start + width).min(hi)],
            exponent: e_lo + gene(2) * (e_hi - e_lo),
            spread: self
                .spread
                .map(|[s_lo, s_hi]| s_lo + gene(3) * (s_hi - s_lo)),
        }
    }

    /// How far `asked` and the `grains` packed from it break the
    /// constraints (0: kept), with the measures behind it.
    pub fn judge(&self, asked: &AskedShape, grains: &[Grain]) -> ShapeMeasures {
        let (sphericity, roundness) = asked.means();
        let aspect_ks = asked.aspect_ks(grains);
        let violation = (self.min_sphericity - sphericity).max(0.0)
            + (self.min_roundness - roundness).max(0.0)
            + (aspect_ks - self.max_shape_ks).max(0.0);
        ShapeMeasures {
            sphericity,
            roundness,
            aspect_ks,
            violation,
        }
    }
}

/// The shape a genome asks for: superellipses of aspect ratio uniform over
/// a range, one exponent, and (aligned particles) an orientation spread.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AskedShape {
    /// Least and greatest aspect ratio (equal: one for all).
    pub aspect: [f64; 2],
    /// The exponent α = β.
    pub exponent: f64,
    /// Standard deviation of aligned particles' orientation (radians);
    /// `None`: as `[shape]` gives it.
    pub spread: Option<f64>,
}

impl AskedShape {
    /// `base` (a superellipse shape: other families are returned as they
    /// are) with this aspect range, exponent and spread.
    pub fn applied_to(&self, base: &ShapeSpec) -> ShapeSpec {
        let mut spec = base.clone();
        if let Family::Superellipse { .. } = spec.family {
            let [lo, hi] = self.aspect;
            spec.family = Family::Superellipse {
                aspect: if hi > lo {
                    Spread::Range(lo, hi)
                } else {
                    Spread::Fixed(lo)
                },
                alpha: Spread::Fixed(self.exponent),
                beta: Spread::Fixed(self.exponent),
            };
        }
        if let (Some(s), Orientation::Aligned { mean, .. }) = (self.spread, spec.orientation) {
            spec.orientation = Orientation::Aligned { mean, spread: s };
        }
        spec
    }

    /// Mean Riley sphericity and Wadell roundness of the outlines asked:
    /// the midpoint rule of [`Spread`]'s nodes over the aspect range.
    pub fn means(&self) -> (f64, f64) {
        let [lo, hi] = self.aspect;
        let aspects = if hi > lo {
            Spread::Range(lo, hi)
        } else {
            Spread::Fixed(lo)
        };
        // Equal weights: the plain mean of the nodes' measures.
        let nodes = aspects.nodes();
        let (s, r) = nodes.iter().fold((0.0, 0.0), |(s, r), &(a, _)| {
            let o = Outline::Superellipse {
                a,
                b: 1.0,
                alpha: self.exponent,
                beta: self.exponent,
            };
            (s + sphericity(&o), r + roundness(&o))
        });
        let n = nodes.len() as f64;
        (s / n, r / n)
    }

    /// KS distance of the packed superellipses' aspect ratios a/b to the
    /// uniform distribution over the range asked (one value: the share of
    /// particles off it by more than 10⁻⁹ relative). 0 with no grain.
    pub fn aspect_ks(&self, grains: &[Grain]) -> f64 {
        let mut aspects: Vec<f64> = grains
            .iter()
            .filter_map(|g| match g.outline {
                Outline::Superellipse { a, b, .. } => Some(a / b),
                Outline::Polygon { .. } => None,
            })
            .collect();
        let n = aspects.len();
        if n == 0 {
            return 0.0;
        }
        let [lo, hi] = self.aspect;
        if hi <= lo {
            let off = aspects
                .iter()
                .filter(|&&a| (a - lo).abs() > 1e-9 * lo)
                .count();
            return off as f64 / n as f64;
        }
        aspects.sort_by(f64::total_cmp);
        let cdf = |a: f64| ((a - lo) / (hi - lo)).clamp(0.0, 1.0);
        aspects
            .iter()
            .enumerate()
            .map(|(i, &a)| {
                let f = cdf(a);
                (f - i as f64 / n as f64).max((i + 1) as f64 / n as f64 - f)
            })
            .fold(0.0, f64::max)
    }
}

/// A shape's constraint measures (see [`ShapeBounds::judge`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeMeasures {
    /// Mean Riley sphericity of the shape asked.
    pub sphericity: f64,
    /// Mean Wadell roundness of the shape asked.
    pub roundness: f64,
    /// KS distance of the packed aspect ratios to those asked.
    pub aspect_ks: f64,
    /// The constraints' total excess (0: kept).
    #[serde(skip)]
    pub violation: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    #[test]
    fn genes_place_the_aspect_range_and_exponent_inside_the_bounds() {
        let b = ShapeBounds::new([1.0, 3.0], [2.0, 4.0]);
        let lowest = b.asked(&[0.0, 0.0, 0.0, 0.0]);
        assert_eq!(lowest.aspect, [1.0, 1.0]);
        assert_eq!(lowest.exponent, 2.0);
        let widest = b.asked(&[0.7, 1.0, 1.0, 0.0]);
        assert_eq!(widest.aspect, [1.0, 3.0]);
        assert_eq!(widest.exponent, 4.0);
        let mid = b.asked(&[1.0, 0.5, 0.5, 0.0]);
        assert!((mid.aspect[0] - 2.0).abs() < 1e-12 && (mid.aspect[1] - 3.0).abs() < 1e-12);
        assert_eq!(b.asked(&b.roundest()).exponent, 2.0);
        let blocky = ShapeBounds::new([1.0, 2.0], [3.0, 5.0]);
        assert_eq!(blocky.asked(&blocky.roundest()).exponent, 3.0);
    }

    #[test]
    fn sphericity_falls_with_aspect_and_the_bound_counts_as_violation() {
        let mut b = ShapeBounds::new([1.0, 4.0], [2.0, 2.0]);
        b.min_sphericity = 0.7;
        let round = b.asked(&[0.0, 0.0, 0.0, 0.0]);
        let long = b.asked(&[1.0, 0.0, 0.0, 0.0]);
        let (s_round, r_round) = round.means();
        let (s_long, _) = long.means();
        assert!((s_round - 1.0).abs() < 1e-6 && (r_round - 1.0).abs() < 1e-6);
        // An ellipse of aspect A: √(1/A).
        assert!((s_long - 0.5).abs() < 1e-3, "{s_long}");
        assert_eq!(b.judge(&round, &[]).violation, 0.0);
        assert!((b.judge(&long, &[]).violation - 0.2).abs() < 1e-3);
    }

    #[test]
    fn the_aspect_ks_sees_particles_that_do_not_follow_the_range() {
        let asked = AskedShape {
            aspect: [1.0, 2.0],
            exponent: 2.0,
            spread: None,
        };
        let spec = asked.applied_to(&ShapeSpec::ellipses(1.0));
        let drawer = spec.drawer();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let grains: Vec<Grain> = (0..2000).map(|_| drawer.draw(1.0, &mut rng)).collect();
        let ks = asked.aspect_ks(&grains);
        assert!(ks < 0.04, "drawn from the range: {ks}");
        // Only the rounder half of them: the KS sees it.
        let rounder: Vec<Grain> = grains
            .iter()
            .filter(|g| matches!(g.outline, Outline::Superellipse { a, b, .. } if a / b < 1.5))
            .cloned()
            .collect();
        assert!(asked.aspect_ks(&rounder) > 0.4);
        let one = AskedShape {
            aspect: [1.5, 1.5],
            ..asked
        };
        assert_eq!(one.aspect_ks(&grains), 1.0);
    }
}
