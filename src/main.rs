//! `gapack`: the command line. A thin layer over the library: parse the
//! arguments, run one subcommand, print one line, exit 0 (success),
//! 1 (the run failed) or 2 (bad input: arguments or config).
//!
//! Adding a subcommand = one variant of [`Command`] + one `run_*` function.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use gapack::config::{self, DEFAULT_CONFIG, DEFAULT_ORIGIN};
use gapack::output::{RunInfo, write_pack_outputs};
use gapack::{Scene, measure, pack};

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
