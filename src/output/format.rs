//! What a run writes: the formats of `[output]`, the export settings, the directory.

use super::plot::Colouring;
use crate::names::{ConfigName, Names};

/// A file format a run can write, by the name `[output] formats` gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// `packing.csv` (`id,x,y,r[,material]`) and the run's tables.
    Csv,
    /// `packing.json`: disks, domain and summary in one document.
    Json,
    /// `packing.vtk` and `boundary.vtk`: legacy VTK POLYDATA for ParaView.
    Vtk,
    /// `packing.vtp`: VTK XML PolyData, binary, for ParaView at any size.
    Vtp,
    /// `packing.npz`: the packing's columns as numpy arrays.
    Npz,
    /// `packing.lammps`: a LAMMPS / LIGGGHTS data file, `atom_style sphere`.
    Lammps,
    /// `packing.yade.txt`: YADE's `ymport.text` format.
    Yade,
    /// `packing.p2dat`: a PFC2D command file.
    Pfc,
    /// `packing.mercury.data`: a MercuryDPM 2D data file.
    Mercury,
    /// `packing.superquadric.data` and `.in`: superellipses for LIGGGHTS'
    /// `atom_style superquadric`.
    LiggghtsSuperquadric,
    /// `packing.geo`: an ESyS-Particle 2D geometry file.
    Esys,
    /// `packing.clumps.lammps`: a LAMMPS data file of rigid clumps of
    /// disks, one molecule per particle (`fix rigid molecule`).
    LammpsClumps,
    /// `packing.clumps.liggghts`: the same clumps for LIGGGHTS' `fix rigid
    /// molecule` (its `fix multisphere` takes no bodies from a data file).
    LiggghtsClumps,
    /// Pictures as SVG: the packing, its grading, its porosity map, the run's charts.
    Svg,
    /// The same pictures as PNG.
    Png,
}

impl Format {
    /// The formats written when `[output] formats` is not given.
    pub const DEFAULT: [Format; 3] = [Format::Csv, Format::Svg, Format::Png];
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
}

pub(crate) const FORMATS: Names<Format> = Names {
    what: "format",
    entries: &[
        ("csv", Format::Csv),
        ("json", Format::Json),
        ("vtk", Format::Vtk),
        ("vtp", Format::Vtp),
        ("npz", Format::Npz),
        ("lammps", Format::Lammps),
        ("yade", Format::Yade),
        ("pfc", Format::Pfc),
        ("mercury", Format::Mercury),
        ("liggghts-superquadric", Format::LiggghtsSuperquadric),
        ("esys", Format::Esys),
        ("lammps-clumps", Format::LammpsClumps),
        ("liggghts-clumps", Format::LiggghtsClumps),
        ("svg", Format::Svg),
        ("png", Format::Png),
    ],
};

pub(crate) const UNITS: Names<LengthUnit> = Names {
    what: "length unit",
    entries: &[("m", LengthUnit::Metre), ("mm", LengthUnit::Millimetre)],
};

impl ConfigName for Format {
    fn config_name(&self) -> &'static str {
        FORMATS.name_of(*self)
    }
}

impl ConfigName for LengthUnit {
    fn config_name(&self) -> &'static str {
        UNITS.name_of(*self)
    }
}

/// How `packing.vtp` stores its arrays (`[output] vtp_compression`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VtpCompression {
    /// Raw little-endian values (the default): fastest to write and read.
    #[default]
    None,
    /// Each array zlib-compressed in blocks, as VTK's
    /// `vtkZLibDataCompressor` writes them: smaller, slower to write.
    Zlib,
}

/// The names `[output] vtp_compression` takes.
pub(crate) const VTP_COMPRESSIONS: Names<VtpCompression> = Names {
    what: "vtp compression",
    entries: &[
        ("none", VtpCompression::None),
        ("zlib", VtpCompression::Zlib),
    ],
};

impl ConfigName for VtpCompression {
    fn config_name(&self) -> &'static str {
        VTP_COMPRESSIONS.name_of(*self)
    }
}

/// A per-particle figure `[output] per_particle` adds to `packing.csv`
/// (a last column), `packing.vtp` (a point array) and `packing.npz` (an
/// array), each under its config name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PerParticle {
    /// The meshless support size h6 (mm): the distance from the particle's
    /// centre to its 6th nearest neighbour's ([`crate::meshless::h6`]).
    H6,
}

/// The names `[output] per_particle` takes.
pub(crate) const PER_PARTICLE: Names<PerParticle> = Names {
    what: "per-particle column",
    entries: &[("h6", PerParticle::H6)],
};

impl ConfigName for PerParticle {
    fn config_name(&self) -> &'static str {
        PER_PARTICLE.name_of(*self)
    }
}

/// A per-particle column a run adds to its tables: its name and one value
/// per packed particle, in placement order.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleColumn {
    /// Its name: the header of `packing.csv`, the array's name elsewhere.
    pub name: &'static str,
    /// One value per packed particle.
    pub values: Vec<f64>,
}

impl ParticleColumn {
    /// The column `what` of `packing`.
    pub fn of(what: PerParticle, packing: &crate::Packing) -> Self {
        let values = match what {
            PerParticle::H6 => crate::meshless::h6(packing),
        };
        ParticleColumn {
            name: what.config_name(),
            values,
        }
    }

    /// Value `i`, NaN beyond the values.
    pub(crate) fn at(&self, i: usize) -> f64 {
        self.values.get(i).copied().unwrap_or(f64::NAN)
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
    /// How non-disk particles become clumps of disks in the DEM exports.
    pub clumps: ClumpOptions,
}

/// How a non-disk particle becomes a clump of overlapping disks, all
/// inside it (`[output] clump_coverage`, `clump_max_disks`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClumpOptions {
    /// Share of each particle's area its disks should cover, in (0, 0.99].
    pub coverage: f64,
    /// Most disks per particle (at least 1).
    pub max_disks: usize,
}

impl ClumpOptions {
    /// Default coverage target.
    pub const DEFAULT_COVERAGE: f64 = 0.9;
    /// Largest coverage target accepted: the last percent needs ever more,
    /// ever smaller disks in the particle's corners.
    pub const MAX_COVERAGE: f64 = 0.99;
    /// Default cap of disks per particle.
    pub const DEFAULT_MAX_DISKS: usize = 32;
    /// Largest cap accepted.
    pub const MOST_DISKS: usize = 1024;
}

impl Default for ClumpOptions {
    fn default() -> Self {
        ClumpOptions {
            coverage: Self::DEFAULT_COVERAGE,
            max_disks: Self::DEFAULT_MAX_DISKS,
        }
    }
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
            clumps: ClumpOptions::default(),
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
    /// How the packing's pictures colour the particles (`colour`); `None`:
    /// by material when there are materials, else by size.
    pub colour: Option<Colouring>,
    /// How `packing.vtp` stores its arrays (`vtp_compression`).
    pub vtp_compression: VtpCompression,
    /// Per-particle figures added to `packing.csv`, `.vtp` and `.npz`
    /// (`per_particle`), each once, in config order; none by default.
    pub per_particle: Vec<PerParticle>,
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
            colour: None,
            vtp_compression: VtpCompression::None,
            per_particle: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (name, value) in FORMATS.entries {
            assert_eq!(FORMATS.get(name), Some(*value));
            assert_eq!(value.config_name(), *name);
        }
        assert_eq!(Format::Lammps.config_name(), "lammps");
        assert_eq!(LengthUnit::Millimetre.config_name(), "mm");
    }
}
