//! `summary.json`: what was packed, how, and how well.

use std::collections::BTreeMap;

use serde::Serialize;

use super::error::OutputError;
use super::run::{FractureInfo, RunInfo};
use crate::fracture::{Extent, MM_PER_M, WindowStep};
use crate::ga::StopReason;
use crate::metrics::Metrics;
use crate::names::ConfigName;
use crate::packer::{PackStats, Packing};

/// File name of the run summary.
pub const SUMMARY_JSON: &str = "summary.json";

/// The summary, key order as written.
#[derive(Serialize)]
pub(super) struct Summary<'a> {
    gapack_version: &'static str,
    config: &'a str,
    seed: u64,
    shape: &'static str,
    walls: &'static str,
    wall_disks: usize,
    method: &'static str,
    index: &'static str,
    one_contact_share: f64,
    gap: f64,
    max_deferred: usize,
    rules: &'static str,
    fill: &'static str,
    grading: GradingSummary,
    #[serde(flatten)]
    metrics: &'a Metrics,
    seconds: f64,
    stats: StatsSummary,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    optimise: Option<&'a OptimiseSummary>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    materials: Vec<MaterialSummary<'a>>,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    layering: Option<LayeringSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    fracture: Option<FractureSummary<'a>>,
}

/// What a fracture run adds to `summary.json`.
#[derive(Serialize)]
struct FractureSummary<'a> {
    name: &'a str,
    width_mm: f64,
    height_m: f64,
    tip_width_mm: Option<f64>,
    extent: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    window: Option<WindowSummary<'a>>,
}

/// A fracture window: the estimate and every window tried.
#[derive(Serialize)]
struct WindowSummary<'a> {
    tolerance: f64,
    settled: bool,
    length_mm: f64,
    /// Window length over the fracture's.
    length_fraction: f64,
    porosity: f64,
    porosity_spread: f64,
    coordination: f64,
    /// All the windows together (s).
    seconds: f64,
    steps: &'a [WindowStep],
}

/// A material as `summary.json` lists it.
#[derive(Serialize)]
struct MaterialSummary<'a> {
    /// Its number for exports that need an integer type: index + 1.
    id: usize,
    name: &'a str,
    properties: BTreeMap<&'a str, f64>,
    /// Share of the packing's solid area (null without a layering).
    area_fraction: Option<f64>,
}

/// What a layering adds to `summary.json`.
#[derive(Serialize)]
struct LayeringSummary {
    profile_rms_error: f64,
    baseline_rms_error: f64,
    baseline_seconds: f64,
    layering: LayeringDetails,
}

#[derive(Serialize)]
struct LayeringDetails {
    mode: &'static str,
    axis: &'static str,
    bins: usize,
    profile: &'static str,
    ga_seconds: f64,
    evaluations: u64,
    generations: usize,
    stop: Option<&'static str>,
}

/// What a target-porosity run adds to `summary.json` (keys in `docs/config.md`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OptimiseSummary {
    /// The porosity aimed at.
    pub target_porosity: f64,
    /// The tolerance the run stopped within, if it did.
    pub tolerance: f64,
    /// Porosity of the packing written.
    pub best_porosity: f64,
    /// |best_porosity − target_porosity|.
    pub error: f64,
    /// The KS limit on the grading.
    pub max_psd_ks: f64,
    /// Distinct genomes evaluated (each once).
    pub evaluations: u64,
    /// Generations run after the initial one.
    pub generations: usize,
    /// Genomes per generation.
    pub population: usize,
    /// Whether the target was reached, or lies in the achievable range (± tolerance).
    pub feasible: bool,
    /// Porosity range of the packings the search made that honour the
    /// grading (`max_psd_ks`): what this domain and grading were seen to reach.
    pub achievable_range: [f64; 2],
    /// The estimate before the search: the range the initial population
    /// spanned, from dense to the loosest packing rules.
    pub initial_range: [f64; 2],
    /// Whether the run was stopped by Ctrl-C (the best packing so far is written).
    pub interrupted: bool,
    /// Why the run stopped: `target reached`, `interrupted`, `generation limit`,
    /// `stagnation` or `time limit`.
    pub stop: &'static str,
}

#[derive(Serialize)]
struct GradingSummary {
    d_min: f64,
    d_max: f64,
    basis: &'static str,
}

#[derive(Serialize)]
struct StatsSummary {
    sizes_drawn: u64,
    sizes_deferred: u64,
    sizes_unplaced: u64,
    front_attempts: u64,
    fallbacks: u64,
    witness_checks: u64,
}

impl From<PackStats> for StatsSummary {
    fn from(s: PackStats) -> Self {
        StatsSummary {
            sizes_drawn: s.sizes_drawn,
            sizes_deferred: s.sizes_deferred,
            sizes_unplaced: s.sizes_unplaced,
            front_attempts: s.front_attempts,
            fallbacks: s.fallbacks,
            witness_checks: s.witness_checks,
        }
    }
}

/// The fracture block of `summary.json`.
fn fracture_summary(info: FractureInfo<'_>) -> FractureSummary<'_> {
    let f = info.well.fracture;
    let (extent, tolerance) = match info.extent {
        Extent::Full => ("full", f64::NAN),
        Extent::Window { tolerance } => ("window", tolerance),
    };
    FractureSummary {
        name: &info.well.name,
        width_mm: f.width,
        height_m: f.length / MM_PER_M,
        tip_width_mm: f.tip_width,
        extent,
        window: info.window.and_then(|w| {
            let last = w.last()?;
            Some(WindowSummary {
                tolerance,
                settled: w.settled,
                length_mm: last.length,
                length_fraction: last.length / f.length,
                porosity: last.porosity,
                porosity_spread: last.spread,
                coordination: last.coordination,
                seconds: w.seconds,
                steps: &w.steps,
            })
        }),
    }
}

/// The run summary as pretty-printed JSON (keys listed in `docs/config.md`).
///
/// `seconds` is the packing time alone (`pack`) or the whole search
/// (`optimise`); non-finite metrics are `null`.
///
/// # Errors
/// [`OutputError::Json`] if serialisation fails (it does not for these types).
pub fn summary_json(
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
) -> Result<Vec<u8>, OutputError> {
    let mut bytes = serde_json::to_vec_pretty(&summary(packing, metrics, run))?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// The object `summary.json` holds, also embedded in `packing.json`.
pub(super) fn summary<'a>(
    packing: &Packing,
    metrics: &'a Metrics,
    run: &RunInfo<'a>,
) -> Summary<'a> {
    let scene = run.scene;
    Summary {
        gapack_version: env!("CARGO_PKG_VERSION"),
        config: run.config,
        seed: scene.seed,
        shape: packing.domain.shape().config_name(),
        walls: packing.walls.config_name(),
        wall_disks: packing.boundary.len(),
        method: scene.packer.method.config_name(),
        index: scene.packer.index.config_name(),
        one_contact_share: scene.packer.one_contact_share,
        gap: scene.packer.gap,
        max_deferred: scene.packer.max_deferred,
        rules: scene.packer.rules.config_name(),
        fill: scene.packer.fill.config_name(),
        grading: GradingSummary {
            d_min: scene.grading.d_min(),
            d_max: scene.grading.d_max(),
            basis: scene.grading.basis().config_name(),
        },
        metrics,
        seconds: run.seconds,
        stats: packing.stats.into(),
        optimise: run.optimise.map(|(summary, _)| summary),
        materials: run
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| MaterialSummary {
                id: i + 1,
                name: &m.name,
                properties: m.properties.iter().map(|(k, v)| (k.as_str(), *v)).collect(),
                area_fraction: run.layering.and_then(|(_, l)| l.fractions.get(i).copied()),
            })
            .collect(),
        layering: run.layering.map(|(settings, l)| LayeringSummary {
            profile_rms_error: l.rms,
            baseline_rms_error: l.baseline_rms,
            baseline_seconds: l.baseline_seconds,
            layering: LayeringDetails {
                mode: settings.mode.config_name(),
                axis: settings.axis.config_name(),
                bins: settings.bins,
                profile: settings.profile.name(),
                ga_seconds: l.seconds,
                evaluations: l.evaluations,
                generations: l.generations,
                stop: l.stop.map(StopReason::describe),
            },
        }),
        fracture: run.fracture.map(fracture_summary),
    }
}
