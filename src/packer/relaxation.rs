//! Relaxation (PFC's explosive repulsion, geometric separation): disks
//! placed at random, overlapping, at a set porosity, then pushed apart.
//!
//! # Behavior
//! The number of disks is the area inside the walls (the domain's, less a
//! strip of half a wall disk along the boundary with `walls = "disks"`) ×
//! (1 − porosity) / the grading's mean disk area, their sizes the first that `pack` draws. Centres start
//! uniform inside the domain. Each sweep pushes every overlapping pair apart
//! along the line of centres, half the overlap each (a wall disk does not
//! move: the other takes it all), and every disk that crosses a wall back
//! inside along the wall's normal; the displacements of a sweep are applied
//! together. The run stops when the largest overlap (relative to the sum of
//! the radii, or to the radius at a wall) falls below the tolerance, or
//! after the set number of sweeps. A periodic cell has no wall: its disks
//! are pushed off every image of the others, and each centre is wrapped
//! back into the cell after each sweep. What overlap is left stays in the
//! packing: the metrics report it, nothing hides it.

use std::cell::Cell;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::index::{Grid, SpatialIndex};
use super::placed::{POSITION_STREAM, Placed, check_fits, radii, unless_stopped};
use super::{PackError, Packing};
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::{Disk, Point};

/// Pack `scene` by relaxation.
///
/// # Errors
/// [`PackError::DomainTooNarrow`] when no disk of the grading fits;
/// [`PackError::TooManyWallDisks`] when the wall disks would be too many.
pub fn pack_relaxation(scene: &Scene, cancel: &Cancel) -> Result<Packing, PackError> {
    let stopped = Cell::new(None);
    check_fits(scene)?;
    let settings = scene.packer.relaxation;
    let domain = &scene.domain;
    // Only the wall disks: they do not move.
    let placed = Placed::new(scene);
    let walls = &placed.disks;
    // Wall disks, centred on the boundary, take a strip half their diameter
    // wide from the area left to the particles: counting it keeps large wall
    // disks from crowding the domain with disks that cannot separate.
    let free = (domain.area() - domain.perimeter() * placed.wall_r).max(0.0);
    let n = (free * (1.0 - settings.porosity) / scene.mean_disk_area())
        .round()
        .max(1.0) as usize;
    if let Some((max, error)) = super::disk_ceiling(scene)
        && n as u64 > max
    {
        return Err(error);
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ POSITION_STREAM);
    let (lo, hi) = domain.bounds();
    let periodic = domain.is_periodic();
    let mut disks: Vec<Disk> = Vec::with_capacity(n);
    for r in radii(scene, cancel, &stopped).take(n) {
        let c = loop {
            let p = Point::new(
                lo.x + (hi.x - lo.x) * rng.r#gen::<f64>(),
                lo.y + (hi.y - lo.y) * rng.r#gen::<f64>(),
            );
            if domain.signed_distance(p) >= 0.0 {
                break p;
            }
        };
        disks.push(Disk { c, r });
    }
    let mut stats = placed.stats;
    stats.sizes_drawn = disks.len() as u64;
    // Wall disks do not move: `placed`'s grid holds them for the whole run,
    // queried as far as their own radius reaches. The moving disks get a
    // grid per sweep sized by their own largest radius, so wall disks larger
    // than the particles do not widen every query (a 5 mm wall disk made
    // each sweep of 1 mm disks visit 25 times the neighbours).
    let r_moving = disks.iter().fold(0.0f64, |m, d| m.max(d.r));
    let margin = Point::new(2.0 * r_moving, 2.0 * r_moving).coords;
    let mut push = vec![Point::origin().coords; n];
    for _ in 0..settings.iterations {
        cancel.check()?;
        stats.front_attempts += 1;
        let mut grid = Grid::new(lo - margin, hi + margin, 2.0 * r_moving);
        for (id, d) in disks.iter().enumerate() {
            grid.insert(id as u32, clamp(d.c, lo - margin, hi + margin));
        }
        push.iter_mut().for_each(|v| *v = Point::origin().coords);
        let mut worst = 0.0f64;
        let nw = walls.len();
        for (i, d) in disks.iter().enumerate() {
            // Push disk i off `o` (index `j` among walls then disks), taking
            // the share `share` of the overlap.
            let mut repel = |j: usize, o: Disk, share: f64| {
                #[cfg(test)]
                tests::VISITS.with(|v| v.set(v.get() + 1));
                let delta = o.c - d.c;
                let dist = delta.norm();
                let overlap = d.r + o.r - dist;
                if overlap <= 0.0 {
                    return;
                }
                worst = worst.max(overlap / (d.r + o.r));
                let dir = if dist > 0.0 {
                    delta / dist
                } else {
                    // Coincident centres: apart along a direction set by the pair.
                    let a = (i * 7919 + j) as f64;
                    nalgebra::Vector2::new(a.cos(), a.sin())
                };
                push[i] -= dir * overlap * share;
            };
            let near = |reach: f64| {
                let half = d.r + reach;
                (
                    Point::new(d.c.x - half, d.c.y - half),
                    Point::new(d.c.x + half, d.c.y + half),
                )
            };
            if !walls.is_empty() {
                let (qlo, qhi) = near(placed.wall_r);
                placed
                    .grid
                    .visit_box(qlo, qhi, |j| repel(j as usize, walls[j as usize], 1.0));
            }
            let (qlo, qhi) = near(r_moving);
            if periodic {
                // Every image of every other disk (and of itself) in reach.
                for v in domain.image_shifts(qlo, qhi) {
                    grid.visit_box(qlo - v, qhi - v, |k| {
                        let k = k as usize;
                        if k != i || v != nalgebra::Vector2::zeros() {
                            let o = disks[k];
                            repel(nw + k, Disk { c: o.c + v, r: o.r }, 0.5);
                        }
                    });
                }
                continue;
            }
            grid.visit_box(qlo, qhi, |k| {
                let k = k as usize;
                if k != i {
                    repel(nw + k, disks[k], 0.5);
                }
            });
            let inside = domain.signed_distance(d.c);
            if inside < d.r {
                worst = worst.max((d.r - inside) / d.r);
                push[i] += inward(domain, d.c, d.r) * (d.r - inside);
            }
        }
        if worst <= settings.tolerance {
            break;
        }
        for (d, v) in disks.iter_mut().zip(&push) {
            d.c += v;
            if periodic {
                d.c = domain.wrap(d.c);
            }
        }
    }
    let mut packing = placed.into_packing();
    packing.disks = disks;
    packing.stats = stats;
    unless_stopped(packing, &stopped)
}

/// The unit direction into the domain at `p`: the signed distance's
/// gradient, by central differences over a step of a millionth of `r`, or
/// of 10⁻¹² of `p`'s coordinates if that is larger (a step far below their
/// spacing would difference rounding).
fn inward(domain: &crate::geometry::Domain, p: Point, r: f64) -> nalgebra::Vector2<f64> {
    let h = (r * 1e-6).max(p.x.abs().max(p.y.abs()) * 1e-12);
    let dx = domain.signed_distance(Point::new(p.x + h, p.y))
        - domain.signed_distance(Point::new(p.x - h, p.y));
    let dy = domain.signed_distance(Point::new(p.x, p.y + h))
        - domain.signed_distance(Point::new(p.x, p.y - h));
    let g = nalgebra::Vector2::new(dx, dy);
    let n = g.norm();
    if n > 0.0 {
        g / n
    } else {
        (domain.centroid() - p).normalize()
    }
}

/// `p` clamped into the box `lo`–`hi` (a disk pushed far out still goes in a bucket).
fn clamp(p: Point, lo: Point, hi: Point) -> Point {
    Point::new(p.x.clamp(lo.x, hi.x), p.y.clamp(lo.y, hi.y))
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use super::*;
    use crate::geometry::{Domain, WallMode};
    use crate::grading::Grading;
    use crate::packer::{Method, PackerSettings, Relaxation};

    thread_local! {
        /// Pairs (disk, neighbour candidate) the sweeps of this thread visited.
        pub(super) static VISITS: Cell<u64> = const { Cell::new(0) };
    }

    /// 1 mm disks in a 40 mm square walled with `wall` mm wall disks,
    /// relaxed for 10 sweeps.
    fn walled(wall: f64) -> Scene {
        Scene::new(
            Domain::rectangle(40.0, 40.0).unwrap(),
            Grading::constant(1.0).unwrap(),
        )
        .with_wall_disks(wall)
        .with_packer(PackerSettings {
            method: Method::Relaxation,
            relaxation: Relaxation {
                iterations: 10,
                ..Relaxation::default()
            },
            ..PackerSettings::default()
        })
        .with_seed(3)
    }

    #[test]
    fn wall_disks_larger_than_the_particles_do_not_widen_every_query() {
        // 10 mm wall disks for 1 mm disks. One grid sized by the wall disks
        // made every disk visit over 400 candidates in each sweep (seconds
        // for 2000 sweeps); now a disk visits its neighbours' cells and the
        // handful of wall disks.
        VISITS.with(|v| v.set(0));
        let packing = pack_relaxation(&walled(10.0), &Cancel::new()).unwrap();
        let sweeps = packing.stats.front_attempts;
        let per_disk = VISITS.with(Cell::get) as f64 / (sweeps as f64 * packing.disks.len() as f64);
        assert!(
            sweeps > 0 && per_disk < 40.0,
            "{per_disk} candidates per disk and sweep"
        );
    }

    #[test]
    fn default_tolerance_leaves_a_loose_packing_the_write_check_passes() {
        // With the old default (1e-4) the sweeps stopped at overlaps of
        // ~1e-4 of the radii sum, and every relaxation packing was refused
        // by the check made before writing (no overlap beyond 1e-9).
        let mut scene = walled(1.0);
        scene.walls = WallMode::Exact;
        scene.wall_disk_diameter = None;
        scene.grading = Grading::uniform(1.0, 1.5, crate::grading::Basis::Number).unwrap();
        scene.packer.relaxation = Relaxation {
            porosity: 0.5,
            ..Relaxation::default()
        };
        let packing = pack_relaxation(&scene, &Cancel::new()).unwrap();
        let sweeps = packing.stats.front_attempts;
        assert!(
            sweeps < Relaxation::default().iterations as u64,
            "did not converge in {sweeps} sweeps"
        );
        let c = crate::check::check(&packing.disks, &packing.domain, None);
        assert!(c.valid(), "{c:?}");
        assert!(packing.disks.len() > 400, "{}", packing.disks.len());
    }

    #[test]
    fn wall_disks_take_their_strip_from_the_disk_count() {
        // Wall disks centred on the boundary cover a strip half their
        // diameter wide. Counting the whole domain crammed 1.7 × the disks
        // that fit into a 40 mm square with 10 mm wall disks, and a 20 mm
        // wide slot with 50 mm wall disks (found by fuzzing) relaxed 1500
        // disks that could never separate for seconds.
        let thin = pack_relaxation(&walled(0.1), &Cancel::new())
            .unwrap()
            .disks
            .len() as f64;
        let thick = pack_relaxation(&walled(10.0), &Cancel::new())
            .unwrap()
            .disks
            .len() as f64;
        // Free areas: 1600 − 160 × 0.05 = 1592 and 1600 − 160 × 5 = 800 mm².
        assert!(
            (thick / thin - 800.0 / 1592.0).abs() < 0.01,
            "{thick} / {thin}"
        );
        // No room at all inside the wall disks: refused, not relaxed.
        assert!(matches!(
            pack_relaxation(&walled(39.5), &Cancel::new()),
            Err(PackError::DomainTooNarrow { .. })
        ));
    }
}
