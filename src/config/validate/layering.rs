//! `[layering]`: where the materials go along an axis, checked against the
//! `[[materials]]`, the scene's bins and the memory limit.

use toml::Spanned;

use super::limits::DEFAULT_MAX_MEMORY_MB;
use super::materials::MaterialPlan;
use super::{KeyAt, Validator};
use crate::Scene;
use crate::config::error::ConfigError;
use crate::config::raw::{RawLayering, Table, WithStop};
use crate::layering::{LayeringError, LayeringMode, LayeringSettings, Profile};
use crate::names::{AXES, MODES, PROFILES, ProfileKind};
use crate::packer::{BYTES_PER_MB, estimated_peak_bytes};

/// Genomes alive at once in a generation of the GA, per genome of the
/// population (`ga::engine`, `Search::step`): the population, the copy
/// handed to the tournament, the parents it picks (half the population in
/// pairs), the children (as many) and the immigrants (an eighth).
const GENOME_COPIES: f64 = 4.125;

/// Bytes of a genome besides its genes: the `Vec` header, phenotype key
/// (a `usize` and a `u128`) and score (three `f64`).
const GENOME_OVERHEAD: f64 = 24.0 + 32.0 + 24.0;

/// Bytes the GA keeps per evaluation, for good (its score, by phenotype
/// key, in a hash map): a 64-byte entry, at most 8/7 buckets per entry and
/// twice that just after the table grows, the old table alive while it
/// moves (about 150 bytes measured, 224 bounded).
const SCORE_BYTES: f64 = 224.0;

/// Bytes of one (bin, area) entry of `BinAreas`, kept twice (the problem holds a copy).
const BIN_ENTRY_BYTES: f64 = 2.0 * 16.0;

/// What a layering run on a scene keeps in memory at most, and of what.
struct LayeringMemory {
    /// Genes per genome: one per particle, at most the domain's area over
    /// the mean disk area.
    genes: f64,
    /// Scores kept: generation 0 and the children and immigrants of every generation.
    evaluations: f64,
    /// Bytes of the genomes alive at once.
    genomes: f64,
    /// Bytes of the scores kept.
    scores: f64,
    /// Every byte: the packing, the bin areas, the genomes and the scores.
    total: f64,
}

impl LayeringMemory {
    /// An upper bound of the memory the layering GA of `settings` uses on a
    /// packing of `scene` (`ga::layering::lay_out`). Checked against
    /// `gapack layer` on `configs/fgm_power.toml` (1627 disks, at most 2035):
    /// population 2000 for 2 generations and 8000 for 3 peaked at 90 and
    /// 332 MB resident; this bound gives 130 and 523 MB.
    fn of(scene: &Scene, settings: &LayeringSettings) -> Self {
        let genes = scene.max_disks().ceil();
        let population = settings.stop.population as f64;
        let per_generation = population + (population / 8.0).floor();
        let evaluations = population + settings.stop.generations as f64 * per_generation;
        let genomes = GENOME_COPIES * population * (genes * 8.0 + GENOME_OVERHEAD);
        let scores = evaluations * SCORE_BYTES;
        // A disk's area is split among the bins it spans: at most every bin,
        // and at most its diameter over a bin's width plus two (a shape's
        // reach, its circumscribed diameter, for particles of a shape).
        let (lo, hi) = scene.domain.bounds();
        let side = (hi.x - lo.x).min(hi.y - lo.y);
        let bins = settings.bins as f64;
        let reach = scene
            .shapes()
            .map(crate::ShapeSpec::reach_ratio)
            .fold(1.0, f64::max);
        let spanned = bins.min(2.0 + 2.0 * bins * scene.d_max() * reach / side);
        let areas = genes * (spanned * BIN_ENTRY_BYTES + 3.0 * 8.0);
        LayeringMemory {
            genes,
            evaluations,
            genomes,
            scores,
            total: estimated_peak_bytes(scene) + areas + genomes + scores,
        }
    }
}

/// An upper bound of the memory (bytes) a layering run of `settings`
/// needs on a packing of `scene`: the packing, the bin areas, the GA's
/// genomes and scores (`LayeringMemory`); a size-graded layout
/// (`mode = "sizes"`) runs no search, so the packing's alone.
pub fn layering_peak_bytes(scene: &Scene, settings: &LayeringSettings) -> f64 {
    if settings.mode == LayeringMode::Sizes {
        estimated_peak_bytes(scene)
    } else {
        LayeringMemory::of(scene, settings).total
    }
}

impl Validator<'_> {
    /// `[layering]` for the given materials.
    pub(super) fn layering(
        &self,
        raw: &Spanned<Table<WithStop<RawLayering>>>,
        materials: &[MaterialPlan],
    ) -> Result<LayeringSettings, ConfigError> {
        let l = raw.get_ref();
        if materials.is_empty() {
            return Err(ConfigError::Missing {
                at: self.at(&raw.span()),
                key: "materials".to_owned(),
                reason: "[layering] needs at least one [[materials]] table".to_owned(),
            });
        }
        let Some(profile_name) = &l.profile else {
            return Err(ConfigError::Missing {
                at: self.at(&raw.span()),
                key: "layering.profile".to_owned(),
                reason: "one of steps, linear, power, sigmoid, table".to_owned(),
            });
        };
        let kind = self.name(&PROFILES, "layering.profile", Some(profile_name))?;
        let profile_at = profile_name.span();
        let names: Vec<&str> = materials.iter().map(|m| m.material.name.as_str()).collect();

        // Each kind takes its own data key; the others do not apply.
        let data = [
            (
                "exponent",
                l.exponent.as_ref().map(Spanned::span),
                matches!(kind, ProfileKind::Power | ProfileKind::Sigmoid),
            ),
            (
                "layers",
                l.layers.as_ref().map(Spanned::span),
                kind == ProfileKind::Steps,
            ),
            (
                "table",
                l.table.as_ref().map(Spanned::span),
                kind == ProfileKind::Table,
            ),
        ];
        for (key, span, wanted) in data {
            match (span, wanted) {
                (Some(span), false) => {
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&span),
                        key: format!("layering.{key}"),
                        reason: format!("does not apply to profile {:?}", profile_name.get_ref()),
                    });
                }
                (None, true) => {
                    return Err(ConfigError::Missing {
                        at: self.at(&profile_at),
                        key: format!("layering.{key}"),
                        reason: format!("profile {:?} needs it", profile_name.get_ref()),
                    });
                }
                _ => {}
            }
        }
        let exponent = |e: &Spanned<f64>| self.positive("layering.exponent", e);
        let exponent_or_one = || {
            Ok(l.exponent
                .as_ref()
                .map(exponent)
                .transpose()?
                .unwrap_or(1.0))
        };
        let (profile, blame) = match kind {
            ProfileKind::Linear => (Profile::Linear, ("layering.profile", profile_at.clone())),
            ProfileKind::Power => (
                Profile::Power(exponent_or_one()?),
                ("layering.profile", profile_at.clone()),
            ),
            ProfileKind::Sigmoid => {
                let e = exponent_or_one()?;
                (
                    Profile::Sigmoid(e),
                    ("layering.profile", profile_at.clone()),
                )
            }
            ProfileKind::Steps => {
                let layers = l
                    .layers
                    .as_ref()
                    .map_or(&[][..], |v| v.get_ref().as_slice());
                let mut steps = Vec::with_capacity(layers.len());
                for (i, layer) in layers.iter().enumerate() {
                    let (name, thickness) = &layer.get_ref().0;
                    let Some(m) = names.iter().position(|n| n == name) else {
                        return Err(ConfigError::Schema {
                            at: self.at(&layer.span()),
                            key: format!("layering.layers[{i}]"),
                            message: format!(
                                "unknown material {name:?}; valid: {}",
                                names.join(", ")
                            ),
                        });
                    };
                    steps.push((m, *thickness));
                }
                let span = l.layers.as_ref().map_or(profile_at.clone(), Spanned::span);
                (Profile::Steps(steps), ("layering.layers", span))
            }
            ProfileKind::Table => {
                let rows = l.table.as_ref().map_or(&[][..], |v| v.get_ref().as_slice());
                let table = rows
                    .iter()
                    .map(|r| {
                        let row = r.get_ref();
                        (
                            row.first().copied().unwrap_or(f64::NAN),
                            row.iter().skip(1).copied().collect(),
                        )
                    })
                    .collect();
                let span = l.table.as_ref().map_or(profile_at.clone(), Spanned::span);
                (Profile::Table(table), ("layering.table", span))
            }
        };
        profile.check(materials.len()).map_err(|error| {
            let (key, span) = match (&error, &blame) {
                // A row's fault is blamed on the row.
                (
                    LayeringError::Fractions { row, .. }
                    | LayeringError::RowLength { row, .. }
                    | LayeringError::TableOrder { row },
                    _,
                ) => (
                    format!("layering.table[{row}]"),
                    l.table
                        .as_ref()
                        .and_then(|t| t.get_ref().get(*row))
                        .map_or(blame.1.clone(), Spanned::span),
                ),
                (LayeringError::TwoMaterials { .. }, _) => {
                    ("layering.profile".to_owned(), profile_at.clone())
                }
                _ => (blame.0.to_owned(), blame.1.clone()),
            };
            ConfigError::Layering {
                at: self.at(&span),
                key,
                error,
            }
        })?;

        let mut s =
            LayeringSettings::new(self.name(&AXES, "layering.axis", l.axis.as_ref())?, profile);
        s.mode = self.name(&MODES, "layering.mode", l.mode.as_ref())?;
        if let Some(v) = &l.bins {
            s.bins = self.whole("layering.bins", v, 1, None)?;
        }
        s.stop = self.stop_rules("layering", &l.stop)?;
        if let Some(v) = &l.tolerance {
            s.tolerance = self.checked("layering.tolerance", v, "a finite number ≥ 0", |v| {
                v.is_finite() && v >= 0.0
            })?;
        }
        if s.mode == LayeringMode::Sizes {
            let missing = materials.iter().position(|m| m.grading.is_none());
            if materials.len() != 2 || missing.is_some() {
                let at = missing.map_or(raw.span(), |i| materials[i].at.clone());
                return Err(ConfigError::NotApplicable {
                    at: self.at(&at),
                    key: "layering.mode".to_owned(),
                    reason: "mode \"sizes\" needs exactly 2 materials, each with a [materials.grading] table".to_owned(),
                });
            }
        }
        Ok(s)
    }

    /// Refuse a layering search ([`LayeringMemory`]) that would not fit the
    /// memory limit, as `[optimise]` is refused; size-graded mode runs none.
    pub(super) fn check_layering_memory(
        &self,
        scene: &Scene,
        settings: &LayeringSettings,
        raw: &Spanned<Table<WithStop<RawLayering>>>,
        (limit_mb, limit_key): (f64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        if settings.mode == LayeringMode::Sizes {
            return Ok(());
        }
        let memory = LayeringMemory::of(scene, settings);
        let estimate_mb = memory.total / BYTES_PER_MB;
        if self.force || estimate_mb <= limit_mb {
            return Ok(());
        }
        let l = raw.get_ref();
        // The key that sets the larger share: the genomes (population) or the scores (generations).
        let dominant = if memory.scores > memory.genomes {
            [
                ("generations", &l.stop.generations),
                ("population", &l.stop.population),
            ]
        } else {
            [
                ("population", &l.stop.population),
                ("generations", &l.stop.generations),
            ]
        };
        let given = dominant
            .into_iter()
            .find_map(|(key, v)| v.as_ref().map(|v| (format!("layering.{key}"), v.span())));
        let (key, span, hint) = match (limit_key, given) {
            (Some(k), _) => (k.key, k.span, "; raise it to allow this run".to_owned()),
            (None, Some((key, span))) => (
                key,
                span,
                format!(
                    "; lower it, or set limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB})"
                ),
            ),
            (None, None) => (
                "layering".to_owned(),
                raw.span(),
                format!(
                    "; set a smaller layering.population or layering.generations, or limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB})"
                ),
            ),
        };
        Err(ConfigError::Memory {
            at: self.at(&span),
            key,
            reason: format!(
                "the layering search ({} genomes of up to {:.0} genes, one per particle, and up to {:.0} scores kept over {} generations) needs up to an estimated {estimate_mb:.0} MB, over the limit of {limit_mb:.0} MB{hint}",
                settings.stop.population,
                memory.genes,
                memory.evaluations,
                settings.stop.generations
            ),
        })
    }

    /// Refuse more bins than particles: a bin's fraction needs particles to measure.
    pub(super) fn check_bins(
        &self,
        scene: &Scene,
        settings: &LayeringSettings,
        raw: &Spanned<Table<WithStop<RawLayering>>>,
    ) -> Result<(), ConfigError> {
        // The most particles this domain holds: solid at the densest (0.9).
        let particles = (0.9 * scene.max_disks()).floor();
        if settings.bins as f64 <= particles {
            return Ok(());
        }
        let span = raw
            .get_ref()
            .bins
            .as_ref()
            .map_or(raw.span(), Spanned::span);
        Err(ConfigError::OutOfRange {
            at: self.at(&span),
            key: "layering.bins".to_owned(),
            range: format!(
                "at most the number of particles the domain holds, about {particles:.0}"
            ),
            value: settings.bins as f64,
        })
    }
}
