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
//! first disk sits at the cell's centre and the second touches it (the
//! only disk placed with one contact in a dense pack); every later one is
//! placed as above, with two changes. Every index query is made once per
//! lattice shift whose images may meet its box ([`Domain::image_shifts`]:
//! one query inside the cell, two or four near its edges), each obstacle
//! found being met as that image, so the neighbours, the witnesses and the
//! holes see across the edges and memory stays one entry per disk; a
//! centre is wrapped into the cell when the disk is placed. And the winning
//! candidate is the nearest the first disk's centre (its nearest image),
//! not the lowest (see `Front::rank`). A domain with walls makes one query
//! with the zero shift and ranks every candidate 0: the same packings, bit
//! for bit.
//!
//! [`PackerSettings::one_contact_share`]: super::PackerSettings::one_contact_share
//! [`PackerSettings::gap`]: super::PackerSettings::gap

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
use crate::geometry::predicates::{
    FEASIBLE_REL, WITNESS_REL, chord_of_offset, clear_disk_disk, clear_disk_walls,
    intersect_circle_circle, intersect_circle_line, max_radius_ray_disk,
};
use crate::geometry::{Disk, Domain, Point, Wall, WallMode};

/// Fronts that fail for a radius within this factor of the smallest are retired, not parked:
/// a gap that refuses such a disk has no room for any size of the grading worth a retry.
const RETIRE_RATIO: f64 = 1.1;

/// Precision of the bound a failing front is parked with: the largest radius
/// it can still take is known to within this factor.
const BOUND_RATIO: f64 = 1.02;

/// Retries of one deferred size before it is given up.
const DEFERRED_RETRIES: u32 = 32;

/// Random angles tried on the free arcs before a one-contact placement falls back to two contacts.
const ONE_CONTACT_TRIES: usize = 16;

/// Relative margin on the distance at which a neighbour is left out of a
/// smaller radius's attempt (`Front::near_for`): far above the rounding of
/// candidates (relative 1e-10 of the halo's radius at the coarsest
/// resolution a config allows) and the tangency slack of halo intersections.
const REACH_REL: f64 = 1e-6;

/// Relative margin on the reach of a front's halo when deciding that no wall is near.
const WALL_MARGIN_REL: f64 = 1e-9;

/// Relative margin by which a packed disk's halo must hold a wall disk's
/// zone to cover it (`Front::covered`): far above the rounding of the
/// candidates an attempt would test.
const COVER_REL: f64 = 1e-9;

/// Stream offset so one-contact angles never share random numbers with the sizes.
const ANGLE_STREAM: u64 = 0x9E37_79B9_7F4A_7C15;

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
/// [`PROGRESS_STEP`] and stopping once `cancel` is raised.
///
/// # Errors
/// As [`pack_genes`], and [`PackError::Cancelled`] when stopped.
pub fn pack_genes_watched(
    scene: &Scene,
    genes: impl Iterator<Item = f64>,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
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

/// The opening of a disk with candidates refused for lying outside its
/// part's region: its free spots inside and outside, when they fit the
/// witnesses' slots (else [`Opening::FRESH`]); its bound was measured
/// inside the region only, so it is not handed on.
fn merged(inside: Witnesses, outside: Witnesses) -> Opening {
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
}

/// Work between two looks at the cancel token inside a run (neighbours
/// visited and tested, candidates made): a few milliseconds, however slowly
/// the sizes go (a wide grading once spent four minutes between two looks
/// made every [`PROGRESS_STEP`] sizes).
const WORK_STEP: u64 = 1 << 20;

/// The most work a run may do per disk the domain could hold
/// ([`Scene::max_disks`]), beyond [`WORK_FLOOR`] (see [`work_budget`]).
pub const WORK_PER_DISK: u64 = 1 << 14;

/// Work any run may do, however few disks its domain holds.
pub(super) const WORK_FLOOR: u64 = 1 << 30;

/// The most work the advancing front may do on `scene` before it stops with
/// [`PackError::WorkBudget`]: [`WORK_PER_DISK`] per disk the domain could
/// hold ([`Scene::max_disks`]) and per wall disk, plus [`WORK_FLOOR`].
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

/// Disks around a hole tried for a two-contact placement, at most.
const HOLE_FRONTS: usize = 32;

/// Free spots a front remembers, at most.
const WITNESSES: usize = 3;

/// A front's remembered free spots: unit directions from its centre in
/// units of 1/[`WITNESS_SCALE`], unused slots `[0, 0]`. Coarse on purpose (an
/// angle within 3e-5 rad): they only decide whether to make an exact attempt,
/// and [`WITNESS_REL`] is far wider than their rounding.
type Witnesses = [[i16; 2]; WITNESSES];

/// Scale of the witness directions' components.
const WITNESS_SCALE: f64 = i16::MAX as f64;

/// Witnesses of a front with none: a fresh front, one whose last full attempt
/// failed, or one whose last spots were found for a disk larger than `r_retire`
/// (they say nothing of the narrower gaps smaller disks fit).
const NO_WITNESS: Witnesses = [[0; 2]; WITNESSES];

/// The witness of a free spot at `q` of a front centred at `c`: the
/// direction from `c`, scaled by [`WITNESS_SCALE`].
fn witness_of(c: Point, q: Point) -> [i16; 2] {
    let (dx, dy) = (q.x - c.x, q.y - c.y);
    let k = WITNESS_SCALE / (dx * dx + dy * dy).sqrt();
    [(dx * k).round() as i16, (dy * k).round() as i16]
}

/// A neighbour of the current front: its centre relative to the front's
/// (`rel`), and its squared clearance for the new radius (`clear_disk_disk`
/// in one comparison).
#[derive(Clone, Copy)]
struct Near {
    disk: Disk,
    rel: Point,
    clear2: f64,
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
struct Cand {
    at: Point,
    off: Point,
    /// Index in `near` of the neighbour whose halo it lies on (`u32::MAX`: a wall's).
    src: u32,
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
    /// In a periodic cell, the first disk's centre (the cell's centre) and
    /// the periods: candidates nearest it go first (see `Front::rank`).
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
            refused: Cell::new(0),
            refused_fronts: Vec::new(),
            handoff: BTreeMap::new(),
            outside: Vec::new(),
            walls,
            periodic: scene.walls == WallMode::Periodic,
            origin: domain
                .period()
                .filter(|_| scene.walls == WallMode::Periodic)
                .map(|period| (domain.centroid(), period)),
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
            // The first two sizes: one disk at the cell's corner, the next
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
                self.stats.front_attempts += 1;
                let placed = self.attempt(f, r, one_contact);
                self.note_refused(f);
                match placed {
                    Some((p, feasible)) => {
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
    fn fill_hole(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
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

    /// Remember front `f` as open for later parts if its last attempt had
    /// a candidate refused only by the part's region.
    fn note_refused(&mut self, f: u32) {
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
    fn hand_off(&mut self, f: u32, r: f64, best: Option<Point>) {
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

    /// A front that failed for `r`: parked for smaller sizes (robust rules) or dropped.
    fn park(&mut self, f: u32, r: f64) {
        if self.robust() && r > self.r_retire {
            self.parked.push((r, f));
        }
    }

    /// Move the parked fronts that failed only for sizes larger than `r` back on the stack.
    fn wake(&mut self, r: f64) -> bool {
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

    /// Whether the next size touches its front only: always, never, or drawn
    /// with probability `one_contact_share` (the draw only when it is strictly
    /// between 0 and 1, so dense and loose runs keep their random streams).
    fn one_contact(&mut self) -> bool {
        let share = self.scene.packer.one_contact_share;
        share >= 1.0 || (share > 0.0 && self.angles.r#gen::<f64>() < share)
    }

    /// Try to place a disk of radius `r` around front `f`: the position and
    /// how many feasible candidates there were (capped at 2).
    fn attempt(&mut self, f: u32, r: f64, one_contact: bool) -> Option<(Point, usize)> {
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
            // Lowest first; in a periodic cell, nearest the first disk first
            // (see `Front::rank`).
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
                let key = self.rank(p);
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
    fn witnesses_closed(&mut self, f: u32) -> bool {
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
    fn wall_front_closed(&mut self, f: u32) -> bool {
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
    fn room_left(&mut self, f: u32, r: f64, one_contact: bool) -> Option<f64> {
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

    /// Neighbours of front `f` whose halo, widened by `gap` radii, meets the
    /// front's halo, into `self.near`; the runs of wall disks within the
    /// same reach into `self.near_runs` (their disks are not neighbours:
    /// `tangent_candidates` and `feasible` take the few that matter).
    fn gather_neighbours(&mut self, f: u32, r: f64, gap: f64) {
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
    fn tangent_candidates(&mut self, f: u32, r: f64, near_wall: bool) {
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
    fn run_blocks(&self, f: u32, p: Point, off: Point, r: f64, gap: f64) -> bool {
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
    fn feasible(&self, f: u32, cand: &Cand, r: f64, near_wall: bool) -> bool {
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

    /// One-contact placement: a random point of the free arcs of the front's
    /// halo, `gap` radii clear of every other disk and inside the domain.
    fn free_angle(&mut self, f: u32, r: f64, gap: f64) -> Option<Point> {
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
    fn free_arcs(&mut self, f: u32, r: f64, gap: f64, measure: Measure) -> f64 {
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

    /// Exact walls: put a disk of radius `r` at the lowest feasible wall–wall
    /// tangency; `false` if none is clear.
    ///
    /// # Errors
    /// As [`Front::place`].
    fn seed(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
        if self.periodic {
            return self.seed_cell(r, tag);
        }
        let mut spots = Vec::new();
        let walls = self.walls.len() as u64;
        self.stats.work += walls * walls.saturating_sub(1) / 2;
        for (i, a) in self.walls.iter().enumerate() {
            for b in &self.walls[i + 1..] {
                wall_wall_spots(a, b, r, &mut spots);
            }
            if let Wall::Circle { center, radius } = *a {
                spots.push(Point::new(center.x, center.y - (radius - r)));
            }
            // A part's lowest spots may lie on its sides, on one wall.
            if let Some(region) = self.region {
                for &plane in &region.planes {
                    wall_spot_on_line(a, r, plane, &mut spots);
                }
            }
        }
        if let Some(region) = self.region {
            spots.retain(|&p| region.contains(p));
        }
        spots.sort_unstable_by(|a, b| lowest_first(*a, *b));
        for p in spots {
            let half = r + self.r_max;
            let (lo, hi) = (
                Point::new(p.x - half, p.y - half),
                Point::new(p.x + half, p.y + half),
            );
            let mut clear = clear_disk_walls(&self.scene.domain, p, r);
            let (obs, tests) = (&self.obs, &self.tests);
            tests.set(tests.get() + 1 + walls);
            self.index.visit_box(lo, hi, |id| {
                tests.set(tests.get() + 1);
                let o = &obs[id as usize];
                clear &= clear_disk_disk(p, r, o.c, o.r);
            });
            if clear {
                self.place(p, r, tag)?;
                return Ok(true);
            }
        }
        Ok(false)
    }
}

impl<I: SpatialIndex> Front<'_, I> {
    /// Whether a disk centred within `reach` of `c` may meet a wall: never
    /// in a periodic cell.
    fn near_wall(&self, c: Point, reach: f64) -> bool {
        !self.periodic && self.scene.domain.signed_distance(c) <= reach
    }

    /// Whether a disk centred within `reach` of `c` may lie outside the
    /// part's region: never in one piece.
    fn near_edge(&self, c: Point, reach: f64) -> bool {
        self.region
            .is_some_and(|region| !region.inside_by(c, reach))
    }

    /// The rank of a candidate at `p`, lower first (then lowest, then
    /// leftmost: [`first_of`]): 0 everywhere with walls, so the lowest
    /// goes first and the pack deposits layer on layer from the bottom. In a
    /// periodic cell, the squared distance from the first disk's centre (the
    /// cell's centre) to the nearest image of `p`: the pack grows out from
    /// its first disk as a round cluster and closes on its own images along
    /// the cell's edges, two rough fronts meeting (the 1 mm bands along the
    /// edges: porosity 0.27 to 0.32, against 0.18 to 0.20 inside; 50 × 100
    /// mm, 1–1.66 mm, 20 seeds). Filled lowest first, the cell grew from a
    /// row of disks centred on its bottom edge, which the last layers met
    /// like a wall of disks: the band below the top edge reached 0.50.
    /// Grown as a horizontal band (nearest in y only), a row formed along
    /// the middle (two bands of 0.13 flanked by 0.22).
    #[inline]
    fn rank(&self, p: Point) -> f64 {
        match self.origin {
            None => 0.0,
            Some((o, period)) => {
                let near = |d: f64, w: f64| d - w * (d / w).round();
                let (dx, dy) = (near(p.x - o.x, period.x), near(p.y - o.y, period.y));
                dx * dx + dy * dy
            }
        }
    }

    /// Periodic cell: put a disk of radius `r` at the cell's centre when
    /// it is empty, or touching the first disk on its right when that is
    /// the only one; `false` otherwise, or if the spot is not clear of
    /// every image.
    ///
    /// # Errors
    /// As [`Front::place`].
    fn seed_cell(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
        let p = match &self.obs[self.first_packed..] {
            [] => self.scene.domain.centroid(),
            [first] => Point::new(first.c.x + first.r + r, first.c.y),
            _ => return Ok(false),
        };
        let half = r + self.r_max;
        let (lo, hi) = (
            Point::new(p.x - half, p.y - half),
            Point::new(p.x + half, p.y + half),
        );
        let (obs, tests) = (&self.obs, &self.tests);
        let blocked = any_image(&self.index, &self.scene.domain, lo, hi, |id, v| {
            tests.set(tests.get() + 1);
            let o = &obs[id as usize];
            !clear_disk_disk(p, r, image(o.c, v), o.r)
        });
        if blocked {
            return Ok(false);
        }
        self.place(p, r, tag)?;
        Ok(true)
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

/// `c` moved by the lattice shift `v`; `c` itself, bit for bit, for the
/// zero shift (every obstacle of a domain with walls).
#[inline]
fn image(c: Point, v: Vector2<f64>) -> Point {
    if v == Vector2::zeros() { c } else { c + v }
}

/// Visit every obstacle in the box `lo`–`hi` (and perhaps a few beyond)
/// until `f` breaks: `f(id, v)` for obstacle `id` met as its image shifted
/// by `v`. A domain with walls makes one query with `v` zero; a periodic
/// cell one per lattice shift whose images may meet the box
/// ([`Domain::image_shifts`]), so an obstacle may come once per image.
#[inline]
fn visit_images<I: SpatialIndex>(
    index: &Indexed<I>,
    domain: &Domain,
    lo: Point,
    hi: Point,
    mut f: impl FnMut(u32, Vector2<f64>) -> ControlFlow<()>,
) -> ControlFlow<()> {
    if !domain.is_periodic() {
        return index.try_visit_box(lo, hi, |id| f(id, Vector2::zeros()));
    }
    for v in domain.image_shifts(lo, hi) {
        index.try_visit_box(lo - v, hi - v, |id| f(id, v))?;
    }
    ControlFlow::Continue(())
}

/// Whether `pred(id, v)` holds for some obstacle image in the box `lo`–`hi`
/// (see [`visit_images`]), stopping at the first that does.
#[inline]
fn any_image<I: SpatialIndex>(
    index: &Indexed<I>,
    domain: &Domain,
    lo: Point,
    hi: Point,
    mut pred: impl FnMut(u32, Vector2<f64>) -> bool,
) -> bool {
    visit_images(index, domain, lo, hi, |id, v| {
        if pred(id, v) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    })
    .is_break()
}

/// Order candidates by rank ([`Front::rank`]), then lowest first, then leftmost.
#[inline]
fn first_of(rank_a: f64, a: Point, rank_b: f64, b: Point) -> std::cmp::Ordering {
    rank_a.total_cmp(&rank_b).then_with(|| lowest_first(a, b))
}

/// Order points lowest first, then leftmost (deposition under gravity).
fn lowest_first(a: Point, b: Point) -> std::cmp::Ordering {
    a.y.total_cmp(&b.y).then(a.x.total_cmp(&b.x))
}

/// Centres of disks of radius `r` tangent to `wall` on the domain side, on the circle (`c`, `rf`).
fn wall_candidates(wall: &Wall, c: Point, rf: f64, r: f64, out: &mut Vec<Point>) {
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

/// The centre of a disk of radius `r` tangent to straight `wall` (inside)
/// on the line `a·x + b·y = c` of `plane` (`[a, b, c]`), if there is one: a
/// part's lowest spot where its side meets a wall.
fn wall_spot_on_line(wall: &Wall, r: f64, [a, b, c]: [f64; 3], out: &mut Vec<Point>) {
    let Wall::Segment { a: p, b: q } = *wall else {
        return;
    };
    let len = (q - p).norm();
    let (ux, uy) = ((q.x - p.x) / len, (q.y - p.y) / len);
    let o = Point::new(p.x - uy * r, p.y + ux * r); // offset inward (left) by r
    let along = a * ux + b * uy;
    if along.abs() > 1e-12 {
        let t = (c - a * o.x - b * o.y) / along;
        if (0.0..=len).contains(&t) {
            out.push(Point::new(o.x + ux * t, o.y + uy * t));
        }
    }
}

/// Centres of disks of radius `r` tangent to both walls (inside), for seeding.
fn wall_wall_spots(a: &Wall, b: &Wall, r: f64, out: &mut Vec<Point>) {
    let offset = |w: &Wall| match *w {
        Wall::Segment { a, b } => {
            let len = (b - a).norm();
            let u = (b - a) / len;
            Some((Point::new(a.x - u.y * r, a.y + u.x * r), u, len))
        }
        Wall::Circle { .. } => None,
    };
    let (Some((p, u, lu)), Some((q, v, lv))) = (offset(a), offset(b)) else {
        return;
    };
    let det = u.x * (-v.y) - u.y * (-v.x);
    if det.abs() < 1e-12 {
        return;
    }
    let w = q - p;
    let t = (w.x * (-v.y) - w.y * (-v.x)) / det;
    let s = (u.x * w.y - u.y * w.x) / det;
    let (ta, sa) = (lu * 1e-12, lv * 1e-12);
    if t >= -ta && t <= lu + ta && s >= -sa && s <= lv + sa {
        out.push(p + u * t);
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

    #[test]
    fn corner_spot_is_tangent_to_both_walls() {
        let bottom = Wall::Segment {
            a: Point::new(0.0, 0.0),
            b: Point::new(10.0, 0.0),
        };
        let left = Wall::Segment {
            a: Point::new(0.0, 10.0),
            b: Point::new(0.0, 0.0),
        };
        let mut out = Vec::new();
        wall_wall_spots(&bottom, &left, 0.5, &mut out);
        assert_eq!(out.len(), 1);
        assert!((out[0] - Point::new(0.5, 0.5)).norm() < 1e-12);
    }
}
