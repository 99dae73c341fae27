//! `summary.json`: what was packed, how, and how well.

use std::collections::BTreeMap;

use serde::Serialize;

use super::error::OutputError;
use super::run::RunInfo;
use crate::fracture::WindowStep;
use crate::metrics::{Metrics, ShapeStats, psd_ks_blend, psd_ks_by_curve, shape_stats};
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
    /// Whether `psd_ks` lies within the sampling noise `gapack verify` allows.
    grading_kept: bool,
    /// Size-graded: each material's KS distance to its own curve (`psd_ks`
    /// is the largest), as `psd.png` shows them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    psd_ks_by_material: Vec<MaterialKs>,
    /// Size-graded: the KS distance of all disks to the blend of the curves.
    #[serde(skip_serializing_if = "Option::is_none")]
    psd_ks_blend: Option<f64>,
    /// Particles that are not disks: their shape measures, both mean
    /// sizes, the size the grading gave and what the `[shape]` asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    particle_shape: Option<&'a ShapeStats>,
    seconds: f64,
    stats: StatsSummary,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    optimise: Option<&'a OptimiseSummary>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    materials: Vec<MaterialSummary<'a>>,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    layering: Option<&'a LayeringSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    fracture: Option<&'a FractureSummary<'a>>,
}

/// What a fracture run adds to `summary.json` (filled in by the job).
#[derive(Debug, Clone, Serialize)]
pub struct FractureSummary<'a> {
    /// The well's name.
    pub name: &'a str,
    /// Fracture width at the well (mm).
    pub width_mm: f64,
    /// Fracture height (m).
    pub height_m: f64,
    /// Width at the tip, for a tapered fracture (mm).
    pub tip_width_mm: Option<f64>,
    /// `full` or `window`.
    pub extent: &'static str,
    /// The window grown, in window mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window: Option<WindowSummary<'a>>,
}

/// A fracture window: the estimate and every window tried.
#[derive(Debug, Clone, Serialize)]
pub struct WindowSummary<'a> {
    /// The settling tolerance asked for.
    pub tolerance: f64,
    /// Whether the last windows agreed within it.
    pub settled: bool,
    /// Length of the last window (mm).
    pub length_mm: f64,
    /// Window length over the fracture's.
    pub length_fraction: f64,
    /// Porosity of the last window's core.
    pub porosity: f64,
    /// Spread of the porosity over its core.
    pub porosity_spread: f64,
    /// Mean coordination number of the last window's core.
    pub coordination: f64,
    /// All the windows together (s).
    pub seconds: f64,
    /// Every window tried.
    pub steps: &'a [WindowStep],
}

/// A material's KS distance to its own grading curve.
#[derive(Serialize)]
struct MaterialKs {
    name: String,
    ks: f64,
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
    /// Particles that are not disks: the shape measures of this
    /// material's particles, against the shape it was drawn with.
    #[serde(skip_serializing_if = "Option::is_none")]
    particle_shape: Option<ShapeStats>,
}

/// What a layering adds to `summary.json` (filled in by the job).
#[derive(Debug, Clone, Serialize)]
pub struct LayeringSummary {
    /// RMS error of the material fractions against the profile.
    pub profile_rms_error: f64,
    /// The same for the baseline assignment.
    pub baseline_rms_error: f64,
    /// Time the baseline took (s).
    pub baseline_seconds: f64,
    /// How the layering ran.
    pub layering: LayeringDetails,
}

/// The settings and effort of a layering, as `summary.json` records them.
#[derive(Debug, Clone, Serialize)]
pub struct LayeringDetails {
    /// `materials` or `sizes`.
    pub mode: &'static str,
    /// `x`, `y` or `radial`.
    pub axis: &'static str,
    /// Bins along the axis.
    pub bins: usize,
    /// The profile's name.
    pub profile: &'static str,
    /// Time the GA took (s).
    pub ga_seconds: f64,
    /// Genomes evaluated.
    pub evaluations: u64,
    /// Generations after the initial one.
    pub generations: usize,
    /// Why the GA stopped (none without a GA).
    pub stop: Option<&'static str>,
    /// Whether the same config and seed give this result on any machine:
    /// false when the GA was stopped by its time limit.
    pub reproducible: bool,
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
    /// Whether the target was reached or lies in the achievable range
    /// (± tolerance): true; out of reach after a search that ran its
    /// course: false; `None` (null) when the search cannot tell.
    pub feasible: Option<bool>,
    /// What the search says of its target: `reached`, `not reached, within
    /// range`, `not reached`, `out of reach` or `interrupted`.
    pub verdict: &'static str,
    /// Porosity range of the packings the search made that honour the
    /// grading (`max_psd_ks`): what this domain and grading were seen to
    /// reach; `None` (null) when no packing honoured it.
    pub achievable_range: Option<[f64; 2]>,
    /// The estimate before the search: the range the initial population
    /// spanned, from dense to the loosest packing rules; `None` (null) when
    /// no initial genome could be packed.
    pub initial_range: Option<[f64; 2]>,
    /// Whether the run was stopped by Ctrl-C (the best packing so far is written).
    pub interrupted: bool,
    /// Why the run stopped: `target reached`, `interrupted`, `generation limit`,
    /// `stagnation`, `evaluation budget` or `time limit`.
    pub stop: &'static str,
    /// Whether the same config and seed give this result on any machine:
    /// false when the search was stopped by its time limit (or interrupted),
    /// which depends on the machine's speed and load.
    pub reproducible: bool,
    /// The window the search ran on, for a large scene (`None`: the whole).
    pub window: Option<Box<SearchWindow>>,
    /// The shape the search found, with `[optimise.shape]` (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape_found: Option<Box<ShapeFound>>,
}

/// The particle shape a target-porosity search found (`[optimise.shape]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeFound {
    /// Least and greatest aspect ratio drawn (uniform between; equal: one for all).
    pub aspect: [f64; 2],
    /// The superellipse exponent α = β.
    pub exponent: f64,
    /// Standard deviation of the aligned particles' orientation (degrees);
    /// `None` (null): the orientation was not searched.
    pub orientation_spread_deg: Option<f64>,
    /// Mean Riley sphericity of the shape found (midpoint rule over its aspects).
    pub mean_sphericity: f64,
    /// Mean Wadell roundness of the shape found.
    pub mean_roundness: f64,
    /// KS distance of the packed aspect ratios to the range found.
    pub aspect_ks: f64,
    /// The bounds it kept: `min_sphericity`, `min_roundness`, `max_shape_ks`.
    pub min_sphericity: f64,
    /// See `min_sphericity`.
    pub min_roundness: f64,
    /// See `min_sphericity`.
    pub max_shape_ks: f64,
}

impl ShapeFound {
    /// The shape in a few words, for the convergence chart.
    pub fn describe(&self) -> String {
        let [lo, hi] = self.aspect;
        let aspect = if hi > lo {
            format!("aspect {lo:.2}–{hi:.2}")
        } else {
            format!("aspect {lo:.2}")
        };
        format!(
            "{aspect}, exponent {:.2}, sphericity {:.2}, roundness {:.2}",
            self.exponent, self.mean_sphericity, self.mean_roundness
        )
    }
}

/// The window a large scene's search ran on (`ga::window`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SearchWindow {
    /// Width and height of the window searched (mm).
    pub size: [f64; 2],
    /// Its area as a share of the domain's.
    pub share: f64,
    /// Disks in it, packed with the scene's own rules.
    pub disks: usize,
    /// Whether the last two windows agreed within the tolerance (else the
    /// window is the largest allowed, a quarter of the domain).
    pub settled: bool,
    /// Every window packed with the scene's own rules: width, height (mm),
    /// porosity, and the porosity of its core (less three largest
    /// diameters along each edge), which must settle.
    pub steps: Vec<[f64; 4]>,
    /// The window's porosity less the whole's, both with the scene's own
    /// rules (the difference of wall effect): the search aimed at the
    /// target plus this, and its ranges are given less it.
    pub offset: f64,
    /// Packs of the whole: one with the scene's own rules, then those
    /// tuning the window's rules on the whole.
    pub whole_packs: u32,
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

/// The shape statistics ([`shape_stats`]) of the grains of each material
/// of `run`, against the shape each was drawn with; empty for a packing of
/// disks or one without materials, `None` for a material without particles.
fn shape_stats_by_material(packing: &Packing, run: &RunInfo<'_>) -> Vec<Option<ShapeStats>> {
    if packing.grains.is_empty() || packing.materials.len() != packing.grains.len() {
        return Vec::new();
    }
    (0..run.materials.len())
        .map(|m| {
            let own: Vec<_> = packing
                .grains
                .iter()
                .zip(&packing.materials)
                .filter(|(_, t)| usize::from(**t) == m)
                .map(|(g, _)| g.clone())
                .collect();
            shape_stats(&own, run.scene.material_shape(m))
        })
        .collect()
}

/// The object `summary.json` holds, also embedded in `packing.json`.
pub(super) fn summary<'a>(
    packing: &Packing,
    metrics: &'a Metrics,
    run: &'a RunInfo<'a>,
) -> Summary<'a> {
    let scene = run.scene;
    let material_shapes = shape_stats_by_material(packing, run);
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
        grading_kept: crate::check::grading_kept(metrics.particles, metrics.psd_ks),
        psd_ks_by_material: if scene.gradient.is_some() {
            psd_ks_by_curve(packing, scene)
                .into_iter()
                .enumerate()
                .map(|(m, ks)| MaterialKs {
                    name: run
                        .materials
                        .get(m)
                        .map_or_else(|| format!("material {}", m + 1), |x| x.name.clone()),
                    ks,
                })
                .collect()
        } else {
            Vec::new()
        },
        psd_ks_blend: psd_ks_blend(packing, scene),
        particle_shape: metrics.shapes.as_ref(),
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
                area_fraction: run
                    .layering
                    .as_ref()
                    .and_then(|l| l.fractions.get(i).copied()),
                particle_shape: material_shapes.get(i).copied().flatten(),
            })
            .collect(),
        layering: run.layering.as_ref().map(|l| &l.summary),
        fracture: run.fracture.as_ref(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain, Grain, Outline};
    use crate::output::OutputSettings;

    #[test]
    fn particle_shape_is_recorded_for_grains_only() {
        let text = "[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 3.0]\n";
        let disks_scene = crate::config::parse_with(text, "t", Default::default())
            .unwrap()
            .scene;
        let scene = disks_scene
            .clone()
            .with_shape(crate::ShapeSpec::ellipses(2.0));
        let domain = Domain::rectangle(20.0, 20.0).unwrap();
        let e = Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
        let r = e.equivalent_radius();
        let grains = Packing {
            grains: vec![Grain::new(e, 0.4)],
            ..Packing::of_disks(domain.clone(), vec![Disk::new(10.0, 10.0, r)])
        };
        let output = OutputSettings::default();
        let json = |p: &Packing, s: &crate::Scene| {
            let m = crate::measure(p, s);
            let run = RunInfo::new(s, "t", 0.0, &output);
            String::from_utf8(summary_json(p, &m, &run).unwrap()).unwrap()
        };
        let with = json(&grains, &scene);
        let v: serde_json::Value = serde_json::from_str(&with).unwrap();
        let shape = &v["particle_shape"];
        assert_eq!(shape["size_measure"], "sieve", "{with}");
        assert_eq!(shape["asked"]["family"], "superellipse");
        assert!((shape["mean_least_width"].as_f64().unwrap() - 2.0).abs() < 1e-9);
        assert!(
            (shape["fabric"]["direction"].as_f64().unwrap() - 0.4f64.to_degrees()).abs() < 1e-9
        );
        // The domain's shape keeps its key.
        assert_eq!(v["shape"], "rectangle");
        let disks = Packing::of_disks(domain, vec![Disk::new(10.0, 10.0, 1.0)]);
        assert!(!json(&disks, &disks_scene).contains("particle_shape"));
    }
}
