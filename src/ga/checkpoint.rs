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
