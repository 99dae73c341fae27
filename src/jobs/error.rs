//! Why a job failed. A front end turns [`JobError::is_input`] into its own
//! answer (exit code 2, HTTP 422) and everything else into a failed run.

use crate::config::ConfigError;
use crate::output::OutputError;
use crate::packer::PackError;

use super::store::StoreError;

/// Why a job could not run or finish.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JobError {
    /// The config is not valid.
    #[error(transparent)]
    Config(Box<ConfigError>),
    /// The request does not fit the config (a missing table, a checkpoint
    /// of another run).
    #[error("{0}")]
    Input(String),
    /// A scene could not be packed.
    #[error("cannot pack {what}")]
    Pack {
        /// `the scene`, or the well's name.
        what: String,
        /// The packer's reason.
        source: PackError,
    },
    /// A fracture window's domain could not be built.
    #[error("cannot grow a window of {what}")]
    Window {
        /// The well's name.
        what: String,
        /// Why its window failed.
        source: crate::fracture::WindowError,
    },
    /// No genome of the search could be packed.
    #[error("no genome could be packed: the domain is too small for the grading")]
    NothingPacked,
    /// An output could not be made (the packing failed its check, a chart failed).
    #[error("cannot write the outputs")]
    Output(#[from] OutputError),
    /// The store could not read or write.
    #[error("cannot write the outputs")]
    Store(#[from] StoreError),
    /// The checkpoint could not be saved: the search stopped and its best
    /// packing was written.
    #[error(
        "the checkpoint could not be saved; the search stopped and its best packing is written"
    )]
    Checkpoint(#[source] StoreError),
    /// The job was cancelled before it had anything to keep.
    #[error("cancelled before anything was finished; nothing was written")]
    Cancelled,
}

impl From<ConfigError> for JobError {
    fn from(e: ConfigError) -> Self {
        JobError::Config(Box::new(e))
    }
}

impl JobError {
    /// Whether the fault lies in the input (config, request), not the run.
    pub fn is_input(&self) -> bool {
        matches!(self, JobError::Config(_) | JobError::Input(_))
    }
}
