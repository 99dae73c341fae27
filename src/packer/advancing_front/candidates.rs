//! The two-contact attempt at a front: the neighbours its halo meets, the
//! candidates (its halo's intersections with theirs, with the wall disks'
//! in reach and with the walls offset by the radius), their feasibility,
//! and the lowest clear one, which the new disk takes. The run's hot path
//! (`feasible` above all).

use std::ops::ControlFlow;

use nalgebra::Vector2;

use super::Front;
use super::closure::{NO_WITNESS, WITNESSES, witness_of};
use super::periodic::{image, visit_images};
use crate::geometry::predicates::{
    FEASIBLE_REL, chord_of_offset, clear_disk_walls, intersect_circle_circle, intersect_circle_line,
};
use crate::geometry::{Disk, Point, Wall};
use crate::packer::index::SpatialIndex;

/// Relative margin on the reach of a front's halo when deciding that no wall is near.
pub(super) const WALL_MARGIN_REL: f64 = 1e-9;

/// A neighbour of the current front: its centre relative to the front's
/// (`rel`), and its squared clearance for the new radius (`clear_disk_disk`
/// in one comparison).
#[derive(Clone, Copy)]
pub(super) struct Near {
    pub(super) disk: Disk,
    pub(super) rel: Point,
    pub(super) clear2: f64,
}

/// A candidate centre: the point, and its offset from the front's centre.
///
/// Feasibility against the neighbours is decided on the offset (against
/// their own offsets), so a candidate's distance to a neighbour carries a
/// rounding of the radii, not of the coordinates. Decided on the points,
/// candidates tangent to a neighbour were judged inside it once the
/// coordinates' rounding reached [`FEASIBLE_REL`] (about 10⁵ radii from the
/// origin): a pocket of a domain 10⁶ diameters from the origin packed 5 to
/// 10 % fewer disks than the same pocket near it (`tests/integration/scales.rs`). The
/// point, computed as before, is where the disk goes (so packings near the
/// origin are unchanged, bit for bit).
#[derive(Clone, Copy)]
pub(super) struct Cand {
    pub(super) at: Point,
    pub(super) off: Point,
    /// Index in `near` of the neighbour whose halo it lies on (`u32::MAX`: a wall's).
    pub(super) src: u32,
}

impl<I: SpatialIndex> Front<'_, I> {
    /// Try to place a disk of radius `r` around front `f`: the position and
    /// how many feasible candidates there were (capped at 2).
    pub(super) fn attempt(&mut self, f: u32, r: f64, one_contact: bool) -> Option<(Point, usize)> {
        let gap = if one_contact {
            self.scene.packer.gap
        } else {
            0.0
        };
        self.gather_neighbours(f, r, gap);
        if one_contact {
            // Its spots are not looked for: the front is attempted again in full.
            self.witness[f as usize] = NO_WITNESS;
            return self.free_angle(f, r, gap).map(|p| (p, 2));
        }
        // Every candidate lies on the front's halo; when the front is deeper
        // inside than the halo plus a radius reaches, no wall is in play.
        let front = self.obs[f as usize];
        let reach = (front.r + 2.0 * r) * (1.0 + WALL_MARGIN_REL);
        let near_wall = self.near_wall(front.c, reach);
        self.near_edge = self.near_edge(front.c, reach);
        self.tangent_candidates(f, r, near_wall);
        // The lowest feasible candidate, and whether the front keeps room:
        // thesis rules, a second feasible candidate; robust rules, a second
        // one still clear of the disk about to be placed (so a front with no
        // room left leaves now instead of costing one more failed attempt).
        let clear = (2.0 * r * (1.0 - FEASIBLE_REL)).powi(2);
        let (best, room) = {
            self.spots.clear();
            // Lowest first; in a periodic cell, lowest key first (see
            // `Front::key`).
            let mut best: Option<(Point, f64)> = None;
            self.outside.clear();
            for i in 0..self.cands.len() {
                let cand = self.cands[i];
                let refusals = self.refused.get();
                if !self.feasible(f, &cand, r, near_wall) {
                    if self.near_edge && self.refused.get() != refusals {
                        self.outside.push(cand.at);
                    }
                    continue;
                }
                let p = cand.at;
                self.spots.push(p);
                let key = self.key(&cand, r);
                if best.is_none_or(|(b, bk)| first_of(key, p, bk, b).is_lt()) {
                    best = Some((p, key));
                }
            }
            if !self.outside.is_empty() {
                self.hand_off(f, r, best.map(|(p, _)| p));
            }
            let (best, _) = best?;
            let room = self.spots.len() >= 2;
            if self.robust() {
                self.spots.retain(|q| (q - best).norm_squared() >= clear);
                if self.spots.len() > WITNESSES {
                    // The lowest ones, whatever order the index gave them in.
                    let mut spots = std::mem::take(&mut self.spots);
                    spots.sort_unstable_by(|a, b| first_of(self.rank(*a), *a, self.rank(*b), *b));
                    self.spots = spots;
                }
            }
            (best, room)
        };
        let room = if self.robust() {
            let c = front.c;
            let mut kept = NO_WITNESS;
            for (slot, q) in kept.iter_mut().zip(&self.spots) {
                *slot = witness_of(c, *q);
            }
            let room = kept[0] != [0, 0];
            self.witness[f as usize] = if r <= self.r_retire { kept } else { NO_WITNESS };
            room
        } else {
            room
        };
        Some((best, if room { 2 } else { 1 }))
    }

    /// Neighbours of front `f` whose halo, widened by `gap` radii, meets the
    /// front's halo, into `self.near`; the runs of wall disks within the
    /// same reach into `self.near_runs` (their disks are not neighbours:
    /// `tangent_candidates` and `feasible` take the few that matter).
    pub(super) fn gather_neighbours(&mut self, f: u32, r: f64, gap: f64) {
        let front = self.obs[f as usize];
        let reach = front.r + (2.0 + gap) * r; // plus the neighbour's own radius
        // The farthest centre the filter below keeps, and a hundredth of
        // the radius against rounding.
        let half = (reach + self.r_max) * (1.0 + FEASIBLE_REL) + 0.01 * r;
        let (lo, hi) = (
            Point::new(front.c.x - half, front.c.y - half),
            Point::new(front.c.x + half, front.c.y + half),
        );
        self.near.clear();
        if !self.runs.is_empty() {
            self.runs
                .near(front.c, reach + self.r_max, &mut self.near_runs);
            self.stats.work += self.runs.len() as u64;
        }
        let (obs, near) = (&self.obs, &mut self.near);
        let clear = 1.0 - FEASIBLE_REL;
        let mut visits = 0u64;
        // In a periodic cell a neighbour is any image of a disk (the front's
        // own images too); its `disk` is then the image.
        let _ = visit_images(&self.index, &self.scene.domain, lo, hi, |id, v| {
            visits += 1;
            let mut o = obs[id as usize];
            o.c = image(o.c, v);
            let s = (reach + o.r) * (1.0 + FEASIBLE_REL);
            let (dx, dy) = (o.c.x - front.c.x, o.c.y - front.c.y);
            if (id != f || v != Vector2::zeros()) && dx * dx + dy * dy < s * s {
                let c = (r + o.r) * clear;
                near.push(Near {
                    disk: o,
                    rel: Point::new(dx, dy),
                    clear2: c * c,
                });
            }
            ControlFlow::Continue(())
        });
        self.stats.work += visits;
    }

    /// Halo intersections around front `f` (with the walls only when
    /// `near_wall`), into `self.cands`.
    pub(super) fn tangent_candidates(&mut self, f: u32, r: f64, near_wall: bool) {
        let front = self.obs[f as usize];
        let rf = front.r + r;
        self.cands.clear();
        for (src, n) in self.near.iter().enumerate() {
            if let Some(chord) = chord_of_offset(n.rel.x, n.rel.y, rf, n.disk.r + r) {
                let (at, off) = (chord.points(front.c), chord.offsets());
                let src = src as u32;
                self.cands.push(Cand {
                    at: at[0],
                    off: off[0],
                    src,
                });
                self.cands.push(Cand {
                    at: at[1],
                    off: off[1],
                    src,
                });
            }
        }
        self.stats.work += self.near.len() as u64;
        // Wall disks of the runs in reach: those whose zone the halo crosses.
        let (runs, obs, cands) = (&self.runs, &self.obs, &mut self.cands);
        let mut sources = 0u64;
        for &run in &self.near_runs {
            runs.sources(run, front.c, rf, r, |id| {
                sources += 1;
                let o = obs[id as usize];
                let (dx, dy) = (o.c.x - front.c.x, o.c.y - front.c.y);
                if id != f
                    && let Some(chord) = chord_of_offset(dx, dy, rf, o.r + r)
                {
                    let (at, off) = (chord.points(front.c), chord.offsets());
                    for k in 0..2 {
                        cands.push(Cand {
                            at: at[k],
                            off: off[k],
                            src: u32::MAX,
                        });
                    }
                }
            });
        }
        self.stats.work += sources;
        if near_wall {
            self.stats.work += self.walls.len() as u64;
            self.wall_points.clear();
            for wall in &self.walls {
                wall_candidates(wall, front.c, rf, r, &mut self.wall_points);
            }
            self.cands.extend(self.wall_points.iter().map(|&at| Cand {
                at,
                off: Point::new(at.x - front.c.x, at.y - front.c.y),
                src: u32::MAX,
            }));
        }
    }

    /// Whether a wall disk of the runs in `near_runs` (front `f` aside)
    /// blocks a disk of radius `r` at `p` (offset `off` from the front's
    /// centre), its halo widened by `gap` radii: the same test as a
    /// neighbour's, on each run's disks nearest `p`.
    pub(super) fn run_blocks(&self, f: u32, p: Point, off: Point, r: f64, gap: f64) -> bool {
        let front = self.obs[f as usize].c;
        let (obs, clear) = (&self.obs, 1.0 - FEASIBLE_REL);
        let mut tests = 0u64;
        let reach = r * (1.0 + gap) + self.runs.radius();
        let blocked = self.near_runs.iter().any(|&run| {
            self.runs.nearest(run, p, reach, |id| {
                tests += 1;
                let o = obs[id as usize];
                let (rx, ry) = (o.c.x - front.x, o.c.y - front.y);
                let (dx, dy) = (off.x - rx, off.y - ry);
                let c = (r * (1.0 + gap) + o.r) * clear;
                id != f && dx * dx + dy * dy < c * c
            })
        });
        self.tests.set(self.tests.get() + tests);
        blocked
    }

    /// Whether a candidate is inside the domain (checked only when
    /// `near_wall`), clear of every neighbour (by its offset) and of the
    /// wall disks of the runs in reach.
    ///
    /// # Performance
    /// Every neighbour is tested before a candidate is found clear, but a
    /// blocked one stops at its first blocker, so the likely blockers go
    /// first: the one that blocked the last candidate (candidates come in
    /// runs that one neighbour blocks), then the neighbours next to the
    /// candidate's own in `near`, outwards both ways (the index gives them
    /// bucket by bucket, so neighbours near in the list are near in space). A
    /// large size at a front among fine disks has thousands of neighbours
    /// and twice as many candidates, nearly all blocked: scanned from the
    /// start, they cost their product (a 5 mm square of 0.02–4 mm sizes by
    /// 3D mass: 6·10⁹ tests); now a few tests each.
    pub(super) fn feasible(&self, f: u32, cand: &Cand, r: f64, near_wall: bool) -> bool {
        let clear_of = |n: &Near| {
            let (dx, dy) = (cand.off.x - n.rel.x, cand.off.y - n.rel.y);
            dx * dx + dy * dy >= n.clear2
        };
        if near_wall {
            self.tests.set(self.tests.get() + self.walls.len() as u64);
            if !clear_disk_walls(&self.scene.domain, cand.at, r) {
                return false;
            }
        }
        if !self.near_runs.is_empty() && self.run_blocks(f, cand.at, cand.off, r, 0.0) {
            return false;
        }
        let last = self.last_blocker.get();
        if self.near.get(last).is_some_and(|n| !clear_of(n)) {
            return false;
        }
        let len = self.near.len();
        let start = if (cand.src as usize) < len {
            cand.src as usize
        } else {
            last.min(len.saturating_sub(1))
        };
        // Offsets 0, −1, +1, −2, +2, … from `start`, each index once.
        let mut tested = 0u64;
        let blocker = (0..len)
            .map(|step| {
                let k = step.div_ceil(2);
                let i = if step % 2 == 1 {
                    start + len - k
                } else {
                    start + k
                };
                // `start < len` and `k ≤ len / 2`: one wrap at most.
                if i >= len { i - len } else { i }
            })
            .find(|&i| {
                tested += 1;
                !clear_of(&self.near[i])
            });
        self.tests.set(self.tests.get() + 1 + tested);
        match blocker {
            Some(i) => {
                self.last_blocker.set(i);
                false
            }
            // A part's region last: most candidates are blocked before.
            None => {
                let inside =
                    !self.near_edge || self.region.is_none_or(|region| region.contains(cand.at));
                if !inside {
                    self.refused.set(self.refused.get() + 1);
                }
                inside
            }
        }
    }

    /// The spots of a disk of radius `r` at front `f` clear of every
    /// obstacle and inside the part's region, each with the gap it leaves
    /// to its third nearest disk (the two it touches aside: how deep it
    /// nests), into `out`. Judged as [`Front::attempt`] judges them; its
    /// witnesses are not updated.
    pub(super) fn nested_spots(&mut self, f: u32, r: f64, out: &mut Vec<(Point, f64)>) {
        self.gather_neighbours(f, r, 0.0);
        let front = self.obs[f as usize];
        let reach = (front.r + 2.0 * r) * (1.0 + WALL_MARGIN_REL);
        let near_wall = self.near_wall(front.c, reach);
        self.near_edge = self.near_edge(front.c, reach);
        self.tangent_candidates(f, r, near_wall);
        for i in 0..self.cands.len() {
            let cand = self.cands[i];
            if !self.feasible(f, &cand, r, near_wall) {
                continue;
            }
            // The three least gaps, to the front and the neighbours (a wall
            // is not counted: a row starting at one nests in disks).
            let mut least = [f64::INFINITY; 3];
            let mut keep = |g: f64| {
                if g < least[2] {
                    least[2] = g;
                    least.sort_unstable_by(f64::total_cmp);
                }
            };
            keep(cand.off.x.hypot(cand.off.y) - front.r - r);
            for n in &self.near {
                keep((cand.off.x - n.rel.x).hypot(cand.off.y - n.rel.y) - n.disk.r - r);
            }
            self.stats.work += self.near.len() as u64;
            out.push((cand.at, least[2]));
        }
    }

    /// Whether a disk centred within `reach` of `c` may meet a wall: never
    /// in a periodic cell.
    pub(super) fn near_wall(&self, c: Point, reach: f64) -> bool {
        !self.periodic && self.scene.domain.signed_distance(c) <= reach
    }

    /// Whether a disk centred within `reach` of `c` may lie outside the
    /// part's region: never in one piece.
    pub(super) fn near_edge(&self, c: Point, reach: f64) -> bool {
        self.region
            .is_some_and(|region| !region.inside_by(c, reach))
    }
}

/// Order candidates by key ([`Front::key`]) or rank ([`Front::rank`]), then
/// lowest first, then leftmost.
#[inline]
fn first_of(rank_a: f64, a: Point, rank_b: f64, b: Point) -> std::cmp::Ordering {
    rank_a.total_cmp(&rank_b).then_with(|| lowest_first(a, b))
}

/// Order points lowest first, then leftmost (deposition under gravity).
pub(super) fn lowest_first(a: Point, b: Point) -> std::cmp::Ordering {
    a.y.total_cmp(&b.y).then(a.x.total_cmp(&b.x))
}

/// Centres of disks of radius `r` tangent to `wall` on the domain side, on the circle (`c`, `rf`).
pub(super) fn wall_candidates(wall: &Wall, c: Point, rf: f64, r: f64, out: &mut Vec<Point>) {
    match *wall {
        Wall::Segment { a, b } => {
            let len = (b - a).norm();
            let (ux, uy) = ((b.x - a.x) / len, (b.y - a.y) / len);
            let q = Point::new(a.x - uy * r, a.y + ux * r); // offset inward (left) by r
            if let Some(ts) = intersect_circle_line(c, rf, q, ux, uy) {
                let slack = len * 1e-12;
                for t in ts {
                    if t >= -slack && t <= len + slack {
                        out.push(Point::new(q.x + ux * t, q.y + uy * t));
                    }
                }
            }
        }
        Wall::Circle { center, radius } => {
            if radius > r
                && let Some(pts) = intersect_circle_circle(c, rf, center, radius - r)
            {
                out.extend_from_slice(&pts);
            }
        }
    }
}
