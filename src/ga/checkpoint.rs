//! A search's state between two generations, to continue it exactly later.

use serde::{Deserialize, Serialize};

use super::engine::Generation;
use super::score::Score;

/// Everything [`super::Search::resume`] needs to go on as if the search had
/// never stopped: the random stream, the population, every score seen, the
/// best genome, the history and the time spent.
///
/// Floats are kept as their bit patterns, so a round trip through text is
/// exact (infinite and NaN scores included); entries are sorted, so the same
/// state always serialises to the same bytes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    pub(super) rng: rand_xoshiro::Xoshiro256PlusPlus,
    /// Genes, phenotype key, score; best first.
    pub(super) population: Vec<(Vec<u64>, Key, [u64; 3])>,
    pub(super) initial: Vec<[u64; 3]>,
    /// Every phenotype scored, sorted by key.
    pub(super) seen: Vec<(Key, [u64; 3])>,
    pub(super) evaluations: u64,
    pub(super) explored: [u64; 2],
    pub(super) best: (Vec<u64>, [u64; 3]),
    /// index, best score (3), mean, worst, evaluations, seconds.
    pub(super) history: Vec<[u64; 8]>,
    pub(super) stagnant: usize,
    /// Wall-clock seconds spent so far (bits).
    pub(super) seconds: u64,
}

/// A checkpoint that cannot be resumed on a problem: it was written for
/// another scene, or edited. Each names the part of the checkpoint at fault
/// and what it holds against what the search needs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ResumeError {
    /// The random generator's state is all zeros: a state xoshiro never
    /// reaches from a seed, in which it draws zeros for ever.
    #[error(
        "its random generator's state is all zeros, which no seeded search reaches (the stream would draw only zeros): the checkpoint was edited"
    )]
    ZeroRandomState,
    /// A part that a search always has is empty.
    #[error("it holds no {0}: a search always records one")]
    Missing(&'static str),
    /// A genome of another length than the problem's.
    #[error(
        "{part} holds {found} genes, the search needs {genes}: the checkpoint was written for another scene, or edited"
    )]
    GeneCount {
        /// Which genome (`genome 3 of the population`, `the best genome`).
        part: String,
        /// Genes it holds.
        found: usize,
        /// Genes the problem needs.
        genes: usize,
    },
    /// A gene that is not a number in [0, 1].
    #[error("gene {index} of {part} is {value}, outside [0, 1]")]
    Gene {
        /// Which genome.
        part: String,
        /// The gene's position.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A score no evaluation gives: NaN or negative parts, or infinite
    /// ones other than the worst score's.
    #[error(
        "{part} is not a score an evaluation gives (violation {}, error {}, value {}): a score is finite with violation and error ≥ 0, or the worst score (∞, ∞, NaN)",
        score.violation, score.error, score.value
    )]
    Score {
        /// Which score.
        part: String,
        /// What it holds.
        score: Score,
    },
    /// A counter or range at odds with the rest of the checkpoint.
    #[error("{field}: {detail}")]
    Inconsistent {
        /// The checkpoint's field (`history`, `evaluations`, `stagnant`, …).
        field: &'static str,
        /// What is wrong with it.
        detail: String,
    },
}

/// A phenotype key: sequence genes read, and the fingerprint as two halves
/// (JSON numbers do not hold 128 bits everywhere).
pub(super) type Key = (usize, [u64; 2]);

impl Checkpoint {
    /// Generations recorded so far, generation 0 included.
    #[cfg(test)]
    pub(super) fn generations(&self) -> usize {
        self.history.len()
    }

    /// Number of genes of its genomes (0 for an empty population).
    pub fn genes(&self) -> usize {
        self.population.first().map_or(0, |m| m.0.len())
    }
}

impl Checkpoint {
    /// Check every field against a problem of `genes` genes, of which
    /// `sequence` are sequence genes, and a population of at most
    /// `population` genomes: no checkpoint that passes can make a resumed
    /// search loop for ever, panic or take more memory than the search it
    /// continues.
    ///
    /// # Errors
    /// The first fault found, as a [`ResumeError`].
    pub(super) fn validate(
        &self,
        genes: usize,
        sequence: usize,
        population: usize,
    ) -> Result<(), ResumeError> {
        if serde_json::to_value(&self.rng).ok() == Some(serde_json::json!({ "s": [0, 0, 0, 0] })) {
            return Err(ResumeError::ZeroRandomState);
        }
        if self.population.is_empty() {
            return Err(ResumeError::Missing("population"));
        }
        if self.history.is_empty() {
            return Err(ResumeError::Missing("history of generations"));
        }
        if self.initial.is_empty() {
            return Err(ResumeError::Missing("initial population's scores"));
        }
        let inconsistent =
            |field: &'static str, detail: String| Err(ResumeError::Inconsistent { field, detail });
        for (field, n) in [
            ("population", self.population.len()),
            ("initial", self.initial.len()),
        ] {
            if n > population {
                return inconsistent(
                    field,
                    format!(
                        "{n} genomes, more than the search keeps ({population}, optimise.population)"
                    ),
                );
            }
        }
        let genome = |part: String, g: &[u64]| -> Result<(), ResumeError> {
            if g.len() != genes {
                return Err(ResumeError::GeneCount {
                    part,
                    found: g.len(),
                    genes,
                });
            }
            match floats(g)
                .into_iter()
                .enumerate()
                .find(|(_, v)| !(0.0..=1.0).contains(v))
            {
                Some((index, value)) => Err(ResumeError::Gene { part, index, value }),
                None => Ok(()),
            }
        };
        let score = |part: &dyn Fn() -> String, b: &[u64; 3]| -> Result<(), ResumeError> {
            let s = score_of(b);
            let worst =
                s.violation == f64::INFINITY && s.error == f64::INFINITY && s.value.is_nan();
            let finite = [s.violation, s.error, s.value]
                .iter()
                .all(|v| v.is_finite())
                && s.violation >= 0.0
                && s.error >= 0.0;
            if worst || finite {
                Ok(())
            } else {
                Err(ResumeError::Score {
                    part: part(),
                    score: s,
                })
            }
        };
        let key = |part: &dyn Fn() -> String, k: &Key| -> Result<(), ResumeError> {
            if k.0 > sequence {
                return inconsistent(
                    "seen",
                    format!(
                        "{} read {} sequence genes, the search has {sequence}",
                        part(),
                        k.0
                    ),
                );
            }
            Ok(())
        };
        for (i, (g, k, s)) in self.population.iter().enumerate() {
            let part = || format!("genome {i} of the population");
            genome(part(), g)?;
            key(&part, k)?;
            score(&|| format!("the score of {}", part()), s)?;
        }
        genome("the best genome".to_owned(), &self.best.0)?;
        score(&|| "the best genome's score".to_owned(), &self.best.1)?;
        for (i, s) in self.initial.iter().enumerate() {
            score(&|| format!("initial score {i}"), s)?;
        }
        for (i, (k, s)) in self.seen.iter().enumerate() {
            key(&|| format!("phenotype {i}"), k)?;
            score(&|| format!("the score of phenotype {i}"), s)?;
        }
        if (self.seen.len() as u64) > self.evaluations {
            return inconsistent(
                "evaluations",
                format!(
                    "{} evaluations, fewer than the {} phenotypes scored",
                    self.evaluations,
                    self.seen.len()
                ),
            );
        }
        let mut evaluations: u64 = 0;
        for (i, record) in self.history.iter().enumerate() {
            let g = generation_of(record);
            if record[0] != i as u64 {
                return inconsistent("history", format!("record {i} is numbered {}", record[0]));
            }
            score(
                &|| format!("the best score of generation {i}"),
                &[record[1], record[2], record[3]],
            )?;
            // A generation scores at most its offspring (two per pair of
            // parents) and its immigrants: under three per member.
            let most = evaluations.saturating_add(3 * population.max(2) as u64);
            if g.evaluations < evaluations || g.evaluations > self.evaluations.min(most) {
                return inconsistent(
                    "history",
                    format!(
                        "generation {i} counts {} evaluations, outside [{evaluations}, {}] (the generation before, and the checkpoint's)",
                        g.evaluations, self.evaluations
                    ),
                );
            }
            evaluations = g.evaluations;
            // The mean is over finite values (0 for none); the worst is a
            // member's value, NaN for the worst score.
            let times = g.seconds.is_finite() && g.seconds >= 0.0;
            if !times || !g.mean_value.is_finite() || g.worst_value.is_infinite() {
                return inconsistent(
                    "history",
                    format!(
                        "generation {i} holds mean {}, worst {}, seconds {}",
                        g.mean_value, g.worst_value, g.seconds
                    ),
                );
            }
        }
        // Checkpoints are of whole generations: the count is the last one's.
        if evaluations != self.evaluations {
            return inconsistent(
                "evaluations",
                format!(
                    "{} evaluations, but the last generation recorded counts {evaluations}",
                    self.evaluations
                ),
            );
        }
        if self.stagnant >= self.history.len() {
            return inconsistent(
                "stagnant",
                format!(
                    "{} generations without progress, but only {} after generation 0 were recorded",
                    self.stagnant,
                    self.history.len() - 1
                ),
            );
        }
        let [lo, hi] = self.explored.map(f64::from_bits);
        let empty = lo == f64::INFINITY && hi == f64::NEG_INFINITY;
        if !(empty || (lo.is_finite() && hi.is_finite() && lo <= hi)) {
            return inconsistent(
                "explored",
                format!(
                    "[{lo}, {hi}] is not a range of values (finite, low ≤ high, or [inf, -inf] for none)"
                ),
            );
        }
        let seconds = f64::from_bits(self.seconds);
        if !(seconds.is_finite() && seconds >= 0.0) {
            return inconsistent("seconds", format!("{seconds} is not a time spent"));
        }
        Ok(())
    }
}

pub(super) fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

pub(super) fn floats(v: &[u64]) -> Vec<f64> {
    v.iter().map(|&b| f64::from_bits(b)).collect()
}

pub(super) fn score_bits(s: &Score) -> [u64; 3] {
    [s.violation.to_bits(), s.error.to_bits(), s.value.to_bits()]
}

pub(super) fn score_of(b: &[u64; 3]) -> Score {
    Score {
        violation: f64::from_bits(b[0]),
        error: f64::from_bits(b[1]),
        value: f64::from_bits(b[2]),
    }
}

pub(super) fn key_bits((read, print): (usize, u128)) -> Key {
    (read, [(print >> 64) as u64, print as u64])
}

pub(super) fn key_of((read, [hi, lo]): Key) -> (usize, u128) {
    (read, (u128::from(hi) << 64) | u128::from(lo))
}

pub(super) fn generation_bits(g: &Generation) -> [u64; 8] {
    let [a, b, c] = score_bits(&g.best);
    [
        g.index as u64,
        a,
        b,
        c,
        g.mean_value.to_bits(),
        g.worst_value.to_bits(),
        g.evaluations,
        g.seconds.to_bits(),
    ]
}

pub(super) fn generation_of(b: &[u64; 8]) -> Generation {
    Generation {
        index: b[0] as usize,
        best: score_of(&[b[1], b[2], b[3]]),
        mean_value: f64::from_bits(b[4]),
        worst_value: f64::from_bits(b[5]),
        evaluations: b[6],
        seconds: f64::from_bits(b[7]),
    }
}
