//! The target-porosity problem (docs/ARCHITECTURE.md, "The genetic
//! algorithm"): grading genes and packing-rule
//! genes, fitness (porosity − target)², grading held within `max_psd_ks`.
//!
//! # Genome
//! - `n` grading genes, n = ⌈domain area / smallest disk area⌉ (the sizes `pack` draws):
//!   gene i is the percent passing of the i-th size drawn, a U in [0, 1]
//!   mapped to a diameter by the curve's inverse CDF, so every gene is a
//!   size the curve allows. Sizes left over when the domain is full are unused.
//! - [`RULE_GENES`] packing-rule genes: the share of one-contact placements,
//!   their gap (× [`MAX_GAP`]), and how many sizes may wait for a place
//!   before the run stops (× [`MAX_DEFERRED`], rounded; the dense end is
//!   the most). Dense advancing front cannot go looser than its own
//!   porosity, and the grading genes alone move it little (the thesis' GA
//!   stopped at 0.24–0.47 for a target of 0.5). One-contact placements with
//!   a gap reach porosities up to about 0.6 while every disk still touches at
//!   least one other and nothing overlaps; the knobs move the porosity
//!   smoothly and monotonically on average, which is what a GA needs to home
//!   in. The third matters for the grading: with few, large disks (the
//!   thesis' AP-4: about 30 disks of 1.2–4.8 mm) the sizes left waiting when
//!   the domain is full are mostly the large ones, which bends the packed
//!   grading (measured on AP-4 loose packs: KS ≤ 0.05 in 0 of 400 with 8
//!   waiting, in 25–87 % with none).
//!
//! - With `[optimise.shape]`, [`SHAPE_GENES`] shape genes last: the
//!   superellipses' aspect range, exponent and orientation spread, within
//!   the bounds given (see the `shapes` module). The gap gene is unused
//!   with shapes (one-contact particles keep no gap).
//!
//! # Constraint
//! The KS distance of the packed sizes to the curve (in its basis) above
//! `max_psd_ks` is the score's violation: a genome within it beats any
//! genome outside it (see [`Score`]). The initial grading genes are a
//! low-discrepancy (Kronecker) sequence, so every prefix of them, however
//! many disks fit, follows the curve closely from the start. With shape
//! genes, the shape's own constraints add to the violation
//! ([`ShapeBounds::judge`]).

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::engine::{Evaluation, Evolution, Problem, StopReason, Variation};
use super::score::Score;
use super::settings::OptimiseSettings;
use super::shapes::{AskedShape, SHAPE_GENES, ShapeBounds};
use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
use crate::metrics::{porosity, psd_ks, solid_area};
use crate::packer::{MAX_DEFERRED, MAX_GAP, PackError, Packing, pack_genes_watched, size_count};
use crate::scene::Family;

/// Packing-rule genes after the grading genes: one-contact share, gap /
/// [`MAX_GAP`], then 1 − max_deferred / [`MAX_DEFERRED`].
pub const RULE_GENES: usize = 3;

/// The golden ratio's conjugate: the step of the Kronecker sequence of initial grading genes.
const GOLDEN: f64 = 0.618_033_988_749_894_9;

/// Initial genomes pinned to the ends of the packing-rule range (dense, then
/// loosest), two of each, so that generation 0 measures the achievable range.
const PINNED_ENDS: usize = 2;

/// Hit a target porosity on a scene (see the module documentation).
#[derive(Debug, Clone)]
pub struct PorosityProblem<'a> {
    scene: &'a Scene,
    settings: OptimiseSettings,
    sizes: usize,
    /// The shape genes' bounds: a superellipse scene with `[optimise.shape]`.
    shapes: Option<ShapeBounds>,
}

impl<'a> PorosityProblem<'a> {
    /// The problem of packing `scene` at `settings.target_porosity`.
    pub fn new(scene: &'a Scene, settings: OptimiseSettings) -> Self {
        let sizes = size_count(&scene.domain, scene.d_min()) as usize;
        let superellipses = scene
            .shape
            .as_ref()
            .is_some_and(|s| matches!(s.family, Family::Superellipse { .. }));
        PorosityProblem {
            scene,
            settings,
            sizes,
            shapes: settings.shape.filter(|_| superellipses),
        }
    }

    /// The scene a genome packs: the problem's scene with the genome's
    /// packing rules (and shape, with shape genes).
    pub fn scene_of(&self, genes: &[f64]) -> Scene {
        let mut scene = self.scene.clone();
        let rules = &genes[self.sizes.min(genes.len())..];
        let gene = |i: usize| rules.get(i).copied().unwrap_or(0.0);
        scene.packer.one_contact_share = gene(0);
        scene.packer.gap = if scene.shape.is_some() {
            0.0
        } else {
            gene(1) * MAX_GAP
        };
        scene.packer.max_deferred = ((1.0 - gene(2)) * MAX_DEFERRED as f64).round() as usize;
        if let (Some(asked), Some(shape)) = (self.asked_of(genes), &scene.shape) {
            scene.shape = Some(asked.applied_to(shape));
        }
        scene
    }

    /// The shape a genome asks for (`None`: no shape genes).
    pub fn asked_of(&self, genes: &[f64]) -> Option<AskedShape> {
        let bounds = self.shapes?;
        let start = (self.sizes + RULE_GENES).min(genes.len());
        Some(bounds.asked(&genes[start..]))
    }

    /// The shape genes' bounds (`None`: the shape, if any, stays as given).
    pub fn shape_bounds(&self) -> Option<ShapeBounds> {
        self.shapes
    }

    /// The packing-rule genes of a genome (see the module documentation).
    pub fn rules_of(&self, genes: &[f64]) -> [f64; RULE_GENES] {
        let rules = &genes[self.sizes.min(genes.len())..];
        std::array::from_fn(|i| rules.get(i).copied().unwrap_or(0.0))
    }

    /// The porosity range generation 0 spans, `[low, high]`: its genomes run
    /// from dense to the loosest packing rules, so this estimates before the
    /// search what the domain and grading can reach. The search refines it
    /// ([`crate::ga::Evolution::explored`]): ordering the sizes well can pack
    /// a little denser than the dense end here (measured: 0.01 on a 50 mm
    /// square of Table 3.1).
    pub fn range(initial: &[Score]) -> [f64; 2] {
        initial
            .iter()
            .map(|s| s.value)
            .filter(|v| v.is_finite())
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
                [lo.min(v), hi.max(v)]
            })
    }

    /// Whether the target lies in `range`, give or take the tolerance (never
    /// in the empty range `[inf, -inf]`).
    pub fn feasible(&self, range: [f64; 2]) -> bool {
        let (t, tol) = (self.settings.target_porosity, self.settings.tolerance);
        range[0] - tol <= t && t <= range[1] + tol
    }

    /// Whether a search that ended as `evolution` could have reached any
    /// target the packing rules can reach, so that missing one is a verdict
    /// on the target rather than on the search: generation 0 held both ends
    /// of the packing-rule range (a population of at least
    /// [`CONCLUSIVE_POPULATION`]: two densest genomes, two loosest), and the
    /// search ran its course: it stopped for stagnation (its best had not
    /// improved for `stagnation` generations), or at its generation limit
    /// after at least `stagnation` generations. A search stopped by the time
    /// limit or a cancel is not conclusive.
    pub fn conclusive<O>(&self, evolution: &Evolution<O>) -> bool {
        let generations = evolution.history.len().saturating_sub(1);
        let ran = match evolution.stop {
            StopReason::Stagnation => true,
            StopReason::Generations => generations >= self.settings.stop.stagnation,
            _ => false,
        };
        self.settings.stop.population >= CONCLUSIVE_POPULATION && ran
    }

    /// What a finished search says of its target (see [`Verdict`]).
    pub fn verdict<O>(&self, evolution: &Evolution<O>) -> Verdict {
        match evolution.stop {
            StopReason::Reached => Verdict::Reached,
            StopReason::Interrupted => Verdict::Interrupted,
            _ if self.feasible(evolution.explored) => Verdict::InRange,
            _ if self.conclusive(evolution) => Verdict::OutOfReach,
            _ => Verdict::NotReached,
        }
    }
}

/// Smallest population whose generation 0 holds both ends of the
/// packing-rule range (`PINNED_ENDS` genomes at each).
pub const CONCLUSIVE_POPULATION: usize = 2 * PINNED_ENDS;

/// What a search says of its target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Verdict {
    /// A packing that honours the grading lies within the tolerance.
    Reached,
    /// The search was cut short: no verdict.
    Interrupted,
    /// Not reached, though the target lies within the range the packings
    /// that honour the grading were seen to span: a longer search may reach it.
    InRange,
    /// Not reached, and outside that range, after a search that was not
    /// [`PorosityProblem::conclusive`]: a longer or wider one may reach it.
    NotReached,
    /// Not reached, and outside that range (or no packing honoured the
    /// grading), after a conclusive search: out of reach of this domain and grading.
    OutOfReach,
}

impl Verdict {
    /// `summary.json`'s `feasible`: true when reached or within the range
    /// seen, false when out of reach, none when the search cannot tell.
    pub fn feasible(self) -> Option<bool> {
        match self {
            Verdict::Reached | Verdict::InRange => Some(true),
            Verdict::OutOfReach => Some(false),
            Verdict::Interrupted | Verdict::NotReached => None,
        }
    }

    /// The verdict in a few words (`summary.json`'s `verdict`).
    pub fn describe(self) -> &'static str {
        match self {
            Verdict::Reached => "reached",
            Verdict::Interrupted => "interrupted",
            Verdict::InRange => "not reached, within range",
            Verdict::NotReached => "not reached",
            Verdict::OutOfReach => "out of reach",
        }
    }
}

impl PorosityProblem<'_> {
    /// The evaluation of a genome whose scene cannot be packed.
    fn unpacked(&self) -> Evaluation<Option<Packing>> {
        Evaluation {
            score: Score::WORST,
            outcome: None,
            read: self.sizes,
        }
    }
}

impl Problem for PorosityProblem<'_> {
    type Outcome = Option<Packing>;

    fn genes(&self) -> usize {
        self.sizes
            + RULE_GENES
            + if self.shapes.is_some() {
                SHAPE_GENES
            } else {
                0
            }
    }

    fn sequence(&self) -> usize {
        self.sizes
    }

    fn initial(&self, index: usize, count: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
        let offset: f64 = rng.r#gen();
        let mut genes: Vec<f64> = (0..self.sizes)
            .map(|k| (offset + k as f64 * GOLDEN).fract())
            .collect();
        // Two pinned at each end of the rule range, the rest stratified in share.
        let rules = match index {
            i if i < PINNED_ENDS => [0.0; RULE_GENES],
            i if i < 2 * PINNED_ENDS => [1.0; RULE_GENES],
            i => [
                (i as f64 + rng.r#gen::<f64>()) / count as f64,
                rng.r#gen(),
                rng.r#gen(),
            ],
        };
        genes.extend(rules);
        if let Some(bounds) = &self.shapes {
            if index < 2 * PINNED_ENDS {
                genes.extend(bounds.roundest());
            } else {
                genes.extend((0..SHAPE_GENES).map(|_| rng.r#gen::<f64>()));
            }
        }
        genes
    }

    fn evaluate(&self, genes: &[f64]) -> Evaluation<Option<Packing>> {
        // A token nobody else holds is never raised.
        self.evaluate_until(genes, &Cancel::new())
            .unwrap_or_else(|_| self.unpacked())
    }

    fn evaluate_until(
        &self,
        genes: &[f64],
        cancel: &Cancel,
    ) -> Result<Evaluation<Option<Packing>>, Cancelled> {
        let scene = self.scene_of(genes);
        let sizes = genes[..self.sizes].iter().copied();
        let packing = match pack_genes_watched(&scene, sizes, &mut |_| {}, cancel) {
            Ok(packing) => packing,
            Err(PackError::Cancelled(why)) => return Err(why),
            Err(_) => return Ok(self.unpacked()),
        };
        let porosity = porosity(solid_area(&packing.disks), packing.domain.area());
        let ks = psd_ks(&packing, &scene);
        let shaped = match (self.shapes, self.asked_of(genes)) {
            (Some(bounds), Some(asked)) => bounds.judge(&asked, &packing.grains).violation,
            _ => 0.0,
        };
        let score = Score {
            violation: (ks - self.settings.max_psd_ks).max(0.0) + shaped,
            error: (porosity - self.settings.target_porosity).powi(2),
            value: porosity,
        };
        Ok(Evaluation {
            score,
            read: packing.stats.sizes_drawn as usize,
            outcome: Some(packing),
        })
    }

    fn reached(&self, score: &Score) -> bool {
        score.is_feasible()
            && (score.value - self.settings.target_porosity).abs() <= self.settings.tolerance
    }

    /// Fine steps on the last sizes drawn tune the porosity by a disk or two.
    fn variation(&self) -> Variation {
        Variation {
            tail_rate: 0.5,
            ..Variation::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ga::{Generation, StopRules};
    use crate::grading::Basis;
    use crate::{Domain, Grading};

    fn scene() -> Scene {
        Scene::new(
            Domain::rectangle(10.0, 10.0).expect("a domain"),
            Grading::uniform(1.0, 2.0, Basis::Number).expect("a grading"),
        )
    }

    /// A search of `population` that stopped for `stop` after `generations`,
    /// its feasible packings spanning `explored`.
    fn ended(stop: StopReason, generations: usize, explored: [f64; 2]) -> Evolution<()> {
        let record = Generation {
            index: 0,
            best: Score::WORST,
            mean_value: 0.0,
            worst_value: 0.0,
            evaluations: 0,
            seconds: 0.0,
        };
        Evolution {
            genes: Vec::new(),
            best: Score::WORST,
            outcome: (),
            history: vec![record; generations + 1],
            evaluations: 0,
            stop,
            seconds: 0.0,
            explored,
        }
    }

    #[test]
    fn out_of_reach_only_after_a_conclusive_search() {
        let scene = scene();
        let settings = |population: usize| OptimiseSettings {
            stop: StopRules {
                population,
                stagnation: 10,
                ..StopRules::default()
            },
            ..OptimiseSettings::new(0.4)
        };
        let wide = PorosityProblem::new(&scene, settings(16));
        let narrow = PorosityProblem::new(&scene, settings(2));
        let dense = [0.2251, 0.2517];
        // Two genomes, one generation: the loosest rules were never tried.
        let short = ended(StopReason::Generations, 1, dense);
        assert_eq!(narrow.verdict(&short), Verdict::NotReached);
        assert_eq!(wide.verdict(&short), Verdict::NotReached);
        assert_eq!(Verdict::NotReached.feasible(), None);
        // Ran its course: stagnation, or the generation limit past `stagnation`.
        let stalled = ended(StopReason::Stagnation, 12, dense);
        assert_eq!(wide.verdict(&stalled), Verdict::OutOfReach);
        assert_eq!(narrow.verdict(&stalled), Verdict::NotReached);
        let long = ended(StopReason::Generations, 10, dense);
        assert_eq!(wide.verdict(&long), Verdict::OutOfReach);
        assert_eq!(Verdict::OutOfReach.feasible(), Some(false));
        // The time limit is no verdict on the target; nor is a cancel.
        let timed = ended(StopReason::TimeLimit, 500, dense);
        assert_eq!(wide.verdict(&timed), Verdict::NotReached);
        let cut = ended(StopReason::Interrupted, 500, dense);
        assert_eq!(wide.verdict(&cut), Verdict::Interrupted);
        // No packing honoured the grading: the empty range holds no target.
        let none = ended(
            StopReason::Stagnation,
            12,
            [f64::INFINITY, f64::NEG_INFINITY],
        );
        assert_eq!(wide.verdict(&none), Verdict::OutOfReach);
        let within = ended(StopReason::Stagnation, 12, [0.2, 0.5]);
        assert_eq!(wide.verdict(&within), Verdict::InRange);
        assert_eq!(Verdict::InRange.feasible(), Some(true));
    }
}
