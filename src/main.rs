//! `gapack`: the command line, a thin layer over the library's jobs: clap
//! arguments → a [`Plan`], Ctrl-C and SIGTERM → its cancel token, events →
//! progress bars, the [`Outcome`] → result lines, the error → exit code 0
//! (success, or stopped with what was finished written), 1 (the run
//! failed), 2 (bad input: arguments or config) or 130 (stopped before
//! anything was finished).

mod bench;
mod cli;
mod serve;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};
use gapack::jobs::{self, Cancel, DirStore, JobError, JobKind, Outcome, Plan, Request};

use cli::{Failure, ProgressObserver, load_text, report};
#[cfg(feature = "mpi")]
use gapack::farm::Farm;

/// Counts heap bytes so that `gapack bench` can report peak memory per disk;
/// only in a binary built for it (`--features count-alloc`).
#[cfg(feature = "count-alloc")]
#[global_allocator]
static ALLOCATOR: bench::counting::PeakAlloc = bench::counting::PeakAlloc;

/// Dense 2D disk packings for DEM simulations.
#[derive(Parser)]
#[command(name = "gapack", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Pack a scene (the embedded default without a config)
    ///
    /// Writes summary.json and what [output] formats asks for (by default
    /// packing.csv and the packing, psd and porosity_map pictures as SVG and
    /// PNG; also packing.json, VTK and the LAMMPS, YADE, PFC, MercuryDPM and
    /// ESyS-Particle files); a [fracture] config packs each fracture (a
    /// batch: a folder each and wells.csv).
    Pack(JobArgs),
    /// Reach the config's target porosity with the genetic algorithm (needs
    /// an [optimise] table); writes what `pack` writes plus convergence.csv
    /// and its chart. Ctrl-C stops and writes the best so far and a checkpoint.
    #[command(visible_alias = "optimize")]
    Optimise(JobArgs),
    /// Lay materials out along the config's [layering] profile on one
    /// packing (baseline, then the GA; or size-graded packing); writes what
    /// `pack` writes with a material column, plus profile.csv and its chart.
    /// Ctrl-C stops the GA and writes the best layout so far.
    Layer(JobArgs),
    /// Run every generator of the config's [compare] table on its scene;
    /// writes compare.csv and a chart of time against accuracy. Ctrl-C
    /// stops and writes the runs finished.
    Compare(JobArgs),
    /// Sweep the [compare] methods over gradings (d_max/d_min 1 to 16),
    /// widths (1.2 to 20 d_max) and shapes; writes stability.csv and a map.
    /// Ctrl-C stops and writes the runs finished.
    Stability(JobArgs),
    /// Run the config's [sweep] parameter study: its job (pack, optimise or
    /// layer) at every combination of the swept values, over seeds; writes
    /// sweep.csv (a row per run) and a chart of the chosen measure. Ctrl-C
    /// stops and writes the runs finished; --resume runs the others.
    Sweep(JobArgs),
    /// Check a config without running it and print the plan the run would
    /// execute: job, scenes, estimated disks and memory, outputs.
    Validate(ValidateArgs),
    /// Check an existing packing (a CSV from gapack or any tool) against a
    /// config: overlaps, containment, porosity, grading (KS). Exit 1 if it fails.
    Verify(cli::inspect::VerifyArgs),
    /// Draw an existing packing (a CSV from gapack or any tool): packing,
    /// psd and porosity_map as SVG and PNG; with --config, its domain and target grading.
    Plot(cli::inspect::PlotArgs),
    /// Measure disks per second and peak memory per disk (MX quadtree vs grid)
    /// on square domains with the thesis' Table 3.4 grading; writes bench.csv.
    Bench(bench::BenchArgs),
    /// Run jobs as an HTTP service (submit, follow, cancel, fetch files);
    /// see docs/api.md. Runs until SIGINT or SIGTERM.
    Serve(serve::ServeArgs),
}

/// Options of every job.
#[derive(Args)]
struct JobArgs {
    /// Config (TOML); `pack` without one packs the embedded default scene.
    config: Option<PathBuf>,
    /// Output directory [default: the config's `[output] dir`, else
    /// out/<config file stem>; `pack` without a config: out/default].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Seed of the run, overriding the config's `seed`: its random sizes,
    /// and for optimise and layer also the GA's draws.
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Neither progress bar nor result line.
    #[arg(long)]
    quiet: bool,
    /// Start even if the scene's upper bound is over the config's [limits]; the
    /// limits still stop the run if the packing itself reaches them.
    #[arg(long)]
    force: bool,
    /// optimise: write <out>/checkpoint.json every N generations (0: never);
    /// it is also written when Ctrl-C or SIGTERM stops the search, and
    /// removed when the search ends by itself.
    #[arg(long, default_value_t = 10, value_name = "N")]
    checkpoint_every: usize,
    /// optimise: go on from <out>/checkpoint.json (same config and seed), to
    /// the same result as a run never stopped; sweep: keep the runs
    /// <out>/sweep.csv finished and run the others.
    #[arg(long)]
    resume: bool,
    /// stability: seconds a run may take before it counts as not finished.
    #[arg(long, default_value_t = 10.0, value_name = "S")]
    time_cap: f64,
}

/// `gapack validate` arguments: the run to preview.
#[derive(Args)]
struct ValidateArgs {
    /// Config (TOML) to check.
    config: PathBuf,
    /// The job to plan [default: optimise with an [optimise] table, else
    /// layer with a [layering] one, else pack].
    #[arg(long, value_name = "JOB", value_parser = job_kind)]
    job: Option<JobKind>,
    /// The output directory the run would use.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// The seed the run would use.
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Describe the scene even if it is over the config's [limits].
    #[arg(long)]
    force: bool,
}

fn job_kind(name: &str) -> Result<JobKind, String> {
    JobKind::ALL
        .into_iter()
        .find(|k| k.name() == name)
        .ok_or_else(|| {
            let names: Vec<&str> = JobKind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown job {name:?}: {}", names.join(", "))
        })
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Pack(args) => run_job(JobKind::Pack, &args),
        Command::Optimise(args) => run_job(JobKind::Optimise, &args),
        Command::Layer(args) => run_job(JobKind::Layer, &args),
        Command::Compare(args) => run_job(JobKind::Compare, &args),
        Command::Stability(args) => run_job(JobKind::Stability, &args),
        Command::Sweep(args) => run_job(JobKind::Sweep, &args),
        Command::Validate(args) => run_validate(&args),
        Command::Verify(args) => cli::inspect::run_verify(&args),
        Command::Plot(args) => cli::inspect::run_plot(&args),
        Command::Bench(args) => bench::run_command(&args),
        Command::Serve(args) => serve::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let code = exit_code(&failure);
            let (Failure::Input(err) | Failure::Run(err) | Failure::Stopped(err)) = failure;
            eprintln!("error: {err:#}");
            ExitCode::from(code)
        }
    }
}

/// 2 for bad input, 1 for a failed run, 130 for a run stopped before
/// anything was finished.
fn exit_code(failure: &Failure) -> u8 {
    match failure {
        Failure::Input(_) => 2,
        Failure::Run(_) => 1,
        Failure::Stopped(_) => 130,
    }
}

/// The request a job's arguments make.
fn request(kind: JobKind, args: &JobArgs) -> Result<Request, Failure> {
    let time_cap = Duration::try_from_secs_f64(args.time_cap)
        .ok()
        .filter(|cap| !cap.is_zero())
        .ok_or_else(|| {
            Failure::Input(anyhow::anyhow!(
                "--time-cap must be a positive number of seconds, got {}",
                args.time_cap
            ))
        })?;
    if kind == JobKind::Pack && args.config.is_none() {
        return Ok(Request {
            seed: args.seed,
            force: args.force,
            ..Request::new(kind)
        });
    }
    Ok(Request {
        seed: args.seed,
        force: args.force,
        resume: args.resume,
        checkpoint_every: args.checkpoint_every,
        time_cap,
        ..Request::new(kind)
    })
}

/// Run one job: plan it, run it with progress bars and Ctrl-C, report.
fn run_job(kind: JobKind, args: &JobArgs) -> Result<(), Failure> {
    if kind != JobKind::Pack && args.config.is_none() {
        return Err(Failure::Input(anyhow::anyhow!(
            "gapack {} needs a config file",
            kind.name()
        )));
    }
    #[cfg(feature = "mpi")]
    if let Some(ranks) = cli::ranks::Ranks::start() {
        // Every rank plans (alike); rank 0 alone tells what is wrong.
        return match plan_job(kind, args) {
            Ok(plan) => run_ranks(&plan, args, &ranks),
            Err(failure) if ranks.leads() => Err(failure),
            // The others end quietly: rank 0's exit code is the job's.
            Err(_) => Ok(()),
        };
    }
    let plan = plan_job(kind, args)?;
    let out = jobs::output_dir(args.out.as_deref(), &plan.config, args.config.as_deref());
    let mut store = DirStore::new(&out);
    let cancel = Cancel::new();
    let handler = cancel.clone();
    // The handler only raises the token, on a thread of its own: the
    // process never exits from a signal, so a run being committed finishes
    // its commit (or undoes it) and removes its temporary files before
    // `main` returns. Without a handler a signal would end the process
    // where it stands: say so rather than run unprotected in silence.
    if let Err(e) = ctrlc::set_handler(move || handler.cancel()) {
        eprintln!("warning: cannot catch Ctrl-C and SIGTERM ({e}); they will end gapack at once");
    }
    let mut observer = ProgressObserver::new(args.quiet);
    let outcome = jobs::run(&plan, &mut observer, &cancel, &mut store);
    observer.finish();
    tell(outcome, args)
}

/// The result lines of a job's outcome, or its failure.
fn tell(outcome: Result<Outcome, JobError>, args: &JobArgs) -> Result<(), Failure> {
    let outcome = outcome.map_err(|e| match e {
        JobError::Cancelled => Failure::Stopped(e.into()),
        e => cli::failure(e),
    })?;
    for line in outcome.lines() {
        report(args.quiet, || line);
    }
    if !args.quiet {
        cli::hint::after_stop(&outcome, args.config.as_deref(), args.seed, args.force);
    }
    Ok(())
}

/// The plan of the job `args` ask for.
fn plan_job(kind: JobKind, args: &JobArgs) -> Result<Plan, Failure> {
    let request = request(kind, args)?;
    let (text, origin) = load_text(args.config.as_deref())?;
    Plan::load(&text, &origin, &request).map_err(cli::failure)
}

/// Run one job on the ranks of an MPI launch: every rank runs the plan,
/// the work is shared out, rank 0 alone shows progress, catches Ctrl-C and
/// writes; the others keep their files in memory and drop them.
#[cfg(feature = "mpi")]
fn run_ranks(plan: &Plan, args: &JobArgs, ranks: &cli::ranks::Ranks) -> Result<(), Failure> {
    let cancel = Cancel::new();
    let handler = cancel.clone();
    let leads = ranks.leads();
    // Rank 0 decides when to stop; the others only keep the signal from
    // ending them before rank 0 has written.
    let raise = move || {
        if leads {
            handler.cancel();
        }
    };
    if let Err(e) = ctrlc::set_handler(raise) {
        eprintln!("warning: cannot catch Ctrl-C and SIGTERM ({e}); they will end gapack at once");
    }
    if !leads {
        let mut store = jobs::MemoryStore::default();
        let _ = jobs::run_on(plan, &mut jobs::Silent, &cancel, &mut store, ranks);
        ranks.wait_done();
    }
    let out = jobs::output_dir(args.out.as_deref(), &plan.config, args.config.as_deref());
    let mut store = DirStore::new(&out);
    let mut observer = ProgressObserver::new(args.quiet);
    let outcome = jobs::run_on(plan, &mut observer, &cancel, &mut store, ranks);
    observer.finish();
    ranks.done();
    tell(outcome, args)
}

/// `gapack validate`: the plan the run would execute, without running it.
fn run_validate(args: &ValidateArgs) -> Result<(), Failure> {
    let (text, origin) = load_text(Some(&args.config))?;
    let options = gapack::config::ParseOptions { force: args.force };
    let config = gapack::config::parse_with(&text, &origin, options)
        .map_err(|e| Failure::Input(e.into()))?;
    let request = Request {
        seed: args.seed,
        force: args.force,
        ..Request::new(args.job.unwrap_or_else(|| JobKind::natural(&config)))
    };
    let plan = Plan::new(config, &text, &origin, &request).map_err(cli::failure)?;
    let out = jobs::output_dir(args.out.as_deref(), &plan.config, Some(&args.config));
    report(false, || format!("{origin}: valid"));
    for line in plan.describe(&out.display().to_string()) {
        report(false, || format!("  {line}"));
    }
    Ok(())
}
