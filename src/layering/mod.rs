//! Functionally graded materials: named materials, target profiles of their
//! area fractions along an axis, the fractions a packing achieves in bins,
//! and a direct (non-GA) assignment of materials to particles.
//!
//! No I/O. The GA refines an assignment in `crate::ga`;
//! the packer's size-graded mode draws sizes from a [`SizeGradient`].

mod baseline;
mod bins;
mod error;
mod material;
mod profile;
mod settings;

pub use baseline::baseline;
pub use bins::{BinAreas, ProfileRow, profile_rows, rms_error};
pub use error::LayeringError;
pub use material::Material;
pub use profile::{Axis, Frame, Profile, SizeGradient};
pub use settings::{LayeringMode, LayeringSettings};
