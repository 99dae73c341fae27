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

mod zones;

use std::time::Instant;

use gapack::strips;
use gapack::{Domain, Grading, IndexKind, PackerSettings, Scene, ShapeSpec, Strips, pack};
use gapack::{porosity, solid_area};

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
        return zones::seams_command(args);
    }
    if args.periodic_edges {
        return zones::periodic_edges_command(args);
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
