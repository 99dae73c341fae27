//! The jobs every front end runs: one [`Plan`] per job, built from a
//! config by [`Plan::new`], and one entry point, [`run`], that talks to the
//! world only through an [`Observer`] (events), a [`Cancel`] token and a
//! [`Store`] (files).
//!
//! A front end translates: its input to a [`Request`] and a plan, events to
//! its medium (progress bars, a stream, callbacks), its stop signal to
//! [`Cancel::cancel`], the [`Outcome`] or [`JobError`] to its answer. The
//! same plan and seed give the same files whatever the front end.

mod describe;
mod error;
mod event;
mod plan;
mod run;
mod store;
mod sweep;

pub use crate::cancel::{Cancel, Cancelled};
pub use describe::duration;
pub use error::JobError;
pub use event::{Event, Observer, Silent, Stage, Warning, WarningKind};
pub use plan::{Job, JobKind, Plan, Request, output_dir};
pub use run::{CHECKPOINT_JSON, MANIFEST_JSON, Outcome, Report, WellOutcome, run, run_on, write};
pub use store::{DirStore, MemoryStore, Staged, Store, StoreError, check_file_name};
pub use sweep::{Study, StudyPoint, StudyRun};
