//! What a job tells its front end while it runs: typed events to an
//! [`Observer`]. The CLI draws progress bars from them, the service streams
//! them, tests record them.

use serde::{Deserialize, Serialize};

use super::registry::JobKind;

/// A part of a job that reports progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Stage {
    /// Packing one scene; counts sizes drawn.
    Pack,
    /// A batch of wells; counts wells.
    Wells,
    /// The target-porosity search; counts generations.
    Optimise,
    /// The layering search; counts generations.
    Layering,
    /// A comparison; counts runs.
    Compare,
    /// A stability sweep; counts runs.
    Stability,
    /// A parameter study (`gapack sweep`); counts runs.
    Sweep,
}

/// Why a job warns: something the user asked for that it cannot or will not do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum WarningKind {
    /// The config has a table this job does not use.
    IgnoredTable,
    /// The target lies outside the range the initial population spans.
    TargetOutsideInitialRange,
    /// The finished search never reached the target: it lies outside what
    /// the packings that honour the grading were seen to reach, after a
    /// search that ran its course (`ga::PorosityProblem::conclusive`).
    TargetOutOfReach,
    /// The search ended without reaching the target, and could not tell
    /// whether it is out of reach (too small, too short, or timed out).
    TargetNotReached,
    /// A packing written bends the grading beyond the sampling noise that
    /// `gapack verify` allows (`check::ks_limit`).
    GradingBent,
    /// Wells of a `[fracture]` batch that the job does not pack.
    IgnoredWells,
    /// A run estimated at over a million disks or 100 MB of files: said
    /// before it starts, in case a length was given in the wrong unit.
    LargeRun,
    /// A value that reads as if given in another unit (a density in g/cm³).
    Units,
    /// A finished row of the `sweep.csv` a resume reads holds a value no
    /// run gives (a porosity outside [0, 1], a NaN): its run is run again.
    ImpossibleRow,
}

/// A warning: its kind and a message naming config keys (never a front
/// end's flags).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// What kind of warning.
    pub kind: WarningKind,
    /// One sentence for a person.
    pub message: String,
}

/// One event of a running job.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
#[non_exhaustive]
pub enum Event {
    /// The job began.
    Started {
        /// Which job.
        job: JobKind,
    },
    /// A stage began, with how many units it counts when that is known
    /// (for a packing, the sizes it is expected to draw: an estimate).
    Stage {
        /// The stage.
        stage: Stage,
        /// Units expected, if known.
        total: Option<u64>,
    },
    /// Units done within the current stage.
    Progress {
        /// The stage.
        stage: Stage,
        /// Units done so far.
        done: u64,
    },
    /// A generation of a search finished (generation 0 is the initial population).
    Generation {
        /// [`Stage::Optimise`] or [`Stage::Layering`].
        stage: Stage,
        /// 0 for the initial population.
        index: usize,
        /// Best value so far (porosity, or the profile's RMS error).
        best: f64,
        /// Whether the best genome honours the constraints (the grading).
        feasible: bool,
        /// Mean value of the population.
        mean: f64,
        /// Worst value of the population.
        worst: f64,
        /// Distinct genomes evaluated so far.
        evaluations: u64,
        /// Time since the search began (s).
        seconds: f64,
    },
    /// A well of a batch (or the only fracture) was packed and written.
    Well {
        /// Its position in the batch, from 0.
        index: usize,
        /// Its name (the folder it was written to in a batch).
        name: String,
        /// Disks packed.
        particles: usize,
        /// Porosity (of the window's core in window mode).
        porosity: f64,
        /// Time to pack it (s).
        seconds: f64,
    },
    /// A run of a comparison, a stability sweep or a parameter study finished.
    Run {
        /// [`Stage::Compare`], [`Stage::Stability`] or [`Stage::Sweep`].
        stage: Stage,
        /// Its position, from 0.
        index: usize,
        /// The method variant, as the charts name it; a study's run by its name.
        label: String,
    },
    /// Something the user should know.
    Warning(Warning),
    /// The run's files were committed (once, at its end, `manifest.json`
    /// included), names relative to the run's folder.
    Written {
        /// The files.
        files: Vec<String>,
    },
}

/// Receives a job's events, in order, on the thread that runs the job.
pub trait Observer {
    /// One event.
    fn event(&mut self, event: &Event);
}

impl<F: FnMut(&Event)> Observer for F {
    fn event(&mut self, event: &Event) {
        self(event);
    }
}

/// An observer that ignores every event.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Observer for Silent {
    fn event(&mut self, _: &Event) {}
}
