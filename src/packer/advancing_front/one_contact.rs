//! One-contact placement: a share of the sizes touch their front only, at
//! a random angle on the free arcs of its halo, a gap clear of every other
//! disk; and, before a loose pack stops, the hole it may still hold, filled
//! at two contacts.

use std::ops::ControlFlow;

use nalgebra::Vector2;
use rand::Rng;

use super::candidates::{WALL_MARGIN_REL, wall_candidates};
use super::periodic::{any_image, image, visit_images};
use super::{Front, PackError};
use crate::geometry::Point;
use crate::geometry::predicates::{FEASIBLE_REL, clear_disk_walls, intersect_circle_circle};
use crate::packer::arcs::{Arcs, Measure};
use crate::packer::index::SpatialIndex;

/// Random angles tried on the free arcs before a one-contact placement falls back to two contacts.
const ONE_CONTACT_TRIES: usize = 16;

/// Stream offset so one-contact angles never share random numbers with the sizes.
pub(super) const ANGLE_STREAM: u64 = 0x9E37_79B9_7F4A_7C15;

/// Disks around a hole tried for a two-contact placement, at most.
const HOLE_FRONTS: usize = 32;

impl<I: SpatialIndex> Front<'_, I> {
    /// Whether the next size touches its front only: always, never, or drawn
    /// with probability `one_contact_share` (the draw only when it is strictly
    /// between 0 and 1, so dense and loose runs keep their random streams).
    pub(super) fn one_contact(&mut self) -> bool {
        let share = self.scene.packer.one_contact_share;
        share >= 1.0 || (share > 0.0 && self.angles.r#gen::<f64>() < share)
    }

    /// One-contact placement: a random point of the free arcs of the front's
    /// halo, `gap` radii clear of every other disk and inside the domain.
    pub(super) fn free_angle(&mut self, f: u32, r: f64, gap: f64) -> Option<Point> {
        let free = self.free_arcs(f, r, gap, Measure::Radians);
        if free <= 0.0 {
            return None;
        }
        let front = self.obs[f as usize];
        let rf = front.r + r;
        let reach = r * (1.0 + gap);
        let clear = 1.0 - FEASIBLE_REL;
        for _ in 0..ONE_CONTACT_TRIES {
            let theta = self.arcs.point(self.angles.r#gen::<f64>() * free);
            let v = Point::new(rf * theta.cos(), rf * theta.sin());
            let p = Point::new(front.c.x + v.x, front.c.y + v.y);
            if (self.periodic || clear_disk_walls(&self.scene.domain, p, r))
                && self.near.iter().all(|n| {
                    let s = (n.disk.r + reach) * clear;
                    (v - n.rel).norm_squared() >= s * s
                })
                && !self.run_blocks(f, p, v, r, gap)
            {
                return Some(p);
            }
        }
        None
    }

    /// The free arcs of front `f`'s halo for a one-contact disk of radius `r`
    /// with `gap` into `self.arcs`, in `measure`; returns their total measure.
    ///
    /// A neighbour, or a wall disk, blocks the arc where its halo, widened
    /// by the gap, covers the front's ([`block_halo`]). Walls block the arcs
    /// where the disk would stick out: the halo's crossings with the walls
    /// offset by `r` split it into arcs that are wholly inside or wholly
    /// outside, told apart by their midpoints.
    pub(super) fn free_arcs(&mut self, f: u32, r: f64, gap: f64, measure: Measure) -> f64 {
        let front = self.obs[f as usize];
        let rf = front.r + r;
        let reach = r * (1.0 + gap);
        self.arcs.clear(measure);
        self.stats.work += self.near.len() as u64;
        // Wall disks, if any, are neighbours; exact walls are blocked here.
        let near_wall = !self.walls.is_empty()
            && self.scene.domain.signed_distance(front.c)
                <= (front.r + 2.0 * r) * (1.0 + WALL_MARGIN_REL);
        if near_wall && !self.block_walls(front.c, rf, r) {
            return 0.0;
        }
        for n in &self.near {
            if !block_halo(&mut self.arcs, rf, n.rel, n.disk.r + reach) {
                return 0.0;
            }
        }
        // The wall disks of the runs, every one whose halo may meet the front's.
        let half = rf + self.r_max + reach;
        let (lo, hi) = (
            Point::new(front.c.x - half, front.c.y - half),
            Point::new(front.c.x + half, front.c.y + half),
        );
        let (obs, arcs) = (&self.obs, &mut self.arcs);
        let mut visits = 0u64;
        let covered = self.runs.any_in_box(obs, lo, hi, |id| {
            visits += 1;
            let o = obs[id as usize];
            let rel = Point::new(o.c.x - front.c.x, o.c.y - front.c.y);
            id != f && !block_halo(arcs, rf, rel, o.r + reach)
        });
        self.stats.work += visits;
        if covered { 0.0 } else { self.arcs.free() }
    }

    /// Push onto `self.arcs` the arcs of the circle (`c`, `rf`) where a disk of
    /// radius `r` centred on it would stick out of the domain; `false` if the
    /// whole circle does.
    fn block_walls(&mut self, c: Point, rf: f64, r: f64) -> bool {
        let measure = self.arcs.measure();
        let at = |a: f64| {
            let (x, y) = measure.direction(a);
            let len = (x * x + y * y).sqrt();
            Point::new(c.x + rf * x / len, c.y + rf * y / len)
        };
        let outside = |p: Point| self.scene.domain.signed_distance(p) < r;
        self.spots.clear();
        self.stats.work += self.walls.len() as u64;
        for wall in &self.walls {
            wall_candidates(wall, c, rf, r, &mut self.spots);
        }
        // Near a reflex corner the disk's centre keeps `r` from the corner
        // itself: the halo's crossings with that circle bound arcs too, or
        // one midpoint beside the corner would block a whole arc that is
        // free on either side of it (found by the stability sweep: a loose
        // pack in an L 1.5 d_max wide stopped at its first disk).
        for &v in self.scene.domain.reflex_vertices() {
            if let Some(pts) = intersect_circle_circle(c, rf, v, r) {
                self.spots.extend_from_slice(&pts);
            }
        }
        if self.spots.is_empty() {
            return !outside(at(0.0));
        }
        let mut cuts: Vec<f64> = self
            .spots
            .iter()
            .map(|p| measure.of(p.x - c.x, p.y - c.y))
            .collect();
        cuts.sort_unstable_by(f64::total_cmp);
        let full = measure.full();
        for (i, &lo) in cuts.iter().enumerate() {
            let hi = cuts.get(i + 1).copied().unwrap_or(cuts[0] + full);
            if hi > lo && outside(at(0.5 * (lo + hi))) {
                self.arcs.block_range(lo, hi);
            }
        }
        true
    }

    /// Before a loose pack stops on a size that fits nowhere: if the domain
    /// still holds a hole, place the size at two contacts around the disk
    /// nearest the hole that takes it, and go on.
    ///
    /// # Behavior
    /// The one-contact gap grows with the new disk, so a chain of small disks
    /// can shut a large size out of every free arc while the domain is still
    /// open; stopping then (`max_deferred` sizes already waiting; 0 by the
    /// GA's loosest rules) left holes of up to 10 `d_max` (found by the
    /// property test). A pack with no hole stops as before: placing every
    /// such size at two contacts instead made loose packs denser (100 mm
    /// square, 0.5–2.5 mm, share 1, gap 0.6: porosity 0.518 to 0.470) and
    /// slower. Dense packs (no one-contact share) skip this: their fronts
    /// failed at two contacts already.
    ///
    /// A disk whose front failed for the smallest size at one contact has
    /// left the stack for good (a constant grading parks nothing), so the
    /// disks are taken from the index, not from the parked fronts; and a
    /// pack whose fronts have all left looks for a hole too before it stops
    /// (found by the property test: in the 21° corner of a 25 × 4 mm
    /// trapezoid lined with wall disks, 0.6 mm disks with a gap of 0.59
    /// radii found no free arc, and the pack stopped at one disk).
    ///
    /// # Performance
    /// One scan of the domain on a grid of spacing `d_max / 2` per stop (one
    /// small query per point, ending at the first hole), and at most
    /// [`HOLE_FRONTS`] attempts.
    pub(super) fn fill_hole(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
        if self.scene.packer.one_contact_share <= 0.0 {
            return Ok(false);
        }
        let hole = self.hole();
        self.account()?;
        let Some(hole) = hole else {
            return Ok(false);
        };
        // The disks around the hole, nearest first: parked fronts, and fronts
        // already dropped (a front that failed for the smallest size at one
        // contact leaves for good, yet may take it at two).
        let half = 2.0 * self.scene.d_max() + self.r_max;
        let (lo, hi) = (
            Point::new(hole.x - half, hole.y - half),
            Point::new(hole.x + half, hole.y + half),
        );
        let mut near: Vec<(f64, u32)> = Vec::new();
        let obs = &self.obs;
        let _ = visit_images(&self.index, &self.scene.domain, lo, hi, |id, v| {
            near.push(((image(obs[id as usize].c, v) - hole).norm_squared(), id));
            ControlFlow::Continue(())
        });
        let _ = self.runs.try_visit_box(obs, lo, hi, |id| {
            near.push(((obs[id as usize].c - hole).norm_squared(), id));
            ControlFlow::Continue(())
        });
        self.stats.work += near.len() as u64;
        near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // A disk met as two images (a periodic cell) is tried once, by its nearest.
        let mut tried: Vec<u32> = Vec::with_capacity(HOLE_FRONTS);
        for (_, f) in near {
            if tried.len() == HOLE_FRONTS {
                break;
            }
            if tried.contains(&f) {
                continue;
            }
            tried.push(f);
            self.stats.front_attempts += 1;
            let placed = self.attempt(f, r, false);
            self.account()?;
            if let Some((p, _)) = placed {
                self.stats.fallbacks += 1;
                self.place(p, r, tag)?;
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// A point of the domain in an empty circle of diameter 2·`d_max` (clear
    /// of every disk and wall), if there is one.
    ///
    /// Every such circle holds a point of a grid of spacing `d_max / 2` no
    /// farther than `d_max / (2√2)` from its centre, so that point is at
    /// least `d_max·(1 − 1/(2√2))` clear.
    fn hole(&self) -> Option<Point> {
        let d_max = self.scene.d_max();
        let step = d_max / 2.0;
        let clear = d_max - step * std::f64::consts::FRAC_1_SQRT_2;
        let reach = clear + self.r_max;
        let (lo, hi) = self.scene.domain.bounds();
        let (nx, ny) = (
            ((hi.x - lo.x) / step).ceil() as usize,
            ((hi.y - lo.y) / step).ceil() as usize,
        );
        let (obs, tests) = (&self.obs, &self.tests);
        let walls = self.walls.len() as u64;
        (0..=ny)
            .flat_map(|iy| (0..=nx).map(move |ix| (ix, iy)))
            .map(|(ix, iy)| Point::new(lo.x + ix as f64 * step, lo.y + iy as f64 * step))
            .find(|&p| {
                tests.set(tests.get() + 1 + walls);
                let (lo, hi) = (
                    Point::new(p.x - reach, p.y - reach),
                    Point::new(p.x + reach, p.y + reach),
                );
                let blocks = |id: u32, v: Vector2<f64>| {
                    tests.set(tests.get() + 1);
                    let o = obs[id as usize];
                    (image(o.c, v) - p).norm() - o.r < clear
                };
                (self.periodic || self.scene.domain.signed_distance(p) >= clear)
                    && !any_image(&self.index, &self.scene.domain, lo, hi, blocks)
                    && !self
                        .runs
                        .any_in_box(obs, lo, hi, |id| blocks(id, Vector2::zeros()))
            })
    }
}

/// Block on `arcs` the arc of the halo of radius `rf` (centred at the
/// origin) that the halo of radius `rj` centred at `rel` covers: the arc
/// between the two crossings, found without trigonometry (the cosine of
/// its half-angle from the triangle of the centres, then a rotation).
/// `false` when it covers the whole halo.
fn block_halo(arcs: &mut Arcs, rf: f64, rel: Point, rj: f64) -> bool {
    let (dx, dy) = (rel.x, rel.y);
    let dist = (dx * dx + dy * dy).sqrt();
    if dist == 0.0 {
        return false;
    }
    let cos = (rf * rf + dist * dist - rj * rj) / (2.0 * rf * dist);
    if cos >= 1.0 {
        return true; // the halos do not meet
    }
    if cos <= -1.0 {
        return false; // the front's halo lies inside the neighbour's
    }
    let sin = (1.0 - cos * cos).sqrt();
    let (ux, uy) = (dx / dist, dy / dist);
    let from = (ux * cos + uy * sin, uy * cos - ux * sin);
    let to = (ux * cos - uy * sin, uy * cos + ux * sin);
    arcs.block(from, to);
    true
}
