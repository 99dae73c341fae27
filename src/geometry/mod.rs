//! Domains, walls, disks and the geometric predicates the packer relies on.

mod disk;
mod domain;
mod inscribed;
mod polygon;
pub mod predicates;

pub use disk::{Disk, Point, bounds_of_disks};
pub use domain::{Domain, GeometryError, ImageShifts, Shape, Wall, WallMode};
