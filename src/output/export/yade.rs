//! `packing.yade.txt`: spheres for YADE's `ymport.text` / `ymport.textExt`.

use super::common::{Export, Num, Text, VERSION, labels};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::format::ExportOptions;
use crate::packer::Packing;

/// File name of the YADE sphere list.
pub const YADE_TEXT: &str = "packing.yade.txt";

/// The packed disks (not the wall disks) as a YADE text sphere list, lengths
/// in `opts.units`.
///
/// # Layout
/// A `#format` line first, as YADE's `export.textExt` writes it and
/// `ymport.textExt` reads it: `#format x_y_z_r` without materials, then one
/// line `x y z r` per disk; `#format x_y_z_r_matId` with materials, then
/// `x y z r matId` where `matId` is the material's index (from 0) — YADE
/// takes it as the id of a material in `O.materials`. A `#` comment line
/// follows with the version, count, unit and, with materials, which id is
/// which, then one saying to append the materials first. z = 0; disks in
/// placement order; no blank line (the reader fails
/// on one). Densities are not in the file: they belong to YADE's
/// materials. A periodic cell adds a comment line declaring it in YADE's
/// terms: `# periodic cell: O.periodic = True; O.cell.setBox(w, h, t)`,
/// `w` × `h` the cell (its lower-left corner at the origin, as gapack's)
/// and `t` four times the largest diameter: z must hold the spheres
/// without their meeting their own images, and YADE's collider refuses a
/// body whose bounding box, enlarged by its Verlet distance (by default
/// half the smallest radius), reaches half the cell (twice the largest
/// diameter was refused: `Body larger than half of the cell size`).
///
/// # In YADE
/// ```text
/// from yade import ymport
/// O.bodies.append(ymport.text('packing.yade.txt'))
/// ```
/// With materials, append them to `O.materials` first, in config order
/// (their ids must be 0, 1, …); YADE is 3D, so keep the spheres in the plane
/// with `b.state.blockedDOFs = 'zXY'`. For a periodic cell, run the
/// commands of its comment line before appending the spheres.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn yade_text(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    let (s, n) = (e.s, e.len());
    let mut t = Text::with_lines(n + 3);
    let ids: Vec<String> = labels(materials)
        .iter()
        .enumerate()
        .map(|(i, label)| format!("{i} {label}"))
        .collect();
    if materials.is_empty() {
        t.line(format_args!("#format x_y_z_r"));
        t.line(format_args!(
            "# gapack {VERSION}: {n} disks, lengths in {}",
            opts.units.config_name()
        ));
    } else {
        t.line(format_args!("#format x_y_z_r_matId"));
        t.line(format_args!(
            "# gapack {VERSION}: {n} disks, lengths in {}, matId = O.materials id: {}",
            opts.units.config_name(),
            ids.join(", ")
        ));
        t.line(format_args!(
            "# append {} materials to O.materials in that order before ymport.text(...), or YADE stops with 'Material id out of range'",
            materials.len()
        ));
    }
    if let Some(cell) = packing.domain.period() {
        let depth = 8.0 * e.r_max();
        t.line(format_args!(
            "# periodic cell: O.periodic = True; O.cell.setBox({}, {}, {})",
            Num(cell.x * s),
            Num(cell.y * s),
            Num(if depth > 0.0 { depth * s } else { 1.0 })
        ));
    }
    for d in e.rows() {
        let (x, y, r) = (d.x, d.y, d.r);
        match d.material {
            Some(m) => t.line(format_args!("{x} {y} 0 {r} {m}")),
            None => t.line(format_args!("{x} {y} 0 {r}")),
        }
    }
    Ok(t.into_bytes())
}
