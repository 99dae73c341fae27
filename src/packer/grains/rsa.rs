//! Random sequential addition of particles that are not disks, the
//! comparison baseline: each size (and its grain, drawn as the front draws
//! it) tries random centres over the domain's bounds and keeps the first
//! that is clear; the first size that finds none stops the run, as for
//! disks.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::Radii;
use super::contact::Newcomer;
use super::front::Front;
use crate::cancel::Cancel;
use crate::geometry::Point;
use crate::packer::advancing_front::{PROGRESS_STEP, size_count};
use crate::packer::index::MxQuadtree;
use crate::packer::placed::POSITION_STREAM;
use crate::packer::{PackError, Packing};
use crate::scene::{SHAPE_STREAM, ShapeSpec};
use crate::{Scene, WallMode};

/// Pack `scene` (next to the origin) by random sequential addition, each
/// gene a size's percent passing.
pub(super) fn pack(
    scene: &Scene,
    shape: &ShapeSpec,
    genes: &mut dyn Iterator<Item = f64>,
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    let mut front = Front::<MxQuadtree>::new(scene, shape, cancel)?;
    let mut shapes = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ SHAPE_STREAM);
    let mut spots = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ POSITION_STREAM);
    let drawer = shape.drawer();
    let mut radii = Radii::default();
    let (lo, hi) = scene.domain.bounds();
    let attempts = scene.packer.attempts.max(1);
    let periodic = scene.walls == WallMode::Periodic;
    for i in 0..size_count(&scene.domain, scene.d_min()) {
        if i.is_multiple_of(PROGRESS_STEP) {
            cancel.check()?;
        }
        let Some(u) = genes.next() else {
            break;
        };
        let grain = drawer.draw(scene.grading.sample(u), &mut shapes);
        front.stats.sizes_drawn += 1;
        let (reach, inner) = radii.of(&grain.outline);
        let (sin, cos) = grain.angle.sin_cos();
        let e = if periodic { 0.0 } else { inner };
        let (x0, x1, y0, y1) = (lo.x + e, hi.x - e, lo.y + e, hi.y - e);
        let mut spot = None;
        {
            let new = Newcomer {
                outline: &grain.outline,
                cos,
                sin,
                reach,
                inner,
                slack: 0.0,
                sampled: None,
            };
            for _ in 0..attempts {
                front.stats.front_attempts += 1;
                let p = Point::new(
                    x0 + (x1 - x0).max(0.0) * spots.r#gen::<f64>(),
                    y0 + (y1 - y0).max(0.0) * spots.r#gen::<f64>(),
                );
                if front.clear(&new, p, &[]) {
                    spot = Some(p);
                    break;
                }
                front.look()?;
            }
        }
        match spot {
            Some(p) => {
                let r_eq = grain.outline.equivalent_radius();
                front.place(p, grain, 0, reach, inner, r_eq, cos, sin, None)?;
            }
            None => {
                front.stats.sizes_unplaced += 1;
                break;
            }
        }
    }
    Ok(front.into_packing())
}
