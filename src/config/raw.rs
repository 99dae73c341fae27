//! Stage one: the config as written, every value with its place in the text.
//!
//! Only TOML syntax, key names and value types are checked here (by serde);
//! meaning is checked in `validate.rs`.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

/// A pair of numbers such as `[x, y]` or a grading row `[d, passing]`.
pub(crate) type Pair = Spanned<[f64; 2]>;

/// A layer of a steps profile: `[material name, thickness]`.
pub(crate) type Layer = Spanned<(String, f64)>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawConfig {
    pub seed: Option<Spanned<u64>>,
    /// Required unless `[fracture]` gives the domain.
    pub domain: Option<Spanned<RawDomain>>,
    pub fracture: Option<Spanned<RawFracture>>,
    /// Required unless `[layering] mode = "sizes"` gives each material its own.
    pub grading: Option<Spanned<RawGrading>>,
    pub packer: Option<RawPacker>,
    #[serde(alias = "optimize")]
    pub optimise: Option<Spanned<RawOptimise>>,
    pub materials: Option<Vec<Spanned<RawMaterial>>>,
    pub layering: Option<Spanned<RawLayering>>,
    pub limits: Option<RawLimits>,
    pub compare: Option<Spanned<RawCompare>>,
    pub output: Option<Spanned<RawOutput>>,
}

/// `[output]`: where runs write and what.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    pub dir: Option<Spanned<String>>,
    pub formats: Option<Spanned<Vec<Spanned<String>>>>,
    pub density: Option<Spanned<f64>>,
    pub units: Option<Spanned<String>>,
}

/// `[compare]`: the methods `gapack compare` runs, and how many seeds.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCompare {
    pub methods: Option<Spanned<Vec<Spanned<String>>>>,
    pub repeats: Option<Spanned<i64>>,
}

/// `[[materials]]`: a name, free-form numeric properties, and in size-graded
/// mode a grading. Any other key is a property (checked to be a number).
#[derive(Debug, Deserialize)]
pub(crate) struct RawMaterial {
    pub name: Spanned<String>,
    pub grading: Option<Spanned<RawGrading>>,
    #[serde(flatten)]
    pub properties: BTreeMap<String, toml::Value>,
}

/// `[layering]`: where materials go along an axis.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLayering {
    pub mode: Option<Spanned<String>>,
    pub axis: Option<Spanned<String>>,
    pub bins: Option<Spanned<i64>>,
    pub profile: Option<Spanned<String>>,
    pub exponent: Option<Spanned<f64>>,
    pub layers: Option<Spanned<Vec<Layer>>>,
    pub table: Option<Spanned<Vec<Spanned<Vec<f64>>>>>,
    pub tolerance: Option<Spanned<f64>>,
    pub population: Option<Spanned<i64>>,
    pub generations: Option<Spanned<i64>>,
    pub stagnation: Option<Spanned<i64>>,
    pub time_limit_s: Option<Spanned<f64>>,
}

/// `[fracture]`: one fracture (absolute or normalised form), or a batch of wells.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFracture {
    pub width_mm: Option<Spanned<f64>>,
    pub height_m: Option<Spanned<f64>>,
    pub tip_width_mm: Option<Spanned<f64>>,
    pub width_ratio: Option<Spanned<f64>>,
    pub length_ratio: Option<Spanned<f64>>,
    pub mean_diameter: Option<Spanned<f64>>,
    pub walls: Option<Spanned<String>>,
    pub wall_disk: Option<Spanned<f64>>,
    pub extent: Option<Spanned<String>>,
    pub window_tolerance: Option<Spanned<f64>>,
    pub wells: Option<Vec<Spanned<RawWell>>>,
}

/// `[[fracture.wells]]`: a named fracture of a batch.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWell {
    pub name: Spanned<String>,
    pub width_mm: Option<Spanned<f64>>,
    pub height_m: Option<Spanned<f64>>,
    pub tip_width_mm: Option<Spanned<f64>>,
    pub fill: Option<Spanned<String>>,
}

/// `[domain]`: one shape and the keys that size it, plus the wall model.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDomain {
    pub shape: Spanned<String>,
    pub width: Option<Spanned<f64>>,
    pub height: Option<Spanned<f64>>,
    pub vertices: Option<Spanned<Vec<Pair>>>,
    pub radius: Option<Spanned<f64>>,
    pub center: Option<Pair>,
    pub bottom: Option<Spanned<f64>>,
    pub top: Option<Spanned<f64>>,
    pub walls: Option<Spanned<String>>,
    pub wall_disk: Option<Spanned<f64>>,
}

/// `[grading]`: exactly one of `table`, `uniform`, `constant`, `preset`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGrading {
    pub table: Option<Spanned<Vec<Pair>>>,
    pub uniform: Option<Pair>,
    pub constant: Option<Spanned<f64>>,
    pub preset: Option<Spanned<String>>,
    pub interpolation: Option<Spanned<String>>,
    pub basis: Option<Spanned<String>>,
}

/// `[packer]`: method and its settings.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPacker {
    pub method: Option<Spanned<String>>,
    pub index: Option<Spanned<String>>,
    pub contacts: Option<Spanned<i64>>,
    pub one_contact_share: Option<Spanned<f64>>,
    pub gap: Option<Spanned<f64>>,
    pub max_deferred: Option<Spanned<i64>>,
    pub rules: Option<Spanned<String>>,
    pub fill: Option<Spanned<String>>,
    pub attempts: Option<Spanned<i64>>,
    pub relaxation_porosity: Option<Spanned<f64>>,
    pub relaxation_iterations: Option<Spanned<i64>>,
    pub relaxation_tolerance: Option<Spanned<f64>>,
}

/// `[optimise]` (or `[optimize]`): a target-porosity run.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOptimise {
    pub target_porosity: Option<Spanned<f64>>,
    pub tolerance: Option<Spanned<f64>>,
    pub population: Option<Spanned<i64>>,
    pub generations: Option<Spanned<i64>>,
    pub stagnation: Option<Spanned<i64>>,
    pub time_limit_s: Option<Spanned<f64>>,
    pub max_psd_ks: Option<Spanned<f64>>,
}

/// `[limits]`: guards against scenes too large for the machine.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLimits {
    pub max_memory_mb: Option<Spanned<f64>>,
    pub max_particles: Option<Spanned<i64>>,
}
