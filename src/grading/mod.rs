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
