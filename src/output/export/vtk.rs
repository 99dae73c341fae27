//! `packing.vtk` and `boundary.vtk`: the packing and its domain for ParaView
//! (legacy VTK, ASCII POLYDATA).

use std::io::Write as _;

use rayon::prelude::*;

use super::common::{Export, Lines, Num, VERSION, Writer, bytes, density, push_num};
use crate::geometry::{Grain, Outline, Point};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::csv::GrainColumns;
use crate::output::digits::push_int;
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
    Ok(bytes(packing_vtk_writer(packing, materials, opts)?))
}

/// [`packing_vtk`] checked, left to be written where the file goes.
///
/// # Errors
/// As [`packing_vtk`].
pub(crate) fn packing_vtk_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &'a ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    // Lengths in mm: rows unscaled.
    let e = Export::new(packing, materials, 1.0)?;
    Ok(Box::new(move |out| {
        let mut t = Lines::new(out);
        if packing.grains.is_empty() {
            disks_vtk(&mut t, &e, materials, opts);
        } else {
            particles_vtk(&mut t, &e, materials, opts);
        }
        t.finish()
    }))
}

/// `packing.vtk` for disks (see [`packing_vtk`]).
fn disks_vtk(t: &mut Lines<'_>, e: &Export<'_>, materials: &[Material], opts: &ExportOptions) {
    let n = e.len();
    head(t, e.packing, &format!("{n} disks"));
    t.line(format_args!("POINTS {n} double"));
    t.rows(n, |i, b| {
        let d = e.row(i);
        push_num(b, d.x.0);
        b.push(b' ');
        push_num(b, d.y.0);
        b.extend_from_slice(b" 0\n");
    });
    t.line(format_args!("VERTICES {n} {}", 2 * n));
    t.rows(n, |i, b| {
        b.extend_from_slice(b"1 ");
        push_int(b, i);
        b.push(b'\n');
    });
    t.line(format_args!("POINT_DATA {n}"));
    scalars(t, "radius", "double", n, |i, b| push_num(b, e.row(i).r.0));
    scalars(t, "diameter", "double", n, |i, b| push_num(b, e.row(i).d.0));
    material_scalars(t, e, materials, opts);
}

/// Points of the polygon each particle is drawn as in `packing.vtk` (a
/// rounded polygon without rounding keeps its own vertices).
pub(crate) const PARTICLE_SEGMENTS: usize = 64;

/// The title, format and dataset lines, and a periodic cell's field data.
fn head(t: &mut Lines<'_>, packing: &Packing, what: &str) {
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

/// The polygon particle `i` of `packing` is drawn as, in world
/// coordinates.
fn outline_of(packing: &Packing, i: usize) -> Vec<Point> {
    let (disk, grain) = (&packing.disks[i], &packing.grains[i]);
    let turned = grain.turned();
    grain
        .outline
        .boundary(PARTICLE_SEGMENTS)
        .into_iter()
        .map(|p| disk.c + turned.to_world(p))
        .collect()
}

/// `packing.vtk` for particles that are not disks: one polygon cell per
/// particle (see [`packing_vtk`]), each polygon made where its rows are
/// written.
fn particles_vtk(t: &mut Lines<'_>, e: &Export<'_>, materials: &[Material], opts: &ExportOptions) {
    let packing = e.packing;
    let n = e.len();
    let counts: Vec<usize> = (0..n)
        .into_par_iter()
        .map(|i| outline_of(packing, i).len())
        .collect();
    // The first point of each polygon.
    let first: Vec<usize> = counts
        .iter()
        .scan(0, |next, &k| {
            let i = *next;
            *next += k;
            Some(i)
        })
        .collect();
    let total: usize = counts.iter().sum();
    let columns = GrainColumns::of(&packing.grains);
    head(
        t,
        packing,
        &format!("{n} particles as polygons of points on their outlines"),
    );
    t.line(format_args!("POINTS {total} double"));
    t.rows(n, |i, b| {
        for p in outline_of(packing, i) {
            // Writing to a Vec cannot fail.
            let _ = writeln!(b, "{} {} 0", Num(p.x), Num(p.y));
        }
    });
    t.line(format_args!("POLYGONS {n} {}", n + total));
    t.rows(n, |i, b| {
        push_int(b, counts[i]);
        for id in first[i]..first[i] + counts[i] {
            b.push(b' ');
            push_int(b, id);
        }
        b.push(b'\n');
    });
    t.line(format_args!("CELL_DATA {n}"));
    let grains = &packing.grains;
    let num = |b: &mut Vec<u8>, x: f64| {
        // Writing to a Vec cannot fail.
        let _ = write!(b, "{}", Num(x));
    };
    scalars(t, "angle", "double", n, |i, b| num(b, grains[i].angle));
    let se = |g: &Grain| match g.outline {
        Outline::Superellipse { a, b, alpha, beta } => [a, b, alpha, beta],
        Outline::Polygon { .. } => [0.0; 4],
    };
    if columns.superellipse {
        for (k, name) in ["a", "b", "alpha", "beta"].into_iter().enumerate() {
            scalars(t, name, "double", n, |i, b| num(b, se(&grains[i])[k]));
        }
    }
    if columns.polygon {
        let poly = |g: &Grain| match &g.outline {
            Outline::Polygon {
                template, rounding, ..
            } => (*template, *rounding),
            Outline::Superellipse { .. } => (0, 0.0),
        };
        scalars(t, "template", "int", n, |i, b| {
            push_int(b, poly(&grains[i]).0);
        });
        scalars(t, "rounding", "double", n, |i, b| {
            num(b, poly(&grains[i]).1);
        });
    }
    scalars(t, "r", "double", n, |i, b| num(b, e.row(i).r.0));
    scalars(t, "least_width", "double", n, |i, b| {
        num(b, grains[i].outline.least_width());
    });
    material_scalars(t, e, materials, opts);
    t.line(format_args!("VECTORS centre double"));
    t.rows(n, |i, b| {
        let d = e.row(i);
        let _ = writeln!(b, "{} {} 0", d.x, d.y);
    });
}

/// The `material_id` (int: material index + 1, 0 without materials) and
/// `density` (double, kg/m³) blocks, one value per particle: point data
/// of the disks, cell data of the polygons.
fn material_scalars(
    t: &mut Lines<'_>,
    e: &Export<'_>,
    materials: &[Material],
    opts: &ExportOptions,
) {
    let n = e.len();
    scalars(t, "material_id", "int", n, |i, b| {
        push_int(b, e.row(i).material.map_or(0, |m| m + 1));
    });
    scalars(t, "density", "double", n, |i, b| {
        push_num(b, density(materials, e.row(i).material, opts));
    });
}

/// One `SCALARS` block of point or cell data: `n` values, value `i`
/// appended by `value(i, buffer)`.
fn scalars(
    t: &mut Lines<'_>,
    name: &str,
    kind: &str,
    n: usize,
    value: impl Fn(usize, &mut Vec<u8>) + Sync,
) {
    t.line(format_args!("SCALARS {name} {kind} 1"));
    t.line(format_args!("LOOKUP_TABLE default"));
    t.rows(n, |i, b| {
        value(i, b);
        b.push(b'\n');
    });
}

/// The domain outline as a legacy VTK file (version 3.0, ASCII POLYDATA):
/// its vertices (a circle as 256 points) at z = 0, in mm, joined by one
/// closed `LINES` polyline (the first point repeated at the end), so
/// ParaView draws the domain next to `packing.vtk`.
pub fn boundary_vtk(packing: &Packing) -> Vec<u8> {
    let outline = packing.domain.outline(CIRCLE_SEGMENTS);
    let m = outline.len();
    let mut bytes = Vec::new();
    let mut t = Lines::new(&mut bytes);
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
    // Writing to a Vec cannot fail.
    let _ = t.finish();
    bytes
}
