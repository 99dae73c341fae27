//! `packing.mercury.data`: a MercuryDPM 2D data file.

use std::io::Write as _;

use super::common::{Export, Lines, Num, VERSION, Writer, bytes, extent, push_num};
use super::liggghts::THICKNESS_REL;
use super::outline::{Superquadric, superquadrics};
use crate::layering::Material;
use crate::output::OutputError;
use crate::output::digits::push_int;
use crate::output::format::ExportOptions;
use crate::packer::Packing;

/// File name of the MercuryDPM data file.
pub const MERCURY_DATA: &str = "packing.mercury.data";

/// The packed disks (not the wall disks) as one time step of a MercuryDPM
/// data file in its 2D layout (format 8), lengths in `opts.units`.
///
/// # Layout
/// A first line `N time xmin ymin xmax ymax` (time 0; the box holds the
/// domain and every disk), then one line per disk in placement order:
/// `x y vx vy radius angle omega species`, with velocities, angle and
/// angular velocity 0 and `species` the material index (from 0; 0 without
/// materials) — MercuryDPM takes it as an index into its species handler.
/// No comments: MercuryDPM reads the first number as the count. Densities
/// are not in the file: they belong to MercuryDPM's species. A periodic
/// cell's box is the cell itself, but the format has no place to declare
/// it periodic: the driver adds the periodic boundaries (below).
///
/// # In MercuryDPM
/// In the driver, before `solve()` (in `setupInitialConditions`):
/// ```text
/// setSystemDimensions(2);
/// setParticleDimensions(2);
/// speciesHandler.copyAndAddObject(species);  // one per material, config order
/// readSpeciesFromDataFile(true);              // only with several materials
/// readDataFile("packing.mercury.data", 8);
/// ```
/// For a periodic cell (`walls = "periodic"`), before reading the data,
/// one `PeriodicBoundary` per axis on the box's bounds:
/// ```text
/// PeriodicBoundary bx, by;
/// bx.set(Vec3D(1, 0, 0), xmin, xmax);
/// by.set(Vec3D(0, 1, 0), ymin, ymax);
/// boundaryHandler.copyAndAddObject(bx);
/// boundaryHandler.copyAndAddObject(by);
/// ```
///
/// # Particles that are not disks
/// MercuryDPM's data files (formats 7, 8, 14) hold spheres only. With
/// non-empty `packing.grains` (superellipses with alpha = beta >= 2) the
/// file is instead a table for the driver to build `SuperQuadricParticle`s
/// from: a first line `# gapack <version>: N superquadrics, …` naming the
/// columns, a second line `N 0 xmin ymin xmax ymax` as above, then per
/// particle `x y z q0 q1 q2 q3 a b c eps1 eps2 species`: the centre (z =
/// 0), the orientation quaternion (q0 = cos(θ/2), q3 = sin(θ/2): a turn by
/// the angle θ about z), the semi-axes a, b and c = 0.5·min(a, b) (a thin
/// third one), the exponents eps1 = eps2 = 2/n (MercuryDPM's superquadric
/// (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1) + |z/c|^(2/eps1) <= 1;
/// its midplane is gapack's |x/a|^n + |y/b|^n <= 1) and the species index.
/// In the driver, per line:
/// ```text
/// SuperQuadricParticle p;
/// p.setSpecies(speciesHandler.getObject(species));
/// p.setAxesAndExponents(a, b, c, eps1, eps2);
/// p.setPosition(Vec3D(x, y, z));
/// p.setOrientation(Quaternion(q0, q1, q2, q3));
/// particleHandler.copyAndAddObject(p);
/// ```
///
/// # Errors
/// [`OutputError::Unsupported`] for a rounded polygon or a superellipse
/// whose exponents differ or are below 2 (no superquadric);
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn mercury_data(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    Ok(bytes(mercury_data_writer(packing, materials, opts)?))
}

/// [`mercury_data`] checked, left to be written where the file goes.
///
/// # Errors
/// As [`mercury_data`].
pub(crate) fn mercury_data_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    if !packing.grains.is_empty() {
        let shapes = superquadrics(&packing.grains, "mercury")?;
        return Ok(Box::new(move |out| {
            let mut t = Lines::new(out);
            superquadric_table(&mut t, &e, &shapes);
            t.finish()
        }));
    }
    Ok(Box::new(move |out| {
        let mut t = Lines::new(out);
        disk_table(&mut t, &e);
        t.finish()
    }))
}

/// The table of the disks of `e` (see [`mercury_data`]).
fn disk_table(t: &mut Lines<'_>, e: &Export<'_>) {
    let (s, n) = (e.s, e.len());
    let (lo, hi) = e.extent();
    t.line(format_args!(
        "{n} 0 {} {} {} {}",
        Num(lo.x * s),
        Num(lo.y * s),
        Num(hi.x * s),
        Num(hi.y * s)
    ));
    // `x y 0 0 r 0 0 species`
    t.rows(n, |id, b| {
        let d = e.row(id);
        push_num(b, d.x.0);
        b.push(b' ');
        push_num(b, d.y.0);
        b.extend_from_slice(b" 0 0 ");
        push_num(b, d.r.0);
        b.extend_from_slice(b" 0 0 ");
        push_int(b, d.material.unwrap_or(0));
        b.push(b'\n');
    });
}

/// The superquadric table of a packing with grains, `shapes` its
/// superquadrics (see [`mercury_data`]).
fn superquadric_table(t: &mut Lines<'_>, e: &Export<'_>, shapes: &[Superquadric]) {
    let packing = e.packing;
    let (s, n) = (e.s, e.len());
    let (lo, hi) = extent(packing);
    t.line(format_args!(
        "# gapack {VERSION}: {n} superquadrics for SuperQuadricParticle (not a MercuryDPM data file): x y z q0 q1 q2 q3 a b c eps1 eps2 species"
    ));
    t.line(format_args!(
        "{n} 0 {} {} {} {}",
        Num(lo.x * s),
        Num(lo.y * s),
        Num(hi.x * s),
        Num(hi.y * s)
    ));
    t.rows(n, |id, b| {
        let (d, q, g) = (e.row(id), &shapes[id], &packing.grains[id]);
        let (sin, cos) = (0.5 * g.angle).sin_cos();
        let eps = 2.0 / q.n;
        // Writing to a Vec cannot fail.
        let _ = writeln!(
            b,
            "{} {} 0 {} 0 0 {} {} {} {} {} {} {}",
            d.x,
            d.y,
            Num(cos),
            Num(sin),
            Num(q.a * s),
            Num(q.b * s),
            Num(THICKNESS_REL * q.a.min(q.b) * s),
            Num(eps),
            Num(eps),
            d.material.unwrap_or(0)
        );
    });
}
