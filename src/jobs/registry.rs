//! The one place the jobs are registered: their names ([`JobKind`]),
//! what each plans ([`Job`]) and reports ([`Report`]), and one arm per job
//! in each dispatch to its own file (`pack.rs`, `wells.rs`, `optimise.rs`,
//! `layer.rs`, `compare.rs`, `stability.rs`, `sweep.rs`), which holds its
//! plan rules, its run and its words.
//!
//! Adding a job: its file, and here a variant of each enum and an arm in
//! each match (the compiler lists the matches that lack it).

use std::time::Duration;

use serde::Serialize;

use super::describe::Words;
use super::error::JobError;
use super::plan::{Plan, Planning};
use super::run::{Running, WellOutcome};
use super::sweep::Study;
use super::{compare, layer, optimise, pack, stability, sweep, wells};
use crate::cancel::Cancel;
use crate::compare::{CompareRun, Variant};
use crate::config::Config;
use crate::ga::{Generation, Layered, OptimiseSettings};
use crate::layering::LayeringSettings;
use crate::metrics::Metrics;
use crate::output::{OptimiseSummary, OutputSettings, RunInfo};
use crate::packer::Packing;
use crate::stability::StabilityRun;
use crate::study::{Measure, Row};

/// The jobs gapack runs, as a front end names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum JobKind {
    /// Pack the scene (or each fracture of a `[fracture]` config).
    Pack,
    /// Search for the `[optimise]` target porosity.
    Optimise,
    /// Lay the `[[materials]]` out along the `[layering]` profile.
    Layer,
    /// Run every generator of `[compare]` on the scene.
    Compare,
    /// Sweep the `[compare]` methods over gradings, widths and shapes.
    Stability,
    /// Run the parameter study of `[sweep]`: the config's job at every
    /// combination of the swept values, over seeds.
    Sweep,
}

impl JobKind {
    /// Every job, in the order front ends list them.
    pub const ALL: [JobKind; 6] = [
        JobKind::Pack,
        JobKind::Optimise,
        JobKind::Layer,
        JobKind::Compare,
        JobKind::Stability,
        JobKind::Sweep,
    ];

    /// The job's name (`pack`, `optimise`, …).
    pub fn name(self) -> &'static str {
        match self {
            JobKind::Pack => "pack",
            JobKind::Optimise => "optimise",
            JobKind::Layer => "layer",
            JobKind::Compare => "compare",
            JobKind::Stability => "stability",
            JobKind::Sweep => "sweep",
        }
    }

    /// The job called `name` (`pack`, `optimise`, …), if there is one.
    pub fn named(name: &str) -> Option<JobKind> {
        JobKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Every job's name, for a message that lists them: `pack, optimise, …`.
    pub fn names() -> String {
        JobKind::ALL.map(JobKind::name).join(", ")
    }

    /// The job a config is written for, its own job: `sweep` with a
    /// `[sweep]` table, else `optimise` with an `[optimise]` one, else
    /// `layer` with a `[layering]` one, else `pack`. A [`super::Request`]
    /// without a kind asks for it ([`Plan::load`] resolves it).
    pub fn natural(config: &Config) -> JobKind {
        if config.sweep.is_some() {
            JobKind::Sweep
        } else {
            JobKind::single(config)
        }
    }

    /// The job one run of the config is, `[sweep]` aside: `optimise` with
    /// an `[optimise]` table, else `layer` with a `[layering]` one, else `pack`.
    pub fn single(config: &Config) -> JobKind {
        if config.optimise.is_some() {
            JobKind::Optimise
        } else if config.layering.is_some() {
            JobKind::Layer
        } else {
            JobKind::Pack
        }
    }
}

/// The job-specific part of a plan.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum Job {
    /// Pack one scene.
    Pack,
    /// Pack each fracture of `[fracture]`: whole or as a window, a batch
    /// writing one folder per well and `wells.csv`.
    Wells {
        /// Whether the wells go to folders of their own (a `wells` list).
        batch: bool,
    },
    /// The target-porosity search, then the layering if the config has one.
    Optimise {
        /// `[optimise]`.
        settings: OptimiseSettings,
        /// Go on from the store's checkpoint.
        resume: bool,
        /// Checkpoint every this many generations (0: only when cancelled).
        checkpoint_every: usize,
    },
    /// Pack once, then lay the materials out.
    Layer {
        /// `[layering]`.
        settings: LayeringSettings,
    },
    /// Every `[compare]` method variant on the scene.
    Compare {
        /// `[optimise] target_porosity`, which gives each run's error.
        target: Option<f64>,
    },
    /// The stability sweep.
    Stability {
        /// Time cap of one run.
        time_cap: Duration,
    },
    /// A parameter study: every run planned.
    Sweep {
        /// The study.
        study: Box<Study>,
    },
}

impl Job {
    /// The job `planning.kind` on its config: each job's plan rules.
    pub(super) fn plan(planning: &mut Planning<'_>) -> Result<Job, JobError> {
        match planning.kind {
            JobKind::Pack => Ok(pack::plan(planning)),
            JobKind::Optimise => optimise::plan(planning),
            JobKind::Layer => layer::plan(planning),
            JobKind::Compare => compare::plan(planning),
            JobKind::Stability => stability::plan(planning),
            JobKind::Sweep => sweep::plan(planning),
        }
    }

    /// Run the job: its report, and whether it was cut short.
    pub(super) fn run(
        &self,
        job: &mut Running<'_>,
        cancel: &Cancel,
    ) -> Result<(Report, bool), JobError> {
        match self {
            Job::Pack => pack::run(job, cancel),
            Job::Wells { batch } => wells::run(job, *batch, cancel),
            Job::Optimise {
                settings,
                resume,
                checkpoint_every,
            } => optimise::run(job, settings, *resume, *checkpoint_every, cancel),
            Job::Layer { settings } => layer::run(job, settings, cancel),
            Job::Compare { target } => compare::run(job, *target, cancel),
            Job::Stability { time_cap } => stability::run(job, *time_cap, cancel),
            Job::Sweep { study } => sweep::run(job, study, cancel),
        }
    }

    /// What `gapack validate` says of the job besides the scene.
    pub(super) fn words(&self, plan: &Plan) -> Words {
        match self {
            Job::Pack => pack::words(),
            Job::Wells { batch } => wells::words(plan, *batch),
            Job::Optimise {
                settings, resume, ..
            } => optimise::words(plan, settings, *resume),
            Job::Layer { .. } => layer::words(),
            Job::Compare { .. } => compare::words(plan),
            Job::Stability { time_cap } => stability::words(plan, *time_cap),
            Job::Sweep { study } => sweep::words(study),
        }
    }
}

/// A job's own results.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum Report {
    /// One scene packed.
    Pack {
        /// The packing written.
        packing: Packing,
        /// Its measurements.
        metrics: Metrics,
        /// Time to pack (s).
        seconds: f64,
    },
    /// Fractures packed, whole or as windows.
    Wells {
        /// Each well finished, in order.
        wells: Vec<WellOutcome>,
        /// Whether they were written to folders of their own with `wells.csv`.
        batch: bool,
        /// Wells in the batch.
        total: usize,
    },
    /// A target-porosity search.
    Optimise {
        /// The best packing found (materials laid out if the config asks).
        packing: Packing,
        /// The scene it was packed from: the config's with the packer rules
        /// and sizes the search found (what `summary.json` records).
        scene: Box<crate::Scene>,
        /// Its measurements.
        metrics: Metrics,
        /// What `summary.json` records of the search.
        summary: Box<OptimiseSummary>,
        /// One record per generation.
        history: Vec<Generation>,
        /// The layering, when the config has one.
        layered: Option<Layered>,
        /// Whether a checkpoint was kept to resume from.
        resumable: bool,
        /// Wall-clock time of the search (s), with the windows and the
        /// densify route's packs where they ran.
        seconds: f64,
    },
    /// One packing with its materials laid out.
    Layer {
        /// The packing written.
        packing: Packing,
        /// Its measurements.
        metrics: Metrics,
        /// The layering.
        layered: Layered,
        /// Time to pack (s).
        seconds: f64,
    },
    /// A comparison of generators.
    Compare {
        /// The runs finished, in order.
        runs: Vec<CompareRun>,
        /// The variants run, in order.
        variants: Vec<Variant>,
        /// Runs planned.
        total: usize,
    },
    /// A stability sweep.
    Stability {
        /// The runs finished, in order.
        runs: Vec<StabilityRun>,
        /// The variants run, in order.
        variants: Vec<Variant>,
        /// Runs planned.
        total: usize,
    },
    /// A parameter study.
    Sweep {
        /// One row per run planned, in product order (those not run too).
        rows: Vec<Row>,
        /// The swept keys, in order.
        keys: Vec<String>,
        /// Runs per point.
        seeds: usize,
        /// The measure charted.
        measure: Measure,
        /// Rows kept from the earlier `sweep.csv` of a resumed study.
        resumed: usize,
    },
}

impl Report {
    /// The packing, its measurements and what its files record, for a
    /// one-packing report (`pack`, `layer`, `optimise`) written with
    /// `output`; `None` for a job that writes its own files.
    pub(super) fn run_info<'a>(
        &'a self,
        plan: &'a Plan,
        output: &'a OutputSettings,
    ) -> Option<(&'a Packing, &'a Metrics, RunInfo<'a>)> {
        match self {
            Report::Pack {
                packing,
                metrics,
                seconds,
            } => Some((packing, metrics, pack::info(plan, *seconds, output))),
            Report::Layer {
                packing,
                metrics,
                layered,
                seconds,
            } => Some((
                packing,
                metrics,
                layer::info(plan, layered, *seconds, output),
            )),
            Report::Optimise {
                packing,
                scene,
                metrics,
                summary,
                history,
                layered,
                seconds,
                ..
            } => Some((
                packing,
                metrics,
                optimise::info(
                    plan,
                    scene,
                    summary,
                    history,
                    layered.as_ref(),
                    *seconds,
                    output,
                ),
            )),
            _ => None,
        }
    }

    /// The result in lines, the run's folder named `at`.
    pub(super) fn lines(&self, at: &str) -> Vec<String> {
        match self {
            Report::Pack {
                metrics, seconds, ..
            } => pack::lines(at, metrics, *seconds),
            Report::Wells {
                wells,
                batch,
                total,
            } => wells::lines(at, wells, *batch, *total),
            Report::Optimise {
                metrics,
                summary,
                layered,
                seconds,
                ..
            } => optimise::lines(at, metrics, summary, layered.as_ref(), *seconds),
            Report::Layer {
                metrics, layered, ..
            } => layer::lines(at, metrics, layered),
            Report::Compare {
                runs,
                variants,
                total,
            } => compare::lines(at, runs, variants, *total),
            Report::Stability {
                runs,
                variants,
                total,
            } => stability::lines(at, runs, variants, *total),
            Report::Sweep {
                rows,
                seeds,
                resumed,
                ..
            } => sweep::lines(at, rows, *seeds, *resumed),
        }
    }

    /// Wall-clock time of the job's main work (s): the packing, or the whole search.
    pub(super) fn seconds(&self) -> f64 {
        match self {
            Report::Pack { seconds, .. }
            | Report::Layer { seconds, .. }
            | Report::Optimise { seconds, .. } => *seconds,
            Report::Wells { wells, .. } => wells.iter().map(|w| w.row.seconds).sum(),
            Report::Compare { runs, .. } => runs.iter().map(|r| r.seconds).sum(),
            Report::Stability { runs, .. } => runs.iter().map(|r| r.seconds).sum(),
            Report::Sweep { rows, .. } => sweep::seconds(rows),
        }
    }
}
