//! Writing the outputs of a run, as one atomic set.

use std::fs;
use std::path::Path;

use std::path::PathBuf;

use super::atomic::write_all_atomic;
use super::csv::{CONVERGENCE_CSV, PACKING_CSV, convergence_csv, packing_csv};
use super::error::OutputError;
use super::json::{OptimiseSummary, SUMMARY_JSON, summary_json};
use super::plot::convergence_chart;
use super::svg::{PACKING_SVG, packing_svg};
use crate::Scene;
use crate::ga::Generation;
use crate::packer::{Metrics, Packing};

/// File names of the convergence chart.
pub const CONVERGENCE_SVG: &str = "convergence.svg";
/// File name of the convergence chart as an image.
pub const CONVERGENCE_PNG: &str = "convergence.png";

/// What a run was, besides its packing and metrics: recorded in `summary.json`.
#[derive(Debug, Clone, Copy)]
pub struct RunInfo<'a> {
    /// The scene that was packed (seed after any command-line override).
    pub scene: &'a Scene,
    /// The config's path as given, or [`crate::config::DEFAULT_ORIGIN`].
    pub config: &'a str,
    /// Wall-clock time of the packing alone, or of the whole search (s).
    pub seconds: f64,
    /// What a target-porosity run adds to the summary.
    pub optimise: Option<&'a OptimiseSummary>,
}

/// Write `packing.csv`, `summary.json` and `packing.svg` into `dir`.
///
/// `dir` is created if needed. Everything is rendered in memory first and
/// the three files are written as one atomic set: on failure none of them is
/// new, and a directory created for them is removed again.
///
/// # Errors
/// [`OutputError`] naming the directory or file and the I/O cause.
pub fn write_pack_outputs(
    dir: &Path,
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
) -> Result<(), OutputError> {
    let files = pack_files(dir, packing, metrics, run)?;
    write_set(dir, &files)
}

/// Write the outputs of `pack` and, beside them, `convergence.csv`,
/// `convergence.svg` and `convergence.png` for the search `history`, as one
/// atomic set (see [`write_pack_outputs`]).
///
/// # Errors
/// [`OutputError`] naming the directory or file and the cause.
pub fn write_optimise_outputs(
    dir: &Path,
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
    history: &[Generation],
    target: f64,
) -> Result<(), OutputError> {
    let mut files = pack_files(dir, packing, metrics, run)?;
    let chart = convergence_chart(history, target);
    files.extend([
        (dir.join(CONVERGENCE_CSV), convergence_csv(history)?),
        (dir.join(CONVERGENCE_SVG), chart.to_svg()?.into_bytes()),
        (dir.join(CONVERGENCE_PNG), chart.to_png()?),
    ]);
    write_set(dir, &files)
}

/// `packing.csv`, `summary.json` and `packing.svg`, rendered.
fn pack_files(
    dir: &Path,
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
) -> Result<Vec<(PathBuf, Vec<u8>)>, OutputError> {
    Ok(vec![
        (dir.join(PACKING_CSV), packing_csv(packing)?),
        (dir.join(SUMMARY_JSON), summary_json(packing, metrics, run)?),
        (
            dir.join(PACKING_SVG),
            packing_svg(packing, &run.scene.grading).into_bytes(),
        ),
    ])
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
