//! `packing.vtk` and `boundary.vtk`: the packing and its domain for ParaView
//! (legacy VTK, ASCII POLYDATA).

use super::common::{Export, Num, Text, VERSION, density};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
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
    let n = e.len();
    let mut t = Text::with_lines(6 * n + 16);
    t.line(format_args!("# vtk DataFile Version 3.0"));
    let (lo, hi) = packing.domain.bounds();
    let cell = format!("{} {} {} {}", Num(lo.x), Num(hi.x), Num(lo.y), Num(hi.y));
    let periodic = packing.domain.is_periodic();
    t.line(format_args!(
        "gapack {VERSION} packing: {n} disks, lengths in mm{}",
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
    scalars(
        &mut t,
        "material_id",
        "int",
        e.rows().map(|d| d.material.map_or(0, |m| m + 1)),
    );
    scalars(
        &mut t,
        "density",
        "double",
        e.rows().map(|d| Num(density(materials, d.material, opts))),
    );
    Ok(t.into_bytes())
}

/// One `SCALARS` block of point data.
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
