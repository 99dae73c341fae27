//! The jobs every front end runs: one [`Plan`] per job, built from a
//! config by [`Plan::load`] (the config's own job when the [`Request`]
//! names none), and one entry point, [`run`], that talks to the world only
//! through an [`Observer`] (events), a [`Cancel`] token and a [`Store`]
//! (files).
//!
//! A front end translates: its input to a [`Request`] and a plan, events to
//! its medium (progress bars, a stream, callbacks), its stop signal to
//! [`Cancel::cancel`], the [`Outcome`] or [`JobError`] to its answer (a
//! [`Summary`] to keep; the run's [`Manifest`] lists its files). The same
//! plan and seed give the same files whatever the front end.
//!
//! Each job is one file — `pack`, `wells` (the pack job of a `[fracture]`
//! config), `optimise`, `layer`, `compare`, `stability`, `sweep` — holding
//! its plan rules, its run and its words; `registry` names them and
//! dispatches to them; `run` commits what a job made.

mod compare;
mod contract;
mod describe;
mod error;
mod event;
mod largest;
mod layer;
mod optimise;
mod pack;
mod plan;
mod registry;
mod run;
mod stability;
mod store;
mod sweep;
mod wells;

pub use crate::cancel::{Cancel, Cancelled};
pub use contract::{Manifest, Summary};
pub use describe::duration;
pub use error::JobError;
pub use event::{Event, Observer, Silent, Stage, Warning, WarningKind};
pub use largest::Largest;
pub use plan::{Plan, Request, output_dir};
pub use registry::{Job, JobKind, Report};
pub use run::{
    CHECKPOINT_JSON, MANIFEST_JSON, Outcome, Step, StepTime, WellOutcome, run, run_on, write,
};
pub use store::{DirStore, MemoryStore, Staged, Store, StoreError, check_file_name};
pub use sweep::{Study, StudyPoint, StudyRun};
