//! `gapack`: the command line, a thin layer over the library's jobs: clap
//! arguments → a [`Plan`], Ctrl-C and SIGTERM → its cancel token, events →
//! progress bars, the [`Outcome`] → result lines (or one JSON object), the
//! error → an exit code ([`EXIT_CODES`]).

mod bench;
mod cli;

use std::process::ExitCode;

use clap::{ColorChoice, CommandFactory, FromArgMatches, Parser, Subcommand};
use gapack::jobs::JobKind;

use cli::Failure;
use cli::job::{JobArgs, ValidateArgs, run_job, run_validate};

/// Counts heap bytes so that `gapack bench` can report peak memory per disk;
/// only in a binary built for it (`--features count-alloc`).
#[cfg(feature = "count-alloc")]
#[global_allocator]
static ALLOCATOR: bench::counting::PeakAlloc = bench::counting::PeakAlloc;

/// `gapack --version`: the version Cargo builds (one place: Cargo.toml)
/// and the commit it was built from (`build.rs`).
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("GAPACK_BUILD_COMMIT"),
    ")"
);

/// The exit codes, as `gapack --help` and docs/usage.md list them.
const EXIT_CODES: &str = "\
Exit status:
  0    success; also a run stopped by Ctrl-C or SIGTERM that wrote what it
       had finished (a note on stderr says so)
  1    the run failed (packing, checking or writing), or `gapack verify`
       found the packing not valid
  2    bad input: unknown command or option, bad option value, unreadable
       or invalid config, a packing table that cannot be read
  101  an internal error (a panic): a bug, please report it
  130  stopped by Ctrl-C or SIGTERM before anything was finished";

/// Dense 2D disk packings for DEM simulations.
#[derive(Parser)]
#[command(name = "gapack", version = VERSION, about, after_help = EXIT_CODES)]
struct Cli {
    /// When to colour help, errors and warnings: auto (on a terminal,
    /// unless NO_COLOR is set), always or never.
    #[arg(long, global = true, value_enum, value_name = "WHEN", default_value_t = ColorChoice::Auto)]
    color: ColorChoice,
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
    /// Write an existing packing (a CSV from gapack or any tool) in the DEM
    /// and viewer formats of a config's [output] formats (vtk, lammps,
    /// liggghts-superquadric, mercury, yade, pfc, esys).
    Export(cli::inspect::ExportArgs),
    /// Draw an existing packing (a CSV from gapack or any tool): packing,
    /// psd and porosity_map as SVG and PNG; with --config, its domain and target grading.
    Plot(cli::inspect::PlotArgs),
    /// Measure disks per second and peak memory per disk (MX quadtree vs grid)
    /// on square domains with the thesis' Table 3.4 grading; writes bench.csv.
    Bench(bench::BenchArgs),
    /// Run jobs as an HTTP service (submit, follow, cancel, fetch files);
    /// see docs/api.md. Runs until SIGINT or SIGTERM.
    Serve(cli::serve::ServeArgs),
    /// Run jobs from a shared job store (PostgreSQL) for the fronts
    /// (gapack serve) that queue them; see docs/deploy.md. Runs until
    /// SIGINT or SIGTERM, which puts its running jobs back in the queue.
    Worker(cli::serve::WorkerArgs),
    /// Add, revoke or list the service's users.
    #[command(subcommand)]
    User(cli::serve::UserCommand),
    /// Print the shell completion script of bash, zsh, fish, powershell or
    /// elvish (e.g. `source <(gapack completions bash)`).
    Completions(cli::docs::CompletionsArgs),
    /// Print the manual page (roff: `gapack man | man -l -`), or write one
    /// page per command with --dir.
    Man(cli::docs::ManArgs),
}

fn main() -> ExitCode {
    // `--color` is read ahead of clap so that clap's own errors follow it.
    let colour = cli::colour::choice_in(std::env::args_os());
    let command = Cli::command().color(colour);
    let cli = match command
        .try_get_matches()
        .and_then(|matches| Cli::from_arg_matches(&matches))
    {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    cli::colour::init(cli.color);
    let result = match cli.command {
        Command::Pack(args) => run_job(JobKind::Pack, &args),
        Command::Optimise(args) => run_job(JobKind::Optimise, &args),
        Command::Layer(args) => run_job(JobKind::Layer, &args),
        Command::Compare(args) => run_job(JobKind::Compare, &args),
        Command::Stability(args) => run_job(JobKind::Stability, &args),
        Command::Sweep(args) => run_job(JobKind::Sweep, &args),
        Command::Validate(args) => run_validate(&args),
        Command::Verify(args) => cli::inspect::run_verify(&args),
        Command::Export(args) => cli::inspect::run_export(&args),
        Command::Plot(args) => cli::inspect::run_plot(&args),
        Command::Bench(args) => bench::run_command(&args),
        Command::Serve(args) => cli::serve::run(&args),
        Command::Worker(args) => cli::serve::run_worker(&args),
        Command::User(command) => cli::serve::run_user(&command),
        Command::Completions(args) => cli::docs::run_completions(&args, Cli::command()),
        Command::Man(args) => cli::docs::run_man(&args, Cli::command()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let code = exit_code(&failure);
            let (Failure::Input(err) | Failure::Run(err) | Failure::Stopped(err)) = failure;
            eprintln!("{} {err:#}", cli::colour::error());
            ExitCode::from(code)
        }
    }
}

/// 2 for bad input, 1 for a failed run, 130 for a run stopped before
/// anything was finished ([`EXIT_CODES`]).
fn exit_code(failure: &Failure) -> u8 {
    match failure {
        Failure::Input(_) => 2,
        Failure::Run(_) => 1,
        Failure::Stopped(_) => 130,
    }
}
