//! Writing the outputs of a run, as one atomic set.

use std::io::{self, Write};
use std::sync::Arc;

use rayon::prelude::*;

use super::csv::{COMPARE_CSV, STABILITY_CSV, compare_csv, stability_csv};
use super::csv::{
    CONVERGENCE_CSV, PACKING_CSV, PROFILE_CSV, WINDOW_CSV, convergence_csv, profile_csv,
    window_csv, write_packing_csv,
};
use super::error::OutputError;
use super::export::{
    BOUNDARY_VTK, ESYS_GEOMETRY, LAMMPS_CLUMPS_DATA, LAMMPS_DATA, LIGGGHTS_CLUMPS_DATA,
    MERCURY_DATA, PACKING_JSON, PACKING_NPZ, PACKING_VTK, PACKING_VTP, PFC_COMMANDS,
    SUPERQUADRIC_DATA, SUPERQUADRIC_INPUT, YADE_SCRIPT, YADE_TEXT, boundary_vtk,
    esys_geometry_writer, lammps_clumps_data_writer, lammps_data_writer,
    liggghts_clumps_data_writer, mercury_data_writer, packing_json_writer, packing_vtk_writer,
    pfc_commands_writer, superquadric_data_writer, superquadric_input_writer,
    write_packing_npz_with, write_packing_vtp_with, yade_script_writer, yade_text_writer,
};
use super::format::{Format, OutputSettings, ParticleColumn};
use super::json::{FractureSummary, LayeringSummary, OptimiseSummary, SUMMARY_JSON, summary_json};
use super::plot::{
    Asked, AskedShape, ORIENTATION_PNG, ORIENTATION_SVG, SHAPE_PNG, SHAPE_SVG, orientation_rose,
    shape_chart,
};
use super::plot::{
    CompareChart, Drawable, PACKING_PNG, POROSITY_MAP_PNG, POROSITY_MAP_SVG, PSD_PNG, PSD_SVG,
    PsdChart, StabilityChart, convergence_chart, packing_png_coloured, porosity_map_chart,
    profile_chart, psd_chart, psd_chart_of_scene, window_chart,
};
use super::svg::{PACKING_SVG, SVG_MAX_BYTES, packing_svg_note, packing_svg_within, svg_of_png};
use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
#[cfg(test)]
use crate::check::check_particles;
use crate::check::{Check, check_sharing};
use crate::compare::CompareRun;
use crate::ga::Generation;
use crate::geometry::Outline;
use crate::geometry::predicates::OVERLAP_REL;
use crate::grading::Grading;
use crate::layering::{Material, ProfileRow};
use crate::metrics::near::SharedIndex;
use crate::metrics::{Metrics, shape_series, shape_stats};
use crate::packer::Packing;
use crate::scene::{Axis, Profile};
use crate::scene::{Family, ShapeSpec, Spread};
use crate::stability::StabilityRun;

/// File name of the convergence chart.
pub const CONVERGENCE_SVG: &str = "convergence.svg";
/// File name of the convergence chart as an image.
pub const CONVERGENCE_PNG: &str = "convergence.png";
/// File name of the profile chart.
pub const PROFILE_SVG: &str = "profile.svg";
/// File name of the profile chart as an image.
pub const PROFILE_PNG: &str = "profile.png";

/// File name of the comparison chart.
pub const COMPARE_SVG: &str = "compare.svg";
/// File name of the comparison chart as an image.
pub const COMPARE_PNG: &str = "compare.png";

/// The files of a run: a name relative to the run's folder and the bytes.
pub type Files = Vec<(String, Vec<u8>)>;

/// Writes a file's bytes to a stream, once, as the file is written.
pub type Stream<'a> = Box<dyn Fn(&mut dyn Write) -> io::Result<()> + Send + Sync + 'a>;

/// A file's contents: made in memory, or streamed where the file goes (a
/// packing's table, as large as the packing), never held whole.
pub enum Body<'a> {
    /// The bytes, made.
    Bytes(Vec<u8>),
    /// The bytes, to be written to a stream.
    Stream(Stream<'a>),
}

impl Body<'_> {
    /// The bytes, made in memory if streamed; `name` names the file in an
    /// error.
    ///
    /// # Errors
    /// [`OutputError::Write`] naming the file, with the stream's error.
    pub fn into_bytes(self, name: &str) -> Result<Vec<u8>, OutputError> {
        match self {
            Body::Bytes(bytes) => Ok(bytes),
            Body::Stream(write) => {
                let mut bytes = Vec::new();
                write(&mut bytes).map_err(|source| OutputError::Write {
                    path: name.into(),
                    source,
                })?;
                Ok(bytes)
            }
        }
    }
}

impl std::fmt::Debug for Body<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Body::Bytes(bytes) => write!(f, "Bytes({} bytes)", bytes.len()),
            Body::Stream(_) => f.write_str("Stream"),
        }
    }
}

/// The files of a comparison: `compare.csv`, `compare.svg`, `compare.png`.
///
/// # Errors
/// [`OutputError`] when a table or chart cannot be made.
pub fn render_compare(runs: &[CompareRun], has_target: bool) -> Result<Files, OutputError> {
    let chart = CompareChart {
        runs: runs.to_vec(),
        has_target,
    };
    Ok(vec![
        (COMPARE_CSV.to_owned(), compare_csv(runs)?),
        (COMPARE_SVG.to_owned(), chart.to_svg()?.into_bytes()),
        (COMPARE_PNG.to_owned(), chart.to_png()?),
    ])
}

/// File name of the stability map.
pub const STABILITY_SVG: &str = "stability.svg";
/// File name of the stability map as an image.
pub const STABILITY_PNG: &str = "stability.png";

/// The files of a stability sweep: `stability.csv`, `stability.svg`, `stability.png`.
///
/// # Errors
/// [`OutputError`] when a table or chart cannot be made.
pub fn render_stability(runs: &[StabilityRun]) -> Result<Files, OutputError> {
    let chart = StabilityChart {
        runs: runs.to_vec(),
    };
    Ok(vec![
        (STABILITY_CSV.to_owned(), stability_csv(runs)?),
        (STABILITY_SVG.to_owned(), chart.to_svg()?.into_bytes()),
        (STABILITY_PNG.to_owned(), chart.to_png()?),
    ])
}

/// File name of a fracture window's chart.
pub const WINDOW_SVG: &str = "window.svg";
/// File name of a fracture window's chart as an image.
pub const WINDOW_PNG: &str = "window.png";

/// A layering run, as the files show it: its summary block, each
/// material's share of the solid, the fractions per bin, and the profile
/// aimed at along its axis (for the chart).
#[derive(Debug, Clone)]
pub struct LayeringReport<'a> {
    /// The block `summary.json` records.
    pub summary: LayeringSummary,
    /// Share of the solid area of each material.
    pub fractions: &'a [f64],
    /// Target and achieved fractions per bin.
    pub rows: &'a [ProfileRow],
    /// The profile aimed at.
    pub profile: &'a Profile,
    /// The axis the profile runs along.
    pub axis: Axis,
}

/// What a run was, besides its packing and metrics: it decides which files
/// are written and what `summary.json` records. Plain records the jobs layer
/// fills in, so that output knows nothing of how a job ran.
#[derive(Debug, Clone)]
pub struct RunInfo<'a> {
    /// The scene that was packed (seed after any command-line override).
    pub scene: &'a Scene,
    /// The config's path as given, or `config::DEFAULT_ORIGIN`.
    pub config: &'a str,
    /// Wall-clock time of the packing alone, or of the whole search (s).
    pub seconds: f64,
    /// The materials the packing's disks refer to (may be empty).
    pub materials: &'a [Material],
    /// A target-porosity run: its summary and its history (one record per generation).
    pub optimise: Option<(&'a OptimiseSummary, &'a [Generation])>,
    /// A layering run.
    pub layering: Option<LayeringReport<'a>>,
    /// A fracture run: which fracture, how much of it, the window if one was grown.
    pub fracture: Option<FractureSummary<'a>>,
    /// What to write (`[output]`).
    pub output: &'a OutputSettings,
}

impl<'a> RunInfo<'a> {
    /// A plain packing run, without materials, search or layering, writing
    /// what `output` asks for.
    pub fn new(
        scene: &'a Scene,
        config: &'a str,
        seconds: f64,
        output: &'a OutputSettings,
    ) -> Self {
        RunInfo {
            scene,
            config,
            seconds,
            materials: &[],
            optimise: None,
            layering: None,
            fracture: None,
            output,
        }
    }
}

/// The outputs of a run, as `run.output` asks:
/// `summary.json` always; `csv`: `packing.csv` and the run's tables
/// (`convergence.csv` with a search, `profile.csv` with layering,
/// `window.csv` with a fracture window); `json`: `packing.json`; `vtk`:
/// `packing.vtk` and `boundary.vtk`; `vtp`: `packing.vtp`; `npz`:
/// `packing.npz`; `lammps`, `yade`, `pfc`, `mercury`,
/// `esys`: one DEM file each; `svg` and `png`: the packing, its grading
/// against the target (`psd`), its local porosity (`porosity_map`) and the
/// run's charts.
///
/// Everything is rendered in memory, after the packing has passed the
/// independent check ([`confirm`]). A run streams the packing's own files
/// instead ([`packing_streams`]) and makes the others
/// ([`render_measured_bodies`]).
///
/// # Errors
/// [`OutputError::Invalid`] when the packing fails the check, or another
/// [`OutputError`] when a file cannot be made.
#[cfg(test)]
pub(crate) fn render_outputs(
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
) -> Result<Files, OutputError> {
    let check = check_particles(&packing.disks, &packing.grains, &packing.domain, None);
    let confirmed = confirm(metrics, &check)?;
    let streams = packing_streams(packing, run.materials, run.output)?
        .into_iter()
        .map(|(name, write)| (name.to_owned(), Body::Stream(write)));
    streams
        .chain(render_measured_bodies(packing, metrics, run, &confirmed)?)
        .map(|(name, body)| {
            let bytes = body.into_bytes(&name)?;
            Ok((name, bytes))
        })
        .collect()
}

/// The files of a packing that do not read its measures, as `out` asks,
/// each a stream that writes it from the packing where it goes (the store
/// streams it to disk; no copy is held in memory): `packing.csv`,
/// `packing.vtk`, `packing.vtp`, `packing.npz` and every DEM export. They
/// are checked here (an unknown material, particles a format does not
/// take), so that a stream can only fail to write. A run stages them while
/// the packing is measured and checked, and commits them only once
/// [`confirm`] has passed; [`render_measured_bodies`] makes the others.
/// The columns of `[output] per_particle` are computed here, once, for
/// the tables that carry them.
///
/// # Errors
/// [`OutputError`] when a file cannot be made of this packing.
pub fn packing_streams<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    out: &'a OutputSettings,
) -> Result<Vec<(&'static str, Stream<'a>)>, OutputError> {
    let opts = &out.export;
    let mut streams: Vec<(&'static str, Stream<'a>)> = Vec::new();
    // `[output] per_particle`: computed once, shared by the tables.
    let tables = [Format::Csv, Format::Vtp, Format::Npz];
    let columns: Arc<[ParticleColumn]> = if tables.iter().any(|&f| out.wants(f)) {
        out.per_particle
            .iter()
            .map(|&what| ParticleColumn::of(what, packing))
            .collect()
    } else {
        Arc::new([])
    };
    if out.wants(Format::Csv) {
        let columns = Arc::clone(&columns);
        streams.push((
            PACKING_CSV,
            Box::new(move |w| write_packing_csv(packing, materials, &columns, w)),
        ));
    }
    if out.wants(Format::Vtk) {
        let write = packing_vtk_writer(packing, materials, opts)?;
        streams.push((PACKING_VTK, Box::new(write)));
    }
    if out.wants(Format::Vtp) {
        let compression = out.vtp_compression;
        let columns = Arc::clone(&columns);
        streams.push((
            PACKING_VTP,
            Box::new(move |w| write_packing_vtp_with(packing, materials, compression, &columns, w)),
        ));
    }
    if out.wants(Format::Npz) {
        let columns = Arc::clone(&columns);
        streams.push((
            PACKING_NPZ,
            Box::new(move |w| write_packing_npz_with(packing, materials, &columns, w)),
        ));
    }
    if out.wants(Format::Lammps) {
        let write = lammps_data_writer(packing, materials, opts)?;
        streams.push((LAMMPS_DATA, Box::new(write)));
    }
    if out.wants(Format::Yade) {
        if packing.grains.is_empty() {
            let write = yade_text_writer(packing, materials, opts)?;
            streams.push((YADE_TEXT, Box::new(write)));
        } else {
            let write = yade_script_writer(packing, materials, opts)?;
            streams.push((YADE_SCRIPT, Box::new(write)));
        }
    }
    if out.wants(Format::Pfc) {
        let write = pfc_commands_writer(packing, materials, opts)?;
        streams.push((PFC_COMMANDS, Box::new(write)));
    }
    if out.wants(Format::Mercury) {
        let write = mercury_data_writer(packing, materials, opts)?;
        streams.push((MERCURY_DATA, Box::new(write)));
    }
    if out.wants(Format::LiggghtsSuperquadric) {
        let data = superquadric_data_writer(packing, materials, opts)?;
        streams.push((SUPERQUADRIC_DATA, Box::new(data)));
        let input = superquadric_input_writer(packing, materials, opts)?;
        streams.push((SUPERQUADRIC_INPUT, Box::new(input)));
    }
    if out.wants(Format::Esys) {
        let write = esys_geometry_writer(packing, materials, opts)?;
        streams.push((ESYS_GEOMETRY, Box::new(write)));
    }
    if out.wants(Format::LammpsClumps) {
        let write = lammps_clumps_data_writer(packing, materials, opts)?;
        streams.push((LAMMPS_CLUMPS_DATA, Box::new(write)));
    }
    if out.wants(Format::LiggghtsClumps) {
        let write = liggghts_clumps_data_writer(packing, materials, opts)?;
        streams.push((LIGGGHTS_CLUMPS_DATA, Box::new(write)));
    }
    Ok(streams)
}

/// The files of a run ([`RunInfo`]) but those of [`packing_streams`]:
/// `summary.json` and `packing.json` (streamed where it goes, as large as
/// the packing), which read `metrics`, and the pictures, charts and small
/// tables, made on all cores. `_confirmed` proves that the packing and
/// its measures passed the check.
///
/// # Errors
/// [`OutputError`] when a file cannot be made.
pub fn render_measured_bodies<'a>(
    packing: &'a Packing,
    metrics: &'a Metrics,
    run: &'a RunInfo<'a>,
    _confirmed: &Confirmed,
) -> Result<Vec<(String, Body<'a>)>, OutputError> {
    let out = run.output;
    let materials = run.materials;
    let mut tasks = Tasks::new(out);
    tasks.add(SUMMARY_JSON, || summary_json(packing, metrics, run));
    if out.wants(Format::Json) {
        tasks.stream(PACKING_JSON, packing_json_writer(packing, metrics, run)?);
    }
    if out.wants(Format::Vtk) {
        tasks.add(BOUNDARY_VTK, || Ok(boundary_vtk(packing)));
    }
    let diameters = (run.scene.d_min(), run.scene.d_max());
    tasks.packing(packing, materials, diameters, || {
        psd_chart_of_scene(packing, run.scene, materials)
    });
    if !packing.grains.is_empty() {
        tasks.shapes(packing, run.scene.shape.as_ref());
    }
    if let Some((summary, history)) = run.optimise {
        if out.wants(Format::Csv) {
            tasks.add(CONVERGENCE_CSV, || convergence_csv(history));
        }
        tasks.chart((CONVERGENCE_SVG, CONVERGENCE_PNG), move || {
            convergence_chart(
                history,
                summary.target_porosity,
                summary.shape_found.as_ref().map(|s| s.describe()),
            )
        });
    }
    if let Some(layering) = &run.layering {
        if out.wants(Format::Csv) {
            tasks.add(PROFILE_CSV, || profile_csv(layering.rows, materials));
        }
        tasks.chart((PROFILE_SVG, PROFILE_PNG), move || {
            profile_chart(layering.rows, materials, layering.profile, layering.axis)
        });
    }
    if let Some(fracture) = &run.fracture
        && let Some(window) = &fracture.window
    {
        if out.wants(Format::Csv) {
            tasks.add(WINDOW_CSV, || window_csv(window.steps));
        }
        tasks.chart((WINDOW_SVG, WINDOW_PNG), move || {
            window_chart(window.steps, window.tolerance, fracture.name)
        });
    }
    tasks.bodies()
}

/// Largest difference between the summary's porosity and the one the check
/// recomputes from the disks (both sum the same areas, in other orders).
const SUMMARY_AGREEMENT: f64 = 1e-9;

/// Proof that a packing and its measures passed [`confirm`], which
/// [`render_measured_bodies`] asks for.
#[derive(Debug)]
pub struct Confirmed(());

/// The independent check of a packing that [`confirm`] reads, stopped by
/// `cancel`: a pair search of its own, independent of the generator and
/// of [`crate::measure`]'s (a run makes it beside the measures). For
/// disks, the neighbour index comes from `shared`, the one the measure
/// uses, when it is theirs: the disks bucketed by size class and
/// position once for both.
///
/// # Errors
/// [`Cancelled`] when `cancel` stops it.
pub(crate) fn check_packing(
    packing: &Packing,
    shared: &SharedIndex<'_>,
    cancel: &Cancel,
) -> Result<Check, Cancelled> {
    check_sharing(
        &packing.disks,
        &packing.grains,
        &packing.domain,
        shared,
        cancel,
    )
}

/// The check made before any packing is written: `check`, the packing's
/// [`check_packing`], must find no overlap and no disk outside the
/// domain, `metrics` must report no overlap with the wall disks either,
/// and its counts and porosity must match the disks.
///
/// # Errors
/// [`OutputError::Invalid`] naming the faults.
pub fn confirm(metrics: &Metrics, check: &Check) -> Result<Confirmed, OutputError> {
    let c = check;
    let mut faults = Vec::new();
    if c.malformed > 0 {
        faults.push(format!("{} malformed disks", c.malformed));
    }
    if let Some((a, b, depth)) = c.worst_overlap {
        faults.push(format!(
            "{} overlapping pairs, the deepest {depth:.2e} of the radii sum (disks {a} and {b})",
            c.overlaps
        ));
    }
    if let Some((i, by)) = c.worst_outside {
        faults.push(format!(
            "{} disks outside the domain, the farthest by {by:.2e} mm (disk {i})",
            c.outside
        ));
    }
    if metrics.max_overlap > OVERLAP_REL {
        faults.push(format!(
            "an overlap of {:.2e} of the radii sum with a wall disk or between disks",
            metrics.max_overlap
        ));
    }
    if metrics.particles != c.particles {
        faults.push(format!(
            "the summary counts {} disks, the packing holds {}",
            metrics.particles, c.particles
        ));
    }
    let gap = (metrics.porosity - c.porosity).abs();
    if gap.is_nan() || gap > SUMMARY_AGREEMENT {
        faults.push(format!(
            "the summary's porosity {} differs from the disks' {}",
            metrics.porosity, c.porosity
        ));
    }
    if faults.is_empty() {
        Ok(Confirmed(()))
    } else {
        Err(OutputError::Invalid(faults.join("; ")))
    }
}

/// How one file is made.
type Make<'a> = Box<dyn FnOnce() -> Result<Vec<u8>, OutputError> + Send + 'a>;

/// How two files made from one thing (a chart, a raster) are made.
type MakeTwo<'a> = Box<dyn FnOnce() -> Result<[Vec<u8>; 2], OutputError> + Send + 'a>;

/// One file of a run, or two made together: made, or streamed where it goes.
enum Task<'a> {
    Make(Make<'a>),
    Two(&'static str, MakeTwo<'a>),
    Stream(Stream<'a>),
}

/// The files of a run, listed first and made together: each file is
/// independent of the others, so they are rendered on all cores (a run's
/// pictures cost far more than its packing on small scenes), and come out
/// in the order listed whatever the number of threads.
struct Tasks<'a> {
    out: &'a OutputSettings,
    list: Vec<(&'static str, Task<'a>)>,
}

impl<'a> Tasks<'a> {
    fn new(out: &'a OutputSettings) -> Self {
        Tasks {
            out,
            list: Vec::new(),
        }
    }

    /// File `name`, made by `make`.
    fn add(
        &mut self,
        name: &'static str,
        make: impl FnOnce() -> Result<Vec<u8>, OutputError> + Send + 'a,
    ) {
        self.list.push((name, Task::Make(Box::new(make))));
    }

    /// Files `first` and `second`, made together by `make` (in that order
    /// among the files).
    fn add_two(
        &mut self,
        (first, second): (&'static str, &'static str),
        make: impl FnOnce() -> Result<[Vec<u8>; 2], OutputError> + Send + 'a,
    ) {
        self.list.push((first, Task::Two(second, Box::new(make))));
    }

    /// File `name`, streamed by `write` where it goes.
    fn stream(
        &mut self,
        name: &'static str,
        write: impl Fn(&mut dyn Write) -> io::Result<()> + Send + Sync + 'a,
    ) {
        self.list.push((name, Task::Stream(Box::new(write))));
    }

    /// The pictures of a packing, each in the formats asked for: the
    /// packing coloured as `[output] colour` asks (by default by material,
    /// else by diameter over `diameters`; over
    /// [`SVG_MAX_BYTES`] the SVG holds the PNG as an image), its
    /// grading chart (`psd`), its porosity map.
    fn packing(
        &mut self,
        packing: &'a Packing,
        materials: &'a [Material],
        diameters: (f64, f64),
        psd: impl FnOnce() -> PsdChart + Send + 'a,
    ) {
        let colour = self.out.colour;
        let (svg, png) = (self.out.wants(Format::Svg), self.out.wants(Format::Png));
        let note = if svg && png {
            packing_svg_note(packing, SVG_MAX_BYTES)
        } else {
            None
        };
        if let Some(note) = note {
            // The SVG holds the PNG: drawn and encoded once for both.
            self.add_two((PACKING_SVG, PACKING_PNG), move || {
                let png = packing_png_coloured(packing, materials, diameters, colour)?;
                Ok([svg_of_png(&note, &png).into_bytes(), png])
            });
        } else {
            self.add_pictures(packing, materials, diameters);
        }
        self.chart((PSD_SVG, PSD_PNG), psd);
        self.chart((POROSITY_MAP_SVG, POROSITY_MAP_PNG), move || {
            porosity_map_chart(packing)
        });
    }

    /// `packing.svg` and `packing.png`, each if asked for, made apart.
    fn add_pictures(
        &mut self,
        packing: &'a Packing,
        materials: &'a [Material],
        diameters: (f64, f64),
    ) {
        let colour = self.out.colour;
        if self.out.wants(Format::Svg) {
            self.add(PACKING_SVG, move || {
                packing_svg_within(packing, materials, diameters, colour, SVG_MAX_BYTES)
                    .map(String::into_bytes)
            });
        }
        if self.out.wants(Format::Png) {
            self.add(PACKING_PNG, move || {
                packing_png_coloured(packing, materials, diameters, colour)
            });
        }
    }

    /// The shape chart (aspect ratio and sphericity found against what
    /// `spec` asked) and the orientation rose of a packing of grains.
    fn shapes(&mut self, packing: &'a Packing, spec: Option<&'a ShapeSpec>) {
        let series = Arc::new(shape_series(&packing.grains));
        let (a, b) = (series.clone(), series);
        self.chart((SHAPE_SVG, SHAPE_PNG), move || {
            shape_chart(&a.0, &a.1, &asked_shape(spec))
        });
        self.chart((ORIENTATION_SVG, ORIENTATION_PNG), move || {
            let half_turn = packing
                .grains
                .iter()
                .all(|g| matches!(g.outline, Outline::Superellipse { .. }));
            let fabric = shape_stats(&packing.grains, spec).map(|s| s.fabric);
            orientation_rose(
                &b.2,
                half_turn,
                fabric.as_ref().map_or(0.0, |f| f.direction),
                fabric.as_ref().map_or(0.0, |f| f.anisotropy),
            )
        });
    }

    /// The chart `make` builds, as SVG and as PNG under `names`, each if
    /// asked for: built once (a porosity map measures the packing), drawn
    /// twice, all in the file tasks (in parallel with the other files).
    fn chart<C: Drawable + Send + Sync + 'a>(
        &mut self,
        (svg, png): (&'static str, &'static str),
        make: impl FnOnce() -> C + Send + 'a,
    ) {
        match (self.out.wants(Format::Svg), self.out.wants(Format::Png)) {
            (true, true) => self.add_two((svg, png), move || {
                let chart = make();
                let (svg, png) = rayon::join(|| chart.to_svg(), || chart.to_png());
                Ok([svg?.into_bytes(), png?])
            }),
            (true, false) => self.add(svg, move || Ok(make().to_svg()?.into_bytes())),
            (false, true) => self.add(png, move || make().to_png()),
            (false, false) => {}
        }
    }

    /// Make every file listed, in parallel; the first error if any fails.
    fn make(self) -> Result<Files, OutputError> {
        self.bodies()?
            .into_iter()
            .map(|(name, body)| {
                let bytes = body.into_bytes(&name)?;
                Ok((name, bytes))
            })
            .collect()
    }

    /// Make every file listed but those streamed, in parallel, in the order
    /// listed; the first error if any fails.
    fn bodies(self) -> Result<Vec<(String, Body<'a>)>, OutputError> {
        let made: Vec<Vec<(String, Body<'a>)>> = self
            .list
            .into_par_iter()
            .map(|(name, task)| {
                Ok(match task {
                    Task::Make(make) => vec![(name.to_owned(), Body::Bytes(make()?))],
                    Task::Two(second, make) => {
                        let [a, b] = make()?;
                        vec![
                            (name.to_owned(), Body::Bytes(a)),
                            (second.to_owned(), Body::Bytes(b)),
                        ]
                    }
                    Task::Stream(write) => vec![(name.to_owned(), Body::Stream(write))],
                })
            })
            .collect::<Result<_, OutputError>>()?;
        Ok(made.into_iter().flatten().collect())
    }
}

/// The pictures of an existing packing: `packing`, `psd` and
/// `porosity_map`, each as SVG and PNG. `diameters` spans the colour scale;
/// `grading`, if known, is the target of the PSD chart.
///
/// # Errors
/// [`OutputError`] when a picture cannot be made.
pub fn render_pictures(
    packing: &Packing,
    materials: &[Material],
    diameters: (f64, f64),
    grading: Option<&Grading>,
) -> Result<Files, OutputError> {
    let out = OutputSettings {
        formats: vec![Format::Svg, Format::Png],
        ..OutputSettings::default()
    };
    let mut tasks = Tasks::new(&out);
    tasks.packing(packing, materials, diameters, || {
        psd_chart(packing, grading)
    });
    tasks.make()
}

/// What `spec` asked of the aspect ratio (sphericity follows from it and
/// the exponents: not asked), for the shape chart.
fn asked_shape(spec: Option<&ShapeSpec>) -> AskedShape {
    let aspect = match spec.map(|s| &s.family) {
        Some(Family::Superellipse { aspect, .. }) => match aspect {
            Spread::Fixed(v) => Asked::Fixed(*v),
            Spread::Range(lo, hi) => Asked::Range(*lo, *hi),
            Spread::Shares(t) => Asked::Shares(t.clone()),
        },
        _ => Asked::Nothing,
    };
    AskedShape {
        aspect,
        sphericity: Asked::Nothing,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Point};
    use crate::{measure, pack};

    fn config() -> crate::config::Config {
        crate::config::parse(
            "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 1.0\n",
            "t.toml",
        )
        .expect("valid config")
    }

    #[test]
    fn a_valid_packing_is_written() {
        let config = config();
        let packing = pack(&config.scene).expect("packs");
        let metrics = measure(&packing, &config.scene);
        let run = RunInfo::new(&config.scene, "t.toml", 0.0, &config.output);
        let files = render_outputs(&packing, &metrics, &run).expect("rendered");
        assert!(files.iter().any(|(name, _)| name == PACKING_CSV));
    }

    #[test]
    fn an_overlap_or_a_disk_outside_or_a_wrong_summary_is_never_written() {
        let config = config();
        let good = pack(&config.scene).expect("packs");
        let metrics = measure(&good, &config.scene);
        let run = RunInfo::new(&config.scene, "t.toml", 0.0, &config.output);
        let faults = [
            // The second disk moved onto the first.
            {
                let mut p = good.clone();
                p.disks[1].c = p.disks[0].c + Point::new(0.5, 0.0).coords;
                (p, "overlapping pairs")
            },
            // One disk pushed through the wall.
            {
                let mut p = good.clone();
                p.disks[0].c.x = -0.2;
                (p, "outside the domain")
            },
            // One disk more than the summary says.
            {
                let mut p = good.clone();
                p.disks.push(Disk::new(100.0, 100.0, 0.0001));
                (p, "the summary counts")
            },
        ];
        for (packing, expected) in faults {
            let err = render_outputs(&packing, &metrics, &run).expect_err(expected);
            assert!(matches!(err, OutputError::Invalid(_)), "{err}");
            assert!(err.to_string().contains(expected), "{err}");
        }
    }
}
