//! The generational loop: genevo tournament selection, our crossover and
//! mutation, parallel evaluation of new genomes only, (μ + λ) reinsertion.
//!
//! # Behavior
//! 1. Generation 0: `population` genomes from [`Problem::initial`], evaluated.
//! 2. Each generation: genevo's tournament (size 3) picks `population / 2`
//!    pairs of parents; each pair gives two children ([`Crossover`], then
//!    [`Mutation`], both confined to the sequence genes the parents' packings
//!    read); `population / 8` immigrants, fresh from [`Problem::initial`],
//!    keep the search from settling too early; the children and immigrants
//!    not seen before are evaluated in parallel; the best `population`
//!    distinct ones of parents, children and immigrants survive (ties keep
//!    the older genome).
//! 3. Stop, checked before each generation, in this order: the best genome
//!    meets [`Problem::reached`]; the stop flag is set (Ctrl-C); `generations`
//!    generations ran; `stagnation` generations brought no progress (a best
//!    that [`Score::improves_on`] the old one); the time limit has passed.
//!
//! # Determinism
//! Every random choice is made on one thread from one seeded stream, and an
//! evaluation depends on its genome alone; rayon returns results in input
//! order. So the same seed gives the same result with any number of threads.
//! On a [`Farm`] of several processes every process follows the same search:
//! the new genomes of a generation are shared out, their scores gathered
//! on every process, and the stop rules that rest on the clock or a signal
//! are decided by the leading process; the best genome's packing is made
//! again at the end (evaluations are pure). So the number of processes does
//! not change the result either.
//!
//! # Performance
//! A genome is never evaluated twice, nor is any genome whose evaluation is
//! bound to repeat an earlier one: an evaluation reports how many sequence
//! genes it read (a packing draws sizes until the domain is full), and a
//! genome that agrees with an evaluated one on those genes and on every
//! parameter gene gets its score without an evaluation. Such genomes are one
//! phenotype and count as duplicates in the population. Scores are kept by a
//! 128-bit fingerprint (FNV-1a over the bit patterns; two different genomes
//! sharing one is not a practical concern at 2⁻⁶⁴ odds for billions of
//! genomes). genevo's own `ElitistReinserter` would re-evaluate every child,
//! serially: hence this loop.

use std::collections::{BTreeSet, HashMap, HashSet};
use std::rc::Rc;
use std::time::{Duration, Instant};

use genevo::algorithm::EvaluatedPopulation;
use genevo::operator::{CrossoverOp, MutationOp, SelectionOp};
use genevo::selection::tournament::TournamentSelector;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use super::checkpoint::{
    Checkpoint, ResumeError, bits, floats, generation_bits, generation_of, key_bits, key_of,
    score_bits, score_of,
};
use super::operators::{Crossover, Mutation};
use super::score::{Fit, Score};
use super::settings::OptimiseSettings;
use crate::cancel::{Cancel, Cancelled};
use crate::farm::{self, Farm, Local};

/// One immigrant per this many genomes of the population, each generation.
const IMMIGRANT_SHARE: usize = 8;

/// A problem the GA solves: genomes of [`Problem::genes`] genes in [0, 1].
pub trait Problem: Sync {
    /// What an evaluation yields besides its score (a packing); the search
    /// keeps the best genome's. The default stands for "none yet".
    type Outcome: Send + Default;

    /// Genes per genome.
    fn genes(&self) -> usize;

    /// How many genes, from the start, form the sequence part (exchanged by
    /// segments in crossover); the rest are parameters (blended).
    fn sequence(&self) -> usize;

    /// The `index`-th of `count` initial genomes, drawing from `rng`.
    fn initial(&self, index: usize, count: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64>;

    /// Score a genome: a pure function of the genes it reads.
    fn evaluate(&self, genes: &[f64]) -> Evaluation<Self::Outcome>;

    /// [`Problem::evaluate`], giving up once `cancel` is raised; problems
    /// whose evaluations take long (a packing) look at it while they work.
    ///
    /// # Errors
    /// [`Cancelled`] when `cancel` is raised.
    fn evaluate_until(
        &self,
        genes: &[f64],
        cancel: &Cancel,
    ) -> Result<Evaluation<Self::Outcome>, Cancelled> {
        cancel.check()?;
        Ok(self.evaluate(genes))
    }

    /// Whether a score is good enough to stop the search.
    fn reached(&self, score: &Score) -> bool;

    /// How strongly to vary genomes; [`Variation::default`] suits most problems.
    fn variation(&self) -> Variation {
        Variation::default()
    }
}

/// Mutation rates a problem asks for: a swap of two sequence genes, and a
/// normal step on one of the last sequence genes read (see the `operators` module).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variation {
    /// Probability that a child gets one swap of two sequence genes.
    pub swap_rate: f64,
    /// Probability that a child gets one fine step on a gene near the end of
    /// its sequence (useful where the last genes read change the outcome least).
    pub tail_rate: f64,
}

impl Default for Variation {
    fn default() -> Self {
        Variation {
            swap_rate: 0.5,
            tail_rate: 0.0,
        }
    }
}

/// What [`Problem::evaluate`] returns.
#[derive(Debug, Clone)]
pub struct Evaluation<O> {
    /// The genome's score.
    pub score: Score,
    /// What else the evaluation made (the packing).
    pub outcome: O,
    /// How many leading sequence genes the evaluation read; the others did
    /// not matter (sizes never drawn).
    pub read: usize,
}

/// How long a search may go on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Genomes per generation (at least 2).
    pub population: usize,
    /// Most generations after generation 0.
    pub generations: usize,
    /// Generations without a better best genome before stopping.
    pub stagnation: usize,
    /// Wall-clock budget, checked between generations.
    pub time_limit: Duration,
    /// Evaluation budget, checked between generations (`None`: none).
    pub max_evaluations: Option<u64>,
}

impl From<&OptimiseSettings> for Limits {
    fn from(s: &OptimiseSettings) -> Self {
        Limits {
            population: s.stop.population.max(2),
            generations: s.stop.generations,
            stagnation: s.stop.stagnation,
            time_limit: Duration::from_secs_f64(s.stop.time_limit_s.max(0.0)),
            max_evaluations: s.stop.max_evaluations,
        }
    }
}

/// One generation's record, for progress reports and `convergence.csv`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Generation {
    /// 0 for the initial population.
    pub index: usize,
    /// Score of the best genome so far.
    pub best: Score,
    /// Mean of the population's values (finite ones).
    pub mean_value: f64,
    /// Value of the population's worst genome.
    pub worst_value: f64,
    /// Distinct genomes evaluated so far.
    pub evaluations: u64,
    /// Wall-clock time since the search started (s).
    pub seconds: f64,
}

/// Why a search stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The best genome met the target.
    Reached,
    /// The stop flag was raised (Ctrl-C).
    Interrupted,
    /// The generation limit was reached.
    Generations,
    /// The best genome stopped improving.
    Stagnation,
    /// The time limit passed.
    TimeLimit,
    /// The evaluation budget was spent.
    Evaluations,
    /// The target lay below the advancing front's range: the densify
    /// method packed the drawn sizes at it (or at the densest it reached).
    Densified,
}

impl StopReason {
    /// The reason in a few words, for reports.
    pub fn describe(self) -> &'static str {
        match self {
            StopReason::Reached => "target reached",
            StopReason::Interrupted => "interrupted",
            StopReason::Generations => "generation limit",
            StopReason::Stagnation => "stagnation",
            StopReason::TimeLimit => "time limit",
            StopReason::Evaluations => "evaluation budget",
            StopReason::Densified => "densified",
        }
    }

    /// Whether the same config and seed stop here on any machine: every
    /// reason but the time limit (which depends on the machine's speed and
    /// load) and an interruption.
    pub fn reproducible(self) -> bool {
        !matches!(self, StopReason::TimeLimit | StopReason::Interrupted)
    }
}

/// The result of a search.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Evolution<O> {
    /// The best genome found.
    pub genes: Vec<f64>,
    /// Its score.
    pub best: Score,
    /// Its outcome (the packing).
    pub outcome: O,
    /// One record per generation, generation 0 first.
    pub history: Vec<Generation>,
    /// Distinct genomes evaluated.
    pub evaluations: u64,
    /// Why the search stopped.
    pub stop: StopReason,
    /// Wall-clock time of the whole search (s).
    pub seconds: f64,
    /// Smallest and largest value of the feasible genomes evaluated (the
    /// range the search explored); `[inf, -inf]` if none was feasible.
    pub explored: [f64; 2],
}

/// Identity of a phenotype: the sequence genes read and a fingerprint of
/// them and of the parameter genes.
type Key = (usize, u128);

/// A genome of the population with its score.
struct Member {
    genes: Vec<f64>,
    key: Key,
    score: Score,
}

/// A search under way: generation 0 is evaluated by [`Search::start`], so
/// that the caller can look at it ([`Search::initial`]) before [`Search::run`].
pub struct Search<'a, P: Problem> {
    problem: &'a P,
    farm: &'a dyn Farm,
    limits: Limits,
    rng: Xoshiro256PlusPlus,
    start: Instant,
    selector: TournamentSelector,
    crossover: Crossover,
    mutation: Mutation,
    /// Sorted best first.
    population: Vec<Member>,
    /// Scores of the initial genomes, in [`Problem::initial`] order.
    initial: Vec<Score>,
    /// Score of every phenotype evaluated.
    seen: HashMap<Key, Score>,
    /// The distinct read lengths in `seen`.
    lengths: BTreeSet<usize>,
    /// Genomes evaluated.
    evaluations: u64,
    /// Value range of the feasible genomes evaluated.
    explored: [f64; 2],
    best: (Vec<f64>, Score, P::Outcome),
    /// The best genome was evaluated on another process: its outcome is
    /// made again when the search ends.
    remake: bool,
    history: Vec<Generation>,
    stagnant: usize,
}

impl<'a, P: Problem> Search<'a, P> {
    /// Draw and evaluate generation 0 of a search seeded by `seed`.
    ///
    /// # Errors
    /// [`Cancelled`] when `cancel` is raised before generation 0 is evaluated.
    pub fn start(
        problem: &'a P,
        limits: Limits,
        seed: u64,
        cancel: &Cancel,
    ) -> Result<Self, Cancelled> {
        Search::start_on(problem, limits, seed, cancel, &Local)
    }

    /// [`Search::start`] with the evaluations spread over `farm`.
    ///
    /// # Errors
    /// [`Cancelled`] when `cancel` is raised before generation 0 is evaluated.
    pub fn start_on(
        problem: &'a P,
        limits: Limits,
        seed: u64,
        cancel: &Cancel,
        farm: &'a dyn Farm,
    ) -> Result<Self, Cancelled> {
        let mut search = Search::fresh(
            problem,
            limits,
            Xoshiro256PlusPlus::seed_from_u64(seed),
            farm,
        );
        let population = search.limits.population.max(2);
        let genomes: Vec<Vec<f64>> = (0..population)
            .map(|i| problem.initial(i, population, &mut search.rng))
            .collect();
        let members = search.evaluate(genomes, cancel)?;
        search.initial = members.iter().map(|m| m.score).collect();
        search.reinsert(members);
        search.record(0);
        Ok(search)
    }

    /// A search with its operators and no genomes yet.
    fn fresh(problem: &'a P, limits: Limits, rng: Xoshiro256PlusPlus, farm: &'a dyn Farm) -> Self {
        let n = problem.sequence();
        let variation = problem.variation();
        Search {
            problem,
            farm,
            limits,
            rng,
            start: Instant::now(),
            // Half the population in pairs, tournaments of 3, the best always wins.
            selector: TournamentSelector::new(0.5, 2, 3, 1.0, false),
            crossover: Crossover {
                sequence: n,
                alpha: 0.5,
            },
            mutation: Mutation {
                sequence: n,
                sequence_rate: 1.0 / n.max(1) as f64,
                swap_rate: variation.swap_rate,
                tail_rate: variation.tail_rate,
                parameter_rate: 0.5,
                sigma: 0.05,
            },
            population: Vec::new(),
            initial: Vec::new(),
            seen: HashMap::new(),
            lengths: BTreeSet::new(),
            evaluations: 0,
            explored: [f64::INFINITY, f64::NEG_INFINITY],
            best: (Vec::new(), Score::WORST, P::Outcome::default()),
            remake: false,
            history: Vec::new(),
            stagnant: 0,
        }
    }

    /// Scores of the initial genomes, in [`Problem::initial`] order.
    pub fn initial(&self) -> &[Score] {
        &self.initial
    }

    /// Run generations until a stop rule holds; `stop` is polled between
    /// generations and inside evaluations (a generation cut short is
    /// dropped whole), `progress` gets generation 0 and then each generation.
    pub fn run(self, stop: &Cancel, progress: impl FnMut(&Generation)) -> Evolution<P::Outcome> {
        self.run_saving(stop, progress, 0, |_| {})
    }

    /// [`Search::run`], handing `save` a [`Checkpoint`] after every `every`-th
    /// generation (never for 0) and when the stop token ends the search, so
    /// that [`Search::resume`] can go on from there.
    pub fn run_saving(
        mut self,
        stop: &Cancel,
        mut progress: impl FnMut(&Generation),
        every: usize,
        mut save: impl FnMut(&Checkpoint),
    ) -> Evolution<P::Outcome> {
        if let Some(g) = self.history.last() {
            progress(g);
        }
        let reason = loop {
            let generation = self.history.len();
            if self.problem.reached(&self.best.1) {
                break StopReason::Reached;
            }
            if farm::agree(self.farm, stop.is_cancelled()) {
                save(&self.checkpoint());
                break StopReason::Interrupted;
            }
            if generation > self.limits.generations {
                break StopReason::Generations;
            }
            if self.stagnant >= self.limits.stagnation {
                break StopReason::Stagnation;
            }
            if self
                .limits
                .max_evaluations
                .is_some_and(|most| self.evaluations >= most)
            {
                break StopReason::Evaluations;
            }
            if farm::agree(self.farm, self.start.elapsed() >= self.limits.time_limit) {
                break StopReason::TimeLimit;
            }
            if self.step(stop).is_err() {
                // The state is that of the last whole generation.
                save(&self.checkpoint());
                break StopReason::Interrupted;
            }
            self.record(generation);
            if let Some(g) = self.history.last() {
                progress(g);
            }
            if every > 0 && generation.is_multiple_of(every) {
                save(&self.checkpoint());
            }
        };
        self.ended(reason)
    }

    /// The search as it stands, ended for `reason` without another
    /// generation: generation 0 alone when called after [`Search::start`]
    /// (a job that reaches its target by other means keeps the record of
    /// what the search measured).
    pub fn ended(self, reason: StopReason) -> Evolution<P::Outcome> {
        let (genes, best, mut outcome) = self.best;
        if self.remake {
            outcome = self.problem.evaluate(&genes).outcome;
        }
        Evolution {
            genes,
            best,
            outcome,
            evaluations: self.evaluations,
            history: self.history,
            stop: reason,
            seconds: self.start.elapsed().as_secs_f64(),
            explored: self.explored,
        }
    }

    /// The state after the last generation recorded.
    pub fn checkpoint(&self) -> Checkpoint {
        let mut seen: Vec<_> = self
            .seen
            .iter()
            .map(|(&k, s)| (key_bits(k), score_bits(s)))
            .collect();
        seen.sort_unstable_by_key(|e| e.0);
        Checkpoint {
            rng: self.rng.clone(),
            population: self
                .population
                .iter()
                .map(|m| (bits(&m.genes), key_bits(m.key), score_bits(&m.score)))
                .collect(),
            initial: self.initial.iter().map(score_bits).collect(),
            seen,
            evaluations: self.evaluations,
            explored: [self.explored[0].to_bits(), self.explored[1].to_bits()],
            best: (bits(&self.best.0), score_bits(&self.best.1)),
            history: self.history.iter().map(generation_bits).collect(),
            stagnant: self.stagnant,
            seconds: self.start.elapsed().as_secs_f64().to_bits(),
        }
    }

    /// Go on with a search from `checkpoint` under `limits` (the time limit
    /// counts the time spent before it). The best genome's outcome is
    /// evaluated again (evaluations are pure, so it is the same), not counted.
    ///
    /// # Errors
    /// [`ResumeError`] when the checkpoint does not fit the problem (another
    /// genome length) or holds what no search writes (an all-zero random
    /// state, genes outside [0, 1], scores no evaluation gives, counters at
    /// odds with each other): see [`Checkpoint`]'s validation.
    pub fn resume(
        problem: &'a P,
        limits: Limits,
        checkpoint: &Checkpoint,
    ) -> Result<Self, ResumeError> {
        Search::resume_on(problem, limits, checkpoint, &Local)
    }

    /// [`Search::resume`] with the evaluations spread over `farm`.
    ///
    /// # Errors
    /// As [`Search::resume`].
    pub fn resume_on(
        problem: &'a P,
        limits: Limits,
        checkpoint: &Checkpoint,
        farm: &'a dyn Farm,
    ) -> Result<Self, ResumeError> {
        checkpoint.validate(
            problem.genes(),
            problem.sequence(),
            limits.population.max(2),
        )?;
        let mut search = Search::fresh(problem, limits, checkpoint.rng.clone(), farm);
        let spent = Duration::try_from_secs_f64(f64::from_bits(checkpoint.seconds))
            .unwrap_or(Duration::ZERO);
        search.start = Instant::now()
            .checked_sub(spent)
            .unwrap_or_else(Instant::now);
        search.population = checkpoint
            .population
            .iter()
            .map(|(g, k, s)| Member {
                genes: floats(g),
                key: key_of(*k),
                score: score_of(s),
            })
            .collect();
        search.initial = checkpoint.initial.iter().map(score_of).collect();
        search.seen = checkpoint
            .seen
            .iter()
            .map(|(k, s)| (key_of(*k), score_of(s)))
            .collect();
        search.lengths = search.seen.keys().map(|k| k.0).collect();
        search.evaluations = checkpoint.evaluations;
        search.explored = checkpoint.explored.map(f64::from_bits);
        let best_genes = floats(&checkpoint.best.0);
        let outcome = problem.evaluate(&best_genes).outcome;
        search.best = (best_genes, score_of(&checkpoint.best.1), outcome);
        search.history = checkpoint.history.iter().map(generation_of).collect();
        search.stagnant = checkpoint.stagnant;
        Ok(search)
    }

    /// One generation: select, breed, evaluate the new children, reinsert.
    /// Cancelled, it leaves the search as it was (the random stream too).
    fn step(&mut self, cancel: &Cancel) -> Result<(), Cancelled> {
        let before = self.best.1;
        let rng = self.rng.clone();
        let (Some(first), Some(last)) = (self.population.first(), self.population.last()) else {
            return Ok(()); // generation 0 always leaves genomes; nothing to breed from otherwise
        };
        let (first, last) = (Fit(first.score), Fit(last.score));
        let offspring = {
            let genomes: Vec<Vec<f64>> = self.population.iter().map(|m| m.genes.clone()).collect();
            let fits: Vec<Fit> = self.population.iter().map(|m| Fit(m.score)).collect();
            let evaluated = EvaluatedPopulation::new(Rc::new(genomes), fits, first, last, first);
            let parents = self.selector.select_from(&evaluated, &mut self.rng);
            let read: HashMap<u128, usize> = self
                .population
                .iter()
                .map(|m| (fingerprint(&m.genes), m.key.0))
                .collect();
            let sequence = self.problem.sequence();
            let mut offspring = Vec::with_capacity(parents.len() * 2);
            // Several processes must breed alike: they look at the flag
            // between generations only.
            let alone = self.farm.processes() == 1;
            for pair in parents {
                // Breeding draws from the stream alone: bounded, but a
                // cancel is honoured here too, the stream put back.
                if alone && let Err(why) = cancel.check() {
                    self.rng = rng;
                    return Err(why);
                }
                // Only the genes the parents' packings read can matter.
                let used = pair
                    .iter()
                    .map(|g| read.get(&fingerprint(g)).copied().unwrap_or(sequence))
                    .max()
                    .unwrap_or(sequence);
                let active = used.min(sequence);
                self.crossover.sequence = active;
                self.mutation.sequence = active;
                self.mutation.sequence_rate = 1.0 / active.max(1) as f64;
                for child in self.crossover.crossover(pair, &mut self.rng) {
                    offspring.push(self.mutation.mutate(child, &mut self.rng));
                }
            }
            let count = self.population.len();
            for i in 0..count / IMMIGRANT_SHARE {
                // Past the pinned ends of the initial population: random rules.
                let index = count - 1 - i;
                offspring.push(self.problem.initial(index, count, &mut self.rng));
            }
            offspring
        };
        let members = match self.evaluate(offspring, cancel) {
            Ok(members) => members,
            Err(why) => {
                self.rng = rng;
                return Err(why);
            }
        };
        self.reinsert(members);
        if self.best.1.improves_on(&before) {
            self.stagnant = 0;
        } else {
            self.stagnant += 1;
        }
        Ok(())
    }

    /// Score `genomes`: known phenotypes from memory, the others evaluated
    /// in parallel (each distinct genome once); the best outcome is kept.
    /// Cancelled, nothing is recorded.
    fn evaluate(
        &mut self,
        genomes: Vec<Vec<f64>>,
        cancel: &Cancel,
    ) -> Result<Vec<Member>, Cancelled> {
        let known: Vec<Option<Key>> = genomes.iter().map(|g| self.known(g)).collect();
        let mut fresh = HashSet::new();
        let todo: Vec<usize> = (0..genomes.len())
            .filter(|&i| known[i].is_none() && fresh.insert(fingerprint(&genomes[i])))
            .collect();
        let problem = self.problem;
        let results: Vec<Evaluation<P::Outcome>> = if self.farm.processes() == 1 {
            todo.par_iter()
                .map(|&i| problem.evaluate_until(&genomes[i], cancel))
                .collect::<Result<_, _>>()?
        } else {
            // Scores travel, packings do not: the best one is made again at the end.
            let scores = farm::map(self.farm, todo.len(), |k| {
                problem
                    .evaluate_until(&genomes[todo[k]], cancel)
                    .map(|e| (e.score, e.read))
            });
            scores
                .into_iter()
                .map(|r| {
                    r.map(|(score, read)| Evaluation {
                        score,
                        outcome: P::Outcome::default(),
                        read,
                    })
                })
                .collect::<Result<_, _>>()?
        };
        let remote = self.farm.processes() > 1;
        self.evaluations += results.len() as u64;
        let mut keys = known;
        for (&i, e) in todo.iter().zip(results) {
            let key = self.key(&genomes[i], e.read);
            self.seen.insert(key, e.score);
            if e.score.is_feasible() && e.score.value.is_finite() {
                let [lo, hi] = self.explored;
                self.explored = [lo.min(e.score.value), hi.max(e.score.value)];
            }
            self.lengths.insert(key.0);
            keys[i] = Some(key);
            if e.score.cmp_quality(&self.best.1).is_lt() || self.best.0.is_empty() {
                self.best = (genomes[i].clone(), e.score, e.outcome);
                self.remake = remote;
            }
        }
        Ok(genomes
            .into_iter()
            .zip(keys)
            .filter_map(|(genes, key)| {
                // Duplicates within the batch share the first one's key.
                let key = key.or_else(|| self.known(&genes))?;
                let score = self.seen.get(&key).copied()?;
                Some(Member { genes, key, score })
            })
            .collect())
    }

    /// The key of an evaluated phenotype `genes` belongs to, if any.
    fn known(&self, genes: &[f64]) -> Option<Key> {
        self.lengths
            .iter()
            .map(|&read| self.key(genes, read))
            .find(|key| self.seen.contains_key(key))
    }

    /// The phenotype key of `genes` when its evaluation reads `read` sequence genes.
    fn key(&self, genes: &[f64], read: usize) -> Key {
        let n = self.problem.sequence().min(genes.len());
        let read = read.min(n);
        let head = genes[..read].iter();
        (read, fingerprint_iter(head.chain(&genes[n..])))
    }

    /// (μ + λ): the best distinct genomes of the population and `members`.
    fn reinsert(&mut self, members: Vec<Member>) {
        let mut pool = std::mem::take(&mut self.population);
        pool.extend(members);
        let mut keys = HashSet::new();
        pool.retain(|m| keys.insert(m.key));
        // Stable: on equal scores the older genome stays ahead.
        pool.sort_by(|a, b| a.score.cmp_quality(&b.score));
        pool.truncate(self.limits.population.max(2));
        self.population = pool;
    }

    fn record(&mut self, index: usize) {
        let values: Vec<f64> = self
            .population
            .iter()
            .map(|m| m.score.value)
            .filter(|v| v.is_finite())
            .collect();
        let mean_value = values.iter().sum::<f64>() / values.len().max(1) as f64;
        self.history.push(Generation {
            index,
            best: self.best.1,
            mean_value,
            worst_value: self.population.last().map_or(f64::NAN, |m| m.score.value),
            evaluations: self.evaluations,
            seconds: self.start.elapsed().as_secs_f64(),
        });
    }
}

/// 128-bit FNV-1a over the genes' bit patterns.
fn fingerprint(genes: &[f64]) -> u128 {
    fingerprint_iter(genes.iter())
}

/// 128-bit FNV-1a over the bit patterns of a run of genes.
fn fingerprint_iter<'g>(genes: impl Iterator<Item = &'g f64>) -> u128 {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;
    let mut h = OFFSET;
    for g in genes {
        for byte in g.to_bits().to_le_bytes() {
            h ^= u128::from(byte);
            h = h.wrapping_mul(PRIME);
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;
    use std::sync::Mutex;

    /// Minimise the distance of the mean gene to 0.3; records every evaluation.
    struct Mean {
        calls: Mutex<Vec<Vec<f64>>>,
    }

    impl Problem for Mean {
        type Outcome = f64;
        fn genes(&self) -> usize {
            6
        }
        fn sequence(&self) -> usize {
            4
        }
        fn initial(&self, _: usize, _: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
            (0..6).map(|_| rng.r#gen()).collect()
        }
        fn evaluate(&self, genes: &[f64]) -> Evaluation<f64> {
            self.calls.lock().unwrap().push(genes.to_vec());
            // Reads the first three sequence genes and both parameters.
            let used: Vec<f64> = genes[..3].iter().chain(&genes[4..]).copied().collect();
            let mean = used.iter().sum::<f64>() / used.len() as f64;
            let score = Score {
                violation: 0.0,
                error: (mean - 0.3).powi(2),
                value: mean,
            };
            Evaluation {
                score,
                outcome: mean,
                read: 3,
            }
        }
        fn reached(&self, score: &Score) -> bool {
            score.error < 1e-8
        }
    }

    fn limits() -> Limits {
        Limits {
            population: 16,
            generations: 60,
            stagnation: 60,
            time_limit: Duration::from_secs(60),
            max_evaluations: None,
        }
    }

    #[test]
    fn an_evaluation_budget_stops_at_the_same_generation_every_time() {
        let budget = 100;
        let run = || {
            let problem = Mean {
                calls: Mutex::new(Vec::new()),
            };
            let limits = Limits {
                max_evaluations: Some(budget),
                ..limits()
            };
            Search::start(&problem, limits, 4, &Cancel::new())
                .expect("a fresh token is never raised")
                .run(&Cancel::new(), |_| {})
        };
        let (a, b) = (run(), run());
        assert_eq!(a.stop, StopReason::Evaluations);
        assert!(a.stop.reproducible());
        // Checked between generations: at or past the budget by less than one generation.
        assert!(
            a.evaluations >= budget && a.evaluations < budget + 3 * 16,
            "{}",
            a.evaluations
        );
        let before = a.history[a.history.len() - 2].evaluations;
        assert!(
            before < budget,
            "the generation before was under the budget"
        );
        assert_eq!(
            (a.evaluations, a.history.len()),
            (b.evaluations, b.history.len())
        );
        assert_eq!(a.genes, b.genes);
        assert!(!StopReason::TimeLimit.reproducible());
    }

    #[test]
    fn converges_and_never_evaluates_a_genome_twice() {
        let problem = Mean {
            calls: Mutex::new(Vec::new()),
        };
        let search = Search::start(&problem, limits(), 1, &Cancel::new())
            .expect("a fresh token is never raised");
        let first = search.initial()[0];
        let result = search.run(&Cancel::new(), |_| {});
        assert!(result.best.cmp_quality(&first).is_le());
        assert!((result.outcome - 0.3).abs() < 0.02, "{}", result.outcome);
        let calls = problem.calls.into_inner().unwrap();
        let distinct: HashSet<u128> = calls.iter().map(|g| fingerprint(g)).collect();
        assert_eq!(distinct.len(), calls.len(), "a genome was evaluated twice");
        // Nor was a genome differing only in the unread fourth gene.
        let phenotypes: HashSet<u128> = calls
            .iter()
            .map(|g| fingerprint_iter(g[..3].iter().chain(&g[4..])))
            .collect();
        assert_eq!(
            phenotypes.len(),
            calls.len(),
            "a phenotype was evaluated twice"
        );
        assert_eq!(result.evaluations, calls.len() as u64);
        // The history is monotone in the best score.
        for w in result.history.windows(2) {
            assert!(w[1].best.cmp_quality(&w[0].best).is_le());
        }
    }

    #[test]
    fn stop_flag_and_limits_end_the_search() {
        let problem = Mean {
            calls: Mutex::new(Vec::new()),
        };
        let stopped = Search::start(&problem, limits(), 2, &Cancel::new())
            .expect("a fresh token is never raised")
            .run(
                &{
                    let c = Cancel::new();
                    c.cancel();
                    c
                },
                |_| {},
            );
        assert_eq!(stopped.stop, StopReason::Interrupted);
        assert_eq!(stopped.history.len(), 1);
        let short = Limits {
            generations: 3,
            ..limits()
        };
        let r = Search::start(&problem, short, 2, &Cancel::new())
            .expect("a fresh token is never raised")
            .run(&Cancel::new(), |_| {});
        assert!(matches!(
            r.stop,
            StopReason::Generations | StopReason::Reached
        ));
        assert!(r.history.len() <= 4);
    }

    #[test]
    fn same_seed_same_search_with_any_thread_count() {
        let run = |threads: usize| {
            let problem = Mean {
                calls: Mutex::new(Vec::new()),
            };
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                Search::start(&problem, limits(), 9, &Cancel::new())
                    .expect("a fresh token is never raised")
                    .run(&Cancel::new(), |_| {})
            })
        };
        let (a, b) = (run(1), run(3));
        assert_eq!(a.genes, b.genes);
        assert_eq!(a.evaluations, b.evaluations);
        assert_eq!(a.history.len(), b.history.len());
    }

    #[test]
    fn a_resumed_search_ends_as_the_uninterrupted_one() {
        let problem = Mean {
            calls: Mutex::new(Vec::new()),
        };
        // A target no genome meets: the search runs to its generation limit.
        let limits = Limits {
            generations: 14,
            stagnation: 100,
            ..limits()
        };
        let go = Cancel::new();
        let without = |h: &[Generation]| -> Vec<Generation> {
            h.iter()
                .map(|g| Generation { seconds: 0.0, ..*g })
                .collect()
        };
        let full = Search::start(&problem, limits, 4, &Cancel::new())
            .expect("a fresh token is never raised")
            .run(&go, |_| {});
        let mut saved: Vec<Checkpoint> = Vec::new();
        let again = Search::start(&problem, limits, 4, &Cancel::new())
            .expect("a fresh token is never raised")
            .run_saving(&go, |_| {}, 5, |c| saved.push(c.clone()));
        assert_eq!(again.genes, full.genes, "saving changes nothing");
        assert_eq!(saved.len(), 2, "after generations 5 and 10");
        for checkpoint in &saved {
            // Through text and back, exactly.
            let text = serde_json::to_string(checkpoint).unwrap();
            let back: Checkpoint = serde_json::from_str(&text).unwrap();
            assert_eq!(&back, checkpoint);
            let resumed = Search::resume(&problem, limits, &back)
                .unwrap()
                .run(&go, |_| {});
            assert_eq!(resumed.genes, full.genes);
            assert_eq!(resumed.best, full.best);
            assert_eq!(resumed.outcome, full.outcome);
            assert_eq!(resumed.evaluations, full.evaluations);
            assert_eq!(resumed.explored, full.explored);
            assert_eq!(resumed.stop, full.stop);
            assert_eq!(without(&resumed.history), without(&full.history));
        }
        // An interrupted search saves where it stopped.
        let mut at_stop = None;
        let stop = Cancel::new();
        stop.cancel();
        let _ = Search::start(&problem, limits, 4, &Cancel::new())
            .expect("a fresh token is never raised")
            .run_saving(&stop, |_| {}, 0, |c| at_stop = Some(c.clone()));
        assert_eq!(at_stop.map(|c| c.generations()), Some(1));
    }

    #[test]
    fn a_checkpoint_of_another_problem_is_refused() {
        struct Longer(Mean);
        impl Problem for Longer {
            type Outcome = f64;
            fn genes(&self) -> usize {
                7
            }
            fn sequence(&self) -> usize {
                4
            }
            fn initial(&self, i: usize, n: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
                let mut g = self.0.initial(i, n, rng);
                g.push(0.5);
                g
            }
            fn evaluate(&self, genes: &[f64]) -> Evaluation<f64> {
                self.0.evaluate(&genes[..6])
            }
            fn reached(&self, score: &Score) -> bool {
                self.0.reached(score)
            }
        }
        let mean = Mean {
            calls: Mutex::new(Vec::new()),
        };
        let checkpoint = Search::start(&mean, limits(), 1, &Cancel::new())
            .expect("a fresh token is never raised")
            .checkpoint();
        let longer = Longer(Mean {
            calls: Mutex::new(Vec::new()),
        });
        let err = Search::resume(&longer, limits(), &checkpoint)
            .err()
            .unwrap();
        assert_eq!(
            err,
            ResumeError::GeneCount {
                part: "genome 0 of the population".to_owned(),
                found: 6,
                genes: 7
            }
        );
    }

    /// A checkpoint of a few generations of [`Mean`], through JSON text as a
    /// file would hold it.
    fn saved() -> serde_json::Value {
        let mean = Mean {
            calls: Mutex::new(Vec::new()),
        };
        let mut saved = None;
        let stop = Limits {
            generations: 3,
            stagnation: 100,
            ..limits()
        };
        Search::start(&mean, stop, 1, &Cancel::new())
            .expect("a fresh token is never raised")
            .run_saving(&Cancel::new(), |_| {}, 3, |c| saved = Some(c.clone()));
        serde_json::to_value(saved.expect("saved after generation 3")).unwrap()
    }

    /// Resume [`Mean`] from `edit` applied to [`saved`].
    fn resumed(edit: impl FnOnce(&mut serde_json::Value)) -> Result<Evolution<f64>, ResumeError> {
        let mut value = saved();
        edit(&mut value);
        let checkpoint: Checkpoint = serde_json::from_value(value).expect("still a checkpoint");
        let mean = Mean {
            calls: Mutex::new(Vec::new()),
        };
        Search::resume(&mean, limits(), &checkpoint).map(|s| s.run(&Cancel::new(), |_| {}))
    }

    #[test]
    fn an_untouched_checkpoint_resumes() {
        let done = resumed(|_| {}).expect("resumes");
        assert!(done.history.len() > 4);
    }

    #[test]
    fn a_checkpoint_with_a_zeroed_random_state_is_refused() {
        let err = resumed(|c| c["rng"]["s"] = serde_json::json!([0, 0, 0, 0])).unwrap_err();
        assert_eq!(err, ResumeError::ZeroRandomState);
        assert!(err.to_string().contains("all zeros"), "{err}");
    }

    #[test]
    fn a_search_from_a_zeroed_random_state_still_ends() {
        // Past the load check (the state set after it): the mutation's normal
        // steps, which looped for ever on a stream of zeros, are bounded.
        let mean = Mean {
            calls: Mutex::new(Vec::new()),
        };
        let mut value = saved();
        let checkpoint: Checkpoint = serde_json::from_value(value.clone()).unwrap();
        let mut search = Search::resume(&mean, limits(), &checkpoint).expect("resumes");
        value["rng"]["s"] = serde_json::json!([0, 0, 0, 0]);
        let zero: Checkpoint = serde_json::from_value(value).unwrap();
        search.rng = zero.rng;
        let done = search.run(&Cancel::new(), |_| {});
        assert!(matches!(
            done.stop,
            StopReason::Stagnation | StopReason::Generations | StopReason::Reached
        ));
    }

    #[test]
    fn every_edited_field_of_a_checkpoint_is_refused_by_name() {
        use serde_json::json;
        type Edit = fn(&mut serde_json::Value);
        let cases: [(Edit, &str); 13] = [
            (|c| c["population"] = json!([]), "no population"),
            (|c| c["history"] = json!([]), "no history"),
            (
                |c| c["best"][0] = json!([]),
                "the best genome holds 0 genes, the search needs 6",
            ),
            (
                |c| c["population"][2][0][1] = json!(2.5f64.to_bits()),
                "gene 1 of genome 2 of the population is 2.5",
            ),
            (
                |c| c["population"][0][2][1] = json!(f64::NAN.to_bits()),
                "the score of genome 0 of the population is not a score",
            ),
            (
                |c| c["seen"][0][1][0] = json!((-1.0f64).to_bits()),
                "the score of phenotype 0 is not a score",
            ),
            (
                |c| c["seen"][0][0][0] = json!(1_000_000),
                "phenotype 0 read 1000000 sequence genes",
            ),
            (|c| c["history"][1][0] = json!(7), "record 1 is numbered 7"),
            (
                |c| c["evaluations"] = json!(3),
                "evaluations: 3 evaluations, fewer than",
            ),
            (
                // Found by fuzzing: the next generation's count overflowed.
                |c| c["evaluations"] = json!(u64::MAX),
                "but the last generation recorded counts",
            ),
            (
                |c| {
                    let last = c["history"].as_array().map_or(0, Vec::len) - 1;
                    c["history"][last][6] = json!(u64::MAX);
                    c["evaluations"] = json!(u64::MAX);
                },
                "evaluations, outside [",
            ),
            (
                |c| c["stagnant"] = json!(1_000_000_000),
                "stagnant: 1000000000 generations without progress",
            ),
            (
                |c| c["explored"] = json!([f64::INFINITY.to_bits(), 0]),
                "explored: [inf, 0] is not a range",
            ),
        ];
        for (edit, says) in cases {
            let err = resumed(edit).expect_err(says).to_string();
            assert!(err.contains(says), "{err} does not say {says:?}");
        }
    }
}
