//! Settings of a target-porosity run (`[optimise]` in a config).

/// Settings of a target-porosity run, with the defaults of `docs/CONFIG.md`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptimiseSettings {
    /// Porosity to reach, in [0, 1).
    pub target_porosity: f64,
    /// Stop once the best feasible packing is within this of the target (porosity units).
    pub tolerance: f64,
    /// Genomes per generation, at least 2.
    pub population: usize,
    /// Most generations after the initial one.
    pub generations: usize,
    /// Stop after this many generations without a better best genome.
    pub stagnation: usize,
    /// Stop after this much wall-clock time (s), checked between generations.
    pub time_limit_s: f64,
    /// Largest KS distance of the packing's sizes to the grading curve (the constraint).
    pub max_psd_ks: f64,
}

impl OptimiseSettings {
    /// Settings aiming at `target_porosity`, everything else at its default.
    pub fn new(target_porosity: f64) -> Self {
        OptimiseSettings {
            target_porosity,
            tolerance: 0.002,
            population: 64,
            generations: 200,
            stagnation: 30,
            time_limit_s: 60.0,
            max_psd_ks: 0.05,
        }
    }
}
