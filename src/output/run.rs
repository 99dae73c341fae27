//! Writing the outputs of a run, as one atomic set.

use std::fs;
use std::path::{Path, PathBuf};

use super::atomic::write_all_atomic;
use super::csv::{
    CONVERGENCE_CSV, PACKING_CSV, PROFILE_CSV, convergence_csv, packing_csv, profile_csv,
};
use super::error::OutputError;
use super::json::{OptimiseSummary, SUMMARY_JSON, summary_json};
use super::plot::{convergence_chart, profile_chart};
use super::svg::{PACKING_SVG, packing_svg};
use crate::Scene;
use crate::ga::{Generation, Layered};
use crate::layering::{LayeringSettings, Material};
use crate::packer::{Metrics, Packing};

/// File name of the convergence chart.
pub const CONVERGENCE_SVG: &str = "convergence.svg";
/// File name of the convergence chart as an image.
pub const CONVERGENCE_PNG: &str = "convergence.png";
/// File name of the profile chart.
pub const PROFILE_SVG: &str = "profile.svg";
/// File name of the profile chart as an image.
pub const PROFILE_PNG: &str = "profile.png";

/// What a run was, besides its packing and metrics: it decides which files
/// are written and what `summary.json` records.
#[derive(Debug, Clone, Copy)]
pub struct RunInfo<'a> {
    /// The scene that was packed (seed after any command-line override).
    pub scene: &'a Scene,
    /// The config's path as given, or [`crate::config::DEFAULT_ORIGIN`].
    pub config: &'a str,
    /// Wall-clock time of the packing alone, or of the whole search (s).
    pub seconds: f64,
    /// The materials the packing's disks refer to (may be empty).
    pub materials: &'a [Material],
    /// A target-porosity run: its summary and its history (one record per generation).
    pub optimise: Option<(&'a OptimiseSummary, &'a [Generation])>,
    /// A layering run: its settings and what it gave.
    pub layering: Option<(&'a LayeringSettings, &'a Layered)>,
}

impl<'a> RunInfo<'a> {
    /// A plain packing run, without materials, search or layering.
    pub fn new(scene: &'a Scene, config: &'a str, seconds: f64) -> Self {
        RunInfo {
            scene,
            config,
            seconds,
            materials: &[],
            optimise: None,
            layering: None,
        }
    }
}

/// Write the outputs of a run into `dir`: always `packing.csv`,
/// `summary.json` and `packing.svg`; with a search, `convergence.csv`,
/// `convergence.svg` and `convergence.png`; with layering, `profile.csv`,
/// `profile.svg` and `profile.png`.
///
/// `dir` is created if needed. Everything is rendered in memory first and
/// the files are written as one atomic set: on failure none of them is new,
/// and a directory created for them is removed again.
///
/// # Errors
/// [`OutputError`] naming the directory or file and the cause.
pub fn write_outputs(
    dir: &Path,
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
) -> Result<(), OutputError> {
    let mut files = vec![
        (dir.join(PACKING_CSV), packing_csv(packing, run.materials)?),
        (dir.join(SUMMARY_JSON), summary_json(packing, metrics, run)?),
        (
            dir.join(PACKING_SVG),
            packing_svg(packing, run.scene, run.materials).into_bytes(),
        ),
    ];
    if let Some((summary, history)) = run.optimise {
        let chart = convergence_chart(history, summary.target_porosity);
        files.extend([
            (dir.join(CONVERGENCE_CSV), convergence_csv(history)?),
            (dir.join(CONVERGENCE_SVG), chart.to_svg()?.into_bytes()),
            (dir.join(CONVERGENCE_PNG), chart.to_png()?),
        ]);
    }
    if let Some((settings, layered)) = run.layering {
        let chart = profile_chart(&layered.rows, run.materials, settings);
        files.extend([
            (
                dir.join(PROFILE_CSV),
                profile_csv(&layered.rows, run.materials)?,
            ),
            (dir.join(PROFILE_SVG), chart.to_svg()?.into_bytes()),
            (dir.join(PROFILE_PNG), chart.to_png()?),
        ]);
    }
    write_set(dir, &files)
}

/// Create `dir` if needed and write `files` atomically; a directory created
/// here is removed again if the writing fails.
fn write_set(dir: &Path, files: &[(PathBuf, Vec<u8>)]) -> Result<(), OutputError> {
    let created = !dir.exists();
    fs::create_dir_all(dir).map_err(|source| OutputError::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let written = write_all_atomic(files);
    if written.is_err() && created {
        // Only succeeds if the directory is still empty, as it should be.
        let _ = fs::remove_dir(dir);
    }
    written
}
