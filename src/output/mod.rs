//! Renderers: every output file of a run made in memory (or streamed), for
//! the job's store to write.
//!
//! One file per format; a job renders its run's whole set after an
//! independent check of the packing.

mod csv;
mod digits;
mod error;
mod export;
mod format;
mod json;
mod palette;
mod plot;
mod read;
mod run;
mod svg;
mod sweep_table;

// What the front ends, the benchmarks and the integration tests use, and
// the types those items name; the rest serves the jobs only.
pub use error::OutputError;
pub use export::{
    BOUNDARY_VTK, ESYS_GEOMETRY, LAMMPS_CLUMPS_DATA, LAMMPS_DATA, LIGGGHTS_CLUMPS_DATA,
    MERCURY_DATA, PACKING_NPZ, PACKING_VTK, PACKING_VTP, PFC_COMMANDS, SUPERQUADRIC_DATA,
    SUPERQUADRIC_INPUT, YADE_SCRIPT, YADE_TEXT,
};
pub use export::{
    boundary_vtk, esys_geometry, lammps_clumps_data, lammps_data, liggghts_clumps_data,
    mercury_data, packing_json, packing_vtk, pfc_commands, superquadric_data, superquadric_input,
    write_packing_npz, write_packing_npz_with, write_packing_vtp, write_packing_vtp_with,
    yade_script, yade_text,
};
pub use format::{
    ClumpOptions, ExportOptions, Format, LengthUnit, OutputSettings, ParticleColumn, PerParticle,
    VtpCompression,
};
pub use json::{
    FractureSummary, LayeringDetails, LayeringSummary, OptimiseSummary, SUMMARY_JSON, SearchWindow,
    ShapeFound, WindowSummary, summary_json,
};
pub use plot::{
    Asked, AskedShape, Colouring, Drawable, LineChart, Mark, ORIENTATION_PNG, ORIENTATION_SVG,
    OrientationRose, PorosityMapChart, PsdChart, SHAPE_PNG, SHAPE_SVG, Series, ShapeChart,
    orientation_rose, packing_png, packing_png_coloured, porosity_map_chart, psd_chart,
    shape_chart,
};
pub use read::{PackingTable, ReadError, read_packing_csv};
pub use run::{Files, LayeringReport, RunInfo, render_pictures};
pub use svg::{diameter_range, packing_svg, packing_svg_coloured};
pub use sweep_table::SWEEP_CSV;

pub(crate) use csv::{
    COMPARE_CSV, CONVERGENCE_CSV, PACKING_CSV, PROFILE_CSV, STABILITY_CSV, WELLS_CSV, WINDOW_CSV,
    WellRow, WellShape, wells_csv,
};
pub(crate) use export::PACKING_JSON;
pub(crate) use format::{FORMATS, PER_PARTICLE, UNITS, VTP_COMPRESSIONS};
pub(crate) use plot::{
    COLOURINGS, PACKING_PNG, POROSITY_MAP_PNG, POROSITY_MAP_SVG, PSD_PNG, PSD_SVG, variant_label,
};
pub(crate) use run::{
    Body, COMPARE_PNG, COMPARE_SVG, CONVERGENCE_PNG, CONVERGENCE_SVG, PROFILE_PNG, PROFILE_SVG,
    STABILITY_PNG, STABILITY_SVG, Stream, WINDOW_PNG, WINDOW_SVG, check_packing, confirm,
    packing_streams, render_compare, render_measured_bodies, render_stability,
};
pub(crate) use svg::{PACKING_SVG, SVG_MAX_BYTES, packing_svg_note};
pub(crate) use sweep_table::{SWEEP_PNG, SWEEP_SVG, read_sweep_csv, render_sweep};

/// Every file name a run may write at the top of its folder.
pub(crate) const FILE_NAMES: &[&str] = &[
    SUMMARY_JSON,
    PACKING_CSV,
    PACKING_JSON,
    PACKING_VTK,
    BOUNDARY_VTK,
    PACKING_VTP,
    PACKING_NPZ,
    LAMMPS_DATA,
    YADE_TEXT,
    PFC_COMMANDS,
    MERCURY_DATA,
    SUPERQUADRIC_DATA,
    SUPERQUADRIC_INPUT,
    ESYS_GEOMETRY,
    YADE_SCRIPT,
    LAMMPS_CLUMPS_DATA,
    LIGGGHTS_CLUMPS_DATA,
    PACKING_SVG,
    PACKING_PNG,
    PSD_SVG,
    PSD_PNG,
    POROSITY_MAP_SVG,
    POROSITY_MAP_PNG,
    SHAPE_SVG,
    SHAPE_PNG,
    ORIENTATION_SVG,
    ORIENTATION_PNG,
    CONVERGENCE_CSV,
    CONVERGENCE_SVG,
    CONVERGENCE_PNG,
    PROFILE_CSV,
    PROFILE_SVG,
    PROFILE_PNG,
    WINDOW_CSV,
    WINDOW_SVG,
    WINDOW_PNG,
    WELLS_CSV,
    COMPARE_CSV,
    COMPARE_SVG,
    COMPARE_PNG,
    STABILITY_CSV,
    STABILITY_SVG,
    STABILITY_PNG,
    SWEEP_CSV,
    SWEEP_SVG,
    SWEEP_PNG,
];
