//! Functionally graded materials: named materials, target profiles of their
//! area fractions along an axis, the fractions a packing achieves in bins,
//! and a direct (non-GA) assignment of materials to particles.
//!
//! No I/O. The GA refines an assignment (`ga::lay_out`); the packer's
//! size-graded mode draws sizes from a [`SizeGradient`]. The profile's
//! geometry ([`Axis`], [`Frame`], [`Profile`], [`SizeGradient`]) is the
//! scene's, re-exported here.

mod baseline;
mod bins;
mod error;
mod material;
mod profile;
mod settings;

pub use crate::scene::{Axis, Frame, Profile, SizeGradient};
pub use baseline::baseline;
pub use bins::{BinAreas, ProfileRow, profile_rows, rms_error};
pub use error::LayeringError;
pub use material::Material;
pub use settings::{LayeringMode, LayeringSettings, StopRules};
