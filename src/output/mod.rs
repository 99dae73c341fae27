//! Renderers: every output file of a run made in memory, and the atomic
//! writes a file store uses to put a set of them in place.
//!
//! One file per format; [`render_outputs`] makes a run's whole set after an
//! independent check of the packing, and [`write_all_atomic`] writes a set
//! (all temporary files first, then all renames), so a failure leaves no new
//! output behind.

mod atomic;
mod csv;
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

pub use atomic::{TempFile, commit_atomic, commit_with_temps, write_all_atomic, write_atomic};
pub use csv::{
    COMPARE_CSV, CONVERGENCE_CSV, PACKING_CSV, PROFILE_CSV, STABILITY_CSV, WELLS_CSV, WINDOW_CSV,
    WellRow, compare_csv, convergence_csv, packing_csv, profile_csv, stability_csv, wells_csv,
    window_csv, write_packing_csv,
};
pub use error::OutputError;
pub use export::{
    BOUNDARY_VTK, ESYS_GEOMETRY, LAMMPS_DATA, MERCURY_DATA, PACKING_JSON, PACKING_VTK,
    PFC_COMMANDS, YADE_TEXT, boundary_vtk, esys_geometry, lammps_data, mercury_data, packing_json,
    packing_vtk, pfc_commands, yade_text,
};
pub use format::{ExportOptions, Format, LengthUnit, OutputSettings};
pub(crate) use format::{FORMATS, UNITS};
pub use json::{
    FractureSummary, LayeringDetails, LayeringSummary, OptimiseSummary, SUMMARY_JSON, SearchWindow,
    WindowSummary, summary_json,
};
pub use plot::{
    CompareChart, Drawable, LineChart, Mark, PACKING_PNG, POROSITY_MAP_PNG, POROSITY_MAP_SVG,
    PSD_PNG, PSD_SVG, PorosityMapChart, PsdChart, Series, StabilityChart, SweepChart,
    convergence_chart, packing_png, porosity_map_chart, profile_chart, psd_chart, variant_label,
    window_chart,
};
pub use read::{PackingTable, ReadError, read_packing_csv};
pub use run::{
    Body, COMPARE_PNG, COMPARE_SVG, CONVERGENCE_PNG, CONVERGENCE_SVG, Files, LayeringReport,
    PROFILE_PNG, PROFILE_SVG, RunInfo, STABILITY_PNG, STABILITY_SVG, Stream, WINDOW_PNG,
    WINDOW_SVG, render_compare, render_output_bodies, render_outputs, render_pictures,
    render_stability,
};
pub use svg::{
    PACKING_SVG, SVG_MAX_BYTES, diameter_range, packing_svg, packing_svg_note, packing_svg_within,
};
pub use sweep_table::{SWEEP_CSV, SWEEP_PNG, SWEEP_SVG, read_sweep_csv, render_sweep, sweep_csv};

/// Every file name a run may write at the top of its folder.
pub const FILE_NAMES: &[&str] = &[
    SUMMARY_JSON,
    PACKING_CSV,
    PACKING_JSON,
    PACKING_VTK,
    BOUNDARY_VTK,
    LAMMPS_DATA,
    YADE_TEXT,
    PFC_COMMANDS,
    MERCURY_DATA,
    ESYS_GEOMETRY,
    PACKING_SVG,
    PACKING_PNG,
    PSD_SVG,
    PSD_PNG,
    POROSITY_MAP_SVG,
    POROSITY_MAP_PNG,
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
