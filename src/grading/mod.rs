//! Grading curves: sieve tables, shorthands, presets, inverse-CDF sampling, fidelity.
//!
//! STUB: the grading helper replaces the `todo!()` bodies; signatures are fixed.

/// How percent passing is interpolated between sieve points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interpolation {
    /// Linear in ln d (a straight line on the semi-log grading chart; default).
    #[default]
    Log,
    /// Linear in d.
    Linear,
}

/// What "percent passing" counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Basis {
    /// Fraction of particle count (the thesis' reading; default).
    #[default]
    Number,
    /// Fraction of 2D solid area (weight d²).
    Mass,
    /// Fraction of 3D sphere mass (weight d³), for true sieve data.
    Mass3d,
}

/// Why a grading cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GradingError {
    /// Placeholder until the module is written.
    #[error("{0}")]
    Invalid(String),
}

/// A grading curve: a cumulative distribution of disk diameters (mm).
#[derive(Debug, Clone, PartialEq)]
pub struct Grading {
    basis: Basis,
}

impl Grading {
    /// From a sieve table of `(diameter_mm, percent_passing)`.
    pub fn from_table(
        points: &[(f64, f64)],
        interpolation: Interpolation,
        basis: Basis,
    ) -> Result<Self, GradingError> {
        todo!("{points:?}{interpolation:?}{basis:?}")
    }
    /// Uniform in diameter between `a` and `b` (in the given basis).
    pub fn uniform(a: f64, b: f64, basis: Basis) -> Result<Self, GradingError> {
        todo!("{a}{b}{basis:?}")
    }
    /// A single diameter.
    pub fn constant(d: f64) -> Result<Self, GradingError> {
        todo!("{d}")
    }
    /// A proppant mesh preset such as "20/40".
    pub fn preset(
        name: &str,
        interpolation: Interpolation,
        basis: Basis,
    ) -> Result<Self, GradingError> {
        todo!("{name}{interpolation:?}{basis:?}")
    }
    /// The basis the curve is expressed in.
    pub fn basis(&self) -> Basis {
        self.basis
    }
    /// Smallest diameter.
    pub fn d_min(&self) -> f64 {
        todo!()
    }
    /// Largest diameter.
    pub fn d_max(&self) -> f64 {
        todo!()
    }
    /// Mean disk area by number (mm²): the expected area of one drawn disk.
    pub fn mean_disk_area(&self) -> f64 {
        todo!()
    }
    /// Inverse CDF by number: the diameter drawn for a gene `u` in [0, 1].
    pub fn sample(&self, u: f64) -> f64 {
        todo!("{u}")
    }
    /// The curve's CDF (fraction passing, 0..1) at `d`, in the curve's basis.
    pub fn cdf(&self, d: f64) -> f64 {
        todo!("{d}")
    }
    /// Kolmogorov–Smirnov distance of `diameters` to the curve, in the curve's basis.
    pub fn ks_distance(&self, diameters: &[f64]) -> f64 {
        todo!("{diameters:?}")
    }
}
