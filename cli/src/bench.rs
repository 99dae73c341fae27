//! `gapack bench`: disks per second and peak memory per disk, MX quadtree
//! against the grid, in one piece and in strips, on square domains with the
//! Table 3.4 grading; `--seams`, how the seams of strips compare with the bulk
//! (Table 3.4 and Table 3.1); `--periodic-edges`, how the edges of periodic
//! cells, where the front closes on its own images, compare with their
//! inside; `--shapes`, particles per second and peak
//! memory per particle for ellipses and superellipses beside disks of the
//! same grading and domain, measured in the same run.
//!
//! Peak memory comes from [`counting::PeakAlloc`], a counting wrapper around
//! the system allocator. It is installed only in a binary built with
//! `--features count-alloc`, so that no other run pays two atomic updates
//! per allocation; without it the memory column reads "not measured".

use std::time::Instant;

use gapack::strips;
use gapack::{Domain, Grading, IndexKind, PackerSettings, Point, Scene, ShapeSpec, Strips, pack};
use gapack::{mean_sd, porosity, solid_area};

/// The counting allocator and its two counters.
#[cfg(feature = "count-alloc")]
pub mod counting {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::sync::atomic::{AtomicUsize, Ordering};

    static CURRENT: AtomicUsize = AtomicUsize::new(0);
    static PEAK: AtomicUsize = AtomicUsize::new(0);

    /// System allocator that keeps the current and peak number of bytes allocated.
    pub struct PeakAlloc;

    // SAFETY: every call is forwarded unchanged to `System`; the wrapper only
    // updates two atomic counters, so the allocator contract is System's.
    unsafe impl GlobalAlloc for PeakAlloc {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            // SAFETY: forwarded with the caller's layout.
            let p = unsafe { System.alloc(layout) };
            if !p.is_null() {
                grow(layout.size());
            }
            p
        }

        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            // SAFETY: forwarded with the caller's pointer and layout.
            unsafe { System.dealloc(ptr, layout) };
            CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
        }

        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            // SAFETY: forwarded with the caller's pointer, layout and size.
            let p = unsafe { System.realloc(ptr, layout, new_size) };
            if !p.is_null() {
                CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
                grow(new_size);
            }
            p
        }
    }

    fn grow(bytes: usize) {
        let now = CURRENT.fetch_add(bytes, Ordering::Relaxed) + bytes;
        PEAK.fetch_max(now, Ordering::Relaxed);
    }

    /// Start a measurement: the peak restarts from the bytes held now.
    pub fn start() -> usize {
        let base = CURRENT.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        base
    }

    /// Peak bytes held since [`start`] returned `base`, beyond `base`.
    pub fn peak_since(base: usize) -> Option<usize> {
        Some(PEAK.load(Ordering::Relaxed).saturating_sub(base))
    }
}

/// Without the counting allocator nothing is measured.
#[cfg(not(feature = "count-alloc"))]
mod counting {
    pub fn start() -> usize {
        0
    }

    pub fn peak_since(_base: usize) -> Option<usize> {
        None
    }
}

/// One measured configuration.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    /// Target number of disks (10⁴, 10⁵, 10⁶).
    pub target: u64,
    /// Side of the square domain (mm).
    pub side_mm: f64,
    /// Index name as written in configs.
    pub index: &'static str,
    /// Strips the domain was packed in (1: one piece).
    pub strips: usize,
    /// Threads the strips could use (rayon's pool).
    pub threads: usize,
    /// Disks packed.
    pub disks: usize,
    /// Porosity reached.
    pub porosity: f64,
    /// Best wall-clock time over the repeats (s).
    pub seconds: f64,
    /// Disks per second (best run).
    pub disks_per_second: f64,
    /// Peak heap bytes during packing, per disk (`None`: the binary was
    /// built without `count-alloc`).
    pub peak_bytes_per_disk: Option<f64>,
}

/// Square side (mm) for a target disk count; 10⁶ maps to the thesis' 1000 mm square scaled up.
fn side_for(target: u64, grading: &Grading) -> f64 {
    (target as f64 * grading.mean_disk_area() / 0.82).sqrt()
}

/// The indexes measured, by their config names.
const INDEXES: [(&str, IndexKind); 2] = [
    ("mx-quadtree", IndexKind::MxQuadtree),
    ("grid", IndexKind::Grid),
];

/// Measure every (size, split, index) triple; `targets` are disk counts.
/// Scenes that `packer.strips = "auto"` packs in strips are measured in one
/// piece too. The two indexes alternate run by run; each keeps its fastest.
pub fn run(
    targets: &[u64],
    repeats: usize,
    mut progress: impl FnMut(&Row),
) -> anyhow::Result<Vec<Row>> {
    let grading = Grading::from_table(
        gapack::THESIS_TABLE_3_4,
        Default::default(),
        Default::default(),
    )?;
    let mut rows = Vec::new();
    for &target in targets {
        let mut sides = vec![side_for(target, &grading)];
        if target == 1_000_000 {
            sides.push(1000.0); // the thesis' own largest square (670,000 disks in 37 s)
        }
        for side in sides {
            let auto = Scene::new(Domain::rectangle(side, side)?, grading.clone())
                .with_packer(PackerSettings {
                    strips: Strips::Auto,
                    ..PackerSettings::default()
                })
                .with_seed(1);
            let mut splits = vec![1];
            splits.extend(strips::count(&auto));
            for count in splits {
                // The indexes take turns, repeat by repeat, so that both
                // meet the machine's drift alike and their ratio is paired.
                let mut best = [f64::INFINITY; 2];
                let mut peak = [Some(0usize); 2];
                let mut packed = [(0usize, 0.0f64); 2];
                for _ in 0..repeats.max(1) {
                    for (k, &(_, index)) in INDEXES.iter().enumerate() {
                        let mut scene = auto.clone();
                        scene.packer.index = index;
                        scene.packer.strips = Strips::Count(count as u32);
                        let base = counting::start();
                        let start = Instant::now();
                        let packing = pack(&scene)?;
                        best[k] = best[k].min(start.elapsed().as_secs_f64());
                        peak[k] = peak[k]
                            .zip(counting::peak_since(base))
                            .map(|(a, b)| a.max(b));
                        let disks = packing.disks.len();
                        packed[k] = (disks, porosity(solid_area(&packing.disks), side * side));
                    }
                }
                for (k, &(name, _)) in INDEXES.iter().enumerate() {
                    let (disks, porosity) = packed[k];
                    let row = Row {
                        target,
                        side_mm: side,
                        index: name,
                        strips: count,
                        threads: rayon::current_num_threads(),
                        disks,
                        porosity,
                        seconds: best[k],
                        disks_per_second: disks as f64 / best[k],
                        peak_bytes_per_disk: peak[k].map(|p| p as f64 / disks.max(1) as f64),
                    };
                    progress(&row);
                    rows.push(row);
                }
            }
        }
    }
    Ok(rows)
}

/// One zone of `gapack bench --seams`, over the seeds.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SeamRow {
    /// The grading packed (a thesis table).
    pub grading: &'static str,
    /// Side of the square (mm), and the strips `"auto"` cut it into.
    pub side_mm: f64,
    pub strips: usize,
    /// How the square was packed: in strips, or in one piece.
    pub packed: &'static str,
    /// Which zone: near the seams (within 3 largest diameters), or away.
    pub zone: &'static str,
    /// Mean and standard deviation over the seeds of the zone's porosity,
    /// coordination and KS distance to the grading.
    pub porosity: f64,
    pub porosity_sd: f64,
    /// Standard deviation of the porosity of one-diameter cells within the
    /// zone (mean over the seeds).
    pub cell_sd: f64,
    pub coordination: f64,
    pub coordination_sd: f64,
    pub psd_ks: f64,
    pub psd_ks_sd: f64,
    /// Disks in the zone (mean over the seeds).
    pub disks: f64,
}

/// A grading table: `(diameter mm, percent passing)`.
type Table = &'static [(f64, f64)];

/// Half width of the seams' zone, in largest diameters.
const SEAM_BAND_DIAMETERS: f64 = 3.0;

/// The gradings of `gapack bench --seams`, each with the side of its square
/// (mm): the thesis' nearly one-size proppant in its 1000 mm square, and its
/// polydisperse benchmark grading in a square wide enough for `"auto"` to cut
/// (strips at least 200 largest diameters wide).
const SEAM_GRADINGS: [(&str, Table, f64); 2] = [
    ("Table 3.4", gapack::THESIS_TABLE_3_4, 1000.0),
    ("Table 3.1", gapack::THESIS_TABLE_3_1, 1500.0),
];

/// `gapack bench --seams`: for each grading of [`SEAM_GRADINGS`], a square
/// (of side `side` mm if given), for each seed packed in strips (`"auto"`)
/// and in one piece, each measured within 3 largest diameters of the strips'
/// seams and away from them, 3 largest diameters clear of the walls.
pub fn run_seams(side: Option<f64>, seeds: u64) -> anyhow::Result<Vec<SeamRow>> {
    let mut rows = Vec::new();
    for (name, table, default_side) in SEAM_GRADINGS {
        let grading = Grading::from_table(table, Default::default(), Default::default())?;
        let side = side.unwrap_or(default_side);
        let half = SEAM_BAND_DIAMETERS * grading.d_max();
        // Per (packed, zone): the zone of each seed.
        let mut zones: [Vec<gapack::Zone>; 4] = Default::default();
        // The layout, and so the seams, depend on the scene, not its seed.
        let strips_of = Scene::new(Domain::rectangle(side, side)?, grading.clone()).with_packer(
            PackerSettings {
                strips: Strips::Auto,
                ..PackerSettings::default()
            },
        );
        let count = strips::count(&strips_of).ok_or_else(|| {
            anyhow::anyhow!(
                "a {side} mm square of {name} is packed in one piece: take a larger side"
            )
        })?;
        let seams = strips::seams(&strips_of, count);
        for seed in 1..=seeds {
            let scene = strips_of.clone().with_seed(seed);
            let mut whole = scene.clone();
            whole.packer.strips = Strips::Count(1);
            for (k, scene) in [scene, whole].iter().enumerate() {
                let packing = pack(scene)?;
                let [near, away] = gapack::zones(&packing, scene, &seams, half, half);
                zones[2 * k].push(near);
                zones[2 * k + 1].push(away);
            }
        }
        let names = [
            ("strips", "near seams"),
            ("strips", "away"),
            ("one piece", "near the same lines"),
            ("one piece", "away"),
        ];
        rows.extend(names.into_iter().zip(zones).map(|((packed, zone), all)| {
            let of = |f: fn(&gapack::Zone) -> f64| mean_sd(&all.iter().map(f).collect::<Vec<_>>());
            let (porosity, porosity_sd) = of(|z| z.porosity);
            let (coordination, coordination_sd) = of(|z| z.coordination);
            let (psd_ks, psd_ks_sd) = of(|z| z.psd_ks);
            SeamRow {
                grading: name,
                side_mm: side,
                strips: count,
                packed,
                zone,
                porosity,
                porosity_sd,
                cell_sd: of(|z| z.cell_sd).0,
                coordination,
                coordination_sd,
                psd_ks,
                psd_ks_sd,
                disks: of(|z| z.disks as f64).0,
            }
        }));
    }
    Ok(rows)
}

/// One zone of `gapack bench --periodic-edges`, over the seeds.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EdgeRow {
    /// The grading packed.
    pub grading: &'static str,
    /// The periodic cell (mm).
    pub width_mm: f64,
    pub height_mm: f64,
    /// Which zone: the bands along the cell's edges (`EDGE_BAND_MM` wide on
    /// each side of each edge, as one-band-wide cells), the inside, the
    /// edges' porosity minus the inside's (per seed), the same bands along
    /// the two lines through the cell's centre (part of the inside: where
    /// the pack starts, a row may form), or the whole cell.
    pub zone: &'static str,
    /// Mean, standard deviation, least and greatest over the seeds of the
    /// zone's porosity.
    pub porosity: f64,
    pub porosity_sd: f64,
    pub porosity_min: f64,
    pub porosity_max: f64,
    /// Standard deviation of the porosity of the zone's cells (mean over
    /// the seeds; NaN for the difference and the whole cell).
    pub cell_sd: f64,
    /// Mean over the seeds of the zone's coordination and KS distance to
    /// the grading (NaN for the difference and the whole cell).
    pub coordination: f64,
    pub psd_ks: f64,
    /// Disks in the zone (mean over the seeds).
    pub disks: f64,
    /// Mean seconds per packing.
    pub seconds: f64,
}

/// Width of the bands along a periodic cell's edges (mm).
const EDGE_BAND_MM: f64 = 1.0;

/// The cells of `gapack bench --periodic-edges`: (grading name, its
/// diameters as a table, width, height in mm): the periodic cell of
/// configs/periodic_pfc.toml (1–1.66 mm uniform), and the thesis' nearly
/// one-size proppant in the same cell.
const EDGE_CELLS: [(&str, Table, f64, f64); 2] = [
    ("1-1.66 mm", &[(1.0, 0.0), (1.66, 100.0)], 50.0, 100.0),
    ("Table 3.4", gapack::THESIS_TABLE_3_4, 50.0, 100.0),
];

/// `gapack bench --periodic-edges`: for each cell of [`EDGE_CELLS`] and
/// seeds 1..=`seeds`, a periodic cell packed by the advancing front, its
/// porosity in 1 mm cells along the four edges (a band 1 mm wide on each
/// side of each edge, the images across it counted) against the other
/// cells, and in the same bands along the lines through its centre.
pub fn run_periodic_edges(seeds: u64) -> anyhow::Result<Vec<EdgeRow>> {
    let mut rows = Vec::new();
    for (name, table, width, height) in EDGE_CELLS {
        let grading = Grading::from_table(table, Default::default(), Default::default())?;
        let cell = Domain::periodic_rectangle(width, height)?;
        let (lo, hi) = cell.bounds();
        let edges = [
            [lo, Point::new(hi.x, lo.y)],
            [Point::new(hi.x, lo.y), hi],
            [hi, Point::new(lo.x, hi.y)],
            [Point::new(lo.x, hi.y), lo],
        ];
        let scene = Scene::new(cell.clone(), grading).with_walls(gapack::WallMode::Periodic);
        // The lines through the cell's centre, where the first disk sits and
        // the pack grows out from.
        let mid = Point::new((lo.x + hi.x) / 2.0, (lo.y + hi.y) / 2.0);
        let centre_lines = [
            [Point::new(lo.x, mid.y), Point::new(hi.x, mid.y)],
            [Point::new(mid.x, lo.y), Point::new(mid.x, hi.y)],
        ];
        // Per seed: edges, inside, centre lines, whole cell, and the seconds.
        let (mut near, mut away, mut centre, mut whole, mut seconds) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), 0.0);
        for seed in 1..=seeds {
            let scene = scene.clone().with_seed(seed);
            let t = Instant::now();
            let packing = pack(&scene)?;
            seconds += t.elapsed().as_secs_f64();
            let [n, a] = gapack::zones(&packing, &scene, &edges, EDGE_BAND_MM / 2.0, 0.0);
            near.push(n);
            away.push(a);
            let [c, _] = gapack::zones(&packing, &scene, &centre_lines, EDGE_BAND_MM / 2.0, 0.0);
            centre.push(c);
            whole.push(porosity(solid_area(&packing.disks), cell.area()));
        }
        let seconds = seconds / seeds.max(1) as f64;
        let stats = |v: &[f64]| {
            let (mean, sd) = mean_sd(v);
            let min = v.iter().copied().fold(f64::INFINITY, f64::min);
            let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (mean, sd, min, max)
        };
        let row = |zone, p: &[f64], z: Option<&[gapack::Zone]>| {
            let (porosity, porosity_sd, porosity_min, porosity_max) = stats(p);
            let of = |f: fn(&gapack::Zone) -> f64| {
                z.map_or(f64::NAN, |z| {
                    mean_sd(&z.iter().map(f).collect::<Vec<_>>()).0
                })
            };
            EdgeRow {
                grading: name,
                width_mm: width,
                height_mm: height,
                zone,
                porosity,
                porosity_sd,
                porosity_min,
                porosity_max,
                cell_sd: of(|z| z.cell_sd),
                coordination: of(|z| z.coordination),
                psd_ks: of(|z| z.psd_ks),
                disks: of(|z| z.disks as f64),
                seconds,
            }
        };
        let p = |z: &[gapack::Zone]| z.iter().map(|z| z.porosity).collect::<Vec<_>>();
        let diff: Vec<f64> = near
            .iter()
            .zip(&away)
            .map(|(n, a)| n.porosity - a.porosity)
            .collect();
        rows.push(row("edges", &p(&near), Some(&near)));
        rows.push(row("inside", &p(&away), Some(&away)));
        rows.push(row("edges - inside", &diff, None));
        rows.push(row("centre lines", &p(&centre), Some(&centre)));
        rows.push(row("whole cell", &whole, None));
    }
    Ok(rows)
}

/// One measured shape of `gapack bench --shapes`.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ShapeRow {
    /// Target number of disks the square is sized for.
    pub target: u64,
    /// Side of the square (mm).
    pub side_mm: f64,
    /// The particles: disks, ellipses or superellipses, with their parameters.
    pub shape: String,
    /// Particles packed.
    pub particles: usize,
    /// Porosity reached.
    pub porosity: f64,
    /// Best wall-clock time over the repeats (s).
    pub seconds: f64,
    /// Particles per second (best run).
    pub particles_per_second: f64,
    /// Particles per second over the disks' in the same run.
    pub ratio_to_disks: f64,
    /// Peak heap bytes during packing, per particle (`None` without `count-alloc`).
    pub peak_bytes_per_particle: Option<f64>,
}

/// The shapes `gapack bench --shapes` measures, beside disks.
fn bench_shapes() -> [(&'static str, Option<ShapeSpec>); 3] {
    [
        ("disks", None),
        ("ellipses aspect 1.5", Some(ShapeSpec::ellipses(1.5))),
        (
            "superellipses alpha=beta=4 aspect 2",
            Some(ShapeSpec::superellipses(2.0, 4.0)),
        ),
    ]
}

/// Measure disks, ellipses and superellipses on one core (in one piece),
/// the Table 3.4 grading (sieve sizes), squares sized for `targets` disks;
/// the shapes take turns repeat by repeat and each keeps its fastest.
pub fn run_shapes(
    targets: &[u64],
    repeats: usize,
    mut progress: impl FnMut(&ShapeRow),
) -> anyhow::Result<Vec<ShapeRow>> {
    let grading = Grading::from_table(
        gapack::THESIS_TABLE_3_4,
        Default::default(),
        Default::default(),
    )?;
    let shapes = bench_shapes();
    let mut rows = Vec::new();
    for &target in targets {
        let side = side_for(target, &grading);
        let base = Scene::new(Domain::rectangle(side, side)?, grading.clone()).with_seed(1);
        let mut best = vec![f64::INFINITY; shapes.len()];
        let mut peak = vec![Some(0usize); shapes.len()];
        let mut packed = vec![(0usize, 0.0f64); shapes.len()];
        for _ in 0..repeats.max(1) {
            for (k, (_, shape)) in shapes.iter().enumerate() {
                let scene = match shape {
                    Some(s) => base.clone().with_shape(s.clone()),
                    None => base.clone(),
                };
                let start_bytes = counting::start();
                let start = Instant::now();
                let packing = pack(&scene)?;
                best[k] = best[k].min(start.elapsed().as_secs_f64());
                peak[k] = peak[k]
                    .zip(counting::peak_since(start_bytes))
                    .map(|(a, b)| a.max(b));
                let n = packing.disks.len();
                packed[k] = (n, porosity(solid_area(&packing.disks), side * side));
            }
        }
        let disk_rate = packed[0].0 as f64 / best[0];
        for (k, (name, _)) in shapes.iter().enumerate() {
            let (particles, porosity) = packed[k];
            let rate = particles as f64 / best[k];
            let row = ShapeRow {
                target,
                side_mm: side,
                shape: (*name).to_owned(),
                particles,
                porosity,
                seconds: best[k],
                particles_per_second: rate,
                ratio_to_disks: rate / disk_rate,
                peak_bytes_per_particle: peak[k].map(|p| p as f64 / particles.max(1) as f64),
            };
            progress(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// `gapack bench` arguments.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Largest disk count measured: 10⁴, 10⁵, 10⁶ and 10⁷ up to this.
    #[arg(long, default_value_t = 1_000_000, value_name = "N")]
    max: u64,
    /// Runs per configuration, the two indexes taking turns; the fastest of each is kept.
    #[arg(long, default_value_t = 3, value_name = "N")]
    repeats: usize,
    /// Output directory for bench.csv (with --densify: densify.csv, densify.svg, densify.png).
    #[arg(long, value_name = "DIR", default_value = "out/bench")]
    out: std::path::PathBuf,
    /// Instead: the densest porosity densify reaches for four gradings in
    /// periodic cells of about 3,000 disks, beside the published jamming
    /// figures, and its convergence (porosity against minimisation steps).
    #[arg(long)]
    densify: bool,
    /// Instead: evaluations per second of a GA whose packings take about
    /// 50 ms, on this process's threads or, under `mpirun` (a build with
    /// `--features mpi`), on every rank, and the bytes the ranks send per
    /// generation.
    #[arg(long, conflicts_with = "densify")]
    ranks: bool,
    /// Instead: a square packed in strips and in one piece, measured near
    /// the strips' seams and away from them (seams.csv).
    #[arg(long, conflicts_with_all = ["densify", "ranks"])]
    seams: bool,
    /// Instead: periodic cells packed by the advancing front, measured in
    /// 1 mm bands along their edges (where the front closes on its own
    /// images) and inside (periodic_edges.csv).
    #[arg(long, conflicts_with_all = ["densify", "ranks", "seams"])]
    periodic_edges: bool,
    /// Instead: particles per second and peak memory per particle of
    /// ellipses (aspect 1.5) and superellipses (α = β = 4, aspect 2) beside
    /// disks of the same grading and domain, on one core (shapes.csv).
    #[arg(long, conflicts_with_all = ["densify", "ranks", "seams", "periodic_edges"])]
    shapes: bool,
    /// With --seams or --periodic-edges: seeds packed (1, 2, …).
    #[arg(long, default_value_t = 3, value_name = "N")]
    seeds: u64,
    /// The side of the square packed (mm). With --ranks (default 110): 110
    /// gives packings of about 50 ms on the reference machine, smaller sides
    /// show what the sharing out costs. With --seams (default 1000 for
    /// Table 3.4, 1500 for Table 3.1).
    #[arg(long, value_name = "MM")]
    side: Option<f64>,
}

/// The search of `gapack bench --ranks` on a square of side `SIDE` mm: a
/// target no packing reaches, so that every generation runs: 16 genomes and
/// 6 generations.
const RANKS_SEARCH: &str = "seed = 1\n[domain]\nshape = \"rectangle\"\nwidth = SIDE\nheight = SIDE\n[grading]\nuniform = [1.0, 1.6]\n[optimise]\ntarget_porosity = 0.95\npopulation = 16\ngenerations = 6\nstagnation = 1000\ntime_limit_s = 3600\n[output]\nformats = [\"csv\"]\n";

/// `gapack bench --ranks`: one search on every rank (or this process),
/// its evaluations per second and the bytes sent per generation, told by rank 0.
fn run_ranks(side: f64) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use gapack::farm::{Farm, Local};
    use gapack::jobs::{self, JobKind, MemoryStore, Plan, Report, Request, Silent};
    #[cfg(feature = "mpi")]
    let ranks = crate::cli::ranks::Ranks::start();
    #[cfg(feature = "mpi")]
    let farm: &dyn Farm = match &ranks {
        Some(r) => r,
        None => &Local,
    };
    #[cfg(not(feature = "mpi"))]
    let farm: &dyn Farm = &Local;
    let text = RANKS_SEARCH.replace("SIDE", &side.to_string());
    let plan = Plan::load(&text, "bench --ranks", &Request::new(JobKind::Optimise))
        .map_err(|e| Failure::Run(e.into()))?;
    let outcome = jobs::run_on(
        &plan,
        &mut Silent,
        &gapack::Cancel::new(),
        &mut MemoryStore::default(),
        farm,
    )
    .map_err(|e| Failure::Run(e.into()))?;
    #[cfg(feature = "mpi")]
    let bytes = ranks.as_ref().map_or(0, |r| r.bytes_sent_by_all());
    #[cfg(not(feature = "mpi"))]
    let bytes = 0;
    let Report::Optimise { history, .. } = outcome.report else {
        return Err(Failure::Run(anyhow::anyhow!(
            "the bench search gave no history"
        )));
    };
    let Some(last) = history.last() else {
        return Err(Failure::Run(anyhow::anyhow!(
            "the bench search gave no history"
        )));
    };
    if farm.leads() {
        let spreads = history.len();
        print_line(format_args!(
            "side {side} mm, ranks {}, threads per rank {}: {} evaluations in {} generations (and generation 0) in {:.2} s: {:.1} evaluations/s; {:.0} bytes sent per generation",
            farm.processes(),
            rayon::current_num_threads(),
            last.evaluations,
            spreads - 1,
            last.seconds,
            last.evaluations as f64 / last.seconds,
            bytes as f64 / spreads as f64,
        ));
    }
    Ok(())
}

/// One grading of `gapack bench --densify`: its name, the curve, the
/// published densest porosity beside it, and where that figure is from.
struct Densest {
    name: &'static str,
    grading: Grading,
    published: f64,
    source: &'static str,
}

/// The densify chart starts at each grading's first point under this porosity.
const CHART_TOP: f64 = 0.45;

/// The gradings of `gapack bench --densify`.
fn densest_gradings() -> anyhow::Result<Vec<Densest>> {
    use gapack::{Basis, Interpolation};
    let table =
        |points: &[(f64, f64)]| Grading::from_table(points, Interpolation::Log, Basis::Number);
    Ok(vec![
        Densest {
            name: "bidisperse 1:1.4, half each by number",
            grading: table(&[(1.0, 0.0), (1.0, 50.0), (1.4, 50.0), (1.4, 100.0)])?,
            published: 1.0 - 0.842,
            source: "O'Hern et al. 2003, this mixture: phi_J = 0.842",
        },
        Densest {
            name: "PFC genesis, uniform 1-1.66 mm",
            grading: Grading::uniform(1.0, 1.66, Basis::Number)?,
            published: 1.0 - 0.84,
            source: "polydisperse disks: phi_J about 0.84",
        },
        Densest {
            name: "thesis Table 3.1, 1.275-3.54 mm",
            grading: table(gapack::THESIS_TABLE_3_1)?,
            published: 1.0 - 0.84,
            source: "polydisperse disks: phi_J about 0.84",
        },
        Densest {
            name: "thesis Table 3.4, 1.2-1.295 mm",
            grading: Grading::from_table(
                gapack::THESIS_TABLE_3_4,
                Interpolation::Log,
                Basis::Number,
            )?,
            published: 1.0 - std::f64::consts::PI / 12f64.sqrt(),
            source: "nearly one size: hexagonal order, phi = 0.9069",
        },
    ])
}

/// `gapack bench --densify`: see [`BenchArgs::densify`]. Each grading is
/// packed in a periodic cell at porosity 0.05, which no disks reach: the
/// run ends with the densest porosity reached, and its trace is the
/// convergence.
fn run_densest(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    use gapack::output::{Drawable, LineChart, Mark, Series};
    use gapack::{Cancel, Method, PackError, WallMode, densify_traced};
    let run = || -> anyhow::Result<(Vec<u8>, LineChart)> {
        let mut csv = csv::Writer::from_writer(Vec::new());
        csv.write_record(["grading", "steps", "porosity"])?;
        let mut series = Vec::new();
        print_line(format_args!(
            "{:<40} {:>6} {:>9} {:>10} {:>8} {:>8}  published",
            "grading", "disks", "densest", "published", "steps", "seconds"
        ));
        for (k, g) in densest_gradings()?.into_iter().enumerate() {
            let side = (3000.0 * g.grading.mean_disk_area() / 0.84).sqrt();
            let mut scene = Scene::new(Domain::rectangle(side, side)?, g.grading)
                .with_walls(WallMode::Periodic)
                .with_method(Method::Densify)
                .with_seed(1);
            scene.packer.densify.porosity = 0.05;
            let start = Instant::now();
            let (result, trace) = densify_traced(&scene, &Cancel::new());
            let seconds = start.elapsed().as_secs_f64();
            let disks = trace.disks;
            let trace = trace.points;
            let (densest, steps) = match result {
                Err(PackError::DensityUnreached { reached, steps, .. }) => (reached, steps),
                Ok(_) => anyhow::bail!("{}: packed at 0.05, below any jamming", g.name),
                Err(e) => return Err(e.into()),
            };
            print_line(format_args!(
                "{:<40} {:>6} {:>9.4} {:>10.4} {:>8} {:>8.2}  {}",
                g.name, disks, densest, g.published, steps, seconds, g.source
            ));
            for [s, p] in &trace {
                csv.write_record([g.name.to_owned(), s.to_string(), format!("{p:.6}")])?;
            }
            let last = trace.last().map_or(1.0, |t| t[0]);
            series.push(Series {
                name: format!("{} (densest {densest:.4})", g.name),
                // From the first point under CHART_TOP: the first steps
                // start from random, overlapping centres (porosity near 1).
                points: trace
                    .iter()
                    .skip_while(|t| t[1] > CHART_TOP)
                    .map(|&[s, p]| (s, p))
                    .collect(),
                mark: Mark::Line,
                colour: k,
            });
            series.push(Series {
                name: format!("published {:.3}", g.published),
                points: vec![(0.0, g.published), (last, g.published)],
                mark: Mark::Dashed,
                colour: k,
            });
        }
        let chart = LineChart {
            title: "Densify in periodic cells: porosity free of overlap against steps".to_owned(),
            x_label: "minimisation steps".to_owned(),
            y_label: "porosity".to_owned(),
            series,
        };
        Ok((csv.into_inner()?, chart))
    };
    let (csv, chart) = run()
        .context("cannot run the densify benchmark")
        .map_err(Failure::Run)?;
    let files = vec![
        ("densify.csv".to_owned(), csv),
        (
            "densify.svg".to_owned(),
            chart
                .to_svg()
                .map_err(|e| Failure::Run(e.into()))?
                .into_bytes(),
        ),
        (
            "densify.png".to_owned(),
            chart.to_png().map_err(|e| Failure::Run(e.into()))?,
        ),
    ];
    DirStore::new(&args.out)
        .write(&files)
        .context("cannot write the densify benchmark")
        .map_err(Failure::Run)?;
    print_line(args.out.join("densify.csv").display());
    Ok(())
}

/// `gapack bench`: print one table row per measured configuration, then write bench.csv.
pub fn run_command(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    if args.densify {
        return run_densest(args);
    }
    if args.ranks {
        return run_ranks(args.side.unwrap_or(110.0));
    }
    if args.seams {
        return seams_command(args);
    }
    if args.periodic_edges {
        return periodic_edges_command(args);
    }
    if args.shapes {
        return shapes_command(args);
    }
    let targets: Vec<u64> = [10_000, 100_000, 1_000_000, 10_000_000]
        .into_iter()
        .filter(|&n| n <= args.max)
        .collect();
    if targets.is_empty() {
        return Err(Failure::Input(anyhow::anyhow!(
            "--max {} is below the smallest benchmark (10000 disks)",
            args.max
        )));
    }
    print_line(format_args!(
        "{:>9} {:>9} {:>12} {:>6} {:>7} {:>9} {:>9} {:>9} {:>12} {:>10}",
        "target",
        "side_mm",
        "index",
        "strips",
        "threads",
        "disks",
        "porosity",
        "seconds",
        "disks/s",
        "bytes/disk"
    ));
    let rows = run(&targets, args.repeats, |r| {
        print_line(format_args!(
            "{:>9} {:>9.1} {:>12} {:>6} {:>7} {:>9} {:>9.4} {:>9.3} {:>12.0} {:>10}",
            r.target,
            r.side_mm,
            r.index,
            r.strips,
            r.threads,
            r.disks,
            r.porosity,
            r.seconds,
            r.disks_per_second,
            r.peak_bytes_per_disk
                .map_or_else(|| "-".to_owned(), |b| format!("{b:.1}"))
        ));
    })
    .context("cannot run the benchmark")
    .map_err(Failure::Run)?;
    if rows.iter().any(|r| r.peak_bytes_per_disk.is_none()) {
        print_line(format_args!(
            "bytes/disk not measured: build with `--features count-alloc` to count them"
        ));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in &rows {
        w.serialize(row)
            .context("cannot format bench.csv")
            .map_err(Failure::Run)?;
    }
    let bytes = w
        .into_inner()
        .context("cannot format bench.csv")
        .map_err(Failure::Run)?;
    DirStore::new(&args.out)
        .write(&[("bench.csv".to_owned(), bytes)])
        .context("cannot write bench.csv")
        .map_err(Failure::Run)?;
    print_line(args.out.join("bench.csv").display());
    Ok(())
}

/// `gapack bench --shapes`: print the table, then write shapes.csv.
fn shapes_command(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    let targets: Vec<u64> = [10_000, 100_000, 1_000_000]
        .into_iter()
        .filter(|&n| n <= args.max)
        .collect();
    if targets.is_empty() {
        return Err(Failure::Input(anyhow::anyhow!(
            "--max {} is below the smallest benchmark (10000 particles)",
            args.max
        )));
    }
    print_line(format_args!(
        "{:>9} {:>9} {:>36} {:>9} {:>9} {:>9} {:>12} {:>9} {:>10}",
        "target",
        "side_mm",
        "shape",
        "particles",
        "porosity",
        "seconds",
        "particles/s",
        "of_disks",
        "bytes/p"
    ));
    let rows = run_shapes(&targets, args.repeats, |r| {
        print_line(format_args!(
            "{:>9} {:>9.1} {:>36} {:>9} {:>9.4} {:>9.3} {:>12.0} {:>9.4} {:>10}",
            r.target,
            r.side_mm,
            r.shape,
            r.particles,
            r.porosity,
            r.seconds,
            r.particles_per_second,
            r.ratio_to_disks,
            r.peak_bytes_per_particle
                .map_or_else(|| "-".to_owned(), |b| format!("{b:.1}"))
        ));
    })
    .context("cannot run the benchmark")
    .map_err(Failure::Run)?;
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in &rows {
        w.serialize(row)
            .context("cannot format shapes.csv")
            .map_err(Failure::Run)?;
    }
    let bytes = w
        .into_inner()
        .context("cannot format shapes.csv")
        .map_err(Failure::Run)?;
    DirStore::new(&args.out)
        .write(&[("shapes.csv".to_owned(), bytes)])
        .context("cannot write shapes.csv")
        .map_err(Failure::Run)?;
    print_line(args.out.join("shapes.csv").display());
    Ok(())
}

/// `gapack bench --seams`: print the table, then write seams.csv.
fn seams_command(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    let rows = run_seams(args.side, args.seeds)
        .context("cannot run the seam benchmark")
        .map_err(Failure::Run)?;
    print_line(format_args!(
        "{:<10} {:>7} {:>6} {:<10} {:<20} {:>17} {:>8} {:>15} {:>17} {:>8}",
        "grading",
        "side",
        "strips",
        "packed",
        "zone",
        "porosity",
        "cell_sd",
        "coordination",
        "psd_ks",
        "disks"
    ));
    for r in &rows {
        print_line(format_args!(
            "{:<10} {:>7} {:>6} {:<10} {:<20} {:>8.4} ± {:<6.4} {:>8.4} {:>6.3} ± {:<6.3} {:>7.4} ± {:<7.4} {:>8.0}",
            r.grading,
            r.side_mm,
            r.strips,
            r.packed,
            r.zone,
            r.porosity,
            r.porosity_sd,
            r.cell_sd,
            r.coordination,
            r.coordination_sd,
            r.psd_ks,
            r.psd_ks_sd,
            r.disks
        ));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in &rows {
        w.serialize(row)
            .context("cannot format seams.csv")
            .map_err(Failure::Run)?;
    }
    let bytes = w
        .into_inner()
        .context("cannot format seams.csv")
        .map_err(Failure::Run)?;
    DirStore::new(&args.out)
        .write(&[("seams.csv".to_owned(), bytes)])
        .context("cannot write seams.csv")
        .map_err(Failure::Run)?;
    print_line(args.out.join("seams.csv").display());
    Ok(())
}

/// `gapack bench --periodic-edges`: print the table, then write periodic_edges.csv.
fn periodic_edges_command(args: &BenchArgs) -> Result<(), crate::cli::Failure> {
    use crate::cli::{Failure, print_line};
    use anyhow::Context;
    use gapack::jobs::{DirStore, Store};
    let rows = run_periodic_edges(args.seeds)
        .context("cannot run the periodic-edges benchmark")
        .map_err(Failure::Run)?;
    print_line(format_args!(
        "{:<10} {:>9} {:<15} {:>17} {:>15} {:>8} {:>6} {:>7} {:>7} {:>8}",
        "grading",
        "cell_mm",
        "zone",
        "porosity",
        "min..max",
        "cell_sd",
        "coord",
        "psd_ks",
        "disks",
        "seconds"
    ));
    for r in &rows {
        print_line(format_args!(
            "{:<10} {:>9} {:<15} {:>8.4} ± {:<6.4} {:>7.4}..{:<6.4} {:>8.4} {:>6.3} {:>7.4} {:>7.0} {:>8.3}",
            r.grading,
            format!("{}x{}", r.width_mm, r.height_mm),
            r.zone,
            r.porosity,
            r.porosity_sd,
            r.porosity_min,
            r.porosity_max,
            r.cell_sd,
            r.coordination,
            r.psd_ks,
            r.disks,
            r.seconds
        ));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in &rows {
        w.serialize(row)
            .context("cannot format periodic_edges.csv")
            .map_err(Failure::Run)?;
    }
    let bytes = w
        .into_inner()
        .context("cannot format periodic_edges.csv")
        .map_err(Failure::Run)?;
    DirStore::new(&args.out)
        .write(&[("periodic_edges.csv".to_owned(), bytes)])
        .context("cannot write periodic_edges.csv")
        .map_err(Failure::Run)?;
    print_line(args.out.join("periodic_edges.csv").display());
    Ok(())
}
