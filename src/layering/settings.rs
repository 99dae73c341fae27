//! Settings of a layering run (`[layering]` in a config).

use crate::scene::{Axis, Profile};

/// How the materials get their place.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LayeringMode {
    /// The packing is made once; materials are then assigned to its particles
    /// (baseline, refined by the GA).
    #[default]
    Materials,
    /// Size-graded: two materials with a grading each; the packer draws each
    /// size from one curve or the other along the axis, following the profile.
    Sizes,
}

/// Settings of a layering run, with the defaults of `docs/config.md`.
#[derive(Debug, Clone, PartialEq)]
pub struct LayeringSettings {
    /// How the materials get their place.
    pub mode: LayeringMode,
    /// Along which axis the fractions change.
    pub axis: Axis,
    /// Bins along the axis in which fractions are measured (at least 1).
    pub bins: usize,
    /// The target fractions.
    pub profile: Profile,
    /// Stop the GA once the RMS profile error is at most this (0: run to the limits below).
    pub tolerance: f64,
    /// GA genomes per generation.
    pub population: usize,
    /// Most GA generations after the initial one.
    pub generations: usize,
    /// Stop the GA after this many generations without progress.
    pub stagnation: usize,
    /// Stop the GA after this much wall-clock time (s); such a stop
    /// depends on the machine's speed and load.
    pub time_limit_s: f64,
    /// Stop the GA at the first generation boundary with at least this
    /// many genomes evaluated, the same on every machine (`None`: no budget).
    pub max_evaluations: Option<u64>,
}

impl LayeringSettings {
    /// Settings for `profile` along `axis`, everything else at its default.
    pub fn new(axis: Axis, profile: Profile) -> Self {
        LayeringSettings {
            mode: LayeringMode::Materials,
            axis,
            bins: 10,
            profile,
            tolerance: 0.0,
            population: 64,
            generations: 200,
            stagnation: 30,
            time_limit_s: 60.0,
            max_evaluations: None,
        }
    }
}
