//! `packing.lammps`: a LAMMPS / LIGGGHTS data file (`atom_style sphere`;
//! `atom_style body rounded/polygon` for particles that are not disks).

use super::common::{Export, Num, Text, VERSION, density, labels, type_count, type_id};
use super::outline::{Moments, Rounded, turned};
use crate::geometry::Point;
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
/// # Particles that are not disks
/// With non-empty `packing.grains` the file is for `atom_style body
/// rounded/polygon` instead: each particle a LAMMPS rounded polygon that
/// lies **inside** it (so that a packing without overlaps stays without
/// contacts). A rounded polygon keeps its vertices and corner radius ρ when
/// ρ is at least 1 % of its least width w; otherwise (sharp corners) its
/// polygon is shrunk by 0.01·w − ρ and rounded by 0.01·w. A superellipse
/// becomes the polygon of 48 points on its outline (inscribed), shrunk by
/// 0.01·w and rounded by 0.01·w. The header adds `N bodies`; the comment
/// lines give the fewest and most vertices (`atom_style body
/// rounded/polygon Nmin Nmax` needs them); `Atoms # body` lines are `id
/// type 1 mass x y z`, the mass that of a slab of the rounded polygon one
/// length unit thick (ρ·area·1; in metres, per metre of thickness); the
/// `Bodies` section gives per particle the line `id 1 M` (one integer, M =
/// 6 + 3N + 1 doubles), the vertex count N, the inertia tensor `Ixx Iyy
/// Izz Ixy Ixz Iyz` of that slab (about its centre, world axes), the N
/// vertex offsets `x y 0` from the centre (world axes: the particle's
/// angle applied), four a line (`x y 0 x y 0 …`: LAMMPS reads the
/// numbers as one stream but allows at most 32 lines a body), and the
/// rounding diameter. See docs/outputs.md for the
/// input script (`pair_style body/rounded/polygon`).
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
    if !packing.grains.is_empty() {
        return Ok(body_data(&e, materials, opts));
    }
    let n = e.len();
    let rho = opts.units.density_per_kg_m3();
    let mut t = Text::with_lines(n + 24);
    let title = format!(
        "gapack {VERSION}: {n} disks, atom_style sphere, lengths in {} ({}), density in kg/{}^3",
        opts.units.config_name(),
        units_style(opts),
        opts.units.config_name()
    );
    header(
        &mut t,
        &e,
        materials,
        &Header {
            title,
            counts: &[(n, "atoms")],
            before: &[],
            after: &["# mass from density: LAMMPS read_data, a sphere (rho*4/3*pi*r^3); LIGGGHTS with dimension 2, a disc of unit thickness (rho*pi*r^2)".to_owned()],
        },
    );
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

/// What a gapack data file for `read_data` (LAMMPS or LIGGGHTS) says in its
/// header besides the box and the types.
pub(super) struct Header<'a> {
    /// The first line (`read_data` skips it): version, counts, units.
    pub(super) title: String,
    /// The counts after it, each `N name` (`N atoms`, `N bodies`).
    pub(super) counts: &'a [(usize, &'a str)],
    /// Comment lines after the box, before a periodic cell's.
    pub(super) before: &'a [String],
    /// Comment lines after a periodic cell's, before the types' names.
    pub(super) after: &'a [String],
}

/// The header of a data file for `read_data`: `h.title`, a blank line,
/// `h.counts`, `T atom types` (one per material, at least one), a blank
/// line, `xlo xhi` and `ylo yhi` (the export's extent), `zlo zhi` (± the
/// largest radius or circumradius: a 2d box must straddle z = 0; ± 0.5
/// without particles), `h.before`, for a periodic cell the comment line
/// `# periodic cell: boundary p p p` (a data file has no boundary keyword:
/// the input script sets it), `h.after`, then `# type i = name` per
/// material. One header for every such file, so that they all agree.
pub(super) fn header(t: &mut Text, e: &Export<'_>, materials: &[Material], h: &Header<'_>) {
    let s = e.s;
    let (lo, hi) = e.extent();
    let r = e.r_max();
    let z = if r > 0.0 { r * s } else { 0.5 };
    t.line(format_args!("{}", h.title));
    t.line(format_args!(""));
    for (count, name) in h.counts {
        t.line(format_args!("{count} {name}"));
    }
    t.line(format_args!("{} atom types", type_count(materials)));
    t.line(format_args!(""));
    t.line(format_args!("{} {} xlo xhi", Num(lo.x * s), Num(hi.x * s)));
    t.line(format_args!("{} {} ylo yhi", Num(lo.y * s), Num(hi.y * s)));
    t.line(format_args!("{} {} zlo zhi", Num(-z), Num(z)));
    for note in h.before {
        t.line(format_args!("{note}"));
    }
    if e.packing.domain.is_periodic() {
        t.line(format_args!(
            "# periodic cell: boundary p p p (x and y periodic: the cell is the box; z periodic as for any 2d run)"
        ));
    }
    for note in h.after {
        t.line(format_args!("{note}"));
    }
    for (i, label) in labels(materials).iter().enumerate() {
        t.line(format_args!("# type {} = {label}", i + 1));
    }
}

/// The LAMMPS `units` style matching the export's length unit, for the
/// title line.
pub(super) fn units_style(opts: &ExportOptions) -> &'static str {
    match opts.units {
        LengthUnit::Metre => "units si",
        LengthUnit::Millimetre => "no LAMMPS units style matches mm",
    }
}

/// Vertices on one line of a body in the data file.
const VERTICES_PER_LINE: usize = 4;

/// The `atom_style body rounded/polygon` data file of a packing with grains
/// (see [`lammps_data`]).
fn body_data(e: &Export<'_>, materials: &[Material], opts: &ExportOptions) -> Vec<u8> {
    let packing = e.packing;
    let (s, n) = (e.s, e.len());
    let rho = opts.units.density_per_kg_m3();
    let bodies: Vec<(Rounded, Vec<Point>)> = packing
        .grains
        .iter()
        .map(|g| {
            let r = Rounded::of(&g.outline);
            let world = turned(g, &r.core);
            (r, world)
        })
        .collect();
    let counts = bodies.iter().map(|(_, w)| w.len());
    let (nmin, nmax) = (counts.clone().min().unwrap_or(3), counts.max().unwrap_or(3));
    let mut t = Text::with_lines(n * 60 + 32);
    let title = format!(
        "gapack {VERSION}: {n} particles, atom_style body rounded/polygon {nmin} {nmax}, lengths in {} ({}), mass in kg per length unit of thickness",
        opts.units.config_name(),
        units_style(opts)
    );
    header(
        &mut t,
        e,
        materials,
        &Header {
            title,
            counts: &[(n, "atoms"), (n, "bodies")],
            before: &[],
            after: &[
                format!(
                    "# vertices per body: min {nmin}, max {nmax} (atom_style body rounded/polygon {nmin} {nmax})"
                ),
                "# each body a rounded polygon inside the particle; mass and inertia of a slab one length unit thick".to_owned(),
            ],
        },
    );
    if n == 0 {
        return t.into_bytes();
    }
    // Mass and area moments about the centre (world axes), per body.
    let slabs: Vec<(f64, Moments)> = bodies
        .iter()
        .zip(e.rows())
        .map(|((r, _), d)| {
            let fine = r.fine();
            let grain = &packing.grains[d.id];
            let m = Moments::of(&turned(grain, &fine));
            let density = density(materials, d.material, opts) * rho;
            (density * m.area * s * s, m)
        })
        .collect();
    t.line(format_args!(""));
    t.line(format_args!("Atoms # body"));
    t.line(format_args!(""));
    for (d, (mass, _)) in e.rows().zip(&slabs) {
        t.line(format_args!(
            "{} {} 1 {} {} {} 0",
            d.id + 1,
            type_id(d.material),
            Num(*mass),
            d.x,
            d.y
        ));
    }
    t.line(format_args!(""));
    t.line(format_args!("Bodies"));
    t.line(format_args!(""));
    for ((d, (mass, m)), (r, world)) in e.rows().zip(&slabs).zip(&bodies) {
        let k = world.len();
        t.line(format_args!("{} 1 {}", d.id + 1, 6 + 3 * k + 1));
        t.line(format_args!("{k}"));
        // Per unit area, times the mass: second moments in the file's unit.
        let per = if m.area > 0.0 {
            mass / m.area * s * s
        } else {
            0.0
        };
        let (ixx, iyy, ixy) = (per * m.yy, per * m.xx, -per * m.xy);
        t.line(format_args!(
            "{} {} {} {} 0 0",
            Num(ixx),
            Num(iyy),
            Num(ixx + iyy),
            Num(ixy)
        ));
        // Several vertices a line: LAMMPS reads a body's numbers as one
        // stream, but refuses bodies of more than 32 lines.
        for chunk in world.chunks(VERTICES_PER_LINE) {
            let line: Vec<String> = chunk
                .iter()
                .map(|p| format!("{} {} 0", Num(p.x * s), Num(p.y * s)))
                .collect();
            t.line(format_args!("{}", line.join(" ")));
        }
        t.line(format_args!("{}", Num(2.0 * r.rounding * s)));
    }
    t.into_bytes()
}
