//! Random sequential addition (PFC's trial generation, YADE's random cloud):
//! each size tries random positions and keeps the first that is clear.
//!
//! # Behavior
//! Sizes come in the order `pack` draws them (same seed, same sizes).
//! Each tries up to `attempts` centres drawn uniformly over the domain's
//! bounds; one inside the domain and clear of every disk is kept. In a
//! periodic cell the centres are drawn over the whole cell, and a spot
//! must be clear of every disk's images too. The first
//! size that finds no place stops the run: at that effort the domain is
//! full (PFC stops the same way when its tries run out). No overlaps; the
//! packing stays loose (jamming near 0.45 porosity for equal disks), which
//! is what users of trial generation meet before they compact.

use std::cell::Cell;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::placed::{POSITION_STREAM, Placed, check_fits, radii, unless_stopped};
use super::{PackError, Packing};
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::{Disk, Point};

/// Pack `scene` by random sequential addition.
///
/// # Errors
/// [`PackError::DomainTooNarrow`] when no disk of the grading fits;
/// [`PackError::TooManyWallDisks`] when the wall disks would be too many.
pub fn pack_rsa(scene: &Scene, cancel: &Cancel) -> Result<Packing, PackError> {
    let stopped = Cell::new(None);
    check_fits(scene)?;
    let mut placed = Placed::new(scene);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ POSITION_STREAM);
    let (lo, hi) = scene.domain.bounds();
    let attempts = scene.packer.attempts.max(1);
    // A disk may cross a periodic cell's edges: its centre anywhere in the cell.
    let inset = |r: f64| if scene.domain.is_periodic() { 0.0 } else { r };
    for r in radii(scene, cancel, &stopped) {
        placed.stats.sizes_drawn += 1;
        let e = inset(r);
        let (x0, x1, y0, y1) = (lo.x + e, hi.x - e, lo.y + e, hi.y - e);
        let mut spot = None;
        for _ in 0..attempts {
            placed.stats.front_attempts += 1;
            let p = Point::new(
                x0 + (x1 - x0).max(0.0) * rng.r#gen::<f64>(),
                y0 + (y1 - y0).max(0.0) * rng.r#gen::<f64>(),
            );
            if placed.clear(p, r) {
                spot = Some(p);
                break;
            }
        }
        match spot {
            Some(c) => placed.insert(Disk { c, r })?,
            None => {
                placed.stats.sizes_unplaced += 1;
                break;
            }
        }
    }
    unless_stopped(placed.into_packing(), &stopped)
}
