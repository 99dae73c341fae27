//! The entry point: TOML text in, validated [`Scene`] or one [`ConfigError`] out.

use super::error::ConfigError;
use super::locate::from_toml_error;
use super::raw::RawConfig;
use super::validate::Validator;
use crate::Scene;
use crate::compare::CompareSettings;
use crate::fracture::FractureRun;
use crate::ga::OptimiseSettings;
use crate::layering::{LayeringSettings, Material};
use crate::output::OutputSettings;
use crate::study::SweepSettings;

/// A validated config: the scene, and what to do with it beyond packing it once.
#[derive(Debug, Clone)]
pub struct Config {
    /// The scene to pack.
    pub scene: Scene,
    /// `[optimise]`: a target-porosity run, if the config asks for one.
    pub optimise: Option<OptimiseSettings>,
    /// `[[materials]]`, in config order (a disk's material is an index into it).
    pub materials: Vec<Material>,
    /// `[layering]`: where the materials go.
    pub layering: Option<LayeringSettings>,
    /// `[fracture]`: the fractures to pack and how much of each (the scene
    /// above is the first one's).
    pub fracture: Option<FractureRun>,
    /// `[compare]`: what `gapack compare` runs (its defaults without the table).
    pub compare: CompareSettings,
    /// `[output]`: where runs write and what (its defaults without the table).
    pub output: OutputSettings,
    /// `[sweep]`: the parameter study `gapack sweep` runs, if the config has one.
    pub sweep: Option<SweepSettings>,
}

/// The embedded default scene: the thesis' proppant fracture (8.6 × 62.5 mm,
/// grading of its Table 3.4, exact walls, seed 0).
pub const DEFAULT_CONFIG: &str = include_str!("../../configs/default.toml");

/// What [`parse`] is told the origin is when the text is [`DEFAULT_CONFIG`].
pub const DEFAULT_ORIGIN: &str = "embedded default";

/// Parse and validate a config.
///
/// `origin` names the text in error messages (a file path, or a label such
/// as [`DEFAULT_ORIGIN`]); nothing is read from disk.
///
/// # Errors
/// The first fault found, with `origin:line:column` and the key path, e.g.
/// `bad.toml:4:9: domain.width: must be a positive finite number, got -1`.
///
/// # Example
/// ```no_run
/// let config = gapack::config::parse(gapack::config::DEFAULT_CONFIG, "embedded default")?;
/// assert_eq!(config.scene.seed, 0);
/// assert!(config.optimise.is_none());
/// # Ok::<(), gapack::config::ConfigError>(())
/// ```
pub fn parse(text: &str, origin: &str) -> Result<Config, ConfigError> {
    parse_with(text, origin, ParseOptions::default())
}

/// How [`parse_with`] treats a config.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ParseOptions {
    /// Skip the `[limits]` refusals made before the run on the scene's
    /// upper bounds (`max_particles`, `max_memory_mb`), for a scene whose
    /// bound is far above what it will hold (a grading with a fine tail);
    /// [`ConfigError::forceable`] tells those refusals, for a front end to
    /// say how its users ask for this. The limits still hold during the
    /// run: it stops with an error if the packing reaches one.
    pub force: bool,
}

/// [`parse`] with options.
///
/// # Errors
/// As [`parse`], but for the limit refusals when `options.force` is set.
pub fn parse_with(text: &str, origin: &str, options: ParseOptions) -> Result<Config, ConfigError> {
    let raw: RawConfig = toml::from_str(text).map_err(|e| from_toml_error(&e, text, origin))?;
    Validator {
        text,
        origin,
        force: options.force,
    }
    .config(raw)
}
