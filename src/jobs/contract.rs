//! What the jobs hand their front ends in typed form: the
//! [`Manifest`] every run writes (`manifest.json`), and the [`Summary`] of
//! a finished job a front end keeps or shows.

use serde::{Deserialize, Serialize};

use super::plan::Plan;
use super::registry::{JobKind, Report};
use super::run::Outcome;
use crate::metrics::ShapeStats;

/// `manifest.json`: the files of the run in a folder, and what run it was.
/// Written by every run ([`super::run`]); read back with
/// [`Manifest::from_bytes`] by a resumed study, by the next run in the same
/// folder (which removes the files it lists and does not write again), and
/// by a front end that serves the files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Manifest {
    /// gapack version that wrote it.
    pub gapack_version: String,
    /// Which job ran.
    pub job: JobKind,
    /// The config's origin (a path, or the embedded scene's label).
    pub config: String,
    /// The plan's identity: the config's text and the seed.
    pub identity: String,
    /// The seed the run used.
    pub seed: u64,
    /// Whether the run was cut short and holds only what it finished.
    pub interrupted: bool,
    /// Every file of the run, this one included, sorted.
    pub files: Vec<String>,
    /// What the files do not show as usual, a sentence each.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

impl Manifest {
    /// The manifest of a run of `plan`.
    pub(super) fn of(
        plan: &Plan,
        interrupted: bool,
        files: Vec<String>,
        notes: Vec<String>,
    ) -> Manifest {
        Manifest {
            gapack_version: env!("CARGO_PKG_VERSION").to_owned(),
            job: plan.kind,
            config: plan.origin.clone(),
            identity: plan.identity.clone(),
            seed: plan.seed(),
            interrupted,
            files,
            notes,
        }
    }

    /// A `manifest.json` read back.
    ///
    /// # Errors
    /// The JSON error when `bytes` are not a manifest.
    pub fn from_bytes(bytes: &[u8]) -> Result<Manifest, serde_json::Error> {
        serde_json::from_slice(bytes)
    }

    /// The bytes of `manifest.json` (pretty JSON, as every run writes it).
    ///
    /// # Errors
    /// The JSON error (none for a manifest of strings and numbers).
    pub fn to_bytes(&self) -> Result<Vec<u8>, serde_json::Error> {
        serde_json::to_vec_pretty(self)
    }
}

/// A finished job in brief, as a front end keeps it (the service stores
/// one per job): its result lines, its files, and the figures of its
/// packing. The fields a job has no figure for are left out of its JSON;
/// they are in alphabetical order, so its JSON is the same whether written
/// from this struct or from a JSON map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Summary {
    /// `optimise`: the porosity of the best packing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best_porosity: Option<f64>,
    /// `optimise`: packings made by the search.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub evaluations: Option<u64>,
    /// Every file of the run, `manifest.json` included.
    pub files: Vec<String>,
    /// `optimise`: generations run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generations: Option<usize>,
    /// Whether the job was cancelled and holds only what it finished.
    pub interrupted: bool,
    /// The result in words ([`Outcome::lines`]).
    pub lines: Vec<String>,
    /// Particles that are not disks (`pack`, `layer`, `optimise`): their
    /// shape measures, as `summary.json`'s `particle_shape`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particle_shape: Option<ShapeStats>,
    /// Disks of the packing (of every well, for a `[fracture]` run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<usize>,
    /// The packing's porosity (`pack`, `layer`, `optimise`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub porosity: Option<f64>,
    /// `optimise`: the porosity aimed at.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_porosity: Option<f64>,
}

impl Summary {
    /// The summary of `outcome`, its lines naming the run's folder as
    /// `location` (`&outcome.location` to keep them as they are; a server
    /// shows its own name for the folder, never its path).
    pub fn of(outcome: &Outcome, location: &str) -> Summary {
        let lines = outcome
            .lines()
            .iter()
            .map(|l| l.replace(&outcome.location, location))
            .collect();
        let mut summary = Summary {
            best_porosity: None,
            evaluations: None,
            files: outcome.files.clone(),
            generations: None,
            interrupted: outcome.interrupted,
            lines,
            particle_shape: None,
            particles: None,
            porosity: None,
            target_porosity: None,
        };
        let metrics = match &outcome.report {
            Report::Pack { metrics, .. } | Report::Layer { metrics, .. } => Some(metrics),
            Report::Optimise {
                metrics,
                summary: s,
                ..
            } => {
                summary.generations = Some(s.generations);
                summary.evaluations = Some(s.evaluations);
                summary.best_porosity = Some(s.best_porosity);
                summary.target_porosity = Some(s.target_porosity);
                Some(metrics)
            }
            Report::Wells { wells, .. } => {
                summary.particles = Some(wells.iter().map(|w| w.row.particles).sum());
                None
            }
            _ => None,
        };
        if let Some(m) = metrics {
            summary.particles = Some(m.particles);
            summary.porosity = Some(m.porosity);
            summary.particle_shape = m.shapes;
        }
        summary
    }

    /// The summary as JSON.
    ///
    /// # Errors
    /// The JSON error (none for a summary of strings and numbers).
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// A summary read back from its JSON.
    ///
    /// # Errors
    /// The JSON error when `text` is not a summary.
    pub fn from_json(text: &str) -> Result<Summary, serde_json::Error> {
        serde_json::from_str(text)
    }
}
