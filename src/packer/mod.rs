//! Packing generators and spatial indexes.

mod advancing_front;
mod arcs;
mod deposition;
pub mod index;
mod packing;
mod placed;
mod relaxation;
mod rsa;
mod sizer;

pub use crate::scene::{
    DEFAULT_ATTEMPTS, Fill, FrontRules, IndexKind, MAX_DEFERRED, MAX_GAP, Method, PackerSettings,
    Relaxation,
};
pub use advancing_front::{pack_genes_watched, size_count};
pub use deposition::pack_deposition;
pub use packing::{PackError, PackStats, Packing};
pub use relaxation::pack_relaxation;
pub use rsa::pack_rsa;

use crate::Scene;
use crate::cancel::Cancel;

/// Upper bound of the packer's peak memory per disk (bytes), checked by `gapack bench`.
pub const PEAK_BYTES_PER_DISK: f64 = 100.0;

/// Estimated peak memory (bytes) to pack `scene`.
///
/// Counts disks as if the domain were filled solid with disks of the
/// grading's mean area (an upper bound), times [`PEAK_BYTES_PER_DISK`].
pub fn estimated_peak_bytes(scene: &Scene) -> f64 {
    scene.max_disks() * PEAK_BYTES_PER_DISK
}

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
/// [`PROGRESS_STEP`] sizes (advancing front only: the comparison generators
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
    match scene.packer.method {
        Method::AdvancingFront => advancing_front::pack(scene, progress, cancel),
        Method::Rsa => near_origin(scene, |s| pack_rsa(s, cancel)),
        Method::Deposition => near_origin(scene, |s| pack_deposition(s, cancel)),
        Method::Relaxation => near_origin(scene, |s| pack_relaxation(s, cancel)),
    }
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
