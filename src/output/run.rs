//! Writing the outputs of one `pack` run.

use std::fs;
use std::path::Path;

use super::atomic::write_all_atomic;
use super::csv::{PACKING_CSV, packing_csv};
use super::error::OutputError;
use super::json::{SUMMARY_JSON, summary_json};
use super::svg::{PACKING_SVG, packing_svg};
use crate::Scene;
use crate::packer::{Metrics, Packing};

/// What a run was, besides its packing and metrics: recorded in `summary.json`.
#[derive(Debug, Clone, Copy)]
pub struct RunInfo<'a> {
    /// The scene that was packed (seed after any command-line override).
    pub scene: &'a Scene,
    /// The config's path as given, or [`crate::config::DEFAULT_ORIGIN`].
    pub config: &'a str,
    /// Wall-clock time of the packing alone (s).
    pub seconds: f64,
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
    let files = [
        (dir.join(PACKING_CSV), packing_csv(packing)?),
        (dir.join(SUMMARY_JSON), summary_json(packing, metrics, run)?),
        (
            dir.join(PACKING_SVG),
            packing_svg(packing, &run.scene.grading).into_bytes(),
        ),
    ];
    let created = !dir.exists();
    fs::create_dir_all(dir).map_err(|source| OutputError::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let written = write_all_atomic(&files);
    if written.is_err() && created {
        // Only succeeds if the directory is still empty, as it should be.
        let _ = fs::remove_dir(dir);
    }
    written
}
