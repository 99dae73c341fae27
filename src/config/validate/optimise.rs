//! `[optimise]` (or `[optimize]`): a target-porosity run, its keys and its memory.

use toml::Spanned;

use super::limits::DEFAULT_MAX_MEMORY_MB;
use super::{KeyAt, Validator};
use crate::Scene;
use crate::config::error::ConfigError;
use crate::config::raw::{RawOptimise, Table, WithStop};
use crate::ga::{OptimiseSettings, RULE_GENES};
use crate::packer::{BYTES_PER_MB, size_count};

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
        let genes = size_count(&scene.domain, scene.d_min()) as f64 + RULE_GENES as f64;
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
}
