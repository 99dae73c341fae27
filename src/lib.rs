//! gapack: dense 2D disk packings for Discrete Element Method (DEM) simulations.
//!
//! The data flows one way: a TOML [`config`] becomes a validated [`Scene`]
//! (domain, grading, packer settings, seed); [`pack`] turns the scene into a
//! [`Packing`] with zero overlaps; [`measure`] reports porosity, grading
//! fidelity and contact statistics; [`check`] verifies a packing; [`jobs`]
//! runs any job (pack, optimise, layer, compare, stability, sweep) for every front
//! end, and [`output`] renders its files as bytes.
//!
//! The core types live at the crate root; the jobs, the search ([`ga`]) and
//! the renderers keep their own namespaces. Library modules do no file or
//! terminal I/O: jobs hand their files to a [`jobs::Store`].
//!
//! ```
//! use gapack::{Basis, Domain, Grading, Scene, check, pack};
//!
//! let domain = Domain::rectangle(10.0, 10.0).unwrap();
//! let grading = Grading::uniform(0.5, 1.0, Basis::Number).unwrap();
//! let scene = Scene::new(domain, grading).with_seed(7);
//! let packing = pack(&scene).unwrap();
//! assert!(check(&packing.disks, &scene.domain, Some(&scene.grading)).valid());
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod cancel;
mod check;
pub mod compare;
pub mod config;
pub mod farm;
pub mod fracture;
pub mod ga;
mod geometry;
mod grading;
pub mod jobs;
pub mod layering;
mod metrics;
mod names;
pub mod output;
mod packer;
mod scene;
pub mod stability;
pub mod study;

pub use cancel::{Cancel, Cancelled};
pub use check::{
    Check, GradingCheck, KS_MARGIN, MIN_GRADING_DISKS, check, check_cancellable, check_particles,
    check_particles_sized, grading_kept, ks_limit,
};
pub use geometry::predicates::OVERLAP_REL;
pub use geometry::{
    Disk, Domain, GeometryError, Grain, ImageShifts, Outline, OutlineError, Point, SUPPORT_REL,
    Separation, Shape, Turned, Wall, WallMode, bounds_of_disks, grain_separation, separation,
};
pub use grading::{
    Basis, Grading, GradingError, Interpolation, THESIS_TABLE_3_1, THESIS_TABLE_3_4,
};
pub use metrics::meshless;
pub use metrics::{
    AskedFamily, AskedOrientation, Fabric, Figures, H6Stats, Metrics, PorosityMap, ShapeAsked,
    ShapeStats, Zone, enclosing_radius, grading_sizes, inscribed_radius, long_axis, mean_sd,
    measure, porosity, porosity_map, psd_ks, roundness, shape_stats, solid_area, sphericity, zones,
};
pub use packer::index::{Grid, MxQuadtree, SpatialIndex};
pub use packer::strips;
pub use packer::{
    DensifyTrace, PEAK_BYTES_PER_DISK, PEAK_BYTES_PER_GRAIN, PackError, PackStats, Packing,
    WORK_PER_DISK, densify_traced, estimated_peak_bytes, pack, pack_observed, size_count,
    work_budget,
};
pub use scene::{
    Axis, Densify, Drawer, Family, Fill, FrontRules, IndexKind, Limits, MAX_DEFERRED, MAX_GAP,
    Method, Orientation, PackerSettings, Profile, Proppant, Relaxation, SHAPE_STREAM, Scene,
    ShapeSpec, SizeGradient, SizeMeasure, Spread, Strips, template_vertices,
};
