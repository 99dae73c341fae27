//! `gapack verify` and `gapack plot`: look at an existing packing without
//! packing anything.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::Args;
use gapack::OVERLAP_REL;
use gapack::config::Config;
use gapack::layering::Material;
use gapack::output::{PackingTable, diameter_range, read_packing_csv, render_pictures};
use gapack::{Check, check};
use gapack::{Domain, Packing, Point, Scene, psd_ks};

use super::{Failure, load_config, report};
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
    let scene = pick_scene(&config, args.well.as_deref(), &origin)?;
    let table = read_table(&args.packing)?;
    let graded = scene.gradient.is_some();
    let mut result = check(
        &table.disks,
        &scene.domain,
        (!graded).then_some(&scene.grading),
    );
    if graded {
        // Size-graded: each material against its own curve.
        result.psd_ks = Some(psd_ks(&packing_of(&table, scene, &config), scene));
    }
    let lines = findings(&result, &table);
    println!(
        "{} against {origin}: {}",
        args.packing.display(),
        if result.valid() && result.grading_kept() {
            "valid"
        } else {
            "FAILED"
        }
    );
    for line in &lines {
        println!("  {line}");
    }
    if !result.valid() {
        return Err(Failure::Run(anyhow!(
            "{}: the packing is not valid (overlaps or disks outside the domain)",
            args.packing.display()
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

/// `gapack plot`: the pictures of an existing packing (`packing`, `psd`,
/// `porosity_map`, as SVG and PNG), next to it unless `--out` says otherwise.
pub fn run_plot(args: &PlotArgs) -> Result<(), Failure> {
    let table = read_table(&args.packing)?;
    let loaded = match &args.config {
        // Nothing is packed: the [limits] do not apply.
        Some(path) => Some(load_config(path, true)?),
        None => None,
    };
    let (packing, materials, diameters, grading) = match &loaded {
        Some((config, origin)) => {
            let scene = pick_scene(config, args.well.as_deref(), origin)?;
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
        None => {
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
            "{}: packing, psd and porosity_map (.svg, .png) of {} ({table})",
            dir.display(),
            args.packing.display()
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
    let (mut lo, mut hi) = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for d in &table.disks {
        lo = Point::new(lo.x.min(d.c.x - d.r), lo.y.min(d.c.y - d.r));
        hi = Point::new(hi.x.max(d.c.x + d.r), hi.y.max(d.c.y + d.r));
    }
    let corners = [lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)];
    Domain::polygon(&corners)
        .context("cannot frame the disks")
        .map_err(Failure::Input)
}

/// The scene a packing of `config` was made for: its own, or the named well's.
fn pick_scene<'c>(
    config: &'c Config,
    well: Option<&str>,
    origin: &str,
) -> Result<&'c Scene, Failure> {
    let Some(run) = &config.fracture else {
        return match well {
            None => Ok(&config.scene),
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
            .map(|w| &w.scene)
            .ok_or_else(|| {
                Failure::Input(anyhow!(
                    "--well: {origin} has no well {name:?}; its wells: {}",
                    names()
                ))
            }),
        None if run.wells.len() == 1 => Ok(&run.wells[0].scene),
        None => Err(Failure::Input(anyhow!(
            "{origin} packs {} wells: name the packing's with --well ({})",
            run.wells.len(),
            names()
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
    packing.materials = table
        .materials
        .iter()
        .map(|&m| by_config[usize::from(m)])
        .collect();
    packing
}

/// The lines `gapack verify` prints under its verdict.
fn findings(c: &Check, table: &PackingTable) -> Vec<String> {
    let row = |i: usize| format!("row {}", i + 1);
    let mut lines = vec![format!(
        "{table}, porosity {:.4} (solid {:.4} of {:.4} mm²)",
        c.porosity, c.solid_area, c.domain_area
    )];
    if c.malformed > 0 {
        lines.push(format!(
            "malformed: {} with a non-finite position or a radius that is not positive",
            count(c.malformed, "disk", "disks")
        ));
    }
    lines.push(match c.worst_overlap {
        None => format!("overlaps: none (tolerance {OVERLAP_REL:.0e} of the radii sum)"),
        Some((a, b, depth)) => format!(
            "overlaps: {}; the deepest {depth:.2e} of the radii sum ({} and {})",
            count(c.overlaps, "pair", "pairs"),
            row(a),
            row(b)
        ),
    });
    lines.push(match c.worst_outside {
        None => "containment: every disk inside the domain".to_owned(),
        Some((i, by)) => format!(
            "containment: {} outside; the farthest by {by:.3e} mm ({})",
            count(c.outside, "disk reaches", "disks reach"),
            row(i)
        ),
    });
    let kept = c.grading_kept();
    lines.push(match c.psd_ks {
        None => "grading: not checked".to_owned(),
        Some(ks) => format!(
            "grading: KS distance {ks:.4} {} {:.4} (sampling noise of {} sizes + {}): {}",
            if kept { "≤" } else { ">" },
            c.ks_limit,
            c.particles,
            gapack::KS_MARGIN,
            if kept { "kept" } else { "bent" }
        ),
    });
    lines
}

/// `1 pair`, `3 pairs`.
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}
