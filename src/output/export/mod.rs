//! Exports for DEM codes and viewers: one file per format, each rendered in
//! memory (the caller writes the set atomically). Only the packed disks are
//! exported, never the wall disks.

mod binary;
mod clumps;
mod common;
mod esys;
mod json;
mod lammps;
mod lammps_clumps;
mod liggghts;
mod mercury;
mod npz;
mod outline;
mod pfc;
mod vtk;
mod vtp;
mod yade;

pub use esys::{ESYS_GEOMETRY, esys_geometry};
pub use json::{PACKING_JSON, packing_json};
pub use lammps::{LAMMPS_DATA, lammps_data};
pub use lammps_clumps::{
    LAMMPS_CLUMPS_DATA, LIGGGHTS_CLUMPS_DATA, lammps_clumps_data, liggghts_clumps_data,
};
pub use liggghts::{SUPERQUADRIC_DATA, SUPERQUADRIC_INPUT, superquadric_data, superquadric_input};
pub use mercury::{MERCURY_DATA, mercury_data};
pub use npz::{PACKING_NPZ, write_packing_npz};
pub use pfc::{PFC_COMMANDS, pfc_commands};
pub use vtk::{BOUNDARY_VTK, PACKING_VTK, boundary_vtk, packing_vtk};
pub use vtp::{PACKING_VTP, write_packing_vtp, write_packing_vtp_with};
pub use yade::{YADE_SCRIPT, YADE_TEXT, yade_script, yade_text};
