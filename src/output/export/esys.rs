//! `packing.geo`: an ESyS-Particle geometry file, 2D.

use super::common::{Export, Lines, Num, Writer, bytes, push_num, type_id};
use crate::layering::Material;
use crate::output::OutputError;
use crate::output::digits::push_int;
use crate::output::format::ExportOptions;
use crate::packer::Packing;

/// File name of the ESyS-Particle geometry.
pub const ESYS_GEOMETRY: &str = "packing.geo";

/// The packed disks (not the wall disks) as an ESyS-Particle geometry file
/// (`LSMGeometry 1.2`, as GenGeo writes it), 2D, lengths in `opts.units`.
///
/// # Layout
/// ```text
/// LSMGeometry 1.2
/// BoundingBox xmin ymin zmin xmax ymax zmax
/// PeriodicBoundaries 0 0 0
/// Dimension 2D
/// BeginParticles
/// Simple
/// N
/// x y z r id tag        (N lines)
/// EndParticles
/// BeginConnect
/// 0
/// EndConnect
/// ```
/// The box holds the domain and every disk, z from minus to plus the
/// largest radius (a periodic cell: the cell, with `PeriodicBoundaries 1 1
/// 0`, periodic along x and y); z = 0; `id` from 0 in placement order (`packing.csv`'s
/// id); `tag` the material index + 1 (1 without materials); no bonds. No
/// comments: ESyS reads the file token by token. Densities are not in the
/// file: set them per tag.
///
/// # In ESyS-Particle
/// ```text
/// sim.readGeometry("packing.geo")
/// sim.setParticleDensity(tag=1, mask=-1, Density=2650.0)
/// ```
///
/// # Errors
/// [`OutputError::Unsupported`] for particles that are not disks
/// (non-empty `packing.grains`): the file holds spheres only;
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn esys_geometry(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    Ok(bytes(esys_geometry_writer(packing, materials, opts)?))
}

/// [`esys_geometry`] checked, left to be written where the file goes.
///
/// # Errors
/// As [`esys_geometry`].
pub(crate) fn esys_geometry_writer<'a>(
    packing: &'a Packing,
    materials: &'a [Material],
    opts: &ExportOptions,
) -> Result<Writer<'a>, OutputError> {
    if !packing.grains.is_empty() {
        return Err(OutputError::Unsupported {
            format: "esys",
            reason: "ESyS-Particle's geometry files hold spheres only, and these particles are not disks; export them as lammps (body rounded/polygon), liggghts-superquadric, mercury or vtk".to_owned(),
        });
    }
    let e = Export::dem(packing, materials, opts)?;
    Ok(Box::new(move |out| {
        let mut t = Lines::new(out);
        write_geometry(&mut t, &e);
        t.finish()
    }))
}

/// The geometry file of the disks of `e` (see [`esys_geometry`]).
fn write_geometry(t: &mut Lines<'_>, e: &Export<'_>) {
    let (s, n) = (e.s, e.len());
    let (lo, hi) = e.extent();
    let z = e.r_max() * s;
    t.line(format_args!("LSMGeometry 1.2"));
    t.line(format_args!(
        "BoundingBox {} {} {} {} {} {}",
        Num(lo.x * s),
        Num(lo.y * s),
        Num(-z),
        Num(hi.x * s),
        Num(hi.y * s),
        Num(z)
    ));
    let periodic = u8::from(e.packing.domain.is_periodic());
    t.line(format_args!("PeriodicBoundaries {periodic} {periodic} 0"));
    t.line(format_args!("Dimension 2D"));
    t.line(format_args!("BeginParticles"));
    t.line(format_args!("Simple"));
    t.line(format_args!("{n}"));
    // `x y 0 r id type`
    t.rows(n, |id, b| {
        let d = e.row(id);
        push_num(b, d.x.0);
        b.push(b' ');
        push_num(b, d.y.0);
        b.extend_from_slice(b" 0 ");
        push_num(b, d.r.0);
        b.push(b' ');
        push_int(b, id);
        b.push(b' ');
        push_int(b, type_id(d.material));
        b.push(b'\n');
    });
    t.line(format_args!("EndParticles"));
    t.line(format_args!("BeginConnect"));
    t.line(format_args!("0"));
    t.line(format_args!("EndConnect"));
}
