//! What the DEM exports share: the length unit and the fallback density.

/// Length unit of the DEM exports.
///
/// gapack works in millimetres; DEM codes are most often run in SI units, so
/// the exports default to metres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LengthUnit {
    /// Metres (SI, as LIGGGHTS, YADE and PFC users usually run).
    #[default]
    Metre,
    /// Millimetres (gapack's own unit).
    Millimetre,
}

impl LengthUnit {
    /// How many of this unit make one millimetre: `0.001` for metres, `1.0`
    /// for millimetres. A length in mm times this factor is the exported length.
    pub fn per_mm(self) -> f64 {
        match self {
            LengthUnit::Metre => 0.001,
            LengthUnit::Millimetre => 1.0,
        }
    }

    /// The unit's symbol as written in file headers: `m` or `mm`.
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Millimetre => "mm",
        }
    }

    /// Factor from kg/m³ to kg per cubic unit: `1` for metres, `1e-9` for
    /// millimetres, so that density × volume is a mass in kg either way.
    pub(super) fn density_per_kg_m3(self) -> f64 {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Millimetre => 1e-9,
        }
    }
}

/// Settings shared by the DEM exports.
///
/// # Example
/// ```
/// use gapack::output::{ExportOptions, LengthUnit};
/// let opts = ExportOptions::default();
/// assert_eq!(opts.density, 2650.0);
/// assert_eq!(opts.units, LengthUnit::Metre);
/// assert_eq!(opts.units.per_mm(), 0.001);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExportOptions {
    /// Density (kg/m³) of disks whose material gives no `density` property
    /// (or when there are no materials). Default 2650 (quartz sand).
    pub density: f64,
    /// Length unit of the DEM exports: metres (default, SI as LIGGGHTS, YADE
    /// and PFC users run) or millimetres (gapack's own unit).
    pub units: LengthUnit,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            density: 2650.0,
            units: LengthUnit::Metre,
        }
    }
}
