//! The advancing front for particles that are not disks, under the disk
//! front's rules: a stack of fronts, each new particle placed touching the
//! front on top and one more obstacle (a particle or a wall) at the lowest
//! clear spot, then put on top; a front that fails is parked with the size
//! it failed for and woken by a smaller one; a size that fits at no front
//! is deferred and retried after later placements, and the run stops when
//! `max_deferred` sizes wait and one more fits nowhere.
//!
//! Two-contact placements solve the exact contact with both obstacles
//! (`contact::two_contact`). For superellipses solved on their contact
//! curves, the screen (`screen`) first marks where the front's curve
//! leaves its neighbours' shadows, on polygons, and only those spots are
//! solved, lowest first; other outlines solve every neighbour's crossings
//! lowest bound first. A screened front that took a particle keeps its
//! other spots and leaves without an attempt once particles placed since
//! cover them all ([`Entry`]). One-contact ones (`packer.one_contact_share`)
//! take the crossing of the bounding circles' halos and slide from there
//! towards the two obstacles by bisection until the particle touches one
//! (seed 001's approximate construction). In a periodic cell the first
//! particle sits at the cell's centre, the second slides against it, and
//! the winning candidate is the one nearest the first particle (its
//! nearest image) rather than the lowest.

use std::collections::{BTreeMap, VecDeque};
use std::ops::ControlFlow;

use nalgebra::Vector2;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::contact::{
    COARSE_REL, GAP_REL, Newcomer, Obstacle, Smooth, clear_of, point_segment_distance, slide,
    starts, two_contact, two_contact_smooth,
};
use super::screen::{Candidate, Halo, Polygon, SIDES, Sampled, Tables, candidates};
use super::{Body, PEAK_BYTES_PER_GRAIN, Radii};
use crate::cancel::Cancel;
use crate::geometry::{Disk, Grain, Outline, Point, Wall};
use crate::packer::advancing_front::{PROGRESS_STEP, size_count, work_budget};
use crate::packer::index::{Grid, MxQuadtree, SpatialIndex};
use crate::packer::sizer::Sizer;
use crate::packer::{BYTES_PER_MB, IndexKind, PackError, PackStats, Packing};
use crate::scene::{SHAPE_STREAM, ShapeSpec};
use crate::{Scene, WallMode};

mod seed;
mod witness;

use witness::{ATTEMPT, Entry, NO_SPOT, WITNESS_BAND, WITNESSES};

/// Seed offset of the stream that picks one-contact placements.
const CONTACT_STREAM: u64 = 0x6F6E_655F_636F_6E74;

/// A parked front wakes for a size at most this share of the one it failed
/// for: a front is tried again only for a clearly smaller particle.
const WAKE_RATIO: f64 = 1.0;

/// A front that fails for a size within this factor of the smallest drawn
/// is closed: no particle fits touching it.
const CLOSE_BAND: f64 = 1.05;

/// Retries of one deferred size before it is given up.
const DEFERRED_RETRIES: u32 = 32;

/// Pack `scene` (next to the origin) with the advancing front.
pub(super) fn pack(
    scene: &Scene,
    shape: &ShapeSpec,
    genes: &mut dyn Iterator<Item = f64>,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    match scene.packer.index {
        IndexKind::MxQuadtree => {
            Front::<MxQuadtree>::new(scene, shape, cancel)?.run(genes, progress)
        }
        IndexKind::Grid => Front::<Grid>::new(scene, shape, cancel)?.run(genes, progress),
    }
}

/// The generator's state.
pub(super) struct Front<'a, I> {
    scene: &'a Scene,
    shape: &'a ShapeSpec,
    cancel: &'a Cancel,
    bodies: Vec<Body>,
    grains: Vec<Grain>,
    disks: Vec<Disk>,
    /// Turns genes into sizes and, in size-graded mode, materials (the
    /// disk front's rule).
    sizer: Sizer<'a>,
    /// Material of each particle placed (size-graded mode only).
    tags: Vec<u16>,
    /// Per particle, what the neighbour search and the screen read.
    halos: Vec<Halo>,
    index: I,
    walls: Vec<Obstacle>,
    periodic: bool,
    /// Largest reach placed so far.
    reach_max: f64,
    /// Fronts to attempt, newest last, each with the spots it remembers.
    stack: Vec<Entry>,
    /// Length of a witness offset's unit step: the longest offset, twice
    /// the largest reach a particle of the scene can have, over `i16::MAX`.
    unit: f64,
    /// Parked fronts by the equivalent radius they failed for.
    parked: BTreeMap<(u64, u32), ()>,
    /// Per particle, the smallest equivalent radius it failed for as a
    /// front (infinite: none yet).
    failed_for: Vec<f64>,
    /// Smallest equivalent radius drawn so far.
    r_small: f64,
    /// Smallest inner radius drawn so far.
    inner_small: f64,
    radii: Radii,
    pub(super) stats: PackStats,
    budget: u64,
    next_look: u64,
    ceiling: Option<(u64, PackError)>,
    contact_rng: Xoshiro256PlusPlus,
    tables: Tables,
    /// Scratch of the attempts: obstacles, and the screen's polygons and
    /// candidates.
    obstacles: Vec<Obstacle>,
    polys: Vec<Polygon>,
    cands: Vec<Candidate>,
    ranked: Vec<((f64, f64), Candidate)>,
    /// The spots the last screened attempt left besides the one it chose
    /// (an entry of its front).
    witnesses: Option<Entry>,
    spots: Vec<((f64, f64), Point)>,
}

impl<'a, I: SpatialIndex> Front<'a, I> {
    pub(super) fn new(
        scene: &'a Scene,
        shape: &'a ShapeSpec,
        cancel: &'a Cancel,
    ) -> Result<Self, PackError> {
        let (lo, hi) = scene.domain.bounds();
        // The widest reach any material's shape can draw.
        let reach_ratio = scene
            .shapes()
            .map(ShapeSpec::reach_ratio)
            .fold(shape.reach_ratio(), f64::max);
        let reach_spec = 0.5 * scene.d_max() * reach_ratio;
        let periodic = scene.walls == WallMode::Periodic;
        if let Some(period) = scene.domain.period() {
            let side = period.x.min(period.y);
            if side < 4.0 * reach_spec {
                return Err(PackError::PeriodicCellTooSmall {
                    side,
                    d_max: 2.0 * reach_spec,
                });
            }
        }
        let walls = scene
            .domain
            .walls()
            .iter()
            .map(|w| match *w {
                Wall::Segment { a, b } => Obstacle::Segment(a, b),
                Wall::Circle { center, radius } => Obstacle::Circle(center, radius),
            })
            .collect();
        let ceiling = ceiling(scene);
        Ok(Front {
            scene,
            shape,
            cancel,
            bodies: Vec::new(),
            grains: Vec::new(),
            disks: Vec::new(),
            sizer: Sizer::new(scene),
            tags: Vec::new(),
            halos: Vec::new(),
            index: I::new(lo, hi, I::BUCKET_DIAMETERS * 2.0 * reach_spec),
            walls: if periodic { Vec::new() } else { walls },
            periodic,
            reach_max: 0.0,
            stack: Vec::new(),
            unit: 2.0 * reach_spec / f64::from(i16::MAX),
            parked: BTreeMap::new(),
            failed_for: Vec::new(),
            r_small: f64::INFINITY,
            inner_small: f64::INFINITY,
            radii: Radii::default(),
            stats: PackStats::default(),
            budget: work_budget(scene),
            next_look: WORK_STEP,
            ceiling,
            contact_rng: Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ CONTACT_STREAM),
            tables: Tables::default(),
            obstacles: Vec::new(),
            polys: Vec::new(),
            cands: Vec::new(),
            ranked: Vec::new(),
            witnesses: None,
            spots: Vec::new(),
        })
    }

    /// Draw the sizes (each gene a percent passing) and place them. In
    /// size-graded mode each size's curve is chosen as the disk front
    /// chooses it (at the front on top), and its grain is drawn with the
    /// shape of that material.
    fn run(
        mut self,
        genes: &mut dyn Iterator<Item = f64>,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Packing, PackError> {
        let scene = self.scene;
        let mut shapes = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ SHAPE_STREAM);
        let first = self.shape.drawer();
        let second = scene
            .gradient
            .as_ref()
            .and_then(|g| g.second_shape.as_ref())
            .map(ShapeSpec::drawer);
        let count = size_count(&scene.domain, scene.d_min());
        let mut deferred: VecDeque<(Grain, u16, u32)> = VecDeque::new();
        let max_deferred = scene.packer.max_deferred;
        // After a placement the oldest waiting size is retried (and the
        // next after it while they fit); a retry that fails waits again,
        // and a new size is drawn (the disk front's order).
        let mut retry = false;
        let mut drawn = 0;
        loop {
            let (grain, tag, tries) = match (retry, deferred.pop_front()) {
                (true, Some(entry)) => entry,
                (_, entry) => {
                    if let Some(entry) = entry {
                        deferred.push_front(entry);
                    }
                    if drawn == count {
                        break;
                    }
                    if drawn.is_multiple_of(PROGRESS_STEP) {
                        progress(drawn);
                        self.cancel.check()?;
                    }
                    let Some(u) = genes.next() else {
                        break;
                    };
                    drawn += 1;
                    self.stats.sizes_drawn += 1;
                    let (d, tag) = self.sizer.size(u, self.growth_point());
                    let drawer = match (tag, &second) {
                        (1, Some(second)) => second,
                        _ => &first,
                    };
                    (drawer.draw(d, &mut shapes), tag, 0)
                }
            };
            if self.try_place(grain.clone(), tag)? {
                retry = !deferred.is_empty();
                continue;
            }
            retry = false;
            if tries == 0 {
                self.stats.sizes_deferred += 1;
            }
            if tries + 1 >= DEFERRED_RETRIES {
                self.stats.sizes_unplaced += 1;
            } else if deferred.len() >= max_deferred {
                // One more size fits nowhere with the most waiting: full.
                self.stats.sizes_unplaced += 1;
                break;
            } else {
                deferred.push_back((grain, tag, tries + 1));
            }
        }
        self.stats.sizes_unplaced += deferred.len() as u64;
        Ok(self.into_packing())
    }

    /// The packing placed so far.
    pub(super) fn into_packing(self) -> Packing {
        Packing {
            grains: self.grains,
            materials: self.tags,
            stats: self.stats,
            ..Packing::of_disks(self.scene.domain.clone(), self.disks)
        }
    }

    /// Where the next particle is expected: the centre of the front on
    /// top, else of the last particle placed, else the domain's lower
    /// corner (the disk front's growth point).
    fn growth_point(&self) -> Point {
        self.stack
            .last()
            .and_then(|e| self.bodies.get(e.front as usize))
            .or_else(|| self.bodies.last())
            .map_or_else(|| self.scene.domain.bounds().0, |b| b.c)
    }

    /// Place `grain` of material `tag` at some front (or as a seed);
    /// `false` if it fits nowhere.
    fn try_place(&mut self, grain: Grain, tag: u16) -> Result<bool, PackError> {
        let (reach, inner) = self.radii.of(&grain.outline);
        let (sin, cos) = grain.angle.sin_cos();
        let r_eq = grain.outline.equivalent_radius();
        self.r_small = self.r_small.min(r_eq);
        self.inner_small = self.inner_small.min(inner);
        let one_contact = match self.scene.packer.one_contact_share {
            s if s <= 0.0 => false,
            s if s >= 1.0 => true,
            s => self.contact_rng.r#gen::<f64>() < s,
        };
        // Wake the fronts parked for a larger size.
        let key = ((r_eq / WAKE_RATIO).to_bits().saturating_add(1), 0);
        let woken: Vec<(u64, u32)> = self.parked.range(key..).map(|(k, _)| *k).collect();
        for k in woken.into_iter().rev() {
            self.parked.remove(&k);
            self.stack.push(Entry::attempt(k.1));
        }
        let sampled = self.tables.sample(&grain.outline, cos, sin);
        let spot = {
            let new = Newcomer {
                outline: &grain.outline,
                cos,
                sin,
                reach,
                inner,
                slack: 0.0,
                sampled,
            };
            let mut spot = None;
            if self.needs_seed() {
                spot = self.seed(&new);
            }
            while spot.is_none() {
                let Some(&entry) = self.stack.last() else {
                    break;
                };
                let front = entry.front;
                // A front's room only shrinks as particles are placed: one
                // that failed for this size or a smaller one waits again
                // without an attempt (woken by a smaller size than that).
                let failed = self.failed_for[front as usize];
                if r_eq >= failed {
                    self.stack.pop();
                    self.parked.insert((failed.to_bits(), front), ());
                    continue;
                }
                if entry.since != ATTEMPT && !self.any_alive(&entry) {
                    self.stack.pop();
                    self.look()?;
                    continue;
                }
                self.stats.front_attempts += 1;
                if let Some(p) = self.attempt(front, &new, one_contact, false) {
                    // A large particle's spots say nothing of the narrower
                    // gaps a smaller one fits (as with the disk front).
                    let kept = self
                        .witnesses
                        .take()
                        .filter(|_| r_eq <= self.r_small * WITNESS_BAND);
                    if let Some(top) = self.stack.last_mut() {
                        *top = kept.unwrap_or(Entry::attempt(front));
                    }
                    spot = Some(p);
                } else {
                    self.stack.pop();
                    self.failed_for[front as usize] = r_eq;
                    // Parked for a smaller size, unless even the smallest
                    // disk inside any particle finds no spot touching it.
                    let smallest = self.inner_small;
                    let probe_outline = Outline::Superellipse {
                        a: smallest,
                        b: smallest,
                        alpha: 2.0,
                        beta: 2.0,
                    };
                    let probe = Newcomer {
                        outline: &probe_outline,
                        cos: 1.0,
                        sin: 0.0,
                        reach: smallest,
                        inner: smallest,
                        slack: 0.0,
                        sampled: self.tables.sample(&probe_outline, 1.0, 0.0),
                    };
                    if r_eq > self.r_small * CLOSE_BAND
                        && self.attempt(front, &probe, false, true).is_some()
                    {
                        self.parked.insert((r_eq.to_bits(), front), ());
                    }
                }
                self.look()?;
            }
            if spot.is_none() && self.stack.is_empty() && !self.periodic {
                // Every front is parked or closed: a new start on the walls.
                spot = self.seed(&new);
            }
            spot
        };
        let Some(p) = spot else {
            return Ok(false);
        };
        self.place(p, grain, tag, reach, inner, r_eq, cos, sin, sampled)?;
        Ok(true)
    }

    /// Put `grain` of material `tag` at `p` (its reach, inner and
    /// equivalent radii and its angle's cosine and sine precomputed).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn place(
        &mut self,
        p: Point,
        grain: Grain,
        tag: u16,
        reach: f64,
        inner: f64,
        r_eq: f64,
        cos: f64,
        sin: f64,
        sampled: Option<Sampled>,
    ) -> Result<(), PackError> {
        if let Some((limit, why)) = &self.ceiling
            && self.disks.len() as u64 >= *limit
        {
            return Err(why.clone());
        }
        let c = self.scene.domain.wrap(p);
        let id = self.bodies.len() as u32;
        self.index.insert(id, c);
        self.bodies.push(Body {
            c,
            outline: grain.outline.clone(),
            cos,
            sin,
            reach,
            inner,
        });
        self.disks.push(Disk { c, r: r_eq });
        self.halos.push(Halo {
            c,
            reach,
            inner,
            sampled,
        });
        self.failed_for.push(f64::INFINITY);
        self.grains.push(grain);
        if self.sizer.graded() {
            self.tags.push(tag);
        }
        self.stack.push(Entry::attempt(id));
        self.reach_max = self.reach_max.max(reach);
        Ok(())
    }

    /// Count work; look at the cancel token and the budget every [`WORK_STEP`].
    pub(super) fn look(&mut self) -> Result<(), PackError> {
        if self.stats.work >= self.next_look {
            self.next_look = self.stats.work + WORK_STEP;
            self.cancel.check()?;
            if self.stats.work > self.budget {
                return Err(PackError::WorkBudget {
                    budget: self.budget,
                    disks: self.disks.len() as u64,
                    sizes_drawn: self.stats.sizes_drawn,
                });
            }
        }
        Ok(())
    }

    /// Visit the placed particles whose images lie in the box about `p`
    /// of half side `half`, until `f` breaks.
    fn visit(
        &self,
        p: Point,
        half: f64,
        mut f: impl FnMut(u32, Vector2<f64>) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let (lo, hi) = (
            Point::new(p.x - half, p.y - half),
            Point::new(p.x + half, p.y + half),
        );
        if !self.periodic {
            return self
                .index
                .try_visit_box(lo, hi, |id| f(id, Vector2::zeros()));
        }
        for v in self.scene.domain.image_shifts(lo, hi) {
            self.index.try_visit_box(lo - v, hi - v, |id| f(id, v))?;
        }
        ControlFlow::Continue(())
    }

    /// Whether the new particle at `p` is clear of every wall and particle
    /// but those in `skip`.
    pub(super) fn clear(&mut self, new: &Newcomer, p: Point, skip: &[Obstacle]) -> bool {
        if !self.periodic && self.scene.domain.signed_distance(p) <= 0.0 {
            return false;
        }
        let mut work = 0u64;
        let walls_clear = self.walls.iter().all(|w| {
            if skip.contains(w) {
                return true;
            }
            work += 1;
            clear_of(&self.bodies, w, new, p)
        });
        if !walls_clear {
            self.stats.work += work;
            return false;
        }
        let half = new.reach + self.reach_max;
        let bodies = &self.bodies;
        let blocked = self
            .visit(p, half, |id, v| {
                let ob = Obstacle::Body(id, v);
                if skip.contains(&ob) {
                    return ControlFlow::Continue(());
                }
                work += 1;
                if clear_of(bodies, &ob, new, p) {
                    ControlFlow::Continue(())
                } else {
                    ControlFlow::Break(())
                }
            })
            .is_break();
        self.stats.work += work;
        !blocked
    }

    /// Whether the new particle at `p`, a centre within the front's halo, is
    /// clear of the domain's outside and of every obstacle in `near` (the
    /// front's obstacles, all that such a centre can meet) but those in
    /// `skip`. The obstacle that blocked the last centre (`witness`) is
    /// checked first: neighbouring candidates are mostly blocked by the same.
    fn clear_near(
        &mut self,
        new: &Newcomer,
        p: Point,
        skip: &[Obstacle],
        near: &[Obstacle],
        witness: &mut usize,
    ) -> bool {
        if !self.periodic && self.scene.domain.signed_distance(p) <= 0.0 {
            return false;
        }
        let first = (*witness).min(near.len());
        let order = near[first..].iter().chain(&near[..first]);
        for (k, ob) in order.enumerate() {
            if skip.contains(ob) {
                continue;
            }
            self.stats.work += 1;
            if !clear_of(&self.bodies, ob, new, p) {
                *witness = (first + k) % near.len();
                return false;
            }
        }
        true
    }

    /// The lowest clear spot touching front `front` and one more obstacle
    /// (with one contact: touching one of them), if any; with `any`, the
    /// first clear spot found.
    fn attempt(
        &mut self,
        front: u32,
        new: &Newcomer,
        one_contact: bool,
        any: bool,
    ) -> Option<Point> {
        let mut obstacles = std::mem::take(&mut self.obstacles);
        obstacles.clear();
        self.witnesses = None;
        let found = self.attempt_among(front, new, one_contact, any, &mut obstacles);
        self.obstacles = obstacles;
        found
    }

    /// [`Self::attempt`], gathering the front's obstacles into `obstacles`.
    fn attempt_among(
        &mut self,
        front: u32,
        new: &Newcomer,
        one_contact: bool,
        any: bool,
        obstacles: &mut Vec<Obstacle>,
    ) -> Option<Point> {
        let f = &self.bodies[front as usize];
        let (cf, rf) = (f.c, f.reach);
        let reach = rf + 2.0 * new.reach;
        let halos = &self.halos;
        let _ = self.visit(cf, reach + self.reach_max, |id, v| {
            let g = &halos[id as usize];
            let (d, s) = (g.c + v - cf, reach + g.reach);
            if d.norm_squared() <= s * s && (id != front || v != Vector2::zeros()) {
                obstacles.push(Obstacle::Body(id, v));
            }
            ControlFlow::Continue(())
        });
        for w in &self.walls {
            let near = match *w {
                Obstacle::Segment(a, b) => point_segment_distance(cf, a, b) <= reach,
                Obstacle::Circle(o, radius) => radius - (cf - o).norm() <= reach,
                Obstacle::Body(..) => false,
            };
            if near {
                obstacles.push(*w);
            }
        }
        let me = Obstacle::Body(front, Vector2::zeros());
        let obstacles = &obstacles[..];
        if !one_contact && let Some(found) = self.screened(front, new, obstacles, any) {
            return found;
        }
        // Each obstacle with the least rank a centre touching it and the
        // front can have (inside both halos): solved lowest bound first,
        // until the best clear spot ranks below every bound left.
        let mut order: Vec<((f64, f64), Obstacle)> = obstacles
            .iter()
            .filter(|ob| one_contact || self.may_cross(front, ob, new))
            .map(|ob| (self.rank_bound(cf, rf + new.reach, ob, new), *ob))
            .collect();
        order.sort_unstable_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        let mut best: Option<((f64, f64), Point)> = None;
        let mut begin = Vec::new();
        // The obstacle that blocked the last candidate, checked first.
        let mut witness = 0;
        let mut work = 0u64;
        for (bound, ob) in &order {
            if best.is_some_and(|(rank, _)| *bound > rank) {
                break;
            }
            begin.clear();
            starts(&self.bodies, cf, rf, ob, new, &mut begin);
            for &s in &begin {
                // A smooth solve is exact at once: no coarse stage.
                let mut exact = false;
                let p = if one_contact {
                    let to = Point::from(0.5 * (cf.coords + reference(&self.bodies, ob, s).coords));
                    slide(&self.bodies, &me, Some(ob), new, s, to, &mut work)
                } else {
                    match two_contact_smooth(&self.bodies, &me, ob, new, s, None, &mut work) {
                        Smooth::Found(p) => {
                            exact = true;
                            Some(p)
                        }
                        Smooth::Missing => None,
                        Smooth::Unsuited => {
                            two_contact(&self.bodies, &me, ob, new, s, true, &mut work)
                        }
                    }
                };
                let Some(mut p) = p else { continue };
                let rank = self.rank(p);
                // A coarse centre is within COARSE_REL·reach of its own:
                // its rank (a height, or a squared distance in a cell)
                // within the slack below.
                let slack = |r: f64| 4.0 * COARSE_REL * new.reach * (1.0 + r.abs().sqrt());
                if best.is_some_and(|(r, _)| rank.0 > r.0 + slack(r.0)) {
                    continue;
                }
                self.stats.work += work;
                work = 0;
                if !one_contact && !exact {
                    // Blocked where it nearly is, by more than the coarse
                    // solve's error: no need to settle it.
                    let eroded = Newcomer {
                        slack: 2.0 * COARSE_REL * new.reach,
                        ..*new
                    };
                    if !self.clear_near(&eroded, p, &[me, *ob], obstacles, &mut witness) {
                        continue;
                    }
                    match two_contact(&self.bodies, &me, ob, new, p, false, &mut work) {
                        Some(fine) => p = fine,
                        None => continue,
                    }
                }
                let rank = self.rank(p);
                if best.is_some_and(|(r, _)| rank >= r) {
                    continue;
                }
                // Certified clear of the two it was solved against already.
                // A one-contact slide towards a large neighbour may end
                // beyond the front's halo, where particles the front did
                // not gather can reach: checked against every particle.
                let clear = if one_contact && (p - cf).norm() > rf + new.reach {
                    self.clear(new, p, &[me, *ob])
                } else {
                    self.clear_near(new, p, &[me, *ob], obstacles, &mut witness)
                };
                if clear {
                    if any {
                        return Some(p);
                    }
                    best = Some((rank, p));
                }
            }
        }
        self.stats.work += work;
        best.map(|(_, p)| p)
    }

    /// The lowest clear spot touching front `front` and one more obstacle
    /// (with `any`, the first clear spot found), solved only where the
    /// screen finds the front's curve leaving an obstacle's shadow
    /// (`screen`); `None` when the screen does not apply.
    fn screened(
        &mut self,
        front: u32,
        new: &Newcomer,
        obstacles: &[Obstacle],
        any: bool,
    ) -> Option<Option<Point>> {
        let f = &self.halos[front as usize];
        let mut cands = std::mem::take(&mut self.cands);
        let mut work = 0u64;
        let screened = candidates(
            &self.tables,
            &self.bodies,
            &self.halos,
            f,
            new,
            obstacles,
            &mut self.polys,
            &mut cands,
            &mut work,
        );
        if screened.is_none() {
            self.cands = cands;
            self.stats.work += work;
            return None;
        }
        // The estimates are within about a side of the polygon of the
        // exact spots: candidates ranked within that of the best are
        // solved too.
        let tol = std::f64::consts::TAU * (f.reach + new.reach) / SIDES as f64;
        let fc = f.c;
        let me = Obstacle::Body(front, Vector2::zeros());
        let mut ranked = std::mem::take(&mut self.ranked);
        ranked.clear();
        ranked.extend(cands.iter().map(|c| (self.rank(c.p), *c)));
        ranked.sort_unstable_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        let mut best: Option<((f64, f64), Point)> = None;
        let mut witness = 0;
        // Spots found clear, then those left unsolved: the witnesses.
        let mut spots = std::mem::take(&mut self.spots);
        spots.clear();
        let mut unsolved = ranked.len();
        for (i, (estimate, cand)) in ranked.iter().enumerate() {
            if let Some((r, _)) = best {
                let slack = if self.periodic {
                    tol * (2.0 * r.0.sqrt() + tol)
                } else {
                    tol
                };
                if estimate.0 > r.0 + slack {
                    unsolved = i;
                    break;
                }
            }
            let ob = obstacles[cand.ob];
            let p = match two_contact_smooth(
                &self.bodies,
                &me,
                &ob,
                new,
                cand.p,
                cand.normals,
                &mut work,
            ) {
                Smooth::Found(p) => p,
                Smooth::Missing => continue,
                Smooth::Unsuited => {
                    match two_contact(&self.bodies, &me, &ob, new, cand.p, false, &mut work) {
                        Some(p) => p,
                        None => continue,
                    }
                }
            };
            let rank = self.rank(p);
            if best.is_some_and(|(r, _)| rank >= r) {
                // Not checked: a spot the front may still have.
                spots.push((rank, p));
                continue;
            }
            if self.clear_near(new, p, &[me, ob], obstacles, &mut witness) {
                if any {
                    best = Some((rank, p));
                    break;
                }
                spots.push((rank, p));
                if best.is_none_or(|(r, _)| rank < r) {
                    best = Some((rank, p));
                }
            }
        }
        if !any && let Some((_, chosen)) = best {
            spots.sort_unstable_by(|a, b| {
                a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal)
            });
            let left = ranked[unsolved..].iter().map(|(r, c)| (*r, c.p));
            let mut w = Entry {
                front,
                since: self.bodies.len() as u32,
                at: [NO_SPOT; WITNESSES],
            };
            let step = |x: f64| (x / self.unit).round().clamp(-32767.0, 32767.0) as i16;
            let kept = spots
                .iter()
                .copied()
                .chain(left)
                .filter(|&(_, q)| q != chosen);
            for (slot, (_, q)) in w.at.iter_mut().zip(kept) {
                let d = q - fc;
                *slot = [step(d.x), step(d.y)];
            }
            self.witnesses = Some(w);
        }
        self.spots = spots;
        self.cands = cands;
        self.ranked = ranked;
        self.stats.work += work;
        Some(best.map(|(_, p)| p))
    }

    /// Whether the new particle may touch both the front and `ob` at once:
    /// `false` when a line square to the centres' direction separates the
    /// two sets of centres touching each (the front grown by the new
    /// particle reflected, and the particle `ob` grown the same way, each
    /// by the gap too), by support values bounded from above. Such a pair
    /// has no crossing to solve for (its halos may still cross: a bounding
    /// circle reaches far beyond an elongated particle's sides). Two
    /// contacts only: a one-contact slide touches one of the two.
    fn may_cross(&self, front: u32, ob: &Obstacle, new: &Newcomer) -> bool {
        let Obstacle::Body(id, v) = *ob else {
            return true;
        };
        let (f, g) = (&self.bodies[front as usize], &self.bodies[id as usize]);
        let d = g.c + v - f.c;
        let n = d.norm();
        if n == 0.0 {
            return true;
        }
        let u = d / n;
        let reach = f.support(u).0 + new.support(-u).0 + new.support(u).0 + g.support(-u).0;
        n <= reach + 2.0 * GAP_REL * new.reach
    }

    /// A lower bound of the rank of a centre within `halo` of the front's
    /// centre `cf` and touching `ob` (inside its halo too).
    fn rank_bound(&self, cf: Point, halo: f64, ob: &Obstacle, new: &Newcomer) -> (f64, f64) {
        // The disk (cf, halo) and the obstacle's own halo: the lowest point
        // of their lens is at least the lower of their lowest points.
        let (c2, r2) = match *ob {
            Obstacle::Body(id, v) => {
                let g = &self.bodies[id as usize];
                (g.c + v, g.reach + new.reach)
            }
            Obstacle::Segment(..) | Obstacle::Circle(..) => (cf, halo),
        };
        if self.periodic {
            let Some(first) = self.bodies.first() else {
                return (0.0, f64::NEG_INFINITY);
            };
            let gap = |c: Point, r: f64| {
                let mut d = c - first.c;
                if let Some(period) = self.scene.domain.period() {
                    d.x -= period.x * (d.x / period.x).round();
                    d.y -= period.y * (d.y / period.y).round();
                }
                (d.norm() - r).max(0.0)
            };
            let g = gap(cf, halo).max(gap(c2, r2));
            return (g * g, f64::NEG_INFINITY);
        }
        ((cf.y - halo).max(c2.y - r2), f64::NEG_INFINITY)
    }

    /// The order candidates are tried in: lowest then leftmost; in a
    /// periodic cell, nearest the first particle (its nearest image).
    fn rank(&self, p: Point) -> (f64, f64) {
        if let (true, Some(first), Some(period)) = (
            self.periodic,
            self.bodies.first(),
            self.scene.domain.period(),
        ) {
            let mut d = p - first.c;
            d.x -= period.x * (d.x / period.x).round();
            d.y -= period.y * (d.y / period.y).round();
            return (d.norm_squared(), p.y);
        }
        (p.y, p.x)
    }
}

/// Work between two looks at the cancel token and the budget.
const WORK_STEP: u64 = 1 << 16;

/// A point of obstacle `ob` to slide towards, from a start `s`: a
/// particle's centre, the foot of `s` on a straight wall, the point of a
/// circular wall beyond `s`.
fn reference(bodies: &[Body], ob: &Obstacle, s: Point) -> Point {
    match *ob {
        Obstacle::Body(id, v) => bodies[id as usize].c + v,
        Obstacle::Segment(a, b) => {
            let e = b - a;
            let t = ((s - a).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
            a + e * t
        }
        Obstacle::Circle(o, radius) => {
            let d = s - o;
            let n = d.norm();
            if n > 0.0 { o + d * (radius / n) } else { o }
        }
    }
}

/// The most particles the scene's limits allow, and the error past it.
fn ceiling(scene: &Scene) -> Option<(u64, PackError)> {
    let by_particles = scene
        .limits
        .max_particles
        .map(|limit| (limit, PackError::ParticleLimit { limit }));
    let by_memory = scene.limits.max_memory_bytes.map(|bytes| {
        let n = (bytes / PEAK_BYTES_PER_GRAIN)
            .floor()
            .clamp(0.0, u64::MAX as f64) as u64;
        (
            n,
            PackError::MemoryLimit {
                limit_mb: bytes / BYTES_PER_MB,
                disks: n,
            },
        )
    });
    match (by_particles, by_memory) {
        (Some(a), Some(b)) => Some(if a.0 <= b.0 { a } else { b }),
        (a, b) => a.or(b),
    }
}
