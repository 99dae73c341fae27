//! `packing.clumps.lammps`: a LAMMPS data file of rigid clumps of disks
//! (`atom_style hybrid sphere molecular`, one molecule per particle).

use super::clumps::clumps;
use super::common::{Export, Num, Text, VERSION, density, labels, type_count, type_id};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::format::{ExportOptions, LengthUnit};
use crate::packer::Packing;

/// File name of the LAMMPS data file of clumps.
pub const LAMMPS_CLUMPS_DATA: &str = "packing.clumps.lammps";

/// Every packed particle as a clump of disks (see the clumps of
/// `opts.clumps`: every disk inside its particle) in a LAMMPS data file
/// for `read_data`, `atom_style hybrid sphere molecular`, lengths in
/// `opts.units`. A packing of disks gives one disk per molecule.
///
/// # Layout
/// A first comment line (version, counts, units); the header `N atoms`
/// (one atom per disk of every clump), `T atom types` (one per material,
/// at least one), `xlo xhi`, `ylo yhi` (the domain's bounds, or a periodic
/// cell's) and `zlo zhi` (± the largest particle radius); comment lines:
/// what the clumps achieved (the coverage target and cap, the least and
/// mean coverage reached, how many particles fall short of the target,
/// never silently), a periodic cell's `boundary p p p`, the mass rule and
/// each type's material; then `Atoms # hybrid`, a blank line and one line
/// per disk: `id type x y z diameter density molecule`, with `id` from 1,
/// `z` = 0, `molecule` the particle's index + 1 (`packing.csv`'s id + 1),
/// `type` its material index + 1 and the density in kg per cubic length
/// unit (the material's `density`, else `opts.density`).
///
/// # In LAMMPS
/// ```text
/// units          si
/// dimension      2
/// boundary       f f p
/// atom_style     hybrid sphere molecular
/// read_data      packing.clumps.lammps
/// neigh_modify   exclude molecule/intra all
/// fix            bodies all rigid molecule
/// fix            flat all enforce2d
/// ```
/// (`fix enforce2d` after `fix rigid`, which LAMMPS requires). Each
/// molecule moves as one rigid body whose mass is the sum of its disks'
/// masses: `read_data` gives each the mass of a sphere, ρ·4/3·π·r³, and
/// the disks of a clump overlap, so their overlaps are counted more than
/// once; set the bodies' masses and inertia with `fix rigid … infile` for
/// the particle's own.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a particle's material is not in a
/// non-empty `materials`.
pub fn lammps_clumps_data(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    let s = e.s;
    let all = clumps(packing, &opts.clumps);
    let atoms = all.disks();
    let rho = opts.units.density_per_kg_m3();
    let (lo, hi) = e.extent();
    let r = e.r_max();
    let z = if r > 0.0 { r * s } else { 0.5 };
    let units = match opts.units {
        LengthUnit::Metre => "units si",
        LengthUnit::Millimetre => "no LAMMPS units style matches mm",
    };
    let u = opts.units.config_name();
    let mut t = Text::with_lines(atoms + 24);
    t.line(format_args!(
        "gapack {VERSION}: {} particles as {atoms} disks in rigid clumps (one molecule each), atom_style hybrid sphere molecular, lengths in {u} ({units}), density in kg/{u}^3",
        e.len()
    ));
    t.line(format_args!(""));
    t.line(format_args!("{atoms} atoms"));
    t.line(format_args!("{} atom types", type_count(materials)));
    t.line(format_args!(""));
    t.line(format_args!("{} {} xlo xhi", Num(lo.x * s), Num(hi.x * s)));
    t.line(format_args!("{} {} ylo yhi", Num(lo.y * s), Num(hi.y * s)));
    t.line(format_args!("{} {} zlo zhi", Num(-z), Num(z)));
    t.line(format_args!("# clumps: {}", all.summary(&opts.clumps)));
    if packing.domain.is_periodic() {
        t.line(format_args!(
            "# periodic cell: boundary p p p (x and y periodic: the cell is the box; z periodic as for any 2d run)"
        ));
    }
    t.line(format_args!(
        "# run with: neigh_modify exclude molecule/intra all; fix bodies all rigid molecule; then fix enforce2d. Mass from density: a sphere per disk (rho*4/3*pi*r^3), overlaps counted more than once"
    ));
    for (i, label) in labels(materials).iter().enumerate() {
        t.line(format_args!("# type {} = {label}", i + 1));
    }
    if atoms > 0 {
        t.line(format_args!(""));
        t.line(format_args!("Atoms # hybrid"));
        t.line(format_args!(""));
        let mut id = 0usize;
        for (row, clump) in e.rows().zip(&all.clumps) {
            let ty = type_id(row.material);
            let rho = Num(density(materials, row.material, opts) * rho);
            for &(c, r) in &clump.disks {
                id += 1;
                t.line(format_args!(
                    "{id} {ty} {} {} 0 {} {rho} {}",
                    Num(c.x * s),
                    Num(c.y * s),
                    Num(2.0 * r * s),
                    row.id + 1
                ));
            }
        }
    }
    Ok(t.into_bytes())
}
