//! `packing.clumps.lammps` and `packing.clumps.liggghts`: data files of
//! rigid clumps of disks for LAMMPS and for LIGGGHTS (`atom_style hybrid
//! sphere molecular`, one molecule per particle): the same atoms, each
//! file saying how its code runs them.

use super::clumps::clumps;
use std::io::Write as _;

use super::common::{Export, Lines, Num, VERSION, Writer, bytes, density, type_id};
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
    Ok(bytes(clumps_data(packing, materials, opts, Code::Lammps)?))
}

/// File name of the LIGGGHTS data file of clumps.
pub const LIGGGHTS_CLUMPS_DATA: &str = "packing.clumps.liggghts";

/// Every packed particle as a clump of spheres (the clumps of
/// `opts.clumps`, as in [`lammps_clumps_data`]) in a LIGGGHTS data file for
/// `read_data`, `atom_style hybrid sphere molecular`, one molecule per
/// particle, for LIGGGHTS' `fix rigid molecule`. A packing of disks gives
/// one sphere per molecule.
///
/// # Why `fix rigid` and not `fix multisphere`
/// LIGGGHTS' own clump fix, `fix multisphere`, takes its bodies only from
/// the insertion fixes (`fix insert/pack`, `insert/stream`,
/// `insert/rate/region`), which place templates
/// (`fix particletemplate/multisphere`) at random points with random or
/// template orientations, and it refuses a molecular atom style, so no
/// data file can hand it bodies at given positions and angles. `fix rigid
/// molecule`, which LIGGGHTS keeps from LAMMPS, integrates each molecule
/// as one rigid body in the same way (the `fix multisphere` docs call the
/// two equivalent), and takes the data file as it is.
///
/// # Layout
/// As [`lammps_clumps_data`]'s, byte for byte in its `Atoms # hybrid`
/// section (`id type x y z diameter density molecule`: LIGGGHTS reads the
/// hybrid sub-styles' columns in the same order); only the first line and
/// the comment line saying how to run it differ.
///
/// # In LIGGGHTS
/// ```text
/// units          si
/// atom_style     hybrid sphere molecular
/// atom_modify    map array
/// boundary       f f p
/// newton         off
/// communicate    single vel yes
/// read_data      packing.clumps.liggghts
/// neigh_modify   delay 0 exclude molecule all
/// (fix property/global material lines, pair_style gran …)
/// fix            bodies all rigid molecule force * on on off torque * off off on
/// ```
/// A 3D run (LIGGGHTS' `fix rigid` warns that its inertia is a 3D body's
/// in 2D) with every sphere at z = 0, each body kept in the plane by the
/// `force` and `torque` flags. Each molecule's mass is the sum of its
/// spheres' (ρ·4/3·π·r³ each in 3D): their overlaps count more than once.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a particle's material is not in a
/// non-empty `materials`.
pub fn liggghts_clumps_data(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    Ok(bytes(clumps_data(
        packing,
        materials,
        opts,
        Code::Liggghts,
    )?))
}

/// [`lammps_clumps_data`] checked, left to be written where the file goes.
///
/// # Errors
/// As [`lammps_clumps_data`].
pub(crate) fn lammps_clumps_data_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &'a ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    clumps_data(packing, materials, opts, Code::Lammps)
}

/// [`liggghts_clumps_data`] checked, left to be written where the file
/// goes.
///
/// # Errors
/// As [`liggghts_clumps_data`].
pub(crate) fn liggghts_clumps_data_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &'a ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    clumps_data(packing, materials, opts, Code::Liggghts)
}

/// Longest comment line of the LIGGGHTS file's header: LIGGGHTS'
/// `read_data` reads a header line into 256 bytes and takes the rest of a
/// longer one for a line of its own, which it refuses (LAMMPS reads any
/// length).
const LIGGGHTS_LINE: usize = 160;

/// `text` as `# ` comment lines of at most `width` characters, broken at
/// spaces (a single longer word stays whole, on a line of its own).
fn comment_lines(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if line.len() + 1 + word.len() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(format!("# {word}")),
        }
    }
    lines
}

/// The code a data file of clumps is for: the same atoms, told how to run.
#[derive(Debug, Clone, Copy)]
enum Code {
    /// LAMMPS: `fix rigid molecule`, `neigh_modify exclude molecule/intra`.
    Lammps,
    /// LIGGGHTS: `fix rigid molecule`, `neigh_modify exclude molecule`.
    Liggghts,
}

/// The data file of clumps for `code` (see [`lammps_clumps_data`] and
/// [`liggghts_clumps_data`]), checked, left to be written.
fn clumps_data<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &'a ExportOptions,
    code: Code,
) -> Result<Writer<'a>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    Ok(Box::new(move |out| {
        let mut t = Lines::new(out);
        write_clumps(&mut t, &e, materials, opts, code);
        t.finish()
    }))
}

/// The data file of clumps for `code`, for the checked export `e`.
fn write_clumps(
    t: &mut Lines<'_>,
    e: &Export<'_>,
    materials: &[Material],
    opts: &ExportOptions,
    code: Code,
) {
    let packing = e.packing;
    let s = e.s;
    let all = clumps(packing, &opts.clumps);
    let atoms = all.disks();
    let rho = opts.units.density_per_kg_m3();
    let u = opts.units.config_name();
    let summary = format!("clumps: {}", all.summary(&opts.clumps));
    let (what, before, after) = match code {
        Code::Lammps => (
            "disks in rigid clumps (one molecule each)",
            vec![format!("# {summary}")],
            vec!["# run with: neigh_modify exclude molecule/intra all; fix bodies all rigid molecule; then fix enforce2d. Mass from density: a sphere per disk (rho*4/3*pi*r^3), overlaps counted more than once".to_owned()],
        ),
        Code::Liggghts => (
            "spheres in rigid clumps (one molecule each) for LIGGGHTS",
            comment_lines(&summary, LIGGGHTS_LINE),
            comment_lines(
                "run with: newton off; neigh_modify exclude molecule all; fix bodies all rigid molecule force * on on off torque * off off on (fix multisphere takes its bodies from fix insert/* only). Mass from density: a sphere per atom in 3D (rho*4/3*pi*r^3), overlaps counted more than once",
                LIGGGHTS_LINE,
            ),
        ),
    };
    let title = format!(
        "gapack {VERSION}: {} particles as {atoms} {what}, atom_style hybrid sphere molecular, lengths in {u} ({}), density in kg/{u}^3",
        e.len(),
        units_style(opts)
    );
    header(
        t,
        e,
        materials,
        &Header {
            title,
            counts: &[(atoms, "atoms")],
            before: &before,
            after: &after,
        },
    );
    if atoms > 0 {
        t.line(format_args!(""));
        t.line(format_args!("Atoms # hybrid"));
        t.line(format_args!(""));
        // The first atom id of each clump's spheres.
        let first: Vec<usize> = all
            .clumps
            .iter()
            .scan(1, |next, clump| {
                let id = *next;
                *next += clump.disks.len();
                Some(id)
            })
            .collect();
        t.rows(e.len(), |i, b| {
            let (row, clump) = (e.row(i), &all.clumps[i]);
            let ty = type_id(row.material);
            let rho = Num(density(materials, row.material, opts) * rho);
            for (k, &(c, r)) in clump.disks.iter().enumerate() {
                // Writing to a Vec cannot fail.
                let _ = writeln!(
                    b,
                    "{} {ty} {} {} 0 {} {rho} {}",
                    first[i] + k,
                    Num(c.x * s),
                    Num(c.y * s),
                    Num(2.0 * r * s),
                    row.id + 1
                );
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain, Grain, Outline};
    use crate::output::format::ClumpOptions;

    /// Two long ellipses side by side, with few disks allowed: their clumps
    /// fall short of the target, so the summary is at its longest.
    fn short_clumps() -> (Packing, ExportOptions) {
        let outline = Outline::superellipse(4.0, 1.0, 2.0, 2.0).unwrap();
        let r = outline.equivalent_radius();
        let mut packing = Packing::of_disks(
            Domain::rectangle(20.0, 10.0).unwrap(),
            vec![Disk::new(6.0, 3.0, r), Disk::new(6.0, 5.0, r)],
        );
        packing.grains = vec![Grain::new(outline.clone(), 0.0); 2];
        let opts = ExportOptions {
            clumps: ClumpOptions {
                coverage: 0.99,
                max_disks: 2,
            },
            ..ExportOptions::default()
        };
        (packing, opts)
    }

    #[test]
    fn the_liggghts_header_fits_its_reader_and_the_atoms_are_the_lammps_ones() {
        let (packing, opts) = short_clumps();
        let liggghts =
            String::from_utf8(liggghts_clumps_data(&packing, &[], &opts).unwrap()).unwrap();
        let lammps = String::from_utf8(lammps_clumps_data(&packing, &[], &opts).unwrap()).unwrap();
        let (head, atoms) = liggghts.split_once("Atoms # hybrid").unwrap();
        assert!(
            head.contains("particles fall short of the target"),
            "{head}"
        );
        assert!(head.lines().all(|l| l.len() < 256), "{head}");
        assert_eq!(
            Some(atoms),
            lammps.split_once("Atoms # hybrid").map(|(_, a)| a)
        );
        assert_eq!(atoms.lines().filter(|l| !l.is_empty()).count(), 4);
        assert!(head.contains("\n4 atoms\n"));
    }

    #[test]
    fn comment_lines_keep_every_word_within_the_width() {
        let text = "one two three four five six seven eight nine ten eleven";
        let lines = comment_lines(text, 16);
        assert!(lines.iter().all(|l| l.starts_with("# ") && l.len() <= 16));
        let words: Vec<&str> = lines
            .iter()
            .flat_map(|l| l.trim_start_matches("# ").split(' '))
            .collect();
        assert_eq!(words.join(" "), text);
        assert_eq!(
            comment_lines("abcdefghijklmnopqrstuvwxyz", 8),
            ["# abcdefghijklmnopqrstuvwxyz"]
        );
    }
}
