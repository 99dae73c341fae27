//! The one error type of the config layer: where the file is at fault and why.

use std::fmt;

use crate::geometry::{GeometryError, OutlineError};
use crate::grading::GradingError;
use crate::layering::LayeringError;
use crate::packer::PackError;

/// A place in a config: its origin (file name or label), line and column (1-based).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// File path or label the text came from, as given to [`crate::config::parse`].
    pub origin: String,
    /// Line, from 1.
    pub line: usize,
    /// Column in characters, from 1.
    pub column: usize,
}

impl Location {
    /// The location of byte `offset` of `text` (clamped to the text).
    pub(crate) fn at(origin: &str, text: &str, offset: usize) -> Self {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        Location {
            origin: origin.to_owned(),
            line,
            column,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.origin, self.line, self.column)
    }
}

/// Why a config cannot become a [`crate::Scene`].
///
/// Every variant knows its [`Location`] and, but for some syntax errors, the
/// key path at fault (`domain.width`, `grading.table[3]`). `Display` gives one
/// line: `configs/bad.toml:4:9: domain.width: must be a positive finite number, got -1`.
/// The message is complete in itself: wrapped errors are part of it, not a
/// separate `source()`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// The text is not valid TOML.
    #[error("{at}: {}TOML syntax error: {message}", key_prefix(.key.as_deref()))]
    Syntax {
        /// Where.
        at: Location,
        /// The key being read, when it can be told.
        key: Option<String>,
        /// The parser's message.
        message: String,
    },
    /// Valid TOML that does not fit the schema: unknown key, wrong type, missing key.
    #[error("{at}: {key}: {message}")]
    Schema {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A size that is zero, negative, NaN or infinite.
    #[error("{at}: {key}: must be a positive finite number, got {value}")]
    NotPositive {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The value given.
        value: f64,
    },
    /// A coordinate that is NaN or infinite.
    #[error("{at}: {key}: must be a finite number, got {value}")]
    NotFinite {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The value given.
        value: f64,
    },
    /// A number outside the range its key allows.
    #[error("{at}: {key}: must be {range}, got {value}")]
    OutOfRange {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The range, in words (`"in [0, 1]"`, `"at least 2"`).
        range: String,
        /// The value given.
        value: f64,
    },
    /// Sizes, each positive and finite, whose product (the domain's area)
    /// overflows to infinity or underflows to zero.
    #[error("{at}: {key}: out of range: the domain's area, {formula}, {}", area_words(*.area))]
    Area {
        /// Where.
        at: Location,
        /// Key path at fault: the largest size when the area overflows, the smallest when it underflows.
        key: String,
        /// How the area is computed, in the config's key names (`"width × height"`).
        formula: String,
        /// The area computed (mm²): infinite, zero or NaN.
        area: f64,
    },
    /// A search (optimisation, layering) that would need more memory than
    /// the limit allows: a [`ConfigError::forceable`] refusal.
    #[error("{at}: {key}: {reason}")]
    Memory {
        /// Where.
        at: Location,
        /// Key path to act on.
        key: String,
        /// What needs how much memory against which limit, and how to act.
        reason: String,
    },
    /// A name that is not one of the valid ones.
    #[error("{at}: {key}: unknown {what} {given}; valid: {}", .valid.join(", "))]
    UnknownName {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// What kind of name (shape, index, ...).
        what: &'static str,
        /// The value given, as written.
        given: String,
        /// The valid names.
        valid: Box<[&'static str]>,
    },
    /// A required key is absent.
    #[error("{at}: {key}: missing; {reason}")]
    Missing {
        /// Where the key was expected (its table or the key that requires it).
        at: Location,
        /// Key path of the missing key.
        key: String,
        /// Why it is needed.
        reason: String,
    },
    /// A key that does not apply here (e.g. `radius` for a rectangle) or clashes with another.
    #[error("{at}: {key}: {reason}")]
    NotApplicable {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// Why it does not apply.
        reason: String,
    },
    /// The domain constructor refused the values.
    #[error("{at}: {key}: {error}")]
    Geometry {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The geometry error.
        error: GeometryError,
    },
    /// A layering profile that cannot work.
    #[error("{at}: {key}: {error}")]
    Layering {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The layering error.
        error: LayeringError,
    },
    /// A `[shape]` outline the outline constructor refused (a polygon
    /// template that is not convex, or has fewer than 3 vertices).
    #[error("{at}: {key}: {error}")]
    Outline {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The outline error.
        error: OutlineError,
    },
    /// The grading constructor refused the values.
    #[error("{at}: {key}: {error}")]
    Grading {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// The grading error.
        error: GradingError,
    },
    /// Domain and grading are valid apiece but the scene cannot be packed
    /// (domain narrower than the smallest disk, or over the memory limit).
    #[error("{at}: {key}: {error}{hint}")]
    Scene {
        /// Where.
        at: Location,
        /// Key path at fault.
        key: String,
        /// Why the scene cannot be packed.
        error: PackError,
        /// What to change, starting with "; " (may be empty).
        hint: String,
    },
}

/// What went wrong with an area that is not a positive finite number.
fn area_words(area: f64) -> String {
    if area == 0.0 {
        "underflows to 0 mm²: the sizes are too small to multiply in floating point".to_owned()
    } else if area.is_nan() {
        "is not a number".to_owned()
    } else {
        format!(
            "overflows to {area} mm² (beyond {:.1e}, the largest number): the sizes are too large",
            f64::MAX
        )
    }
}

fn key_prefix(key: Option<&str>) -> String {
    key.map_or_else(String::new, |k| format!("{k}: "))
}

impl ConfigError {
    /// Where in the config the error lies.
    pub fn location(&self) -> &Location {
        match self {
            ConfigError::Syntax { at, .. }
            | ConfigError::Schema { at, .. }
            | ConfigError::NotPositive { at, .. }
            | ConfigError::NotFinite { at, .. }
            | ConfigError::OutOfRange { at, .. }
            | ConfigError::Area { at, .. }
            | ConfigError::Memory { at, .. }
            | ConfigError::UnknownName { at, .. }
            | ConfigError::Missing { at, .. }
            | ConfigError::NotApplicable { at, .. }
            | ConfigError::Geometry { at, .. }
            | ConfigError::Layering { at, .. }
            | ConfigError::Outline { at, .. }
            | ConfigError::Grading { at, .. }
            | ConfigError::Scene { at, .. } => at,
        }
    }

    /// The fault without its place: `key: what is wrong`.
    pub(crate) fn detail(&self) -> String {
        let text = self.to_string();
        let at = format!("{}: ", self.location());
        text.strip_prefix(&at)
            .map_or_else(|| text.clone(), str::to_owned)
    }

    /// What is wrong, without the place or the key.
    pub(crate) fn message(&self) -> String {
        let detail = self.detail();
        match self.key() {
            Some(key) => detail
                .strip_prefix(&format!("{key}: "))
                .map_or_else(|| detail.clone(), str::to_owned),
            None => detail,
        }
    }

    /// The same fault, placed at `place` and blamed on `name`: a value of
    /// a `[sweep]` table found at fault in the config it makes.
    pub(crate) fn relocated(mut self, place: Location, name: String) -> Self {
        match &mut self {
            ConfigError::Syntax { at, key, .. } => {
                *at = place;
                *key = Some(name);
            }
            ConfigError::Schema { at, key, .. }
            | ConfigError::NotPositive { at, key, .. }
            | ConfigError::NotFinite { at, key, .. }
            | ConfigError::OutOfRange { at, key, .. }
            | ConfigError::Area { at, key, .. }
            | ConfigError::Memory { at, key, .. }
            | ConfigError::UnknownName { at, key, .. }
            | ConfigError::Missing { at, key, .. }
            | ConfigError::NotApplicable { at, key, .. }
            | ConfigError::Geometry { at, key, .. }
            | ConfigError::Layering { at, key, .. }
            | ConfigError::Outline { at, key, .. }
            | ConfigError::Grading { at, key, .. }
            | ConfigError::Scene { at, key, .. } => {
                *at = place;
                *key = name;
            }
        }
        self
    }

    /// Whether this is a `[limits]` refusal made before the run on the
    /// scene's upper bounds (too many particles, too much memory for the
    /// scene, the optimisation or the layering search), which
    /// [`ParseOptions::force`](super::ParseOptions::force) skips.
    ///
    /// The message ends with the config keys that raise the limit; a
    /// front end appends how its own users force the run
    /// (`, or run with --force to go ahead` on the command line).
    pub fn forceable(&self) -> bool {
        matches!(
            self,
            ConfigError::Memory { .. }
                | ConfigError::Scene {
                    error: PackError::TooManyParticles { .. } | PackError::TooLarge { .. },
                    ..
                }
        )
    }

    /// The key path at fault (`domain.width`), if known.
    pub fn key(&self) -> Option<&str> {
        match self {
            ConfigError::Syntax { key, .. } => key.as_deref(),
            ConfigError::Schema { key, .. }
            | ConfigError::NotPositive { key, .. }
            | ConfigError::NotFinite { key, .. }
            | ConfigError::OutOfRange { key, .. }
            | ConfigError::Area { key, .. }
            | ConfigError::Memory { key, .. }
            | ConfigError::UnknownName { key, .. }
            | ConfigError::Missing { key, .. }
            | ConfigError::NotApplicable { key, .. }
            | ConfigError::Geometry { key, .. }
            | ConfigError::Layering { key, .. }
            | ConfigError::Outline { key, .. }
            | ConfigError::Grading { key, .. }
            | ConfigError::Scene { key, .. } => Some(key),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn location_counts_lines_and_characters() {
        let text = "a = 1\nbé = 2\n";
        let at = Location::at("f.toml", text, text.find('2').unwrap_or(0));
        assert_eq!((at.line, at.column), (2, 6));
        assert_eq!(Location::at("f", text, 0).to_string(), "f:1:1");
        // Past the end and inside a multi-byte character are clamped, not a panic.
        assert_eq!(Location::at("f", text, 999).line, 3);
        assert_eq!(Location::at("f", text, 8).column, 2);
    }
}
