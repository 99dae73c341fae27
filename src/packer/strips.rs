//! One domain packed on every core: the advancing front in tiles laid
//! in strips and levels, packed along a diagonal wavefront
//! (docs/ARCHITECTURE.md, "Strips").
//!
//! # Behavior
//! The domain is cut into [`count`] strips, each of `COLUMNS_PER_STRIP`
//! columns, and the columns into levels: the tiles. The cut depends on the
//! scene only, never on the machine, so a packing is the same whatever the
//! number of threads. Each tile is packed by the advancing front from its
//! own seeded stream of sizes: its disks' centres stay in it (its sides are
//! open: a disk may stick out by its radius), and the disks packed before
//! within reach (the tile on its left, and the level below) are fixed
//! obstacles, and those their own tile left open are the fronts it grows
//! from (see `PartPacking::open`). A tile is packed once the tile on its
//! left and those below it are (`tiles`).
//!
//! Why this shape: a front closing sideways on a packed face leaves a layer
//! of voids along it, each row ending in a gap no size fills (porosity
//! 0.33–0.36 within a quarter diameter of such a seam, against 0.175
//! around; 1000 mm square of Table 3.4), while a front resting on packed
//! disks does not. So a tile rests on the level below, and its rows run
//! left to right only: each starts against the tile on its left, in the
//! corner of that tile's row end and its own row below, continuing that
//! row, and stops at the tile's right side, where the next tile continues
//! it (0.20–0.22 in the same quarter diameters at a face where every row
//! starts). Within 3 largest diameters of the seams the porosity is then
//! 0.179, as away from them (`gapack bench --seams`), where trapezoids
//! whose rows closed on every other seam gave 0.184 against 0.173.
//!
//! Zero overlaps and containment hold as in one piece: every candidate is
//! tested against every obstacle in reach, fixed ones included, and against
//! the domain's walls. Tiles packed at once are more than a largest
//! diameter apart, so their disks never meet. The scene's particle and
//! memory limits count the disks of every tile together.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock, PoisonError};

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::advancing_front::{
    Opening, Part, PartPacking, WORK_FLOOR, WORK_PER_DISK, pack_part, size_count_in,
};
use super::{FrontRules, PackError, PackStats, Packing, Strips};
use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
use crate::geometry::{Disk, Point, Shape, WallMode};

/// Scenes of more disks than this are split by [`Strips::Auto`].
pub const AUTO_DISKS: f64 = 200_000.0;

/// Fewest disks a strip holds, about, when [`Strips::Auto`] splits a scene.
const STRIP_DISKS: f64 = 50_000.0;

/// Narrowest strip [`Strips::Auto`] makes, in largest diameters.
const AUTO_WIDTH_DIAMETERS: f64 = 200.0;

/// Width of the strips [`Strips::Auto`] aims at, in largest diameters: the
/// wider, the fewer seams each tile packs around (10⁷ disks of Table
/// 3.4 in 7 or 8 strips packed some 5 % faster on two threads than in 14).
const AUTO_AIM_DIAMETERS: f64 = 400.0;

/// Fewest strips [`Strips::Auto`] cuts a scene into where strips of
/// [`AUTO_WIDTH_DIAMETERS`] allow it: with fewer, the tiles wait on
/// each other (10⁶ disks of Table 3.4 packed in 0.27–0.29 s on two threads
/// in 2 strips, 0.27 s in 3).
const AUTO_MIN_STRIPS: f64 = 3.0;

/// Narrowest strip a config may ask for, in largest diameters: its tiles
/// are then two wide and one high, and those packed at once still more
/// than one apart.
pub const MIN_WIDTH_DIAMETERS: f64 = 8.0;

/// Tile columns per strip: the tiles are packed along a diagonal wavefront
/// (see [`tiles`]) as long as the columns plus twice the levels; with one
/// column per strip, 10⁶ disks of Table 3.4 in 3 strips packed some 40 %
/// slower than with two.
const COLUMNS_PER_STRIP: usize = 2;

/// A tile's height over its column's width. The level lines, where rows
/// lie flat and in step on the level below, spread the porosity of the
/// cells near them more than the sloped sides do: on 1000 mm of Table 3.4
/// (`gapack bench --seams --seeds 5`) the cells within 3 largest diameters
/// of a seam spread 1.22 times the bulk's with tiles half as high as wide,
/// 1.19 times with square tiles (half as many level lines).
const TILE_HEIGHT: f64 = 1.0;

/// How far a tile's sides run across over its height, leaning left going
/// up: each row of a tile then ends no further right than the row below
/// it, so the next tile's rows start under no overhang. On 1000 mm of Table
/// 3.4 (2 seeds), the porosity within 3 largest diameters of the seams was
/// 0.1792 at a run of 0.4 or 0.6, 0.1804 at 0.8, 0.1808 at 1, 0.1827 at
/// 1.6, and 0.1828 with upright sides (0.1788–0.1793 away from them).
const SIDE_RUN: f64 = 0.5;

/// How far a tile reaches into those packed before it (below it and on its
/// left), in largest diameters, so that its disks settle into the hollows
/// of their surface. Where both sides of a seam kept their centres to one
/// line, each laid a row of disks along it as along a wall: the porosity
/// across a level's seam swung between 0.156 and 0.21 from one half
/// diameter to the next, against 0.178 in bulk.
const DIP_DIAMETERS: f64 = 0.5;

/// Why a scene cannot be packed in strips (`None`: it can): they need the
/// advancing front's dense robust packs in a rectangle with exact walls.
pub fn unsupported(scene: &Scene) -> Option<&'static str> {
    if !matches!(scene.domain.shape(), Shape::Rectangle { .. }) {
        Some("a rectangle")
    } else if scene.walls != WallMode::Exact {
        Some("walls = \"exact\"")
    } else if scene.packer.rules != FrontRules::Robust {
        Some("rules = \"robust\"")
    } else if scene.packer.one_contact_share > 0.0 {
        Some("dense packs (no one-contact placements)")
    } else {
        None
    }
}

/// How many strips the scene is cut into (at least 2), or `None` when it is
/// packed in one piece.
///
/// # Behavior
/// [`Strips::Auto`] splits scenes of more than [`AUTO_DISKS`] disks
/// ([`Scene::estimated_disks`]) that allow it into strips of about
/// `AUTO_AIM_DIAMETERS` largest diameters, but at least
/// `AUTO_MIN_STRIPS`, none narrower than `AUTO_WIDTH_DIAMETERS` nor
/// holding fewer than about `STRIP_DISKS` disks; [`Strips::Count`] into
/// that many. The strips are
/// taken in the frame the front fills in (a scene filled rightwards is cut
/// across its height).
pub fn count(scene: &Scene) -> Option<usize> {
    let (lo, hi) = scene.domain.bounds();
    let width = hi.x - lo.x;
    let count = match scene.packer.strips {
        Strips::Count(n) => n as usize,
        Strips::Auto => {
            let disks = scene.estimated_disks();
            if disks <= AUTO_DISKS || unsupported(scene).is_some() {
                return None;
            }
            let by_disks = (disks / STRIP_DISKS).ceil();
            let strips_of = |diameters: f64| (width / (diameters * scene.d_max())).floor();
            let aimed = strips_of(AUTO_AIM_DIAMETERS).max(AUTO_MIN_STRIPS);
            by_disks.min(strips_of(AUTO_WIDTH_DIAMETERS)).min(aimed) as usize
        }
    };
    (count >= 2).then_some(count)
}

/// The abscissae `count` strips of equal width cut the scene's domain at,
/// from its left side to its right (both included).
pub fn cuts(scene: &Scene, count: usize) -> Vec<f64> {
    let (lo, hi) = scene.domain.bounds();
    let step = (hi.x - lo.x) / count as f64;
    let mut cuts: Vec<f64> = (0..count).map(|i| lo.x + step * i as f64).collect();
    cuts.push(hi.x);
    cuts
}

/// A convex region of the plane: the points on or below every plane's
/// line (`a·x + b·y ≤ c`, with `(a, b)` of unit length), inside the
/// bounds `lo`–`hi`.
#[derive(Debug, Clone)]
pub struct Region {
    /// The planes `[a, b, c]` (a tile: floor, ceiling and sides).
    pub planes: [[f64; 3]; 4],
    /// Lower-left corner of a box holding the region (within the domain's bounds).
    pub lo: Point,
    /// Upper-right corner of that box.
    pub hi: Point,
}

impl Region {
    /// Whether `p` lies in the region (on its edges included).
    #[inline]
    pub fn contains(&self, p: Point) -> bool {
        self.inside_by(p, 0.0)
    }

    /// Whether `p` lies at least `margin` inside every plane of the region
    /// (then every point within `margin` of it is in the region); a
    /// negative margin: at most that far outside any plane.
    #[inline]
    pub fn inside_by(&self, p: Point, margin: f64) -> bool {
        self.planes
            .iter()
            .all(|&[a, b, c]| a * p.x + b * p.y + margin <= c)
    }

    /// Whether a disk centred at `c` is within `reach` of the region: in
    /// its box widened by `reach`, and at most `reach` outside any plane.
    #[inline]
    fn reaches(&self, c: Point, reach: f64) -> bool {
        c.x >= self.lo.x - reach
            && c.x <= self.hi.x + reach
            && c.y >= self.lo.y - reach
            && c.y <= self.hi.y + reach
            && self.inside_by(c, -reach)
    }

    /// Whether the boxes of two regions, each widened by `by`, meet.
    fn near(&self, other: &Region, by: f64) -> bool {
        self.lo.x - by <= other.hi.x + by
            && other.lo.x - by <= self.hi.x + by
            && self.lo.y - by <= other.hi.y + by
            && other.lo.y - by <= self.hi.y + by
    }
}

/// The plane `a·x + b·y ≤ c` normalised to a unit normal.
fn plane(a: f64, b: f64, c: f64) -> [f64; 3] {
    let n = a.hypot(b);
    [a / n, b / n, c / n]
}

/// The tiles' grid for `count` strips: the columns' edges at the levels'
/// floors ([`cuts`] of [`COLUMNS_PER_STRIP`] columns a strip), the levels'
/// floors and the top, and half of how far a side runs across a level.
fn grid(scene: &Scene, count: usize) -> (Vec<f64>, Vec<f64>, f64) {
    let (lo, hi) = scene.domain.bounds();
    let xs = cuts(scene, count * COLUMNS_PER_STRIP);
    let levels = ((hi.y - lo.y) / (TILE_HEIGHT * (xs[1] - xs[0])))
        .ceil()
        .max(1.0) as usize;
    let h = (hi.y - lo.y) / levels as f64;
    let mut ys: Vec<f64> = (0..levels).map(|l| lo.y + h * l as f64).collect();
    ys.push(hi.y);
    (xs, ys, 0.5 * SIDE_RUN * h)
}

/// The seams of the scene packed in `count` strips: the edges between its
/// tiles (the columns' sides in each level, and the lines between levels).
pub fn seams(scene: &Scene, count: usize) -> Vec<[Point; 2]> {
    let (lo, hi) = scene.domain.bounds();
    let (xs, ys, t) = grid(scene, count);
    let mut lines = Vec::new();
    for &x in &xs[1..xs.len() - 1] {
        for w in ys.windows(2) {
            lines.push([Point::new(x + t, w[0]), Point::new(x - t, w[1])]);
        }
    }
    for &y in &ys[1..ys.len() - 1] {
        lines.push([Point::new(lo.x, y), Point::new(hi.x, y)]);
    }
    lines
}

/// Seed of tile `i`'s sizes (in packing order): the scene's seed and
/// the tile, mixed (splitmix64), so neighbours draw unrelated streams.
fn part_seed(seed: u64, i: usize) -> u64 {
    let mut z = seed ^ (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Every tile of `scene` in `count` strips, in packing order (level by
/// level, left to right), and for each the earlier ones it rests on: the
/// one on its left and those of the level below whose boxes come within
/// `reach`.
///
/// # Behavior
/// A tile spans a column of a level; its sides run from `t` right of the
/// column's edges at its floor to `t` left of them at its ceiling (the
/// domain's walls bound the outer columns). It reaches `dip` below its
/// floor and past its left side. Its rows run left to right ([`Part`]'s
/// `raster`): they start against the tile on its left, continuing that
/// tile's rows, and stop at its right side, where the next tile continues
/// them; no row closes on a packed face but at the domain's right wall.
/// Tile (i, l) waits for (i − 1, l) and (i + 1, l − 1), so the tiles packed
/// at once lie along i + 2l, and are a column or a level apart.
fn tiles(scene: &Scene, count: usize, reach: f64) -> (Vec<Region>, Vec<Vec<usize>>) {
    let (lo, hi) = scene.domain.bounds();
    let (xs, ys, t) = grid(scene, count);
    let dip = DIP_DIAMETERS * scene.d_max();
    let columns = xs.len() - 1;
    let mut regions: Vec<Region> = Vec::new();
    let mut deps = Vec::new();
    for (l, w) in ys.windows(2).enumerate() {
        let (y0, y1) = (w[0], w[1]);
        // A side passes (x + t, y0) and (x − t, y1): points right of it
        // satisfy −x − k·y ≤ −(x + t) − k·y0.
        let k = 2.0 * t / (y1 - y0);
        for i in 0..columns {
            let (x0, x1) = (xs[i], xs[i + 1]);
            let left = if i == 0 {
                plane(-1.0, 0.0, -x0 + dip)
            } else {
                let [a, b, c] = plane(-1.0, -k, -x0 - t - k * y0);
                [a, b, c + dip]
            };
            let right = if i + 1 == columns {
                plane(1.0, 0.0, x1)
            } else {
                plane(1.0, k, x1 + t + k * y0)
            };
            let region = Region {
                planes: [
                    plane(0.0, -1.0, -(y0 - dip)),
                    plane(0.0, 1.0, y1),
                    left,
                    right,
                ],
                lo: Point::new((x0 - t - 2.0 * dip).max(lo.x), (y0 - dip).max(lo.y)),
                hi: Point::new((x1 + t).min(hi.x), y1.min(hi.y)),
            };
            let below = (l > 0).then(|| (l - 1) * columns + i.saturating_sub(1));
            let below = below.map_or(0..0, |first| {
                first..(l - 1) * columns + (i + 2).min(columns)
            });
            let left_one = (i > 0).then(|| l * columns + i - 1);
            let mut on: Vec<usize> = below.chain(left_one).collect();
            on.retain(|&k| regions[k].near(&region, reach));
            deps.push(on);
            regions.push(region);
        }
    }
    (regions, deps)
}

/// Pack `scene` (filling up, near the origin) in `count` strips of
/// tiles, telling `progress` the sizes drawn as they go.
///
/// # Behavior
/// A tile is packed as soon as every one it rests on is (the tile on its
/// left, and those of the level below within reach), so the levels overlap
/// in time and no core waits for a whole level; what each tile sees is
/// fixed by the layout, so the packing is not.
///
/// # Errors
/// The first error of a tile, in packing order: a limit passed
/// (counted over every tile), the work budget, or
/// [`PackError::Cancelled`].
pub(super) fn pack_up(
    scene: &Scene,
    count: usize,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    super::placed::check_fits(scene)?;
    let reach = scene.d_max(); // two largest radii
    let (regions, deps) = tiles(scene, count, reach);
    let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); regions.len()];
    let mut slots: Vec<Vec<usize>> = Vec::with_capacity(deps.len());
    for (k, on) in deps.iter().enumerate() {
        slots.push(on.iter().map(|&d| dependents[d].len()).collect());
        for &d in on {
            dependents[d].push(k);
        }
    }
    let farm = Farm {
        scene,
        regions: &regions,
        deps: &deps,
        slots: &slots,
        dependents: &dependents,
        waiting: deps.iter().map(|on| AtomicUsize::new(on.len())).collect(),
        done: (0..regions.len()).map(|_| OnceLock::new()).collect(),
        assembly: Mutex::new(Assembly::new(regions.len())),
        finished: AtomicUsize::new(0),
        drawn: AtomicU64::new(0),
        placed: AtomicU64::new(0),
        stop: cancel.child(),
        reach,
        caller: std::thread::current(),
    };
    // The calling thread reports progress while the pool packs, unless it
    // is one of the pool's own threads (it would hold one back). The
    // tiles start in the order they become ready, so the levels rise
    // together, the lowest first: started newest first, a thread climbed
    // one column of levels while the others waited for it (10⁶ disks in 3
    // strips, two threads: 0.29–0.30 s, now 0.27 s).
    rayon::in_place_scope_fifo(|s| {
        for (k, on) in deps.iter().enumerate() {
            if on.is_empty() {
                let farm = &farm;
                s.spawn_fifo(move |s| farm.pack(s, k));
            }
        }
        if rayon::current_thread_index().is_none() {
            while farm.finished.load(Ordering::Acquire) < regions.len() && !farm.stop.is_cancelled()
            {
                progress(farm.drawn.load(Ordering::Relaxed));
                std::thread::park_timeout(PROGRESS_NAP);
            }
        }
    });
    progress(farm.drawn.load(Ordering::Relaxed));
    let outcomes = farm.done.into_iter().map(|p| {
        p.into_inner()
            .unwrap_or(Err(PackError::Cancelled(Cancelled::Flag)))
            .map(drop)
    });
    first_error(outcomes, cancel)?;
    // Every tile packed, so every one was appended.
    let mut all = farm
        .assembly
        .into_inner()
        .unwrap_or_else(PoisonError::into_inner);
    all.disks.shrink_to_fit();
    all.materials.shrink_to_fit();
    Ok(Packing {
        domain: scene.domain.clone(),
        walls: scene.walls,
        boundary: Vec::new(),
        disks: all.disks,
        grains: Vec::new(),
        materials: all.materials,
        stats: all.stats,
    })
}

/// Raises the tiles' stop when packing one panics: the others end,
/// the thread reporting progress stops waiting for the tiles that
/// will never start, and the scope passes the panic on.
struct StopOnPanic<'a>(&'a Cancel);

impl Drop for StopOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.cancel();
        }
    }
}

/// How often the calling thread reports progress while the tiles are
/// packed (it is woken at once when they are done).
const PROGRESS_NAP: std::time::Duration = std::time::Duration::from_millis(20);

/// The tiles of a scene being packed, each as soon as those it rests on are.
struct Farm<'a> {
    scene: &'a Scene,
    regions: &'a [Region],
    /// Per tile: those it rests on, and those resting on it.
    deps: &'a [Vec<usize>],
    /// Per tile, per one it rests on: its place among those resting
    /// on that one (which of that one's borders are its own).
    slots: &'a [Vec<usize>],
    dependents: &'a [Vec<usize>],
    /// Per tile: how many it rests on are not packed yet.
    waiting: Vec<AtomicUsize>,
    /// Per tile, once packed: its disks within reach of each of those
    /// resting on it.
    done: Vec<OnceLock<Result<Borders, PackError>>>,
    /// The whole packing, appended to as the tiles are packed.
    assembly: Mutex<Assembly>,
    /// Trapezoids done, and sizes drawn by them.
    finished: AtomicUsize,
    drawn: AtomicU64,
    /// Disks placed by every tile, against the scene's limits.
    placed: AtomicU64,
    /// Raised when a tile fails: the others stop.
    stop: Cancel,
    /// Two largest radii: how far a disk packed before may touch one placed.
    reach: f64,
    /// The thread reporting progress: woken when the last tile is
    /// done or one fails, rather than at its next look.
    caller: std::thread::Thread,
}

/// Per tile resting on a packed one (in `Farm::dependents` order): the
/// packed one's disks within its reach, in packing order, and whether each
/// is open (see `PartPacking::open`).
type Borders = Vec<(Vec<Disk>, Vec<Option<Opening>>)>;

/// The whole packing, assembled in packing order: each tile's disks
/// are appended by the thread that packed it (or the one packing the last
/// before it to end), while the others go on packing, so no copy is left
/// for after the last tile.
struct Assembly {
    /// The next tile to append.
    next: usize,
    /// Per tile: its packing, once done and until appended.
    waiting: Vec<Option<PartPacking>>,
    disks: Vec<Disk>,
    materials: Vec<u16>,
    stats: PackStats,
}

impl Assembly {
    /// An empty packing of `parts` tiles.
    fn new(parts: usize) -> Assembly {
        Assembly {
            next: 0,
            waiting: (0..parts).map(|_| None).collect(),
            disks: Vec::new(),
            materials: Vec::new(),
            stats: PackStats::default(),
        }
    }

    /// Take tile `k`'s packing, and append those waiting in order.
    fn take(&mut self, k: usize, mut part: PartPacking) {
        if k != self.next {
            // Only its own disks wait, in a vector no longer reserved for
            // the tile's box, which it half fills.
            part.packing.disks.drain(..part.fixed);
            part.fixed = 0;
            part.packing.disks.shrink_to_fit();
            part.packing.materials.shrink_to_fit();
            part.open = Vec::new();
        }
        self.waiting[k] = Some(part);
        while let Some(p) = self.waiting.get_mut(self.next).and_then(Option::take) {
            self.disks.extend_from_slice(p.own());
            self.materials.extend_from_slice(&p.packing.materials);
            add_stats(&mut self.stats, &p.packing.stats);
            self.next += 1;
        }
    }
}

impl Farm<'_> {
    /// Pack tile `k`, start those resting on it that wait for nothing
    /// more, and append its disks to the whole packing.
    fn pack<'s>(&'s self, s: &rayon::ScopeFifo<'s>, k: usize) {
        let _stop = StopOnPanic(&self.stop);
        let (borders, part) = match self.pack_one(k) {
            Ok(part) => {
                self.drawn
                    .fetch_add(part.packing.stats.sizes_drawn, Ordering::Relaxed);
                (Ok(self.borders(k, &part)), Some(part))
            }
            Err(e) => {
                self.stop.cancel();
                (Err(e), None)
            }
        };
        // Set once: each tile is started once, when its count reaches 0.
        let _ = self.done[k].set(borders);
        for &d in &self.dependents[k] {
            if self.waiting[d].fetch_sub(1, Ordering::AcqRel) == 1 {
                s.spawn_fifo(move |s| self.pack(s, d));
            }
        }
        if let Some(part) = part {
            let mut all = self.assembly.lock().unwrap_or_else(PoisonError::into_inner);
            all.take(k, part);
        }
        let finished = self.finished.fetch_add(1, Ordering::Release) + 1;
        if finished == self.regions.len() || self.stop.is_cancelled() {
            self.caller.unpark();
        }
    }

    /// Trapezoid `k`'s packing around the disks of those it rests on.
    fn pack_one(&self, k: usize) -> Result<PartPacking, PackError> {
        // A small tile may end before its front looks at the token.
        self.stop.check()?;
        let (scene, region) = (self.scene, &self.regions[k]);
        let (mut fixed, mut open): (Vec<Disk>, Vec<Option<Opening>>) = (Vec::new(), Vec::new());
        for (&d, &slot) in self.deps[k].iter().zip(&self.slots[k]) {
            let Some(Ok(borders)) = self.done[d].get() else {
                return Err(PackError::Cancelled(Cancelled::Flag));
            };
            let (disks, opens) = &borders[slot];
            fixed.extend_from_slice(disks);
            open.extend_from_slice(opens);
        }
        let (lo, hi) = (region.lo, region.hi);
        let area = scene.domain.area_in_box(lo.x, hi.x, lo.y, hi.y);
        let share = area / scene.domain.area();
        let disks = share * scene.max_disks() + fixed.len() as f64;
        let part = Part {
            region,
            fixed: &fixed,
            open: &open,
            placed: &self.placed,
            budget: (disks as u64)
                .saturating_mul(WORK_PER_DISK)
                .saturating_add(WORK_FLOOR),
            raster: true,
        };
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(part_seed(scene.seed, k));
        let genes = (0..size_count_in(area, scene.d_min())).map(move |_| rng.r#gen::<f64>());
        pack_part(scene, Some(&part), genes, &self.stop)
    }

    /// For each tile resting on `k`, the disks of `k`'s packing within
    /// reach of its region ([`Region::reaches`]), in packing order. Only
    /// the disks near `k`'s edges are looked at ([`edge_band`]).
    fn borders(&self, k: usize, part: &PartPacking) -> Borders {
        let reach = self.reach;
        let (disks, open) = (part.own(), &part.open);
        let opening = |i: usize| {
            let at = open.binary_search_by_key(&(i as u32), |&(d, _)| d);
            at.ok().map(|at| open[at].1)
        };
        let own = &self.regions[k];
        let inner = edge_band(self.scene.d_max(), reach);
        let near_edge: Vec<usize> = (0..disks.len())
            .filter(|&i| !own.inside_by(disks[i].c, inner))
            .collect();
        self.dependents[k]
            .iter()
            .map(|&d| {
                let region = &self.regions[d];
                near_edge
                    .iter()
                    .filter(|&&i| region.reaches(disks[i].c, reach))
                    .map(|&i| (disks[i], opening(i)))
                    .unzip()
            })
            .collect()
    }
}

/// How far inside every plane of its own tile a centre lies beyond
/// the reach of every tile resting on that one: those reach at most
/// `dip` past its ceiling or a side (see [`tiles`]; the planes they share
/// are the same lines), and take the centres within `reach` of that; the
/// margin doubles the reach against rounding.
fn edge_band(d_max: f64, reach: f64) -> f64 {
    DIP_DIAMETERS * d_max + 2.0 * reach
}

/// The first error of the tiles' outcomes, in order, that is not only
/// the stop another tile's error raised.
fn first_error(
    outcomes: impl Iterator<Item = Result<(), PackError>>,
    cancel: &Cancel,
) -> Result<(), PackError> {
    let outcomes: Vec<Result<(), PackError>> = outcomes.collect();
    let stopped = |e: &PackError| matches!(e, PackError::Cancelled(_)) && cancel.check().is_ok();
    if let Some(e) = outcomes
        .iter()
        .filter_map(|s| s.as_ref().err())
        .find(|e| !stopped(e))
    {
        return Err(e.clone());
    }
    outcomes.into_iter().collect()
}

/// Add a tile's counts to the whole packing's.
fn add_stats(all: &mut PackStats, part: &PackStats) {
    all.sizes_drawn += part.sizes_drawn;
    all.sizes_deferred += part.sizes_deferred;
    all.sizes_unplaced += part.sizes_unplaced;
    all.front_attempts += part.front_attempts;
    all.fallbacks += part.fallbacks;
    all.witness_checks += part.witness_checks;
    all.work += part.work;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grading::Grading;
    use crate::{Domain, PackerSettings};

    fn scene(strips: u32) -> Scene {
        Scene::new(
            Domain::rectangle(120.0, 60.0).unwrap(),
            Grading::uniform(1.0, 1.5, Default::default()).unwrap(),
        )
        .with_packer(PackerSettings {
            strips: Strips::Count(strips),
            ..PackerSettings::default()
        })
        .with_seed(3)
    }

    /// A part whose rows run left to right, packed beside one packed
    /// before it on its left, starts each row in the corner of that part's
    /// row end: the band along their seam holds far less void than where
    /// the rows turn back and end against the packed face, for a nearly
    /// one-size grading (nothing fills a gap narrower than a disk).
    #[test]
    fn rows_starting_at_a_packed_face_leave_less_void_along_it_than_rows_ending_there() {
        let (d_min, d_max) = (1.2, 1.3);
        let scene = Scene::new(
            Domain::rectangle(60.0, 40.0).unwrap(),
            Grading::uniform(d_min, d_max, Default::default()).unwrap(),
        )
        .with_seed(4);
        let dip = DIP_DIAMETERS * d_max;
        let left = Region {
            planes: [plane(1.0, 0.0, 30.0); 4],
            lo: Point::new(0.0, 0.0),
            hi: Point::new(30.0, 40.0),
        };
        let right = Region {
            planes: [plane(-1.0, 0.0, dip - 30.0); 4],
            lo: Point::new(30.0 - dip, 0.0),
            hi: Point::new(60.0, 40.0),
        };
        let placed = AtomicU64::new(0);
        let pack_in = |region: &Region, fixed: &[Disk], open: &[Option<Opening>], raster| {
            let part = Part {
                region,
                fixed,
                open,
                placed: &placed,
                budget: u64::MAX / 2,
                raster,
            };
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
            let genes = (0..size_count_in(1200.0, d_min)).map(move |_| rng.r#gen::<f64>());
            pack_part(&scene, Some(&part), genes, &Cancel::new()).unwrap()
        };
        let first = pack_in(&left, &[], &[], true);
        let fixed: Vec<Disk> = first.own().to_vec();
        let open = vec![Some(Opening::FRESH); fixed.len()];
        // Void in the band within 0.75 d_max of the seam, away from the
        // floor and the ceiling, sampled on a 0.05 mm grid.
        let void = |raster: bool| {
            let second = pack_in(&right, &fixed, &open, raster);
            let disks: Vec<Disk> = fixed.iter().chain(second.own()).copied().collect();
            let (mut empty, mut all) = (0u32, 0u32);
            for i in 0..=600 {
                for j in 0..=40 {
                    let p = Point::new(
                        30.0 - 0.75 * d_max + 0.05 * f64::from(j),
                        5.0 + 0.05 * f64::from(i),
                    );
                    all += 1;
                    empty += u32::from(!disks.iter().any(|d| (d.c - p).norm() <= d.r));
                }
            }
            f64::from(empty) / f64::from(all)
        };
        let (starting, turning) = (void(true), void(false));
        assert!(
            starting + 0.05 < turning,
            "porosity along the seam: {starting:.3} with rows starting there, {turning:.3} with rows turning back"
        );
    }

    /// A disk its part closed takes no disk in a part packed after it: the
    /// part above, grown from every disk below it again, places the same
    /// disks at more attempts, for a narrow and a wide grading. And the
    /// open ones carry their room: handed on fresh, they cost more attempts
    /// for no more disks.
    #[test]
    fn disks_closed_in_their_part_take_nothing_later_open_ones_carry_their_room() {
        for (d_min, d_max) in [(1.0, 1.5), (0.3, 3.0)] {
            let scene = Scene::new(
                Domain::rectangle(60.0, 60.0).unwrap(),
                Grading::uniform(d_min, d_max, Default::default()).unwrap(),
            )
            .with_seed(5);
            let dip = DIP_DIAMETERS * d_max;
            let below = Region {
                planes: [plane(0.0, 1.0, 30.0); 4],
                lo: Point::new(0.0, 0.0),
                hi: Point::new(60.0, 30.0),
            };
            let above = Region {
                planes: [plane(0.0, -1.0, dip - 30.0); 4],
                lo: Point::new(0.0, 30.0 - dip),
                hi: Point::new(60.0, 60.0),
            };
            let placed = AtomicU64::new(0);
            let pack_in = |region: &Region, fixed: &[Disk], open: &[Option<Opening>], seed: u64| {
                let part = Part {
                    region,
                    fixed,
                    open,
                    placed: &placed,
                    budget: u64::MAX / 2,
                    raster: false,
                };
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
                let genes = (0..size_count_in(1800.0, d_min)).map(move |_| rng.r#gen::<f64>());
                pack_part(&scene, Some(&part), genes, &Cancel::new()).unwrap()
            };
            let first = pack_in(&below, &[], &[], 1);
            let opening = |i: usize| first.open.iter().find(|&&(d, _)| d as usize == i);
            let (fixed, open): (Vec<Disk>, Vec<Option<Opening>>) = first
                .own()
                .iter()
                .enumerate()
                .filter(|(_, d)| above.inside_by(d.c, -d_max))
                .map(|(i, d)| (*d, opening(i).map(|&(_, o)| o)))
                .unzip();
            let closed = open.iter().filter(|o| o.is_none()).count();
            assert!(
                closed > 0 && closed < open.len(),
                "{closed} of {}",
                open.len()
            );
            let skipping = pack_in(&above, &fixed, &open, 2);
            let reopened: Vec<Option<Opening>> =
                open.iter().map(|o| o.or(Some(Opening::FRESH))).collect();
            let all = pack_in(&above, &fixed, &reopened, 2);
            assert!(skipping.own().len() > 500);
            assert!(skipping.own() == all.own(), "{d_min}–{d_max} mm");
            assert!(
                skipping.packing.stats.front_attempts < all.packing.stats.front_attempts,
                "{} attempts, {} growing from every fixed disk",
                skipping.packing.stats.front_attempts,
                all.packing.stats.front_attempts
            );
            // What the part below learnt of its open disks' room spares
            // attempts on those the part above has covered since.
            let carried = open
                .iter()
                .filter(|o| o.is_some_and(|o| o != Opening::FRESH));
            assert!(carried.count() > 0);
            let fresh: Vec<Option<Opening>> =
                open.iter().map(|o| o.map(|_| Opening::FRESH)).collect();
            let blind = pack_in(&above, &fixed, &fresh, 2);
            let (a, b) = (&skipping, &blind);
            let (attempts_a, attempts_b) = (
                a.packing.stats.front_attempts,
                b.packing.stats.front_attempts,
            );
            assert!(
                attempts_a < attempts_b && a.own().len() as f64 >= 0.99 * b.own().len() as f64,
                "{d_min}–{d_max} mm: {} disks at {attempts_a} attempts, {} at {attempts_b} with nothing carried",
                a.own().len(),
                b.own().len(),
            );
        }
    }

    /// A centre deeper inside its tile than the edge band is within
    /// reach of none of the tiles resting on it (so `borders` may skip
    /// it), for narrow and wide gradings and several strip counts.
    #[test]
    fn centres_past_the_edge_band_reach_no_tile_resting_on_theirs() {
        for (strips, d_min, d_max, side) in [
            (4, 1.0, 1.5, 120.0),
            (3, 0.3, 3.0, 240.0),
            (2, 1.0, 1.5, 90.0),
        ] {
            let s = Scene::new(
                Domain::rectangle(side, 0.5 * side).unwrap(),
                Grading::uniform(d_min, d_max, Default::default()).unwrap(),
            );
            let reach = s.d_max();
            let (regions, deps) = tiles(&s, strips, reach);
            let inner = edge_band(s.d_max(), reach);
            let (mut deep, mut reached) = (0, 0);
            for (k, own) in regions.iter().enumerate() {
                let resting: Vec<&Region> = (0..regions.len())
                    .filter(|&d| deps[d].contains(&k))
                    .map(|d| &regions[d])
                    .collect();
                for i in 0..=120 {
                    for j in 0..=120 {
                        let p = Point::new(
                            own.lo.x + (own.hi.x - own.lo.x) * f64::from(i) / 120.0,
                            own.lo.y + (own.hi.y - own.lo.y) * f64::from(j) / 120.0,
                        );
                        if !own.contains(p) {
                            continue;
                        }
                        let near = resting.iter().any(|r| r.reaches(p, reach));
                        if own.inside_by(p, inner) {
                            assert!(!near, "{p:?} in tile {k} ({strips} strips)");
                            deep += 1;
                        } else if near {
                            reached += 1;
                        }
                    }
                }
            }
            assert!(deep > 0 && reached > 0, "{deep} deep, {reached} reached");
        }
    }

    /// A raised token stops every tile, and the run says so; progress
    /// is told the sizes drawn, ending at the packing's own count.
    #[test]
    fn strips_stop_when_cancelled_and_report_the_sizes_drawn() {
        let cancel = Cancel::new();
        cancel.cancel();
        let stopped = super::super::pack_observed(&scene(4), &mut |_| {}, &cancel);
        assert!(
            matches!(stopped, Err(PackError::Cancelled(_))),
            "not stopped: {:?}",
            stopped.map(|p| p.disks.len())
        );
        let mut told = Vec::new();
        let packing =
            super::super::pack_observed(&scene(4), &mut |n| told.push(n), &Cancel::new()).unwrap();
        assert_eq!(told.last(), Some(&packing.stats.sizes_drawn));
        assert!(packing.stats.sizes_drawn >= packing.disks.len() as u64);
    }

    /// Tiles that may be packed at once (neither waits for the other, even
    /// through others) keep more than a largest diameter apart, for narrow
    /// and wide gradings, the narrowest strips allowed among them; every
    /// tile rests on the one on its left.
    #[test]
    fn tiles_packed_at_once_stay_more_than_a_diameter_apart() {
        for (strips, d_min, d_max, side) in [
            (4, 1.0, 1.5, 120.0),
            (3, 0.3, 3.0, 240.0),
            (5, 1.0, 1.0, 5.0 * MIN_WIDTH_DIAMETERS),
        ] {
            let s = Scene::new(
                Domain::rectangle(side, 0.5 * side).unwrap(),
                Grading::uniform(d_min, d_max, Default::default()).unwrap(),
            );
            let (regions, deps) = tiles(&s, strips, s.d_max());
            let n = regions.len();
            let columns = strips * COLUMNS_PER_STRIP;
            assert!(n >= 2 * columns, "{n} tiles");
            // after[a][b]: b waits for a, through any chain.
            let mut after = vec![vec![false; n]; n];
            for k in 0..n {
                for &d in &deps[k] {
                    assert!(d < k);
                    after[d][k] = true;
                    for row in after.iter_mut().take(d) {
                        if row[d] {
                            row[k] = true;
                        }
                    }
                }
                if k % columns > 0 {
                    assert!(deps[k].contains(&(k - 1)), "tile {k}");
                }
            }
            let points = |r: &Region| {
                let mut v = Vec::new();
                for i in 0..=60 {
                    for j in 0..=60 {
                        let p = Point::new(
                            r.lo.x + (r.hi.x - r.lo.x) * f64::from(i) / 60.0,
                            r.lo.y + (r.hi.y - r.lo.y) * f64::from(j) / 60.0,
                        );
                        if r.contains(p) {
                            v.push(p);
                        }
                    }
                }
                v
            };
            let sampled: Vec<Vec<Point>> = regions.iter().map(points).collect();
            let mut pairs = 0;
            for a in 0..n {
                for b in a + 1..n {
                    // Pairs whose boxes come within a column of each other.
                    if after[a][b] || !regions[a].near(&regions[b], 0.5 * side / columns as f64) {
                        continue;
                    }
                    pairs += 1;
                    let nearest = sampled[a]
                        .iter()
                        .flat_map(|p| sampled[b].iter().map(move |q| (p - q).norm()))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        nearest > s.d_max(),
                        "tiles {a} and {b}: {nearest} ≤ {}",
                        s.d_max()
                    );
                }
            }
            assert!(pairs > 0);
        }
    }
}
