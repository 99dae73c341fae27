//! What the comparison generators share: the sizes a scene draws, and the
//! disks placed so far (wall disks first) with a grid to query them.

use std::cell::Cell;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::index::{Grid, SpatialIndex};
use super::{Method, PackError, PackStats, Packing, size_count};
use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
use crate::geometry::predicates::{FEASIBLE_REL, clear_disk_walls};
use crate::geometry::{Disk, Domain, Point, WallMode};
use crate::names::ConfigName;

/// Stream offset so positions never share random numbers with the sizes.
pub(super) const POSITION_STREAM: u64 = 0xD1B5_4A32_D192_ED03;

/// Sizes drawn between two looks at the cancel token by the comparison generators.
const CANCEL_STEP: u64 = 64;

/// The radii `pack` would draw for `scene`, in order: the same seeded
/// stream through the grading's inverse CDF, `ceil(area / smallest disk
/// area)` of them. The stream ends early once `cancel` is raised, and
/// `stopped` then says why.
pub(super) fn radii<'a>(
    scene: &'a Scene,
    cancel: &'a Cancel,
    stopped: &'a Cell<Option<Cancelled>>,
) -> impl Iterator<Item = f64> + 'a {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(scene.seed);
    let count = size_count(&scene.domain, scene.d_min());
    (0..count).map_while(move |i| {
        if i.is_multiple_of(CANCEL_STEP)
            && let Err(why) = cancel.check()
        {
            stopped.set(Some(why));
            return None;
        }
        Some(scene.grading.sample(rng.r#gen::<f64>()) / 2.0)
    })
}

/// `packing`, or the reason the sizes stopped early.
pub(super) fn unless_stopped(
    packing: Packing,
    stopped: &Cell<Option<Cancelled>>,
) -> Result<Packing, PackError> {
    match stopped.get() {
        Some(why) => Err(why.into()),
        None => Ok(packing),
    }
}

/// Refuse, for every method, a scene no disk of the grading fits
/// in, and one whose wall disks would be too many to make (packing it
/// without them would leave the walls out unannounced); and a periodic
/// model that is not a periodic cell (walls on it, another shape), or a
/// cell under twice the largest diameter.
pub(super) fn check_fits(scene: &Scene) -> Result<(), PackError> {
    check_periodic(scene)?;
    let (inscribed, d_min) = (scene.inscribed_diameter(), scene.d_min());
    if inscribed < d_min {
        return Err(PackError::DomainTooNarrow { inscribed, d_min });
    }
    let diameter = scene.wall_disk();
    if scene.walls == WallMode::Disks && scene.domain.boundary_disk_count(diameter).is_none() {
        return Err(PackError::TooManyWallDisks {
            diameter,
            max: Domain::MAX_BOUNDARY_DISKS,
        });
    }
    Ok(())
}

/// Whether `method` packs periodic cells: the advancing front, and the
/// comparison generators that need no wall (`rsa`, `relaxation`); any
/// other (deposition drops disks onto a floor) is refused one.
pub(crate) fn packs_periodic(method: Method) -> bool {
    matches!(
        method,
        Method::AdvancingFront | Method::Rsa | Method::Relaxation | Method::Densify
    )
}

/// The periodic model's own refusals (see [`check_fits`]).
fn check_periodic(scene: &Scene) -> Result<(), PackError> {
    let periodic = scene.walls == WallMode::Periodic;
    if periodic != scene.domain.is_periodic() {
        return Err(if periodic {
            PackError::NotPeriodic {
                shape: scene.domain.shape().config_name(),
            }
        } else {
            PackError::PeriodicWalls {
                walls: scene.walls.config_name(),
            }
        });
    }
    if let Some(period) = scene.domain.period() {
        let (side, d_max) = (period.x.min(period.y), scene.d_max());
        if side < 2.0 * d_max {
            return Err(PackError::PeriodicCellTooSmall { side, d_max });
        }
        let method = scene.packer.method;
        if !packs_periodic(method) {
            return Err(PackError::PeriodicMethod {
                method: method.config_name(),
            });
        }
    }
    Ok(())
}

/// Disks placed so far, wall disks first, with a grid over their centres.
pub(super) struct Placed<'a> {
    pub domain: &'a Domain,
    walls: WallMode,
    pub disks: Vec<Disk>,
    first_packed: usize,
    /// Grid over the centres of `disks`, bucketed by `r_max`.
    pub grid: Grid,
    pub r_max: f64,
    /// Radius of the wall disks (0 with exact walls).
    pub wall_r: f64,
    pub stats: PackStats,
    /// The most disks the scene's limits allow, and the error past it.
    ceiling: Option<(u64, PackError)>,
}

impl<'a> Placed<'a> {
    /// Empty but for the wall disks of `walls = "disks"`.
    pub fn new(scene: &'a Scene) -> Self {
        let domain = &scene.domain;
        let disks = match scene.walls {
            WallMode::Disks => domain.boundary_disks(scene.wall_disk()),
            WallMode::Exact | WallMode::Periodic => Vec::new(),
        };
        let wall_r = disks.iter().fold(0.0f64, |m, d| m.max(d.r));
        let r_max = wall_r.max(scene.d_max() / 2.0);
        let (lo, hi) = domain.bounds();
        let margin = Point::new(r_max, r_max).coords;
        let mut grid = Grid::new(lo - margin, hi + margin, 2.0 * r_max);
        for (id, d) in disks.iter().enumerate() {
            grid.insert(id as u32, d.c);
        }
        Placed {
            domain,
            walls: scene.walls,
            first_packed: disks.len(),
            disks,
            grid,
            r_max,
            wall_r,
            stats: PackStats::default(),
            ceiling: super::disk_ceiling(scene),
        }
    }

    /// Whether a disk of radius `r` at `p` is inside the domain and clear
    /// of every disk; in a periodic cell, of every disk's images too (and
    /// no wall).
    pub fn clear(&self, p: Point, r: f64) -> bool {
        let slack = 1.0 - FEASIBLE_REL;
        let half = r + self.r_max;
        let (lo, hi) = (
            Point::new(p.x - half, p.y - half),
            Point::new(p.x + half, p.y + half),
        );
        if self.domain.is_periodic() {
            return !self.domain.image_shifts(lo, hi).any(|v| {
                self.grid.any_in_box(lo - v, hi - v, |id| {
                    let o = self.disks[id as usize];
                    let s = (r + o.r) * slack;
                    (o.c + v - p).norm_squared() < s * s
                })
            });
        }
        if !clear_disk_walls(self.domain, p, r) {
            return false;
        }
        !self.grid.any_in_box(lo, hi, |id| {
            let o = self.disks[id as usize];
            let s = (r + o.r) * slack;
            (o.c - p).norm_squared() < s * s
        })
    }

    /// Every disk whose centre lies in the box `lo`–`hi` (and perhaps a few beyond).
    pub fn visit(&self, lo: Point, hi: Point, mut f: impl FnMut(Disk)) {
        self.grid.visit_box(lo, hi, |id| f(self.disks[id as usize]));
    }

    /// Place a disk.
    ///
    /// # Errors
    /// The scene's particle or memory limit, when this disk would pass it.
    pub fn insert(&mut self, d: Disk) -> Result<(), PackError> {
        if let Some((max, error)) = &self.ceiling
            && (self.disks.len() - self.first_packed) as u64 >= *max
        {
            return Err(error.clone());
        }
        let d = Disk {
            c: self.domain.wrap(d.c),
            r: d.r,
        };
        self.grid.insert(self.disks.len() as u32, d.c);
        self.disks.push(d);
        Ok(())
    }

    /// The packing: the disks placed after the wall disks.
    pub fn into_packing(mut self) -> Packing {
        let boundary: Vec<Disk> = self.disks.drain(..self.first_packed).collect();
        Packing {
            domain: self.domain.clone(),
            walls: self.walls,
            boundary,
            disks: self.disks,
            grains: Vec::new(),
            materials: Vec::new(),
            stats: self.stats,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grading::Grading;
    use crate::packer::{Method, pack};

    #[test]
    fn comparison_generators_refuse_too_many_wall_disks() {
        // 80 mm of boundary in wall disks of 10 nm: 8 million, over the cap.
        // These generators used to pack without any wall disk instead.
        for method in [
            Method::Rsa,
            Method::Deposition,
            Method::Relaxation,
            Method::Densify,
        ] {
            let scene = Scene::new(
                Domain::rectangle(20.0, 20.0).unwrap(),
                Grading::constant(1.0).unwrap(),
            )
            .with_wall_disks(1e-5)
            .with_method(method);
            assert!(
                matches!(pack(&scene), Err(PackError::TooManyWallDisks { .. })),
                "{method:?}"
            );
        }
    }
}
