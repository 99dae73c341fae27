//! The one way a chart gets a numeric axis from data: [`Axis`].
//!
//! Plotters' own axes trust their range. A logarithmic axis over
//! `5e-324..1e300` asks for a key point per decade from a start that
//! underflows to zero, and never stops (it grows until the allocation
//! fails); a linear axis narrower than the rounding of its values loops on
//! its tick step. An [`Axis`] can only be made by [`Axis::linear`],
//! [`Axis::log`] or [`Axis::exact`], which skip values that are not finite,
//! pad the range, keep it finite and wide enough for its magnitude, and
//! give a logarithmic axis at most [`MAX_DECADES`] decades of positive
//! values (otherwise the axis is linear). Every chart drawn from data
//! builds its coordinates from two of them, so no data reaches plotters'
//! tick code as an unchecked range.

use std::ops::Range;

use plotters::coord::combinators::{IntoLogRange, LogCoord};
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;

/// Most decades a logarithmic axis spans; wider data get a linear axis.
pub(super) const MAX_DECADES: f64 = 30.0;
/// Largest magnitude an axis reaches: larger values are clamped to it, so
/// the width of any axis stays finite.
const MAX_ABS: f64 = 1e300;
/// Smallest positive end of a logarithmic axis (normal numbers only).
const MIN_LOG: f64 = 1e-300;
/// Narrowest half-width of a linear axis, relative to its magnitude: its
/// ticks then differ in the sixth digit, far above rounding.
const MIN_REL_HALF: f64 = 1e-6;
/// Narrowest half-width of a linear axis around zero.
const MIN_ABS_HALF: f64 = 1e-12;
/// Narrowest padding of a logarithmic axis (decades each side).
const MIN_DECADE_PAD: f64 = 0.01;

/// How much room an axis leaves beyond its data, each side: `share` of the
/// data's span (in decades on a logarithmic axis), and at least `least`
/// (on a linear axis a share of the largest magnitude, on a logarithmic
/// one decades).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Pad {
    /// Share of the data's span.
    pub share: f64,
    /// Least padding (see [`Pad`]).
    pub least: f64,
}

/// A checked axis range: finite ends, `lo < hi`, wide enough for its
/// magnitude, and when logarithmic `lo ≥ 1e-300` and at most
/// [`MAX_DECADES`] decades. It is a plotters coordinate itself
/// (`build_cartesian_2d(x_axis, y_axis)`), drawing as plotters' linear or
/// logarithmic `f64` axis would.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Axis {
    /// A linear axis over `values` (those not finite skipped), padded by `pad`;
    /// `0..1` without any.
    pub(super) fn linear(values: impl IntoIterator<Item = f64>, pad: Pad) -> Self {
        match extent(values) {
            Some((lo, hi)) => Self::linear_over(lo, hi, pad),
            None => Axis {
                lo: 0.0,
                hi: 1.0,
                log: false,
            },
        }
    }

    /// A logarithmic axis over `values` (those not finite skipped), padded
    /// by `pad`; a linear one (padded by `pad.share`) when a value is not
    /// positive or the padded range leaves `[1e-300, 1e300]` or spans more
    /// than [`MAX_DECADES`] decades; `1..10` without any value.
    pub(super) fn log(values: impl IntoIterator<Item = f64>, pad: Pad) -> Self {
        let Some((lo, hi)) = extent(values) else {
            return Axis {
                lo: 1.0,
                hi: 10.0,
                log: true,
            };
        };
        if lo > 0.0 {
            let decades = (hi / lo).log10();
            let side = (pad.share * decades).max(pad.least).max(MIN_DECADE_PAD);
            let factor = 10f64.powf(side);
            let (a, b) = (lo / factor, hi * factor);
            if a >= MIN_LOG && b <= MAX_ABS && (b / a).log10() <= MAX_DECADES {
                return Axis {
                    lo: a,
                    hi: b,
                    log: true,
                };
            }
        }
        Self::linear_over(
            lo,
            hi,
            Pad {
                share: pad.share,
                least: 0.0,
            },
        )
    }

    /// A linear axis from `lo` to `hi` as given (a map drawn to scale),
    /// widened only if it is too narrow or not finite.
    pub(super) fn exact(lo: f64, hi: f64) -> Self {
        Self::linear(
            [lo, hi],
            Pad {
                share: 0.0,
                least: 0.0,
            },
        )
    }

    /// Whether the axis is logarithmic.
    pub(super) fn is_log(&self) -> bool {
        self.log
    }

    /// Its two ends.
    pub(super) fn ends(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }

    /// The linear axis over `lo..=hi` (finite, ordered), padded.
    fn linear_over(lo: f64, hi: f64, pad: Pad) -> Self {
        let (lo, hi) = (lo.clamp(-MAX_ABS, MAX_ABS), hi.clamp(-MAX_ABS, MAX_ABS));
        let magnitude = lo.abs().max(hi.abs());
        let side = (pad.share * (hi - lo)).max(pad.least * magnitude);
        let (a, b) = (lo - side, hi + side);
        // A single value, or a range too narrow for its magnitude: widen it
        // around its middle.
        let least_half = (MIN_REL_HALF * magnitude).max(MIN_ABS_HALF);
        if b - a >= 2.0 * least_half {
            Axis {
                lo: a,
                hi: b,
                log: false,
            }
        } else {
            let mid = 0.5 * (a + b);
            Axis {
                lo: mid - least_half,
                hi: mid + least_half,
                log: false,
            }
        }
    }

    fn coord_linear(&self) -> RangedCoordf64 {
        (self.lo..self.hi).into()
    }

    fn coord_log(&self) -> LogCoord<f64> {
        (self.lo..self.hi).log_scale().into()
    }
}

/// The smallest and largest finite value, if any.
fn extent(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
        })
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        if self.log {
            self.coord_log().map(value, limit)
        } else {
            self.coord_linear().map(value, limit)
        }
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if self.log {
            self.coord_log().key_points(hint)
        } else {
            self.coord_linear().key_points(hint)
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAD: Pad = Pad {
        share: 0.05,
        least: 1e-3,
    };

    /// Finite ordered ends, and plotters' ticks come back (bounded work).
    fn sound(axis: Axis) -> Axis {
        let (lo, hi) = axis.ends();
        assert!(lo.is_finite() && hi.is_finite() && lo < hi, "{axis:?}");
        if axis.is_log() {
            assert!(lo >= MIN_LOG && (hi / lo).log10() <= MAX_DECADES + 1e-9);
        }
        let ticks = axis.key_points(12usize);
        assert!(ticks.len() <= 200, "{axis:?}: {} ticks", ticks.len());
        assert!(axis.map(&lo, (0, 900)) <= axis.map(&hi, (0, 900)));
        axis
    }

    #[test]
    fn degenerate_data_give_a_sound_axis() {
        for values in [
            vec![5e-324],
            vec![5e-324, 2.0],
            vec![1e-300, 1e300],
            vec![1e300],
            vec![f64::MAX, -f64::MAX],
            vec![0.0],
            vec![1e300, 1e300 * (1.0 + f64::EPSILON)],
            vec![f64::NAN, f64::INFINITY],
            vec![],
        ] {
            sound(Axis::linear(values.iter().copied(), PAD));
            sound(Axis::log(values.iter().copied(), PAD));
        }
    }

    #[test]
    fn a_log_axis_over_too_many_decades_or_a_zero_is_linear() {
        assert!(!Axis::log([5e-324, 2.0], PAD).is_log());
        assert!(!Axis::log([1e-20, 1e20], PAD).is_log());
        assert!(!Axis::log([0.0, 2.0], PAD).is_log());
        let axis = sound(Axis::log([1e-12, 1e12], PAD));
        assert!(axis.is_log());
        // A single positive value gets room around it.
        let (lo, hi) = sound(Axis::log([3.0], PAD)).ends();
        assert!(lo < 3.0 && hi > 3.0);
    }

    #[test]
    fn ordinary_data_are_padded_as_asked() {
        let (lo, hi) = Axis::linear([0.0, 10.0], PAD).ends();
        assert!((lo + 0.5).abs() < 1e-12 && (hi - 10.5).abs() < 1e-12);
        let axis = Axis::log(
            [1.0, 100.0],
            Pad {
                share: 0.0,
                least: 1.0,
            },
        );
        let (lo, hi) = axis.ends();
        assert!(axis.is_log() && (lo - 0.1).abs() < 1e-12 && (hi - 1000.0).abs() < 1e-9);
        assert_eq!(Axis::exact(2.0, 7.0).ends(), (2.0, 7.0));
    }
}
