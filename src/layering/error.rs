//! Why a layering request cannot be built.

/// A profile or material list that cannot work.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LayeringError {
    /// The profile needs exactly two materials.
    #[error("profile \"{profile}\" needs exactly 2 materials, got {got}")]
    TwoMaterials {
        /// The profile's name.
        profile: &'static str,
        /// Materials given.
        got: usize,
    },
    /// An exponent that is not a positive finite number.
    #[error("the exponent must be a positive finite number, got {0}")]
    Exponent(f64),
    /// Layer thicknesses that do not add up to 1.
    #[error("layer thicknesses must add up to 1 (± 1e-6), got {0}")]
    Thicknesses(f64),
    /// A layer thickness that is negative or not finite.
    #[error("a layer thickness must be a finite number ≥ 0, got {0}")]
    Thickness(f64),
    /// Fractions of a table row that do not add up to 1.
    #[error("the fractions of table row {row} must add up to 1 (± 1e-6), got {sum}")]
    Fractions {
        /// Row index, from 0.
        row: usize,
        /// Their sum.
        sum: f64,
    },
    /// A table row of the wrong length.
    #[error("table row {row} has {got} numbers; it needs s and one fraction per material ({want})")]
    RowLength {
        /// Row index, from 0.
        row: usize,
        /// Numbers given.
        got: usize,
        /// Numbers needed.
        want: usize,
    },
    /// Table rows whose s is outside [0, 1] or not increasing, or a negative fraction.
    #[error("table row {row}: s must rise within [0, 1] and fractions be ≥ 0")]
    TableOrder {
        /// Row index, from 0.
        row: usize,
    },
    /// A table with no rows, or steps with no layer.
    #[error("the profile has no {0}")]
    Empty(&'static str),
}
