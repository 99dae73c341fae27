//! Domains, walls, disks, the outlines of particles that are not disks, and
//! the geometric predicates the packer relies on.

mod disk;
mod domain;
mod grain;
mod inscribed;
mod polygon;
pub mod predicates;

pub use disk::{Disk, Point, bounds_of_disks};
pub use domain::{Domain, GeometryError, ImageShifts, Shape, Wall, WallMode};
pub use grain::{
    Grain, Outline, OutlineError, SUPPORT_REL, Separation, Turned, apart, grain_separation,
    separation,
};
