//! `packing.superquadric.data` and `packing.superquadric.in`: superellipse
//! particles for LIGGGHTS' `atom_style superquadric`.

use std::io::Write as _;

use super::common::{Export, Lines, Num, VERSION, Writer, bytes, density, type_id};
use super::lammps::{Header, header};
use super::outline::{Superquadric, superquadrics};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::format::ExportOptions;
use crate::packer::Packing;

/// File name of the LIGGGHTS superquadric data file.
pub const SUPERQUADRIC_DATA: &str = "packing.superquadric.data";

/// File name of the LIGGGHTS commands that turn each particle.
pub const SUPERQUADRIC_INPUT: &str = "packing.superquadric.in";

/// Third semi-axis of an exported superquadric, as a fraction of its
/// smaller in-plane semi-axis: a thin particle, its midplane the 2D one.
pub(super) const THICKNESS_REL: f64 = 0.5;

/// The config name of this format.
const FORMAT: &str = "liggghts-superquadric";

/// The data file of `superquadric_files`.
///
/// # Errors
/// As `superquadric_files`.
pub fn superquadric_data(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    Ok(bytes(superquadric_data_writer(packing, materials, opts)?))
}

/// The `set … quat` commands of `superquadric_files`.
///
/// # Errors
/// As `superquadric_files`.
pub fn superquadric_input(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    Ok(bytes(superquadric_input_writer(packing, materials, opts)?))
}

/// [`superquadric_data`] checked, left to be written where the file goes.
///
/// # Errors
/// As [`superquadric_files`].
pub(crate) fn superquadric_data_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &'a ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    let (e, shapes) = superquadric_files(packing, materials, opts)?;
    Ok(Box::new(move |out| {
        let mut t = Lines::new(out);
        write_data(&mut t, &e, &shapes, materials, opts);
        t.finish()
    }))
}

/// [`superquadric_input`] checked, left to be written where the file goes.
///
/// # Errors
/// As [`superquadric_files`].
pub(crate) fn superquadric_input_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    superquadric_files(packing, materials, opts)?;
    Ok(Box::new(move |out| {
        let mut t = Lines::new(out);
        write_input(&mut t, packing);
        t.finish()
    }))
}

/// The packed particles (superellipses with alpha = beta >= 2) as a
/// LIGGGHTS data file for `atom_style superquadric` (`packing.superquadric.data`)
/// and the `set` commands turning each (`packing.superquadric.in`),
/// lengths in `opts.units`.
///
/// # Layout
/// The data file: a comment line, `N atoms`, `T atom types`, the box
/// (`xlo xhi`, `ylo yhi` holding every particle, `zlo zhi` ± the largest
/// circumradius), for a periodic cell the comment line `# periodic cell:
/// boundary p p p`, comment lines naming the types, then `Atoms` and one line
/// per particle: `id type density shapex shapey shapez blockiness1
/// blockiness2 x y z` — id from 1 in placement order, density in kg per
/// cubic length unit, `shapex` = a and `shapey` = b (the semi-axes along
/// the particle's own axes), `shapez` = 0.5·min(a, b) (a thin third
/// semi-axis: LIGGGHTS runs superquadrics in 3D only), `blockiness1` =
/// `blockiness2` = the exponent, z = 0. LIGGGHTS' superquadric is
/// (|x/a|^n2 + |y/b|^n2)^(n1/n2) + |z/c|^n1 <= 1, whose midplane z = 0 is
/// gapack's |x/a|^n + |y/b|^n <= 1 whatever n1.
///
/// The input file: one `set atom id quat 0 0 1 θ` line per particle (θ its
/// angle in degrees, about z), to `include` after `read_data`.
///
/// # Errors
/// [`OutputError::Unsupported`] for a packing of disks (use `lammps`), a
/// rounded polygon, or a superellipse whose exponents differ or are below
/// 2; [`OutputError::UnknownMaterial`] if a particle's material is not in
/// a non-empty `materials`.
fn superquadric_files<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &ExportOptions,
) -> Result<(Export<'a>, Vec<Superquadric>), OutputError> {
    if packing.grains.is_empty() {
        return Err(OutputError::Unsupported {
            format: FORMAT,
            reason: "the packing is of disks, which the lammps format exports (atom_style sphere)"
                .to_owned(),
        });
    }
    let shapes = superquadrics(&packing.grains, FORMAT)?;
    let e = Export::dem(packing, materials, opts)?;
    Ok((e, shapes))
}

/// The data file of the particles of `e`, `shapes` their superquadrics
/// (see [`superquadric_files`]).
fn write_data(
    t: &mut Lines<'_>,
    e: &Export<'_>,
    shapes: &[Superquadric],
    materials: &[Material],
    opts: &ExportOptions,
) {
    let (s, n) = (e.s, e.len());
    let rho = opts.units.density_per_kg_m3();
    let title = format!(
        "gapack {VERSION}: {n} superquadrics, atom_style superquadric, lengths in {}, density in kg/{}^3, shapez = {THICKNESS_REL} min(shapex, shapey)",
        opts.units.config_name(),
        opts.units.config_name()
    );
    header(
        t,
        e,
        materials,
        &Header {
            title,
            counts: &[(n, "atoms")],
            before: &[],
            after: &[],
        },
    );
    t.line(format_args!(""));
    t.line(format_args!("Atoms"));
    t.line(format_args!(""));
    t.rows(n, |id, b| {
        let (d, q) = (e.row(id), &shapes[id]);
        // Writing to a Vec cannot fail.
        let _ = writeln!(
            b,
            "{} {} {} {} {} {} {} {} {} {} 0",
            d.id + 1,
            type_id(d.material),
            Num(density(materials, d.material, opts) * rho),
            Num(q.a * s),
            Num(q.b * s),
            Num(THICKNESS_REL * q.a.min(q.b) * s),
            Num(q.n),
            Num(q.n),
            d.x,
            d.y
        );
    });
}

/// The `set … quat` commands turning each particle of `packing` (see
/// [`superquadric_files`]).
fn write_input(t: &mut Lines<'_>, packing: &Packing) {
    t.line(format_args!(
        "# gapack {VERSION}: each particle's orientation, a turn about z by its angle (degrees); include after read_data {SUPERQUADRIC_DATA}"
    ));
    t.rows(packing.grains.len(), |i, b| {
        // Writing to a Vec cannot fail.
        let _ = writeln!(
            b,
            "set atom {} quat 0 0 1 {}",
            i + 1,
            Num(packing.grains[i].angle.to_degrees())
        );
    });
}
