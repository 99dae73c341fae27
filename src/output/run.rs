//! Writing the outputs of a run, as one atomic set.

use std::fs;
use std::path::{Path, PathBuf};

use super::atomic::write_all_atomic;
use super::csv::{COMPARE_CSV, STABILITY_CSV, compare_csv, stability_csv};
use super::csv::{
    CONVERGENCE_CSV, PACKING_CSV, PROFILE_CSV, WINDOW_CSV, convergence_csv, packing_csv,
    profile_csv, window_csv,
};
use super::error::OutputError;
use super::json::{OptimiseSummary, SUMMARY_JSON, summary_json};
use super::plot::{
    CompareChart, Drawable, StabilityChart, convergence_chart, profile_chart, window_chart,
};
use super::svg::{PACKING_SVG, packing_svg};
use crate::Scene;
use crate::compare::CompareRun;
use crate::fracture::{Extent, Well, Window};
use crate::ga::{Generation, Layered};
use crate::layering::{LayeringSettings, Material};
use crate::packer::{Metrics, Packing};
use crate::stability::StabilityRun;

/// File name of the convergence chart.
pub const CONVERGENCE_SVG: &str = "convergence.svg";
/// File name of the convergence chart as an image.
pub const CONVERGENCE_PNG: &str = "convergence.png";
/// File name of the profile chart.
pub const PROFILE_SVG: &str = "profile.svg";
/// File name of the profile chart as an image.
pub const PROFILE_PNG: &str = "profile.png";

/// File name of the comparison chart.
pub const COMPARE_SVG: &str = "compare.svg";
/// File name of the comparison chart as an image.
pub const COMPARE_PNG: &str = "compare.png";

/// Write a comparison into `dir` atomically: `compare.csv`, `compare.svg`, `compare.png`.
///
/// # Errors
/// [`OutputError`] naming the directory or file and the cause.
pub fn write_compare(dir: &Path, runs: &[CompareRun], has_target: bool) -> Result<(), OutputError> {
    let chart = CompareChart {
        runs: runs.to_vec(),
        has_target,
    };
    let files = [
        (dir.join(COMPARE_CSV), compare_csv(runs)?),
        (dir.join(COMPARE_SVG), chart.to_svg()?.into_bytes()),
        (dir.join(COMPARE_PNG), chart.to_png()?),
    ];
    write_set(dir, &files)
}

/// File name of the stability map.
pub const STABILITY_SVG: &str = "stability.svg";
/// File name of the stability map as an image.
pub const STABILITY_PNG: &str = "stability.png";

/// Write a stability sweep into `dir` atomically: `stability.csv`, `stability.svg`, `stability.png`.
///
/// # Errors
/// [`OutputError`] naming the directory or file and the cause.
pub fn write_stability(dir: &Path, runs: &[StabilityRun]) -> Result<(), OutputError> {
    let chart = StabilityChart {
        runs: runs.to_vec(),
    };
    let files = [
        (dir.join(STABILITY_CSV), stability_csv(runs)?),
        (dir.join(STABILITY_SVG), chart.to_svg()?.into_bytes()),
        (dir.join(STABILITY_PNG), chart.to_png()?),
    ];
    write_set(dir, &files)
}

/// File name of a fracture window's chart.
pub const WINDOW_SVG: &str = "window.svg";
/// File name of a fracture window's chart as an image.
pub const WINDOW_PNG: &str = "window.png";

/// A fracture run: which fracture, how much of it, and the window if one was grown.
#[derive(Debug, Clone, Copy)]
pub struct FractureInfo<'a> {
    /// The fracture (a well of a batch, or the config's one).
    pub well: &'a Well,
    /// What was asked for.
    pub extent: Extent,
    /// The windows grown, in window mode.
    pub window: Option<&'a Window>,
}

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
    /// A fracture run.
    pub fracture: Option<FractureInfo<'a>>,
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
            fracture: None,
        }
    }
}

/// Write the outputs of a run into `dir`: always `packing.csv`,
/// `summary.json` and `packing.svg`; with a search, `convergence.csv`,
/// `convergence.svg` and `convergence.png`; with layering, `profile.csv`,
/// `profile.svg` and `profile.png`; with a fracture window, `window.csv`,
/// `window.svg` and `window.png`.
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
            packing_svg(
                packing,
                run.materials,
                (run.scene.d_min(), run.scene.d_max()),
            )
            .into_bytes(),
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
    if let Some(FractureInfo {
        well,
        extent: Extent::Window { tolerance },
        window: Some(window),
    }) = run.fracture
    {
        let chart = window_chart(&window.steps, tolerance, &well.name);
        files.extend([
            (dir.join(WINDOW_CSV), window_csv(&window.steps)?),
            (dir.join(WINDOW_SVG), chart.to_svg()?.into_bytes()),
            (dir.join(WINDOW_PNG), chart.to_png()?),
        ]);
    }
    write_set(dir, &files)
}

/// Write one table (`wells.csv`) into `dir` atomically, creating `dir` if needed.
///
/// # Errors
/// [`OutputError`] naming the directory or file and the cause.
pub fn write_table(dir: &Path, name: &str, bytes: Vec<u8>) -> Result<(), OutputError> {
    write_set(dir, &[(dir.join(name), bytes)])
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
