//! The optimise job: [`crate::ga::optimise`] searches for the
//! `[optimise]` target porosity (its routes and verdict are the GA's); this
//! job reads and keeps its checkpoint, lays the materials out when the
//! config has a `[layering]`, and writes what the search found.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use super::describe::{TIME_LIMIT_NOTE, Words, duration, grading_note, memory};
use super::error::JobError;
use super::event::{Event, Observer, Stage, Warning, WarningKind};
use super::layer::{lay_out, layering_line, layering_report};
use super::plan::{Plan, Planning};
use super::registry::{Job, Report};
use super::run::{CHECKPOINT_JSON, Running, generation, single_material};
use super::store::{Store, StoreError};
use super::wells::whole_fracture;
use crate::cancel::Cancel;
use crate::farm;
use crate::ga::{
    self, Checkpoint, Generation, Layered, OptimiseError, OptimiseObserver, OptimiseSettings,
    Optimised, Start, StopReason, TargetWarning, TargetWarningKind, Verdict,
};
use crate::metrics::{Metrics, measure_sharing};
use crate::output::{OptimiseSummary, OutputSettings, RunInfo, SearchWindow, ShapeFound};

/// The optimise job's rules: it needs an `[optimise]` table.
pub(super) fn plan(p: &mut Planning<'_>) -> Result<Job, JobError> {
    let Some(settings) = p.config.optimise else {
        return Err(JobError::Input(format!(
            "{}:1:1: optimise: missing table [optimise]; the optimise job needs one with at least target_porosity",
            p.origin
        )));
    };
    Ok(Job::Optimise {
        settings,
        resume: p.request.resume,
        checkpoint_every: p.request.checkpoint_every,
    })
}

/// Search, lay out, write: the best packing found and the search's record.
pub(super) fn run(
    job: &mut Running<'_>,
    settings: &OptimiseSettings,
    resume: bool,
    every: usize,
    cancel: &Cancel,
) -> Result<(Report, bool), JobError> {
    let plan = job.plan;
    let config = &plan.config;
    let scene = &config.scene;
    // The job's own token: a failed checkpoint stops the search without
    // raising the front end's.
    let stop = cancel.child();
    let checkpoint = if resume {
        Some(read_checkpoint(job)?)
    } else {
        None
    };
    let start = match &checkpoint {
        Some(c) => Start::Resume(c),
        None => Start::Seed(plan.seed()),
    };
    let mut told = Told {
        plan,
        observer: &mut *job.observer,
        store: &mut *job.store,
        stop: &stop,
        saved: false,
        failed: None,
    };
    let found = ga::optimise(scene, settings, start, every, job.farm, &stop, &mut told);
    let (saved, save_failed) = (told.saved, told.failed);
    let found = found.map_err(search_error)?;
    let Optimised {
        mut packing,
        scene: best_scene,
        verdict,
        achievable_range,
        initial_range,
        warning,
        evaluations,
        history,
        stop: stopped,
        window,
        whole_packs,
        seconds,
        shape,
        ..
    } = found;
    let interrupted = verdict == Verdict::Interrupted;
    let layered = config
        .layering
        .as_ref()
        .map(|l| lay_out(job, &packing, l, &stop));
    match &layered {
        Some(l) => packing.materials = l.assignment.clone(),
        None => single_material(&mut packing, config),
    }
    // The search is over: a cancel now no longer stops the run.
    let (metrics, ahead) = job.measure_packing(
        "",
        &packing,
        &config.output,
        &Cancel::new(),
        |shared, stop| measure_sharing(&packing, &best_scene, Some(shared), stop),
    )?;
    if let Some(warning) = warning {
        job.event(Event::Warning(warning_of(warning)));
    }
    let summary = OptimiseSummary {
        target_porosity: settings.target_porosity,
        tolerance: settings.tolerance,
        best_porosity: metrics.porosity,
        error: (metrics.porosity - settings.target_porosity).abs(),
        max_psd_ks: settings.max_psd_ks,
        evaluations,
        generations: history.len().saturating_sub(1),
        population: settings.stop.population,
        feasible: verdict.feasible(),
        verdict: verdict.describe(),
        achievable_range,
        initial_range,
        interrupted,
        stop: if interrupted {
            StopReason::Interrupted.describe()
        } else {
            stopped.describe()
        },
        reproducible: !interrupted && stopped.reproducible(),
        window: window.as_ref().map(|w| {
            Box::new(SearchWindow {
                size: w.steps.last().map_or([0.0; 2], |s| s.size),
                share: w.share(scene),
                disks: w.steps.last().map_or(0, |s| s.disks),
                settled: w.settled,
                steps: w
                    .steps
                    .iter()
                    .map(|s| [s.size[0], s.size[1], s.porosity, s.core])
                    .collect(),
                offset: w.offset,
                whole_packs: 1 + whole_packs,
            })
        }),
        shape_found: shape.zip(settings.shape).map(|((asked, m), bounds)| {
            Box::new(ShapeFound {
                aspect: asked.aspect,
                exponent: asked.exponent,
                orientation_spread_deg: asked.spread.map(f64::to_degrees),
                mean_sphericity: m.sphericity,
                mean_roundness: m.roundness,
                aspect_ks: m.aspect_ks,
                min_sphericity: bounds.min_sphericity,
                min_roundness: bounds.min_roundness,
                max_shape_ks: bounds.max_shape_ks,
            })
        }),
    };
    let resumable = interrupted && saved;
    let report = Report::Optimise {
        packing,
        scene: Box::new(best_scene),
        metrics,
        summary: Box::new(summary),
        history,
        layered,
        resumable,
        seconds,
    };
    job.write_report(&report, &config.output, ahead)?;
    if let Some(e) = save_failed {
        return Err(JobError::Checkpoint(e));
    }
    if resumable {
        job.files.push(CHECKPOINT_JSON.to_owned());
    }
    // Otherwise the search is over: the commit removes its checkpoint
    // with the other stale files, only once the outputs are in place.
    Ok((report, interrupted))
}

/// The search's events to the job's observer, its checkpoints to the
/// store; a checkpoint that cannot be saved stops the search (its best
/// so far is still written).
struct Told<'a> {
    plan: &'a Plan,
    observer: &'a mut dyn Observer,
    store: &'a mut dyn Store,
    stop: &'a Cancel,
    saved: bool,
    failed: Option<StoreError>,
}

impl OptimiseObserver for Told<'_> {
    fn warning(&mut self, warning: TargetWarning) {
        self.observer.event(&Event::Warning(warning_of(warning)));
    }

    fn started(&mut self, generations: u64) {
        self.observer.event(&Event::Stage {
            stage: Stage::Optimise,
            total: Some(generations),
        });
    }

    fn generation(&mut self, g: &Generation) {
        self.observer.event(&generation(Stage::Optimise, g));
    }

    fn checkpoint(&mut self, checkpoint: &Checkpoint) {
        let plan = self.plan;
        let file = CheckpointFile {
            gapack_version: env!("CARGO_PKG_VERSION").to_owned(),
            config: plan.origin.clone(),
            identity: plan.identity.clone(),
            seed: Some(plan.seed()),
            search: Cow::Borrowed(checkpoint),
        };
        let written = serde_json::to_vec(&file)
            .map_err(|e| StoreError::Write(e.into()))
            .and_then(|bytes| self.store.write(&[(CHECKPOINT_JSON.to_owned(), bytes)]));
        match written {
            Ok(()) => self.saved = true,
            Err(e) => {
                // Stop at the next generation: the best so far is still written.
                self.stop.cancel();
                self.failed.get_or_insert(e);
            }
        }
    }
}

/// A warning of the search as the job's.
fn warning_of(warning: TargetWarning) -> Warning {
    Warning {
        kind: match warning.kind {
            TargetWarningKind::OutsideInitialRange => WarningKind::TargetOutsideInitialRange,
            TargetWarningKind::OutOfReach => WarningKind::TargetOutOfReach,
            _ => WarningKind::TargetNotReached,
        },
        message: warning.message,
    }
}

/// The search's failure as the job's.
fn search_error(e: OptimiseError) -> JobError {
    match e {
        OptimiseError::Resume(e) => JobError::Input(format!("{CHECKPOINT_JSON}: {e}")),
        OptimiseError::Pack { what, source } => JobError::Pack {
            what: what.to_owned(),
            source,
        },
        OptimiseError::NothingPacked => JobError::NothingPacked,
        OptimiseError::Cancelled => JobError::Cancelled,
    }
}

/// `checkpoint.json`: the search's state and what run it belongs to. The
/// search is borrowed when written, owned when read.
#[derive(Serialize, Deserialize)]
struct CheckpointFile<'a> {
    /// gapack version that wrote it.
    gapack_version: String,
    /// The config's origin.
    config: String,
    /// The plan's identity (config text and seed).
    identity: String,
    /// The seed (files written before it was recorded have none).
    #[serde(default)]
    seed: Option<u64>,
    /// The search.
    search: Cow<'a, Checkpoint>,
}

/// The store's checkpoint, if it belongs to this plan.
fn read_checkpoint(job: &Running<'_>) -> Result<Checkpoint, JobError> {
    let place = format!("{} in {}", CHECKPOINT_JSON, job.store.location());
    // Every process resumes from the leading one's checkpoint.
    let read = job.store.read(CHECKPOINT_JSON);
    let shared = farm::share(
        job.farm,
        read.as_ref().map(Clone::clone).map_err(ToString::to_string),
    );
    let bytes = match (read, shared) {
        (Err(e), _) => return Err(e.into()),
        (Ok(_), Err(e)) => return Err(JobError::Input(format!("{place}: {e}"))),
        (Ok(_), Ok(bytes)) => bytes,
    };
    let Some(bytes) = bytes else {
        return Err(JobError::Input(format!(
            "there is no {place} to resume from"
        )));
    };
    let file: CheckpointFile = serde_json::from_slice(&bytes)
        .map_err(|e| JobError::Input(format!("{place} is not a gapack checkpoint: {e}")))?;
    let plan = job.plan;
    if file.identity != plan.identity {
        let seed = file
            .seed
            .map_or_else(|| "unrecorded".to_owned(), |s| s.to_string());
        return Err(JobError::Input(format!(
            "{place} belongs to another run: config {} with seed {seed}; this run is {} with seed {} (the config's text or the seed differ)",
            file.config,
            plan.origin,
            plan.seed()
        )));
    }
    Ok(file.search.into_owned())
}

/// What the files of a search record: its summary and history, the
/// layering if any, the well of a `[fracture]` config.
pub(super) fn info<'a>(
    plan: &'a Plan,
    scene: &'a crate::Scene,
    summary: &'a OptimiseSummary,
    history: &'a [Generation],
    layered: Option<&'a Layered>,
    seconds: f64,
    output: &'a OutputSettings,
) -> RunInfo<'a> {
    let config = &plan.config;
    RunInfo {
        materials: &config.materials,
        optimise: Some((summary, history)),
        layering: config
            .layering
            .as_ref()
            .zip(layered)
            .map(|(settings, layered)| layering_report(settings, layered)),
        fracture: whole_fracture(config),
        ..RunInfo::new(scene, &plan.origin, seconds, output)
    }
}

/// `job: optimise: target porosity 0.2 ± 0.005, …`, and the search's memory.
pub(super) fn words(plan: &Plan, o: &OptimiseSettings, resume: bool) -> Words {
    let mut words = Words::new(format!(
        "job: optimise{}: target porosity {} ± {}, population {}, at most {} generations{}, {} s",
        if resume {
            " (resumed from the checkpoint)"
        } else {
            ""
        },
        o.target_porosity,
        o.tolerance,
        o.stop.population,
        o.stop.generations,
        o.stop
            .max_evaluations
            .map(|n| format!(" or {n} evaluations"))
            .unwrap_or_default(),
        o.stop.time_limit_s
    ));
    words.memory = Some(format!(
        "search memory: about {} ({} genomes)",
        memory(o.peak_bytes(&plan.config.scene)),
        o.stop.population
    ));
    words
}

/// The best packing against the target, the search's effort and verdict.
pub(super) fn lines(
    at: &str,
    metrics: &Metrics,
    summary: &OptimiseSummary,
    layered: Option<&Layered>,
    seconds: f64,
) -> Vec<String> {
    let layering = layered.map_or(String::new(), |l| format!("; {}", layering_line(l)));
    // The stop says `target reached` or `interrupted`; otherwise the verdict.
    let said = [Verdict::Reached, Verdict::Interrupted].map(Verdict::describe);
    let verdict = if said.contains(&summary.verdict) {
        String::new()
    } else if summary.achievable_range.is_none() {
        format!(
            "; target {}, no packing honoured the grading (max_psd_ks {})",
            summary.verdict, summary.max_psd_ks
        )
    } else {
        format!("; target {}", summary.verdict)
    };
    let window = summary.window.as_ref().map_or(String::new(), |w| {
        format!(
            "; searched on a {:.0} × {:.0} mm window ({:.1}% of the domain{}), the whole packed {}",
            w.size[0],
            w.size[1],
            100.0 * w.share,
            if w.settled { "" } else { ", not settled" },
            match w.whole_packs {
                1 => "once".to_owned(),
                n => format!("{n} times"),
            }
        )
    });
    let mut lines = vec![format!(
        "{at}: porosity {:.4} (target {}, error {:.4}), psd_ks {:.3}, {} {}, {} evaluations in {} generations, {} ({}{verdict}{window}){layering}{}",
        metrics.porosity,
        summary.target_porosity,
        summary.error,
        metrics.psd_ks,
        metrics.particles,
        if metrics.shapes.is_some() {
            "particles"
        } else {
            "disks"
        },
        summary.evaluations,
        summary.generations,
        duration(seconds),
        summary.stop,
        grading_note(metrics),
    )];
    if !summary.reproducible && !summary.interrupted {
        lines.push(TIME_LIMIT_NOTE.to_owned());
    }
    lines
}
