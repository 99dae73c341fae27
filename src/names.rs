//! The names users write for each choice, in one table per choice (LAMMPS style):
//! the parser looks names up here, and reports print them from here. The
//! output formats' and length units' tables sit beside their types in
//! `output`, which writes those names.

use crate::geometry::{Shape, WallMode};
use crate::grading::{Basis, Interpolation};
use crate::layering::LayeringMode;
use crate::scene::{Axis, Fill, FrontRules, IndexKind, Method};
use crate::study::{Keep, Measure, RunJob};

/// The default packing method's name.
pub const METHOD: &str = "advancing-front";

/// A table of the names of one choice.
pub(crate) struct Names<T: 'static> {
    /// What is being named, for messages ("shape", "index").
    pub what: &'static str,
    /// Name as written in the config, value; the first entry is the default.
    pub entries: &'static [(&'static str, T)],
}

impl<T: Copy + PartialEq> Names<T> {
    /// The value of `name`, if it is one of the table's.
    pub fn get(&self, name: &str) -> Option<T> {
        self.entries.iter().find(|(n, _)| *n == name).map(|e| e.1)
    }

    /// The name of `value`.
    pub fn name_of(&self, value: T) -> &'static str {
        self.entries
            .iter()
            .find(|(_, v)| *v == value)
            .map_or("unnamed", |e| e.0)
    }

    /// All valid names, in table order.
    pub fn valid(&self) -> Box<[&'static str]> {
        self.entries.iter().map(|e| e.0).collect()
    }
}

/// Kinds of domain shape, without their sizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ShapeKind {
    Rectangle,
    Polygon,
    Circle,
    Trapezoid,
}

impl ShapeKind {
    /// The keys of `[domain]` that give this shape its size, required ones first.
    pub fn size_keys(self) -> (&'static [&'static str], &'static [&'static str]) {
        match self {
            ShapeKind::Rectangle => (&["width", "height"], &[]),
            ShapeKind::Polygon => (&["vertices"], &[]),
            ShapeKind::Circle => (&["radius"], &["center"]),
            ShapeKind::Trapezoid => (&["bottom", "top", "height"], &[]),
        }
    }
}

pub(crate) const SHAPES: Names<ShapeKind> = Names {
    what: "shape",
    entries: &[
        ("rectangle", ShapeKind::Rectangle),
        ("polygon", ShapeKind::Polygon),
        ("circle", ShapeKind::Circle),
        ("trapezoid", ShapeKind::Trapezoid),
    ],
};

pub(crate) const WALLS: Names<WallMode> = Names {
    what: "wall model",
    entries: &[
        ("exact", WallMode::Exact),
        ("disks", WallMode::Disks),
        ("periodic", WallMode::Periodic),
    ],
};

pub(crate) const INTERPOLATIONS: Names<Interpolation> = Names {
    what: "interpolation",
    entries: &[
        ("log", Interpolation::Log),
        ("linear", Interpolation::Linear),
    ],
};

pub(crate) const BASES: Names<Basis> = Names {
    what: "basis",
    entries: &[
        ("number", Basis::Number),
        ("mass", Basis::Mass),
        ("mass3d", Basis::Mass3d),
    ],
};

pub(crate) const METHODS: Names<Method> = Names {
    what: "method",
    entries: &[
        (METHOD, Method::AdvancingFront),
        ("rsa", Method::Rsa),
        ("deposition", Method::Deposition),
        ("relaxation", Method::Relaxation),
        ("densify", Method::Densify),
    ],
};

pub(crate) const INDEXES: Names<IndexKind> = Names {
    what: "index",
    entries: &[
        ("mx-quadtree", IndexKind::MxQuadtree),
        ("grid", IndexKind::Grid),
    ],
};

pub(crate) const RULES: Names<FrontRules> = Names {
    what: "front rules",
    entries: &[
        ("robust", FrontRules::Robust),
        ("thesis", FrontRules::Thesis),
    ],
};

pub(crate) const FILLS: Names<Fill> = Names {
    what: "fill direction",
    entries: &[("up", Fill::Up), ("right", Fill::Right)],
};

/// Kinds of fracture extent, without the window's tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum ExtentKind {
    #[default]
    Full,
    Window,
}

pub(crate) const EXTENTS: Names<ExtentKind> = Names {
    what: "extent",
    entries: &[("full", ExtentKind::Full), ("window", ExtentKind::Window)],
};

pub(crate) const AXES: Names<Axis> = Names {
    what: "axis",
    entries: &[("y", Axis::Y), ("x", Axis::X), ("radial", Axis::Radial)],
};

pub(crate) const MODES: Names<LayeringMode> = Names {
    what: "layering mode",
    entries: &[
        ("materials", LayeringMode::Materials),
        ("sizes", LayeringMode::Sizes),
    ],
};

/// Kinds of profile, without their data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum ProfileKind {
    #[default]
    Steps,
    Linear,
    Power,
    Sigmoid,
    Table,
}

pub(crate) const PROFILES: Names<ProfileKind> = Names {
    what: "profile",
    entries: &[
        ("steps", ProfileKind::Steps),
        ("linear", ProfileKind::Linear),
        ("power", ProfileKind::Power),
        ("sigmoid", ProfileKind::Sigmoid),
        ("table", ProfileKind::Table),
    ],
};

/// `packer.contacts` is written as a number; it sets the one-contact share.
pub(crate) const CONTACTS: Names<f64> = Names {
    what: "contact count",
    entries: &[("2", 0.0), ("1", 1.0)],
};

pub(crate) const KEEPS: Names<Keep> = Names {
    what: "keep mode",
    entries: &[
        ("none", Keep::None),
        ("summary", Keep::Summary),
        ("all", Keep::All),
    ],
};

pub(crate) const MEASURES: Names<Measure> = Names {
    what: "measure",
    entries: &[
        ("porosity", Measure::Porosity),
        ("particles", Measure::Particles),
        ("psd_ks", Measure::PsdKs),
        ("coordination", Measure::Coordination),
        ("error", Measure::Error),
        ("seconds", Measure::Seconds),
    ],
};

/// The jobs a study's runs may be (`sweep.job`).
pub(crate) const RUN_JOBS: Names<RunJob> = Names {
    what: "job",
    entries: &[
        ("pack", RunJob::Pack),
        ("optimise", RunJob::Optimise),
        ("optimize", RunJob::Optimise),
        ("layer", RunJob::Layer),
    ],
};

/// The name a choice is written with in a config (`"mx-quadtree"`, `"exact"`, `"2"`).
///
/// Reports use it so that they speak the user's language.
pub trait ConfigName {
    /// The config name of this value.
    fn config_name(&self) -> &'static str;
}

impl ConfigName for WallMode {
    fn config_name(&self) -> &'static str {
        WALLS.name_of(*self)
    }
}

impl ConfigName for Interpolation {
    fn config_name(&self) -> &'static str {
        INTERPOLATIONS.name_of(*self)
    }
}

impl ConfigName for Basis {
    fn config_name(&self) -> &'static str {
        BASES.name_of(*self)
    }
}

impl ConfigName for IndexKind {
    fn config_name(&self) -> &'static str {
        INDEXES.name_of(*self)
    }
}

impl ConfigName for FrontRules {
    fn config_name(&self) -> &'static str {
        RULES.name_of(*self)
    }
}

impl ConfigName for Method {
    fn config_name(&self) -> &'static str {
        METHODS.name_of(*self)
    }
}

impl ConfigName for Fill {
    fn config_name(&self) -> &'static str {
        FILLS.name_of(*self)
    }
}

impl ConfigName for Axis {
    fn config_name(&self) -> &'static str {
        AXES.name_of(*self)
    }
}

impl ConfigName for LayeringMode {
    fn config_name(&self) -> &'static str {
        MODES.name_of(*self)
    }
}

impl ConfigName for Keep {
    fn config_name(&self) -> &'static str {
        KEEPS.name_of(*self)
    }
}

impl ConfigName for Measure {
    fn config_name(&self) -> &'static str {
        MEASURES.name_of(*self)
    }
}

impl ConfigName for RunJob {
    fn config_name(&self) -> &'static str {
        RUN_JOBS.name_of(*self)
    }
}

impl ConfigName for Shape {
    fn config_name(&self) -> &'static str {
        SHAPES.name_of(match self {
            Shape::Rectangle { .. } => ShapeKind::Rectangle,
            Shape::Polygon { .. } => ShapeKind::Polygon,
            Shape::Circle { .. } => ShapeKind::Circle,
            Shape::Trapezoid { .. } => ShapeKind::Trapezoid,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (name, value) in INDEXES.entries {
            assert_eq!(INDEXES.get(name), Some(*value));
            assert_eq!(value.config_name(), *name);
        }
        assert_eq!(CONTACTS.get("1"), Some(1.0));
        assert_eq!(WallMode::Disks.config_name(), "disks");
        assert_eq!(Basis::Mass3d.config_name(), "mass3d");
        assert_eq!(FrontRules::Thesis.config_name(), "thesis");
        assert_eq!(Interpolation::Linear.config_name(), "linear");
        assert_eq!(SHAPES.get("hexagon"), None);
        let circle = Shape::Circle {
            center: crate::geometry::Point::new(0.0, 0.0),
            radius: 1.0,
        };
        assert_eq!(circle.config_name(), "circle");
    }
}
