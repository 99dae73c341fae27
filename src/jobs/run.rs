//! [`run`]: any plan, with an observer, a cancel token and a store.

use std::borrow::Cow;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::error::JobError;
use super::event::{Event, Observer, Stage, Warning, WarningKind};
use super::plan::{Job, JobKind, Plan};
use super::store::{Staged, Store, StoreError};
use super::sweep::{self, Study};
use crate::Method;
use crate::cancel::{Cancel, Cancelled};
use crate::check::{KS_MARGIN, grading_kept, ks_limit};
use crate::compare::{CompareRun, Variant, compare};
use crate::config::Config;
use crate::farm::{self, Farm, Local};
use crate::fracture::{Extent, MM_PER_M, Well, Window, WindowError, WindowStep, settle};
use crate::ga::{
    CONCLUSIVE_POPULATION, Checkpoint, Evolution, Generation, Layered, Limits, OptimiseSettings,
    PorosityProblem, Search, StopReason, Verdict, lay_out, window,
};
use crate::layering::LayeringSettings;
use crate::metrics::{Metrics, measure, measure_cancellable};
use crate::names::ConfigName;
use crate::output::{
    Body, FILE_NAMES, Format, FractureSummary, LayeringDetails, LayeringReport, LayeringSummary,
    OptimiseSummary, OutputError, OutputSettings, RunInfo, SVG_MAX_BYTES, SearchWindow, WELLS_CSV,
    WellRow, WindowSummary, packing_svg_note, render_compare, render_output_bodies,
    render_stability, variant_label, wells_csv,
};
use crate::packer::{PackError, Packing, pack_observed};
use crate::stability::{self, StabilityRun};
use crate::study::{Measure, Row};

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
        summary: OptimiseSummary,
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
    pub window: Option<(Vec<WindowStep>, bool)>,
    /// The packing's measurements (the last window's in window mode).
    pub metrics: Metrics,
}

/// Run `plan`: events to `observer`, stopped by `cancel`, files to `store`.
///
/// # Behavior
/// Every file is made in memory (a packing's after it has passed an
/// independent check; its table streamed to the store instead,
/// [`Store::stage`]) and the run's files go to the store in one
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
    let mut job = Running {
        plan,
        observer,
        store,
        farm,
        files: Vec::new(),
        pending: Vec::new(),
        notes: Vec::new(),
    };
    let done = match &plan.job {
        Job::Pack => job.pack(cancel),
        Job::Wells { batch } => job.wells(*batch, cancel),
        Job::Optimise {
            settings,
            resume,
            checkpoint_every,
        } => job.optimise(settings, *resume, *checkpoint_every, cancel),
        Job::Layer { settings } => job.layer(settings, cancel),
        Job::Compare { target } => job.compare(*target, cancel),
        Job::Stability { time_cap } => job.stability(*time_cap, cancel),
        Job::Sweep { study } => job.sweep(study, cancel),
    };
    let (report, interrupted) = match done {
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
    let mut job = Running {
        plan,
        observer: &mut silent,
        store,
        farm: &Local,
        files: Vec::new(),
        pending: Vec::new(),
        notes: Vec::new(),
    };
    job.write_report(&outcome.report, output)?;
    job.finish(outcome.interrupted)
}

/// One well of a batch packed and drawn on its own: what travels between processes.
#[derive(Serialize, Deserialize)]
struct WellPiece {
    outcome: WellOutcome,
    files: Vec<(String, Vec<u8>)>,
    notes: Vec<String>,
    warnings: Vec<Warning>,
}

/// Why a piece of a batch gave nothing.
#[derive(Serialize, Deserialize)]
enum Halt {
    /// The flag was raised.
    Cancelled,
    /// It failed; the error is made again where it is reported.
    Failed,
}

/// Keeps the warnings a piece of work raises.
#[derive(Default)]
struct Warnings(Vec<Warning>);

impl Observer for Warnings {
    fn event(&mut self, event: &Event) {
        if let Event::Warning(w) = event {
            self.0.push(w.clone());
        }
    }
}

/// Pack and draw one well of a batch, in its folder, away from the job.
fn well_alone(
    plan: &Plan,
    well: &Well,
    extent: Extent,
    cancel: &Cancel,
) -> Result<WellPiece, Halt> {
    let mut warnings = Warnings::default();
    let mut unused = super::MemoryStore::default();
    let mut alone = Running {
        plan,
        observer: &mut warnings,
        store: &mut unused,
        farm: &Local,
        files: Vec::new(),
        pending: Vec::new(),
        notes: Vec::new(),
    };
    let outcome = match alone.well(well, extent, format!("{}/", well.name), cancel) {
        Ok(outcome) => outcome,
        Err(JobError::Cancelled) => return Err(Halt::Cancelled),
        Err(_) => return Err(Halt::Failed),
    };
    // Staged in memory: the bytes travel with the piece.
    let files = alone
        .pending
        .into_iter()
        .map(|file| Ok((file.name().to_owned(), file.into_bytes()?)))
        .collect::<Result<Vec<_>, StoreError>>()
        .map_err(|_| Halt::Failed)?;
    let notes = alone.notes;
    Ok(WellPiece {
        outcome,
        files,
        notes,
        warnings: warnings.0,
    })
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

/// `manifest.json`: the files of the run in a folder, and what run it was.
#[derive(Debug, Serialize, Deserialize)]
struct Manifest {
    gapack_version: String,
    job: JobKind,
    config: String,
    identity: String,
    seed: u64,
    interrupted: bool,
    files: Vec<String>,
    /// What the files do not show as usual, a sentence each.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    notes: Vec<String>,
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

/// A job under way: its plan, its observer, its store, the names of its
/// files so far and the files it has made but not yet committed.
struct Running<'p> {
    plan: &'p Plan,
    observer: &'p mut dyn Observer,
    store: &'p mut dyn Store,
    /// The processes the work is shared out to.
    farm: &'p dyn Farm,
    /// Every file of the run, for the manifest (a checkpoint the search
    /// wrote itself included).
    files: Vec<String>,
    /// The files made or staged, held until [`Running::finish`] commits
    /// them with the manifest in one step: a run that fails leaves none of
    /// them (a staged file is removed when dropped).
    pending: Vec<Staged>,
    /// What the files do not show as usual, for the manifest and the result lines.
    notes: Vec<String>,
}

impl Running<'_> {
    fn config(&self) -> &Config {
        &self.plan.config
    }

    fn event(&mut self, event: Event) {
        self.observer.event(&event);
    }

    /// Add a set of files under `folder` to the run's files, committed by
    /// [`Running::finish`] with all the others or not at all.
    fn write(&mut self, folder: &str, files: Vec<(String, Vec<u8>)>) -> Result<(), JobError> {
        for (name, bytes) in files {
            let name = format!("{folder}{name}");
            self.files.push(name.clone());
            self.pending.push(Staged::bytes(name, bytes));
        }
        Ok(())
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

    /// Check, render and write one packing's outputs.
    fn write_packing(
        &mut self,
        folder: &str,
        packing: &Packing,
        metrics: &Metrics,
        run: &RunInfo<'_>,
    ) -> Result<(), JobError> {
        let files =
            render_output_bodies(packing, metrics, run).map_err(|e| relaxation_hint(e, run))?;
        self.write_bodies(folder, files)?;
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

    /// Check, render and write the files of a one-packing report (`pack`,
    /// `layer`, `optimise`) as `output` asks: the one place a report
    /// becomes its run's files, during the run and in [`write`].
    fn write_report(&mut self, report: &Report, output: &OutputSettings) -> Result<(), JobError> {
        let plan = self.plan;
        let config = &plan.config;
        let (packing, metrics, run) = match report {
            Report::Pack {
                packing,
                metrics,
                seconds,
            } => (
                packing,
                metrics,
                RunInfo {
                    materials: &config.materials,
                    ..RunInfo::new(&config.scene, &plan.origin, *seconds, output)
                },
            ),
            Report::Layer {
                packing,
                metrics,
                layered,
                seconds,
            } => (
                packing,
                metrics,
                RunInfo {
                    materials: &config.materials,
                    layering: config
                        .layering
                        .as_ref()
                        .map(|settings| layering_report(settings, layered)),
                    fracture: whole_fracture(config),
                    ..RunInfo::new(&config.scene, &plan.origin, *seconds, output)
                },
            ),
            Report::Optimise {
                packing,
                scene,
                metrics,
                summary,
                history,
                layered,
                seconds,
                ..
            } => (
                packing,
                metrics,
                RunInfo {
                    materials: &config.materials,
                    optimise: Some((summary, history)),
                    layering: config
                        .layering
                        .as_ref()
                        .zip(layered.as_ref())
                        .map(|(settings, layered)| layering_report(settings, layered)),
                    fracture: whole_fracture(config),
                    ..RunInfo::new(scene, &plan.origin, *seconds, output)
                },
            ),
            _ => {
                return Err(JobError::Input(format!(
                    "the {} job's files are written by the job itself; only a pack, layer or optimise outcome is written again",
                    plan.kind.name()
                )));
            }
        };
        self.write_packing("", packing, metrics, &run)
    }

    /// Pack `scene` with progress events; a cancel is [`JobError::Cancelled`].
    fn pack_scene(
        &mut self,
        scene: &crate::Scene,
        what: &str,
        cancel: &Cancel,
    ) -> Result<(Packing, f64), JobError> {
        self.event(Event::Stage {
            stage: Stage::Pack,
            total: Some(scene.estimated_disks().round() as u64),
        });
        let start = Instant::now();
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

    fn pack(&mut self, cancel: &Cancel) -> Result<(Report, bool), JobError> {
        let plan = self.plan;
        let scene = &plan.config.scene;
        let (packing, seconds) = self.pack_scene(scene, "the scene", cancel)?;
        // A cancel while measuring writes nothing, as one while packing.
        let metrics = measure_cancellable(&packing, scene, cancel)?;
        let report = Report::Pack {
            packing,
            metrics,
            seconds,
        };
        self.write_report(&report, &plan.config.output)?;
        Ok((report, false))
    }

    fn wells(&mut self, batch: bool, cancel: &Cancel) -> Result<(Report, bool), JobError> {
        let plan = self.plan;
        let Some(run) = &plan.config.fracture else {
            return Err(JobError::Input(format!(
                "{}: the config has no [fracture] table",
                plan.origin
            )));
        };
        if batch {
            self.event(Event::Stage {
                stage: Stage::Wells,
                total: Some(run.wells.len() as u64),
            });
        }
        let mut wells = Vec::with_capacity(run.wells.len());
        let mut interrupted = false;
        if batch {
            // The wells are shared out: each packed and drawn on its own,
            // their files gathered here in order.
            let farm = self.farm;
            let mut failed = None;
            farm::waves(
                farm,
                run.wells.len(),
                || cancel.is_raised(),
                |i| well_alone(plan, &run.wells[i], run.extent, cancel),
                |i, piece| match piece {
                    Ok(piece) => {
                        for warning in piece.warnings {
                            self.event(Event::Warning(warning));
                        }
                        self.notes.extend(piece.notes);
                        for (name, bytes) in piece.files {
                            self.files.push(name.clone());
                            self.pending.push(Staged::bytes(name, bytes));
                        }
                        self.told(i, &piece.outcome);
                        wells.push(piece.outcome);
                        true
                    }
                    Err(Halt::Cancelled) => false,
                    Err(Halt::Failed) => {
                        failed = Some(i);
                        false
                    }
                },
            );
            if let Some(i) = failed {
                // The well's own error, from the same (pure) run here.
                let well = &run.wells[i];
                self.well(well, run.extent, format!("{}/", well.name), &Cancel::new())?;
            }
            interrupted = wells.len() < run.wells.len();
        } else {
            for (index, well) in run.wells.iter().enumerate() {
                match self.well(well, run.extent, String::new(), cancel) {
                    Ok(done) => {
                        self.told(index, &done);
                        wells.push(done);
                    }
                    Err(JobError::Cancelled) => {
                        interrupted = true;
                        break;
                    }
                    Err(e) => return Err(e),
                }
            }
        }
        if wells.is_empty() && interrupted {
            return Err(JobError::Cancelled);
        }
        if batch {
            let rows: Vec<WellRow> = wells.iter().map(|w| w.row.clone()).collect();
            let table = wells_csv(&rows)?;
            self.write("", vec![(WELLS_CSV.to_owned(), table)])?;
        }
        Ok((
            Report::Wells {
                wells,
                batch,
                total: run.wells.len(),
            },
            interrupted,
        ))
    }

    /// Tell the front end a well is done.
    fn told(&mut self, index: usize, done: &WellOutcome) {
        self.event(Event::Well {
            index,
            name: done.row.well.clone(),
            particles: done.row.particles,
            porosity: done.row.porosity,
            seconds: done.row.seconds,
        });
    }

    /// Pack one fracture, whole or as a window, and write its outputs under `folder`.
    fn well(
        &mut self,
        well: &Well,
        extent: Extent,
        folder: String,
        cancel: &Cancel,
    ) -> Result<WellOutcome, JobError> {
        let plan = self.plan;
        let (packing, scene, seconds, window) = match extent {
            Extent::Full => {
                let (packing, seconds) = self.pack_scene(&well.scene, &well.name, cancel)?;
                (packing, Cow::Borrowed(&well.scene), seconds, None)
            }
            Extent::Window { tolerance } => {
                let window = match settle(well, tolerance, cancel) {
                    Ok(window) => window,
                    Err(WindowError::Pack(PackError::Cancelled(_))) => {
                        return Err(JobError::Cancelled);
                    }
                    Err(WindowError::Pack(source)) => {
                        return Err(JobError::Pack {
                            what: well.name.clone(),
                            source,
                        });
                    }
                    Err(source) => {
                        return Err(JobError::Window {
                            what: well.name.clone(),
                            source,
                        });
                    }
                };
                let mut packing = window.packing.clone();
                single_material(&mut packing, self.config());
                let seconds = window.seconds;
                (
                    packing,
                    Cow::Owned(window.scene.clone()),
                    seconds,
                    Some(window),
                )
            }
        };
        let metrics = measure(&packing, &scene);
        let run = RunInfo {
            materials: &plan.config.materials,
            fracture: Some(fracture_summary(well, extent, window.as_ref())),
            ..RunInfo::new(&scene, &plan.origin, seconds, &plan.config.output)
        };
        self.write_packing(&folder, &packing, &metrics, &run)?;
        let f = well.fracture;
        let mut row = WellRow {
            well: well.name.clone(),
            width_mm: f.width,
            height_m: f.length / MM_PER_M,
            particles: metrics.particles,
            porosity: metrics.porosity,
            psd_ks: metrics.psd_ks,
            coordination: metrics.coordination,
            seconds,
        };
        if let Some(last) = window.as_ref().and_then(|w| w.last()) {
            row.porosity = last.porosity;
            row.coordination = last.coordination;
        }
        Ok(WellOutcome {
            folder,
            row,
            length: f.length,
            window: window.map(|w| (w.steps, w.settled)),
            metrics,
        })
    }

    fn optimise(
        &mut self,
        settings: &OptimiseSettings,
        resume: bool,
        every: usize,
        cancel: &Cancel,
    ) -> Result<(Report, bool), JobError> {
        let plan = self.plan;
        let config = &plan.config;
        let scene = &config.scene;
        let started = Instant::now();
        // The job's own token: a failed checkpoint stops the search without
        // raising the front end's.
        let stop = cancel.child();
        // A large scene is searched on a window of it, aiming at the target
        // plus the window's extra wall effect (ga::window).
        let window = if window::windowed(scene, settings.window_disks) {
            match window::settle(scene, settings.tolerance, &stop) {
                Ok(w) => Some(w),
                Err(PackError::Cancelled(_)) => return Err(JobError::Cancelled),
                Err(source) => {
                    return Err(JobError::Pack {
                        what: "the scene and its windows".to_owned(),
                        source,
                    });
                }
            }
        } else {
            None
        };
        let offset = window.as_ref().map_or(0.0, |w| w.offset);
        let problem = PorosityProblem::new(
            window.as_ref().map_or(scene, |w| &w.scene),
            OptimiseSettings {
                target_porosity: settings.target_porosity + offset,
                ..*settings
            },
        );
        // The window's porosities as the whole's.
        let whole_range = |r: Option<[f64; 2]>| r.map(|[lo, hi]| [lo - offset, hi - offset]);
        let limits = Limits::from(settings);
        let search = if resume {
            let checkpoint = self.read_checkpoint()?;
            Search::resume_on(&problem, limits, &checkpoint, self.farm)
                .map_err(|e| JobError::Input(format!("{CHECKPOINT_JSON}: {e}")))?
        } else {
            Search::start_on(&problem, limits, plan.seed(), &stop, self.farm)
                .map_err(|_| JobError::Cancelled)?
        };
        let searched_range = span(PorosityProblem::range(search.initial()));
        let initial_range = whole_range(searched_range);
        // A target below every porosity the advancing front packed in
        // generation 0, beyond its tolerance: the densify method packs the
        // drawn sizes at it directly (docs/densify.md), no search needed.
        let dense_route = !resume
            && initial_range
                .is_some_and(|[lo, _]| settings.target_porosity < lo - settings.tolerance);
        if !resume && searched_range.is_none_or(|r| !problem.feasible(r)) {
            self.event(Event::Warning(Warning {
                kind: WarningKind::TargetOutsideInitialRange,
                message: match initial_range {
                    Some([lo, hi]) if dense_route => format!(
                        "optimise.target_porosity = {} lies below the range of the initial population, [{lo:.4}, {hi:.4}]: the densify method packs the drawn sizes at it (docs/densify.md)",
                        settings.target_porosity
                    ),
                    Some([lo, hi]) => format!(
                        "optimise.target_porosity = {} lies outside the range of the initial population, [{lo:.4}, {hi:.4}]; searching beyond it",
                        settings.target_porosity
                    ),
                    None => format!(
                        "optimise.target_porosity = {}: no genome of the initial population could be packed; searching on",
                        settings.target_porosity
                    ),
                },
            }));
        }
        self.event(Event::Stage {
            stage: Stage::Optimise,
            total: Some(if dense_route {
                0
            } else {
                settings.generations as u64
            }),
        });
        let mut save_failed: Option<StoreError> = None;
        let mut saved = false;
        let mut dense = None;
        let evolution = if let Some([lo, hi]) = initial_range.filter(|_| dense_route) {
            let evolution = search.ended(StopReason::Densified);
            for g in &evolution.history {
                self.event(generation(Stage::Optimise, g));
            }
            dense = Some(self.densify_to(settings, [lo, hi], &stop)?);
            evolution
        } else {
            let observer = &mut *self.observer;
            let store = &mut *self.store;
            search.run_saving(
                &stop,
                |g| observer.event(&generation(Stage::Optimise, g)),
                every,
                |checkpoint| {
                    let file = CheckpointFile {
                        gapack_version: env!("CARGO_PKG_VERSION").to_owned(),
                        config: plan.origin.clone(),
                        identity: plan.identity.clone(),
                        seed: Some(plan.seed()),
                        search: Cow::Borrowed(checkpoint),
                    };
                    let written = serde_json::to_vec(&file)
                        .map_err(|e| StoreError::Write(e.into()))
                        .and_then(|bytes| store.write(&[(CHECKPOINT_JSON.to_owned(), bytes)]));
                    match written {
                        Ok(()) => saved = true,
                        Err(e) => {
                            // Stop at the next generation: the best so far is still written.
                            stop.cancel();
                            save_failed.get_or_insert(e);
                        }
                    }
                },
            )
        };
        let mut whole_packs = 0;
        let (verdict, range, warning, packs, best) = match (dense, &window) {
            (
                Some(Dense {
                    verdict,
                    range,
                    warning,
                    packs,
                    best,
                }),
                _,
            ) => (verdict, range, warning, packs, best),
            (None, None) => {
                let verdict = problem.verdict(&evolution);
                let range = span(evolution.explored);
                let warning = verdict_warning(settings, &evolution, verdict, range);
                (verdict, range, warning, 0, None)
            }
            (None, Some(w)) => {
                let searched = problem.verdict(&evolution);
                let range = whole_range(span(evolution.explored));
                let fitted = if searched == Verdict::Interrupted {
                    Err(PackError::Cancelled(Cancelled::Flag))
                } else {
                    window::fit_whole(
                        scene,
                        problem.rules_of(&evolution.genes),
                        w.whole.clone(),
                        [
                            settings.target_porosity,
                            settings.tolerance,
                            settings.max_psd_ks,
                        ],
                        &stop,
                    )
                };
                let whole = match fitted {
                    Ok(whole) => whole,
                    // Interrupted: the whole packed with the scene's own rules is written.
                    Err(PackError::Cancelled(_)) => window::Whole {
                        packing: w.whole.0.clone(),
                        scene: scene.clone(),
                        porosity: w.whole.1,
                        packs: 0,
                    },
                    Err(source) => {
                        return Err(JobError::Pack {
                            what: "the scene with the rules found on its window".to_owned(),
                            source,
                        });
                    }
                };
                whole_packs = whole.packs;
                let ks = crate::metrics::psd_ks(&whole.packing, &whole.scene);
                let hit = (whole.porosity - settings.target_porosity).abs() <= settings.tolerance
                    && ks <= settings.max_psd_ks;
                let verdict = match searched {
                    Verdict::Interrupted => Verdict::Interrupted,
                    _ if hit => Verdict::Reached,
                    Verdict::OutOfReach => Verdict::OutOfReach,
                    _ => Verdict::NotReached,
                };
                let warning = (!matches!(verdict, Verdict::Reached | Verdict::Interrupted)).then(|| Warning {
                    kind: if verdict == Verdict::OutOfReach {
                        WarningKind::TargetOutOfReach
                    } else {
                        WarningKind::TargetNotReached
                    },
                    message: format!(
                        "optimise.target_porosity = {}: searched on a window of {:.0} × {:.0} mm, the whole packed with the rules found there (tuned over {} packs of it) reached porosity {:.4}, psd_ks {:.3} (optimise.tolerance {}, optimise.max_psd_ks {}){}",
                        settings.target_porosity,
                        w.steps.last().map_or(0.0, |s| s.size[0]),
                        w.steps.last().map_or(0.0, |s| s.size[1]),
                        whole.packs,
                        whole.porosity,
                        ks,
                        settings.tolerance,
                        settings.max_psd_ks,
                        if verdict == Verdict::OutOfReach {
                            denser_than(settings.target_porosity, range)
                        } else {
                            ""
                        }
                    ),
                });
                let range = range.map(|[lo, hi]| [lo.min(whole.porosity), hi.max(whole.porosity)]);
                (
                    verdict,
                    range,
                    warning,
                    0,
                    Some((whole.packing, whole.scene)),
                )
            }
        };
        let interrupted = verdict == Verdict::Interrupted;
        let (mut packing, best_scene) = match best {
            Some(best) => best,
            None => {
                let Some(packing) = evolution.outcome else {
                    return Err(JobError::NothingPacked);
                };
                (packing, problem.scene_of(&evolution.genes))
            }
        };
        let layered = config
            .layering
            .as_ref()
            .map(|l| self.lay_out(&packing, l, &stop));
        match &layered {
            Some(l) => packing.materials = l.assignment.clone(),
            None => single_material(&mut packing, config),
        }
        let metrics = measure(&packing, &best_scene);
        if let Some(warning) = warning {
            self.event(Event::Warning(warning));
        }
        let summary = OptimiseSummary {
            target_porosity: settings.target_porosity,
            tolerance: settings.tolerance,
            best_porosity: metrics.porosity,
            error: (metrics.porosity - settings.target_porosity).abs(),
            max_psd_ks: settings.max_psd_ks,
            evaluations: evolution.evaluations + packs + u64::from(whole_packs),
            generations: evolution.history.len().saturating_sub(1),
            population: settings.population,
            feasible: verdict.feasible(),
            verdict: verdict.describe(),
            achievable_range: range,
            initial_range,
            interrupted,
            stop: if interrupted {
                StopReason::Interrupted.describe()
            } else {
                evolution.stop.describe()
            },
            reproducible: !interrupted && evolution.stop.reproducible(),
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
        };
        // The search's own time (summed over resumed runs), or all of this
        // run's where windows or densify packed beside it.
        let seconds = if window.is_some() || evolution.stop == StopReason::Densified {
            started.elapsed().as_secs_f64()
        } else {
            evolution.seconds
        };
        let resumable = interrupted && saved;
        let report = Report::Optimise {
            packing,
            scene: Box::new(best_scene),
            metrics,
            summary,
            history: evolution.history,
            layered,
            resumable,
            seconds,
        };
        self.write_report(&report, &config.output)?;
        if let Some(e) = save_failed {
            return Err(JobError::Checkpoint(e));
        }
        if resumable {
            self.files.push(CHECKPOINT_JSON.to_owned());
        }
        // Otherwise the search is over: the commit removes its checkpoint
        // with the other stale files, only once the outputs are in place.
        Ok((report, interrupted))
    }

    /// Pack the drawn sizes at the target with the densify method; if the
    /// disks jam before it, the densest packing of the true sizes found,
    /// from just above the porosity at which they jammed. `front` is the
    /// range the advancing front packed in generation 0.
    fn densify_to(
        &mut self,
        settings: &OptimiseSettings,
        front: [f64; 2],
        stop: &Cancel,
    ) -> Result<Dense, JobError> {
        let target = settings.target_porosity;
        let at = |porosity: f64| {
            let mut scene = self.plan.config.scene.clone();
            scene.packer.method = Method::Densify;
            scene.packer.densify.porosity = porosity;
            scene
        };
        let interrupted = || Dense {
            verdict: Verdict::Interrupted,
            range: Some(front),
            warning: None,
            packs: 1,
            best: None,
        };
        let scene = at(target);
        let jammed = match pack_observed(&scene, &mut |_| {}, stop) {
            Ok(packing) => {
                let m = measure(&packing, &scene);
                let reached = (m.porosity - target).abs() <= settings.tolerance
                    && m.psd_ks <= settings.max_psd_ks;
                let warning = (!reached).then(|| Warning {
                    kind: WarningKind::TargetNotReached,
                    message: format!(
                        "optimise.target_porosity = {target}: the densify method packed the drawn sizes at porosity {:.4}, psd_ks {:.3} (optimise.tolerance {}, optimise.max_psd_ks {})",
                        m.porosity, m.psd_ks, settings.tolerance, settings.max_psd_ks
                    ),
                });
                return Ok(Dense {
                    verdict: if reached {
                        Verdict::Reached
                    } else {
                        Verdict::NotReached
                    },
                    range: Some([m.porosity.min(front[0]), front[1]]),
                    warning,
                    packs: 1,
                    best: Some((packing, scene)),
                });
            }
            Err(PackError::DensityUnreached { reached, .. }) => reached,
            Err(PackError::Cancelled(_)) => return Ok(interrupted()),
            Err(source) => return Err(dense_failure(source)),
        };
        // Step up from where the disks jammed until the true sizes pack,
        // then halve the last step twice towards the jamming point.
        let step = settings.tolerance.max(DENSE_STEP_MIN);
        for k in 1..=DENSE_STEPS {
            let porosity = jammed + k as f64 * step;
            if porosity >= front[0] {
                break;
            }
            let scene = at(porosity);
            match pack_observed(&scene, &mut |_| {}, stop) {
                Ok(packing) => {
                    let (mut packing, mut scene, mut packs) = (packing, scene, 1 + k as u64);
                    let mut failed = porosity - step;
                    let mut packed = porosity;
                    for _ in 0..DENSE_REFINE {
                        let mid = 0.5 * (failed + packed);
                        let trial = at(mid);
                        packs += 1;
                        match pack_observed(&trial, &mut |_| {}, stop) {
                            Ok(p) => (packing, scene, packed) = (p, trial, mid),
                            Err(PackError::DensityUnreached { .. }) => failed = mid,
                            Err(PackError::Cancelled(_)) => break,
                            Err(source) => return Err(dense_failure(source)),
                        }
                    }
                    let m = measure(&packing, &scene);
                    return Ok(Dense {
                        verdict: Verdict::OutOfReach,
                        range: Some([m.porosity, front[1]]),
                        warning: Some(Warning {
                            kind: WarningKind::TargetOutOfReach,
                            message: format!(
                                "optimise.target_porosity = {target} is below the densest packing found for this grading and domain: the drawn disks jam at porosity {jammed:.4} (densify, their radii scaled down until no overlap is left; jammed polydisperse disks reach about 0.16, O'Hern et al. 2003); the densest packing of the true sizes found, porosity {:.4}, is written",
                                m.porosity
                            ),
                        }),
                        packs,
                        best: Some((packing, scene)),
                    });
                }
                Err(PackError::DensityUnreached { .. }) => {}
                Err(PackError::Cancelled(_)) => return Ok(interrupted()),
                Err(source) => return Err(dense_failure(source)),
            }
        }
        // Nothing between the jamming point and the front's range packed:
        // the front's densest packing of generation 0 stands.
        Ok(Dense {
            verdict: Verdict::OutOfReach,
            range: Some(front),
            warning: Some(Warning {
                kind: WarningKind::TargetOutOfReach,
                message: format!(
                    "optimise.target_porosity = {target} is below the densest packing found for this grading and domain: the drawn disks jam at porosity {jammed:.4} (densify), and no denser packing of the true sizes than the advancing front's {:.4} was found; that one is written",
                    front[0]
                ),
            }),
            packs: 1 + DENSE_STEPS as u64,
            best: None,
        })
    }

    /// The store's checkpoint, if it belongs to this plan.
    fn read_checkpoint(&self) -> Result<Checkpoint, JobError> {
        let place = format!("{} in {}", CHECKPOINT_JSON, self.store.location());
        // Every process resumes from the leading one's checkpoint.
        let read = self.store.read(CHECKPOINT_JSON);
        let shared = farm::share(
            self.farm,
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
        if file.identity != self.plan.identity {
            let seed = file
                .seed
                .map_or_else(|| "unrecorded".to_owned(), |s| s.to_string());
            return Err(JobError::Input(format!(
                "{place} belongs to another run: config {} with seed {seed}; this run is {} with seed {} (the config's text or the seed differ)",
                file.config,
                self.plan.origin,
                self.plan.seed()
            )));
        }
        Ok(file.search.into_owned())
    }

    /// Lay the config's materials out on `packing`, with generation events.
    fn lay_out(
        &mut self,
        packing: &Packing,
        settings: &LayeringSettings,
        stop: &Cancel,
    ) -> Layered {
        self.event(Event::Stage {
            stage: Stage::Layering,
            total: Some(settings.generations as u64),
        });
        let observer = &mut *self.observer;
        lay_out(
            packing,
            settings,
            self.plan.config.materials.len(),
            self.plan.seed(),
            stop,
            self.farm,
            |g| observer.event(&generation(Stage::Layering, g)),
        )
    }

    fn layer(
        &mut self,
        settings: &LayeringSettings,
        cancel: &Cancel,
    ) -> Result<(Report, bool), JobError> {
        let plan = self.plan;
        let config = &plan.config;
        let scene = &config.scene;
        let (mut packing, seconds) = self.pack_scene(scene, "the scene", cancel)?;
        let layered = self.lay_out(&packing, settings, cancel);
        packing.materials = layered.assignment.clone();
        let metrics = measure(&packing, scene);
        let interrupted = layered.stop == Some(StopReason::Interrupted);
        let report = Report::Layer {
            packing,
            metrics,
            layered,
            seconds,
        };
        self.write_report(&report, &config.output)?;
        Ok((report, interrupted))
    }

    fn compare(
        &mut self,
        target: Option<f64>,
        cancel: &Cancel,
    ) -> Result<(Report, bool), JobError> {
        let config = &self.plan.config;
        let settings = &config.compare;
        let variants = Variant::expand(&settings.methods);
        let total = variants.len() * settings.repeats;
        self.event(Event::Stage {
            stage: Stage::Compare,
            total: Some(total as u64),
        });
        let observer = &mut *self.observer;
        let mut index = 0;
        let runs = compare(&config.scene, settings, target, cancel, self.farm, |r| {
            observer.event(&Event::Run {
                stage: Stage::Compare,
                index,
                label: variant_label(&r.variant),
            });
            index += 1;
        })
        .map_err(|source| JobError::Pack {
            what: "the scene".to_owned(),
            source,
        })?;
        let interrupted = runs.len() < total;
        if runs.is_empty() && interrupted {
            return Err(JobError::Cancelled);
        }
        let files = render_compare(&runs, target.is_some())?;
        self.write("", files)?;
        Ok((
            Report::Compare {
                runs,
                variants,
                total,
            },
            interrupted,
        ))
    }

    fn stability(
        &mut self,
        cap: std::time::Duration,
        cancel: &Cancel,
    ) -> Result<(Report, bool), JobError> {
        let config = &self.plan.config;
        let variants = stability::variants(&config.compare.methods);
        let cases = stability::Case::all();
        // Each case over `compare.repeats` seeds from the config's, as compare does.
        let seeds: Vec<u64> = (0..config.compare.repeats as u64)
            .map(|k| config.scene.seed.wrapping_add(k))
            .collect();
        let total = cases.len() * variants.len() * seeds.len();
        self.event(Event::Stage {
            stage: Stage::Stability,
            total: Some(total as u64),
        });
        let observer = &mut *self.observer;
        let mut index = 0;
        let runs = stability::sweep(
            &config.scene,
            (&cases, &variants, &seeds),
            cap,
            cancel,
            self.farm,
            |r: &StabilityRun| {
                observer.event(&Event::Run {
                    stage: Stage::Stability,
                    index,
                    label: format!(
                        "{} {} seed {}",
                        variant_label(&r.variant),
                        r.case.shape.name(),
                        r.seed
                    ),
                });
                index += 1;
            },
        );
        let interrupted = runs.len() < total;
        if runs.is_empty() && interrupted {
            return Err(JobError::Cancelled);
        }
        let files = render_stability(&runs)?;
        self.write("", files)?;
        Ok((
            Report::Stability {
                runs,
                variants,
                total,
            },
            interrupted,
        ))
    }

    /// Run a parameter study (`jobs::sweep`): its own files, each run's
    /// that it keeps, and those of the runs it resumed (left in place).
    fn sweep(&mut self, study: &Study, cancel: &Cancel) -> Result<(Report, bool), JobError> {
        let done = sweep::run(
            self.plan,
            study,
            self.observer,
            cancel,
            self.store,
            self.farm,
        )?;
        self.files.extend(done.kept);
        self.write("", done.files)?;
        Ok((done.report, done.interrupted))
    }

    /// Commit the run: its files, its manifest and the removal of the
    /// files an earlier run left that this one did not write (those its
    /// manifest lists, or in a folder without one, any output name of
    /// ours), in one [`Store::commit`]: on failure the folder is as the
    /// earlier run left it. The files of the run, manifest included.
    fn finish(&mut self, interrupted: bool) -> Result<Vec<String>, JobError> {
        let mut files = std::mem::take(&mut self.files);
        files.push(MANIFEST_JSON.to_owned());
        files.sort();
        files.dedup();
        let earlier: Vec<String> = match self.store.read(MANIFEST_JSON)? {
            Some(bytes) => serde_json::from_slice::<Manifest>(&bytes)
                .map(|m| m.files)
                .unwrap_or_default(),
            None => FILE_NAMES.iter().map(|&name| name.to_owned()).collect(),
        };
        let manifest = Manifest {
            gapack_version: env!("CARGO_PKG_VERSION").to_owned(),
            job: self.plan.kind,
            config: self.plan.origin.clone(),
            identity: self.plan.identity.clone(),
            seed: self.plan.seed(),
            interrupted,
            files: files.clone(),
            notes: self.notes.clone(),
        };
        let bytes =
            serde_json::to_vec_pretty(&manifest).map_err(|e| StoreError::Write(e.into()))?;
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

/// A generation record as an event.
/// A range of values, or none for the empty range `[inf, -inf]` (nothing
/// seen) or anything else that is not one: never an infinite range.
fn span([lo, hi]: [f64; 2]) -> Option<[f64; 2]> {
    (lo.is_finite() && hi.is_finite() && lo <= hi).then_some([lo, hi])
}

/// The densify route's packer failed for another reason than jamming.
fn dense_failure(source: PackError) -> JobError {
    JobError::Pack {
        what: "the scene with the densify method".to_owned(),
        source,
    }
}

/// Tries of the densify route between the jamming point and the front's range.
const DENSE_STEPS: usize = 8;
/// Smallest step of porosity between those tries.
const DENSE_STEP_MIN: f64 = 0.001;
/// Halvings of the last step once the true sizes pack.
const DENSE_REFINE: usize = 2;

/// What the densify route of an optimise found: the verdict on the
/// target, the range measured (its dense end the densest packing of the
/// true sizes found), the warning to give, the packings made, and the
/// packing to write with its scene (`None`: the search's best stands).
struct Dense {
    verdict: Verdict,
    range: Option<[f64; 2]>,
    warning: Option<Warning>,
    packs: u64,
    best: Option<(Packing, crate::Scene)>,
}

/// Where a target lies below every porosity the advancing front packed:
/// the method that packs denser than it, down to the grading's jamming limit.
fn denser_than(target: f64, range: Option<[f64; 2]>) -> &'static str {
    match range {
        Some([lo, _]) if target < lo => {
            "; [packer] method = \"densify\" with densify_porosity packs the drawn sizes denser than the advancing front, down to near the grading's jamming limit (docs/densify.md)"
        }
        _ => "",
    }
}

/// The warning a finished search gives about its target, if any: out of
/// reach only after a conclusive search (`PorosityProblem::conclusive`),
/// else not reached in so many evaluations.
fn verdict_warning<O>(
    settings: &OptimiseSettings,
    evolution: &Evolution<O>,
    verdict: Verdict,
    range: Option<[f64; 2]>,
) -> Option<Warning> {
    let target = settings.target_porosity;
    let generations = evolution.history.len().saturating_sub(1);
    let effort = format!(
        "{} evaluations in {generations} generation{} of {} genomes ({})",
        evolution.evaluations,
        if generations == 1 { "" } else { "s" },
        settings.population,
        evolution.stop.describe()
    );
    let seen = match range {
        Some([lo, hi]) => format!(
            "the packings that honour the grading span [{lo:.4}, {hi:.4}]; the nearest one, {:.4}, is written",
            evolution.best.value
        ),
        None => format!(
            "no packing honoured the grading (optimise.max_psd_ks = {}); the one nearest to it, porosity {:.4}, is written",
            settings.max_psd_ks, evolution.best.value
        ),
    };
    let longer = if settings.population < CONCLUSIVE_POPULATION {
        format!(
            "a longer search may reach it (optimise.generations, optimise.stagnation, optimise.time_limit_s), and a population of at least {CONCLUSIVE_POPULATION} tries the loosest packing rules (optimise.population)"
        )
    } else {
        "a longer search may reach it (optimise.generations, optimise.stagnation, optimise.time_limit_s)".to_owned()
    };
    let (kind, message) = match verdict {
        Verdict::Reached | Verdict::Interrupted => return None,
        Verdict::OutOfReach => (
            WarningKind::TargetOutOfReach,
            format!(
                "optimise.target_porosity = {target} is out of reach: after {effort}, {seen}{}",
                denser_than(target, range)
            ),
        ),
        Verdict::InRange => (
            WarningKind::TargetNotReached,
            format!(
                "optimise.target_porosity = {target} was not reached in {effort}, though it lies within the range seen: {seen}; {longer}"
            ),
        ),
        _ => (
            WarningKind::TargetNotReached,
            format!(
                "optimise.target_porosity = {target} was not reached in {effort}: {seen}; {longer}"
            ),
        ),
    };
    Some(Warning { kind, message })
}

fn generation(stage: Stage, g: &Generation) -> Event {
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
fn single_material(packing: &mut Packing, config: &Config) {
    if config.materials.len() == 1 && packing.materials.is_empty() {
        packing.materials = vec![0; packing.disks.len()];
    }
}

/// The one fracture of a `[fracture]` config that `optimise` or `layer`
/// packs whole (a batch or a window is refused by the config).
fn whole_fracture(config: &Config) -> Option<FractureSummary<'_>> {
    config.fracture.as_ref().and_then(|run| {
        run.wells
            .first()
            .map(|well| fracture_summary(well, Extent::Full, None))
    })
}

/// What the files of a fracture run record: the well, the extent asked
/// for, and the last window grown (with every window tried).
fn fracture_summary<'a>(
    well: &'a Well,
    extent: Extent,
    window: Option<&'a Window>,
) -> FractureSummary<'a> {
    let f = well.fracture;
    let (extent, tolerance) = match extent {
        Extent::Full => ("full", f64::NAN),
        Extent::Window { tolerance } => ("window", tolerance),
    };
    FractureSummary {
        name: &well.name,
        width_mm: f.width,
        height_m: f.length / MM_PER_M,
        tip_width_mm: f.tip_width,
        extent,
        window: window.and_then(|w| {
            let last = w.last()?;
            Some(WindowSummary {
                tolerance,
                settled: w.settled,
                length_mm: last.length,
                length_fraction: last.length / f.length,
                porosity: last.porosity,
                porosity_spread: last.spread,
                coordination: last.coordination,
                seconds: w.seconds,
                steps: &w.steps,
            })
        }),
    }
}

/// What the files of a layering record: its summary block, the shares,
/// the bins and the profile aimed at.
fn layering_report<'a>(settings: &'a LayeringSettings, l: &'a Layered) -> LayeringReport<'a> {
    LayeringReport {
        summary: LayeringSummary {
            profile_rms_error: l.rms,
            baseline_rms_error: l.baseline_rms,
            baseline_seconds: l.baseline_seconds,
            layering: LayeringDetails {
                mode: settings.mode.config_name(),
                axis: settings.axis.config_name(),
                bins: settings.bins,
                profile: settings.profile.name(),
                ga_seconds: l.seconds,
                evaluations: l.evaluations,
                generations: l.generations,
                stop: l.stop.map(StopReason::describe),
                reproducible: l.stop.is_none_or(StopReason::reproducible),
            },
        },
        fractions: &l.fractions,
        rows: &l.rows,
        profile: &settings.profile,
        axis: settings.axis,
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
        let read: Manifest = serde_json::from_str(&plain).expect("reads");
        assert!(read.notes.is_empty());
    }
}
