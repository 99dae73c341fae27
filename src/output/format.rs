//! What a run writes: the formats of `[output]`, the export settings, the directory.

/// A file format a run can write, by the name `[output] formats` gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// `packing.csv` (`id,x,y,r[,material]`) and the run's tables.
    Csv,
    /// `packing.json`: disks, domain and summary in one document.
    Json,
    /// `packing.vtk` and `boundary.vtk`: legacy VTK POLYDATA for ParaView.
    Vtk,
    /// `packing.lammps`: a LAMMPS / LIGGGHTS data file, `atom_style sphere`.
    Lammps,
    /// `packing.yade.txt`: YADE's `ymport.text` format.
    Yade,
    /// `packing.p2dat`: a PFC2D command file.
    Pfc,
    /// `packing.mercury.data`: a MercuryDPM 2D data file.
    Mercury,
    /// `packing.geo`: an ESyS-Particle 2D geometry file.
    Esys,
    /// Pictures as SVG: the packing, its grading, its porosity map, the run's charts.
    Svg,
    /// The same pictures as PNG.
    Png,
}

impl Format {
    /// Every format, in the order the names are listed in messages.
    pub const ALL: [Format; 10] = [
        Format::Csv,
        Format::Json,
        Format::Vtk,
        Format::Lammps,
        Format::Yade,
        Format::Pfc,
        Format::Mercury,
        Format::Esys,
        Format::Svg,
        Format::Png,
    ];

    /// The formats written when `[output] formats` is not given.
    pub const DEFAULT: [Format; 3] = [Format::Csv, Format::Svg, Format::Png];

    /// The name written in a config.
    pub fn name(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Json => "json",
            Format::Vtk => "vtk",
            Format::Lammps => "lammps",
            Format::Yade => "yade",
            Format::Pfc => "pfc",
            Format::Mercury => "mercury",
            Format::Esys => "esys",
            Format::Svg => "svg",
            Format::Png => "png",
        }
    }

    /// The format named `name`, if it is one.
    pub fn from_name(name: &str) -> Option<Format> {
        Format::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// Length unit of the DEM exports (LAMMPS, YADE, PFC, MercuryDPM, ESyS).
///
/// gapack works in millimetres; DEM codes are mostly run in SI, where a
/// density in kg/m³ only fits lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LengthUnit {
    /// Metres: coordinates and radii divided by 1000 (the default).
    #[default]
    Metre,
    /// Millimetres: gapack's own numbers.
    Millimetre,
}

impl LengthUnit {
    /// Every unit, in the order the names are listed in messages.
    pub const ALL: [LengthUnit; 2] = [LengthUnit::Metre, LengthUnit::Millimetre];

    /// The unit's length for one millimetre (0.001 for metres).
    pub fn per_mm(self) -> f64 {
        match self {
            LengthUnit::Metre => 1e-3,
            LengthUnit::Millimetre => 1.0,
        }
    }

    /// Factor from kg/m³ to kg per cubic unit: `1` for metres, `1e-9` for
    /// millimetres, so that density × volume is a mass in kg either way.
    pub(crate) fn density_per_kg_m3(self) -> f64 {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Millimetre => 1e-9,
        }
    }

    /// The name written in a config and in file headers (`"m"`, `"mm"`).
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Millimetre => "mm",
        }
    }

    /// The unit named `name`, if it is one.
    pub fn from_name(name: &str) -> Option<LengthUnit> {
        LengthUnit::ALL.into_iter().find(|u| u.name() == name)
    }
}

/// Settings shared by the DEM exports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExportOptions {
    /// Density (kg/m³) of disks whose material gives no `density` property,
    /// or of every disk when there are no materials.
    pub density: f64,
    /// Length unit of the DEM exports.
    pub units: LengthUnit,
}

impl ExportOptions {
    /// Quartz, the usual proppant and sand mineral (kg/m³).
    pub const DEFAULT_DENSITY: f64 = 2650.0;
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            density: Self::DEFAULT_DENSITY,
            units: LengthUnit::default(),
        }
    }
}

/// `[output]`: where a run writes and what.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputSettings {
    /// Output directory as written in the config (relative to the working
    /// directory); `None` lets the command choose (`out/<config stem>`).
    pub dir: Option<String>,
    /// The formats to write, each once, in config order.
    pub formats: Vec<Format>,
    /// Settings of the DEM exports.
    pub export: ExportOptions,
}

impl OutputSettings {
    /// Whether `format` is asked for.
    pub fn wants(&self, format: Format) -> bool {
        self.formats.contains(&format)
    }
}

impl Default for OutputSettings {
    fn default() -> Self {
        OutputSettings {
            dir: None,
            formats: Format::DEFAULT.to_vec(),
            export: ExportOptions::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for f in Format::ALL {
            assert_eq!(Format::from_name(f.name()), Some(f));
        }
        for u in LengthUnit::ALL {
            assert_eq!(LengthUnit::from_name(u.name()), Some(u));
        }
        assert_eq!(Format::from_name("xyz"), None);
        assert_eq!(LengthUnit::from_name("km"), None);
    }
}
