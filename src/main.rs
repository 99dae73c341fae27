//! `gapack`: the command line. A thin layer over the library: parse the
//! arguments, run one subcommand, print one line, exit 0 (success),
//! 1 (the run failed) or 2 (bad input: arguments or config).
//!
//! Adding a subcommand = one variant of [`Command`] + one `run_*` function.

mod bench;
mod cli;

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use gapack::compare::{CompareRun, Variant, compare};
use gapack::config::{self, Config, DEFAULT_CONFIG, DEFAULT_ORIGIN};
use gapack::fracture::{Extent, FractureRun, MM_PER_M, Well, settle};
use gapack::ga::{Layered, Limits, PorosityProblem, Search, StopReason, lay_out};
use gapack::geometry::predicates::OVERLAP_REL;
use gapack::output::{
    FractureInfo, OptimiseSummary, RunInfo, WELLS_CSV, WellRow, variant_label, wells_csv,
    write_compare, write_outputs, write_stability, write_table,
};
use gapack::stability::{self, StabilityRun, Status};
use gapack::{measure, pack, pack_observed};
use indicatif::{ProgressBar, ProgressStyle};

/// Counts heap bytes so that `gapack bench` can report peak memory per disk.
#[global_allocator]
static ALLOCATOR: bench::PeakAlloc = bench::PeakAlloc;

/// Dense 2D disk packings for DEM simulations.
#[derive(Parser)]
#[command(name = "gapack", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Pack a scene and write packing.csv, summary.json and packing.svg.
    Pack(PackArgs),
    /// Reach the config's target porosity with the genetic algorithm (needs an
    /// [optimise] table); writes what `pack` writes plus convergence.csv,
    /// convergence.svg and convergence.png. Ctrl-C stops and writes the best so far.
    #[command(alias = "optimize")]
    Optimise(OptimiseArgs),
    /// Lay materials out along the config's [layering] profile on one
    /// packing (baseline, then the GA; or size-graded packing); writes what
    /// `pack` writes with a material column, plus profile.csv, profile.svg
    /// and profile.png.
    Layer(LayerArgs),
    /// Run every generator on the config's scene (its [compare] table:
    /// methods, repeats): the advancing front with each index and contact
    /// rule, random sequential addition, deposition, relaxation; writes
    /// compare.csv and a chart of time against accuracy (compare.svg, .png).
    Compare(CompareArgs),
    /// Sweep every method of the config's [compare] table over gradings
    /// (d_max/d_min 1 to 16), domain widths (1.2 to 20 d_max) and shapes
    /// (rectangle, circle, 20° triangle, L): finished, filled, overlap-free,
    /// grading kept; writes stability.csv and a map (stability.svg, .png).
    Stability(StabilityArgs),
    /// Check a config without running it and print the scene it would build:
    /// domain, size range, estimated disk count and memory, outputs.
    Validate(cli::inspect::ValidateArgs),
    /// Check an existing packing (a CSV from gapack or any tool) against a
    /// config: overlaps, containment, porosity, grading (KS). Exit 1 if it fails.
    Verify(cli::inspect::VerifyArgs),
    /// Draw an existing packing (a CSV from gapack or any tool): packing,
    /// psd and porosity_map as SVG and PNG; with --config, its domain and target grading.
    Plot(cli::inspect::PlotArgs),
    /// Measure disks per second and peak memory per disk (MX quadtree vs grid)
    /// on square domains with the thesis' Table 3.4 grading; writes bench.csv.
    Bench(BenchArgs),
}

#[derive(Args)]
struct BenchArgs {
    /// Largest disk count measured: 10⁴, 10⁵ and 10⁶ up to this.
    #[arg(long, default_value_t = 1_000_000, value_name = "N")]
    max: u64,
    /// Runs per configuration; the fastest is kept.
    #[arg(long, default_value_t = 3, value_name = "N")]
    repeats: usize,
    /// Output directory for bench.csv.
    #[arg(long, value_name = "DIR", default_value = "out/bench")]
    out: PathBuf,
}

#[derive(Args)]
struct CompareArgs {
    /// Scene config (TOML); an [optimise] target, if any, gives the porosity error.
    config: PathBuf,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(Args)]
struct StabilityArgs {
    /// Scene config (TOML): its grading's d_max and basis, packer settings,
    /// seed and [compare] methods set the sweep.
    config: PathBuf,
    /// Seconds a run may take before it counts as not finished.
    #[arg(long, default_value_t = 10.0, value_name = "S")]
    time_cap: f64,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(Args)]
struct OptimiseArgs {
    /// Config (TOML) with an [optimise] table.
    config: PathBuf,
    /// Write the search's state to <out>/checkpoint.json every N generations
    /// (0: never); it is also written when Ctrl-C or SIGTERM stops the
    /// search, and removed when the search ends by itself.
    #[arg(long, default_value_t = 10, value_name = "N")]
    checkpoint_every: usize,
    /// Go on from <out>/checkpoint.json (same config and seed), to the same
    /// result as a run never stopped.
    #[arg(long)]
    resume: bool,
    #[command(flatten)]
    run: RunArgs,
}

/// File name of a search's checkpoint, in the output directory.
const CHECKPOINT_JSON: &str = "checkpoint.json";

/// `checkpoint.json`: the search's state and what it belongs to. The search
/// is borrowed when written, owned when read.
#[derive(serde::Serialize, serde::Deserialize)]
struct CheckpointFile<'a> {
    /// gapack version that wrote it.
    gapack_version: String,
    /// The config as given.
    config: String,
    /// FNV-1a of the config text and the seed: a checkpoint resumes only the run it came from.
    identity: String,
    /// The search.
    search: std::borrow::Cow<'a, gapack::ga::Checkpoint>,
}

/// FNV-1a (64 bits) of the config's text and the seed, as hex.
fn run_identity(path: &Path, seed: u64) -> Result<String, Failure> {
    let text = std::fs::read(path)
        .with_context(|| format!("cannot read {}", path.display()))
        .map_err(Failure::Input)?;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.iter().chain(&seed.to_le_bytes()) {
        h ^= u64::from(*byte);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    Ok(format!("{h:016x}"))
}

/// Read `<out>/checkpoint.json` and check it belongs to this config and seed.
fn read_checkpoint(out: &Path, identity: &str) -> Result<gapack::ga::Checkpoint, Failure> {
    let path = out.join(CHECKPOINT_JSON);
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("--resume: cannot read {}", path.display()))
        .map_err(Failure::Input)?;
    let file: CheckpointFile = serde_json::from_str(&text)
        .with_context(|| format!("--resume: {} is not a gapack checkpoint", path.display()))
        .map_err(Failure::Input)?;
    if file.identity != identity {
        return Err(Failure::Input(anyhow::anyhow!(
            "--resume: {} was written for another config or seed ({}); run without --resume to start afresh",
            path.display(),
            file.config
        )));
    }
    Ok(file.search.into_owned())
}

#[derive(Args)]
struct LayerArgs {
    /// Config (TOML) with [[materials]] and a [layering] table.
    config: PathBuf,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(Args)]
struct PackArgs {
    /// Scene config (TOML); without it the embedded default scene is packed.
    config: Option<PathBuf>,
    #[command(flatten)]
    run: RunArgs,
}

/// Options of every run that writes a packing.
#[derive(Args)]
struct RunArgs {
    /// Output directory [default: the config's `[output] dir`, else
    /// out/<config file stem>, or out/default].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Seed of the random sizes (and of the search), overriding the config's `seed`.
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Neither progress bar nor result line.
    #[arg(long)]
    quiet: bool,
    /// Run even if the scene is over the config's [limits] (particles, memory).
    #[arg(long)]
    force: bool,
}

/// A failed run: the error and the exit code it maps to.
enum Failure {
    /// Bad input (unreadable or invalid config): exit code 2.
    Input(anyhow::Error),
    /// The run itself failed (packing, writing): exit code 1.
    Run(anyhow::Error),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Pack(args) => run_pack(&args),
        Command::Optimise(args) => run_optimise(&args),
        Command::Layer(args) => run_layer(&args),
        Command::Compare(args) => run_compare(&args),
        Command::Stability(args) => run_stability(&args),
        Command::Validate(args) => cli::inspect::run_validate(&args),
        Command::Verify(args) => cli::inspect::run_verify(&args),
        Command::Plot(args) => cli::inspect::run_plot(&args),
        Command::Bench(args) => run_bench(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let (err, code) = match failure {
                Failure::Input(err) => (err, 2),
                Failure::Run(err) => (err, 1),
            };
            eprintln!("error: {err:#}");
            ExitCode::from(code)
        }
    }
}

/// `gapack pack`: read and validate the config, pack, measure, write, report.
fn run_pack(args: &PackArgs) -> Result<(), Failure> {
    let (config, origin, out) = prepare(args.config.as_deref(), &args.run)?;
    if let Some(run) = &config.fracture {
        return run_fracture(&config, run, &origin, &out, args.run.quiet);
    }
    let scene = &config.scene;
    let start = Instant::now();
    let mut packing = pack_shown(scene, args.run.quiet)?;
    let seconds = start.elapsed().as_secs_f64();
    if config.materials.len() == 1 && packing.materials.is_empty() {
        packing.materials = vec![0; packing.disks.len()];
    }
    let metrics = measure(&packing, scene);
    let run = RunInfo {
        materials: &config.materials,
        ..RunInfo::new(scene, &origin, seconds, &config.output)
    };
    write(&out, &packing, &metrics, &run)?;
    report(args.run.quiet, || pack_line(&out, &metrics, seconds));
    Ok(())
}

/// `out/x: 345 disks, porosity 0.2139, psd_ks 0.061, max overlap 7.3e-14, coordination 3.69, packed in 0.3 ms`.
fn pack_line(out: &Path, metrics: &gapack::Metrics, seconds: f64) -> String {
    format!(
        "{}: {} disks, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, packed in {}",
        out.display(),
        metrics.particles,
        metrics.porosity,
        metrics.psd_ks,
        overlap(metrics.max_overlap),
        metrics.coordination,
        duration(seconds),
    )
}

/// `gapack pack` on a `[fracture]` config: each fracture whole or as a
/// window; a batch writes one sub-directory per well, then `wells.csv`.
fn run_fracture(
    config: &Config,
    run: &FractureRun,
    origin: &str,
    out: &Path,
    quiet: bool,
) -> Result<(), Failure> {
    let bar = if run.batch {
        count_bar(run.wells.len(), "well", quiet)
    } else {
        ProgressBar::hidden()
    };
    let mut rows = Vec::with_capacity(run.wells.len());
    for well in &run.wells {
        bar.set_message(well.name.clone());
        let dir = if run.batch {
            out.join(&well.name)
        } else {
            out.to_path_buf()
        };
        let (row, line) = pack_well(config, run.extent, well, origin, &dir)?;
        bar.inc(1);
        bar.suspend(|| report(quiet, || line));
        rows.push(row);
    }
    bar.finish_and_clear();
    if run.batch {
        let table = wells_csv(&rows)
            .context("cannot write the wells table")
            .map_err(Failure::Run)?;
        write_table(out, WELLS_CSV, table)
            .context("cannot write the wells table")
            .map_err(Failure::Run)?;
        report(quiet, || {
            format!(
                "{}: {} wells in {}",
                out.join(WELLS_CSV).display(),
                rows.len(),
                duration(rows.iter().map(|r| r.seconds).sum())
            )
        });
    }
    Ok(())
}

/// Pack one fracture, whole or as a window, and write its outputs into `dir`:
/// its row of `wells.csv` and its result line.
fn pack_well(
    config: &Config,
    extent: Extent,
    well: &Well,
    origin: &str,
    dir: &Path,
) -> Result<(WellRow, String), Failure> {
    let failed = |e: anyhow::Error| Failure::Run(e.context(format!("cannot pack {}", well.name)));
    let (mut packing, scene, seconds, window) = match extent {
        Extent::Full => {
            let start = Instant::now();
            let packing = pack(&well.scene).map_err(|e| failed(e.into()))?;
            let seconds = start.elapsed().as_secs_f64();
            (packing, well.scene.clone(), seconds, None)
        }
        Extent::Window { tolerance } => {
            let window = settle(well, tolerance).map_err(|e| failed(e.into()))?;
            let seconds = window.seconds;
            (
                window.packing.clone(),
                window.scene.clone(),
                seconds,
                Some(window),
            )
        }
    };
    if config.materials.len() == 1 && packing.materials.is_empty() {
        packing.materials = vec![0; packing.disks.len()];
    }
    let metrics = measure(&packing, &scene);
    let run = RunInfo {
        materials: &config.materials,
        fracture: Some(FractureInfo {
            well,
            extent,
            window: window.as_ref(),
        }),
        ..RunInfo::new(&scene, origin, seconds, &config.output)
    };
    write(dir, &packing, &metrics, &run)?;
    let f = well.fracture;
    let mut row = WellRow {
        well: well.name.clone(),
        width_mm: f.width,
        height_m: f.length / MM_PER_M,
        particles: metrics.particles,
        porosity: metrics.porosity,
        psd_ks: metrics.psd_ks,
        coordination: metrics.coordination,
        seconds,
    };
    let line = match window.as_ref().and_then(|w| w.last().map(|last| (w, last))) {
        None => pack_line(dir, &metrics, seconds),
        Some((w, last)) => {
            row.porosity = last.porosity;
            row.coordination = last.coordination;
            format!(
                "{}: window {:.1} mm of {:.0} mm ({:.1}%), porosity {:.4} ± {:.4}, coordination {:.2}, {} disks, {} windows in {}{}",
                dir.display(),
                last.length,
                f.length,
                100.0 * last.length / f.length,
                last.porosity,
                last.spread,
                last.coordination,
                last.particles,
                w.steps.len(),
                duration(seconds),
                if w.settled {
                    ""
                } else {
                    " (not settled: the whole fracture was packed)"
                }
            )
        }
    };
    Ok((row, line))
}

/// `gapack compare`: every method variant on the scene, `repeats` seeds
/// each; the table, the chart and one line per variant.
fn run_compare(args: &CompareArgs) -> Result<(), Failure> {
    let (config, _origin, out) = prepare(Some(&args.config), &args.run)?;
    let settings = &config.compare;
    let target = config.optimise.map(|o| o.target_porosity);
    let total = Variant::expand(&settings.methods).len() * settings.repeats;
    let bar = count_bar(total, "run", args.run.quiet);
    let runs = compare(&config.scene, settings, target, |r| {
        bar.set_message(variant_label(&r.variant));
        bar.inc(1);
    })
    .context("cannot pack the scene")
    .map_err(Failure::Run)?;
    bar.finish_and_clear();
    write_compare(&out, &runs, target.is_some())
        .context("cannot write the outputs")
        .map_err(Failure::Run)?;
    for variant in Variant::expand(&settings.methods) {
        let mine: Vec<&CompareRun> = runs.iter().filter(|r| r.variant == variant).collect();
        let n = mine.len().max(1) as f64;
        let mean = |f: fn(&CompareRun) -> f64| mine.iter().map(|r| f(r)).sum::<f64>() / n;
        let worst_overlap = mine.iter().map(|r| r.max_overlap).fold(0.0, f64::max);
        report(args.run.quiet, || {
            format!(
                "{:<40} {} runs: {} disks, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, {} each",
                variant_label(&variant),
                mine.len(),
                mean(|r| r.particles as f64).round(),
                mean(|r| r.porosity),
                mean(|r| r.psd_ks),
                overlap(worst_overlap),
                mean(|r| r.coordination),
                duration(mean(|r| r.seconds)),
            )
        });
    }
    report(args.run.quiet, || {
        format!("{}: compare.csv, compare.svg, compare.png", out.display())
    });
    Ok(())
}

/// `gapack stability`: the sweep, the table, the map and one line per method.
fn run_stability(args: &StabilityArgs) -> Result<(), Failure> {
    let cap = match std::time::Duration::try_from_secs_f64(args.time_cap) {
        Ok(cap) if !cap.is_zero() => cap,
        _ => {
            return Err(Failure::Input(anyhow::anyhow!(
                "--time-cap must be a positive number of seconds, got {}",
                args.time_cap
            )));
        }
    };
    let (config, _origin, out) = prepare(Some(&args.config), &args.run)?;
    let variants = stability::variants(&config.compare.methods);
    let total = stability::Case::all().len() * variants.len();
    let bar = count_bar(total, "run", args.run.quiet);
    let cases = stability::Case::all();
    let runs = stability::sweep(&config.scene, &cases, &variants, cap, |r| {
        bar.set_message(format!(
            "{} {}",
            variant_label(&r.variant),
            r.case.shape.name()
        ));
        bar.inc(1);
    });
    bar.finish_and_clear();
    write_stability(&out, &runs)
        .context("cannot write the outputs")
        .map_err(Failure::Run)?;
    for variant in &variants {
        let mine: Vec<&StabilityRun> = runs.iter().filter(|r| r.variant == *variant).collect();
        let count = |f: &dyn Fn(&StabilityRun) -> bool| mine.iter().filter(|r| f(r)).count();
        report(args.run.quiet, || {
            format!(
                "{:<40} pass {:>3}, fail {:>3} (overlap {}, empty {}, KS {}), refused {:>3}, timed out {:>3}",
                variant_label(variant),
                count(&|r| r.passed()),
                count(&|r| r.status == Status::Finished && !r.passed()),
                count(&|r| r.status == Status::Finished && r.max_overlap > OVERLAP_REL),
                count(&|r| r.status == Status::Finished && r.empty > stability::MAX_EMPTY),
                count(&|r| r.status == Status::Finished && r.grading_bent()),
                count(&|r| r.status == Status::Refused),
                count(&|r| r.status == Status::TimedOut),
            )
        });
    }
    report(args.run.quiet, || {
        format!(
            "{}: stability.csv, stability.svg, stability.png",
            out.display()
        )
    });
    Ok(())
}

/// The one fracture of a `[fracture]` config that `optimise` or `layer`
/// packs whole (a batch or a window is refused by the config).
fn whole_fracture(config: &Config) -> Option<FractureInfo<'_>> {
    config.fracture.as_ref().and_then(|run| {
        run.wells.first().map(|well| FractureInfo {
            well,
            extent: Extent::Full,
            window: None,
        })
    })
}

/// `gapack layer`: pack the scene once, lay the materials out along the
/// profile (baseline, then the GA), write, report.
fn run_layer(args: &LayerArgs) -> Result<(), Failure> {
    let (config, origin, out) = prepare(Some(&args.config), &args.run)?;
    let Some(settings) = &config.layering else {
        return Err(Failure::Input(anyhow::anyhow!(
            "{origin}:1:1: layering: missing table [layering]; gapack layer needs one with at least profile, and [[materials]] (see docs/config.md)"
        )));
    };
    let scene = &config.scene;
    let stop = stop_flag();
    let start = Instant::now();
    let mut packing = pack_shown(scene, args.run.quiet)?;
    let seconds = start.elapsed().as_secs_f64();
    let layered = lay_out_shown(&packing, settings, &config, &stop, args.run.quiet);
    packing.materials = layered.assignment.clone();
    let metrics = measure(&packing, scene);
    let run = RunInfo {
        materials: &config.materials,
        layering: Some((settings, &layered)),
        fracture: whole_fracture(&config),
        ..RunInfo::new(scene, &origin, seconds, &config.output)
    };
    write(&out, &packing, &metrics, &run)?;
    report(args.run.quiet, || {
        format!(
            "{}: {} disks, porosity {:.4}, {}",
            out.display(),
            metrics.particles,
            metrics.porosity,
            layering_line(&layered)
        )
    });
    Ok(())
}

/// `gapack optimise`: search for the target porosity, lay out the materials
/// if the config has a `[layering]`, write the best packing found and the
/// convergence record, report.
fn run_optimise(args: &OptimiseArgs) -> Result<(), Failure> {
    let (config, origin, out) = prepare(Some(&args.config), &args.run)?;
    let Some(settings) = config.optimise else {
        return Err(Failure::Input(anyhow::anyhow!(
            "{origin}:1:1: optimise: missing table [optimise]; gapack optimise needs one with at least target_porosity (see docs/config.md)"
        )));
    };
    let scene = &config.scene;
    let stop = stop_flag();
    let identity = run_identity(&args.config, scene.seed)?;
    let problem = PorosityProblem::new(scene, settings);
    let limits = Limits::from(&settings);
    let search = if args.resume {
        let checkpoint = read_checkpoint(&out, &identity)?;
        Search::resume(&problem, limits, &checkpoint)
            .context("--resume")
            .map_err(Failure::Input)?
    } else {
        Search::start(&problem, limits, scene.seed)
    };
    let initial_range = PorosityProblem::range(search.initial());
    if !problem.feasible(initial_range) && !args.run.quiet && !args.resume {
        eprintln!(
            "note: target porosity {} lies outside the range of the initial population, [{:.4}, {:.4}]; searching beyond it",
            settings.target_porosity, initial_range[0], initial_range[1]
        );
    }
    let bar = progress_bar(settings.generations, args.run.quiet);
    let checkpoint_path = out.join(CHECKPOINT_JSON);
    let mut save_failed: Option<anyhow::Error> = None;
    let evolution = search.run_saving(
        &stop,
        |g| {
            bar.set_position(g.index as u64);
            bar.set_message(format!("best porosity {:.4}", g.best.value));
        },
        args.checkpoint_every,
        |checkpoint| {
            let file = CheckpointFile {
                gapack_version: env!("CARGO_PKG_VERSION").to_owned(),
                config: args.config.display().to_string(),
                identity: identity.clone(),
                search: std::borrow::Cow::Borrowed(checkpoint),
            };
            let saved = serde_json::to_vec(&file)
                .context("cannot format the checkpoint")
                .and_then(|bytes| {
                    std::fs::create_dir_all(&out)
                        .with_context(|| format!("cannot create {}", out.display()))?;
                    gapack::output::write_atomic(&checkpoint_path, &bytes)
                        .context("cannot write the checkpoint")
                });
            if let Err(e) = saved {
                // Stop at the next generation: the best so far is still written.
                stop.store(true, Ordering::Relaxed);
                save_failed.get_or_insert(e);
            }
        },
    );
    bar.finish_and_clear();

    let reached = evolution.stop == StopReason::Reached;
    let range = evolution.explored;
    let feasible = reached || problem.feasible(range);
    if !feasible {
        eprintln!(
            "warning: target porosity {} is out of reach: the packings that honour the grading span [{:.4}, {:.4}]; the nearest one, {:.4}, is written",
            settings.target_porosity, range[0], range[1], evolution.best.value
        );
    }
    let Some(mut packing) = evolution.outcome else {
        return Err(Failure::Run(anyhow::anyhow!(
            "no genome could be packed: the domain is too small for the grading"
        )));
    };
    let best_scene = problem.scene_of(&evolution.genes);
    let layered = config
        .layering
        .as_ref()
        .map(|l| lay_out_shown(&packing, l, &config, &stop, args.run.quiet));
    if let Some(l) = &layered {
        packing.materials = l.assignment.clone();
    } else if config.materials.len() == 1 && packing.materials.is_empty() {
        packing.materials = vec![0; packing.disks.len()];
    }
    let metrics = measure(&packing, &best_scene);
    let summary = OptimiseSummary {
        target_porosity: settings.target_porosity,
        tolerance: settings.tolerance,
        best_porosity: metrics.porosity,
        error: (metrics.porosity - settings.target_porosity).abs(),
        max_psd_ks: settings.max_psd_ks,
        evaluations: evolution.evaluations,
        generations: evolution.history.len().saturating_sub(1),
        population: settings.population,
        feasible,
        achievable_range: range,
        initial_range,
        interrupted: evolution.stop == StopReason::Interrupted,
        stop: evolution.stop.describe(),
    };
    let run = RunInfo {
        materials: &config.materials,
        optimise: Some((&summary, &evolution.history)),
        layering: config.layering.as_ref().zip(layered.as_ref()),
        fracture: whole_fracture(&config),
        ..RunInfo::new(&best_scene, &origin, evolution.seconds, &config.output)
    };
    write(&out, &packing, &metrics, &run)?;
    if let Some(e) = save_failed {
        return Err(Failure::Run(e.context(format!(
            "the search stopped, its best packing is written to {}",
            out.display()
        ))));
    }
    if evolution.stop == StopReason::Interrupted && checkpoint_path.exists() && !args.run.quiet {
        eprintln!(
            "note: stopped after generation {}; `gapack optimise {} --resume` goes on from {}",
            evolution.history.len().saturating_sub(1),
            args.config.display(),
            checkpoint_path.display()
        );
    }
    if evolution.stop != StopReason::Interrupted && checkpoint_path.exists() {
        // The search is over: nothing is left to resume.
        std::fs::remove_file(&checkpoint_path)
            .with_context(|| format!("cannot remove {}", checkpoint_path.display()))
            .map_err(Failure::Run)?;
    }
    report(args.run.quiet, || {
        let layering = layered
            .as_ref()
            .map_or(String::new(), |l| format!("; {}", layering_line(l)));
        format!(
            "{}: porosity {:.4} (target {}, error {:.4}), psd_ks {:.3}, {} disks, {} evaluations in {} generations, {} ({}){layering}",
            out.display(),
            metrics.porosity,
            settings.target_porosity,
            summary.error,
            metrics.psd_ks,
            metrics.particles,
            summary.evaluations,
            summary.generations,
            duration(evolution.seconds),
            summary.stop,
        )
    });
    Ok(())
}

/// Packs expected to hold at least this many disks show a progress bar
/// (about a second at the generator's speed).
const LARGE_PACK: f64 = 200_000.0;

/// Pack `scene`, with a progress bar over the expected disks when the pack is large.
fn pack_shown(scene: &gapack::Scene, quiet: bool) -> Result<gapack::Packing, Failure> {
    let expected = scene.estimated_disks();
    let bar = if expected >= LARGE_PACK {
        count_bar(expected as usize, "disk", quiet)
    } else {
        ProgressBar::hidden()
    };
    let len = bar.length().unwrap_or(0);
    let packing = pack_observed(scene, &mut |drawn| bar.set_position(drawn.min(len)))
        .context("cannot pack the scene")
        .map_err(Failure::Run);
    bar.finish_and_clear();
    packing
}

/// Lay the config's materials out on `packing`, with a progress bar over the GA's generations.
fn lay_out_shown(
    packing: &gapack::Packing,
    settings: &gapack::layering::LayeringSettings,
    config: &Config,
    stop: &AtomicBool,
    quiet: bool,
) -> Layered {
    let bar = progress_bar(settings.generations, quiet);
    let layered = lay_out(
        packing,
        settings,
        config.materials.len(),
        config.scene.seed,
        stop,
        |g| {
            bar.set_position(g.index as u64);
            bar.set_message(format!("profile RMS {:.4}", g.best.value));
        },
    );
    bar.finish_and_clear();
    layered
}

/// The config of a run (seed overridden), its origin for messages, and the
/// output directory.
fn prepare(path: Option<&Path>, run: &RunArgs) -> Result<(Config, String, PathBuf), Failure> {
    let (mut config, origin) = load_config(path, run.force).map_err(Failure::Input)?;
    if let Some(seed) = run.seed {
        config.scene.seed = seed;
    }
    let out = output_dir(run.out.as_deref(), &config, path);
    Ok((config, origin, out))
}

/// A flag Ctrl-C raises. Without a handler (one is already installed)
/// Ctrl-C ends the process: the outputs are written atomically, so nothing
/// partial is left either way.
fn stop_flag() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    stop
}

/// Write a run's outputs, a failure mapped to exit code 1.
fn write(
    out: &Path,
    packing: &gapack::Packing,
    metrics: &gapack::Metrics,
    run: &RunInfo<'_>,
) -> Result<(), Failure> {
    write_outputs(out, packing, metrics, run)
        .context("cannot write the outputs")
        .map_err(Failure::Run)
}

/// `profile RMS 0.0123 (baseline 0.0187), GA 1.20 s, baseline 2.1 ms`.
fn layering_line(l: &Layered) -> String {
    if l.stop.is_none() {
        format!("profile RMS {:.4} (size-graded)", l.rms)
    } else {
        format!(
            "profile RMS {:.4} (baseline {:.4}), GA {} ({} evaluations), baseline {}",
            l.rms,
            l.baseline_rms,
            duration(l.seconds),
            l.evaluations,
            duration(l.baseline_seconds)
        )
    }
}

/// Print a run's one result line on stdout, unless `quiet`.
fn report(quiet: bool, line: impl FnOnce() -> String) {
    if !quiet {
        // A closed stdout (e.g. `| head -0`) is no reason to fail a finished run.
        let _ = writeln!(std::io::stdout(), "{}", line());
    }
}

/// A progress bar over the generations on stderr, hidden when `quiet` or
/// when stderr is not a terminal.
fn progress_bar(generations: usize, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(generations as u64);
    if let Ok(style) =
        ProgressStyle::with_template("generation {pos:>4}/{len} [{bar:30}] {msg} ({elapsed})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// A progress bar over `len` items on stderr, hidden when `quiet` or when
/// stderr is not a terminal.
fn count_bar(len: usize, what: &str, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len as u64);
    let template = format!("{what} {{pos:>3}}/{{len}} [{{bar:30}}] {{msg}} ({{elapsed}})");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// `gapack bench`: print one table row per measured configuration, then write bench.csv.
fn run_bench(args: &BenchArgs) -> Result<(), Failure> {
    let targets: Vec<u64> = [10_000, 100_000, 1_000_000]
        .into_iter()
        .filter(|&n| n <= args.max)
        .collect();
    if targets.is_empty() {
        return Err(Failure::Input(anyhow::anyhow!(
            "--max {} is below the smallest benchmark (10000 disks)",
            args.max
        )));
    }
    println!(
        "{:>9} {:>9} {:>12} {:>9} {:>9} {:>9} {:>12} {:>10}",
        "target", "side_mm", "index", "disks", "porosity", "seconds", "disks/s", "bytes/disk"
    );
    let rows = bench::run(&targets, args.repeats, |r| {
        println!(
            "{:>9} {:>9.1} {:>12} {:>9} {:>9.4} {:>9.3} {:>12.0} {:>10.1}",
            r.target,
            r.side_mm,
            r.index,
            r.disks,
            r.porosity,
            r.seconds,
            r.disks_per_second,
            r.peak_bytes_per_disk
        );
    })
    .context("cannot run the benchmark")
    .map_err(Failure::Run)?;
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
    let path = args.out.join("bench.csv");
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))
        .map_err(Failure::Run)?;
    gapack::output::write_atomic(&path, &bytes)
        .context("cannot write bench.csv")
        .map_err(Failure::Run)?;
    println!("{}", path.display());
    Ok(())
}

/// The config and the origin named in messages and in `summary.json`;
/// `force` skips the `[limits]` refusals.
fn load_config(path: Option<&Path>, force: bool) -> anyhow::Result<(Config, String)> {
    let options = config::ParseOptions { force };
    let Some(path) = path else {
        return Ok((
            config::parse_with(DEFAULT_CONFIG, DEFAULT_ORIGIN, options)?,
            DEFAULT_ORIGIN.to_owned(),
        ));
    };
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {origin}"))?;
    Ok((config::parse_with(&text, &origin, options)?, origin))
}

/// Where a run of the config at `path` writes: `--out`, else `[output] dir`,
/// else [`default_out`].
fn output_dir(cli_out: Option<&Path>, config: &Config, path: Option<&Path>) -> PathBuf {
    cli_out
        .map(Path::to_path_buf)
        .or_else(|| config.output.dir.as_ref().map(PathBuf::from))
        .unwrap_or_else(|| default_out(path))
}

/// `out/<config file stem>`, or `out/default` for the embedded scene.
fn default_out(config: Option<&Path>) -> PathBuf {
    let stem = config
        .and_then(Path::file_stem)
        .map_or_else(|| "default".into(), |s| s.to_string_lossy().into_owned());
    Path::new("out").join(stem)
}

/// `0` for no overlap, else 2 significant digits.
fn overlap(v: f64) -> String {
    if v == 0.0 {
        "0".to_owned()
    } else {
        format!("{v:.1e}")
    }
}

/// `0.4 ms`, `812.3 ms`, `3.21 s`.
fn duration(seconds: f64) -> String {
    if seconds < 1.0 {
        format!("{:.1} ms", seconds * 1e3)
    } else {
        format!("{seconds:.2} s")
    }
}
