//! Packing metrics: porosity, grading fidelity, overlaps, clearance, contacts, uniformity.
//!
//! STUB: bodies to come; fields are fixed.

use crate::grading::Grading;
use crate::packer::Packing;

/// What a packing achieved.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Number of packed disks (wall disks excluded).
    pub particles: usize,
    /// Domain area (mm²).
    pub domain_area: f64,
    /// Total area of the packed disks (mm²).
    pub solid_area: f64,
    /// 1 − solid_area / domain_area.
    pub porosity: f64,
    /// Kolmogorov–Smirnov distance of the packed sizes to the grading, in its basis.
    pub psd_ks: f64,
    /// Largest overlap between two disks (packed or wall), relative to the sum of their radii; 0 if none.
    pub max_overlap: f64,
    /// Smallest distance from a disk's edge to the domain boundary (mm); negative means outside.
    pub min_wall_clearance: f64,
    /// Mean number of disk–disk contacts per packed disk (gap within 1e-6 of the radii sum).
    pub coordination: f64,
    /// Standard deviation of local porosity over square windows of about 5·d_max.
    pub local_porosity_std: f64,
    /// Diameter of the largest empty circle left in the domain (mm).
    pub largest_hole: f64,
}

/// Measure a packing against its grading.
pub fn measure(packing: &Packing, grading: &Grading) -> Metrics {
    todo!("{packing:?}{grading:?}")
}
