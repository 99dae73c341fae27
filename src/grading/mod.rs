//! Grading curves: sieve tables, shorthands, presets, inverse-CDF sampling, fidelity.
//!
//! A [`Grading`] is a cumulative distribution of disk diameters (mm) given as
//! a sieve table. Its percent passing may count particles
//! ([`Basis::Number`]), 2D solid area ([`Basis::Mass`]) or 3D mass
//! ([`Basis::Mass3d`]); [`Grading::sample`] always draws by number so that a
//! packing built from its draws reproduces the curve in the curve's basis,
//! and [`Grading::ks_distance`] measures how well it does.

mod curve;
mod error;
mod fidelity;
mod preset;
#[cfg(test)]
mod test_tables;

pub use curve::{Basis, Grading, Interpolation};
pub use error::GradingError;

/// The thesis' Table 3.1 (Pinto 2009), `(diameter mm, percent passing by
/// number)`: the polydisperse grading of its benchmark run.
pub const THESIS_TABLE_3_1: &[(f64, f64)] =
    &[(1.275, 0.0), (1.8, 35.0), (2.55, 95.0), (3.54, 100.0)];

/// The thesis' Table 3.4 (Pinto 2009), `(diameter mm, percent passing by
/// number)`: the proppant grading of its fracture case and square domains,
/// used by the reproduction tests and `gapack bench`.
pub const THESIS_TABLE_3_4: &[(f64, f64)] = &[
    (1.200, 0.0),
    (1.215, 11.0),
    (1.225, 21.0),
    (1.235, 31.0),
    (1.245, 43.0),
    (1.255, 54.0),
    (1.265, 65.0),
    (1.275, 77.0),
    (1.285, 89.0),
    (1.295, 100.0),
];
