//! The advancing-front generator (DESIGN §3). STUB: body to come.

use crate::Scene;
use crate::packer::{PackError, Packing};

/// Pack a scene with the advancing-front generator.
pub fn pack(scene: &Scene) -> Result<Packing, PackError> {
    todo!("{scene:?}")
}
