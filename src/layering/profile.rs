//! What layering adds to a [`Profile`]: its check against the materials and
//! its averages over bins.

use super::error::LayeringError;
use crate::scene::{Axis, Profile};

/// Tolerance on sums that must be 1 (fractions, thicknesses).
const SUM_TOLERANCE: f64 = 1e-6;

/// Points per bin when a profile is averaged over a bin.
const BIN_SAMPLES: usize = 64;

impl Profile {
    /// Check the profile against the number of materials.
    ///
    /// # Errors
    /// [`LayeringError`] for a profile that cannot serve `materials` materials.
    pub fn check(&self, materials: usize) -> Result<(), LayeringError> {
        let two = |profile| {
            if materials == 2 {
                Ok(())
            } else {
                Err(LayeringError::TwoMaterials {
                    profile,
                    got: materials,
                })
            }
        };
        let exponent = |p: f64| {
            if p.is_finite() && p > 0.0 {
                Ok(())
            } else {
                Err(LayeringError::Exponent(p))
            }
        };
        match self {
            Profile::Linear => two("linear"),
            Profile::Power(p) => two("power").and(exponent(*p)),
            Profile::Sigmoid(p) => two("sigmoid").and(exponent(*p)),
            Profile::Steps(layers) => {
                if layers.is_empty() {
                    return Err(LayeringError::Empty("layers"));
                }
                if let Some(&(_, t)) = layers.iter().find(|(_, t)| !(t.is_finite() && *t >= 0.0)) {
                    return Err(LayeringError::Thickness(t));
                }
                let sum: f64 = layers.iter().map(|l| l.1).sum();
                if (sum - 1.0).abs() > SUM_TOLERANCE {
                    return Err(LayeringError::Thicknesses(sum));
                }
                Ok(())
            }
            Profile::Table(rows) => {
                if rows.is_empty() {
                    return Err(LayeringError::Empty("rows"));
                }
                let mut last = 0.0;
                for (row, (s, fractions)) in rows.iter().enumerate() {
                    if fractions.len() != materials {
                        return Err(LayeringError::RowLength {
                            row,
                            got: fractions.len() + 1,
                            want: materials + 1,
                        });
                    }
                    let ordered = (last..=1.0).contains(s) && fractions.iter().all(|f| *f >= 0.0);
                    if !ordered {
                        return Err(LayeringError::TableOrder { row });
                    }
                    last = *s;
                    let sum: f64 = fractions.iter().sum();
                    if (sum - 1.0).abs() > SUM_TOLERANCE {
                        return Err(LayeringError::Fractions { row, sum });
                    }
                }
                Ok(())
            }
        }
    }

    /// The target fractions averaged over each of `bins` equal bins of s
    /// (flat: bin b's fractions at `b·materials..`). Along x and y every s
    /// weighs the same; radially a ring weighs by its radius (its area).
    pub fn bin_targets(&self, axis: Axis, bins: usize, materials: usize) -> Vec<f64> {
        let mut out = vec![0.0; bins * materials];
        let mut at = vec![0.0; materials];
        for b in 0..bins {
            let target = &mut out[b * materials..(b + 1) * materials];
            let mut weights = 0.0;
            for k in 0..BIN_SAMPLES {
                let s = (b as f64 + (k as f64 + 0.5) / BIN_SAMPLES as f64) / bins as f64;
                let w = if axis == Axis::Radial { s } else { 1.0 };
                self.fractions(s, &mut at);
                for (t, f) in target.iter_mut().zip(&at) {
                    *t += w * f;
                }
                weights += w;
            }
            target.iter_mut().for_each(|t| *t /= weights);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bin_targets_average_the_profile() {
        let t = Profile::Linear.bin_targets(Axis::Y, 4, 2);
        for b in 0..4 {
            let mid = (b as f64 + 0.5) / 4.0;
            assert!((t[2 * b + 1] - mid).abs() < 1e-9);
            assert!((t[2 * b] + t[2 * b + 1] - 1.0).abs() < 1e-12);
        }
        // A step at a bin edge gives pure bins; radial rings weigh outer s more.
        let steps = Profile::Steps(vec![(0, 0.5), (1, 0.5)]);
        assert_eq!(steps.bin_targets(Axis::X, 2, 2), vec![1.0, 0.0, 0.0, 1.0]);
        let r = Profile::Linear.bin_targets(Axis::Radial, 1, 2);
        assert!((r[1] - 2.0 / 3.0).abs() < 1e-3, "{}", r[1]);
    }

    #[test]
    fn bad_profiles_are_refused() {
        assert!(Profile::Power(0.0).check(2).is_err());
        assert!(Profile::Linear.check(3).is_err());
        assert!(Profile::Steps(vec![(0, 0.5), (1, 0.4)]).check(2).is_err());
        assert!(
            Profile::Table(vec![(0.0, vec![0.5, 0.4])])
                .check(2)
                .is_err()
        );
        assert!(
            Profile::Table(vec![(0.5, vec![1.0, 0.0]), (0.2, vec![0.0, 1.0])])
                .check(2)
                .is_err()
        );
        assert!(Profile::Steps(vec![(0, 0.5), (1, 0.5)]).check(2).is_ok());
    }
}
