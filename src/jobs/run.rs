//! [`run`]: any plan, with an observer, a cancel token and a store — the
//! dispatch to the job's own file ([`Job::run`]) and the commit of what it
//! made, with its `manifest.json`, in one step.

use serde::{Deserialize, Serialize};

use super::contract::Manifest;
use super::error::JobError;
use super::event::{Event, Observer, Stage, Warning, WarningKind};
use super::plan::Plan;
use super::registry::{Job, JobKind, Report};
use super::store::{Staged, Store, StoreError};
use crate::Method;
use crate::cancel::{Cancel, Cancelled};
use crate::check::{Check, KS_MARGIN, grading_kept, ks_limit};
use crate::config::Config;
use crate::farm::{Farm, Local};
use crate::ga::Generation;
use crate::metrics::Metrics;
use crate::metrics::near::SharedIndex;
use crate::output::{
    Body, FILE_NAMES, Format, OutputError, OutputSettings, RunInfo, SVG_MAX_BYTES, Stream, WellRow,
    check_packing, confirm, packing_streams, packing_svg_note, render_measured_bodies,
};
use crate::packer::{PackError, Packing, pack_observed};

/// File name of the list of a run's files, in its folder.
pub const MANIFEST_JSON: &str = "manifest.json";

/// File name of a search's checkpoint, in the run's folder.
pub const CHECKPOINT_JSON: &str = "checkpoint.json";

/// What a job gives back: what it made, where, and whether it was cut short.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Outcome {
    /// Which job ran.
    pub kind: JobKind,
    /// Where its files are ([`Store::location`]).
    pub location: String,
    /// Whether it was cancelled and returns only what it had finished.
    pub interrupted: bool,
    /// Every file of the run (as listed in `manifest.json`, which is one of them).
    pub files: Vec<String>,
    /// What its files do not show as usual (`packing.svg` holding an image
    /// of a huge packing), a sentence each, as `manifest.json` lists them.
    pub notes: Vec<String>,
    /// The job's own results.
    pub report: Report,
    /// Wall-clock seconds of each step of the run that packs, measures or
    /// writes, in the order first met (a batch sums its wells').
    pub steps: Vec<StepTime>,
}

impl Outcome {
    /// Disks placed elsewhere (a table read back, a packing edited by hand)
    /// as the outcome of `plan`'s pack job: measured against the plan's
    /// scene, nothing written yet, no time spent. A front end hands it to
    /// [`write()`] to render a packing it did not make; [`write()`] checks it
    /// first, as it checks every packing.
    ///
    /// # Errors
    /// [`JobError::Cancelled`] once `cancel` is raised.
    pub fn of_packing(plan: &Plan, packing: Packing, cancel: &Cancel) -> Result<Outcome, JobError> {
        let metrics = crate::metrics::measure_cancellable(&packing, &plan.config.scene, cancel)?;
        Ok(Outcome {
            kind: JobKind::Pack,
            location: plan.origin.clone(),
            interrupted: false,
            files: Vec::new(),
            notes: Vec::new(),
            report: Report::Pack {
                packing,
                metrics,
                seconds: 0.0,
            },
            steps: Vec::new(),
        })
    }
}

/// One step of a run and the wall-clock seconds it took: how a front end
/// shows where a long run spends its time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[non_exhaustive]
pub struct StepTime {
    /// Which step.
    pub step: Step,
    /// Its wall-clock seconds, summed over the times it ran.
    pub seconds: f64,
}

/// A step of a run that works on packings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Step {
    /// Packing the scene (every scene of a batch).
    Pack,
    /// Measuring the packing (`metrics::measure`).
    Measure,
    /// The independent check, rendering every file and committing them:
    /// the time after packing not spent measuring (the check and the
    /// packing's largest files are made while it is measured).
    Write,
}

impl Step {
    /// Its name in a result line.
    pub fn name(self) -> &'static str {
        match self {
            Step::Pack => "pack",
            Step::Measure => "measure",
            Step::Write => "write",
        }
    }
}

/// One fracture of a `[fracture]` run.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[non_exhaustive]
pub struct WellOutcome {
    /// Its folder in the store (`""` for the only fracture of a run, else `name/`).
    pub folder: String,
    /// Its row of `wells.csv`.
    pub row: WellRow,
    /// Its length (mm).
    pub length: f64,
    /// The windows grown, in window mode, and whether they settled.
    pub window: Option<(Vec<crate::fracture::WindowStep>, bool)>,
    /// The packing's measurements (the last window's in window mode).
    pub metrics: Metrics,
}

/// Run `plan`: events to `observer`, stopped by `cancel`, files to `store`.
///
/// # Behavior
/// Every file is made after the packing has passed an independent check
/// (the packing's tables and exports streamed to the store while they are
/// formatted, [`Store::stage`]; the pictures and small files in memory) and the run's files go to the store in one
/// [`Store::commit_staged`] at the end, whole or not at all: its files, its
/// `manifest.json` listing them, and the removal of the files an earlier
/// run left in the same place that this run did not write. A run that
/// fails — bad input, a scene that cannot be packed, a well of a batch that
/// cannot be written — leaves the store as it found it. A cancelled job returns what it
/// finished: the search its best packing so far (and a checkpoint), a
/// batch its finished wells, a comparison or sweep its finished runs; a
/// job with nothing finished writes nothing and returns
/// [`JobError::Cancelled`].
///
/// # Errors
/// [`JobError`]: bad input, a scene that cannot be packed, an output or
/// store failure, or a cancel before anything was finished.
pub fn run(
    plan: &Plan,
    observer: &mut dyn Observer,
    cancel: &Cancel,
    store: &mut dyn Store,
) -> Result<Outcome, JobError> {
    run_on(plan, observer, cancel, store, &Local)
}

/// [`run`] on one process of `farm`: every process of the farm runs the
/// same plan, the work of each search and batch is shared out among them
/// ([`crate::farm`]), and the files are the same as [`run`]'s. The
/// processes that do not lead should be given a store that keeps nothing
/// (a [`super::MemoryStore`]) and an observer that shows nothing.
///
/// # Errors
/// As [`run`].
pub fn run_on(
    plan: &Plan,
    observer: &mut dyn Observer,
    cancel: &Cancel,
    store: &mut dyn Store,
    farm: &dyn Farm,
) -> Result<Outcome, JobError> {
    observer.event(&Event::Started { job: plan.kind });
    for warning in &plan.warnings {
        observer.event(&Event::Warning(warning.clone()));
    }
    let mut job = Running::new(plan, observer, store, farm);
    let (report, interrupted) = match plan.job.run(&mut job, cancel) {
        Ok(done) => done,
        Err(e @ JobError::Checkpoint(_)) => {
            // The search stopped early and keeps its best packing: that
            // result is committed (as interrupted), then the error is told.
            job.finish(true)?;
            return Err(e);
        }
        // Nothing of a failed or refused run is committed: no file, no folder.
        Err(e) => return Err(e),
    };
    let files = job.finish(interrupted)?;
    Ok(Outcome {
        kind: plan.kind,
        location: job.store.location(),
        interrupted,
        files,
        notes: job.notes,
        report,
        steps: job.steps,
    })
}

/// Write the files of a finished `pack`, `layer` or `optimise` job again,
/// into `store`, as [`run`] writes them but with `output` in place of the
/// config's `[output]` (other formats, say): the same renderers from the
/// same report, so the same plan, seed and formats give the same bytes as
/// a run that wrote them itself (the `seconds` recorded are the run's).
/// The files go in one [`Store::commit`] with their `manifest.json`,
/// removing what an earlier run left there, as [`run`] does. A front end
/// that holds a run's packing (the Python package) runs the job with no
/// formats and writes later, where and as its user asks.
///
/// A search's checkpoint is not written: a search resumes from a run that
/// wrote its own files.
///
/// # Errors
/// [`JobError::Input`] for an outcome of another job; [`JobError::Output`]
/// or [`JobError::Store`] when a file cannot be made or written.
pub fn write(
    plan: &Plan,
    outcome: &Outcome,
    output: &OutputSettings,
    store: &mut dyn Store,
) -> Result<Vec<String>, JobError> {
    // The warnings were told when the job ran.
    let mut silent = super::Silent;
    let mut job = Running::new(plan, &mut silent, store, &Local);
    let Some((packing, metrics, _)) = outcome.report.run_info(plan, output) else {
        return Err(not_one_packing(plan));
    };
    let (_, ahead) =
        job.measure_packing("", packing, output, &Cancel::new(), |_, _| Ok(*metrics))?;
    job.write_report(&outcome.report, output, ahead)?;
    job.finish(outcome.interrupted)
}

/// A job under way: its plan, its observer, its store, the names of its
/// files so far and the files it has made but not yet committed. Each
/// job's file runs its job on one.
pub(super) struct Running<'p> {
    /// The plan run.
    pub plan: &'p Plan,
    /// Where the events go.
    pub observer: &'p mut dyn Observer,
    /// Where the files go.
    pub store: &'p mut dyn Store,
    /// The processes the work is shared out to.
    pub farm: &'p dyn Farm,
    /// Every file of the run, for the manifest (a checkpoint the search
    /// wrote itself included).
    pub files: Vec<String>,
    /// The files made or staged, held until [`Running::finish`] commits
    /// them with the manifest in one step: a run that fails leaves none of
    /// them (a staged file is removed when dropped).
    pub pending: Vec<Staged>,
    /// What the files do not show as usual, for the manifest and the result lines.
    pub notes: Vec<String>,
    /// The time taken by each step so far.
    pub steps: Vec<StepTime>,
}

impl<'p> Running<'p> {
    /// A run of `plan` with nothing made yet.
    pub fn new(
        plan: &'p Plan,
        observer: &'p mut dyn Observer,
        store: &'p mut dyn Store,
        farm: &'p dyn Farm,
    ) -> Self {
        Running {
            plan,
            observer,
            store,
            farm,
            files: Vec::new(),
            pending: Vec::new(),
            notes: Vec::new(),
            steps: Vec::new(),
        }
    }

    /// Add `seconds` to `step`'s time.
    pub fn spent(&mut self, step: Step, seconds: f64) {
        match self.steps.iter_mut().find(|s| s.step == step) {
            Some(s) => s.seconds += seconds,
            None => self.steps.push(StepTime { step, seconds }),
        }
    }

    /// The plan's config.
    pub fn config(&self) -> &'p Config {
        &self.plan.config
    }

    /// Tell the observer.
    pub fn event(&mut self, event: Event) {
        self.observer.event(&event);
    }

    /// Add a set of files under `folder` to the run's files, committed by
    /// [`Running::finish`] with all the others or not at all.
    pub fn write(&mut self, folder: &str, files: Vec<(String, Vec<u8>)>) {
        for (name, bytes) in files {
            let name = format!("{folder}{name}");
            self.files.push(name.clone());
            self.pending.push(Staged::bytes(name, bytes));
        }
    }

    /// [`Running::write`] of files made or streamed: a streamed one is
    /// staged in the store now, while what it streams from is at hand.
    fn write_bodies(
        &mut self,
        folder: &str,
        files: Vec<(String, Body<'_>)>,
    ) -> Result<(), JobError> {
        for (name, body) in files {
            let name = format!("{folder}{name}");
            self.files.push(name.clone());
            let staged = match body {
                Body::Bytes(bytes) => Staged::bytes(name, bytes),
                Body::Stream(write) => self.store.stage(&name, &mut |out| write(out))?,
            };
            self.pending.push(staged);
        }
        Ok(())
    }

    /// Measure `packing` by `measure` and check it ([`check_packing`],
    /// independent of the measures) on threads of their own, while this one
    /// stages in the store, under `folder`, the packing's files that do not
    /// read the measures ([`packing_streams`], as `output` asks): the
    /// largest files are written and the check made while the packing is
    /// measured, the three sides' serial steps (the measure's sort and
    /// index, the check's index, the files' copy to disk) side by side.
    /// Nothing is committed: [`Running::write_packing`] adds the files to
    /// the run's once the check passes, and they are removed if it fails
    /// or the run stops. `measure` is given the disks' neighbour index the
    /// check shares ([`SharedIndex`]: built once, by the first to ask),
    /// and each side a token raised when `cancel` is or another side
    /// fails, which stops them all.
    ///
    /// # Errors
    /// [`JobError::Cancelled`] when `cancel` stops the work; an output or
    /// store error when a file cannot be made or staged.
    pub fn measure_packing(
        &mut self,
        folder: &str,
        packing: &Packing,
        output: &OutputSettings,
        cancel: &Cancel,
        measure: impl FnOnce(&SharedIndex<'_>, &Cancel) -> Result<Metrics, Cancelled> + Send,
    ) -> Result<(Metrics, Ahead), JobError> {
        let start = std::time::Instant::now();
        let plan = self.plan;
        let streams = packing_streams(packing, &plan.config.materials, output)?;
        // Any side that fails stops the others.
        let stop = cancel.child();
        let store = &mut *self.store;
        let shared = SharedIndex::new(&packing.disks);
        let side = || {
            let begun = std::time::Instant::now();
            let metrics = measure(&shared, &stop);
            if metrics.is_err() {
                stop.cancel();
            }
            (metrics, begun.elapsed().as_secs_f64())
        };
        let checking = || {
            let check = check_packing(packing, &shared, &stop);
            if check.is_err() {
                stop.cancel();
            }
            check
        };
        let staging = |store: &mut dyn Store| {
            let staged = stage_streams(store, folder, streams, &stop);
            if staged.is_err() {
                stop.cancel();
            }
            staged
        };
        let (side, check, staged) = if rayon::current_thread_index().is_some() {
            // On a worker of rayon's pool (the runs of a sweep, a batch or
            // a search): a thread waited for there would hold a worker the
            // measure's own parallel loops may be queued behind, so the
            // sides run one after the other.
            let measured = side();
            (Ok(measured), Ok(checking()), staging(store))
        } else {
            std::thread::scope(|s| {
                let measuring = s.spawn(side);
                let checked = s.spawn(checking);
                let staged = staging(store);
                (measuring.join(), checked.join(), staged)
            })
        };
        let check = match check {
            Ok(check) => check,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        let (metrics, measured) = match side {
            Ok(side) => side,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        self.spent(Step::Measure, measured);
        let after = start.elapsed().as_secs_f64() - measured;
        self.spent(Step::Write, after.max(0.0));
        if cancel.is_cancelled() {
            return Err(JobError::Cancelled);
        }
        // A side stopped without a cancel was stopped by another's failure:
        // the staging's own error first (the others fail only by a cancel).
        let ahead = Ahead {
            staged: staged?,
            check: check?,
        };
        Ok((metrics?, ahead))
    }

    /// Check, render and write one packing's outputs: those staged while
    /// it was measured (`ahead`, [`Running::measure_packing`]) and the others.
    pub fn write_packing(
        &mut self,
        folder: &str,
        packing: &Packing,
        metrics: &Metrics,
        run: &RunInfo<'_>,
        ahead: Ahead,
    ) -> Result<(), JobError> {
        let start = std::time::Instant::now();
        let written = self.write_confirmed(folder, packing, metrics, run, ahead);
        self.spent(Step::Write, start.elapsed().as_secs_f64());
        written?;
        self.notes
            .extend(picture_notes(folder, packing, run.output, SVG_MAX_BYTES));
        if !grading_kept(metrics.particles, metrics.psd_ks) {
            let advice = match self.plan.job {
                Job::Optimise { .. } => {
                    "a smaller optimise.max_psd_ks, another seed or a larger domain"
                }
                _ => "another seed, a larger domain, or packer.max_deferred = 0",
            };
            self.event(Event::Warning(Warning {
                kind: WarningKind::GradingBent,
                message: format!(
                    "{folder}packing.csv bends the grading: psd_ks {:.4} exceeds {:.4}, the sampling noise of {} sizes + {KS_MARGIN}, so `gapack verify` rejects it (summary.json: grading_kept = false); try {advice}",
                    metrics.psd_ks,
                    ks_limit(metrics.particles),
                    metrics.particles,
                ),
            }));
        }
        Ok(())
    }

    /// [`Running::write_packing`]'s files, untimed: none unless the
    /// packing passes the check ([`confirm`]); a file staged ahead is
    /// removed when `ahead` is dropped.
    fn write_confirmed(
        &mut self,
        folder: &str,
        packing: &Packing,
        metrics: &Metrics,
        run: &RunInfo<'_>,
        ahead: Ahead,
    ) -> Result<(), JobError> {
        let confirmed = confirm(metrics, &ahead.check).map_err(|e| relaxation_hint(e, run))?;
        let files = render_measured_bodies(packing, metrics, run, &confirmed)?;
        for staged in ahead.staged {
            self.files.push(staged.name().to_owned());
            self.pending.push(staged);
        }
        self.write_bodies(folder, files)
    }

    /// Check, render and write the files of a one-packing report (`pack`,
    /// `layer`, `optimise`) as `output` asks, with those staged `ahead`
    /// as its packing was measured: the one place a report becomes its
    /// run's files, during the run and in [`write`].
    pub fn write_report(
        &mut self,
        report: &Report,
        output: &OutputSettings,
        ahead: Ahead,
    ) -> Result<(), JobError> {
        let plan = self.plan;
        let Some((packing, metrics, run)) = report.run_info(plan, output) else {
            return Err(not_one_packing(plan));
        };
        self.write_packing("", packing, metrics, &run, ahead)
    }

    /// Pack `scene` with progress events; a cancel is [`JobError::Cancelled`].
    pub fn pack_scene(
        &mut self,
        scene: &crate::Scene,
        what: &str,
        cancel: &Cancel,
    ) -> Result<(Packing, f64), JobError> {
        self.event(Event::Stage {
            stage: Stage::Pack,
            total: Some(scene.estimated_disks().round() as u64),
        });
        let start = std::time::Instant::now();
        let observer = &mut *self.observer;
        let packing = pack_observed(
            scene,
            &mut |done| {
                observer.event(&Event::Progress {
                    stage: Stage::Pack,
                    done,
                })
            },
            cancel,
        );
        let seconds = start.elapsed().as_secs_f64();
        self.spent(Step::Pack, seconds);
        match packing {
            Ok(mut packing) => {
                single_material(&mut packing, self.config());
                Ok((packing, seconds))
            }
            Err(PackError::Cancelled(_)) => Err(JobError::Cancelled),
            Err(source) => Err(JobError::Pack {
                what: what.to_owned(),
                source,
            }),
        }
    }

    /// Commit the run: its files, its manifest and the removal of the
    /// files an earlier run left that this one did not write (those its
    /// manifest lists, or in a folder without one, any output name of
    /// ours), in one [`Store::commit`]: on failure the folder is as the
    /// earlier run left it. The files of the run, manifest included.
    pub fn finish(&mut self, interrupted: bool) -> Result<Vec<String>, JobError> {
        let start = std::time::Instant::now();
        let files = self.commit(interrupted);
        self.spent(Step::Write, start.elapsed().as_secs_f64());
        files
    }

    /// [`Running::finish`] untimed.
    fn commit(&mut self, interrupted: bool) -> Result<Vec<String>, JobError> {
        let mut files = std::mem::take(&mut self.files);
        files.push(MANIFEST_JSON.to_owned());
        files.sort();
        files.dedup();
        let earlier: Vec<String> = match self.store.read(MANIFEST_JSON)? {
            Some(bytes) => Manifest::from_bytes(&bytes)
                .map(|m| m.files)
                .unwrap_or_default(),
            None => FILE_NAMES.iter().map(|&name| name.to_owned()).collect(),
        };
        let manifest = Manifest::of(self.plan, interrupted, files.clone(), self.notes.clone());
        let bytes = manifest
            .to_bytes()
            .map_err(|e| StoreError::Write(e.into()))?;
        let mut pending = std::mem::take(&mut self.pending);
        pending.push(Staged::bytes(MANIFEST_JSON.to_owned(), bytes));
        // A checkpoint this run does not list belongs to a search that is
        // over or superseded.
        let mut stale: Vec<String> = earlier
            .into_iter()
            .chain([CHECKPOINT_JSON.to_owned()])
            .filter(|f| !files.contains(f))
            .collect();
        stale.sort();
        stale.dedup();
        let written = pending.iter().map(|f| f.name().to_owned()).collect();
        self.store.commit_staged(pending, &stale)?;
        self.event(Event::Written { files: written });
        Ok(files)
    }
}

/// The notes on the pictures of a packing written under `folder`:
/// `packing.svg` holding an image when drawing every disk would exceed
/// `max_bytes` ([`packing_svg_note`]).
fn picture_notes(
    folder: &str,
    packing: &Packing,
    output: &OutputSettings,
    max_bytes: usize,
) -> Vec<String> {
    if !output.wants(Format::Svg) {
        return Vec::new();
    }
    packing_svg_note(packing, max_bytes)
        .map(|note| format!("{folder}{note}"))
        .into_iter()
        .collect()
}

/// A packing's check and its files staged while it was measured
/// ([`Running::measure_packing`]), for [`Running::write_packing`]; the
/// staged files are removed if this is dropped.
pub(super) struct Ahead {
    check: Check,
    staged: Vec<Staged>,
}

/// Bytes a staged stream writes between two polls of its token.
const POLL_BYTES: usize = 1 << 20;

/// Stage each of `streams` in `store` under `folder`, in order; a stream
/// fails once `stop` is raised (polled every [`POLL_BYTES`] bytes).
fn stage_streams(
    store: &mut dyn Store,
    folder: &str,
    streams: Vec<(&'static str, Stream<'_>)>,
    stop: &Cancel,
) -> Result<Vec<Staged>, JobError> {
    streams
        .into_iter()
        .map(|(name, write)| {
            let mut polled = |out: &mut dyn std::io::Write| {
                write(&mut Polled {
                    out,
                    stop,
                    since: POLL_BYTES,
                })
            };
            Ok(store.stage(&format!("{folder}{name}"), &mut polled)?)
        })
        .collect()
}

/// A writer that fails once its token is raised, polled every
/// [`POLL_BYTES`] bytes (the first write included).
struct Polled<'w> {
    out: &'w mut dyn std::io::Write,
    stop: &'w Cancel,
    since: usize,
}

impl std::io::Write for Polled<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.since >= POLL_BYTES {
            self.since = 0;
            if self.stop.is_cancelled() {
                return Err(std::io::Error::other("stopped"));
            }
        }
        let n = self.out.write(buf)?;
        self.since += n;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

/// The refusal to write again the files of a job that writes its own.
fn not_one_packing(plan: &Plan) -> JobError {
    JobError::Input(format!(
        "the {} job's files are written by the job itself; only a pack, layer or optimise outcome is written again",
        plan.kind.name()
    ))
}

/// A generation record as an event.
pub(super) fn generation(stage: Stage, g: &Generation) -> Event {
    Event::Generation {
        stage,
        index: g.index,
        best: g.best.value,
        feasible: g.best.is_feasible(),
        mean: g.mean_value,
        worst: g.worst_value,
        evaluations: g.evaluations,
        seconds: g.seconds,
    }
}

/// With one material, every disk is of it (the files then name it).
pub(super) fn single_material(packing: &mut Packing, config: &Config) {
    if config.materials.len() == 1 && packing.materials.is_empty() {
        packing.materials = vec![0; packing.disks.len()];
    }
}

/// A relaxation packing the write check refuses still overlaps: the
/// error says which keys let the sweeps separate the disks.
fn relaxation_hint(err: OutputError, run: &RunInfo<'_>) -> OutputError {
    match err {
        OutputError::Invalid(faults) if run.scene.packer.method == Method::Relaxation => {
            OutputError::Invalid(format!(
                "{faults}; the relaxation sweeps left these overlaps: raise \
                 packer.relaxation_iterations (more sweeps) or \
                 packer.relaxation_porosity (fewer disks placed)"
            ))
        }
        other => other,
    }
}

impl From<Cancelled> for JobError {
    fn from(_: Cancelled) -> Self {
        JobError::Cancelled
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};
    use crate::jobs::store::tests::listing;

    /// A plan of a 10 mm square writing its table and VTP file, a fresh
    /// folder for its files, and a packing of two disks, overlapping or apart.
    fn staged_run(name: &str, overlapping: bool) -> (Plan, std::path::PathBuf, Packing) {
        let text = "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n\
            [grading]\nconstant = 1.0\n[output]\nformats = [\"csv\", \"vtp\"]\n";
        let plan =
            Plan::load(text, "t.toml", &super::super::Request::new(JobKind::Pack)).expect("plans");
        let dir = std::env::temp_dir().join(format!("gapack-ahead-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch dir");
        let second = if overlapping { 2.5 } else { 5.0 };
        let packing = Packing::of_disks(
            Domain::rectangle(10.0, 10.0).expect("square"),
            vec![Disk::new(2.0, 2.0, 1.0), Disk::new(second, 2.0, 1.0)],
        );
        (plan, dir, packing)
    }

    /// The packing's files are staged while it is measured, but a packing
    /// that then fails the check leaves none of them, nor any other file;
    /// one that passes has them committed with the others.
    #[test]
    fn files_staged_while_measuring_are_committed_only_after_the_check() {
        for overlapping in [true, false] {
            let (plan, dir, packing) = staged_run(&format!("check-{overlapping}"), overlapping);
            let metrics = crate::measure(&packing, &plan.config.scene);
            let mut store = super::super::DirStore::new(&dir);
            let mut silent = super::super::Silent;
            let mut job = Running::new(&plan, &mut silent, &mut store, &Local);
            let output = &plan.config.output;
            let (measured, ahead) = job
                .measure_packing("", &packing, output, &Cancel::new(), |_, _| Ok(metrics))
                .expect("measured and staged");
            // NaN in a small packing's figures: compared as printed.
            assert_eq!(format!("{measured:?}"), format!("{metrics:?}"));
            let staged = listing(&dir);
            assert_eq!(staged.len(), 2, "packing.csv and .vtp staged: {staged:?}");
            assert!(staged.iter().all(|n| n.starts_with('.')), "{staged:?}");
            let run = RunInfo::new(&plan.config.scene, "t.toml", 0.0, output);
            let written = job.write_packing("", &packing, &metrics, &run, ahead);
            if overlapping {
                let err = written.expect_err("the check refuses an overlap");
                let JobError::Output(OutputError::Invalid(faults)) = &err else {
                    panic!("{err:?}");
                };
                assert!(faults.contains("overlapping pairs"), "{faults}");
                drop(job);
                assert_eq!(listing(&dir), Vec::<String>::new(), "nothing left");
            } else {
                written.expect("written");
                job.finish(false).expect("committed");
                assert_eq!(
                    listing(&dir),
                    [
                        "manifest.json",
                        "packing.csv",
                        "packing.vtp",
                        "summary.json"
                    ]
                );
            }
            let _ = std::fs::remove_dir_all(&dir);
        }
    }

    /// A cancel while the packing is measured stops the run with nothing
    /// left of the files staged beside the measures.
    #[test]
    fn a_cancel_while_measuring_leaves_no_staged_file() {
        let (plan, dir, packing) = staged_run("cancel", false);
        let mut store = super::super::DirStore::new(&dir);
        let mut silent = super::super::Silent;
        let mut job = Running::new(&plan, &mut silent, &mut store, &Local);
        let cancel = Cancel::new();
        let done = job.measure_packing("", &packing, &plan.config.output, &cancel, |_, stop| {
            cancel.cancel();
            stop.check()?;
            Ok(crate::measure(&packing, &plan.config.scene))
        });
        assert!(matches!(done, Err(JobError::Cancelled)), "{:?}", done.err());
        assert_eq!(listing(&dir), Vec::<String>::new(), "nothing left");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A huge packing's `packing.svg` is said to hold an image, with its
    /// folder, when the SVG is asked for; the real limit is far above a
    /// small packing.
    #[test]
    fn a_lightened_svg_is_noted_for_the_manifest() {
        let p = Packing::of_disks(
            Domain::rectangle(10.0, 10.0).expect("square"),
            vec![Disk::new(2.0, 2.0, 1.0), Disk::new(5.0, 5.0, 1.0)],
        );
        let all = OutputSettings::default();
        let notes = picture_notes("w/", &p, &all, 100);
        assert_eq!(notes.len(), 1);
        assert!(notes[0].starts_with("w/packing.svg holds packing.png as an image"));
        assert!(picture_notes("w/", &p, &all, SVG_MAX_BYTES).is_empty());
        let png_only = OutputSettings {
            formats: vec![Format::Png],
            ..OutputSettings::default()
        };
        assert!(picture_notes("w/", &p, &png_only, 100).is_empty());
        // The manifest lists the notes, and reads one without any.
        let manifest = Manifest {
            gapack_version: "0".to_owned(),
            job: JobKind::Pack,
            config: "c.toml".to_owned(),
            identity: "i".to_owned(),
            seed: 0,
            interrupted: false,
            files: vec!["packing.svg".to_owned()],
            notes,
        };
        let text = serde_json::to_string(&manifest).expect("json");
        assert!(text.contains(r#""notes":["w/packing.svg holds"#), "{text}");
        let plain = text.replace(r#","notes":["#, r#","x":["#);
        let read = Manifest::from_bytes(plain.as_bytes()).expect("reads");
        assert!(read.notes.is_empty());
    }

    /// Disks packed by a run, handed back as a packing made elsewhere,
    /// measure and write as that run's: the same porosity and count in
    /// `summary.json`; overlapping disks are refused when written.
    #[test]
    fn a_packing_made_elsewhere_is_measured_and_checked_as_a_run() {
        let text = "seed = 2\n[domain]\nshape = \"rectangle\"\nwidth = 12\nheight = 8\n[grading]\nuniform = [1.0, 2.0]\n";
        let plan =
            Plan::load(text, "t.toml", &super::super::Request::new(JobKind::Pack)).expect("plans");
        let mut quiet = plan.clone();
        quiet.config.output.formats.clear();
        let mut store = super::super::MemoryStore::default();
        let ran = run(
            &quiet,
            &mut super::super::Silent,
            &Cancel::new(),
            &mut store,
        )
        .expect("packs");
        let Report::Pack {
            packing, metrics, ..
        } = &ran.report
        else {
            panic!("a pack report")
        };
        let again = Packing::of_disks(packing.domain.clone(), packing.disks.clone());
        let outcome = Outcome::of_packing(&quiet, again, &Cancel::new()).expect("measures");
        let Report::Pack { metrics: found, .. } = &outcome.report else {
            panic!("a pack report")
        };
        assert_eq!(found.particles, metrics.particles);
        assert!((found.porosity - metrics.porosity).abs() < 1e-12);
        let mut out = super::super::MemoryStore::default();
        write(&quiet, &outcome, &quiet.config.output, &mut out).expect("writes");
        assert!(out.files.contains_key(crate::output::SUMMARY_JSON));
        let mut piled = packing.disks.clone();
        piled.push(piled[0]);
        let piled = Outcome::of_packing(
            &quiet,
            Packing::of_disks(packing.domain.clone(), piled),
            &Cancel::new(),
        )
        .expect("measures");
        let mut out = super::super::MemoryStore::default();
        assert!(write(&quiet, &piled, &quiet.config.output, &mut out).is_err());
        let raised = Cancel::new();
        raised.cancel();
        assert!(matches!(
            Outcome::of_packing(
                &quiet,
                Packing::of_disks(packing.domain.clone(), Vec::new()),
                &raised
            ),
            Err(JobError::Cancelled)
        ));
    }
}
