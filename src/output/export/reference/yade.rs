//! `packing.yade.txt`: spheres for YADE's `ymport.text` / `ymport.textExt`;
//! `packing.yade.py`: a script appending clumps, for non-disk particles.

use super::clumps::clumps;
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
    let n = e.len();
    let mut t = Text::with_lines(n + 3);
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
            material_ids(materials)
        ));
        t.line(format_args!(
            "# append {} materials to O.materials in that order before ymport.text(...), or YADE stops with 'Material id out of range'",
            materials.len()
        ));
    }
    periodic_cell(&mut t, &e);
    for d in e.rows() {
        let (x, y, r) = (d.x, d.y, d.r);
        match d.material {
            Some(m) => t.line(format_args!("{x} {y} 0 {r} {m}")),
            None => t.line(format_args!("{x} {y} 0 {r}")),
        }
    }
    Ok(t.into_bytes())
}

/// File name of the YADE script of clumps (packings of non-disk particles).
pub const YADE_SCRIPT: &str = "packing.yade.py";

/// The packed particles as clumps of spheres (see the clumps of
/// `opts.clumps`: every sphere inside its particle) in a YADE Python
/// script, lengths in `opts.units`: the `yade` format of a packing of
/// non-disk particles (a sphere list cannot say which spheres make one
/// body). A packing of disks gives one sphere per clump.
///
/// # Layout
/// `#` comment lines: the version, the counts and the unit; what the
/// clumps achieved (the coverage target and cap, the least and mean
/// coverage reached, how many particles fall short of the target, never
/// silently); with materials, which `O.materials` id is which; for a
/// periodic cell, its `O.periodic = True; O.cell.setBox(w, h, t)` as in
/// the sphere list. Then `gapack_data = [`, one line per particle in
/// placement order, `(m, ((x, y, r), (x, y, r), …)),` with `m` the
/// material's index (from 0; -1 without materials) and its spheres'
/// centres (z = 0) and radii, and `]`. Last, the lines that append each
/// particle with `O.bodies.appendClumped` (its spheres made by
/// `utils.sphere`, with `material=m` when there are materials) and keep
/// the clump ids in `gapack_clumps`, in placement order.
///
/// # In YADE
/// `yade packing.yade.py`, or `exec(open('packing.yade.py').read())` in a
/// script, after appending the materials (their ids must be 0, 1, …).
/// Densities belong to the materials; a clump's mass is its spheres'
/// union's, as YADE computes it. Keep the clumps in the plane with
/// `O.bodies[i].state.blockedDOFs = 'zXY'` for `i` in `gapack_clumps`.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a particle's material is not in a
/// non-empty `materials`.
pub fn yade_script(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    let (s, n) = (e.s, e.len());
    let all = clumps(packing, &opts.clumps);
    let mut t = Text::with_lines(n + 16);
    t.line(format_args!(
        "# gapack {VERSION}: {n} particles as {} spheres in clumps for YADE, lengths in {}",
        all.disks(),
        opts.units.config_name()
    ));
    t.line(format_args!("# clumps: {}", all.summary(&opts.clumps)));
    if !materials.is_empty() {
        t.line(format_args!(
            "# m = O.materials id: {}; append {} materials to O.materials in that order first",
            material_ids(materials),
            materials.len()
        ));
    }
    periodic_cell(&mut t, &e);
    t.line(format_args!(
        "# run with: yade packing.yade.py, or exec(open('packing.yade.py').read()); keep the clumps in the plane: blockedDOFs = 'zXY'"
    ));
    t.line(format_args!("from yade import utils"));
    t.line(format_args!("gapack_data = ["));
    for (row, clump) in e.rows().zip(&all.clumps) {
        let m = row.material.map_or(-1, |m| m as i64);
        let spheres: Vec<String> = clump
            .disks
            .iter()
            .map(|&(c, r)| format!("({}, {}, {})", Num(c.x * s), Num(c.y * s), Num(r * s)))
            .collect();
        t.line(format_args!("({m}, ({},)),", spheres.join(", ")));
    }
    t.line(format_args!("]"));
    t.line(format_args!("def gapack_sphere(x, y, r, m):"));
    t.line(format_args!(
        "    return utils.sphere((x, y, 0.0), r) if m < 0 else utils.sphere((x, y, 0.0), r, material=m)"
    ));
    t.line(format_args!(
        "gapack_clumps = [O.bodies.appendClumped([gapack_sphere(x, y, r, m) for x, y, r in spheres])[0] for m, spheres in gapack_data]"
    ));
    Ok(t.into_bytes())
}

/// Which `O.materials` id is which material: `0 name, 1 name, …`.
fn material_ids(materials: &[Material]) -> String {
    let ids: Vec<String> = labels(materials)
        .iter()
        .enumerate()
        .map(|(i, label)| format!("{i} {label}"))
        .collect();
    ids.join(", ")
}

/// A periodic cell's comment line, `# periodic cell: O.periodic = True;
/// O.cell.setBox(w, h, t)` with `t` four times the largest diameter (see
/// [`yade_text`]); nothing for a domain with walls.
fn periodic_cell(t: &mut Text, e: &Export<'_>) {
    if let Some(cell) = e.packing.domain.period() {
        let (s, depth) = (e.s, 8.0 * e.r_max());
        t.line(format_args!(
            "# periodic cell: O.periodic = True; O.cell.setBox({}, {}, {})",
            Num(cell.x * s),
            Num(cell.y * s),
            Num(if depth > 0.0 { depth * s } else { 1.0 })
        ));
    }
}
