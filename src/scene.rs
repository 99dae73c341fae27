//! The validated scene: everything the packer needs, nothing it does not.

use crate::geometry::{Domain, WallMode};
use crate::grading::Grading;
use crate::packer::PackerSettings;

/// A validated scene: domain, wall model, grading curve, packer settings and seed.
///
/// Built from a config (see [`crate::config`]) or directly in code; the same
/// scene and seed always give the same packing.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The region to fill (mm).
    pub domain: Domain,
    /// How walls are modelled: exact lines and arcs, or discretised into disks.
    pub walls: WallMode,
    /// Diameter of the wall disks for `walls = "disks"`; `None` uses the grading's smallest.
    pub wall_disk_diameter: Option<f64>,
    /// The grading curve sizes are drawn from.
    pub grading: Grading,
    /// Packer method, spatial index and contact rule.
    pub packer: PackerSettings,
    /// Seed of the random sizes (and of one-contact placement angles).
    pub seed: u64,
}
