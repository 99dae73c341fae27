//! gapack: dense 2D disk packings for Discrete Element Method (DEM) simulations.
//!
//! The data flows one way: a TOML [`config`] becomes a validated [`Scene`]
//! (domain, grading, packer settings, seed); [`pack`] turns the scene into a
//! [`Packing`] with zero overlaps; [`measure`] reports porosity, grading
//! fidelity and contact statistics; the binary writes the outputs.
//!
//! Library modules do no file or terminal I/O; only `output` and the binary do.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod cancel;
pub mod check;
pub mod compare;
pub mod config;
pub mod fracture;
pub mod ga;
pub mod geometry;
pub mod grading;
pub mod jobs;
pub mod layering;
pub mod metrics;
mod names;
pub mod output;
pub mod packer;
mod scene;
pub mod stability;

pub use geometry::{Disk, Domain, GeometryError, Point, Shape, Wall, WallMode};
pub use grading::{Basis, Grading, GradingError, Interpolation};
pub use metrics::{Metrics, PorosityMap, measure, porosity_map, psd_ks};
pub use packer::{PackError, PackStats, Packing, pack, pack_observed};
pub use scene::{
    Fill, FrontRules, IndexKind, MAX_DEFERRED, MAX_GAP, Method, PackerSettings, Scene,
};
