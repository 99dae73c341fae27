//! The advancing-front generator (docs/ARCHITECTURE.md, "The advancing
//! front"): each new disk is placed tangent
//! to the current front and to one more obstacle, at the lowest feasible spot.
//!
//! # Behavior
//! 1. Obstacles: wall disks (`walls = "disks"`, see "Wall disks" below) or
//!    exact walls plus the polygon's reflex corners as zero-radius point
//!    obstacles (`"exact"`).
//! 2. Fronts: a stack. Wall disks start it, lowest then leftmost on top; with
//!    exact walls the first disk is seeded at the lowest wall–wall tangency.
//! 3. For the front on top and a new radius `r`, the neighbours come from one
//!    box query of half side `r_front + 1.1·d_new + r_max`.
//! 4. Candidates are the intersections of the front's halo (radius
//!    `r_front + r`) with each neighbour's halo and each wall offset by `r`.
//! 5. A candidate is feasible when it is inside the domain and in no other halo.
//! 6. The lowest feasible candidate (then the leftmost) wins; the new disk
//!    goes on top of the stack.
//! 7. A front with no feasible candidate leaves the stack and the same size
//!    goes to the next front; one with fewer than two leaves after placing.
//! 8. The run stops when the sizes (`ceil(area / smallest disk area)` of
//!    them) or the fronts run out.
//!
//! With [`FrontRules::Robust`] (default) step 7 parks a failing front with the
//! radius it failed for and wakes it when a smaller size comes, and a size
//! that fits at no front is deferred and retried after later placements
//! instead of emptying the stack (the thesis' weak spot with wide gradings).
//! The run then stops when `max_deferred` deferred sizes still fit
//! nowhere: the domain is full for this grading (a loose pack first fills
//! any hole left, see `Front::fill_hole`). A front also leaves after a
//! placement when no other feasible spot stays clear of the new disk (the
//! thesis keeps it for one more, failing, attempt).
//!
//! # Closed fronts (robust rules)
//! Nearly every disk stays on the stack after its first placement (it still
//! has a free spot) and is buried later by disks placed around newer fronts;
//! confirming each of them closed with a full, failing attempt was half the
//! work of a run. Two exact-or-near-exact shortcuts replace those attempts:
//! - A front that stays remembers its free spots clear of the new disk (its
//!   *witnesses*, up to [`WITNESSES`]). When it comes up again and none of them
//!   takes even the smallest disk ([`max_radius_ray_disk`], one small query
//!   per spot), it leaves without an attempt. Any gap left on its edge lies
//!   next to a newer disk, whose own attempt saw it as a spot. Only spots
//!   found for a disk of at most [`RETIRE_RATIO`]·r_min count: spots of a large
//!   disk say nothing of the narrower gaps smaller disks fit.
//! - A front that fails for a large size is tested once more for the smallest
//!   size with the neighbours already gathered: if even that fails it leaves
//!   instead of being parked (a disk that fits touching a front contains the
//!   smaller disk touching it at the same point, so no size fits).
//!
//! Measured against the packer that made full attempts (commit 9ec5d27) on
//! 17 scenes × 3 seeds (the example configs, Table 3.1/3.4/4.1 squares up to
//! 1000 mm, uniform 0.5–5 mm, both wall models, both contact rules): the same
//! disk count and porosity in 48 of 51 runs; the 1000 mm square (seed 1) lost
//! 6 of 667,685 disks and an 80 mm circle 1 of 3,327 (gaps below the witness
//! size), and a one-contact pack gained 1 of 5,105 (its random angles took
//! another course).
//!
//! # Wall disks
//! Wall disks on straight edges are not in the index but in runs, edge by
//! edge (`super::wall_runs`): a front's candidates against them come from
//! the few whose zone its halo crosses, a candidate is tested against each
//! edge's disks nearest it, and a wall disk leaves the stack without an
//! attempt once packed disks cover its zones (`Front::covered`). The same
//! packings, bit for bit, as with every wall disk in the index and
//! attempted (18 configs with wall disks compared, the wells among them):
//! on the thesis' wells (160,000 to 500,000 wall disks) front attempts fell
//! from 186,000 / 562,000 / 422,000 to 26,000 / 62,000 / 82,000, the work
//! 9- to 20-fold, and the time 4- to 6-fold. A circle's wall disks stay in
//! the index.
//!
//! A share of the placements ([`PackerSettings::one_contact_share`], drawn
//! per size from the seeded stream) touch the front only, at a random angle
//! drawn uniformly over the free arcs of the front's halo, keeping
//! [`PackerSettings::gap`] radii clear of every other disk (it may rest
//! against a wall); a front with no such arc left fails for that size.
//!
//! # Periodic cells
//! With `walls = "periodic"` there is no wall and no reflex corner: the
//! first disk sits a quarter period from the cell's low corner in x and
//! y (see `Front::rank`) and the second touches it (the only disk placed
//! with one contact in a dense pack); every later one is placed as above,
//! with two changes. Every index query is made once per
//! lattice shift whose images may meet its box ([`Domain::image_shifts`]:
//! one query inside the cell, two or four near its edges), each obstacle
//! found being met as that image, so the neighbours, the witnesses and the
//! holes see across the edges and memory stays one entry per disk; a
//! centre is wrapped into the cell when the disk is placed. And the winning
//! candidate is the one of lowest key instead of the lowest: a rank that
//! grows a round cluster from the first disk but is flat across the lines
//! half a period from it, so that the front runs on into its own images
//! rather than meeting them face to face (see `Front::rank`), plus a
//! weight on how loosely the spot nests, which decides where the rank is
//! flat, where the front closes on itself (see `Front::key`). A domain with walls
//! makes one query with the zero shift and ranks every candidate 0: the
//! same packings, bit for bit.
//!
//! # Files
//! This file holds the entry points, the generator's state and its loop
//! (sizes, fronts, deferred sizes, placement); the rest lives beside it:
//! `candidates` (the two-contact attempt: neighbours, candidates, their
//! feasibility, the lowest clear one), `closure` (witnesses, bounds and
//! parked fronts), `one_contact` (one-contact placement and a loose pack's
//! last hole), `periodic` (lattice images, the rank and the key) and `seed` (the
//! first disks).
//!
//! [`PackerSettings::one_contact_share`]: super::PackerSettings::one_contact_share
//! [`PackerSettings::gap`]: super::PackerSettings::gap
//! [`WITNESSES`]: closure::WITNESSES
//! [`max_radius_ray_disk`]: crate::geometry::predicates::max_radius_ray_disk

use nalgebra::Vector2;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::cell::Cell;
use std::collections::{BTreeMap, VecDeque};
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU64, Ordering};

use super::arcs::{Arcs, Measure};
use super::index::{Grid, MxQuadtree, SpatialIndex};
use super::sizer::Sizer;
use super::strips::Region;
use super::wall_runs::WallRuns;
use super::{Fill, FrontRules, IndexKind, PackError, PackStats, Packing};
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::{Disk, Domain, Point, Wall, WallMode};

mod candidates;
mod closure;
mod one_contact;
mod periodic;
mod rows;
mod seed;

use candidates::{Cand, Near, lowest_first};
use closure::{NO_WITNESS, RETIRE_RATIO, Witnesses, merged};
use one_contact::ANGLE_STREAM;
pub(crate) use seed::offset_crossing;

/// Retries of one deferred size before it is given up.
const DEFERRED_RETRIES: u32 = 32;

/// Number of sizes the thesis draws: `ceil(domain area / area of the smallest disk)`.
pub fn size_count(domain: &Domain, d_min: f64) -> u64 {
    size_count_in(domain.area(), d_min)
}

/// [`size_count`] of an area (mm²).
pub(super) fn size_count_in(area: f64, d_min: f64) -> u64 {
    let a_min = std::f64::consts::PI * d_min * d_min / 4.0;
    (area / a_min).ceil() as u64
}

/// Sizes drawn between two calls of a packing's progress callback, and
/// between two looks at its cancel token.
pub const PROGRESS_STEP: u64 = 4096;

/// Pack a scene with the advancing-front generator, sizes drawn from its
/// grading; `progress` is told the sizes drawn so far every [`PROGRESS_STEP`]
/// (a scene packed in strips, [`super::strips`], after each colour).
///
/// # Errors
/// As [`pack_genes`], and [`PackError::Cancelled`] once `cancel` is raised.
pub fn pack(
    scene: &Scene,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    let strips = match scene.packer.fill {
        Fill::Right => super::strips::count(&scene.transposed()),
        Fill::Up => super::strips::count(scene),
    };
    if let Some(strips) = strips {
        // Cut in the frame the front fills in, next to the origin.
        return super::near_origin(scene, |scene| {
            filled(scene, |up| {
                super::strips::pack_up(up, strips, progress, cancel)
            })
        });
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(scene.seed);
    let count = size_count(&scene.domain, scene.d_min());
    let genes = (0..count).map(move |_| rng.r#gen::<f64>());
    pack_genes_watched(scene, genes, progress, cancel)
}

/// [`pack_genes`], telling `progress` how many genes were read every
/// [`PROGRESS_STEP`] and stopping once `cancel` is raised. A scene with a
/// `[shape]` is packed by the particles' own front (or rsa) with these
/// genes as its sizes, each particle's outline drawn from the shape's stream.
///
/// # Errors
/// As [`pack_genes`], and [`PackError::Cancelled`] when stopped.
pub fn pack_genes_watched(
    scene: &Scene,
    genes: impl Iterator<Item = f64>,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    if let Some(shape) = &scene.shape {
        let mut genes = genes;
        return super::grains::pack(scene, shape, &mut genes, progress, cancel);
    }
    let stopped = Cell::new(None);
    let watched = genes.enumerate().map_while(|(i, u)| {
        let i = i as u64;
        if i.is_multiple_of(PROGRESS_STEP) {
            progress(i);
            if let Err(why) = cancel.check() {
                stopped.set(Some(why));
                return None;
            }
        }
        Some(u)
    });
    let packing = pack_genes(scene, watched, cancel);
    match stopped.get() {
        Some(why) => Err(why.into()),
        None => packing,
    }
}

/// Pack a scene with the sizes drawn by the given genes, in order: each gene
/// U in [0, 1] is a percent passing, mapped to a diameter by the grading's
/// inverse CDF (in size-graded mode, by the curve chosen for it, see
/// [`Scene::gradient`]).
///
/// This is the fitness kernel's entry: a caller that evolves the sizes (the
/// GA's grading genes) passes them here.
///
/// With [`Fill::Right`] the scene is mirrored in the line y = x, packed
/// upwards and mirrored back (the same genes give the same sizes). A domain
/// far from the origin is packed next to it and moved back
/// ([`Domain::local_offset`]).
///
/// # Errors
/// As [`pack_up`]'s checks ([`PackError::DomainTooNarrow`], …), and
/// [`PackError::Cancelled`] or [`PackError::WorkBudget`] when the run stops.
fn pack_genes(
    scene: &Scene,
    genes: impl Iterator<Item = f64>,
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    super::near_origin(scene, |scene| pack_filled(scene, genes, cancel))
}

/// [`pack_genes`] in the scene's own frame: up, or right by the mirrored scene.
fn pack_filled(
    scene: &Scene,
    genes: impl Iterator<Item = f64>,
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    filled(scene, |up| pack_up(up, genes, cancel))
}

/// `pack_up`'s packing of `scene` filling up, or, filling right, of the
/// mirrored scene mirrored back.
fn filled(
    scene: &Scene,
    pack_up: impl FnOnce(&Scene) -> Result<Packing, PackError>,
) -> Result<Packing, PackError> {
    if scene.packer.fill == Fill::Right {
        let mut packing = pack_up(&scene.transposed())?;
        let swap = |d: &mut Disk| d.c = Point::new(d.c.y, d.c.x);
        packing.disks.iter_mut().for_each(swap);
        packing.boundary.iter_mut().for_each(swap);
        packing.domain = scene.domain.clone();
        return Ok(packing);
    }
    pack_up(scene)
}

/// [`pack_genes`] with the front advancing up (lowest ordinate first).
fn pack_up(
    scene: &Scene,
    genes: impl Iterator<Item = f64>,
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    super::placed::check_fits(scene)?;
    pack_part(scene, None, genes, cancel).map(|p| p.packing)
}

/// Pack `scene`, or only `part` of it, with the sizes the genes draw.
pub(super) fn pack_part(
    scene: &Scene,
    part: Option<&Part>,
    genes: impl Iterator<Item = f64>,
    cancel: &Cancel,
) -> Result<PartPacking, PackError> {
    match scene.packer.index {
        IndexKind::MxQuadtree => Front::<MxQuadtree>::new(scene, cancel, part).pack(genes),
        IndexKind::Grid => Front::<Grid>::new(scene, cancel, part).pack(genes),
    }
}

/// A part's packing, and which of its disks the parts packed after it
/// still grow from.
pub(super) struct PartPacking {
    /// In a part, its disks come after the `fixed` disks it was packed
    /// against (see [`PartPacking::own`]): they are not shifted out, so
    /// the part's own disks are copied once, into the whole packing.
    pub packing: Packing,
    pub fixed: usize,
    /// The disks of a part (none in one piece) that may still take a disk
    /// in a part packed after this one, by index in `packing.disks`,
    /// ascending, with what their part learnt of their room. A disk its
    /// own part closed (it failed for the smallest sizes and left the
    /// fronts) without a candidate refused for lying outside the part's
    /// region has no room left anywhere: every disk or wall that blocked it
    /// is within reach of any later part it touches, so there it is an
    /// obstacle only.
    pub open: Vec<(u32, Opening)>,
}

impl PartPacking {
    /// The disks the part placed, in order (`open` indexes them).
    pub fn own(&self) -> &[Disk] {
        &self.packing.disks[self.fixed..]
    }
}

/// What a part learnt of the room of a disk it left open, for the parts
/// packed after it: its free spots and the radius it is known not to take,
/// as its own part would go on using them (see [`Front::witnesses_closed`]).
/// They hold in a later part too when no candidate of the disk was ever
/// refused for lying outside its own part's region (every spot it found, or
/// ruled out, was then judged on obstacles a later part sees as well);
/// otherwise the disk is handed on as fresh ([`Opening::FRESH`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Opening {
    witness: Witnesses,
    bound: f32,
}

impl Opening {
    /// An open disk with nothing known of its room: attempted in full.
    pub const FRESH: Opening = Opening {
        witness: NO_WITNESS,
        bound: f32::INFINITY,
    };
}

/// A part of a domain packed on its own (see `super::strips`): the disks'
/// centres lie in a convex region, clear of fixed disks packed before.
pub(super) struct Part<'a> {
    /// Where the centres lie.
    pub region: &'a Region,
    /// Disks packed before, from the parts beside this one: obstacles,
    /// not part of the packing returned.
    pub fixed: &'a [Disk],
    /// Per fixed disk: whether it is a front here, open at the end of its
    /// own part, and what that part learnt of its room (see [`PartPacking::open`]).
    pub open: &'a [Option<Opening>],
    /// Disks placed by every part of the domain so far, against the scene's limits.
    pub placed: &'a AtomicU64,
    /// The work after which this part stops ([`work_budget`] of its share).
    pub budget: u64,
    /// Whether rows run left to right only: a row that would turn back at
    /// its end starts again at the left (see `Front::restart`), so every
    /// row starts against the disks packed before on the part's left.
    pub raster: bool,
}

/// Work between two looks at the cancel token inside a run (neighbours
/// visited and tested, candidates made): a few milliseconds, however slowly
/// the sizes go (a wide grading once spent four minutes between two looks
/// made every [`PROGRESS_STEP`] sizes).
const WORK_STEP: u64 = 1 << 20;

/// The most work a run may do per disk the domain could hold
/// ([`Scene::max_disks`]), beyond `WORK_FLOOR` (see [`work_budget`]).
pub const WORK_PER_DISK: u64 = 1 << 14;

/// Work any run may do, however few disks its domain holds.
pub(super) const WORK_FLOOR: u64 = 1 << 30;

/// The most work the advancing front may do on `scene` before it stops with
/// [`PackError::WorkBudget`]: [`WORK_PER_DISK`] per disk the domain could
/// hold ([`Scene::max_disks`]) and per wall disk, plus `WORK_FLOOR`.
///
/// # Behavior
/// Work counts neighbours visited in the index and tested against
/// candidates, candidates made and wall tests, the units the run's time is
/// spent in (about 5·10⁸ a second). The shipped configs use at most about
/// 2,000 per disk the domain can hold (`wells.toml`, wall disks aside); a
/// 20 mm square of 0.02–4 mm sizes by 3D mass, 7,300. A scene that reaches
/// the budget would run for many minutes more, and stops instead: a
/// packing cut short is not a sample of its grading, so none is returned.
pub fn work_budget(scene: &Scene) -> u64 {
    let disks = scene.max_disks() + super::wall_disk_count(scene) as f64;
    let disks = disks.min(u64::MAX as f64 / WORK_PER_DISK as f64);
    (disks as u64)
        .saturating_mul(WORK_PER_DISK)
        .saturating_add(WORK_FLOOR)
}

/// The generator's state while packing.
struct Front<'a, I> {
    scene: &'a Scene,
    /// Looked at every [`WORK_STEP`] of work.
    cancel: &'a Cancel,
    /// The work after which the run stops ([`work_budget`]).
    budget: u64,
    /// The work at which the cancel token is looked at next.
    next_look: u64,
    /// Neighbour tests made by `feasible` (which borrows the state shared),
    /// not yet counted in `stats.work`.
    tests: Cell<u64>,
    /// The most disks the scene's limits allow, and the error past it.
    ceiling: Option<(u64, PackError)>,
    /// Packing a part of the domain: the disks every part placed so far
    /// (the ceiling counts them all).
    placed: Option<&'a AtomicU64>,
    /// Packing a part of the domain: where its centres lie.
    region: Option<&'a Region>,
    /// Whether the current front's candidates may lie outside the part's
    /// region (set per attempt: deeper inside, the region is not tested).
    near_edge: bool,
    /// Rows left to right only (see [`Part::raster`]), and whether the
    /// stack was just reordered for a new row (see [`Front::restart`]).
    raster: bool,
    restarted: bool,
    /// The spots a row's first disk chooses among (see `Front::row_start`).
    row_spots: Vec<(u32, Point, f64)>,
    /// Set by `feasible` when a candidate clear of every obstacle lies
    /// outside the part's region; taken after each front's attempt.
    refused: Cell<u32>,
    /// Fronts that had a candidate refused so (see [`PartPacking::open`]).
    refused_fronts: Vec<u32>,
    /// Packing a part: per front that had candidates refused for lying
    /// outside the region, those of its last attempt near the region's
    /// edges, for the parts packed after it (`None`: not all known).
    handoff: BTreeMap<u32, Option<Witnesses>>,
    /// The spots of the current attempt refused so.
    outside: Vec<Point>,
    /// Walls the candidates must respect exactly (empty with wall disks
    /// and in a periodic cell).
    walls: Vec<Wall>,
    /// A periodic cell: no walls, and every obstacle is met with its images.
    periodic: bool,
    /// In a periodic cell, the first disk's centre (a quarter period from
    /// the cell's low corner) and the periods: candidates nearest it go
    /// first (see `Front::rank`).
    origin: Option<(Point, Vector2<f64>)>,
    /// Obstacles by id: wall disks or reflex corners first, then packed disks.
    obs: Vec<Disk>,
    /// Wall disks on straight edges, by edge (they are not in `index`).
    runs: WallRuns,
    /// Runs within reach of the current front (see `gather_neighbours`).
    near_runs: Vec<u32>,
    /// Per run: the packed disk that last covered a wall disk of it (see
    /// `Front::covered`), `u32::MAX` until one did.
    coverer: Vec<u32>,
    first_packed: usize,
    index: Indexed<I>,
    r_max: f64,
    r_retire: f64,
    /// Front stack; the top is the last element.
    fronts: Vec<u32>,
    /// Per obstacle id: the free spots that kept it on the stack, or [`NO_WITNESS`].
    witness: Vec<Witnesses>,
    /// Per obstacle id: a radius it is known not to take (room only shrinks,
    /// so the bound stays true); infinite until a failure measures it.
    /// Single precision, rounded up: still a radius it does not take.
    bound: Vec<f32>,
    /// Smallest radius of the grading: a front that cannot take it is closed.
    r_min: f64,
    /// Fronts that failed for a radius, waiting for a smaller one.
    parked: Vec<(f64, u32)>,
    /// Sizes (radius, material) that fitted nowhere, with their retry counts.
    deferred: VecDeque<(f64, u16, u32)>,
    /// Turns genes into sizes.
    sizer: Sizer<'a>,
    /// Material of each packed disk, in size-graded mode (else empty).
    tags: Vec<u16>,
    angles: Xoshiro256PlusPlus,
    stats: PackStats,
    // Scratch buffers reused by every attempt.
    near: Vec<Near>,
    cands: Vec<Cand>,
    /// Wall-tangent points of one attempt, before they become candidates.
    wall_points: Vec<Point>,
    spots: Vec<Point>,
    arcs: Arcs,
    /// Index in `near` of the neighbour that blocked the last candidate.
    last_blocker: Cell<usize>,
    /// The neighbours gathered for a failed size, while `room_left` bisects.
    near_all: Vec<(f64, Near)>,
}

impl<'a, I: SpatialIndex> Front<'a, I> {
    fn new(scene: &'a Scene, cancel: &'a Cancel, part: Option<&Part<'a>>) -> Self {
        let domain = &scene.domain;
        // A part (exact walls only) spans its region's bounds and the
        // fixed disks' (within a largest diameter): what may touch a disk it
        // places. Its index and its reflex corners are those of that span.
        let (mut lo, mut hi) = domain.bounds();
        if let Some(part) = part {
            let d = scene.d_max();
            lo = Point::new(
                lo.x.max(part.region.lo.x - d),
                lo.y.max(part.region.lo.y - d),
            );
            hi = Point::new(
                hi.x.min(part.region.hi.x + d),
                hi.y.min(part.region.hi.y + d),
            );
        }
        let (mut obs, walls) = match scene.walls {
            WallMode::Disks => (domain.boundary_disks(scene.wall_disk()), Vec::new()),
            WallMode::Periodic => (Vec::new(), Vec::new()),
            WallMode::Exact => {
                let corners = domain.reflex_vertices().iter();
                let corners = corners
                    .filter(|c| (lo.x..=hi.x).contains(&c.x) && (lo.y..=hi.y).contains(&c.y));
                (
                    corners.map(|&c| Disk { c, r: 0.0 }).collect(),
                    domain.walls().to_vec(),
                )
            }
        };
        let corners = obs.len();
        if let Some(part) = part {
            obs.extend_from_slice(part.fixed);
        }
        let first_packed = obs.len();
        let runs = match scene.walls {
            WallMode::Disks => {
                let edges = domain.boundary_disk_edges(scene.wall_disk());
                WallRuns::new(domain, &obs, edges)
            }
            WallMode::Exact | WallMode::Periodic => WallRuns::default(),
        };
        // Wall disks in runs stay out of the index.
        let base = if runs.is_empty() { 0 } else { first_packed };
        let mut witness = Vec::with_capacity(first_packed);
        witness.resize(first_packed, NO_WITNESS);
        let mut bound = vec![f32::INFINITY; first_packed];
        if let Some(part) = part {
            for (i, o) in part.open.iter().enumerate() {
                if let Some(o) = o {
                    witness[corners + i] = o.witness;
                    bound[corners + i] = o.bound;
                }
            }
        }
        let wall_r = obs.iter().fold(0.0f64, |m, o| m.max(o.r));
        let r_max = (scene.d_max() / 2.0).max(wall_r);
        // As many as the domain holds solid at the mean disk area (more come
        // only from wide gradings); reserving the upper bound, up to ten
        // times more for them, would only inflate the peak.
        let share = match part {
            None => 1.0,
            Some(_) => (domain.area_in_box(lo.x, hi.x, lo.y, hi.y) / domain.area()).min(1.0),
        };
        let expected = (share * domain.area() / scene.mean_disk_area())
            .min(scene.max_disks())
            .ceil() as usize;
        obs.reserve(expected);
        witness.reserve(expected);
        bound.reserve(expected);
        let margin = Point::new(r_max, r_max).coords;
        let mut index = Indexed {
            index: I::new(lo - margin, hi + margin, I::BUCKET_DIAMETERS * 2.0 * r_max),
            base: base as u32,
        };
        for (id, o) in obs.iter().enumerate().skip(base) {
            index.insert(id as u32, o.c);
        }
        // Wall disks, or a part's fixed disks, start the front list: lowest,
        // then leftmost, on top.
        let mut fronts: Vec<u32> = if scene.walls == WallMode::Disks {
            (0..first_packed as u32).collect()
        } else {
            let open = part.map_or(&[][..], |p| p.open);
            (corners..first_packed)
                .filter(|&i| open.get(i - corners).is_none_or(Option::is_some))
                .map(|i| i as u32)
                .collect()
        };
        fronts.sort_by(|&a, &b| lowest_first(obs[b as usize].c, obs[a as usize].c));
        Front {
            scene,
            cancel,
            budget: part.map_or_else(|| work_budget(scene), |p| p.budget),
            next_look: WORK_STEP,
            tests: Cell::new(0),
            ceiling: super::disk_ceiling(scene),
            placed: part.map(|p| p.placed),
            region: part.map(|p| p.region),
            near_edge: false,
            raster: part.is_some_and(|p| p.raster),
            restarted: false,
            row_spots: Vec::new(),
            refused: Cell::new(0),
            refused_fronts: Vec::new(),
            handoff: BTreeMap::new(),
            outside: Vec::new(),
            walls,
            periodic: scene.walls == WallMode::Periodic,
            origin: domain
                .period()
                .filter(|_| scene.walls == WallMode::Periodic)
                .map(|period| (domain.bounds().0 + period / 4.0, period)),
            obs,
            coverer: vec![u32::MAX; runs.len()],
            runs,
            near_runs: Vec::new(),
            first_packed,
            index,
            witness,
            bound,
            r_min: scene.d_min() / 2.0,
            r_max,
            r_retire: scene.d_min() / 2.0 * RETIRE_RATIO,
            fronts,
            parked: Vec::new(),
            deferred: VecDeque::new(),
            sizer: Sizer::new(scene),
            tags: Vec::new(),
            angles: Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ ANGLE_STREAM),
            stats: PackStats::default(),
            near: Vec::new(),
            cands: Vec::new(),
            wall_points: Vec::new(),
            spots: Vec::new(),
            arcs: Arcs::new(Measure::Radians),
            last_blocker: Cell::new(0),
            near_all: Vec::new(),
        }
    }

    fn robust(&self) -> bool {
        self.scene.packer.rules == FrontRules::Robust
    }

    /// Pack with the sizes the genes draw until they run out (or the
    /// sizes fit nowhere); in a part, with which disks stay open.
    fn pack(mut self, mut genes: impl Iterator<Item = f64>) -> Result<PartPacking, PackError> {
        if self.periodic {
            // The first two sizes: one disk at the rank's origin, the next
            // touching it (no wall offers a second contact yet).
            for u in genes.by_ref() {
                self.stats.sizes_drawn += 1;
                let (d, tag) = self.sizer.size(u, self.growth_point());
                let seeded = self.seed(d / 2.0, tag)?;
                self.account()?;
                if !seeded {
                    self.stats.sizes_deferred += 1;
                    self.stats.sizes_unplaced += 1;
                }
                if self.obs.len() >= 2 {
                    break;
                }
            }
        }
        if self.scene.walls == WallMode::Exact && self.fronts.is_empty() {
            // The first disk sits in the lowest corner (a part's lowest
            // spot); retry smaller sizes if it does not fit. A part with
            // fixed disks grows from them.
            for u in genes.by_ref() {
                self.stats.sizes_drawn += 1;
                let (d, tag) = self.sizer.size(u, self.growth_point());
                let seeded = self.seed(d / 2.0, tag)?;
                self.account()?;
                if seeded {
                    break;
                }
                self.stats.sizes_deferred += 1;
                self.stats.sizes_unplaced += 1;
            }
        }
        let mut retry_deferred = false;
        loop {
            let (r, tag, tries) = match (retry_deferred, self.deferred.pop_front()) {
                (true, Some(entry)) => entry,
                (_, entry) => {
                    if let Some(entry) = entry {
                        self.deferred.push_front(entry);
                    }
                    let Some(u) = genes.next() else { break };
                    self.stats.sizes_drawn += 1;
                    let (d, tag) = self.sizer.size(u, self.growth_point());
                    (d / 2.0, tag, 0)
                }
            };
            if self.place_size(r, tag)? {
                retry_deferred = !self.deferred.is_empty();
                continue;
            }
            retry_deferred = false;
            if !self.robust() {
                break;
            }
            let exhausted = self.fronts.is_empty() && self.parked.is_empty();
            if exhausted && r <= self.r_retire {
                if self.fill_hole(r, tag)? {
                    continue;
                }
                break;
            }
            if tries == 0 {
                self.stats.sizes_deferred += 1;
            }
            if tries >= DEFERRED_RETRIES {
                self.stats.sizes_unplaced += 1;
            } else if self.deferred.len() >= self.scene.packer.max_deferred {
                if self.fill_hole(r, tag)? {
                    continue;
                }
                self.stats.sizes_unplaced += 1;
                break;
            } else {
                self.deferred.push_back((r, tag, tries + 1));
            }
        }
        self.stats.sizes_unplaced += self.deferred.len() as u64;
        let mut open = Vec::new();
        if self.region.is_some() {
            // The refused first: sorted stably, they win over the same disk
            // as a front.
            for &f in &self.refused_fronts {
                let outside = self.handoff.get(&f).copied().flatten();
                let w = self.witness[f as usize];
                open.push((f, outside.map_or(Opening::FRESH, |o| merged(w, o))));
            }
            let fronts = self.fronts.iter().chain(self.parked.iter().map(|(_, f)| f));
            for &f in fronts {
                let (witness, bound) = (self.witness[f as usize], self.bound[f as usize]);
                open.push((f, Opening { witness, bound }));
            }
            open.sort_by_key(|&(f, _)| f);
            open.dedup_by_key(|&mut (f, _)| f);
            let first = self.first_packed as u32;
            open.retain(|&(f, _)| f >= first);
            for (f, _) in &mut open {
                *f -= first;
            }
        }
        let (boundary, fixed) = match self.scene.walls {
            WallMode::Disks => (self.obs.drain(..self.first_packed).collect(), 0),
            WallMode::Exact | WallMode::Periodic => {
                // A part keeps the disks it was packed against ahead of its own.
                let fixed = if self.region.is_some() {
                    self.first_packed
                } else {
                    0
                };
                self.obs.drain(..self.first_packed - fixed);
                (Vec::new(), fixed)
            }
        };
        Ok(PartPacking {
            packing: Packing {
                domain: self.scene.domain.clone(),
                walls: self.scene.walls,
                boundary,
                disks: self.obs,
                grains: Vec::new(),
                materials: self.tags,
                stats: self.stats,
            },
            fixed,
            open,
        })
    }

    /// Count the work done since the last call in `stats.work` and, every
    /// [`WORK_STEP`], look at the cancel token and the budget.
    ///
    /// # Errors
    /// [`PackError::Cancelled`] once the token is raised,
    /// [`PackError::WorkBudget`] once the work passes the budget.
    fn account(&mut self) -> Result<(), PackError> {
        self.stats.work += self.tests.take();
        if self.stats.work < self.next_look {
            return Ok(());
        }
        self.next_look = self.stats.work.saturating_add(WORK_STEP);
        self.cancel.check()?;
        if self.stats.work > self.budget {
            return Err(PackError::WorkBudget {
                budget: self.budget,
                disks: (self.obs.len() - self.first_packed) as u64,
                sizes_drawn: self.stats.sizes_drawn,
            });
        }
        Ok(())
    }

    /// Where the packing grows: the front on top of the stack, else the last
    /// disk placed, else the domain's lowest corner (where the first disk goes).
    fn growth_point(&self) -> Point {
        self.fronts
            .last()
            .map(|&f| self.obs[f as usize].c)
            .or_else(|| self.obs[self.first_packed..].last().map(|d| d.c))
            .unwrap_or_else(|| self.scene.domain.bounds().0)
    }

    /// Place one disk of radius `r` and material `tag` at some front; `false` if it fits at none.
    ///
    /// # Errors
    /// As [`Front::account`].
    fn place_size(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
        // The first disk takes two contacts: with wall disks, one-contact
        // disks could not keep their gap from the wall disks around them.
        let one_contact = self.obs.len() > self.first_packed && self.one_contact();
        loop {
            while let Some(&f) = self.fronts.last() {
                self.stats.work += 1;
                self.account()?;
                let bound = f64::from(self.bound[f as usize]);
                if r >= bound {
                    // Measured too small for this size before: no attempt.
                    self.fronts.pop();
                    self.park(f, bound);
                    continue;
                }
                if self.witnesses_closed(f) || self.wall_front_closed(f) {
                    self.fronts.pop();
                    continue;
                }
                let (f, placed) = match self.restarted && !one_contact {
                    true => match self.row_start(f, r) {
                        // Attempted in full next time (see `row_start`).
                        Some((g, p)) => (g, Some((p, 2))),
                        None => (f, self.attempt_counted(f, r, false)),
                    },
                    false => (f, self.attempt_counted(f, r, one_contact)),
                };
                match placed {
                    Some((p, _)) if self.turns_back(f, p) => {
                        self.restart(f);
                        continue;
                    }
                    Some((p, feasible)) => {
                        self.restarted = false;
                        if feasible < 2 {
                            self.fronts.pop();
                            self.park(f, r);
                        }
                        self.place(p, r, tag)?;
                        return Ok(true);
                    }
                    None => {
                        self.witness[f as usize] = NO_WITNESS;
                        self.fronts.pop();
                        if !self.robust() || r <= self.r_retire {
                            self.park(f, r);
                        } else {
                            let bound = self.room_left(f, r, one_contact);
                            if self.refused.get() > 0 {
                                // Spots refused at other radii: not handed on.
                                self.handoff.insert(f, None);
                            }
                            self.note_refused(f);
                            if let Some(bound) = bound {
                                self.bound[f as usize] = (bound as f32).next_up();
                                self.park(f, bound);
                            }
                        }
                    }
                }
            }
            if !self.robust() || !self.wake(r) {
                break;
            }
        }
        // A loose pack grows from its first disk only: a disk seeded later in a
        // corner could stay touching no other disk.
        let loose = self.scene.packer.one_contact_share > 0.0;
        let seeded =
            self.robust() && !(loose && self.obs.len() > self.first_packed) && self.seed(r, tag)?;
        self.account()?;
        Ok(seeded)
    }

    /// [`Front::attempt`], counted, its refused spots noted.
    fn attempt_counted(&mut self, f: u32, r: f64, one_contact: bool) -> Option<(Point, usize)> {
        self.stats.front_attempts += 1;
        let placed = self.attempt(f, r, one_contact);
        self.note_refused(f);
        placed
    }

    /// Place a disk of radius `r` and material `tag` at `p`.
    ///
    /// # Errors
    /// The scene's particle or memory limit, when this disk would pass it.
    fn place(&mut self, p: Point, r: f64, tag: u16) -> Result<(), PackError> {
        if let Some((max, error)) = &self.ceiling {
            let placed = match self.placed {
                Some(all) => all.fetch_add(1, Ordering::Relaxed),
                None => (self.obs.len() - self.first_packed) as u64,
            };
            if placed >= *max {
                return Err(error.clone());
            }
        }
        let id = self.obs.len() as u32;
        // In a periodic cell the centre is stored in the cell (the identity elsewhere).
        let p = self.scene.domain.wrap(p);
        self.obs.push(Disk { c: p, r });
        if self.sizer.graded() {
            self.tags.push(tag);
        }
        self.witness.push(NO_WITNESS);
        self.bound.push(f32::INFINITY);
        self.index.insert(id, p);
        self.fronts.push(id);
        Ok(())
    }
}

/// The spatial index over the obstacles it holds: ids from `base` on (the
/// packed disks, and wall disks that are not in runs), stored from 0.
struct Indexed<I> {
    index: I,
    base: u32,
}

impl<I: SpatialIndex> Indexed<I> {
    /// Add obstacle `id` (at least `base`, ids in order) at `p`.
    fn insert(&mut self, id: u32, p: Point) {
        self.index.insert(id - self.base, p);
    }

    /// [`SpatialIndex::try_visit_box`] with obstacle ids.
    #[inline]
    fn try_visit_box(
        &self,
        lo: Point,
        hi: Point,
        mut f: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let base = self.base;
        self.index.try_visit_box(lo, hi, |id| f(id + base))
    }

    /// [`SpatialIndex::any_in_box`] with obstacle ids.
    #[inline]
    fn any_in_box(&self, lo: Point, hi: Point, mut pred: impl FnMut(u32) -> bool) -> bool {
        let base = self.base;
        self.index.any_in_box(lo, hi, |id| pred(id + base))
    }

    /// [`SpatialIndex::visit_box`] with obstacle ids.
    #[inline]
    fn visit_box(&self, lo: Point, hi: Point, mut f: impl FnMut(u32)) {
        let _ = self.try_visit_box(lo, hi, |id| {
            f(id);
            ControlFlow::Continue(())
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grading::{Basis, Grading, Interpolation};
    use crate::{Limits, pack};

    /// A square of `side` mm with diameters 0.02 to 4 mm, uniform by 3D
    /// mass: nearly every size is fine, the few large ones hold the mass.
    fn wide_by_mass(side: f64) -> Scene {
        let grading = Grading::from_table(
            &[(0.02, 0.0), (4.0, 100.0)],
            Interpolation::Linear,
            Basis::Mass3d,
        )
        .unwrap();
        Scene::new(Domain::rectangle(side, side).unwrap(), grading).with_seed(1)
    }

    #[test]
    fn a_wide_grading_by_mass_costs_a_few_thousand_tests_per_disk() {
        // Each large size was tested at every front among thousands of
        // fine neighbours, every candidate against every neighbour from the
        // first: 90,000 tests per disk on an 8 mm square, growing with the
        // square (a 20 mm square packed for 1,140 s). Now the likely
        // blocker is tested first, and smaller radii skip the neighbours
        // out of their reach.
        let packing = pack(&wide_by_mass(3.0)).unwrap();
        let per_disk = packing.stats.work as f64 / packing.disks.len() as f64;
        assert!(packing.disks.len() > 3000, "{}", packing.disks.len());
        assert!(per_disk < 20_000.0, "{per_disk:.0} units of work per disk");
    }

    #[test]
    fn the_disks_packed_never_pass_the_scenes_upper_bound() {
        // The old bound, the domain filled solid with disks of the mean
        // area, said "at most 318" for this scene, which packs 2,369.
        let grading = Grading::from_table(
            &[(0.01, 0.0), (10.0, 100.0)],
            Interpolation::Linear,
            Basis::Mass,
        )
        .unwrap();
        let scene = Scene::new(Domain::rectangle(5.0, 5.0).unwrap(), grading).with_seed(1);
        let packing = pack(&scene).unwrap();
        assert!(
            packing.disks.len() as f64 > scene.domain.area() / scene.mean_disk_area(),
            "the scene no longer shows what the mean-area bound missed"
        );
        assert!(packing.disks.len() as f64 <= scene.max_disks());
        assert!(scene.max_disks() as u64 == size_count(&scene.domain, scene.d_min()));
    }

    #[test]
    fn a_run_stops_with_an_error_once_its_work_budget_is_spent() {
        let scene = wide_by_mass(3.0);
        let cancel = Cancel::new();
        let mut front = Front::<Grid>::new(&scene, &cancel, None);
        front.budget = 1 << 16;
        front.next_look = 0;
        let genes = (0..10_000).map(|i| f64::from(i % 97) / 97.0);
        match front.pack(genes).map(|p| p.packing) {
            Err(PackError::WorkBudget { budget, disks, .. }) => {
                assert_eq!(budget, 1 << 16);
                assert!(disks < 5000, "{disks}");
            }
            other => panic!("{:?}", other.map(|p| p.disks.len())),
        }
        // The default budget is far above what an ordinary scene uses.
        let packing = pack(&scene).unwrap();
        assert!(packing.stats.work * 8 < work_budget(&scene));
    }

    #[test]
    fn a_run_looks_at_its_cancel_token_between_sizes_not_only_between_draws() {
        // The token was looked at only every 4,096 sizes drawn: a run whose
        // sizes each took tens of milliseconds ignored Ctrl-C for minutes.
        let scene = wide_by_mass(3.0);
        let cancel = Cancel::new();
        cancel.cancel();
        let mut front = Front::<Grid>::new(&scene, &cancel, None);
        front.next_look = 0;
        let genes = std::iter::repeat_n(0.5, 100);
        assert!(matches!(
            front.pack(genes).map(|p| p.packing),
            Err(PackError::Cancelled(crate::cancel::Cancelled::Flag))
        ));
    }

    #[test]
    fn every_method_stops_at_the_particle_and_memory_ceilings() {
        let scene = Scene::new(
            Domain::rectangle(12.0, 12.0).unwrap(),
            Grading::constant(1.0).unwrap(),
        )
        .with_seed(3);
        for method in [
            crate::Method::AdvancingFront,
            crate::Method::Rsa,
            crate::Method::Deposition,
            crate::Method::Relaxation,
            crate::Method::Densify,
        ] {
            let scene = scene.clone().with_method(method);
            let free = pack(&scene).unwrap();
            let n = free.disks.len() as u64;
            assert!(n > 50, "{method:?}: {n}");
            let limited = |limits| pack(&scene.clone().with_limits(limits));
            // At the count packed, the same packing; one fewer, an error.
            let same = limited(Limits::none().with_max_particles(n)).unwrap();
            assert_eq!(same.disks, free.disks, "{method:?}");
            assert_eq!(
                limited(Limits::none().with_max_particles(n - 1)).unwrap_err(),
                PackError::ParticleLimit { limit: n - 1 },
                "{method:?}"
            );
            let bytes = (n - 1) as f64 * crate::packer::PEAK_BYTES_PER_DISK;
            assert!(
                matches!(
                    limited(Limits::none().with_max_memory_bytes(bytes)),
                    Err(PackError::MemoryLimit { disks, .. }) if disks == n - 1
                ),
                "{method:?}"
            );
        }
    }

    #[test]
    fn wall_disks_are_neither_attempted_nor_visited_one_by_one() {
        // A 2.6 × 300 mm slot of the thesis' wells: 6,000 wall disks. Each
        // was attempted as a front and visited by every neighbour search
        // near its wall (186,000 attempts for 12,700 disks on the 8 m
        // well); covered ones now leave without an attempt, and the wall
        // disks met are a few per edge.
        let grading =
            Grading::from_table(crate::THESIS_TABLE_3_4, Interpolation::Log, Basis::Number)
                .unwrap();
        let domain = Domain::rectangle(2.6, 300.0).unwrap();
        for rules in [FrontRules::Thesis, FrontRules::Robust] {
            let mut scene = Scene::new(domain.clone(), grading.clone())
                .with_walls(WallMode::Disks)
                .with_seed(2);
            scene.packer.rules = rules;
            let packing = pack(&scene).unwrap();
            let (disks, walls) = (packing.disks.len() as u64, packing.boundary.len() as u64);
            assert!(
                walls > 5000 && disks > 400,
                "{walls} wall disks, {disks} disks"
            );
            let attempts = packing.stats.front_attempts;
            assert!(attempts < 3 * disks, "{rules:?}: {attempts} attempts");
            let per_disk = packing.stats.work / disks;
            assert!(
                per_disk < 600,
                "{rules:?}: {per_disk} units of work per disk"
            );
            let m = crate::measure(&packing, &scene);
            assert!(m.max_overlap <= crate::OVERLAP_REL, "{}", m.max_overlap);
            let outside = -crate::OVERLAP_REL * scene.d_max();
            assert!(m.min_wall_clearance >= outside, "{}", m.min_wall_clearance);
        }
    }
}
