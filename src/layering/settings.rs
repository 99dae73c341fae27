//! Settings of a layering run (`[layering]` in a config), and the
//! population and stop rules it shares with a target-porosity run.

use crate::scene::{Axis, Profile};

/// The population of a GA search and the rules that stop it: the keys
/// `[optimise]` and `[layering]` share, with the defaults of `docs/config.md`.
///
/// Held by [`LayeringSettings`] and by `ga::OptimiseSettings` (`ga`
/// re-exports it). It lives here, not in `ga`, because `ga` builds on
/// `layering` (the layering GA): `layering` naming `ga` would make the two
/// a cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopRules {
    /// Genomes per generation, at least 2.
    pub population: usize,
    /// Most generations after the initial one.
    pub generations: usize,
    /// Stop after this many generations without a better best genome.
    pub stagnation: usize,
    /// Stop after this much wall-clock time (s), checked between
    /// generations. A stop here depends on the machine's speed and load.
    pub time_limit_s: f64,
    /// Stop at the first generation boundary with at least this many
    /// genomes evaluated: a budget that stops at the same place on every
    /// machine (`None`: no budget).
    pub max_evaluations: Option<u64>,
}

impl Default for StopRules {
    fn default() -> Self {
        StopRules {
            population: 64,
            generations: 200,
            stagnation: 30,
            time_limit_s: 60.0,
            max_evaluations: None,
        }
    }
}

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
    /// Stop the GA once the RMS profile error is at most this (0: run to the stop rules).
    pub tolerance: f64,
    /// The GA's population and stop rules.
    pub stop: StopRules,
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
            stop: StopRules::default(),
        }
    }
}
