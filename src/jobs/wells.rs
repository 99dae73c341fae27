//! The wells of a `[fracture]` config, packed by the pack job: each whole
//! or as a window; a batch (a `wells` list) a folder each and `wells.csv`,
//! its wells shared out to the farm.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use super::describe::{Words, duration, grading_note, memory, pack_line};
use super::error::JobError;
use super::event::{Event, Observer, Stage, Warning};
use super::plan::Plan;
use super::registry::Report;
use super::run::{Running, WellOutcome, single_material};
use super::store::{Staged, StoreError};
use crate::cancel::Cancel;
use crate::config::Config;
use crate::farm::{self, Local};
use crate::fracture::{Extent, MM_PER_M, Well, Window, WindowError, settle};
use crate::metrics::measure_sharing;
use crate::output::{
    FractureSummary, RunInfo, WELLS_CSV, WellRow, WellShape, WindowSummary, wells_csv,
};
use crate::packer::{PackError, estimated_peak_bytes};

/// Pack every well of the config's `[fracture]`: a batch's shared out,
/// each in its folder, with `wells.csv`; a single well in the run's folder.
pub(super) fn run(
    job: &mut Running<'_>,
    batch: bool,
    cancel: &Cancel,
) -> Result<(Report, bool), JobError> {
    let plan = job.plan;
    let Some(run) = &plan.config.fracture else {
        return Err(JobError::Input(format!(
            "{}: the config has no [fracture] table",
            plan.origin
        )));
    };
    if batch {
        job.event(Event::Stage {
            stage: Stage::Wells,
            total: Some(run.wells.len() as u64),
        });
    }
    let mut wells = Vec::with_capacity(run.wells.len());
    let mut interrupted = false;
    if batch {
        // The wells are shared out: each packed and drawn on its own,
        // their files gathered here in order.
        let farm = job.farm;
        let mut failed = None;
        farm::waves(
            farm,
            run.wells.len(),
            || cancel.is_raised(),
            |i| well_alone(plan, &run.wells[i], run.extent, cancel),
            |i, piece| match piece {
                Ok(piece) => {
                    for warning in piece.warnings {
                        job.event(Event::Warning(warning));
                    }
                    job.notes.extend(piece.notes);
                    for (name, bytes) in piece.files {
                        job.files.push(name.clone());
                        job.pending.push(Staged::bytes(name, bytes));
                    }
                    told(job, i, &piece.outcome);
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
            self::well(
                job,
                well,
                run.extent,
                format!("{}/", well.name),
                &Cancel::new(),
            )?;
        }
        interrupted = wells.len() < run.wells.len();
    } else {
        for (index, well) in run.wells.iter().enumerate() {
            match self::well(job, well, run.extent, String::new(), cancel) {
                Ok(done) => {
                    told(job, index, &done);
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
        job.write("", vec![(WELLS_CSV.to_owned(), table)]);
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
    let mut alone = Running::new(plan, &mut warnings, &mut unused, &Local);
    let outcome = match self::well(&mut alone, well, extent, format!("{}/", well.name), cancel) {
        Ok(outcome) => outcome,
        Err(JobError::Cancelled) => return Err(Halt::Cancelled),
        Err(_) => return Err(Halt::Failed),
    };
    // Staged in memory: the bytes travel with the piece.
    let files = std::mem::take(&mut alone.pending)
        .into_iter()
        .map(|file| Ok((file.name().to_owned(), file.into_bytes()?)))
        .collect::<Result<Vec<_>, StoreError>>()
        .map_err(|_| Halt::Failed)?;
    let notes = std::mem::take(&mut alone.notes);
    drop(alone);
    Ok(WellPiece {
        outcome,
        files,
        notes,
        warnings: warnings.0,
    })
}

/// Tell the front end a well is done.
fn told(job: &mut Running<'_>, index: usize, done: &WellOutcome) {
    job.event(Event::Well {
        index,
        name: done.row.well.clone(),
        particles: done.row.particles,
        porosity: done.row.porosity,
        seconds: done.row.seconds,
    });
}

/// Pack one fracture, whole or as a window, and write its outputs under `folder`.
fn well(
    job: &mut Running<'_>,
    well: &Well,
    extent: Extent,
    folder: String,
    cancel: &Cancel,
) -> Result<WellOutcome, JobError> {
    let plan = job.plan;
    let (packing, scene, seconds, window) = match extent {
        Extent::Full => {
            let (packing, seconds) = job.pack_scene(&well.scene, &well.name, cancel)?;
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
            single_material(&mut packing, job.config());
            let seconds = window.seconds;
            (
                packing,
                Cow::Owned(window.scene.clone()),
                seconds,
                Some(window),
            )
        }
    };
    // A well packed is finished: a cancel now no longer stops it.
    let (metrics, ahead) = job.measure_packing(
        &folder,
        &packing,
        &plan.config.output,
        &Cancel::new(),
        |shared, stop| measure_sharing(&packing, &scene, Some(shared), stop),
    )?;
    let run = RunInfo {
        materials: &plan.config.materials,
        fracture: Some(fracture_summary(well, extent, window.as_ref())),
        ..RunInfo::new(&scene, &plan.origin, seconds, &plan.config.output)
    };
    job.write_packing(&folder, &packing, &metrics, &run, ahead)?;
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
        shape: metrics.shapes.as_ref().map(WellShape::of),
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

/// The one fracture of a `[fracture]` config that `optimise` or `layer`
/// packs whole (a batch or a window is refused by the config).
pub(super) fn whole_fracture(config: &Config) -> Option<FractureSummary<'_>> {
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

/// `job: pack: 3 fractures (a folder each, and wells.csv), packed whole`,
/// and a batch's memory: its wells are packed a few at a time, one per thread.
pub(super) fn words(plan: &Plan, batch: bool) -> Words {
    let config = &plan.config;
    let n = config.fracture.as_ref().map_or(0, |f| f.wells.len());
    let mut words = Words::new(format!(
        "job: pack: {n} fracture{}{}, {}",
        if n == 1 { "" } else { "s" },
        if batch {
            " (a folder each, and wells.csv)"
        } else {
            ""
        },
        match plan.extent() {
            Some(Extent::Window { tolerance }) =>
                format!("representative windows (porosity tolerance {tolerance})"),
            _ => "packed whole".to_owned(),
        }
    ));
    if let (true, Some(run)) = (batch, &config.fracture) {
        let at_once = rayon::current_num_threads().min(run.wells.len());
        let mut peaks: Vec<f64> = run
            .wells
            .iter()
            .map(|w| estimated_peak_bytes(&w.scene))
            .collect();
        peaks.sort_by(|a, b| b.total_cmp(a));
        words.memory = Some(format!(
            "batch memory: about {} ({at_once} wells at once, one per thread)",
            memory(peaks.iter().take(at_once).sum())
        ));
    }
    words
}

/// A line per well (its window, or its packing), and a batch's `wells.csv`.
pub(super) fn lines(at: &str, wells: &[WellOutcome], batch: bool, total: usize) -> Vec<String> {
    let mut lines = Vec::new();
    for w in wells {
        let dir = format!("{at}/{}", w.folder.trim_end_matches('/'));
        let dir = dir.trim_end_matches('/');
        let line = match &w.window {
            Some((steps, settled)) if !steps.is_empty() => {
                let last = &steps[steps.len() - 1];
                format!(
                    "{dir}: window {:.1} mm of {:.0} mm ({:.1}%), porosity {:.4} ± {:.4}, coordination {:.2}, {} {}, {} windows in {}{}{}",
                    last.length,
                    w.length,
                    100.0 * last.length / w.length,
                    last.porosity,
                    last.spread,
                    last.coordination,
                    last.particles,
                    if w.row.shape.is_some() {
                        "particles"
                    } else {
                        "disks"
                    },
                    steps.len(),
                    duration(w.row.seconds),
                    if *settled {
                        ""
                    } else {
                        " (not settled: the whole fracture was packed)"
                    },
                    grading_note(&w.metrics)
                )
            }
            _ => pack_line(dir, &w.metrics, w.row.seconds),
        };
        lines.push(match &w.row.shape {
            None => line,
            Some(shape) => format!(
                "{line}; particles' mean sphericity {:.3}, roundness {:.3}, aspect {:.2}, fabric anisotropy {:.2}",
                shape.sphericity, shape.roundness, shape.aspect, shape.anisotropy
            ),
        });
    }
    if batch {
        lines.push(format!(
            "{at}/wells.csv: {} wells in {}{}",
            wells.len(),
            duration(wells.iter().map(|w| w.row.seconds).sum()),
            if wells.len() < total {
                format!(" (interrupted: {} of {total} wells)", wells.len())
            } else {
                String::new()
            }
        ));
    }
    lines
}
