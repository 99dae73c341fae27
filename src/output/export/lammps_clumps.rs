//! `packing.clumps.lammps`: a LAMMPS data file of rigid clumps of disks
//! (`atom_style hybrid sphere molecular`, one molecule per particle).

use super::clumps::clumps;
use super::common::{Export, Num, Text, VERSION, density, type_id};
use super::lammps::{Header, header, units_style};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::format::ExportOptions;
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
    let u = opts.units.config_name();
    let mut t = Text::with_lines(atoms + 24);
    let title = format!(
        "gapack {VERSION}: {} particles as {atoms} disks in rigid clumps (one molecule each), atom_style hybrid sphere molecular, lengths in {u} ({}), density in kg/{u}^3",
        e.len(),
        units_style(opts)
    );
    header(
        &mut t,
        &e,
        materials,
        &Header {
            title,
            counts: &[(atoms, "atoms")],
            before: &[format!("# clumps: {}", all.summary(&opts.clumps))],
            after: &["# run with: neigh_modify exclude molecule/intra all; fix bodies all rigid molecule; then fix enforce2d. Mass from density: a sphere per disk (rho*4/3*pi*r^3), overlaps counted more than once".to_owned()],
        },
    );
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
