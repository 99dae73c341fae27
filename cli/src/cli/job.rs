//! The job subcommands (`pack`, `optimise`, `layer`, `compare`,
//! `stability`, `sweep`) and `validate`: their arguments → a [`Plan`], Ctrl-C
//! and SIGTERM → its cancel token, events → progress bars, the [`Outcome`]
//! → result lines.

use std::path::PathBuf;
use std::time::Duration;

use clap::Args;
#[cfg(feature = "mpi")]
use gapack::farm::Farm;
use gapack::jobs::{self, Cancel, DirStore, JobError, JobKind, Outcome, Plan, Request, Summary};

use super::{Failure, ProgressObserver, load_text, report};

/// Options of every job.
#[derive(Args)]
pub struct JobArgs {
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
    /// Also print where the run's time went: packing, measuring, and the
    /// check with every file written, in wall-clock seconds.
    #[arg(long)]
    timings: bool,
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
pub struct ValidateArgs {
    /// Config (TOML) to check.
    config: PathBuf,
    /// The job to plan [default: the config's own: sweep with a [sweep]
    /// table, else optimise with an [optimise] one, else layer with a
    /// [layering] one, else pack].
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
    JobKind::named(name).ok_or_else(|| format!("unknown job {name:?}: {}", JobKind::names()))
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
pub fn run_job(kind: JobKind, args: &JobArgs) -> Result<(), Failure> {
    if kind != JobKind::Pack && args.config.is_none() {
        return Err(Failure::Input(anyhow::anyhow!(
            "gapack {} needs a config file",
            kind.name()
        )));
    }
    #[cfg(feature = "mpi")]
    if let Some(ranks) = super::ranks::Ranks::start() {
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
        e => super::failure(e),
    })?;
    for line in Summary::of(&outcome, &outcome.location).lines {
        report(args.quiet, || line);
    }
    if args.timings
        && let Some(line) = outcome.timings_line()
    {
        super::print_line(line);
    }
    if !args.quiet {
        super::hint::after_stop(&outcome, args.config.as_deref(), args.seed, args.force);
    }
    Ok(())
}

/// The plan of the job `args` ask for.
fn plan_job(kind: JobKind, args: &JobArgs) -> Result<Plan, Failure> {
    let request = request(kind, args)?;
    let (text, origin) = load_text(args.config.as_deref())?;
    Plan::load(&text, &origin, &request).map_err(super::failure)
}

/// Run one job on the ranks of an MPI launch: every rank runs the plan,
/// the work is shared out, rank 0 alone shows progress, catches Ctrl-C and
/// writes; the others keep their files in memory and drop them.
#[cfg(feature = "mpi")]
fn run_ranks(plan: &Plan, args: &JobArgs, ranks: &super::ranks::Ranks) -> Result<(), Failure> {
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
pub fn run_validate(args: &ValidateArgs) -> Result<(), Failure> {
    let (text, origin) = load_text(Some(&args.config))?;
    let request = Request {
        seed: args.seed,
        force: args.force,
        ..Request::asking(args.job)
    };
    let plan = Plan::load(&text, &origin, &request).map_err(super::failure)?;
    let out = jobs::output_dir(args.out.as_deref(), &plan.config, Some(&args.config));
    report(false, || format!("{origin}: valid"));
    for line in plan.describe(&out.display().to_string()) {
        report(false, || format!("  {line}"));
    }
    Ok(())
}
