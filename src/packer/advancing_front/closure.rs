//! Closed fronts (robust rules, see "Closed fronts" in [`super`]): the free
//! spots a front remembers (its witnesses) and the bound on the largest
//! radius it can still take, which let a closed front leave the stack
//! without a full attempt; the parking of fronts that failed for a size
//! until a smaller one comes; and the witnesses a part hands on to the
//! parts packed after it.

use nalgebra::Vector2;

use super::candidates::{Near, WALL_MARGIN_REL};
use super::periodic::{any_image, image};
use super::{Front, Opening};
use crate::geometry::Point;
use crate::geometry::predicates::{FEASIBLE_REL, WITNESS_REL, max_radius_ray_disk};
use crate::packer::arcs::Measure;
use crate::packer::index::SpatialIndex;

/// Fronts that fail for a radius within this factor of the smallest are retired, not parked:
/// a gap that refuses such a disk has no room for any size of the grading worth a retry.
pub(super) const RETIRE_RATIO: f64 = 1.1;

/// Precision of the bound a failing front is parked with: the largest radius
/// it can still take is known to within this factor.
const BOUND_RATIO: f64 = 1.02;

/// Relative margin on the distance at which a neighbour is left out of a
/// smaller radius's attempt (`Front::near_for`): far above the rounding of
/// candidates (relative 1e-10 of the halo's radius at the coarsest
/// resolution a config allows) and the tangency slack of halo intersections.
const REACH_REL: f64 = 1e-6;

/// Relative margin by which a packed disk's halo must hold a wall disk's
/// zone to cover it (`Front::covered`): far above the rounding of the
/// candidates an attempt would test.
const COVER_REL: f64 = 1e-9;

/// Free spots a front remembers, at most.
pub(super) const WITNESSES: usize = 3;

/// A front's remembered free spots: unit directions from its centre in
/// units of 1/[`WITNESS_SCALE`], unused slots `[0, 0]`. Coarse on purpose (an
/// angle within 3e-5 rad): they only decide whether to make an exact attempt,
/// and [`WITNESS_REL`] is far wider than their rounding.
pub(super) type Witnesses = [[i16; 2]; WITNESSES];

/// Scale of the witness directions' components.
const WITNESS_SCALE: f64 = i16::MAX as f64;

/// Witnesses of a front with none: a fresh front, one whose last full attempt
/// failed, or one whose last spots were found for a disk larger than `r_retire`
/// (they say nothing of the narrower gaps smaller disks fit).
pub(super) const NO_WITNESS: Witnesses = [[0; 2]; WITNESSES];

/// The witness of a free spot at `q` of a front centred at `c`: the
/// direction from `c`, scaled by [`WITNESS_SCALE`].
pub(super) fn witness_of(c: Point, q: Point) -> [i16; 2] {
    let (dx, dy) = (q.x - c.x, q.y - c.y);
    let k = WITNESS_SCALE / (dx * dx + dy * dy).sqrt();
    [(dx * k).round() as i16, (dy * k).round() as i16]
}

/// The opening of a disk with candidates refused for lying outside its
/// part's region: its free spots inside and outside, when they fit the
/// witnesses' slots (else [`Opening::FRESH`]); its bound was measured
/// inside the region only, so it is not handed on.
pub(super) fn merged(inside: Witnesses, outside: Witnesses) -> Opening {
    let spots = inside.into_iter().chain(outside).filter(|&w| w != [0, 0]);
    all_witnesses(spots).map_or(Opening::FRESH, |witness| Opening {
        witness,
        bound: f32::INFINITY,
    })
}

/// Witnesses of every spot of `spots`, or `None` when they are more than
/// [`WITNESSES`].
fn all_witnesses(mut spots: impl Iterator<Item = [i16; 2]>) -> Option<Witnesses> {
    let mut witness = NO_WITNESS;
    for slot in &mut witness {
        if let Some(w) = spots.next() {
            *slot = w;
        }
    }
    spots.next().is_none().then_some(witness)
}

impl<I: SpatialIndex> Front<'_, I> {
    /// Whether front `f`'s witnesses prove it closed: none of its remembered
    /// spots still takes the smallest disk, and they were found for a disk
    /// near the smallest (spots found for a larger disk say nothing of the
    /// narrower gaps that smaller disks fit). Robust rules only.
    ///
    /// # Performance
    /// One query of half side `r_min + r_max` per spot, stopping at the first
    /// obstacle that blocks it, and at the first spot that is still free:
    /// every obstacle that blocks the smallest disk touching `f` in the spot's
    /// direction is in that box. Walls are not checked: the spot was inside
    /// for the size that found it.
    pub(super) fn witnesses_closed(&mut self, f: u32) -> bool {
        let witnesses = self.witness[f as usize];
        if witnesses[0] == [0, 0] {
            return false;
        }
        self.stats.witness_checks += 1;
        let front = self.obs[f as usize];
        let r = self.r_min;
        witnesses
            .into_iter()
            .take_while(|&w| w != [0, 0])
            .all(|[wx, wy]| {
                let (wx, wy) = (f64::from(wx), f64::from(wy));
                let len = (wx * wx + wy * wy).sqrt();
                let u = [wx / len, wy / len];
                let t = Point::new(front.c.x + u[0] * front.r, front.c.y + u[1] * front.r);
                let (px, py) = (t.x + u[0] * r, t.y + u[1] * r);
                let half = r + self.r_max;
                let (lo, hi) = (
                    Point::new(px - half, py - half),
                    Point::new(px + half, py + half),
                );
                let (obs, blocked) = (&self.obs, r * (1.0 - WITNESS_REL));
                let tests = &self.tests;
                let blocks = |id: u32, v: Vector2<f64>| {
                    tests.set(tests.get() + 1);
                    let o = obs[id as usize];
                    (id != f || v != Vector2::zeros())
                        && max_radius_ray_disk(t, u, image(o.c, v), o.r) < blocked
                };
                // The disk that took the spot usually has its centre in the spot's own bucket.
                let p = Point::new(px, py);
                let domain = &self.scene.domain;
                any_image(&self.index, domain, p, p, blocks)
                    || any_image(&self.index, domain, lo, hi, blocks)
                    || self
                        .runs
                        .any_in_box(obs, lo, hi, |id| blocks(id, Vector2::zeros()))
            })
    }

    /// Whether front `f` is a wall disk that an attempt would leave the
    /// stack without placing, and without parking it: its spots are covered
    /// for the smallest radius ([`Front::covered`]), so no size fits there
    /// (a disk that fits touching it contains the smaller disk touching it
    /// at the same point) and, by robust rules, `room_left` finds no room.
    /// Dense packs only: a one-contact attempt draws random angles even
    /// where it fails, and the draws must stay the same.
    ///
    /// # Performance
    /// Nearly every wall disk leaves the stack this way, without an attempt
    /// (500,000 attempts of the 560,000 the 25 m well made): a disk packed
    /// against the wall covers 20 to 30 of them, and is met first.
    pub(super) fn wall_front_closed(&mut self, f: u32) -> bool {
        f < self.first_packed as u32
            && self.scene.packer.one_contact_share <= 0.0
            && self.covered(f, self.r_min)
    }

    /// Whether wall disk `f` (on a straight edge, not at its ends) is
    /// covered for radius `rho`: each of its two zones, where a disk of
    /// radius `rho` touching it clears its neighbours on the wall
    /// ([`WallRuns::zones`]), lies outside the domain or inside the halo of
    /// one packed disk. Then no disk of radius `rho` or more touches it.
    ///
    /// # Performance
    /// The packed disk that covered the last wall disk of the same edge is
    /// tried first; else one query around the zone, stopping at the first
    /// that covers it.
    ///
    /// [`WallRuns::zones`]: crate::packer::wall_runs::WallRuns::zones
    fn covered(&mut self, f: u32, rho: f64) -> bool {
        let q = self.obs[f as usize].c;
        let (Some(zones), Some(run)) = (self.runs.zones(f, q, rho), self.runs.run_of(f)) else {
            return false;
        };
        let obs = &self.obs;
        let covers = |id: u32, zone: &[Point; 3]| {
            let o = obs[id as usize];
            let s = (rho + o.r) * (1.0 - FEASIBLE_REL) * (1.0 - COVER_REL);
            zone.iter().all(|p| (p - o.c).norm_squared() < s * s)
        };
        let mut tests = 3u64;
        let closed = zones.iter().all(|zone| {
            // Outside: every point of the zone within `reach` of its tip,
            // which lies deeper outside than that (the distance is 1-Lipschitz).
            let tip = zone[2];
            let reach = (zone[0] - tip).norm().max((zone[1] - tip).norm());
            if self.scene.domain.signed_distance(tip) + reach < 0.5 * rho {
                return true;
            }
            let last = self.coverer[run];
            if last != u32::MAX && covers(last, zone) {
                return true;
            }
            let half = rho + self.r_max;
            let (lo, hi) = (
                Point::new(tip.x - half, tip.y - half),
                Point::new(tip.x + half, tip.y + half),
            );
            let mut found = None;
            self.index.any_in_box(lo, hi, |id| {
                tests += 1;
                let hit = covers(id, zone);
                if hit {
                    found = Some(id);
                }
                hit
            });
            if let Some(id) = found {
                self.coverer[run] = id;
            }
            found.is_some()
        });
        self.stats.work += tests;
        closed
    }

    /// After front `f` failed for radius `r` (at one contact or two): an upper
    /// bound, below `r`, of the radii it can still take in the placements the
    /// run may make, or `None` when it cannot take even the smallest.
    ///
    /// # Behavior
    /// Room shrinks with the radius: a disk that fits touching a front
    /// contains the smaller disk touching it at the same point (and so does
    /// its gap). So the largest radius that fits is found by bisection between
    /// `r_min` and `r`, to within [`BOUND_RATIO`]. A front whose halo meets no
    /// other is taken to fit any size.
    ///
    /// # Performance
    /// No query but at most one: the neighbours gathered for `r` cover every
    /// smaller radius (gathered again with the gap if `r` was tried at two
    /// contacts in a run that also makes one-contact placements).
    pub(super) fn room_left(&mut self, f: u32, r: f64, one_contact: bool) -> Option<f64> {
        let (share, gap) = (self.scene.packer.one_contact_share, self.scene.packer.gap);
        if share > 0.0 && gap > 0.0 && !one_contact {
            self.gather_neighbours(f, r, gap);
        }
        // A front too far from the walls for the largest radius is too far
        // for every smaller one the bisection tries.
        let front = self.obs[f as usize];
        let reach = (front.r + 2.0 * r) * (1.0 + WALL_MARGIN_REL);
        let near_wall = self.near_wall(front.c, reach);
        self.near_edge = self.near_edge(front.c, reach);
        // The neighbours gathered for `r`, each with the least radius whose
        // halo reaches it (see `near_for`).
        let widen = if share > 0.0 { gap } else { 0.0 };
        let mut all = std::mem::take(&mut self.near_all);
        all.clear();
        all.extend(self.near.iter().map(|n| {
            let d = (n.rel.x * n.rel.x + n.rel.y * n.rel.y).sqrt();
            let rho = (d / (1.0 + REACH_REL) - n.disk.r - front.r) / (2.0 + widen);
            (rho, *n)
        }));
        let (mut lo, mut hi) = (self.r_min, r);
        let fits = |this: &mut Self, rho: f64| {
            this.near_for(&all, rho);
            (share < 1.0 && this.fits_two_contacts(f, rho, near_wall))
                || (share > 0.0 && this.free_arcs(f, rho, gap, Measure::Pseudo) > 0.0)
        };
        let bound = if fits(self, lo) {
            while hi > lo * BOUND_RATIO {
                let mid = (lo * hi).sqrt();
                if fits(self, mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            Some(hi)
        } else {
            None
        };
        self.near_all = all;
        bound
    }

    /// Into `self.near`, in their order, the neighbours of `all` that a
    /// disk of radius `rho` at the front can touch or be blocked by: those
    /// whose least radius is below `rho`.
    ///
    /// # Behavior
    /// A candidate lies on the front's halo (radius `r_f + rho`, to within
    /// rounding), and a neighbour of radius `r_o` at distance `d` makes a
    /// candidate or blocks one only if `d < r_f + 2·rho + r_o` (plus the gap
    /// of a one-contact disk): the others change no answer, and leaving them
    /// out (with a margin of [`REACH_REL`], far above any rounding and any
    /// tangency slack) spares a bisection over small radii the thousands
    /// of neighbours a large size gathers among fine disks.
    fn near_for(&mut self, all: &[(f64, Near)], rho: f64) {
        self.stats.work += all.len() as u64;
        self.near.clear();
        self.near.extend(
            all.iter()
                .filter(|(least, _)| *least < rho)
                .map(|(_, n)| *n),
        );
    }

    /// Whether a disk of radius `r` has a feasible two-contact spot at front
    /// `f` with the neighbours in `self.near` (or no candidate to judge by);
    /// the walls are tested only when `near_wall`.
    fn fits_two_contacts(&mut self, f: u32, r: f64, near_wall: bool) -> bool {
        let clear = 1.0 - FEASIBLE_REL;
        for n in &mut self.near {
            let c = (r + n.disk.r) * clear;
            n.clear2 = c * c;
        }
        self.tangent_candidates(f, r, near_wall);
        self.cands.is_empty() || self.cands.iter().any(|c| self.feasible(f, c, r, near_wall))
    }

    /// A front that failed for `r`: parked for smaller sizes (robust rules) or dropped.
    pub(super) fn park(&mut self, f: u32, r: f64) {
        if self.robust() && r > self.r_retire {
            self.parked.push((r, f));
        }
    }

    /// Move the parked fronts that failed only for sizes larger than `r` back on the stack.
    pub(super) fn wake(&mut self, r: f64) -> bool {
        let before = self.fronts.len();
        self.stats.work += self.parked.len() as u64;
        let fronts = &mut self.fronts;
        self.parked.retain(|&(failed, f)| {
            let wakes = failed > r;
            if wakes {
                fronts.push(f);
            }
            !wakes
        });
        self.fronts.len() > before
    }

    /// Remember front `f` as open for later parts if its last attempt had
    /// a candidate refused only by the part's region.
    pub(super) fn note_refused(&mut self, f: u32) {
        if self.refused.take() > 0 && self.refused_fronts.last() != Some(&f) {
            self.refused_fronts.push(f);
        }
    }

    /// Remember the spots of front `f`'s attempt for radius `r` refused for
    /// lying outside the part's region, as directions from its centre,
    /// less those the disk about to go `best` covers: the later parts it
    /// touches look there first (see [`Opening`]). Not all known when they
    /// are more than [`WITNESSES`], or found for a disk larger than
    /// `r_retire` (see [`NO_WITNESS`]).
    pub(super) fn hand_off(&mut self, f: u32, r: f64, best: Option<Point>) {
        let clear = (2.0 * r * (1.0 - FEASIBLE_REL)).powi(2);
        let c = self.obs[f as usize].c;
        let spots = self
            .outside
            .iter()
            .filter(|q| best.is_none_or(|b| (*q - b).norm_squared() >= clear))
            .map(|q| witness_of(c, *q));
        let known = all_witnesses(spots).filter(|_| r <= self.r_retire);
        self.handoff.insert(f, known);
    }
}
