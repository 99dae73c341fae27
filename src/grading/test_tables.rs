//! Reference tables and sampling helpers shared by the grading unit tests.

use super::Grading;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Thesis Table 3.1 (benchmark run).
pub(super) use super::THESIS_TABLE_3_1 as TABLE_3_1;

/// Thesis Table 3.4 (proppant, fracture case).
pub(super) use super::THESIS_TABLE_3_4 as TABLE_3_4;

/// Thesis Table 4.1 (AP-5 three-part grading with a step at 2.4 mm).
pub(super) const TABLE_4_1: &[(f64, f64)] = &[(1.2, 0.0), (2.4, 10.0), (2.4, 90.0), (6.0, 100.0)];

/// `n` draws at evenly spaced genes u = (i + 0.5) / n.
pub(super) fn even_sample(g: &Grading, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| g.sample((i as f64 + 0.5) / n as f64))
        .collect()
}

/// `n` draws at seeded uniform random genes.
pub(super) fn random_sample(g: &Grading, n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..n).map(|_| g.sample(rng.r#gen::<f64>())).collect()
}
