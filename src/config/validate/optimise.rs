//! `[optimise]` (or `[optimize]`): a target-porosity run, its keys and its memory.

use toml::Spanned;

use super::limits::DEFAULT_MAX_MEMORY_MB;
use super::shape::{Bounds, aspect_bounds, exponent_bounds};
use super::{KeyAt, Validator};
use crate::Scene;
use crate::config::error::ConfigError;
use crate::config::raw::{Pair, RawOptimise, RawShapeSearch, Table, WithStop};
use crate::ga::{OptimiseSettings, RULE_GENES, SHAPE_GENES, ShapeBounds};
use crate::packer::{BYTES_PER_MB, size_count};
use crate::scene::{Family, Orientation, ShapeSpec};

/// Largest orientation spread `[optimise.shape]` may search (degrees): a
/// normal spread this wide is as good as random.
const MAX_SPREAD_DEG: f64 = 90.0;

impl Validator<'_> {
    /// `[optimise]` or `[optimize]`: one table under either spelling, not both.
    pub(super) fn one_spelling(
        &self,
        optimise: Option<Spanned<Table<WithStop<RawOptimise>>>>,
        optimize: Option<Spanned<Table<WithStop<RawOptimise>>>>,
    ) -> Result<Option<Spanned<Table<WithStop<RawOptimise>>>>, ConfigError> {
        match (optimise, optimize) {
            (Some(a), Some(b)) => {
                let (first, second, later) = if a.span().start <= b.span().start {
                    ("optimise", "optimize", b.span())
                } else {
                    ("optimize", "optimise", a.span())
                };
                Err(ConfigError::NotApplicable {
                    at: self.at(&later),
                    key: second.to_owned(),
                    reason: format!(
                        "[{first}] is given too: [optimise] and [optimize] are one table under two spellings; give only one"
                    ),
                })
            }
            (a, b) => Ok(a.or(b)),
        }
    }

    /// `[optimise]`: every key checked against its range.
    pub(super) fn optimise(
        &self,
        raw: &Spanned<Table<WithStop<RawOptimise>>>,
    ) -> Result<OptimiseSettings, ConfigError> {
        let o = raw.get_ref();
        let Some(target) = &o.target_porosity else {
            return Err(ConfigError::Missing {
                at: self.at(&raw.span()),
                key: "optimise.target_porosity".to_owned(),
                reason: "[optimise] needs the porosity to reach, in [0, 1)".to_owned(),
            });
        };
        let mut s = OptimiseSettings::new(self.checked(
            "optimise.target_porosity",
            target,
            "in [0, 1)",
            |v| (0.0..1.0).contains(&v),
        )?);
        if let Some(v) = &o.tolerance {
            s.tolerance = self.checked("optimise.tolerance", v, "a finite number ≥ 0", |v| {
                v.is_finite() && v >= 0.0
            })?;
        }
        if let Some(v) = &o.max_psd_ks {
            s.max_psd_ks = self.checked("optimise.max_psd_ks", v, "in (0, 1]", |v| {
                v > 0.0 && v <= 1.0
            })?;
        }
        if let Some(v) = &o.window_disks {
            s.window_disks = self.whole("optimise.window_disks", v, 0, None)? as u64;
        }
        s.stop = self.stop_rules("optimise", &o.stop)?;
        Ok(s)
    }

    /// Refuse an optimisation whose genomes and packings would not fit the
    /// memory limit ([`OptimiseSettings::peak_bytes`]).
    pub(super) fn check_optimise_memory(
        &self,
        scene: &Scene,
        settings: &OptimiseSettings,
        raw: &Spanned<Table<WithStop<RawOptimise>>>,
        (limit_mb, limit_key): (f64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        let estimate_mb = settings.peak_bytes(scene) / BYTES_PER_MB;
        if self.force || estimate_mb <= limit_mb {
            return Ok(());
        }
        let genes =
            size_count(&scene.domain, scene.d_min()) as f64 + (RULE_GENES + SHAPE_GENES) as f64;
        let disks = scene.max_disks();
        let (key, span, hint) = match (limit_key, &raw.get_ref().stop.population) {
            (Some(k), _) => (k.key, k.span, "; raise it to allow this run".to_owned()),
            (None, Some(p)) => (
                "optimise.population".to_owned(),
                p.span(),
                format!(
                    "; lower it, or set limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB})"
                ),
            ),
            (None, None) => (
                "optimise".to_owned(),
                raw.span(),
                format!(
                    "; set a smaller optimise.population or limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB})"
                ),
            ),
        };
        Err(ConfigError::Memory {
            at: self.at(&span),
            key,
            reason: format!(
                "the optimisation ({} genomes of {genes:.0} genes, {disks:.0} disks each) needs an estimated {estimate_mb:.0} MB, over the limit of {limit_mb:.0} MB{hint}",
                settings.stop.population
            ),
        })
    }

    /// `[optimise.shape]`, checked against the `[shape]` it moves (`shape`,
    /// with its table's span for the messages): bounds default to the
    /// `[shape]`'s own ranges.
    pub(super) fn shape_search(
        &self,
        raw: &Spanned<Table<RawShapeSearch>>,
        shape: Option<&ShapeSpec>,
    ) -> Result<ShapeBounds, ConfigError> {
        let r = raw.get_ref();
        let refuse = |reason: &str| ConfigError::NotApplicable {
            at: self.at(&raw.span()),
            key: "optimise.shape".to_owned(),
            reason: reason.to_owned(),
        };
        let Some(shape) = shape else {
            return Err(refuse(
                "needs a [shape] table: the search moves the particles' shape within these bounds",
            ));
        };
        let Family::Superellipse { aspect, alpha, .. } = &shape.family else {
            return Err(refuse(
                "the search moves the aspect ratio and exponents of superellipses (shape.kind = \"superellipse\"); polygon templates stay as given: remove [optimise.shape] to search sizes and packing rules only",
            ));
        };
        let pair = |key: &str, given: &Option<Pair>, default: (f64, f64), bounds: &Bounds| {
            let Some(p) = given else {
                return Ok([default.0, default.1]);
            };
            let [lo, hi] = p.get_ref().0;
            let lo = self.bounded(&format!("{key}[0]"), lo, &p.span(), bounds)?;
            let hi = self.bounded(&format!("{key}[1]"), hi, &p.span(), bounds)?;
            if lo > hi {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&p.span()),
                    key: format!("{key}[1]"),
                    range: format!("at least the low end {lo}: a range is [low, high]"),
                    value: hi,
                });
            }
            Ok([lo, hi])
        };
        let mut b = ShapeBounds::new(
            pair(
                "optimise.shape.aspect",
                &r.aspect,
                aspect.bounds(),
                &aspect_bounds(),
            )?,
            pair(
                "optimise.shape.exponent",
                &r.exponent,
                alpha.bounds(),
                &exponent_bounds(),
            )?,
        );
        if let Some(p) = &r.orientation_spread {
            if !matches!(shape.orientation, Orientation::Aligned { .. }) {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&p.span()),
                    key: "optimise.shape.orientation_spread".to_owned(),
                    reason: "applies only to shape.orientation = \"aligned\" (random orientations have no spread to move)".to_owned(),
                });
            }
            let [lo, hi] = p.get_ref().0;
            let in_range = |v: f64| (0.0..=MAX_SPREAD_DEG).contains(&v);
            if !(in_range(lo) && in_range(hi) && lo <= hi) {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&p.span()),
                    key: "optimise.shape.orientation_spread".to_owned(),
                    range: format!("[low, high] in degrees, 0 ≤ low ≤ high ≤ {MAX_SPREAD_DEG}"),
                    value: if in_range(lo) { hi } else { lo },
                });
            }
            b.spread = Some([lo.to_radians(), hi.to_radians()]);
        }
        let unit = |key: &str, v: &Option<Spanned<f64>>| match v {
            None => Ok(0.0),
            Some(v) => self.checked(key, v, "in [0, 1]", |v| (0.0..=1.0).contains(&v)),
        };
        b.min_sphericity = unit("optimise.shape.min_sphericity", &r.min_sphericity)?;
        b.min_roundness = unit("optimise.shape.min_roundness", &r.min_roundness)?;
        if let Some(v) = &r.max_shape_ks {
            b.max_shape_ks = self.checked("optimise.shape.max_shape_ks", v, "in (0, 1]", |v| {
                v > 0.0 && v <= 1.0
            })?;
        }
        // The roundest shape allowed must keep the bounds, or no genome can.
        let (sphericity, roundness) = b.asked(&b.roundest()).means();
        for (key, least, got, given) in [
            (
                "min_sphericity",
                b.min_sphericity,
                sphericity,
                &r.min_sphericity,
            ),
            (
                "min_roundness",
                b.min_roundness,
                roundness,
                &r.min_roundness,
            ),
        ] {
            if let Some(v) = given.as_ref().filter(|_| got < least) {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&v.span()),
                    key: format!("optimise.shape.{key}"),
                    range: format!(
                        "at most {:.3}: the roundest shape the bounds allow (aspect {}, exponent {}) has {:.4}",
                        (got * 1e3).floor() / 1e3,
                        b.aspect[0],
                        b.asked(&b.roundest()).exponent,
                        got
                    ),
                    value: least,
                });
            }
        }
        Ok(b)
    }
}
