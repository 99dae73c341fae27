//! `packing.lammps`: a LAMMPS / LIGGGHTS data file (`atom_style sphere`).

use super::common::{Export, Num, Text, VERSION, density, labels, type_count, type_id};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::format::{ExportOptions, LengthUnit};
use crate::packer::Packing;

/// File name of the LAMMPS / LIGGGHTS data file.
pub const LAMMPS_DATA: &str = "packing.lammps";

/// The packed disks (not the wall disks) as a LAMMPS / LIGGGHTS data file
/// for `read_data`, `atom_style sphere`, lengths in `opts.units`.
///
/// # Layout
/// A first comment line (`read_data` always skips it) giving the version,
/// the count and the units (`units si` in metres); the header `N atoms`,
/// `T atom types` (one per material, at least one), `xlo xhi` and `ylo yhi`
/// (the domain's bounds, which hold every disk; a periodic cell's own
/// bounds, which its disks cross) and `zlo zhi` (± the largest radius: a 2d
/// box must straddle z = 0); for a periodic cell the comment line `#
/// periodic cell: boundary p p p` (a data file has no boundary keyword:
/// the input script sets it); a comment line saying how LAMMPS and
/// LIGGGHTS each turn the density into a mass; comment lines naming each
/// type;
/// then `Atoms # sphere` (the comment lets LAMMPS check the atom style), a
/// blank line and one line per disk: `id type diameter density x y z`, with
/// `id` from 1 in placement order (`packing.csv`'s id + 1), `type` the
/// material index + 1, `z` = 0, and the density in kg per cubic length unit
/// (kg/m³ in metres, kg/mm³ = 1e-9 × kg/m³ in millimetres): the material's
/// `density`, else `opts.density`.
///
/// # In LAMMPS or LIGGGHTS
/// ```text
/// units          si
/// dimension      2
/// boundary       f f p
/// atom_style     sphere
/// read_data      packing.lammps
/// fix            flat all enforce2d
/// ```
/// `read_data` turns density into mass as for a sphere, m = ρ·4/3·π·r³,
/// even with `dimension 2` (LAMMPS `read_data` docs); for the mass of a disk
/// use `set type 1 density/disc ρ·t` (mass per area, t the thickness) and
/// `fix nve/sphere disc`. A 2d run needs z periodic. A periodic cell
/// (`walls = "periodic"`) needs `boundary p p p` instead of `f f p`: its
/// centres lie in `[xlo, xhi) × [ylo, yhi)` and the disks crossing an edge
/// meet their neighbours across it.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn lammps_data(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    let (s, n) = (e.s, e.len());
    let rho = opts.units.density_per_kg_m3();
    let (lo, hi) = e.extent();
    let r = e.r_max();
    let z = if r > 0.0 { r * s } else { 0.5 };
    let units = match opts.units {
        LengthUnit::Metre => "units si",
        LengthUnit::Millimetre => "no LAMMPS units style matches mm",
    };
    let mut t = Text::with_lines(n + 24);
    t.line(format_args!(
        "gapack {VERSION}: {n} disks, atom_style sphere, lengths in {} ({units}), density in kg/{}^3",
        opts.units.config_name(),
        opts.units.config_name()
    ));
    t.line(format_args!(""));
    t.line(format_args!("{n} atoms"));
    t.line(format_args!("{} atom types", type_count(materials)));
    t.line(format_args!(""));
    t.line(format_args!("{} {} xlo xhi", Num(lo.x * s), Num(hi.x * s)));
    t.line(format_args!("{} {} ylo yhi", Num(lo.y * s), Num(hi.y * s)));
    t.line(format_args!("{} {} zlo zhi", Num(-z), Num(z)));
    if packing.domain.is_periodic() {
        t.line(format_args!(
            "# periodic cell: boundary p p p (x and y periodic: the cell is the box; z periodic as for any 2d run)"
        ));
    }
    t.line(format_args!(
        "# mass from density: LAMMPS read_data, a sphere (rho*4/3*pi*r^3); LIGGGHTS with dimension 2, a disc of unit thickness (rho*pi*r^2)"
    ));
    for (i, label) in labels(materials).iter().enumerate() {
        t.line(format_args!("# type {} = {label}", i + 1));
    }
    if n > 0 {
        t.line(format_args!(""));
        t.line(format_args!("Atoms # sphere"));
        t.line(format_args!(""));
        for d in e.rows() {
            t.line(format_args!(
                "{} {} {} {} {} {} 0",
                d.id + 1,
                type_id(d.material),
                d.d,
                Num(density(materials, d.material, opts) * rho),
                d.x,
                d.y
            ));
        }
    }
    Ok(t.into_bytes())
}
