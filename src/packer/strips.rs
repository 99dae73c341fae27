//! One domain packed on every core: the advancing front in trapezoids laid
//! in strips and levels, packed in turns (docs/ARCHITECTURE.md, "Strips").
//!
//! # Behavior
//! The domain is cut into [`count`] strips, and each strip into levels; the
//! cut depends on the scene only, never on the machine, so a packing is the
//! same whatever the number of threads. A level holds trapezoids of two
//! kinds: *mounds*, wide at the bottom, centred on the strips' edges, and
//! *valleys*, wide at the top, between them; their sides slope at 45°.
//! Level by level, the mounds are packed at once, then the valleys at once.
//! Each trapezoid is packed by the advancing front from its own seeded
//! stream of sizes: its disks' centres stay in it (its sides are open: a
//! disk may stick out by its radius), and the disks packed before within
//! reach (the level below, and for a valley the mounds beside it) are fixed
//! obstacles, and those their own trapezoid left open are the fronts it
//! grows from (see `PartPacking::open`).
//!
//! Why this shape: every trapezoid is packed *on top of* the disks packed
//! before it (the level below, and for a valley the mounds' slopes), as the
//! front packs on top of its own disks. Vertical strips side by side, the
//! second filling the gap between the first's faces, left a layer of voids
//! on each seam (porosity 0.36–0.38 within half a diameter of it, against
//! 0.17 around; 1000 mm square of Table 3.4): a front closing sideways on
//! a packed face leaves gaps a front resting on it does not.
//!
//! Zero overlaps and containment hold as in one piece: every candidate is
//! tested against every obstacle in reach, fixed ones included, and against
//! the domain's walls. Trapezoids packed at once are more than a largest
//! diameter apart, so their disks never meet. The scene's particle and
//! memory limits count the disks of every trapezoid together.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::advancing_front::{
    Part, PartPacking, WORK_FLOOR, WORK_PER_DISK, pack_part, size_count_in,
};
use super::{FrontRules, PackError, PackStats, Packing, Strips};
use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
use crate::geometry::{Disk, Point, Shape, WallMode, bounds_of};

/// Scenes of more disks than this are split by [`Strips::Auto`].
pub const AUTO_DISKS: f64 = 200_000.0;

/// Disks a strip holds, about, when [`Strips::Auto`] splits a scene.
const STRIP_DISKS: f64 = 50_000.0;

/// Narrowest strip [`Strips::Auto`] makes, in largest diameters.
const AUTO_WIDTH_DIAMETERS: f64 = 200.0;

/// Narrowest strip a config may ask for, in largest diameters: the gaps
/// between trapezoids packed at once take four of them.
pub const MIN_WIDTH_DIAMETERS: f64 = 8.0;

/// Width of a valley's bottom and of a mound's top, in largest diameters:
/// what keeps two trapezoids packed at once apart.
const GAP_DIAMETERS: f64 = 3.0;

/// How far a trapezoid reaches into those packed before it (below it, and
/// for a valley into the mounds beside it), in largest diameters, so that
/// its disks settle into the hollows of their surface. Where both sides of
/// a seam kept their centres to one line, each laid a row of disks along
/// it as along a wall: the porosity across a level's seam swung between
/// 0.156 and 0.21 from one half diameter to the next, against 0.178 in bulk.
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
/// [`STRIP_DISKS`] disks, none narrower than [`AUTO_WIDTH_DIAMETERS`]
/// largest diameters; [`Strips::Count`] into that many. The strips are
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
            let by_width = (width / (AUTO_WIDTH_DIAMETERS * scene.d_max())).floor();
            by_disks.min(by_width) as usize
        }
    };
    (count >= 2).then_some(count)
}

/// The abscissae `count` strips of equal width cut the scene's domain at,
/// from its left side to its right (both included): the seams are the
/// inner ones, each the axis of a column of mounds.
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
    /// The planes `[a, b, c]`.
    pub planes: Vec<[f64; 3]>,
    /// Lower-left corner of a box holding the region (within the domain's bounds).
    pub lo: Point,
    /// Upper-right corner of that box.
    pub hi: Point,
}

impl Region {
    /// Whether `p` lies in the region (on its edges included).
    #[inline]
    pub fn contains(&self, p: Point) -> bool {
        self.planes.iter().all(|&[a, b, c]| a * p.x + b * p.y <= c)
    }

    /// How far `p` lies outside the region's planes, at most (≤ 0 inside):
    /// a lower bound of its distance to the region.
    fn outside(&self, p: Point) -> f64 {
        self.planes.iter().fold(f64::NEG_INFINITY, |m, &[a, b, c]| {
            m.max(a * p.x + b * p.y - c)
        })
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

/// The trapezoids of one level, `(mounds, valleys)`, left to right: the level
/// spans `y0..y1`, the mounds' tops are centred on `cuts` (the domain's
/// sides included), `top` wide, their sides running `run` across; each
/// reaches `dip` below `y0`, and a valley `dip` into the mounds' sides.
fn level(
    cuts: &[f64],
    (y0, y1): (f64, f64),
    (top, run, dip): (f64, f64, f64),
    bounds: (Point, Point),
) -> (Vec<Region>, Vec<Region>) {
    let slope = run / (y1 - y0);
    let clip = |lo: Point, hi: Point| {
        (
            Point::new(lo.x.max(bounds.0.x), lo.y.max(bounds.0.y)),
            Point::new(hi.x.min(bounds.1.x), hi.y.min(bounds.1.y)),
        )
    };
    // A mound's left side passes through (x, y0) rising right: points right
    // of it satisfy −x + slope·y ≤ −x + slope·y0; its right side mirrors it.
    let left_of = |x: f64| plane(-1.0, slope, -x + slope * y0);
    let right_of = |x: f64| plane(1.0, slope, x + slope * y0);
    let (floor, ceiling) = (plane(0.0, -1.0, -(y0 - dip)), plane(0.0, 1.0, y1));
    let mounds = cuts
        .iter()
        .map(|&x| {
            let (a, b) = (x - 0.5 * top - run, x + 0.5 * top + run);
            let (lo, hi) = clip(
                Point::new(a - 2.0 * dip, y0 - dip),
                Point::new(b + 2.0 * dip, y1),
            );
            Region {
                planes: vec![floor, ceiling, left_of(a), right_of(b)],
                lo,
                hi,
            }
        })
        .collect();
    let valleys = cuts
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0] + 0.5 * top + run, w[1] - 0.5 * top - run);
            let (lo, hi) = clip(
                Point::new(w[0] + 0.5 * top - 2.0 * dip, y0 - dip),
                Point::new(w[1] - 0.5 * top + 2.0 * dip, y1),
            );
            // Beyond the mounds' sides (the opposite half-planes), less the dip.
            let [ra, rb, rc] = right_of(a);
            let [la, lb, lc] = left_of(b);
            Region {
                planes: vec![floor, ceiling, [-ra, -rb, -rc + dip], [-la, -lb, -lc + dip]],
                lo,
                hi,
            }
        })
        .collect();
    (mounds, valleys)
}

/// The layout of `count` strips: the strips' edges ([`cuts`]), the width
/// of a mound's top and a valley's bottom, how far a side runs across (and
/// up: a level is as high), and the levels.
fn layout(scene: &Scene, count: usize) -> (Vec<f64>, f64, f64, usize) {
    let (lo, hi) = scene.domain.bounds();
    let cuts = cuts(scene, count);
    let gap = GAP_DIAMETERS * scene.d_max();
    let run = 0.5 * ((cuts[1] - cuts[0]) - 2.0 * gap);
    let levels = ((hi.y - lo.y) / run).ceil().max(1.0) as usize;
    (cuts, gap, run, levels)
}

/// The seams of the scene packed in `count` strips: the edges between its
/// trapezoids (the mounds' sides, and the lines between levels).
pub fn seams(scene: &Scene, count: usize) -> Vec<[Point; 2]> {
    let (lo, hi) = scene.domain.bounds();
    let (cuts, gap, run, levels) = layout(scene, count);
    let mut lines = Vec::new();
    for l in 0..levels {
        let (y0, y1) = (lo.y + run * l as f64, lo.y + run * (l + 1) as f64);
        if l > 0 {
            lines.push([Point::new(lo.x, y0), Point::new(hi.x, y0)]);
        }
        for &x in &cuts {
            let (a, b) = (x - 0.5 * gap - run, x + 0.5 * gap + run);
            lines.push([Point::new(a, y0), Point::new(a + run, y1)]);
            lines.push([Point::new(b, y0), Point::new(b - run, y1)]);
        }
    }
    lines
}

/// Seed of trapezoid `i`'s sizes (in packing order): the scene's seed and
/// the trapezoid, mixed (splitmix64), so neighbours draw unrelated streams.
fn part_seed(seed: u64, i: usize) -> u64 {
    let mut z = seed ^ (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Pack `scene` (filling up, near the origin) in `count` strips of
/// trapezoids, telling `progress` the sizes drawn as they go.
///
/// # Behavior
/// A trapezoid is packed as soon as every one it rests on is (those of the
/// level below within reach, and for a valley the mounds beside it), so the
/// levels overlap in time and no core waits for a whole level; what each
/// trapezoid sees is fixed by the layout, so the packing is not.
///
/// # Errors
/// The first error of a trapezoid, in packing order: a limit passed
/// (counted over every trapezoid), the work budget, or
/// [`PackError::Cancelled`].
pub(super) fn pack_up(
    scene: &Scene,
    count: usize,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    super::placed::check_fits(scene)?;
    let bounds = scene.domain.bounds();
    let (cuts, gap, run, levels) = layout(scene, count);
    let reach = scene.d_max(); // two largest radii
    let dip = DIP_DIAMETERS * scene.d_max();
    // Every trapezoid in packing order, and the earlier ones each rests on.
    let mut regions: Vec<Region> = Vec::new();
    let mut deps: Vec<Vec<usize>> = Vec::new();
    let mut below = 0..0;
    for l in 0..levels {
        let y = |k: usize| bounds.0.y + run * k as f64;
        let (mounds, valleys) = level(&cuts, (y(l), y(l + 1)), (gap, run, dip), bounds);
        let first = regions.len();
        for (kind, list) in [(0, mounds), (1, valleys)] {
            let mounds = first..regions.len();
            for region in list {
                let mut on: Vec<usize> = below.clone().collect();
                if kind == 1 {
                    on.extend(mounds.clone());
                }
                on.retain(|&k| regions[k].near(&region, reach));
                deps.push(on);
                regions.push(region);
            }
        }
        below = first..regions.len();
    }
    let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); regions.len()];
    for (k, on) in deps.iter().enumerate() {
        for &d in on {
            dependents[d].push(k);
        }
    }
    let farm = Farm {
        scene,
        regions: &regions,
        deps: &deps,
        dependents: &dependents,
        waiting: deps.iter().map(|on| AtomicUsize::new(on.len())).collect(),
        done: (0..regions.len()).map(|_| OnceLock::new()).collect(),
        finished: AtomicUsize::new(0),
        drawn: AtomicU64::new(0),
        placed: AtomicU64::new(0),
        stop: cancel.child(),
        reach,
        caller: std::thread::current(),
    };
    // The calling thread reports progress while the pool packs, unless it
    // is one of the pool's own threads (it would hold one back).
    rayon::in_place_scope(|s| {
        for (k, on) in deps.iter().enumerate() {
            if on.is_empty() {
                let farm = &farm;
                s.spawn(move |s| farm.pack(s, k));
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
    let parts = farm
        .done
        .into_iter()
        .map(|p| {
            p.into_inner()
                .unwrap_or(Err(PackError::Cancelled(Cancelled::Flag)))
                .map(|done| done.part.packing)
        })
        .collect();
    let parts = first_error(parts, cancel)?;
    let mut stats = PackStats::default();
    let total = parts.iter().map(|p| p.disks.len()).sum();
    let (mut disks, mut materials) = (Vec::with_capacity(total), Vec::new());
    for mut p in parts {
        add_stats(&mut stats, &p.stats);
        disks.append(&mut p.disks);
        materials.append(&mut p.materials);
    }
    Ok(Packing {
        domain: scene.domain.clone(),
        walls: scene.walls,
        boundary: Vec::new(),
        disks,
        materials,
        stats,
    })
}

/// Raises the trapezoids' stop when packing one panics: the others end,
/// the thread reporting progress stops waiting for the trapezoids that
/// will never start, and the scope passes the panic on.
struct StopOnPanic<'a>(&'a Cancel);

impl Drop for StopOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.cancel();
        }
    }
}

/// How often the calling thread reports progress while the trapezoids are
/// packed (it is woken at once when they are done).
const PROGRESS_NAP: std::time::Duration = std::time::Duration::from_millis(20);

/// The trapezoids of a scene being packed, each as soon as those it rests on are.
struct Farm<'a> {
    scene: &'a Scene,
    regions: &'a [Region],
    /// Per trapezoid: those it rests on, and those resting on it.
    deps: &'a [Vec<usize>],
    dependents: &'a [Vec<usize>],
    /// Per trapezoid: how many it rests on are not packed yet.
    waiting: Vec<AtomicUsize>,
    /// Per trapezoid: its packing, once done.
    done: Vec<OnceLock<Result<Done, PackError>>>,
    /// Trapezoids done, and sizes drawn by them.
    finished: AtomicUsize,
    drawn: AtomicU64,
    /// Disks placed by every trapezoid, against the scene's limits.
    placed: AtomicU64,
    /// Raised when a trapezoid fails: the others stop.
    stop: Cancel,
    /// Two largest radii: how far a disk packed before may touch one placed.
    reach: f64,
    /// The thread reporting progress: woken when the last trapezoid is
    /// done or one fails, rather than at its next look.
    caller: std::thread::Thread,
}

impl Farm<'_> {
    /// Pack trapezoid `k`, then start those resting on it that wait for nothing more.
    fn pack<'s>(&'s self, s: &rayon::Scope<'s>, k: usize) {
        let _stop = StopOnPanic(&self.stop);
        let packed = self.pack_one(k).map(|mut part| {
            let p = &mut part.packing;
            // Reserved for the trapezoid's box, which it half fills: the
            // slack would stay until the end.
            p.disks.shrink_to_fit();
            p.materials.shrink_to_fit();
            self.drawn.fetch_add(p.stats.sizes_drawn, Ordering::Relaxed);
            let boxes = p
                .disks
                .chunks(CHUNK)
                .map(|c| bounds_of(c.iter().map(|d| &d.c)))
                .collect();
            Done { part, boxes }
        });
        if packed.is_err() {
            self.stop.cancel();
        }
        // Set once: each trapezoid is started once, when its count reaches 0.
        let _ = self.done[k].set(packed);
        for &d in &self.dependents[k] {
            if self.waiting[d].fetch_sub(1, Ordering::AcqRel) == 1 {
                s.spawn(move |s| self.pack(s, d));
            }
        }
        let finished = self.finished.fetch_add(1, Ordering::Release) + 1;
        if finished == self.regions.len() || self.stop.is_cancelled() {
            self.caller.unpark();
        }
    }

    /// Trapezoid `k`'s packing around the disks of those it rests on.
    fn pack_one(&self, k: usize) -> Result<PartPacking, PackError> {
        // A small trapezoid may end before its front looks at the token.
        self.stop.check()?;
        let (scene, region, reach) = (self.scene, &self.regions[k], self.reach);
        let (mut fixed, mut open): (Vec<Disk>, Vec<bool>) = (Vec::new(), Vec::new());
        for &d in &self.deps[k] {
            let Some(Ok(before)) = self.done[d].get() else {
                return Err(PackError::Cancelled(Cancelled::Flag));
            };
            before.within_reach(region, reach, &mut fixed, &mut open);
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
        };
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(part_seed(scene.seed, k));
        let genes = (0..size_count_in(area, scene.d_min())).map(move |_| rng.r#gen::<f64>());
        pack_part(scene, Some(&part), genes, &self.stop)
    }
}

/// Disks per chunk of a trapezoid's packing whose centres' box those
/// packed after it look at before its disks (see `Farm::pack_one`).
const CHUNK: usize = 64;

/// A trapezoid's packing, and the box of its disks' centres for each
/// [`CHUNK`] of them in packing order (the front packs near the last disk,
/// so a chunk's box is small).
struct Done {
    part: PartPacking,
    boxes: Vec<(Point, Point)>,
}

impl Done {
    /// Append to `fixed` (and their openness to `open`) this packing's disks
    /// within `reach` of `region` (their centres in its box widened by
    /// `reach` and at most `reach` outside its planes), in packing order:
    /// the disks a scan of them all would take, without reading the chunks
    /// whose box is out of reach.
    fn within_reach(
        &self,
        region: &Region,
        reach: f64,
        fixed: &mut Vec<Disk>,
        open: &mut Vec<bool>,
    ) {
        let (lo, hi) = (
            Point::new(region.lo.x - reach, region.lo.y - reach),
            Point::new(region.hi.x + reach, region.hi.y + reach),
        );
        let (disks, opens) = (&self.part.packing.disks, &self.part.open);
        for (c, &(blo, bhi)) in self.boxes.iter().enumerate() {
            if bhi.x < lo.x || blo.x > hi.x || bhi.y < lo.y || blo.y > hi.y {
                continue;
            }
            let chunk = c * CHUNK..disks.len().min((c + 1) * CHUNK);
            for (d, &o) in disks[chunk.clone()].iter().zip(&opens[chunk]) {
                if d.c.x >= lo.x
                    && d.c.x <= hi.x
                    && d.c.y >= lo.y
                    && d.c.y <= hi.y
                    && region.outside(d.c) <= reach
                {
                    fixed.push(*d);
                    open.push(o);
                }
            }
        }
    }
}

/// The trapezoids' packings, or the first error in order that is not only
/// the stop another trapezoid's error raised.
fn first_error(
    parts: Vec<Result<Packing, PackError>>,
    cancel: &Cancel,
) -> Result<Vec<Packing>, PackError> {
    let stopped = |e: &PackError| matches!(e, PackError::Cancelled(_)) && cancel.check().is_ok();
    if let Some(e) = parts
        .iter()
        .filter_map(|s| s.as_ref().err())
        .find(|e| !stopped(e))
    {
        return Err(e.clone());
    }
    parts.into_iter().collect()
}

/// Add a trapezoid's counts to the whole packing's.
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

    /// The chunks' boxes leave out no disk within reach: on a random walk
    /// of disks (packing order keeps neighbours near), every region takes
    /// the disks a scan of them all takes, in the same order.
    #[test]
    fn chunks_take_what_a_full_scan_takes() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let mut at = Point::new(50.0, 50.0);
        let disks: Vec<Disk> = (0..5000)
            .map(|_| {
                at = Point::new(
                    (at.x + rng.gen_range(-1.0..1.0)).clamp(0.0, 100.0),
                    (at.y + rng.gen_range(-0.2..1.0)).rem_euclid(100.0),
                );
                Disk::new(at.x, at.y, rng.gen_range(0.2..0.6))
            })
            .collect();
        let open: Vec<bool> = (0..disks.len()).map(|i| i % 3 == 0).collect();
        let packing = Packing {
            domain: Domain::rectangle(100.0, 100.0).unwrap(),
            walls: WallMode::Exact,
            boundary: Vec::new(),
            disks: disks.clone(),
            materials: Vec::new(),
            stats: PackStats::default(),
        };
        let boxes = disks
            .chunks(CHUNK)
            .map(|c| bounds_of(c.iter().map(|d| &d.c)))
            .collect();
        let done = Done {
            part: PartPacking {
                packing,
                open: open.clone(),
            },
            boxes,
        };
        let mut taken = 0;
        for _ in 0..200 {
            let (x, y) = (rng.gen_range(-10.0..100.0), rng.gen_range(-10.0..100.0));
            let (w, h) = (rng.gen_range(1.0..40.0), rng.gen_range(1.0..40.0));
            let region = Region {
                planes: vec![plane(1.0, rng.gen_range(-1.0..1.0), x + w)],
                lo: Point::new(x, y),
                hi: Point::new(x + w, y + h),
            };
            let reach = rng.gen_range(0.0..3.0);
            let (mut fixed, mut opens) = (Vec::new(), Vec::new());
            done.within_reach(&region, reach, &mut fixed, &mut opens);
            let all: Vec<(Disk, bool)> = disks
                .iter()
                .zip(&open)
                .filter(|(d, _)| {
                    d.c.x >= region.lo.x - reach
                        && d.c.x <= region.hi.x + reach
                        && d.c.y >= region.lo.y - reach
                        && d.c.y <= region.hi.y + reach
                        && region.outside(d.c) <= reach
                })
                .map(|(d, &o)| (*d, o))
                .collect();
            assert_eq!(fixed.into_iter().zip(opens).collect::<Vec<_>>(), all);
            taken += all.len();
        }
        assert!(taken > 10_000, "the regions took only {taken} disks");
    }

    /// A disk its part closed takes no disk in a part packed after it: the
    /// part above, grown from every disk below it again, places the same
    /// disks at more attempts, for a narrow and a wide grading.
    #[test]
    fn disks_closed_in_their_part_take_nothing_later() {
        for (d_min, d_max) in [(1.0, 1.5), (0.3, 3.0)] {
            let scene = Scene::new(
                Domain::rectangle(60.0, 60.0).unwrap(),
                Grading::uniform(d_min, d_max, Default::default()).unwrap(),
            )
            .with_seed(5);
            let dip = DIP_DIAMETERS * d_max;
            let below = Region {
                planes: vec![plane(0.0, 1.0, 30.0)],
                lo: Point::new(0.0, 0.0),
                hi: Point::new(60.0, 30.0),
            };
            let above = Region {
                planes: vec![plane(0.0, -1.0, dip - 30.0)],
                lo: Point::new(0.0, 30.0 - dip),
                hi: Point::new(60.0, 60.0),
            };
            let placed = AtomicU64::new(0);
            let pack_in = |region: &Region, fixed: &[Disk], open: &[bool], seed: u64| {
                let part = Part {
                    region,
                    fixed,
                    open,
                    placed: &placed,
                    budget: u64::MAX / 2,
                };
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
                let genes = (0..size_count_in(1800.0, d_min)).map(move |_| rng.r#gen::<f64>());
                pack_part(&scene, Some(&part), genes, &Cancel::new()).unwrap()
            };
            let first = pack_in(&below, &[], &[], 1);
            let (fixed, open): (Vec<Disk>, Vec<bool>) = first
                .packing
                .disks
                .iter()
                .zip(&first.open)
                .filter(|(d, _)| above.outside(d.c) <= d_max)
                .unzip();
            let closed = open.iter().filter(|&&o| !o).count();
            assert!(
                closed > 0 && closed < open.len(),
                "{closed} of {}",
                open.len()
            );
            let skipping = pack_in(&above, &fixed, &open, 2);
            let all = pack_in(&above, &fixed, &vec![true; fixed.len()], 2);
            assert!(skipping.packing.disks.len() > 500);
            assert!(
                skipping.packing.disks == all.packing.disks,
                "{d_min}–{d_max} mm"
            );
            assert!(
                skipping.packing.stats.front_attempts < all.packing.stats.front_attempts,
                "{} attempts, {} growing from every fixed disk",
                skipping.packing.stats.front_attempts,
                all.packing.stats.front_attempts
            );
        }
    }

    /// A raised token stops every trapezoid, and the run says so; progress
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

    /// The layout: mounds and valleys tile each level, trapezoids packed at
    /// once (mounds of a level, valleys of a level) keep more than a
    /// largest diameter apart.
    #[test]
    fn trapezoids_packed_at_once_stay_more_than_a_diameter_apart() {
        let s = scene(4);
        let (cuts, gap, run, levels) = layout(&s, 4);
        assert_eq!(cuts.len(), 5);
        let dip = DIP_DIAMETERS * s.d_max();
        let (lo, hi) = s.domain.bounds();
        let (mounds, valleys) = level(
            &cuts,
            (lo.y + run, lo.y + 2.0 * run),
            (gap, run, dip),
            (lo, hi),
        );
        assert!(levels >= 2);
        // Sample points of each region on a fine grid; nearest points of
        // two neighbours at once must be farther apart than d_max.
        let points = |r: &Region| {
            let mut v = Vec::new();
            for i in 0..=200 {
                for j in 0..=100 {
                    let p = Point::new(
                        r.lo.x + (r.hi.x - r.lo.x) * f64::from(i) / 200.0,
                        r.lo.y + (r.hi.y - r.lo.y) * f64::from(j) / 100.0,
                    );
                    if r.contains(p) {
                        v.push(p);
                    }
                }
            }
            v
        };
        for group in [&mounds, &valleys] {
            for pair in group.windows(2) {
                let (a, b) = (points(&pair[0]), points(&pair[1]));
                assert!(!a.is_empty() && !b.is_empty());
                let nearest = a
                    .iter()
                    .flat_map(|p| b.iter().map(move |q| (p - q).norm()))
                    .fold(f64::INFINITY, f64::min);
                assert!(nearest > s.d_max(), "{nearest} ≤ {}", s.d_max());
            }
        }
    }
}
