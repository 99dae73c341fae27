//! The job subcommands (`pack`, `optimise`, `layer`, `compare`,
//! `stability`, `sweep`) and `validate`: their arguments → a [`Plan`], Ctrl-C
//! and SIGTERM → its cancel token, events → progress bars, the [`Outcome`]
//! → result lines.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context;
use clap::Args;
#[cfg(feature = "mpi")]
use gapack::farm::Farm;
use gapack::jobs::{
    self, Cancel, DirStore, JobError, JobKind, Outcome, Plan, Request, Store, Summary,
};
use gapack::output::SUMMARY_JSON;
use serde::de::{MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use serde_json::value::{RawValue, to_raw_value};
use serde_json::{Map, Value};

use super::{Failure, ProgressObserver, load_text, print_line, report};

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
    /// Print the result as one JSON object on stdout instead of its lines:
    /// the job, its folder, its files and result lines, and the figures of
    /// the summary.json it wrote (docs/usage.md); progress and notes stay
    /// on stderr.
    #[arg(long, conflicts_with = "quiet")]
    json: bool,
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
    /// Print the plan as one JSON object on stdout (docs/usage.md).
    #[arg(long)]
    json: bool,
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
        eprintln!(
            "{} cannot catch Ctrl-C and SIGTERM ({e}); they will end gapack at once",
            super::colour::warning()
        );
    }
    let mut observer = ProgressObserver::new(args.quiet);
    let outcome = jobs::run(&plan, &mut observer, &cancel, &mut store);
    observer.finish();
    tell(kind, outcome, &store, args)
}

/// The result lines of a job's outcome (or its JSON object), or its failure.
fn tell(
    kind: JobKind,
    outcome: Result<Outcome, JobError>,
    store: &DirStore,
    args: &JobArgs,
) -> Result<(), Failure> {
    let outcome = outcome.map_err(|e| match e {
        JobError::Cancelled => Failure::Stopped(e.into()),
        e => super::failure(e),
    })?;
    let summary = Summary::of(&outcome, &outcome.location);
    let timings = if args.timings {
        outcome.timings_line()
    } else {
        None
    };
    if args.json {
        print_line(result_json(kind, &outcome, &summary, store)?);
        // Nothing but the object on stdout.
        if let Some(line) = timings {
            eprintln!("{line}");
        }
    } else {
        for line in summary.lines {
            report(args.quiet, || line);
        }
        if let Some(line) = timings {
            print_line(line);
        }
    }
    if !args.quiet {
        super::hint::after_stop(&outcome, args.config.as_deref(), args.seed, args.force);
    }
    Ok(())
}

/// A job's result as one JSON object (`--json`): `job` and `out` (its
/// folder), the entries of the `summary.json` it wrote in that folder, in
/// its order and as written (its numbers' digits are copied, not parsed
/// and printed again), then those of the job's [`Summary`] (`files`,
/// `interrupted`, `lines`, and its figures, which `summary.json` holds
/// alike: they take the file's place). A job whose runs each have a
/// folder of their own (a batch of wells, a study) has no `summary.json`
/// at the top: its object is the [`Summary`]'s, and the runs' files are in
/// `files`.
fn result_json(
    kind: JobKind,
    outcome: &Outcome,
    summary: &Summary,
    store: &DirStore,
) -> Result<String, Failure> {
    let raw = |text: &str| to_raw_value(text).map_err(|e| Failure::Run(e.into()));
    let mut entries = Entries(vec![
        ("job".to_owned(), raw(kind.name())?),
        ("out".to_owned(), raw(&outcome.location)?),
    ]);
    if outcome.files.iter().any(|f| f == SUMMARY_JSON) {
        let bytes = store
            .read(SUMMARY_JSON)
            .map_err(anyhow::Error::from)
            .and_then(|b| b.context("it is gone"))
            .with_context(|| format!("cannot read {}/{SUMMARY_JSON}", outcome.location))
            .map_err(Failure::Run)?;
        let written: Entries = serde_json::from_slice(&bytes)
            .with_context(|| format!("{}/{SUMMARY_JSON}: not a JSON object", outcome.location))
            .map_err(Failure::Run)?;
        for (key, value) in written.0 {
            // The file is pretty-printed: its tables on one line.
            let value =
                RawValue::from_string(compact(value.get())).map_err(|e| Failure::Run(e.into()))?;
            entries.0.push((key, value));
        }
    }
    let own: Entries = serde_json::to_string(summary)
        .and_then(|text| serde_json::from_str(&text))
        .map_err(|e| Failure::Run(e.into()))?;
    for (key, value) in own.0 {
        match entries.0.iter_mut().find(|(k, _)| *k == key) {
            Some(entry) => entry.1 = value,
            None => entries.0.push((key, value)),
        }
    }
    serde_json::to_string(&entries).map_err(|e| Failure::Run(e.into()))
}

/// JSON text without the whitespace between its tokens (strings kept whole).
fn compact(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    let (mut in_string, mut escaped) = (false, false);
    for c in json.chars() {
        if in_string {
            out.push(c);
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_string = false;
            }
        } else if !c.is_ascii_whitespace() {
            in_string = c == '"';
            out.push(c);
        }
    }
    out
}

/// A JSON object's entries in their order, each value as its JSON text.
struct Entries(Vec<(String, Box<RawValue>)>);

impl Serialize for Entries {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

impl<'de> Deserialize<'de> for Entries {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> Visitor<'de> for Visit {
            type Value = Entries;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Entries, A::Error> {
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry()? {
                    entries.push(entry);
                }
                Ok(Entries(entries))
            }
        }
        deserializer.deserialize_map(Visit)
    }
}

/// The JSON object `value` serialises to.
fn object_of(value: &impl Serialize) -> Result<Map<String, Value>, Failure> {
    match serde_json::to_value(value) {
        Ok(Value::Object(map)) => Ok(map),
        Ok(other) => Err(Failure::Run(anyhow::anyhow!(
            "expected a JSON object, made {other}"
        ))),
        Err(e) => Err(Failure::Run(e.into())),
    }
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
        eprintln!(
            "{} cannot catch Ctrl-C and SIGTERM ({e}); they will end gapack at once",
            super::colour::warning()
        );
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
    tell(plan.kind, outcome, &store, args)
}

/// What `gapack validate` says of a config: valid, and the plan of the run.
#[derive(Serialize)]
struct Validation {
    /// The config as named on the command line.
    config: String,
    /// Always true: a config that is not valid fails with exit code 2.
    valid: bool,
    /// The job the run would be.
    job: &'static str,
    /// The seed it would use.
    seed: u64,
    /// The folder it would write.
    out: String,
    /// The plan, a line each (as printed under `<config>: valid`).
    plan: Vec<String>,
    /// The warnings among them, without their `warning: ` prefix.
    warnings: Vec<String>,
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
    let out = out.display().to_string();
    let validation = Validation {
        plan: plan.describe(&out),
        config: origin,
        valid: true,
        job: plan.kind.name(),
        seed: plan.seed(),
        out,
        warnings: plan.warnings.iter().map(|w| w.message.clone()).collect(),
    };
    if args.json {
        print_line(Value::Object(object_of(&validation)?));
        return Ok(());
    }
    print_line(format_args!("{}: valid", validation.config));
    for line in &validation.plan {
        print_line(format_args!("  {line}"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::compact;

    #[test]
    fn compact_drops_the_space_between_tokens_only() {
        let pretty = "{\n  \"a b\": [\n    1.5e-15,\n    \"x \\\" y\"\n  ],\n  \"c\": {}\n}";
        assert_eq!(compact(pretty), r#"{"a b":[1.5e-15,"x \" y"],"c":{}}"#);
        let value: serde_json::Value = serde_json::from_str(pretty).unwrap();
        assert_eq!(serde_json::to_string(&value).unwrap(), compact(pretty));
    }
}
