//! `gapack validate` and `gapack verify`: look at a config or a packing
//! without packing anything.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::Args;
use gapack::check::{Check, check};
use gapack::config::{Config, ConfigName};
use gapack::fracture::{Extent, MM_PER_M};
use gapack::geometry::predicates::OVERLAP_REL;
use gapack::layering::Material;
use gapack::output::{PackingTable, diameter_range, read_packing_csv, write_pictures};
use gapack::packer::{PEAK_BYTES_PER_DISK, estimated_peak_bytes};
use gapack::{Domain, Packing, Point, Scene, Shape, psd_ks};

use crate::{Failure, load_config, output_dir, report};

/// `gapack validate` arguments.
#[derive(Args)]
pub struct ValidateArgs {
    /// Config (TOML) to check.
    config: PathBuf,
    /// Describe the scene even if it is over the config's [limits].
    #[arg(long)]
    force: bool,
}

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

/// `gapack validate`: the config's scene (or each well's) and what a run
/// would write, without running it.
pub fn run_validate(args: &ValidateArgs) -> Result<(), Failure> {
    let (config, origin) = load_config(Some(&args.config), args.force).map_err(Failure::Input)?;
    println!("{origin}: valid");
    for line in describe(&config, &args.config) {
        println!("  {line}");
    }
    Ok(())
}

/// What `gapack validate` prints: the job, the scenes, the outputs.
fn describe(config: &Config, path: &Path) -> Vec<String> {
    let scene = &config.scene;
    let mut lines = Vec::new();
    let job = if let Some(o) = &config.optimise {
        format!(
            "job: gapack optimise: target porosity {} ± {}, population {}, at most {} generations, {} s",
            o.target_porosity, o.tolerance, o.population, o.generations, o.time_limit_s
        )
    } else if config.layering.is_some() {
        "job: gapack layer (or gapack pack for the packing alone)".to_owned()
    } else if let Some(run) = &config.fracture {
        format!(
            "job: gapack pack: {} fracture{}, {}",
            run.wells.len(),
            if run.wells.len() == 1 { "" } else { "s" },
            match run.extent {
                Extent::Full => "packed whole".to_owned(),
                Extent::Window { tolerance } =>
                    format!("representative windows (porosity tolerance {tolerance})"),
            }
        )
    } else {
        "job: gapack pack".to_owned()
    };
    lines.push(job);
    if let Some(l) = &config.layering {
        lines.push(format!(
            "layering: {} material(s), {} along {}, {} bins",
            config.materials.len(),
            l.mode.config_name(),
            l.axis.config_name(),
            l.bins
        ));
    }
    let g = &scene.grading;
    lines.push(format!(
        "grading: d {} to {} mm ({} basis, {} interpolation){}, seed {}",
        tidy(scene.d_min()),
        tidy(scene.d_max()),
        g.basis().config_name(),
        g.interpolation().config_name(),
        if scene.gradient.is_some() {
            ", size-graded"
        } else {
            ""
        },
        scene.seed
    ));
    lines.push(format!(
        "packer: {}, {} index, {} rules, fill {}",
        scene.packer.method.config_name(),
        scene.packer.index.config_name(),
        scene.packer.rules.config_name(),
        scene.packer.fill.config_name()
    ));
    match &config.fracture {
        Some(run) => {
            for well in &run.wells {
                let f = well.fracture;
                let taper = f
                    .tip_width
                    .map_or(String::new(), |t| format!(" tapering to {} mm", tidy(t)));
                lines.push(format!(
                    "well {}: {} mm wide{taper}, {} m high; {}",
                    well.name,
                    tidy(f.width),
                    tidy(f.length / MM_PER_M),
                    scene_line(&well.scene)
                ));
            }
        }
        None => lines.push(format!("domain: {}", scene_line(scene))),
    }
    if let Some(o) = &config.optimise {
        lines.push(format!(
            "search memory: about {} ({} genomes)",
            memory(o.peak_bytes(scene)),
            o.population
        ));
    }
    let out = output_dir(None, config, Some(path));
    let formats: Vec<&str> = config
        .output
        .formats
        .iter()
        .map(|f| f.config_name())
        .collect();
    lines.push(format!(
        "output: {} ({}; summary.json always)",
        out.display(),
        if formats.is_empty() {
            "no format".to_owned()
        } else {
            formats.join(", ")
        }
    ));
    lines
}

/// `rectangle 8.6 × 62.5 mm, area 537.5 mm², exact walls: about 340 disks (at most 430), peak memory 0.04 MB`.
fn scene_line(scene: &Scene) -> String {
    let domain = &scene.domain;
    let shape = match domain.shape() {
        Shape::Rectangle { width, height } => {
            format!("rectangle {} × {} mm", tidy(*width), tidy(*height))
        }
        Shape::Polygon { vertices } => format!("polygon of {} vertices", vertices.len()),
        Shape::Circle { radius, .. } => format!("circle of radius {} mm", tidy(*radius)),
        Shape::Trapezoid {
            bottom,
            top,
            height,
        } => format!(
            "trapezoid {} / {} × {} mm",
            tidy(*bottom),
            tidy(*top),
            tidy(*height)
        ),
    };
    let bytes = estimated_peak_bytes(scene);
    format!(
        "{shape}, area {} mm², walls {}: about {:.0} disks (at most {:.0}), peak memory about {}",
        tidy(domain.area()),
        scene.walls.config_name(),
        scene.estimated_disks(),
        bytes / PEAK_BYTES_PER_DISK,
        memory(bytes)
    )
}

/// `12 kB`, `1.6 MB`, `2.3 GB` (powers of 1024).
fn memory(bytes: f64) -> String {
    let kb = bytes / 1024.0;
    if kb < 1024.0 {
        format!("{kb:.0} kB")
    } else if kb < 1024.0 * 1024.0 {
        format!("{:.1} MB", kb / 1024.0)
    } else {
        format!("{:.1} GB", kb / (1024.0 * 1024.0))
    }
}

/// Four significant digits, no trailing zeros.
fn tidy(v: f64) -> String {
    let s = format!("{}", (v * 1e4).round() / 1e4);
    if v.abs() >= 1e4 || s.len() <= 8 {
        s
    } else {
        format!("{v:.4}")
    }
}

/// `gapack verify`: read the packing, check it against the config's domain
/// and grading, print the findings; exit 1 when it fails.
pub fn run_verify(args: &VerifyArgs) -> Result<(), Failure> {
    let (config, origin) = load_config(Some(&args.config), true).map_err(Failure::Input)?;
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
        Some(path) => Some(load_config(Some(path), true).map_err(Failure::Input)?),
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
                (
                    Packing {
                        materials: table.materials.clone(),
                        ..packing
                    },
                    own_materials(&table),
                )
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
            let packing = Packing {
                materials: table.materials.clone(),
                ..Packing::of_disks(domain, table.disks.clone())
            };
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
    write_pictures(&dir, &packing, &materials, diameters, grading)
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
    Packing {
        walls: scene.walls,
        materials: table
            .materials
            .iter()
            .map(|&m| by_config[usize::from(m)])
            .collect(),
        ..Packing::of_disks(scene.domain.clone(), table.disks.clone())
    }
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
            gapack::check::KS_MARGIN,
            if kept { "kept" } else { "bent" }
        ),
    });
    lines
}

/// `1 pair`, `3 pairs`.
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}
