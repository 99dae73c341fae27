//! Why an output could not be written.
//!
//! `Display` gives this layer's part of the message; the I/O cause is the
//! error's `source()` (printed after it by the CLI).

use std::io;
use std::path::PathBuf;

/// Why an output could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The output directory could not be created.
    #[error("cannot create directory {}", .path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// A file could not be written (its temporary file was removed).
    #[error("cannot write {}", .path.display())]
    Write {
        /// The file that was to be written.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// A written temporary file could not be renamed into place.
    #[error("cannot replace {}", .path.display())]
    Rename {
        /// The file that was to be replaced.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// A file could not be removed (set aside until the set it belongs to
    /// was written whole; put back on failure).
    #[error("cannot remove {}", .path.display())]
    Remove {
        /// The file that was to be removed.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// The CSV writer failed.
    #[error("cannot format CSV")]
    Csv(#[from] ::csv::Error),
    /// The JSON serialiser failed.
    #[error("cannot format JSON")]
    Json(#[from] serde_json::Error),
    /// The packing failed the independent check made before writing it
    /// (overlaps, disks outside the domain, or a summary that does not match
    /// the disks): nothing was written.
    #[error("the packing fails the check before writing, nothing was written: {0}")]
    Invalid(String),
    /// A chart could not be drawn or encoded.
    #[error("cannot draw a chart: {0}")]
    Plot(String),
    /// A packed disk refers to a material that is not in the list given to
    /// an export (the file would name a type its reader does not know).
    #[error("disk {disk} has material index {material}, but only {count} materials are defined")]
    UnknownMaterial {
        /// Index of the disk in placement order (from 0).
        disk: usize,
        /// Its material index.
        material: u16,
        /// How many materials were given.
        count: usize,
    },
    /// A format cannot hold the packing's particles (their family, or
    /// their shape's parameters, have no counterpart in it).
    #[error("{format}: {reason}")]
    Unsupported {
        /// The file's format, as `[output] formats` names it.
        format: &'static str,
        /// Why, and what to use instead.
        reason: String,
    },
}
