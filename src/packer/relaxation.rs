//! Relaxation (PFC's explosive repulsion, geometric separation): disks
//! placed at random, overlapping, at a set porosity, then pushed apart.
//!
//! # Behavior
//! The number of disks is the domain area × (1 − porosity) / the grading's
//! mean disk area, their sizes the first that `pack` draws. Centres start
//! uniform inside the domain. Each sweep pushes every overlapping pair apart
//! along the line of centres, half the overlap each (a wall disk does not
//! move: the other takes it all), and every disk that crosses a wall back
//! inside along the wall's normal; the displacements of a sweep are applied
//! together. The run stops when the largest overlap (relative to the sum of
//! the radii, or to the radius at a wall) falls below the tolerance, or
//! after the set number of sweeps. What overlap is left stays in the
//! packing: the metrics report it, nothing hides it.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::index::{Grid, SpatialIndex};
use super::placed::{POSITION_STREAM, Placed, check_fits, radii};
use super::{PackError, Packing};
use crate::Scene;
use crate::geometry::{Disk, Point};

/// Pack `scene` by relaxation.
///
/// # Errors
/// [`PackError::DomainTooNarrow`] when no disk of the grading fits;
/// [`PackError::TooManyWallDisks`] when the wall disks would be too many.
pub fn pack_relaxation(scene: &Scene) -> Result<Packing, PackError> {
    check_fits(scene)?;
    let settings = scene.packer.relaxation;
    let domain = &scene.domain;
    let placed = Placed::new(scene);
    let walls: Vec<Disk> = placed.disks.clone();
    let n = (domain.area() * (1.0 - settings.porosity) / scene.mean_disk_area())
        .round()
        .max(1.0) as usize;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ POSITION_STREAM);
    let (lo, hi) = domain.bounds();
    let mut disks: Vec<Disk> = Vec::with_capacity(n);
    for r in radii(scene).take(n) {
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
    let r_max = placed.r_max;
    let mut stats = placed.stats;
    stats.sizes_drawn = disks.len() as u64;
    let margin = Point::new(2.0 * r_max, 2.0 * r_max).coords;
    let mut push = vec![Point::origin().coords; n];
    for _ in 0..settings.iterations {
        stats.front_attempts += 1;
        // Wall disks first, then the moving disks, in one grid per sweep.
        let mut grid = Grid::new(lo - margin, hi + margin, 2.0 * r_max);
        let all: Vec<Disk> = walls.iter().chain(&disks).copied().collect();
        for (id, d) in all.iter().enumerate() {
            grid.insert(id as u32, clamp(d.c, lo - margin, hi + margin));
        }
        push.iter_mut().for_each(|v| *v = Point::origin().coords);
        let mut worst = 0.0f64;
        let nw = walls.len();
        for (i, d) in disks.iter().enumerate() {
            let id = nw + i;
            let half = d.r + r_max;
            let (qlo, qhi) = (
                Point::new(d.c.x - half, d.c.y - half),
                Point::new(d.c.x + half, d.c.y + half),
            );
            grid.visit_box(qlo, qhi, |j| {
                let j = j as usize;
                if j == id {
                    return;
                }
                let o = all[j];
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
                let share = if j < nw { 1.0 } else { 0.5 };
                push[i] -= dir * overlap * share;
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
        }
    }
    let mut packing = Placed::new(scene).into_packing();
    packing.disks = disks;
    packing.stats = stats;
    Ok(packing)
}

/// The unit direction into the domain at `p`: the signed distance's
/// gradient, by central differences over a step of a millionth of `r`.
fn inward(domain: &crate::geometry::Domain, p: Point, r: f64) -> nalgebra::Vector2<f64> {
    let h = (r * 1e-6).max(1e-12);
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
