//! The exports as they were rendered before they were streamed: each file
//! built whole in memory. Kept for the tests only, as the reference the
//! streamed files must equal byte for byte.

mod common;
mod esys;
mod json;
mod lammps;
mod lammps_clumps;
mod liggghts;
mod mercury;
mod pfc;
mod vtk;
mod yade;

use super::{clumps, outline};

pub(super) use esys::esys_geometry;
pub(super) use json::packing_json;
pub(super) use lammps::lammps_data;
pub(super) use lammps_clumps::{lammps_clumps_data, liggghts_clumps_data};
pub(super) use liggghts::{superquadric_data, superquadric_input};
pub(super) use mercury::mercury_data;
pub(super) use pfc::pfc_commands;
pub(super) use vtk::{boundary_vtk, packing_vtk};
pub(super) use yade::{yade_script, yade_text};
