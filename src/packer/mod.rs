//! Packing generators and spatial indexes.

mod advancing_front;
mod arcs;
mod densify;
mod deposition;
mod grains;
pub mod index;
mod packing;
mod placed;
mod relaxation;
mod rsa;
mod sizer;
pub mod strips;
mod wall_runs;

pub use crate::scene::{
    DEFAULT_ATTEMPTS, Densify, Fill, FrontRules, IndexKind, MAX_DEFERRED, MAX_GAP, Method,
    PackerSettings, Relaxation, Strips,
};
pub use advancing_front::{WORK_PER_DISK, pack_genes_watched, size_count, work_budget};
pub use densify::{DensifyTrace, densify_traced, pack_densify};
pub use deposition::pack_deposition;
pub use grains::PEAK_BYTES_PER_GRAIN;
pub use packing::{PackError, PackStats, Packing};
pub use relaxation::pack_relaxation;
pub use rsa::pack_rsa;

pub(crate) use placed::packs_periodic;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::Scene;
use crate::cancel::Cancel;

/// Upper bound of the packer's peak memory per disk (bytes), checked by `gapack bench`.
pub const PEAK_BYTES_PER_DISK: f64 = 100.0;

/// Estimated peak memory (bytes) to pack `scene`: an upper bound.
///
/// Every particle the scene can hold ([`Scene::max_disks`], a true upper
/// bound) and every wall disk, times `peak_bytes_per_particle`. A run
/// with [`Limits::max_memory_bytes`](crate::Limits) counts its obstacles
/// the same way and stops when they reach the limit.
pub fn estimated_peak_bytes(scene: &Scene) -> f64 {
    (scene.max_disks() + wall_disk_count(scene) as f64) * peak_bytes_per_particle(scene)
}

/// Upper bound of the peak memory per particle of `scene` (bytes):
/// [`PEAK_BYTES_PER_DISK`], or [`PEAK_BYTES_PER_GRAIN`] with a `[shape]`.
pub fn peak_bytes_per_particle(scene: &Scene) -> f64 {
    if scene.shape.is_some() {
        PEAK_BYTES_PER_GRAIN
    } else {
        PEAK_BYTES_PER_DISK
    }
}

/// Wall disks the scene's walls are made of (0 with exact walls, or when
/// they would be too many to make: `pack` refuses that scene).
pub(crate) fn wall_disk_count(scene: &Scene) -> usize {
    match scene.walls {
        crate::geometry::WallMode::Disks => scene
            .domain
            .boundary_disk_count(scene.wall_disk())
            .unwrap_or(0),
        crate::geometry::WallMode::Exact | crate::geometry::WallMode::Periodic => 0,
    }
}

/// The most disks (wall disks aside) a run of `scene` may place under its
/// limits, with the error to stop with when one more would pass it; `None`
/// without limits. The memory limit counts the wall disks too, as
/// [`estimated_peak_bytes`] does.
pub(crate) fn disk_ceiling(scene: &Scene) -> Option<(u64, PackError)> {
    let by_particles = scene
        .limits
        .max_particles
        .map(|limit| (limit, PackError::ParticleLimit { limit }));
    let by_memory = scene.limits.max_memory_bytes.map(|bytes| {
        let obstacles = (bytes / PEAK_BYTES_PER_DISK)
            .floor()
            .clamp(0.0, u64::MAX as f64) as u64;
        let disks = obstacles.saturating_sub(wall_disk_count(scene) as u64);
        (
            disks,
            PackError::MemoryLimit {
                limit_mb: bytes / BYTES_PER_MB,
                disks,
            },
        )
    });
    match (by_particles, by_memory) {
        (Some(a), Some(b)) => Some(if a.0 <= b.0 { a } else { b }),
        (a, b) => a.or(b),
    }
}

/// Bytes in one MB, as `limits.max_memory_mb` counts them (2^20).
pub const BYTES_PER_MB: f64 = 1_048_576.0;

/// Pack a scene with its packer's method (the advancing front by default),
/// sizes drawn from its grading with its seed.
///
/// # Returns
/// A packing with every disk inside the domain and, but for relaxation
/// (which reports what overlap it leaves), zero overlaps; or an error when
/// no disk of the grading fits in the domain.
///
/// # Example
/// ```
/// use gapack::{Domain, Grading, Scene, pack};
/// let domain = Domain::rectangle(10.0, 10.0).unwrap();
/// let scene = Scene::new(domain, Grading::constant(1.0).unwrap()).with_seed(1);
/// let packing = pack(&scene).unwrap();
/// assert!(packing.disks.len() > 80);
/// ```
pub fn pack(scene: &Scene) -> Result<Packing, PackError> {
    pack_observed(scene, &mut |_| {}, &Cancel::new())
}

/// [`pack`], telling `progress` how many sizes have been drawn so far, every
/// `PROGRESS_STEP` sizes (advancing front only: the comparison generators
/// do not report), and stopping within a few thousand sizes once `cancel`
/// is raised. About [`Scene::estimated_disks`] sizes are drawn in all.
///
/// # Errors
/// As [`pack`], and [`PackError::Cancelled`] when stopped.
pub fn pack_observed(
    scene: &Scene,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    if let Some(shape) = &scene.shape {
        let mut sizes = Xoshiro256PlusPlus::seed_from_u64(scene.seed);
        let mut genes = std::iter::repeat_with(|| sizes.r#gen::<f64>());
        return grains::pack(scene, shape, &mut genes, progress, cancel);
    }
    match scene.packer.method {
        Method::AdvancingFront => advancing_front::pack(scene, progress, cancel),
        Method::Rsa => near_origin(scene, |s| pack_rsa(s, cancel)),
        Method::Deposition => near_origin(scene, |s| pack_deposition(s, cancel)),
        Method::Relaxation => near_origin(scene, |s| pack_relaxation(s, cancel)),
        Method::Densify => near_origin(scene, |s| pack_densify(s, cancel)),
    }
}

/// [`pack_observed`] with the densify method, without its search for a
/// looser target that packs when the target is not reached: for a caller
/// that steps through targets itself (the optimise job's densify route).
///
/// # Errors
/// As [`pack_densify`], `advice` always `None`.
pub(crate) fn pack_densify_stepped(scene: &Scene, cancel: &Cancel) -> Result<Packing, PackError> {
    near_origin(scene, |s| densify::pack_densify_unadvised(s, cancel))
}

/// Pack `scene` with `generate` next to the origin and move the packing back.
///
/// # Behavior
/// The domain is moved by [`Domain::local_offset`](crate::Domain::local_offset)
/// (exactly; nothing moves for a domain near the origin), so that rounding
/// in the generator scales with the domain's extent, not with how far from
/// the origin it lies. The centres are moved back with one rounding each,
/// and the packing holds the scene's own domain.
fn near_origin(
    scene: &Scene,
    generate: impl FnOnce(&Scene) -> Result<Packing, PackError>,
) -> Result<Packing, PackError> {
    let v = scene.domain.local_offset();
    if v.x == 0.0 && v.y == 0.0 {
        return generate(scene);
    }
    let local = scene.clone().with_domain(scene.domain.translated(v));
    let mut packing = generate(&local)?;
    for d in packing.disks.iter_mut().chain(packing.boundary.iter_mut()) {
        d.c -= v;
    }
    packing.domain = scene.domain.clone();
    Ok(packing)
}
