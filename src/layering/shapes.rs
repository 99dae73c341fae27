//! The particle shape statistics of each material of a packing of grains.

use crate::Scene;
use crate::metrics::{ShapeStats, shape_stats};
use crate::packer::Packing;
use crate::scene::ShapeSpec;

/// The shape a particle of material `m` of `scene` was drawn with: in
/// size-graded mode the second material's own shape when it has one,
/// otherwise the scene's (`None`: disks).
pub fn material_shape(scene: &Scene, m: usize) -> Option<&ShapeSpec> {
    let second = scene
        .gradient
        .as_ref()
        .and_then(|g| g.second_shape.as_ref());
    match (m, second) {
        (1, Some(shape)) => Some(shape),
        _ => scene.shape.as_ref(),
    }
}

/// The shape statistics ([`shape_stats`]) of the grains of each of
/// `materials` materials of `packing`, against the shape each was drawn
/// with; empty for a packing of disks or one without materials, `None`
/// for a material without particles.
pub fn shape_stats_by_material(
    packing: &Packing,
    scene: &Scene,
    materials: usize,
) -> Vec<Option<ShapeStats>> {
    if packing.grains.is_empty() || packing.materials.len() != packing.grains.len() {
        return Vec::new();
    }
    (0..materials)
        .map(|m| {
            let own: Vec<_> = packing
                .grains
                .iter()
                .zip(&packing.materials)
                .filter(|(_, t)| usize::from(**t) == m)
                .map(|(g, _)| g.clone())
                .collect();
            shape_stats(&own, material_shape(scene, m))
        })
        .collect()
}
