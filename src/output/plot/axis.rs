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
//! tick code as an unchecked range. Its ticks are its own: a logarithmic
//! axis is labelled 1-2-5 (`Axis::log_ticks`; plotters labelled powers of
//! ten only, none at all over 1.2–4.8), a linear axis of counts at whole
//! numbers ([`Axis::whole`]).

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
    /// Ticks at whole numbers only (a linear axis of counts).
    whole: bool,
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
                whole: false,
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
                whole: false,
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
                    whole: false,
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

    /// The axis with ticks at whole numbers only (generations, counts),
    /// when it is linear.
    pub(super) fn whole(self) -> Self {
        Axis {
            whole: !self.log,
            ..self
        }
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
                whole: false,
            }
        } else {
            let mid = 0.5 * (a + b);
            Axis {
                lo: mid - least_half,
                hi: mid + least_half,
                log: false,
                whole: false,
            }
        }
    }

    fn coord_linear(&self) -> RangedCoordf64 {
        (self.lo..self.hi).into()
    }

    fn coord_log(&self) -> LogCoord<f64> {
        (self.lo..self.hi).log_scale().into()
    }

    /// The labelled ticks of a logarithmic axis, at most `max`: 1-2-5 ×
    /// 10^k; powers of ten (every one, or every second, third …) when
    /// those crowd; denser round values (1.5, 3, 4 …, then plain decimal
    /// steps) when they give fewer than three. Ticks crowd when two lie
    /// closer than 1/`max` of the axis: each label then has that share of
    /// the axis' length to itself, and none overlaps the next.
    fn log_ticks(&self, max: usize) -> Vec<f64> {
        let (lo, hi) = (self.lo, self.hi);
        let least_gap = (hi / lo).log10() / max.max(1) as f64;
        let fits = |ticks: &[f64]| {
            ticks.len() <= max && ticks.windows(2).all(|w| (w[1] / w[0]).log10() >= least_gap)
        };
        let one_two_five = decimal_ticks(lo, hi, &[1.0, 2.0, 5.0], 1);
        if !fits(&one_two_five) {
            return (1..=MAX_DECADES as i32 + 1)
                .map(|step| decimal_ticks(lo, hi, &[1.0], step))
                .find(|ticks| fits(ticks))
                .unwrap_or_default();
        }
        let mut best = one_two_five;
        let denser = DENSER
            .iter()
            .map(|mantissas| decimal_ticks(lo, hi, mantissas, 1))
            .chain([self.coord_linear().key_points(max)]);
        for ticks in denser {
            if best.len() >= 3 {
                break;
            }
            if fits(&ticks) && ticks.len() > best.len() {
                best = ticks;
            }
        }
        best
    }
}

/// Mantissas of a logarithmic axis' ticks denser than 1-2-5, per decade.
const DENSER: [&[f64]; 2] = [
    &[1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0],
    &[1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0],
];

/// The values m·10^k in `lo..=hi`, m in `mantissas` and k a multiple of
/// `step`, in order, each the double nearest its decimal (labels print it exactly).
fn decimal_ticks(lo: f64, hi: f64, mantissas: &[f64], step: i32) -> Vec<f64> {
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (k0..=k1)
        .filter(|k| k.rem_euclid(step) == 0)
        .flat_map(|k| {
            mantissas
                .iter()
                .filter_map(move |m| format!("{m}e{k}").parse::<f64>().ok())
        })
        .filter(|v| (lo..=hi).contains(v))
        .collect()
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
            // Light grid lines at 1…9 × 10^k, when not too many.
            let light = decimal_ticks(
                self.lo,
                self.hi,
                &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
                1,
            );
            if hint.weight().allow_light_points() && light.len() <= hint.max_num_points() {
                light
            } else {
                self.log_ticks(hint.bold_points())
            }
        } else if self.whole {
            self.coord_linear()
                .key_points(hint)
                .into_iter()
                .filter(|v| (v - v.round()).abs() <= 1e-9 * v.abs().max(1.0))
                .map(f64::round)
                .collect()
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
    use plotters::coord::ranged1d::BoldPoints;

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

    /// Labelled ticks of a log axis over `values` (padded as the grading chart pads).
    fn log_labels(values: &[f64]) -> Vec<f64> {
        let axis = Axis::log(
            values.iter().copied(),
            Pad {
                share: 0.04,
                least: 0.0,
            },
        );
        assert!(axis.is_log());
        axis.key_points(BoldPoints(11))
    }

    #[test]
    fn log_axes_are_labelled_1_2_5_with_at_least_three_ticks() {
        // Under a decade: intermediate round values.
        assert_eq!(log_labels(&[1.2, 4.8]), [1.5, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(log_labels(&[0.5, 2.0]), [0.5, 1.0, 2.0]);
        assert_eq!(log_labels(&[1.275, 3.54]), [1.5, 2.0, 3.0]);
        // Two decades: 1-2-5.
        assert_eq!(log_labels(&[0.3, 30.0]), [0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
        // Too many for 1-2-5: powers of ten, every one or every few.
        assert_eq!(log_labels(&[0.1, 1000.0]), [0.1, 1.0, 10.0, 100.0, 1000.0]);
        let wide = log_labels(&[1e-12, 1e12]);
        assert!(wide.len() >= 3 && wide.len() <= 11, "{wide:?}");
        // A few percent wide: plain decimal steps.
        let narrow = log_labels(&[3.0, 3.1]);
        assert!(narrow.len() >= 3, "{narrow:?}");
        // Never closer than 1/11 of the axis (each label has that room).
        for values in [
            [1.2, 4.8],
            [0.5, 2.0],
            [0.3, 30.0],
            [1e-12, 1e12],
            [3.0, 3.1],
        ] {
            let axis = Axis::log(values, PAD);
            let ticks = axis.key_points(BoldPoints(11));
            let span = (axis.hi / axis.lo).log10();
            assert!(
                ticks
                    .windows(2)
                    .all(|w| (w[1] / w[0]).log10() >= span / 11.0 - 1e-12),
                "{values:?}: {ticks:?}"
            );
        }
    }

    #[test]
    fn a_whole_axis_ticks_whole_numbers_only() {
        let axis = Axis::linear([0.0, 1.0], PAD).whole();
        assert_eq!(axis.key_points(BoldPoints(11)), [0.0, 1.0]);
        assert_eq!(axis.key_points(12usize), [0.0, 1.0]);
        let axis = Axis::linear([0.0, 30.0], PAD).whole();
        assert!(
            axis.key_points(BoldPoints(11))
                .iter()
                .all(|v| v.fract() == 0.0)
        );
    }
}
