//! The layering problem (docs/ARCHITECTURE.md, "The genetic algorithm";
//! FGM): the packing's geometry is fixed;
//! the genes assign a material to each particle so that the area fractions
//! in bins along the axis follow a target profile.
//!
//! # Genome
//! One gene per particle, in placement order (which runs along the growing
//! packing, so the crossover's segments are regions of it): gene u gives
//! material ⌊u·M⌋ of M. Fitness: the RMS difference between achieved and
//! target fractions over bins and materials ([`rms_error`]), to minimise.
//!
//! # Start
//! Generation 0 holds the baseline assignment ([`crate::layering::baseline`])
//! and copies of it with a few particles changed, so the search starts from
//! the baseline and, with (μ + λ) survival, never ends worse than it.

use std::time::{Duration, Instant};

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::engine::{Evaluation, Evolution, Generation, Limits, Problem, Search, StopReason};
use super::score::Score;
use crate::cancel::Cancel;
use crate::farm::Farm;
use crate::layering::{
    BinAreas, Frame, LayeringMode, LayeringSettings, ProfileRow, baseline, profile_rows, rms_error,
};
use crate::packer::Packing;

/// Share of the particles whose material a perturbed copy of the baseline redraws.
const PERTURBATION: f64 = 0.02;

/// Assign materials to a fixed packing's particles to follow a profile.
#[derive(Debug, Clone)]
pub struct LayeringProblem {
    areas: BinAreas,
    targets: Vec<f64>,
    materials: usize,
    baseline: Vec<usize>,
    tolerance: f64,
}

impl LayeringProblem {
    /// The problem of following `targets` (flat by bin, `materials` per bin)
    /// with the particles whose bin areas are `areas`, from the `baseline`
    /// assignment; the search stops once the RMS error is at most `tolerance`.
    pub fn new(
        areas: BinAreas,
        targets: Vec<f64>,
        materials: usize,
        baseline: Vec<usize>,
        tolerance: f64,
    ) -> Self {
        LayeringProblem {
            areas,
            targets,
            materials: materials.max(1),
            baseline,
            tolerance,
        }
    }

    /// The material of each particle that `genes` stand for.
    pub fn assignment(&self, genes: &[f64]) -> Vec<usize> {
        genes.iter().map(|&u| self.material(u)).collect()
    }

    fn material(&self, u: f64) -> usize {
        ((u * self.materials as f64) as usize).min(self.materials - 1)
    }

    /// The gene that stands for material `m`: the middle of its range.
    fn gene(&self, m: usize) -> f64 {
        (m as f64 + 0.5) / self.materials as f64
    }
}

impl Problem for LayeringProblem {
    type Outcome = ();

    fn genes(&self) -> usize {
        self.baseline.len()
    }

    fn sequence(&self) -> usize {
        self.baseline.len()
    }

    fn initial(&self, index: usize, _count: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
        self.baseline
            .iter()
            .map(|&m| {
                if index > 0 && rng.r#gen::<f64>() < PERTURBATION {
                    rng.r#gen()
                } else {
                    self.gene(m)
                }
            })
            .collect()
    }

    fn evaluate(&self, genes: &[f64]) -> Evaluation<()> {
        let mut areas = vec![0.0; self.areas.bins() * self.materials];
        self.areas
            .material_areas(self.materials, |i| self.material(genes[i]), &mut areas);
        let rms = rms_error(&areas, &self.targets, self.materials);
        Evaluation {
            score: Score {
                violation: 0.0,
                error: rms,
                value: rms,
            },
            outcome: (),
            read: genes.len(),
        }
    }

    fn reached(&self, score: &Score) -> bool {
        score.value <= self.tolerance
    }
}

/// What laying materials out on a packing gave.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Layered {
    /// Material of each packed disk (index into the materials).
    pub assignment: Vec<u16>,
    /// RMS profile error of the assignment.
    pub rms: f64,
    /// RMS profile error of the baseline assignment (NaN in size-graded mode).
    pub baseline_rms: f64,
    /// Time the baseline took (s).
    pub baseline_seconds: f64,
    /// Time the GA took after the baseline (s); 0 in size-graded mode.
    pub seconds: f64,
    /// Genomes the GA evaluated.
    pub evaluations: u64,
    /// GA generations after the initial one.
    pub generations: usize,
    /// Why the GA stopped (`None` in size-graded mode: there is no GA).
    pub stop: Option<StopReason>,
    /// Target and achieved fractions per bin.
    pub rows: Vec<ProfileRow>,
    /// Share of the solid area of each material over the whole packing.
    pub fractions: Vec<f64>,
}

/// Lay `materials` materials out on `packing` following `settings`: the
/// baseline, then the GA started from it (seeded by `seed`, stopped by
/// `stop` between generations, `progress` told of each generation); in
/// size-graded mode the packing's own materials are only measured. The
/// GA's evaluations are spread over `farm`.
pub fn lay_out(
    packing: &Packing,
    settings: &LayeringSettings,
    materials: usize,
    seed: u64,
    stop: &Cancel,
    farm: &dyn Farm,
    progress: impl FnMut(&Generation),
) -> Layered {
    let materials = materials.max(1);
    let frame = Frame::new(settings.axis, &packing.domain);
    let areas = BinAreas::of_particles(&packing.disks, &packing.grains, &frame, settings.bins);
    let targets = settings
        .profile
        .bin_targets(settings.axis, settings.bins, materials);
    let measure = |assignment: &[u16]| {
        let mut per_bin = vec![0.0; areas.bins() * materials];
        areas.material_areas(materials, |i| usize::from(assignment[i]), &mut per_bin);
        per_bin
    };
    let finish = |assignment: Vec<u16>, per_bin: Vec<f64>| {
        let mut fractions = vec![0.0; materials];
        for bin in per_bin.chunks(materials) {
            fractions.iter_mut().zip(bin).for_each(|(f, a)| *f += a);
        }
        let solid: f64 = fractions.iter().sum();
        fractions
            .iter_mut()
            .for_each(|f| *f /= solid.max(f64::MIN_POSITIVE));
        (
            assignment,
            rms_error(&per_bin, &targets, materials),
            profile_rows(&per_bin, &targets, materials),
            fractions,
        )
    };

    if settings.mode == LayeringMode::Sizes {
        let tags = packing.materials.clone();
        let per_bin = measure(&tags);
        let (assignment, rms, rows, fractions) = finish(tags, per_bin);
        return Layered {
            assignment,
            rms,
            baseline_rms: f64::NAN,
            baseline_seconds: 0.0,
            seconds: 0.0,
            evaluations: 0,
            generations: 0,
            stop: None,
            rows,
            fractions,
        };
    }

    let start = Instant::now();
    let base = baseline(&packing.disks, &frame, &settings.profile, materials, seed);
    let baseline_seconds = start.elapsed().as_secs_f64();
    let base_tags: Vec<u16> = base.iter().map(|&m| m as u16).collect();
    let baseline_rms = rms_error(&measure(&base_tags), &targets, materials);

    let problem = LayeringProblem::new(
        areas.clone(),
        targets.clone(),
        materials,
        base,
        settings.tolerance,
    );
    let limits = Limits {
        population: settings.stop.population,
        generations: settings.stop.generations,
        stagnation: settings.stop.stagnation,
        time_limit: Duration::from_secs_f64(settings.stop.time_limit_s),
        max_evaluations: settings.stop.max_evaluations,
    };
    let (tags, seconds, evaluations, generations, stopped) =
        match Search::start_on(&problem, limits, seed, stop, farm) {
            Ok(search) => {
                let evolution = search.run(stop, progress);
                let tags = problem
                    .assignment(&evolution.genes)
                    .into_iter()
                    .map(|m| m as u16)
                    .collect();
                let generations = evolution.history.len().saturating_sub(1);
                let Evolution {
                    seconds,
                    evaluations,
                    stop,
                    ..
                } = evolution;
                (tags, seconds, evaluations, generations, stop)
            }
            // Stopped before generation 0 was scored: the baseline stands.
            Err(_) => (base_tags, 0.0, 0, 0, StopReason::Interrupted),
        };
    let per_bin = measure(&tags);
    let (assignment, rms, rows, fractions) = finish(tags, per_bin);
    Layered {
        assignment,
        rms,
        baseline_rms,
        baseline_seconds,
        seconds,
        evaluations,
        generations,
        stop: Some(stopped),
        rows,
        fractions,
    }
}
