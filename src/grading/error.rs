//! Typed errors of the grading module, worded for a user editing a TOML file.

use super::preset::preset_list;

/// Why a grading cannot be built.
///
/// Row numbers are 1-based, as the user counts the rows of the table.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GradingError {
    /// The sieve table has fewer than two points.
    #[error("grading table: needs at least 2 points [diameter_mm, percent_passing], got {count}")]
    TooFewPoints {
        /// Number of points given.
        count: usize,
    },
    /// A diameter is zero, negative, infinite or NaN.
    #[error(
        "grading table: diameter at row {row} must be a positive, finite number of millimetres, got {diameter}"
    )]
    InvalidDiameter {
        /// 1-based row of the offending point.
        row: usize,
        /// The diameter given (mm).
        diameter: f64,
    },
    /// A diameter is smaller than the one in the row before it.
    #[error(
        "grading table: diameter decreases from {from} to {to} mm at row {row}; list sieve sizes from smallest to largest"
    )]
    DiameterDecreases {
        /// 1-based row of the smaller diameter.
        row: usize,
        /// Diameter of the previous row (mm).
        from: f64,
        /// Diameter of this row (mm).
        to: f64,
    },
    /// A percent passing is outside [0, 100], infinite or NaN.
    #[error(
        "grading table: percent passing at row {row} must be a number from 0 to 100, got {percent}"
    )]
    InvalidPercent {
        /// 1-based row of the offending point.
        row: usize,
        /// The percent given.
        percent: f64,
    },
    /// A percent passing is smaller than the one in the row before it.
    #[error(
        "grading table: percent passing decreases from {from} to {to} at row {row} (d = {diameter} mm)"
    )]
    PercentDecreases {
        /// 1-based row of the smaller percent.
        row: usize,
        /// Diameter of that row (mm).
        diameter: f64,
        /// Percent passing of the previous row.
        from: f64,
        /// Percent passing of this row.
        to: f64,
    },
    /// The first row (smallest diameter) does not have 0 % passing.
    #[error(
        "grading table: the first row (d = {diameter} mm) must have 0 % passing, got {percent}"
    )]
    FirstPercentNotZero {
        /// Diameter of the first row (mm).
        diameter: f64,
        /// Percent passing given there.
        percent: f64,
    },
    /// The last row (largest diameter) does not have 100 % passing.
    #[error(
        "grading table: the last row (row {row}, d = {diameter} mm) must have 100 % passing, got {percent}"
    )]
    LastPercentNotHundred {
        /// 1-based row number of the last row.
        row: usize,
        /// Diameter of the last row (mm).
        diameter: f64,
        /// Percent passing given there.
        percent: f64,
    },
    /// The bounds of a uniform grading are not `0 < min <= max`, finite.
    #[error(
        "uniform grading: needs finite diameters with 0 < min <= max (mm), got min = {min}, max = {max}"
    )]
    InvalidUniformRange {
        /// Smallest diameter given (mm).
        min: f64,
        /// Largest diameter given (mm).
        max: f64,
    },
    /// The diameter of a constant grading is not positive and finite.
    #[error(
        "constant grading: diameter must be a positive, finite number of millimetres, got {diameter}"
    )]
    InvalidConstant {
        /// The diameter given (mm).
        diameter: f64,
    },
    /// No preset has this name.
    #[error("unknown grading preset {name:?}; valid presets: {}", preset_list())]
    UnknownPreset {
        /// The name asked for.
        name: String,
    },
}
