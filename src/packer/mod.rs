//! Packing generators, spatial indexes and packing metrics.

mod advancing_front;
mod arcs;
pub mod index;
mod metrics;
mod packing;
mod settings;
mod sizer;

pub use advancing_front::{pack, pack_genes, size_count};
pub use metrics::{Metrics, measure};
pub use packing::{PackError, PackStats, Packing};
pub use settings::{Fill, FrontRules, IndexKind, MAX_DEFERRED, MAX_GAP, PackerSettings};

use crate::Scene;

/// Upper bound of the packer's peak memory per disk (bytes), checked by `gapack bench`.
pub const PEAK_BYTES_PER_DISK: f64 = 100.0;

/// Estimated peak memory (bytes) to pack `scene`.
///
/// Counts disks as if the domain were filled solid with disks of the
/// grading's mean area (an upper bound), times [`PEAK_BYTES_PER_DISK`].
pub fn estimated_peak_bytes(scene: &Scene) -> f64 {
    scene.domain.area() / scene.mean_disk_area() * PEAK_BYTES_PER_DISK
}
