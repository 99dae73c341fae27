//! Variation operators on genomes of genes in [0, 1], as genevo operators.
//!
//! A genome is a *sequence* part (genes whose position matters, such as the
//! grading genes: the i-th drawn size) followed by a *parameter* part
//! (real-valued settings such as the packing-rule genes). genevo has no
//! real-valued crossover, hence these.

use genevo::operator::{CrossoverOp, GeneticOperator, MutationOp};
use genevo::random::Rng;
use rand::RngCore;
use rand_distr::{Distribution, StandardNormal};

/// How many sequence genes, counted from the end, the tail step may move.
pub(super) const TAIL: usize = 3;

/// Two-point crossover on the sequence genes (the children swap one
/// segment, so each position keeps a parent's gene) and BLX-α on the
/// parameter genes (each child gene uniform in the parents' interval widened
/// by α of its length on both sides, clamped to [0, 1]).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Crossover {
    /// Number of sequence genes at the start of the genome.
    pub sequence: usize,
    /// BLX widening, as a fraction of the parents' interval.
    pub alpha: f64,
}

impl GeneticOperator for Crossover {
    fn name() -> String {
        "segment/BLX-alpha crossover".to_owned()
    }
}

impl CrossoverOp<Vec<f64>> for Crossover {
    fn crossover<R: Rng + Sized>(&self, parents: Vec<Vec<f64>>, rng: &mut R) -> Vec<Vec<f64>> {
        let (Some(a), Some(b)) = (parents.first(), parents.get(1)) else {
            return parents;
        };
        let (mut c, mut d) = (a.clone(), b.clone());
        let n = self.sequence.min(a.len());
        if n > 1 {
            let (mut i, mut j) = (rng.gen_range(0..=n), rng.gen_range(0..=n));
            if i > j {
                std::mem::swap(&mut i, &mut j);
            }
            c[i..j].copy_from_slice(&b[i..j]);
            d[i..j].copy_from_slice(&a[i..j]);
        }
        for k in n..a.len() {
            let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
            let reach = self.alpha * (hi - lo);
            for child in [&mut c, &mut d] {
                let u: f64 = rng.r#gen();
                child[k] = (lo - reach + u * (hi - lo + 2.0 * reach)).clamp(0.0, 1.0);
            }
        }
        vec![c, d]
    }
}

/// Mutation: each sequence gene is redrawn uniformly with probability
/// `sequence_rate`; with probability `swap_rate` two sequence genes trade
/// places (the same sizes, drawn in another order); with probability
/// `tail_rate` one of the last [`TAIL`] sequence genes moves by a normal step
/// of standard deviation `sigma` (the last sizes drawn move only the last
/// disks: a fine adjustment where earlier genes reshuffle the whole
/// packing); each parameter gene moves by a normal step of standard
/// deviation `sigma` with probability `parameter_rate`. Steps are clamped to
/// [0, 1].
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Mutation {
    /// Number of sequence genes at the start of the genome.
    pub sequence: usize,
    /// Probability that one sequence gene is redrawn.
    pub sequence_rate: f64,
    /// Probability that a genome gets one swap of two sequence genes.
    pub swap_rate: f64,
    /// Probability that a genome gets one step on a gene near the end of its sequence.
    pub tail_rate: f64,
    /// Probability that one parameter gene moves.
    pub parameter_rate: f64,
    /// Standard deviation of a parameter gene's step.
    pub sigma: f64,
}

impl GeneticOperator for Mutation {
    fn name() -> String {
        "redraw/normal-step mutation".to_owned()
    }
}

impl MutationOp<Vec<f64>> for Mutation {
    fn mutate<R: Rng + Sized>(&self, mut genome: Vec<f64>, rng: &mut R) -> Vec<f64> {
        let n = self.sequence.min(genome.len());
        for gene in &mut genome[..n] {
            if rng.r#gen::<f64>() < self.sequence_rate {
                *gene = rng.r#gen();
            }
        }
        if n > 1 && rng.r#gen::<f64>() < self.swap_rate {
            genome.swap(rng.gen_range(0..n), rng.gen_range(0..n));
        }
        if n > 0 && rng.r#gen::<f64>() < self.tail_rate {
            let k = n - 1 - rng.gen_range(0..TAIL.min(n));
            let step = normal_step(rng);
            genome[k] = (genome[k] + self.sigma * step).clamp(0.0, 1.0);
        }
        for gene in &mut genome[n..] {
            if rng.r#gen::<f64>() < self.parameter_rate {
                let step = normal_step(rng);
                *gene = (*gene + self.sigma * step).clamp(0.0, 1.0);
            }
        }
        genome
    }
}

/// Most words of the random stream one normal step may draw.
///
/// A standard normal draw (rand_distr's ziggurat) takes one word, rarely two
/// or a few (its rejection steps accept with probability above 0.98), so a
/// stream that gives a normal draw ever does so within this budget, but for
/// odds below 10⁻⁵⁰. A stream that does not — the all-zero state of
/// xoshiro, which draws zeros for ever and sends the ziggurat's tail loop
/// round for ever — gets the words of [`Budget`] once the budget is spent,
/// which end every loop of the draw at once: a finite step all the same.
pub(super) const NORMAL_BUDGET: u32 = 64;

/// A standard normal draw from `rng` that cannot loop for ever: the same
/// value as `StandardNormal.sample(rng)` whenever that takes at most
/// [`NORMAL_BUDGET`] words of the stream, else a finite value made of the
/// words drawn and [`Budget`]'s settling word.
pub(super) fn normal_step<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    StandardNormal.sample(&mut Budget {
        rng,
        left: NORMAL_BUDGET,
    })
}

/// A random stream that gives at most `left` words of `rng`, then
/// [`Budget::SETTLE`] for ever.
struct Budget<'r, R: ?Sized> {
    rng: &'r mut R,
    left: u32,
}

impl<R: ?Sized> Budget<'_, R> {
    /// A word that ends every loop of the ziggurat: as its first word,
    /// layer 1 (low byte) and 3.0 in [2, 4) from the 52 bits above the 12
    /// lowest, so u = 3.0 − 3.0 = 0 and x = 0 lies inside every layer; as a
    /// float in (0, 1) inside the tail loop, ½, whose logarithms meet the
    /// tail's test at once.
    const SETTLE: u64 = 0x8000_0000_0000_0001;
}

impl<R: RngCore + ?Sized> RngCore for Budget<'_, R> {
    fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    fn next_u64(&mut self) -> u64 {
        if self.left == 0 {
            return Self::SETTLE;
        }
        self.left -= 1;
        self.rng.next_u64()
    }

    fn fill_bytes(&mut self, dest: &mut [u8]) {
        for chunk in dest.chunks_mut(8) {
            let word = self.next_u64().to_le_bytes();
            chunk.copy_from_slice(&word[..chunk.len()]);
        }
    }

    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), rand::Error> {
        self.fill_bytes(dest);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    #[test]
    fn crossover_keeps_positions_and_blends_parameters_within_bounds() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let op = Crossover {
            sequence: 6,
            alpha: 0.5,
        };
        let a = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.2, 0.0];
        let b = vec![1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.4, 1.0];
        for _ in 0..200 {
            let children = op.crossover(vec![a.clone(), b.clone()], &mut rng);
            assert_eq!(children.len(), 2);
            let (c, d) = (&children[0], &children[1]);
            for k in 0..6 {
                // Each position holds one parent's gene, and the two children complement.
                assert!(c[k] == 0.0 || c[k] == 1.0);
                assert_eq!(c[k] + d[k], 1.0);
            }
            for child in [c, d] {
                assert!((0.1..=0.5).contains(&child[6]), "BLX range: {}", child[6]);
                assert!((0.0..=1.0).contains(&child[7]));
            }
        }
    }

    #[test]
    fn mutation_rates_are_honoured() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let op = Mutation {
            sequence: 1000,
            sequence_rate: 0.01,
            swap_rate: 0.0,
            tail_rate: 0.0,
            parameter_rate: 1.0,
            sigma: 0.1,
        };
        let mut changed = 0;
        for _ in 0..100 {
            let g = op.mutate(vec![0.5; 1002], &mut rng);
            changed += g[..1000].iter().filter(|&&x| x != 0.5).count();
            assert!(g[1000] != 0.5 && (0.0..=1.0).contains(&g[1000]));
        }
        // 100 genomes × 1000 genes × 1 % = 1000 redraws expected.
        assert!((800..1200).contains(&changed), "{changed}");
    }

    #[test]
    fn a_normal_step_is_the_standard_normal_draw_of_a_real_stream() {
        let (mut a, mut b) = (
            Xoshiro256PlusPlus::seed_from_u64(11),
            Xoshiro256PlusPlus::seed_from_u64(11),
        );
        for _ in 0..100_000 {
            let plain: f64 = StandardNormal.sample(&mut a);
            assert_eq!(normal_step(&mut b).to_bits(), plain.to_bits());
        }
        assert_eq!(a, b, "the same words drawn");
    }

    #[test]
    fn a_stream_of_zeros_gets_a_finite_step_instead_of_an_endless_loop() {
        // The all-zero state of xoshiro: every word is 0, for ever. Built
        // through serde, the only way to reach it (seeding avoids it).
        let mut zero: Xoshiro256PlusPlus =
            serde_json::from_str(r#"{"s":[0,0,0,0]}"#).expect("a state");
        assert_eq!(zero.next_u64(), 0);
        assert!(normal_step(&mut zero).is_finite());
        // A first word that settles at once gives exactly 0.
        let mut settled = Budget {
            rng: &mut zero,
            left: 0,
        };
        let step: f64 = StandardNormal.sample(&mut settled);
        assert_eq!(step, 0.0);
        // And so a mutation with every step on finishes.
        let op = Mutation {
            sequence: 4,
            sequence_rate: 1.0,
            swap_rate: 1.0,
            tail_rate: 1.0,
            parameter_rate: 1.0,
            sigma: 0.1,
        };
        let g = op.mutate(vec![0.5; 6], &mut zero);
        assert!(g.iter().all(|x| (0.0..=1.0).contains(x)), "{g:?}");
    }
}
