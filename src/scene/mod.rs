//! The validated scene: everything the packer needs, nothing it does not:
//! the domain and grading, the packer's settings, and in size-graded mode
//! the profile the sizes follow.

mod profile;
mod proppant;
mod settings;
mod shape;

pub use profile::{Axis, Frame, Profile, SizeGradient};
pub use proppant::Proppant;
pub use settings::{
    DEFAULT_ATTEMPTS, Densify, Fill, FrontRules, IndexKind, MAX_DEFERRED, MAX_GAP, Method,
    PackerSettings, Relaxation, Strips,
};
pub use shape::{
    Drawer, Family, MAX_ASPECT, MAX_EXPONENT, Orientation, SHAPE_STREAM, ShapeSpec, SizeMeasure,
    Spread, template_vertices,
};

use crate::geometry::{Domain, WallMode};
use crate::grading::Grading;

/// A validated scene: domain, wall model, grading curve, packer settings and seed.
///
/// Built from a config (`config::parse`) or in code by [`Scene::new`] and
/// its `with_*` methods; the same scene and seed always give the same packing.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Scene {
    /// The region to fill (mm).
    pub domain: Domain,
    /// How walls are modelled: exact lines and arcs, discretised into
    /// disks, or none (a periodic cell, whose domain is then
    /// [`Domain::periodic_rectangle`]: see [`Scene::with_walls`]).
    pub walls: WallMode,
    /// Diameter of the wall disks for `walls = "disks"`; `None` uses
    /// [`Scene::DEFAULT_WALL_DISK_FRACTION`] of the grading's smallest diameter.
    pub wall_disk_diameter: Option<f64>,
    /// The grading curve sizes are drawn from (in size-graded mode, the
    /// first material's).
    pub grading: Grading,
    /// Size-graded mode: the grading blends into a second curve along an axis.
    pub gradient: Option<SizeGradient>,
    /// Packer method, spatial index and contact rule.
    pub packer: PackerSettings,
    /// Seed of the random sizes (and of one-contact placement angles).
    pub seed: u64,
    /// Ceilings the run stops at (none unless set).
    pub limits: Limits,
    /// The particles' shape (`[shape]`); `None`: disks.
    pub shape: Option<ShapeSpec>,
}

/// Ceilings a run may not pass: it stops with an error when it reaches
/// one, rather than write a packing bigger than the user allows.
///
/// A config sets them from `[limits]`; the refusals made before a run on
/// the scene's upper bounds ([`Scene::max_disks`]) are the config's.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub struct Limits {
    /// Most disks a packing may hold (wall disks aside).
    pub max_particles: Option<u64>,
    /// Most memory (bytes) the run may take, counted as the estimate counts
    /// it: every obstacle (wall disks too) at `PEAK_BYTES_PER_DISK` bytes,
    /// or every particle at `PEAK_BYTES_PER_GRAIN` with a shape.
    pub max_memory_bytes: Option<f64>,
}

impl Limits {
    /// No ceiling.
    pub fn none() -> Limits {
        Limits::default()
    }

    /// These limits with a ceiling on the disks a packing may hold.
    #[must_use]
    pub fn with_max_particles(self, max: u64) -> Limits {
        Limits {
            max_particles: Some(max),
            ..self
        }
    }

    /// These limits with a ceiling on the run's memory (bytes).
    #[must_use]
    pub fn with_max_memory_bytes(self, max: f64) -> Limits {
        Limits {
            max_memory_bytes: Some(max),
            ..self
        }
    }
}

impl Scene {
    /// A scene of `domain` filled with sizes of `grading`: exact walls, the
    /// default packer settings, seed 0.
    pub fn new(domain: Domain, grading: Grading) -> Scene {
        Scene {
            domain,
            walls: WallMode::Exact,
            wall_disk_diameter: None,
            grading,
            gradient: None,
            packer: PackerSettings::default(),
            seed: 0,
            limits: Limits::none(),
            shape: None,
        }
    }

    /// The same scene with another seed.
    #[must_use]
    pub fn with_seed(self, seed: u64) -> Scene {
        Scene { seed, ..self }
    }

    /// The same scene with another wall model. `WallMode::Periodic` makes
    /// a rectangle a periodic cell ([`Domain::with_periodic`]), any other
    /// model makes a periodic cell a plain rectangle again; a periodic model
    /// on another shape leaves the domain as it is, and `pack` refuses it.
    #[must_use]
    pub fn with_walls(self, walls: WallMode) -> Scene {
        let domain = self.domain.with_periodic(walls == WallMode::Periodic);
        Scene {
            walls,
            domain,
            ..self
        }
    }

    /// The same scene with walls of disks of `diameter` (mm).
    #[must_use]
    pub fn with_wall_disks(self, diameter: f64) -> Scene {
        Scene {
            walls: WallMode::Disks,
            wall_disk_diameter: Some(diameter),
            ..self
        }
    }

    /// The same scene with other packer settings.
    #[must_use]
    pub fn with_packer(self, packer: PackerSettings) -> Scene {
        Scene { packer, ..self }
    }

    /// The same scene with another packing method (other settings kept).
    #[must_use]
    pub fn with_method(mut self, method: Method) -> Scene {
        self.packer.method = method;
        self
    }

    /// The same scene in size-graded mode: the grading blends into
    /// `gradient.second` along its axis.
    #[must_use]
    pub fn with_gradient(self, gradient: SizeGradient) -> Scene {
        Scene {
            gradient: Some(gradient),
            ..self
        }
    }

    /// The same scene with particles of `shape` instead of disks.
    #[must_use]
    pub fn with_shape(self, shape: ShapeSpec) -> Scene {
        Scene {
            shape: Some(shape),
            ..self
        }
    }

    /// The same scene with ceilings the run stops at.
    #[must_use]
    pub fn with_limits(self, limits: Limits) -> Scene {
        Scene { limits, ..self }
    }

    /// The same scene over another domain. A periodic cell
    /// ([`Domain::periodic_rectangle`]) sets `walls = "periodic"`; with
    /// periodic walls already, a rectangle becomes a periodic cell.
    #[must_use]
    pub fn with_domain(self, domain: Domain) -> Scene {
        let walls = if domain.is_periodic() {
            WallMode::Periodic
        } else {
            self.walls
        };
        let domain = if walls == WallMode::Periodic {
            domain.with_periodic(true)
        } else {
            domain
        };
        Scene {
            domain,
            walls,
            ..self
        }
    }

    /// Default wall-disk diameter as a fraction of the smallest diameter.
    ///
    /// Wall disks sit centred on the boundary, touching or overlapping their
    /// neighbours. This fine discretisation reproduces the thesis' porosities
    /// (fracture case 0.225, squares of Table 3.13) within their scatter; wall
    /// disks as large as the particles cost a layer of porosity along every
    /// wall (0.36 instead of 0.225 on the fracture case).
    pub const DEFAULT_WALL_DISK_FRACTION: f64 = 1.0 / 12.0;

    /// Diameter of the wall disks used with `walls = "disks"`.
    pub fn wall_disk(&self) -> f64 {
        self.wall_disk_diameter
            .unwrap_or(self.d_min() * Self::DEFAULT_WALL_DISK_FRACTION)
    }

    /// Diameter of the largest disk that fits inside the walls (mm): the
    /// domain's inscribed diameter, less one wall-disk diameter with
    /// `walls = "disks"` (wall disks are centred on the boundary, so each
    /// reaches half its diameter into the domain). A periodic cell's is its
    /// shorter side (a wider disk would overlap its own image). A scene
    /// whose smallest disk is larger packs nothing.
    pub fn inscribed_diameter(&self) -> f64 {
        let inscribed = 2.0 * self.domain.inradius();
        match self.walls {
            WallMode::Exact | WallMode::Periodic => inscribed,
            WallMode::Disks => (inscribed - self.wall_disk()).max(0.0),
        }
    }

    /// Smallest diameter any size can have (mm), over both curves in size-graded mode.
    pub fn d_min(&self) -> f64 {
        self.curves()
            .map(Grading::d_min)
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest diameter any size can have (mm).
    pub fn d_max(&self) -> f64 {
        self.curves().map(Grading::d_max).fold(0.0, f64::max)
    }

    /// Porosity a dense packing of a wide grading typically reaches in 2D
    /// (the advancing front gives 0.15–0.25 on the reference scenes).
    pub const TYPICAL_POROSITY: f64 = 0.2;

    /// Disks a packing of this scene is expected to hold: the domain filled
    /// to [`Scene::TYPICAL_POROSITY`] with disks of the grading's mean area.
    /// An estimate for progress bars and `gapack validate`; the particle and
    /// memory checks use the upper bound [`Scene::max_disks`] instead.
    /// With a [`ShapeSpec`], the mean particle area is the mean disk area
    /// times [`ShapeSpec::mean_area_ratio`] (an ellipse of aspect A sized by
    /// sieve covers A times the disk of its least width).
    pub fn estimated_disks(&self) -> f64 {
        let solid = self.domain.area() * (1.0 - Self::TYPICAL_POROSITY);
        match &self.shape {
            None => solid / self.mean_disk_area(),
            Some(shape) => solid / (self.mean_disk_area() * shape.mean_area_ratio()),
        }
    }

    /// The most disks any packing of this scene can hold (wall disks aside):
    /// `ceil(domain area / area of the smallest disk)`.
    ///
    /// # Behavior
    /// A true upper bound, for every method: the disks do not overlap
    /// (relaxation places fewer, at its porosity, over the mean disk area),
    /// each covers at least the smallest disk's area, and the advancing
    /// front, deposition and RSA draw no more sizes than this. The domain
    /// filled solid with disks of the grading's *mean* area, the bound this
    /// replaced, was passed by wide gradings: the sizes that fit lean small
    /// (a 20 mm square of 0.02–4 mm by mass: 6,366 "at most", 7,841 packed).
    ///
    /// With a [`ShapeSpec`], a particle's area is at least
    /// [`ShapeSpec::least_area_ratio`] times the disk of its measured size
    /// (polygons sized by sieve can be smaller than that disk), and the
    /// bound is divided by that ratio (the least of the materials' shapes
    /// in size-graded mode).
    pub fn max_disks(&self) -> f64 {
        let d_min = self.d_min();
        let least_area = std::f64::consts::FRAC_PI_4 * d_min * d_min;
        match &self.shape {
            None => (self.domain.area() / least_area).ceil(),
            Some(_) => {
                let ratio = self
                    .shapes()
                    .map(ShapeSpec::least_area_ratio)
                    .fold(f64::INFINITY, f64::min);
                (self.domain.area() / (least_area * ratio)).ceil()
            }
        }
    }

    /// Smallest mean disk area of the curves (mm²): more disks than any
    /// curve alone would give are not expected.
    pub fn mean_disk_area(&self) -> f64 {
        self.curves()
            .map(Grading::mean_disk_area)
            .fold(f64::INFINITY, f64::min)
    }

    /// The scene mirrored in the line y = x: its domain transposed, a size
    /// gradient along x running along y (and the reverse), filling up.
    /// Packing it and swapping the coordinates back fills this scene along x.
    pub fn transposed(&self) -> Scene {
        let gradient = self.gradient.as_ref().map(|g| SizeGradient {
            axis: match g.axis {
                Axis::X => Axis::Y,
                Axis::Y => Axis::X,
                Axis::Radial => Axis::Radial,
            },
            ..g.clone()
        });
        Scene {
            domain: self.domain.transposed(),
            gradient,
            packer: PackerSettings {
                fill: Fill::Up,
                ..self.packer
            },
            ..self.clone()
        }
    }

    /// The particles' shapes: the scene's, and in size-graded mode the
    /// second material's when it has its own (none for disks).
    pub(crate) fn shapes(&self) -> impl Iterator<Item = &ShapeSpec> {
        self.shape
            .iter()
            .chain(self.gradient.as_ref().and_then(|g| g.second_shape.as_ref()))
    }

    /// The shape a particle of material `m` was drawn with: in size-graded
    /// mode the second material's own shape when it has one, otherwise the
    /// scene's (`None`: disks).
    pub fn material_shape(&self, m: usize) -> Option<&ShapeSpec> {
        let second = self.gradient.as_ref().and_then(|g| g.second_shape.as_ref());
        match (m, second) {
            (1, Some(shape)) => Some(shape),
            _ => self.shape.as_ref(),
        }
    }

    /// The grading, and the second curve in size-graded mode.
    pub(crate) fn curves(&self) -> impl Iterator<Item = &Grading> {
        std::iter::once(&self.grading).chain(self.gradient.as_ref().map(|g| &g.second))
    }
}
