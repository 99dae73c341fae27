//! `packing.vtk` and `boundary.vtk`: the packing and its domain for ParaView
//! (legacy VTK, ASCII POLYDATA).

use super::common::{Export, Num, Text, VERSION, density};
use crate::geometry::{Grain, Outline, Point};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::csv::GrainColumns;
use crate::output::format::ExportOptions;
use crate::output::svg::CIRCLE_SEGMENTS;
use crate::packer::Packing;

/// File name of the disks for ParaView.
pub const PACKING_VTK: &str = "packing.vtk";

/// File name of the domain outline for ParaView.
pub const BOUNDARY_VTK: &str = "boundary.vtk";

/// The packed disks (not the wall disks) as a legacy VTK file (version 3.0,
/// ASCII POLYDATA) for ParaView and VisIt.
///
/// One point per disk at `(x, y, 0)`, in placement order (point `i` is row
/// `i` of `packing.csv`), each with a one-point `VERTICES` cell so the
/// points show without a filter; point data `radius` and `diameter`
/// (double), `material_id` (int: material index + 1, 0 without materials)
/// and `density` (double, kg/m³: the material's `density`, else
/// `opts.density`). Lengths are in mm, gapack's unit, whatever
/// `opts.units` says: ParaView has no units and the picture matches the
/// other outputs.
///
/// A periodic cell says so in the title line (`periodic cell xmin xmax
/// ymin ymax`) and in field data of the dataset, before the points:
/// `periodic` (int, 1) and `cell` (double, one tuple `xmin xmax ymin
/// ymax`); a domain with walls has neither.
///
/// Particles that are not disks (non-empty `packing.grains`) are written
/// instead as one `POLYGONS` cell each, in placement order: the polygon of
/// 64 points on the particle's outline (inscribed: it lies inside the
/// particle; a rounded polygon without rounding keeps its own vertices), in
/// world coordinates at z = 0, with cell data `angle` (radians,
/// counter-clockwise), `a`, `b`, `alpha`, `beta` for superellipses and
/// `template` (int), `rounding` for rounded polygons (0 on a particle of
/// the other family, in a packing of both), `r` (area-equivalent radius),
/// `least_width`, `material_id`, `density` and the vector `centre`. The
/// title line says `particles`; ParaView shows the cells as they are.
///
/// In ParaView: open the file, add a Glyph filter with Glyph Type `Sphere`,
/// Orientation Array `No orientation array`, Scale Array `radius`, Scale
/// Factor `2` (the sphere source has diameter 1) and Glyph Mode `All Points`
/// (the default mode draws only a sample of the disks).
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn packing_vtk(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    // Lengths in mm: rows unscaled.
    let e = Export::new(packing, materials, 1.0)?;
    if !packing.grains.is_empty() {
        return Ok(particles_vtk(&e, materials, opts));
    }
    let n = e.len();
    let mut t = Text::with_lines(6 * n + 16);
    head(&mut t, packing, &format!("{n} disks"));
    t.line(format_args!("POINTS {n} double"));
    for d in e.rows() {
        t.line(format_args!("{} {} 0", d.x, d.y));
    }
    t.line(format_args!("VERTICES {n} {}", 2 * n));
    for i in 0..n {
        t.line(format_args!("1 {i}"));
    }
    t.line(format_args!("POINT_DATA {n}"));
    scalars(&mut t, "radius", "double", e.rows().map(|d| d.r));
    scalars(&mut t, "diameter", "double", e.rows().map(|d| d.d));
    material_scalars(&mut t, &e, materials, opts);
    Ok(t.into_bytes())
}

/// Points of the polygon each particle is drawn as in `packing.vtk` (a
/// rounded polygon without rounding keeps its own vertices).
pub(crate) const PARTICLE_SEGMENTS: usize = 64;

/// The title, format and dataset lines, and a periodic cell's field data.
fn head(t: &mut Text, packing: &Packing, what: &str) {
    t.line(format_args!("# vtk DataFile Version 3.0"));
    let (lo, hi) = packing.domain.bounds();
    let cell = format!("{} {} {} {}", Num(lo.x), Num(hi.x), Num(lo.y), Num(hi.y));
    let periodic = packing.domain.is_periodic();
    t.line(format_args!(
        "gapack {VERSION} packing: {what}, lengths in mm{}",
        if periodic {
            format!(", periodic cell {cell}")
        } else {
            String::new()
        }
    ));
    t.line(format_args!("ASCII"));
    t.line(format_args!("DATASET POLYDATA"));
    if periodic {
        t.line(format_args!("FIELD FieldData 2"));
        t.line(format_args!("periodic 1 1 int"));
        t.line(format_args!("1"));
        t.line(format_args!("cell 4 1 double"));
        t.line(format_args!("{cell}"));
    }
}

/// `packing.vtk` for particles that are not disks: one polygon cell per
/// particle (see [`packing_vtk`]).
fn particles_vtk(e: &Export<'_>, materials: &[Material], opts: &ExportOptions) -> Vec<u8> {
    let packing = e.packing;
    let n = e.len();
    let outlines: Vec<Vec<Point>> = packing
        .disks
        .iter()
        .zip(&packing.grains)
        .map(|(disk, grain)| {
            let turned = grain.turned();
            grain
                .outline
                .boundary(PARTICLE_SEGMENTS)
                .into_iter()
                .map(|p| disk.c + turned.to_world(p))
                .collect()
        })
        .collect();
    let total: usize = outlines.iter().map(Vec::len).sum();
    let columns = GrainColumns::of(&packing.grains);
    let mut t = Text::with_lines(total + 12 * n + 32);
    head(
        &mut t,
        packing,
        &format!("{n} particles as polygons of points on their outlines"),
    );
    t.line(format_args!("POINTS {total} double"));
    for p in outlines.iter().flatten() {
        t.line(format_args!("{} {} 0", Num(p.x), Num(p.y)));
    }
    t.line(format_args!("POLYGONS {n} {}", n + total));
    let mut first = 0;
    for outline in &outlines {
        let ids: Vec<String> = (first..first + outline.len())
            .map(|i| i.to_string())
            .collect();
        t.line(format_args!("{} {}", outline.len(), ids.join(" ")));
        first += outline.len();
    }
    t.line(format_args!("CELL_DATA {n}"));
    let grains = &packing.grains;
    scalars(
        &mut t,
        "angle",
        "double",
        grains.iter().map(|g| Num(g.angle)),
    );
    let se = |g: &Grain| match g.outline {
        Outline::Superellipse { a, b, alpha, beta } => [a, b, alpha, beta],
        Outline::Polygon { .. } => [0.0; 4],
    };
    if columns.superellipse {
        for (k, name) in ["a", "b", "alpha", "beta"].into_iter().enumerate() {
            scalars(&mut t, name, "double", grains.iter().map(|g| Num(se(g)[k])));
        }
    }
    if columns.polygon {
        let poly = |g: &Grain| match &g.outline {
            Outline::Polygon {
                template, rounding, ..
            } => (*template, *rounding),
            Outline::Superellipse { .. } => (0, 0.0),
        };
        scalars(&mut t, "template", "int", grains.iter().map(|g| poly(g).0));
        scalars(
            &mut t,
            "rounding",
            "double",
            grains.iter().map(|g| Num(poly(g).1)),
        );
    }
    scalars(&mut t, "r", "double", e.rows().map(|d| d.r));
    scalars(
        &mut t,
        "least_width",
        "double",
        grains.iter().map(|g| Num(g.outline.least_width())),
    );
    material_scalars(&mut t, e, materials, opts);
    t.line(format_args!("VECTORS centre double"));
    for d in e.rows() {
        t.line(format_args!("{} {} 0", d.x, d.y));
    }
    t.into_bytes()
}

/// The `material_id` (int: material index + 1, 0 without materials) and
/// `density` (double, kg/m³) blocks, one value per particle: point data
/// of the disks, cell data of the polygons.
fn material_scalars(t: &mut Text, e: &Export<'_>, materials: &[Material], opts: &ExportOptions) {
    scalars(
        t,
        "material_id",
        "int",
        e.rows().map(|d| d.material.map_or(0, |m| m + 1)),
    );
    scalars(
        t,
        "density",
        "double",
        e.rows().map(|d| Num(density(materials, d.material, opts))),
    );
}

/// One `SCALARS` block of point or cell data.
fn scalars<T: std::fmt::Display>(
    t: &mut Text,
    name: &str,
    kind: &str,
    values: impl Iterator<Item = T>,
) {
    t.line(format_args!("SCALARS {name} {kind} 1"));
    t.line(format_args!("LOOKUP_TABLE default"));
    for v in values {
        t.line(format_args!("{v}"));
    }
}

/// The domain outline as a legacy VTK file (version 3.0, ASCII POLYDATA):
/// its vertices (a circle as 256 points) at z = 0, in mm, joined by one
/// closed `LINES` polyline (the first point repeated at the end), so
/// ParaView draws the domain next to `packing.vtk`.
pub fn boundary_vtk(packing: &Packing) -> Vec<u8> {
    let outline = packing.domain.outline(CIRCLE_SEGMENTS);
    let m = outline.len();
    let mut t = Text::with_lines(m + 8);
    t.line(format_args!("# vtk DataFile Version 3.0"));
    t.line(format_args!(
        "gapack {VERSION} domain outline ({}{}), lengths in mm",
        packing.domain.shape().config_name(),
        if packing.domain.is_periodic() {
            ", a periodic cell: its edges are not walls"
        } else {
            ""
        }
    ));
    t.line(format_args!("ASCII"));
    t.line(format_args!("DATASET POLYDATA"));
    t.line(format_args!("POINTS {m} double"));
    for p in &outline {
        t.line(format_args!("{} {} 0", Num(p.x), Num(p.y)));
    }
    let ring: Vec<String> = (0..m).chain(0..1).map(|i| i.to_string()).collect();
    t.line(format_args!("LINES 1 {}", m + 2));
    t.line(format_args!("{} {}", m + 1, ring.join(" ")));
    t.into_bytes()
}
