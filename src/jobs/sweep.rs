//! The sweep job: a parameter study planned from `[sweep]` — every run's
//! own plan, the config's job at one point and seed — and run over the
//! farm: the runs are shared out to the threads (and the ranks of an MPI
//! launch) in waves, each run alone on its thread in a store of its own,
//! and their rows and kept files come back to build the study's files.
//!
//! # Behavior
//! A run's row is a pure function of its plan (its seconds aside): it
//! runs on [`Local`] with no observer, and only what comes back from
//! [`farm::map`] builds the study's files, so they are the same whatever
//! the number of threads and processes. A cancel stops the runs under way
//! (each reports it, and its row is `not run`) and the waves after; the
//! leading process alone decides that ([`farm::agree`]). A resumed study
//! keeps the finished rows of the store's `sweep.csv` when its
//! `manifest.json` names the same plan, and runs the others.

use std::collections::BTreeMap;
use std::error::Error;

use serde::{Deserialize, Serialize};

use super::contract::Manifest;
use super::describe::{Words, duration, interrupted_runs, memory};
use super::error::JobError;
use super::event::{Event, Observer, Stage, Warning, WarningKind};
use super::largest::Largest;
use super::plan::{Plan, Planning, Request};
use super::registry::{Job, JobKind, Report};
use super::run::{MANIFEST_JSON, Running, run_on};
use super::store::{MemoryStore, Store, StoreError};
use crate::cancel::Cancel;
use crate::config::{
    Config, ConfigError, ConfigName, Location, ParseOptions, SweepConfigs, key_location,
};
use crate::farm::{self, Farm, Local};
use crate::fracture::Extent;
use crate::output::{SUMMARY_JSON, SWEEP_CSV, read_sweep_csv, render_sweep};
use crate::study::{
    Keep, Measure, Measures, Row, RunJob, Status, SweepSettings, SweptKey, point_names, points,
    run_name,
};

/// Runs per worker (thread × process) in a wave: the runs of a wave are
/// shared out together, and the progress events come after each wave.
const WAVE_PER_WORKER: usize = 2;

/// Runs named in a warning that several runs gave, before `and N more`.
const NAMED_RUNS: usize = 3;

/// A parameter study, planned: its points and its runs (each a point and
/// a seed), and the largest scene and memory of any run.
///
/// # Performance
/// A study holds no config per point nor plan per run: a point's config is
/// made when its runs run ([`Study::run_plan`]) from the study's config
/// held once ([`SweepConfigs`]), so a study of 100,000 points costs little
/// more memory than their names, and one of many seeds no more than one
/// of a single seed.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Study {
    /// `[sweep]`.
    pub settings: SweepSettings,
    /// The job every run is.
    pub kind: JobKind,
    /// Every point, in product order.
    pub points: Vec<StudyPoint>,
    /// Every run, in product order (`seeds` to a point).
    pub runs: Vec<StudyRun>,
    /// Keep the finished rows of the store's `sweep.csv` and run the others.
    pub resume: bool,
    /// The largest scene and memory over every point's runs, found when
    /// the study was planned (the points that cannot run left out).
    pub largest: Largest,
    /// Every point's config, made on demand.
    configs: SweepConfigs,
    /// The config's origin, which the runs' messages and files name.
    origin: String,
    /// Skip the `[limits]` refusals (the request's `force`).
    force: bool,
    /// The request's time cap, passed on to each run's.
    time_cap: std::time::Duration,
}

/// One point of a study: a value of every swept key.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct StudyPoint {
    /// Its name (`width_mm=2.5,preset=20-40`).
    pub name: String,
    /// The value of each swept key, as `sweep.csv` shows it.
    pub values: Vec<String>,
    /// The index of each swept key's value.
    pub indices: Vec<usize>,
}

/// One run of a study.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct StudyRun {
    /// Its name: the point's, then its seed (`width_mm=2.5,preset=20-40,seed=3`).
    pub name: String,
    /// Its point, an index into [`Study::points`].
    pub point: usize,
    /// Its seed: the config's (or the request's) plus its place among the point's seeds.
    pub seed: u64,
}

impl Study {
    /// Point `p`'s config as TOML text (for its runs' identity), and its
    /// config or why its scene cannot be packed (its runs fail with it).
    ///
    /// # Errors
    /// A fault of the point's config (none of a point of a planned study:
    /// planning made every one), in one line.
    pub fn point_config(&self, p: usize) -> Result<(String, Result<Config, String>), String> {
        let point = self.points.get(p).ok_or("no such point")?;
        let made = self
            .configs
            .point(&self.settings, &point.indices, &point.name)
            .map_err(|e| e.to_string().replace(['\n', '\r'], " "))?;
        Ok((made.text, made.config))
    }

    /// The plan of `run`: its point's config, its seed, the study's job;
    /// without `keep = "all"` no file but `summary.json` is made.
    ///
    /// # Errors
    /// Why the run cannot run: its point's scene cannot be packed, or the
    /// job refuses its config, in one line.
    pub fn run_plan(&self, run: &StudyRun) -> Result<Plan, String> {
        let (text, config) = self.point_config(run.point)?;
        let mut plan = self.plan_point(config?, &text, run.seed)?;
        // The runs' other files are not kept: not made either.
        if self.settings.keep != Keep::All {
            plan.config.output.formats.clear();
        }
        Ok(plan)
    }

    /// The plan of the study's job on a point's `config` (of `text`) with `seed`.
    fn plan_point(&self, config: Config, text: &str, seed: u64) -> Result<Plan, String> {
        let request = Request {
            kind: Some(self.kind),
            seed: Some(seed),
            force: self.force,
            resume: false,
            checkpoint_every: 0,
            time_cap: self.time_cap,
        };
        Plan::new(config, text, &self.origin, &request).map_err(|e| one_line(&e))
    }
}

/// The sweep job's rules: it needs a `[sweep]` table, and plans every
/// point and run of the study ([`study`]).
pub(super) fn plan(p: &mut Planning<'_>) -> Result<Job, JobError> {
    let study = study(p.config, p.text, p.origin, p.request, &mut p.more)?;
    Ok(Job::Sweep {
        study: Box::new(study),
    })
}

/// Plan the study of `config` (of `text`, named `origin`): every point's
/// config made and checked by planning its first run, a point at a time
/// (each dropped once its largest scene and memory are kept); each run's
/// warnings once in `warnings`.
///
/// # Errors
/// [`JobError::Input`] without a `[sweep]` table; [`JobError::Config`]
/// for a key or value of `[sweep]` at fault, placed at its entry, or a
/// measure the runs do not give; what [`Plan::new`] refuses of a run.
fn study(
    config: &Config,
    text: &str,
    origin: &str,
    request: &Request,
    warnings: &mut Vec<Warning>,
) -> Result<Study, JobError> {
    let Some(settings) = config.sweep.clone() else {
        return Err(JobError::Input(format!(
            "{origin}:1:1: sweep: missing table [sweep]; the sweep job needs one naming at least one config key and its values, e.g. \"fracture.width_mm\" = [2.0, 2.5, 3.0]"
        )));
    };
    let kind = match settings.job {
        Some(RunJob::Pack) => JobKind::Pack,
        Some(RunJob::Optimise) => JobKind::Optimise,
        Some(RunJob::Layer) => JobKind::Layer,
        None => JobKind::single(config),
    };
    if settings.measure == Measure::Error && config.optimise.is_none() && kind != JobKind::Layer {
        return Err(ConfigError::NotApplicable {
            at: key_location(text, origin, "sweep.measure")
                .unwrap_or_else(|| Location::at(origin, text, 0)),
            key: "sweep.measure".to_owned(),
            reason: format!(
                "the {} runs have no target to measure an error against: give [optimise] target_porosity, or chart another measure",
                kind.name()
            ),
        }
        .into());
    }
    let options = ParseOptions {
        force: request.force,
    };
    let texts: Vec<Vec<String>> = settings.keys.iter().map(SweptKey::texts).collect();
    let points: Vec<StudyPoint> = points(&settings.keys)
        .into_iter()
        .zip(point_names(&settings.keys))
        .map(|(indices, name)| StudyPoint {
            name,
            values: indices
                .iter()
                .enumerate()
                .map(|(k, &i)| texts[k][i].clone())
                .collect(),
            indices,
        })
        .collect();
    let mut study = Study {
        kind,
        points,
        runs: Vec::with_capacity(settings.runs()),
        resume: request.resume,
        largest: Largest::none(),
        configs: SweepConfigs::new(text, origin, options)?,
        origin: origin.to_owned(),
        force: request.force,
        time_cap: request.time_cap,
        settings,
    };
    for (p, point) in study.points.iter().enumerate() {
        for k in 0..study.settings.seeds as u64 {
            let seed = config.scene.seed.wrapping_add(k);
            study.runs.push(StudyRun {
                name: run_name(&point.name, seed),
                point: p,
                seed,
            });
        }
    }
    // Each point's first run planned now: a point's fault, or a job that
    // refuses a point's config, refuses the study; each warning is said
    // once, before it runs; the largest scene and memory are kept.
    let first_seed = config.scene.seed;
    let mut largest = Largest::none();
    for point in &study.points {
        let made = study
            .configs
            .point(&study.settings, &point.indices, &point.name)?;
        let Ok(config) = made.config else {
            continue;
        };
        let plan = Plan::new(
            config,
            &made.text,
            origin,
            &Request {
                kind: Some(kind),
                seed: Some(first_seed),
                force: request.force,
                resume: false,
                checkpoint_every: 0,
                time_cap: request.time_cap,
            },
        )?;
        largest.merge(&plan.largest(), &point.name);
        for w in plan.warnings {
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
    }
    study.largest = largest;
    Ok(study)
}

/// What one run gives back to every process: how it ended, the files the
/// study keeps of it, and the warnings it gave while running.
#[derive(Debug, Serialize, Deserialize)]
struct Ran {
    status: Status,
    files: Vec<(String, Vec<u8>)>,
    warnings: Vec<Warning>,
}

/// A study run: its report, whether it was cut short, the files it made,
/// and the files of runs resumed, which stay as the earlier study wrote them.
struct Finished {
    report: Report,
    interrupted: bool,
    files: Vec<(String, Vec<u8>)>,
    kept: Vec<String>,
}

/// Run a parameter study: its own files, each run's that it keeps, and
/// those of the runs it resumed (left in place).
pub(super) fn run(
    job: &mut Running<'_>,
    study: &Study,
    cancel: &Cancel,
) -> Result<(Report, bool), JobError> {
    let done = run_study(job.plan, study, job.observer, cancel, job.store, job.farm)?;
    job.files.extend(done.kept);
    job.write("", done.files);
    Ok((done.report, done.interrupted))
}

/// Run `study` (of `plan`): events to `observer`, stopped by `cancel`,
/// the earlier study read from `store` when resuming.
///
/// # Errors
/// [`JobError::Input`] when a resume finds no study of this plan to go on
/// from; [`JobError::Cancelled`] when no run was finished; an output error.
fn run_study(
    plan: &Plan,
    study: &Study,
    observer: &mut dyn Observer,
    cancel: &Cancel,
    store: &dyn Store,
    farm: &dyn Farm,
) -> Result<Finished, JobError> {
    let total = study.runs.len();
    observer.event(&Event::Stage {
        stage: Stage::Sweep,
        total: Some(total as u64),
    });
    let mut rows: Vec<Option<Row>> = vec![None; total];
    let mut kept = Vec::new();
    if study.resume {
        let earlier = earlier(plan, study, store, farm)?;
        for (i, run) in study.runs.iter().enumerate() {
            let Some(row) = earlier.rows.get(&run.name) else {
                continue;
            };
            let Status::Finished(measures) = &row.status else {
                continue;
            };
            if row.values != study.points[run.point].values || row.seed != run.seed {
                continue;
            }
            if let Some(why) = impossible(measures) {
                observer.event(&Event::Warning(Warning {
                    kind: WarningKind::ImpossibleRow,
                    message: format!(
                        "{SWEEP_CSV} in {}: the finished row of run {} has {why}, which no run gives: the run is run again",
                        store.location(),
                        run.name
                    ),
                }));
                continue;
            }
            let folder = format!("runs/{}/", run.name);
            kept.extend(
                earlier
                    .files
                    .iter()
                    .filter(|f| f.starts_with(&folder))
                    .cloned(),
            );
            rows[i] = Some(row.clone());
            observer.event(&Event::Run {
                stage: Stage::Sweep,
                index: i,
                label: format!("{} (resumed)", run.name),
            });
        }
    }
    let resumed = rows.iter().flatten().count();
    let pending: Vec<usize> = (0..total).filter(|&i| rows[i].is_none()).collect();
    let workers = rayon::current_num_threads().max(1) * farm.processes().max(1);
    let wave = farm::share(farm, workers * WAVE_PER_WORKER).max(1);
    let keep = study.settings.keep;
    let mut files = Vec::new();
    let mut warned: Vec<(String, Warning)> = Vec::new();
    for chunk in pending.chunks(wave) {
        let ran: Vec<Ran> = farm::map(farm, chunk.len(), |j| {
            execute(study, &study.runs[chunk[j]], keep, cancel)
        });
        for (&i, ran) in chunk.iter().zip(ran) {
            let run = &study.runs[i];
            if ran.status == Status::NotRun {
                continue;
            }
            observer.event(&Event::Run {
                stage: Stage::Sweep,
                index: i,
                label: run.name.clone(),
            });
            files.extend(ran.files);
            warned.extend(ran.warnings.into_iter().map(|w| (run.name.clone(), w)));
            rows[i] = Some(row(study, run, ran.status));
        }
        if farm::agree(farm, cancel.is_cancelled()) {
            break;
        }
    }
    let rows: Vec<Row> = rows
        .into_iter()
        .zip(&study.runs)
        .map(|(r, run)| r.unwrap_or_else(|| row(study, run, Status::NotRun)))
        .collect();
    let interrupted = rows.iter().any(|r| r.status == Status::NotRun);
    if interrupted && rows.iter().all(|r| r.status == Status::NotRun) {
        return Err(JobError::Cancelled);
    }
    for warning in gathered(warned) {
        observer.event(&Event::Warning(warning));
    }
    let mut made = render_sweep(&study.settings, &rows)?;
    made.extend(files);
    Ok(Finished {
        report: Report::Sweep {
            rows,
            keys: study.settings.keys.iter().map(|k| k.path.clone()).collect(),
            seeds: study.settings.seeds,
            measure: study.settings.measure,
            resumed,
        },
        interrupted,
        files: made,
        kept,
    })
}

fn row(study: &Study, run: &StudyRun, status: Status) -> Row {
    Row {
        run: run.name.clone(),
        values: study.points[run.point].values.clone(),
        seed: run.seed,
        status,
    }
}

/// Run one run of a study alone: on this thread's farm, into a store of
/// its own, its events recorded only for the warnings it gives.
fn execute(study: &Study, run: &StudyRun, keep: Keep, cancel: &Cancel) -> Ran {
    let ended = |status| Ran {
        status,
        files: Vec::new(),
        warnings: Vec::new(),
    };
    let plan = match study.run_plan(run) {
        Ok(plan) => plan,
        Err(why) => return ended(Status::Failed(why)),
    };
    if cancel.is_cancelled() {
        return ended(Status::NotRun);
    }
    let mut store = MemoryStore::default();
    let mut warnings = Vec::new();
    let mut observer = |e: &Event| {
        if let Event::Warning(w) = e
            && !plan.warnings.contains(w)
        {
            warnings.push(w.clone());
        }
    };
    let outcome = run_on(&plan, &mut observer, cancel, &mut store, &Local);
    let status = match outcome {
        Ok(outcome) if outcome.interrupted => return ended(Status::NotRun),
        Ok(outcome) => match measures(&plan, &outcome.report, outcome.seconds()) {
            Some(m) => Status::Finished(m),
            None => Status::Failed("the run gave no measures".to_owned()),
        },
        Err(JobError::Cancelled) => return ended(Status::NotRun),
        Err(e) => Status::Failed(one_line(&e)),
    };
    let files = if matches!(status, Status::Finished(_)) {
        store
            .files
            .into_iter()
            .filter(|(name, _)| match keep {
                Keep::None => false,
                Keep::Summary => {
                    name == SUMMARY_JSON || name.ends_with(&format!("/{SUMMARY_JSON}"))
                }
                Keep::All => true,
            })
            .map(|(name, bytes)| (format!("runs/{}/{name}", run.name), bytes))
            .collect()
    } else {
        Vec::new()
    };
    Ran {
        status,
        files,
        warnings,
    }
}

/// A finished run's measures; the totals and means over the wells of a batch.
fn measures(plan: &Plan, report: &Report, seconds: f64) -> Option<Measures> {
    let target = plan.config.optimise.map(|o| o.target_porosity);
    let error = |porosity: f64| target.map(|t| (porosity - t).abs());
    let of = |m: &crate::Metrics, target_error| Measures {
        particles: m.particles,
        porosity: m.porosity,
        psd_ks: m.psd_ks,
        coordination: m.coordination,
        target_error,
        seconds,
    };
    match report {
        Report::Pack { metrics, .. } => Some(of(metrics, error(metrics.porosity))),
        Report::Optimise {
            metrics, summary, ..
        } => Some(of(metrics, Some(summary.error))),
        Report::Layer {
            metrics, layered, ..
        } => Some(of(metrics, Some(layered.rms))),
        Report::Wells { wells, .. } if !wells.is_empty() => {
            let n = wells.len() as f64;
            let mean = |f: fn(&super::WellOutcome) -> f64| wells.iter().map(f).sum::<f64>() / n;
            let porosity = mean(|w| w.row.porosity);
            Some(Measures {
                particles: wells.iter().map(|w| w.row.particles).sum(),
                porosity,
                psd_ks: mean(|w| w.row.psd_ks),
                coordination: mean(|w| w.row.coordination),
                target_error: error(porosity),
                seconds,
            })
        }
        _ => None,
    }
}

/// The first measure of a finished row that no run gives, in words
/// (`porosity -7, outside [0, 1]`): a row edited or damaged, which a
/// resume must not keep as a result.
fn impossible(m: &Measures) -> Option<String> {
    let fraction = |v: f64| (0.0..=1.0).contains(&v);
    let not_negative = |v: f64| v.is_finite() && v >= 0.0;
    let target_error = m.target_error.unwrap_or(0.0);
    [
        (
            "porosity",
            m.porosity,
            fraction(m.porosity),
            "outside [0, 1]",
        ),
        ("psd_ks", m.psd_ks, fraction(m.psd_ks), "outside [0, 1]"),
        (
            "coordination",
            m.coordination,
            not_negative(m.coordination),
            "not a finite number ≥ 0",
        ),
        (
            "target_error",
            target_error,
            not_negative(target_error),
            "not a finite number ≥ 0",
        ),
        (
            "seconds",
            m.seconds,
            not_negative(m.seconds),
            "not a finite number ≥ 0",
        ),
    ]
    .into_iter()
    .find(|(_, _, ok, _)| !ok)
    .map(|(name, value, _, why)| format!("{name} {value}, {why}"))
}

/// An error and its causes in one line: `cannot pack the scene: …`.
fn one_line(e: &JobError) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        let said = cause.to_string();
        if !text.contains(&said) {
            text = format!("{text}: {said}");
        }
        source = cause.source();
    }
    text.replace(['\n', '\r'], " ")
}

/// The warnings the runs gave, one per kind: the first run's, with how
/// many others gave one of that kind and some of their names.
fn gathered(warned: Vec<(String, Warning)>) -> Vec<Warning> {
    let mut kinds: Vec<WarningKind> = Vec::new();
    for (_, w) in &warned {
        if !kinds.contains(&w.kind) {
            kinds.push(w.kind);
        }
    }
    kinds
        .into_iter()
        .filter_map(|kind| {
            let mine: Vec<&(String, Warning)> =
                warned.iter().filter(|(_, w)| w.kind == kind).collect();
            let (first, warning) = mine.first()?;
            let others: Vec<&str> = mine[1..].iter().map(|(name, _)| name.as_str()).collect();
            let more = match others.len() {
                0 => String::new(),
                n if n <= NAMED_RUNS => format!(" (so did {})", others.join(", ")),
                n => format!(
                    " (so did {} and {} more runs)",
                    others[..NAMED_RUNS].join(", "),
                    n - NAMED_RUNS
                ),
            };
            Some(Warning {
                kind,
                message: format!("run {first}: {}{more}", warning.message),
            })
        })
        .collect()
}

/// The earlier study a resume goes on from: its rows by run name, and the files its manifest lists.
struct Earlier {
    rows: BTreeMap<String, Row>,
    files: Vec<String>,
}

/// The store's `sweep.csv` and `manifest.json`, read by the leading
/// process and shared, if they belong to this plan.
fn earlier(
    plan: &Plan,
    study: &Study,
    store: &dyn Store,
    farm: &dyn Farm,
) -> Result<Earlier, JobError> {
    let location = store.location();
    let read = |name: &str| -> Result<Option<Vec<u8>>, StoreError> { store.read(name) };
    let local = read(MANIFEST_JSON).and_then(|m| Ok((m, read(SWEEP_CSV)?)));
    let shared = farm::share(
        farm,
        local
            .as_ref()
            .map(Clone::clone)
            .map_err(ToString::to_string),
    );
    let (manifest, table) = match (local, shared) {
        (Err(e), _) => return Err(e.into()),
        (Ok(_), Err(e)) => return Err(JobError::Input(format!("{location}: {e}"))),
        (Ok(_), Ok(both)) => both,
    };
    let (Some(manifest), Some(table)) = (manifest, table) else {
        return Err(JobError::Input(format!(
            "there is no study to resume in {location}: it needs the {SWEEP_CSV} and {MANIFEST_JSON} of a stopped gapack sweep"
        )));
    };
    let manifest = Manifest::from_bytes(&manifest).map_err(|e| {
        JobError::Input(format!(
            "{MANIFEST_JSON} in {location} is not a gapack manifest: {e}"
        ))
    })?;
    if manifest.job != JobKind::Sweep || manifest.identity != plan.identity {
        return Err(JobError::Input(format!(
            "{SWEEP_CSV} in {location} belongs to another run: the {} job of config {} with seed {}; this study is {} with seed {} (the config's text or the seed differ)",
            manifest.job.name(),
            manifest.config,
            manifest.seed,
            plan.origin,
            plan.seed()
        )));
    }
    let rows = read_sweep_csv(&table, study.settings.keys.len())
        .into_iter()
        .map(|r| (r.run.clone(), r))
        .collect();
    Ok(Earlier {
        rows,
        files: manifest.files,
    })
}

/// The study's lines for `gapack validate`: its runs, then each point; its own files.
pub(super) fn words(study: &Study) -> Words {
    let mut words = Words::new(study_line(study));
    words.head.extend(point_lines(study));
    words.files = Some((
        match study.settings.keep {
            Keep::None => "sweep.csv, .svg, .png",
            Keep::Summary => "sweep.csv, .svg, .png, and runs/<run>/summary.json",
            Keep::All => "sweep.csv, .svg, .png, and every file of each run in runs/<run>/",
        },
        "manifest.json",
    ));
    words
}

/// A line per point (its measures over the seeds), then the files and counts.
pub(super) fn lines(at: &str, rows: &[Row], seeds: usize, resumed: usize) -> Vec<String> {
    let mut lines = study_result(rows, seeds);
    let count = |f: fn(&Status) -> bool| rows.iter().filter(|r| f(&r.status)).count();
    let finished = count(|s| matches!(s, Status::Finished(_)));
    let failed = count(|s| matches!(s, Status::Failed(_)));
    let done = finished + failed;
    lines.push(format!(
        "{at}: sweep.csv, sweep.svg, sweep.png: {} runs, {finished} finished, {failed} failed{}{}",
        rows.len(),
        if resumed > 0 {
            format!(" ({resumed} kept from the earlier sweep.csv)")
        } else {
            String::new()
        },
        interrupted_runs(done, rows.len())
    ));
    lines
}

/// The time of the runs finished (s).
pub(super) fn seconds(rows: &[Row]) -> f64 {
    rows.iter()
        .map(|r| match &r.status {
            Status::Finished(m) => m.seconds,
            _ => 0.0,
        })
        .sum()
}

/// Points of a study listed by `gapack validate`, before `and N more`.
const LISTED_POINTS: usize = 40;

/// `job: sweep: 3 values of fracture.width_mm × 2 of grading.preset × 5 seeds = 30 pack runs, porosity charted`.
fn study_line(study: &Study) -> String {
    let s = &study.settings;
    let keys: Vec<String> = s
        .keys
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let n = k.values.len();
            if i == 0 {
                format!("{n} value{} of {}", plural(n), k.path)
            } else {
                format!("{n} of {}", k.path)
            }
        })
        .collect();
    format!(
        "job: sweep{}: {} × {} seed{} = {} {} runs, {} charted against {}",
        if study.resume {
            " (resumed: the finished rows of sweep.csv are kept)"
        } else {
            ""
        },
        keys.join(" × "),
        s.seeds,
        plural(s.seeds),
        study.runs.len(),
        study.kind.name(),
        s.measure.config_name(),
        s.keys.first().map_or("", |k| k.path.as_str()),
    )
}

/// One line per point of a study: its particles (estimated, per run), or why it cannot run.
fn point_lines(study: &Study) -> Vec<String> {
    let mut lines: Vec<String> = study
        .points
        .iter()
        .enumerate()
        .take(LISTED_POINTS)
        .map(|(p, point)| {
            let name = &point.name;
            match study.point_config(p) {
                Ok((_, Ok(config))) => {
                    let (disks, window) = match &config.fracture {
                        Some(f) => (
                            f.wells
                                .iter()
                                .map(|w| w.scene.estimated_disks())
                                .sum::<f64>(),
                            matches!(f.extent, Extent::Window { .. }),
                        ),
                        None => (config.scene.estimated_disks(), false),
                    };
                    format!(
                        "point {name}: about {disks:.0} particles a run{}",
                        if window {
                            " if packed whole (a window packs fewer)"
                        } else {
                            ""
                        }
                    )
                }
                Ok((_, Err(why))) | Err(why) => format!("point {name}: its runs fail: {why}"),
            }
        })
        .collect();
    let points = study.points.len();
    if points > LISTED_POINTS {
        lines.push(format!("… and {} more points", points - LISTED_POINTS));
    }
    let largest = &study.largest;
    if largest.max_disks_in != "no run" {
        lines.push(format!(
            "largest run: {}, at most {:.0} disks; most memory: {}, about {}",
            largest.max_disks_in,
            largest.max_disks,
            largest.peak_bytes_in,
            memory(largest.peak_bytes)
        ));
    }
    lines
}

/// One line per point of a study's rows: its measures over the seeds
/// that finished (porosity with its range), or why its runs failed.
fn study_result(rows: &[Row], seeds: usize) -> Vec<String> {
    let spreads = crate::study::spreads(rows, seeds, Measure::Porosity);
    rows.chunks(seeds.max(1))
        .zip(spreads)
        .filter_map(|(point, porosity)| {
            let first = point.first()?;
            let name = first
                .run
                .rsplit_once(",seed=")
                .map_or(first.run.as_str(), |(p, _)| p);
            let done: Vec<&crate::study::Measures> = point
                .iter()
                .filter_map(|r| match &r.status {
                    Status::Finished(m) => Some(m),
                    _ => None,
                })
                .collect();
            let Some(p) = porosity else {
                let failed = point.iter().find_map(|r| match &r.status {
                    Status::Failed(why) => Some(why.as_str()),
                    _ => None,
                });
                return failed.map(|why| format!("{name:<40} failed: {why}"));
            };
            let n = done.len() as f64;
            let mean = |f: fn(&crate::study::Measures) -> f64| done.iter().map(|m| f(m)).sum::<f64>() / n;
            let errors: Vec<f64> = done.iter().filter_map(|m| m.target_error).collect();
            Some(format!(
                "{name:<40} porosity {:.4} ({:.4}–{:.4}), {:.0} particles, psd_ks {:.3}, coordination {:.2}{}, {} of {} runs, {} each",
                p.mean,
                p.min,
                p.max,
                mean(|m| m.particles as f64),
                mean(|m| m.psd_ks),
                mean(|m| m.coordination),
                if errors.is_empty() {
                    String::new()
                } else {
                    format!(
                        ", target error {:.4}",
                        errors.iter().sum::<f64>() / errors.len() as f64
                    )
                },
                done.len(),
                point.len(),
                duration(mean(|m| m.seconds)),
            ))
        })
        .collect()
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn warning(kind: WarningKind, message: &str) -> Warning {
        Warning {
            kind,
            message: message.to_owned(),
        }
    }

    /// The runs' warnings are said once per kind, naming a few of the runs.
    #[test]
    fn the_runs_warnings_are_gathered_by_kind() {
        let bent = |run: &str| {
            (
                run.to_owned(),
                warning(WarningKind::GradingBent, &format!("{run} bends")),
            )
        };
        let mut warned: Vec<(String, Warning)> = ["a", "b", "c", "d", "e"].map(bent).to_vec();
        warned.insert(
            1,
            (
                "b".to_owned(),
                warning(WarningKind::TargetNotReached, "not reached"),
            ),
        );
        let said = gathered(warned);
        assert_eq!(said.len(), 2);
        assert_eq!(said[0].kind, WarningKind::GradingBent);
        assert_eq!(
            said[0].message,
            "run a: a bends (so did b, c, d and 1 more runs)"
        );
        assert_eq!(said[1].message, "run b: not reached");
        assert!(gathered(Vec::new()).is_empty());
    }

    /// A failure's causes follow it on one line, none said twice.
    #[test]
    fn measures_no_run_gives_are_told_apart() {
        let fine = Measures {
            particles: 10,
            porosity: 0.3,
            psd_ks: 0.05,
            coordination: 2.5,
            target_error: Some(0.01),
            seconds: 0.2,
        };
        assert_eq!(impossible(&fine), None);
        assert_eq!(
            impossible(&Measures {
                target_error: None,
                porosity: 0.0,
                psd_ks: 1.0,
                ..fine
            }),
            None
        );
        for (edited, said) in [
            (
                Measures {
                    porosity: -7.0,
                    ..fine
                },
                "porosity -7, outside [0, 1]",
            ),
            (
                Measures {
                    porosity: f64::NAN,
                    ..fine
                },
                "porosity NaN, outside [0, 1]",
            ),
            (
                Measures {
                    psd_ks: 1.5,
                    ..fine
                },
                "psd_ks 1.5, outside [0, 1]",
            ),
            (
                Measures {
                    coordination: f64::INFINITY,
                    ..fine
                },
                "coordination inf, not a finite number ≥ 0",
            ),
            (
                Measures {
                    target_error: Some(-0.1),
                    ..fine
                },
                "target_error -0.1, not a finite number ≥ 0",
            ),
            (
                Measures {
                    seconds: -1.0,
                    ..fine
                },
                "seconds -1, not a finite number ≥ 0",
            ),
        ] {
            assert_eq!(impossible(&edited).as_deref(), Some(said));
        }
    }

    #[test]
    fn a_failure_is_one_line_with_its_causes() {
        let e = JobError::Pack {
            what: "the scene".to_owned(),
            source: crate::PackError::DomainTooNarrow {
                inscribed: 0.2,
                d_min: 0.4,
            },
        };
        let line = one_line(&e);
        assert!(line.starts_with("cannot pack the scene: "), "{line}");
        assert!(
            line.contains("too narrow") && !line.contains('\n'),
            "{line}"
        );
    }
}
