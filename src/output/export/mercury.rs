//! `packing.mercury.data`: a MercuryDPM 2D data file.

use super::common::{Export, Num, Text};
use crate::layering::Material;
use crate::output::OutputError;
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
/// # Errors
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn mercury_data(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    let (s, n) = (e.s, e.len());
    let (lo, hi) = e.extent();
    let mut t = Text::with_lines(n + 1);
    t.line(format_args!(
        "{n} 0 {} {} {} {}",
        Num(lo.x * s),
        Num(lo.y * s),
        Num(hi.x * s),
        Num(hi.y * s)
    ));
    for d in e.rows() {
        t.line(format_args!(
            "{} {} 0 0 {} 0 0 {}",
            d.x,
            d.y,
            d.r,
            d.material.unwrap_or(0)
        ));
    }
    Ok(t.into_bytes())
}
