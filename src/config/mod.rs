//! TOML configuration: raw serde stage, then validation into a [`Config`]
//! (a [`crate::Scene`] and what to do with it).
//!
//! No I/O here: [`parse`] takes the text and a name for its origin. Every
//! fault is one [`ConfigError`] naming the origin, line, column and key path.
//! The keys are documented in `docs/config.md`.

mod error;
mod locate;
mod parse;
mod raw;
mod sweep_points;
mod validate;

#[cfg(test)]
mod tests;

pub use crate::names::{ConfigName, METHOD};
pub use error::{ConfigError, Location};
pub use locate::key_location;
pub use parse::{Config, DEFAULT_CONFIG, DEFAULT_ORIGIN, ParseOptions, parse, parse_with};
pub use sweep_points::{SweepConfigs, SweepPoint};
pub use validate::{DEFAULT_MAX_MEMORY_MB, DEFAULT_MAX_PARTICLES, layering_peak_bytes};
