//! `gapack verify` and `gapack plot`: look at an existing packing without
//! packing anything.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::Args;
use gapack::config::Config;
use gapack::config::ConfigName;
use gapack::fracture::{Extent, Well};
use gapack::layering::Material;
use gapack::output::{
    BOUNDARY_VTK, ESYS_GEOMETRY, Format, LAMMPS_CLUMPS_DATA, LAMMPS_DATA, LIGGGHTS_CLUMPS_DATA,
    MERCURY_DATA, PACKING_NPZ, PACKING_VTK, PACKING_VTP, PFC_COMMANDS, PackingTable, SUMMARY_JSON,
    SUPERQUADRIC_DATA, SUPERQUADRIC_INPUT, YADE_SCRIPT, YADE_TEXT, boundary_vtk, diameter_range,
    esys_geometry, lammps_clumps_data, lammps_data, liggghts_clumps_data, mercury_data,
    packing_vtk, pfc_commands, read_packing_csv, render_pictures, superquadric_data,
    superquadric_input, write_packing_npz, write_packing_vtp, yade_script, yade_text,
};
use gapack::{Check, GradingCheck, MIN_GRADING_DISKS, OVERLAP_REL, check, check_particles_sized};
use gapack::{Domain, Packing, Point, Scene, bounds_of_disks, grading_sizes, psd_ks};
use serde::Serialize;

use super::{Failure, load_config, print_line, report};
use gapack::jobs::{DirStore, Store};

/// `gapack verify` arguments.
#[derive(Args)]
pub struct VerifyArgs {
    /// The packing: a CSV with columns x, y and r (or radius, d, diameter), material optional.
    packing: PathBuf,
    /// The config whose domain and grading the packing must honour.
    #[arg(long, value_name = "CONFIG")]
    config: PathBuf,
    /// In a fracture batch, the well the packing belongs to [default: the only well].
    #[arg(long, value_name = "NAME")]
    well: Option<String>,
    /// No findings printed: the exit code alone says (0 valid, 1 not).
    #[arg(long)]
    quiet: bool,
    /// Print the verdict and what was checked as one JSON object on stdout
    /// (docs/usage.md); the exit code is the same.
    #[arg(long, conflicts_with = "quiet")]
    json: bool,
}

/// `gapack export` arguments.
#[derive(Args)]
pub struct ExportArgs {
    /// The packing: a CSV as `gapack verify` reads it (with its particle
    /// columns when the particles are not disks).
    packing: PathBuf,
    /// The config whose domain, materials and [output] formats, density and
    /// units the files follow.
    #[arg(long, value_name = "CONFIG")]
    config: PathBuf,
    /// In a fracture batch, the well the packing belongs to [default: the only well].
    #[arg(long, value_name = "NAME")]
    well: Option<String>,
    /// Output directory [default: the packing's own directory].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// `gapack plot` arguments.
#[derive(Args)]
pub struct PlotArgs {
    /// The packing: a CSV with columns x, y and r (or radius, d, diameter), material optional.
    packing: PathBuf,
    /// The config it was packed from: its domain outline, colour scale and
    /// target grading [default: the disks' bounding box, their own sizes, no target].
    #[arg(long, value_name = "CONFIG")]
    config: Option<PathBuf>,
    /// In a fracture batch, the well the packing belongs to [default: the only well].
    #[arg(long, value_name = "NAME")]
    well: Option<String>,
    /// Output directory [default: the packing's own directory].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// No result line.
    #[arg(long)]
    quiet: bool,
}

/// `gapack verify`: read the packing, check it against the config's domain
/// and grading, print the findings; exit 1 when it fails.
pub fn run_verify(args: &VerifyArgs) -> Result<(), Failure> {
    let (config, origin) = load_config(&args.config, true)?;
    let (scene, domain_note) = packed_scene(&config, args.well.as_deref(), &origin, &args.packing)?;
    let scene = scene.as_ref();
    let table = read_table(&args.packing)?;
    let graded = scene.gradient.is_some();
    let grading = (!graded).then_some(&scene.grading);
    let mut result = if table.grains.is_empty() {
        check(&table.disks, &scene.domain, grading)
    } else {
        // Certified apart and inside by support functions; the grading on
        // the size it measures (the config's [shape] size, else the
        // equivalent diameter).
        let packing = Packing::of_disks(scene.domain.clone(), table.disks.clone())
            .with_grains(table.grains.clone());
        let sizes = grading_sizes(&packing, scene);
        check_particles_sized(&table.disks, &table.grains, &scene.domain, grading, &sizes)
    };
    if graded {
        // Size-graded: each material against its own curve.
        result.grading = GradingCheck::of(result.particles - result.malformed, || {
            psd_ks(&packing_of(&table, scene, &config), scene)
        });
    }
    let mut lines = findings(&result, &table, scene.domain.is_periodic());
    lines.splice(0..0, domain_note);
    let verdict = Verdict::of(&result, args.packing.display().to_string(), origin, lines);
    if args.json {
        print_line(serde_json::to_value(&verdict).map_err(|e| Failure::Run(e.into()))?);
    } else if !args.quiet {
        print_line(format_args!(
            "{} against {}: {}",
            verdict.packing, verdict.config, verdict.verdict
        ));
        for line in &verdict.findings {
            print_line(format_args!("  {line}"));
        }
    }
    if !result.valid() {
        return Err(Failure::Run(anyhow!(
            "{}: the packing is not valid: {}",
            args.packing.display(),
            why_invalid(&result, &table, scene.domain.is_periodic())
        )));
    }
    if !result.grading_kept() {
        return Err(Failure::Run(anyhow!(
            "{}: the sizes do not follow the config's grading",
            args.packing.display()
        )));
    }
    Ok(())
}

/// What `gapack verify` says of a packing: the verdict line and the
/// findings under it, and with `--json` the figures they are made of.
#[derive(Serialize)]
struct Verdict {
    /// The packing's CSV as named on the command line.
    packing: String,
    /// The config as named on the command line.
    config: String,
    /// `valid`, `valid, grading not checked` or `FAILED`.
    verdict: &'static str,
    /// No malformed disk, no overlap, none outside, and the grading kept
    /// (or not checked): exit code 0.
    valid: bool,
    /// Particles in the table.
    particles: usize,
    /// With a non-finite position or a size that is not positive.
    malformed: usize,
    /// Pairs overlapping beyond the tolerance (a lower bound when
    /// `overlaps_complete` is false).
    overlaps: usize,
    /// Whether `overlaps` counts every overlapping pair.
    overlaps_complete: bool,
    /// The deepest overlap beyond the tolerance, relative to the radii
    /// sum; null without one.
    deepest_overlap: Option<f64>,
    /// Disks reaching outside the domain (centres outside a periodic cell).
    outside: usize,
    /// How far the farthest one reaches outside (mm); null without one.
    farthest_outside: Option<f64>,
    /// Domain area (mm²).
    domain_area: f64,
    /// Area of the particles (mm²).
    solid_area: f64,
    /// 1 − solid_area / domain_area.
    porosity: f64,
    /// `measured`, `too few disks` or `not asked` (size-graded packings are
    /// measured against each material's curve).
    grading: &'static str,
    /// KS distance of the sizes to the grading; null when not measured.
    psd_ks: Option<f64>,
    /// The largest KS distance sampling noise explains here.
    ks_limit: f64,
    /// `psd_ks` ≤ `ks_limit`, or the grading not measured.
    grading_kept: bool,
    /// The lines printed under the verdict.
    findings: Vec<String>,
}

impl Verdict {
    fn of(c: &Check, packing: String, config: String, findings: Vec<String>) -> Verdict {
        let verdict = match (c.valid() && c.grading_kept(), c.grading) {
            (false, _) => "FAILED",
            (true, GradingCheck::TooFewDisks(_)) => "valid, grading not checked",
            (true, _) => "valid",
        };
        let grading = match c.grading {
            GradingCheck::Measured(_) => "measured",
            GradingCheck::TooFewDisks(_) => "too few disks",
            _ => "not asked",
        };
        Verdict {
            packing,
            config,
            verdict,
            valid: c.valid() && c.grading_kept(),
            particles: c.particles,
            malformed: c.malformed,
            overlaps: c.overlaps,
            overlaps_complete: c.overlaps_complete,
            deepest_overlap: c.worst_overlap.map(|(_, _, depth)| depth),
            outside: c.outside,
            farthest_outside: c.worst_outside.map(|(_, by)| by),
            domain_area: c.domain_area,
            solid_area: c.solid_area,
            porosity: c.porosity,
            grading,
            psd_ks: c.grading.ks(),
            ks_limit: c.ks_limit,
            grading_kept: c.grading_kept(),
            findings,
        }
    }
}

/// `gapack export`: an existing packing in the DEM and viewer formats the
/// config's `[output] formats` name (vtk, vtp, npz, lammps, liggghts-superquadric,
/// mercury, yade, pfc, esys; csv, json and the pictures belong to a run or
/// to `gapack plot`, and are skipped with a note).
pub fn run_export(args: &ExportArgs) -> Result<(), Failure> {
    let (config, origin) = load_config(&args.config, true)?;
    let (scene, _) = packed_scene(&config, args.well.as_deref(), &origin, &args.packing)?;
    let table = read_table(&args.packing)?;
    let packing = packing_of(&table, scene.as_ref(), &config);
    let materials = if table.materials.is_empty() {
        &[][..]
    } else {
        &config.materials[..]
    };
    let opts = &config.output.export;
    let dir = match &args.out {
        Some(dir) => dir.clone(),
        None => args
            .packing
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf(),
    };
    let mut files: Vec<(&str, Vec<u8>)> = Vec::new();
    let run = |r: Result<Vec<u8>, gapack::output::OutputError>| {
        r.map_err(|e| Failure::Run(anyhow!("{}: {e}", args.packing.display())))
    };
    // A binary export, made in memory like the others.
    let binary =
        |write: fn(&Packing, &[Material], &mut dyn std::io::Write) -> std::io::Result<()>| {
            let mut bytes = Vec::new();
            write(&packing, materials, &mut bytes)
                .map(|()| bytes)
                .map_err(|e| Failure::Run(anyhow!("{}: {e}", args.packing.display())))
        };
    for format in &config.output.formats {
        match format {
            Format::Vtp => files.push((PACKING_VTP, binary(write_packing_vtp)?)),
            Format::Npz => files.push((PACKING_NPZ, binary(write_packing_npz)?)),
            Format::Vtk => {
                files.push((PACKING_VTK, run(packing_vtk(&packing, materials, opts))?));
                files.push((BOUNDARY_VTK, boundary_vtk(&packing)));
            }
            Format::Lammps => {
                files.push((LAMMPS_DATA, run(lammps_data(&packing, materials, opts))?));
            }
            Format::LiggghtsSuperquadric => {
                files.push((
                    SUPERQUADRIC_DATA,
                    run(superquadric_data(&packing, materials, opts))?,
                ));
                files.push((
                    SUPERQUADRIC_INPUT,
                    run(superquadric_input(&packing, materials, opts))?,
                ));
            }
            Format::Mercury => {
                files.push((MERCURY_DATA, run(mercury_data(&packing, materials, opts))?));
            }
            Format::Yade if packing.grains.is_empty() => {
                files.push((YADE_TEXT, run(yade_text(&packing, materials, opts))?));
            }
            Format::Yade => {
                files.push((YADE_SCRIPT, run(yade_script(&packing, materials, opts))?));
            }
            Format::LammpsClumps => {
                files.push((
                    LAMMPS_CLUMPS_DATA,
                    run(lammps_clumps_data(&packing, materials, opts))?,
                ));
            }
            Format::LiggghtsClumps => {
                files.push((
                    LIGGGHTS_CLUMPS_DATA,
                    run(liggghts_clumps_data(&packing, materials, opts))?,
                ));
            }
            Format::Pfc => {
                files.push((PFC_COMMANDS, run(pfc_commands(&packing, materials, opts))?));
            }
            Format::Esys => {
                files.push((
                    ESYS_GEOMETRY,
                    run(esys_geometry(&packing, materials, opts))?,
                ));
            }
            other => print_line(format_args!(
                "  {}: skipped (a run's file, not an export)",
                other.config_name()
            )),
        }
    }
    // Written all at once, each file atomically.
    let named: Vec<(String, Vec<u8>)> = files
        .into_iter()
        .map(|(name, bytes)| (name.to_owned(), bytes))
        .collect();
    DirStore::new(&dir)
        .write(&named)
        .with_context(|| format!("cannot write the exports in {}", dir.display()))
        .map_err(Failure::Run)?;
    for (name, _) in &named {
        print_line(format_args!("{}", dir.join(name).display()));
    }
    Ok(())
}

/// `gapack plot`: the pictures of an existing packing (`packing`, `psd`,
/// `porosity_map`, as SVG and PNG), next to it unless `--out` says otherwise.
pub fn run_plot(args: &PlotArgs) -> Result<(), Failure> {
    let table = read_table(&args.packing)?;
    let loaded = match &args.config {
        // Nothing is packed: the [limits] do not apply.
        Some(path) => Some(load_config(path, true)?),
        None => None,
    };
    let scene = match &loaded {
        Some((config, origin)) => {
            Some(packed_scene(config, args.well.as_deref(), origin, &args.packing)?.0)
        }
        None => None,
    };
    let (packing, materials, diameters, grading) = match (&loaded, &scene) {
        (Some((config, _)), Some(scene)) => {
            let packing = packing_of(&table, scene, config);
            let named = packing
                .materials
                .iter()
                .all(|&m| usize::from(m) < config.materials.len());
            let (packing, materials) = if named {
                (packing, config.materials.clone())
            } else {
                // Names the config does not list: colour by the table's own.
                let mut packing = packing;
                packing.materials = table.materials.clone();
                (packing, own_materials(&table))
            };
            (
                packing,
                materials,
                (scene.d_min(), scene.d_max()),
                Some(&scene.grading),
            )
        }
        _ => {
            let domain = bounding_box(&table)?;
            let mut packing = Packing::of_disks(domain, table.disks.clone());
            packing.materials = table.materials.clone();
            let diameters = diameter_range(&packing);
            (packing, own_materials(&table), diameters, None)
        }
    };
    let dir = match &args.out {
        Some(dir) => dir.clone(),
        None => args
            .packing
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
    };
    let files = render_pictures(&packing, &materials, diameters, grading)
        .context("cannot draw the pictures")
        .map_err(Failure::Run)?;
    DirStore::new(&dir)
        .write(&files)
        .context("cannot write the pictures")
        .map_err(Failure::Run)?;
    report(args.quiet, || {
        format!(
            "{}: packing, psd and porosity_map (.svg, .png) of {} ({table}){}",
            dir.display(),
            args.packing.display(),
            if scene.is_none() {
                "; without --config the domain drawn is the disks' bounding box, and the porosities shown are of that box"
            } else {
                ""
            }
        )
    });
    Ok(())
}

/// The table's own material names as materials without properties.
fn own_materials(table: &PackingTable) -> Vec<Material> {
    table
        .material_names
        .iter()
        .map(|name| Material {
            name: name.clone(),
            properties: Vec::new(),
        })
        .collect()
}

/// The disks' bounding box as the domain, when no config gives one.
fn bounding_box(table: &PackingTable) -> Result<Domain, Failure> {
    let empty = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    let (lo, hi) = bounds_of_disks(empty, &table.disks);
    let corners = [lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)];
    Domain::polygon(&corners)
        .context("cannot frame the disks")
        .map_err(Failure::Input)
}

/// The well of `config` a packing belongs to: none without `[fracture]`,
/// else the named one or the only one.
fn pick_well<'c>(
    config: &'c Config,
    well: Option<&str>,
    origin: &str,
) -> Result<Option<&'c Well>, Failure> {
    let Some(run) = &config.fracture else {
        return match well {
            None => Ok(None),
            Some(_) => Err(Failure::Input(anyhow!(
                "--well: {origin} has no [fracture] wells"
            ))),
        };
    };
    let names = || {
        run.wells
            .iter()
            .map(|w| w.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    match well {
        Some(name) => run
            .wells
            .iter()
            .find(|w| w.name == name)
            .map(Some)
            .ok_or_else(|| {
                Failure::Input(anyhow!(
                    "--well: {origin} has no well {name:?}; its wells: {}",
                    names()
                ))
            }),
        None if run.wells.len() == 1 => Ok(Some(&run.wells[0])),
        None => Err(Failure::Input(anyhow!(
            "{origin} packs {} wells: name the packing's with --well ({})",
            run.wells.len(),
            names()
        ))),
    }
}

/// The scene the packing at `packing` was made in, and a line saying so
/// when it is not the config's own.
///
/// Without `[fracture]` that is the config's scene; with it, the well's
/// (see [`pick_well`]). A window run packs only the fracture's first
/// `length_mm` (the window that settled), recorded in the `summary.json`
/// the run wrote next to its `packing.csv`: its domain is the fracture cut
/// to that length, so that porosity and containment are of the window and
/// not of the whole fracture. A window config without that record is
/// refused rather than checked against the whole fracture.
fn packed_scene<'c>(
    config: &'c Config,
    well: Option<&str>,
    origin: &str,
    packing: &Path,
) -> Result<(Cow<'c, Scene>, Option<String>), Failure> {
    let Some(well) = pick_well(config, well, origin)? else {
        return Ok((Cow::Borrowed(&config.scene), None));
    };
    let dir = packing
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let summary = dir.join(SUMMARY_JSON);
    let windowed = config
        .fracture
        .as_ref()
        .is_some_and(|run| matches!(run.extent, Extent::Window { .. }));
    let Some(length) = recorded_window(&summary, &well.name)? else {
        if windowed {
            return Err(Failure::Input(anyhow!(
                "{origin} packs windows (extent = \"window\"): the length of {:?}'s window is in its run's {SUMMARY_JSON}, and {} has none for it; verify the packing in the folder its run wrote",
                well.name,
                summary.display()
            )));
        }
        return Ok((Cow::Borrowed(&well.scene), None));
    };
    let full = well.fracture.length;
    if !(length > 0.0 && length <= full) {
        return Err(Failure::Input(anyhow!(
            "{}: fracture.window.length_mm must lie in (0, {full}] (the fracture's length in mm), got {length}",
            summary.display()
        )));
    }
    let domain = well
        .fracture
        .cut(length)
        .domain()
        .with_context(|| format!("cannot cut {} to its window", well.name))
        .map_err(Failure::Input)?;
    let note = format!(
        "domain: the window of {:?}, its first {length} mm of {full} mm, as {} records",
        well.name,
        summary.display()
    );
    Ok((
        Cow::Owned(well.scene.clone().with_domain(domain)),
        Some(note),
    ))
}

/// The window length (mm) the run summary at `path` records for well
/// `name`: none when there is no summary, or it is of another well or of a
/// whole fracture.
fn recorded_window(path: &Path, name: &str) -> Result<Option<f64>, Failure> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(None);
    };
    let json: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a run summary", path.display()))
        .map_err(Failure::Input)?;
    let fracture = &json["fracture"];
    if fracture["extent"] != "window" || fracture["name"] != name {
        return Ok(None);
    }
    match fracture["window"]["length_mm"].as_f64() {
        Some(length) => Ok(Some(length)),
        None => Err(Failure::Input(anyhow!(
            "{}: fracture.window.length_mm: expected a number, got {}",
            path.display(),
            fracture["window"]["length_mm"]
        ))),
    }
}

/// Read a packing table, every fault located (file, line, column).
pub fn read_table(path: &Path) -> Result<PackingTable, Failure> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read {}", path.display()))
        .map_err(Failure::Input)?;
    read_packing_csv(&text, &path.display().to_string()).map_err(|e| Failure::Input(e.into()))
}

/// The table as a packing of `scene`, materials numbered as the config lists them.
fn packing_of(table: &PackingTable, scene: &Scene, config: &Config) -> Packing {
    let by_config: Vec<u16> = table
        .material_names
        .iter()
        .map(|name| {
            config
                .materials
                .iter()
                .position(|m| &m.name == name)
                .map_or(u16::MAX, |i| i as u16)
        })
        .collect();
    let mut packing = Packing::of_disks(scene.domain.clone(), table.disks.clone());
    packing.walls = scene.walls;
    packing.grains = table.grains.clone();
    packing.materials = table
        .materials
        .iter()
        .map(|&m| by_config[usize::from(m)])
        .collect();
    packing
}

/// The lines `gapack verify` prints under its verdict.
fn findings(c: &Check, table: &PackingTable, periodic: bool) -> Vec<String> {
    let row = |i: usize| table.disk_name(i);
    // Disks that fill more than the domain's area lie (mostly) outside it:
    // a porosity below 0 would only say the config is another scene's.
    let mut lines = vec![if c.porosity < 0.0 {
        format!(
            "{table}, solid {:.4} mm² against a domain of {:.4} mm²: the disks do not fit in this config's domain (is it the packing's config?); porosity not measured",
            c.solid_area, c.domain_area
        )
    } else {
        format!(
            "{table}, porosity {:.4} (solid {:.4} of {:.4} mm²)",
            c.porosity, c.solid_area, c.domain_area
        )
    }];
    if c.malformed > 0 {
        lines.push(format!(
            "malformed: {} with a non-finite position or a radius that is not positive",
            count(c.malformed, "disk", "disks")
        ));
    }
    let images = if periodic {
        ", images across the periodic edges included"
    } else {
        ""
    };
    lines.push(match c.worst_overlap {
        None => format!("overlaps: none (tolerance {OVERLAP_REL:.0e} of the radii sum{images})"),
        Some((a, b, depth)) => format!(
            "overlaps: {}{}{images}; the deepest {depth:.2e} of the radii sum ({} and {})",
            if c.overlaps_complete { "" } else { "at least " },
            count(c.overlaps, "pair", "pairs"),
            row(a),
            row(b)
        ),
    });
    lines.push(match (c.worst_outside, periodic) {
        (None, false) => "containment: every disk inside the domain".to_owned(),
        (None, true) => "containment: every centre inside the periodic cell".to_owned(),
        (Some((i, by)), false) => format!(
            "containment: {} outside; the farthest by {by:.3e} mm ({})",
            count(c.outside, "disk reaches", "disks reach"),
            row(i)
        ),
        (Some((i, by)), true) => format!(
            "containment: {} outside the periodic cell; the farthest by {by:.3e} mm ({})",
            count(c.outside, "centre lies", "centres lie"),
            row(i)
        ),
    });
    let kept = c.grading_kept();
    lines.push(match c.grading {
        GradingCheck::TooFewDisks(n) => format!(
            "grading: not checked: a grading check needs at least {MIN_GRADING_DISKS} disks, the table has {n} (with fewer, sampling noise explains any sizes)"
        ),
        GradingCheck::Measured(ks) => format!(
            "grading: KS distance {ks:.4} {} {:.4} (sampling noise of {} sizes + {}): {}",
            if kept { "≤" } else { ">" },
            c.ks_limit,
            c.particles,
            gapack::KS_MARGIN,
            if kept { "kept" } else { "bent" }
        ),
        _ => "grading: not checked".to_owned(),
    });
    lines
}

/// Why `gapack verify` fails a packing, each fault by its worst case named
/// as a person finds it in the file: by `id` and file line (line 1 the
/// header), e.g. `overlap: disks 12 and 40 (lines 14 and 42) overlap by
/// 3.1e-3 of their radii sum`.
fn why_invalid(c: &Check, table: &PackingTable, periodic: bool) -> String {
    let line = |i: usize| table.lines.get(i).copied().unwrap_or(0);
    let sum = if table.grains.is_empty() {
        "radii"
    } else {
        "circumradii"
    };
    let mut faults = Vec::new();
    if let Some((a, b, depth)) = c.worst_overlap {
        let pair = match (table.ids.get(a), table.ids.get(b)) {
            (Some(ia), Some(ib)) => {
                format!("disks {ia} and {ib} (lines {} and {})", line(a), line(b))
            }
            _ => format!("the disks on lines {} and {}", line(a), line(b)),
        };
        let of = if !c.overlaps_complete {
            format!(
                " (the deepest of at least {} overlapping pairs: the disks pile up, and each disk's search stopped soon after its first overlap)",
                c.overlaps
            )
        } else if c.overlaps > 1 {
            format!(" (the deepest of {} overlapping pairs)", c.overlaps)
        } else {
            String::new()
        };
        faults.push(format!(
            "overlap: {pair} overlap by {depth:.1e} of their {sum} sum{of}"
        ));
    }
    if let Some((i, by)) = c.worst_outside {
        let disk = match table.ids.get(i) {
            Some(id) => format!("disk {id} (line {})", line(i)),
            None => format!("the disk on line {}", line(i)),
        };
        let place = if periodic {
            format!("its centre lies {by:.1e} mm outside the periodic cell")
        } else {
            format!("it reaches {by:.1e} mm outside the domain")
        };
        let of = if c.outside > 1 {
            format!(" (the farthest of {} disks outside)", c.outside)
        } else {
            String::new()
        };
        faults.push(format!("outside: {disk}: {place}{of}"));
    }
    if c.malformed > 0 {
        faults.push(format!(
            "malformed: {} with a non-finite value or a size that is not positive",
            count(c.malformed, "disk", "disks")
        ));
    }
    faults.join("; ")
}

/// `1 pair`, `3 pairs`.
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}
