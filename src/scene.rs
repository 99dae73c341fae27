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
    /// Diameter of the wall disks for `walls = "disks"`; `None` uses
    /// [`Scene::DEFAULT_WALL_DISK_FRACTION`] of the grading's smallest diameter.
    pub wall_disk_diameter: Option<f64>,
    /// The grading curve sizes are drawn from.
    pub grading: Grading,
    /// Packer method, spatial index and contact rule.
    pub packer: PackerSettings,
    /// Seed of the random sizes (and of one-contact placement angles).
    pub seed: u64,
}

impl Scene {
    /// Default wall-disk diameter as a fraction of the smallest diameter.
    ///
    /// Wall disks sit centred on the boundary, touching or overlapping their
    /// neighbours. This fine discretisation reproduces the thesis' porosities
    /// (fracture case 0.225, squares of Table 3.13) within their scatter; wall
    /// disks as large as the particles cost a layer of porosity along every
    /// wall (0.36 instead of 0.225 on the fracture case).
    pub const DEFAULT_WALL_DISK_FRACTION: f64 = 1.0 / 12.0;

    /// Diameter of the wall disks used with `walls = "disks"`.
    pub fn wall_disk(&self) -> f64 {
        self.wall_disk_diameter
            .unwrap_or(self.grading.d_min() * Self::DEFAULT_WALL_DISK_FRACTION)
    }
}
