//! How good a genome is, and genevo's view of it.

use std::cmp::Ordering;

use genevo::genetic::Fitness;

/// The score of a genome: constraint violation first, then error; lower is
/// better for both.
///
/// A feasible genome (no violation) beats every infeasible one, whatever
/// their errors (Deb's rule): the GA first honours the constraints, then
/// hits the target.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Score {
    /// How far the genome breaks the constraints, ≥ 0 (0 = feasible), in the
    /// constraint's units (KS distance beyond `max_psd_ks` for the porosity target).
    pub violation: f64,
    /// The objective's error, ≥ 0, in the objective's units (squared porosity
    /// difference for the porosity target).
    pub error: f64,
    /// The quantity the objective aims at, for reports (the porosity).
    pub value: f64,
}

impl Score {
    /// The worst possible score: what a genome that cannot be evaluated gets.
    pub const WORST: Score = Score {
        violation: f64::INFINITY,
        error: f64::INFINITY,
        value: f64::NAN,
    };

    /// Order by quality: `Less` when `self` is better (smaller violation, then
    /// smaller error); a total order (NaN after everything).
    pub fn cmp_quality(&self, other: &Score) -> Ordering {
        self.violation
            .total_cmp(&other.violation)
            .then(self.error.total_cmp(&other.error))
    }

    /// Whether the genome meets the constraints.
    pub fn is_feasible(&self) -> bool {
        self.violation == 0.0
    }

    /// Whether `self` is better than `old` by enough to count as progress:
    /// it becomes feasible, or shrinks the violation or (as feasible) the
    /// error by at least [`Score::PROGRESS`] of it. Creeping by less does not
    /// hold off a stop for stagnation.
    pub fn improves_on(&self, old: &Score) -> bool {
        let keep = 1.0 - Self::PROGRESS;
        if old.is_feasible() {
            self.is_feasible() && self.error < old.error * keep
        } else {
            self.violation < old.violation * keep
        }
    }

    /// Least relative gain that counts as progress (2 % of the error, which
    /// for a squared error is 1 % of the distance to the target).
    pub const PROGRESS: f64 = 0.02;
}

/// genevo's fitness: a [`Score`] ordered so that greater is better.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Fit(pub Score);

impl Eq for Fit {}

impl PartialOrd for Fit {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Fit {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.cmp_quality(&self.0)
    }
}

impl Fitness for Fit {
    fn zero() -> Self {
        Fit(Score {
            violation: 0.0,
            error: 0.0,
            value: 0.0,
        })
    }

    fn abs_diff(&self, other: &Self) -> Self {
        Fit(Score {
            violation: (self.0.violation - other.0.violation).abs(),
            error: (self.0.error - other.0.error).abs(),
            value: (self.0.value - other.0.value).abs(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(violation: f64, error: f64) -> Score {
        Score {
            violation,
            error,
            value: 0.0,
        }
    }

    #[test]
    fn progress_needs_a_relative_gain() {
        assert!(s(0.0, 0.0097).improves_on(&s(0.0, 0.01)));
        assert!(!s(0.0, 0.0099).improves_on(&s(0.0, 0.01)));
        assert!(s(0.0, 5.0).improves_on(&s(0.01, 0.0)));
        assert!(!s(0.02, 0.0).improves_on(&s(0.0, 9.0)));
        assert!(s(0.01, 0.0).improves_on(&s(0.02, 0.0)));
    }

    #[test]
    fn feasibility_comes_before_error() {
        assert!(s(0.0, 1.0).cmp_quality(&s(0.01, 0.0)).is_lt());
        assert!(s(0.0, 0.1).cmp_quality(&s(0.0, 0.2)).is_lt());
        assert!(s(0.02, 0.0).cmp_quality(&s(0.01, 9.0)).is_gt());
        assert!(Fit(s(0.0, 0.1)) > Fit(s(0.0, 0.2)));
        assert!(Fit(Score::WORST) < Fit(s(1e9, 1e9)));
    }
}
