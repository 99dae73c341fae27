//! `gapack`: the command line. A thin layer over the library: parse the
//! arguments, run one subcommand, print one line, exit 0 (success),
//! 1 (the run failed) or 2 (bad input: arguments or config).
//!
//! Adding a subcommand = one variant of [`Command`] + one `run_*` function.

mod bench;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use gapack::config::{self, DEFAULT_CONFIG, DEFAULT_ORIGIN};
use gapack::output::{RunInfo, write_pack_outputs};
use gapack::{Scene, measure, pack};

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
struct PackArgs {
    /// Scene config (TOML); without it the embedded default scene is packed.
    config: Option<PathBuf>,
    /// Output directory [default: out/<config file stem>, or out/default].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Seed of the random sizes, overriding the config's `seed`.
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Do not print the result line.
    #[arg(long)]
    quiet: bool,
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
    let (mut scene, origin) = load_scene(args.config.as_deref()).map_err(Failure::Input)?;
    if let Some(seed) = args.seed {
        scene.seed = seed;
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| default_out(args.config.as_deref()));

    let start = Instant::now();
    let packing = pack(&scene)
        .context("cannot pack the scene")
        .map_err(Failure::Run)?;
    let seconds = start.elapsed().as_secs_f64();
    let metrics = measure(&packing, &scene.grading);

    let run = RunInfo {
        scene: &scene,
        config: &origin,
        seconds,
    };
    write_pack_outputs(&out, &packing, &metrics, &run)
        .context("cannot write the outputs")
        .map_err(Failure::Run)?;

    if !args.quiet {
        let line = format!(
            "{}: {} disks, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, packed in {}",
            out.display(),
            metrics.particles,
            metrics.porosity,
            metrics.psd_ks,
            overlap(metrics.max_overlap),
            metrics.coordination,
            duration(seconds),
        );
        // A closed stdout (e.g. `| head -0`) is no reason to fail a finished run.
        let _ = writeln!(std::io::stdout(), "{line}");
    }
    Ok(())
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

/// The scene and the origin named in messages and in `summary.json`.
fn load_scene(path: Option<&Path>) -> anyhow::Result<(Scene, String)> {
    let Some(path) = path else {
        return Ok((
            config::parse(DEFAULT_CONFIG, DEFAULT_ORIGIN)?,
            DEFAULT_ORIGIN.to_owned(),
        ));
    };
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {origin}"))?;
    Ok((config::parse(&text, &origin)?, origin))
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
