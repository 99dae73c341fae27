//! Settings of a target-porosity run (`[optimise]` in a config).

use super::RULE_GENES;
use super::shapes::{SHAPE_GENES, ShapeBounds};
use crate::Scene;
use crate::layering::StopRules;
use crate::packer::{estimated_peak_bytes, size_count};

/// Settings of a target-porosity run, with the defaults of `docs/config.md`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptimiseSettings {
    /// Porosity to reach, in [0, 1).
    pub target_porosity: f64,
    /// Stop once the best feasible packing is within this of the target (porosity units).
    pub tolerance: f64,
    /// The search's population and stop rules.
    pub stop: StopRules,
    /// Search a scene estimated at this many disks or more on a window of
    /// it (`ga::window`); 0: always the whole.
    pub window_disks: u64,
    /// Largest KS distance of the packing's sizes to the grading curve (the constraint).
    pub max_psd_ks: f64,
    /// What the search may move of a superellipse `[shape]`
    /// (`[optimise.shape]`); `None`: the shape stays as given.
    pub shape: Option<ShapeBounds>,
}

/// Default `window_disks`: scenes of this many disks or more are searched on a window.
pub const WINDOW_DISKS: u64 = 50_000;

impl OptimiseSettings {
    /// Estimated peak memory (bytes) of a search on `scene`.
    ///
    /// A generation holds about four copies of the population's genomes
    /// (population, offspring, selection, parents) and one packing per child
    /// evaluated at once, beside the packer's own peak.
    ///
    /// A scene searched on a window ([`super::window`]) holds the search on
    /// at most [`MAX_SHARE`](super::window::MAX_SHARE) of its area (genes
    /// and disks scale with the area), beside the packer's peak on the whole
    /// and two packings of the whole (its own rules', and the best tuned).
    pub fn peak_bytes(&self, scene: &Scene) -> f64 {
        let genes =
            size_count(&scene.domain, scene.d_min()) as f64 + (RULE_GENES + SHAPE_GENES) as f64;
        let disks = scene.max_disks();
        let population = self.stop.population as f64;
        if super::window::windowed(scene, self.window_disks) {
            let share = super::window::MAX_SHARE;
            return population * share * (4.0 * genes * 8.0 + disks * 24.0)
                + (1.0 + share) * estimated_peak_bytes(scene)
                + 2.0 * disks * 24.0;
        }
        population * (4.0 * genes * 8.0 + disks * 24.0) + estimated_peak_bytes(scene)
    }

    /// Settings aiming at `target_porosity`, everything else at its default.
    pub fn new(target_porosity: f64) -> Self {
        OptimiseSettings {
            target_porosity,
            tolerance: 0.002,
            stop: StopRules::default(),
            window_disks: WINDOW_DISKS,
            max_psd_ks: 0.05,
            shape: None,
        }
    }
}
