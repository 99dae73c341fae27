//! Fidelity of a set of diameters to a grading curve: the Kolmogorov–Smirnov
//! distance in the curve's basis.

use rayon::prelude::*;

use super::Grading;

impl Grading {
    /// Kolmogorov–Smirnov distance of `diameters` to the curve, in the curve's basis.
    ///
    /// # Behavior
    /// The empirical CDF weighs each diameter as the curve's basis does
    /// (Number: 1, Mass: d², Mass3d: d³); the result is the supremum over all
    /// d of |F_emp(d) − F(d)|, in [0, 1]. Both one-sided limits are compared
    /// at every distinct sample value (ties are grouped), so a step of the
    /// curve met exactly by the sample counts as a match: a constant grading
    /// measured on disks of exactly its diameter gives 0. Between two sample
    /// values F_emp is constant and F monotone, so the largest gap there is
    /// at one of the ends, and the curve's atoms need no separate visit.
    ///
    /// # Returns
    /// 1.0 (the largest possible distance) for an empty slice or one holding
    /// a diameter that is not positive and finite, since such a set cannot
    /// follow any curve.
    ///
    /// # Performance
    /// Sorts a copy (`sort_positive`): O(n) time, O(n) memory; the
    /// curve's CDF at each distinct size on every core
    /// ([`Grading::ks_distance_sorting`] sorts the caller's own instead).
    pub fn ks_distance(&self, diameters: &[f64]) -> f64 {
        self.ks_distance_sorting(&mut diameters.to_vec())
    }

    /// [`Grading::ks_distance`] of `diameters`, sorting them in place: no
    /// copy, for a caller that collected them for this alone.
    pub fn ks_distance_sorting(&self, diameters: &mut [f64]) -> f64 {
        if diameters.is_empty() || diameters.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
            return 1.0;
        }
        sort_positive(diameters);
        let sorted = &*diameters;
        let k = self.basis().exponent();
        let largest = sorted.last().copied().unwrap_or(1.0);
        // Weights relative to the largest diameter: no overflow, the largest weighs 1.
        let weight = |d: f64| if k == 0 { 1.0 } else { (d / largest).powi(k) };
        let total: f64 = sorted.iter().map(|&d| weight(d)).sum();
        // The weight below each run of groups, summed group by group in
        // order as the sweep would: each run is then swept on its own
        // (the curve's CDF at every group is the costly part), with the
        // same sums bit for bit whatever the number of threads.
        let mut runs = vec![(0, 0.0)];
        let (mut below, mut start) = (0.0, 0);
        for group in sorted.chunk_by(|a, b| a == b) {
            if start - runs.last().map_or(0, |r| r.0) >= KS_RUN {
                runs.push((start, below));
            }
            below += group.iter().map(|&x| weight(x)).sum::<f64>();
            start += group.len();
        }
        runs.push((sorted.len(), below));
        runs.par_windows(2)
            .map(|run| {
                let ((from, mut below), (to, _)) = (run[0], run[1]);
                let mut seen = from;
                let mut distance = 0.0f64;
                for group in sorted[from..to].chunk_by(|a, b| a == b) {
                    let d = group.first().copied().unwrap_or(largest);
                    let through = below + group.iter().map(|&x| weight(x)).sum::<f64>();
                    seen += group.len();
                    let before = below / total;
                    let after = if seen == sorted.len() {
                        1.0
                    } else {
                        through / total
                    };
                    let (left, at) = self.cdf_limits(d);
                    distance = distance.max((before - left).abs()).max((after - at).abs());
                    below = through;
                }
                distance
            })
            .reduce(|| 0.0, f64::max)
            .min(1.0)
    }
}

/// Sizes a run of the KS sweep holds, at least: the sweep's tasks.
const KS_RUN: usize = if cfg!(test) { 5 } else { 1 << 16 };

/// Sort positive finite numbers (whose bits order as the numbers do, each
/// value one pattern) by their bits: the same order as `f64::total_cmp`.
///
/// # Performance
/// A least-significant-digit radix sort, a byte a pass, the passes where
/// every number shares the byte skipped (the high bytes of sizes within a
/// factor of a few): O(n) time, one copy of the numbers beside them.
pub(crate) fn sort_positive(values: &mut [f64]) {
    if values.len() < 1 << 10 {
        values.sort_unstable_by(f64::total_cmp);
        return;
    }
    let n = values.len();
    let digit = |x: f64, pass: usize| ((x.to_bits() >> (8 * pass)) & 0xff) as usize;
    let mut counts = [[0usize; 256]; 8];
    for &x in values.iter() {
        for (pass, count) in counts.iter_mut().enumerate() {
            count[digit(x, pass)] += 1;
        }
    }
    let mut spare = vec![0.0f64; n];
    let mut in_values = true;
    for (pass, count) in counts.iter().enumerate() {
        if count.contains(&n) {
            continue;
        }
        let mut next = [0usize; 256];
        let mut sum = 0;
        for (slot, &c) in next.iter_mut().zip(count) {
            *slot = sum;
            sum += c;
        }
        let (from, to): (&[f64], &mut [f64]) = if in_values {
            (values, &mut spare)
        } else {
            (&spare, values)
        };
        for &x in from {
            let slot = &mut next[digit(x, pass)];
            to[*slot] = x;
            *slot += 1;
        }
        in_values = !in_values;
    }
    if !in_values {
        values.copy_from_slice(&spare);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_tables::{TABLE_3_1, TABLE_4_1, random_sample};
    use super::super::{Basis, Interpolation};
    use super::*;
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// KS by brute force: |F_emp(y) − F(y)| with F_emp counted directly, at
    /// every sample value, curve atom and point of a fine grid, and just
    /// below each of them (for the left limits).
    fn ks_brute_force(g: &Grading, xs: &[f64], atoms: &[f64]) -> f64 {
        let grid: Vec<f64> = (0..=700).map(|i| 0.5 + f64::from(i) * 0.01).collect();
        let k = g.basis().exponent();
        let w = |d: f64| d.powi(k);
        let total: f64 = xs.iter().map(|&d| w(d)).sum();
        let emp = |y: f64| xs.iter().filter(|&&d| d <= y).map(|&d| w(d)).sum::<f64>() / total;
        let mut worst = 0.0f64;
        for &x in xs.iter().chain(atoms).chain(&grid) {
            for y in [x, x * (1.0 - 1e-12)] {
                worst = worst.max((emp(y) - g.cdf(y)).abs());
            }
        }
        worst
    }

    #[test]
    fn radix_sort_orders_as_total_cmp() {
        // Sizes over many octaves (every byte of the bits varies), a
        // narrow grading's (the high bytes shared: their passes skipped),
        // ties, and lengths either side of the small-slice cut.
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        for n in [0, 1, 5, 1023, 1024, 1025, 40_000] {
            let wide: Vec<f64> = (0..n)
                .map(|_| 10f64.powf(rng.gen_range(-300.0..300.0)))
                .collect();
            let narrow: Vec<f64> = (0..n).map(|_| rng.gen_range(1.2..1.3)).collect();
            let tied: Vec<f64> = (0..n).map(|_| f64::from(rng.gen_range(1..9u8))).collect();
            for mut values in [wide, narrow, tied] {
                let mut expected = values.clone();
                expected.sort_unstable_by(f64::total_cmp);
                sort_positive(&mut values);
                assert_eq!(
                    values.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    expected.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
                );
            }
        }
    }

    #[test]
    fn hand_computed_distances() {
        let g = Grading::uniform(1.0, 2.0, Basis::Number).expect("ok");
        assert!((g.ks_distance(&[1.5]) - 0.5).abs() < 1e-12);
        assert!((g.ks_distance(&[1.75, 1.25]) - 0.25).abs() < 1e-12);
        assert_eq!(g.ks_distance(&[0.5]), 1.0);
        assert_eq!(g.ks_distance(&[7.0, 8.0]), 1.0);
        // by area, [1, 2]: weights 1 and 4, F_emp jumps 0.2 at 1 and 0.8 at 2
        let m = Grading::uniform(1.0, 2.0, Basis::Mass).expect("ok");
        assert!((m.ks_distance(&[2.0, 1.0]) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn step_met_exactly_counts_both_limits() {
        let g = Grading::from_table(TABLE_4_1, Interpolation::Log, Basis::Number).expect("ok");
        // all at the step: F(2.4−) = 0.1 and F(2.4) = 0.9 against 0 and 1
        assert!((g.ks_distance(&[2.4; 10]) - 0.1).abs() < 1e-12);
        // 10 % at 1.2, 80 % at 2.4, 10 % at 6.0 (the ends): the gap is the
        // segment mass each side, 0.1
        let mut xs = vec![2.4; 80];
        xs.extend([1.2; 10]);
        xs.extend([6.0; 10]);
        assert!((g.ks_distance(&xs) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn constant_packed_exactly_is_zero() {
        for basis in [Basis::Number, Basis::Mass, Basis::Mass3d] {
            let g = Grading::uniform(1.25, 1.25, basis).expect("ok");
            assert_eq!(g.ks_distance(&[1.25, 1.25, 1.25]), 0.0);
            // half the disks (by number) too large: about half off
            let off = g.ks_distance(&[1.25, 1.26]);
            assert!((off - 0.5).abs() < 0.01, "{basis:?}: {off}");
        }
    }

    #[test]
    fn empty_or_invalid_input_is_worst() {
        let g = Grading::constant(1.0).expect("ok");
        assert_eq!(g.ks_distance(&[]), 1.0);
        for bad in [f64::NAN, f64::INFINITY, 0.0, -1.0] {
            assert_eq!(g.ks_distance(&[1.0, bad]), 1.0, "{bad}");
        }
    }

    #[test]
    fn order_does_not_matter() {
        let g = Grading::from_table(TABLE_3_1, Interpolation::Log, Basis::Mass).expect("ok");
        let xs = random_sample(&g, 1000, 5);
        let mut shuffled = xs.clone();
        shuffled.shuffle(&mut Xoshiro256PlusPlus::seed_from_u64(6));
        assert_eq!(g.ks_distance(&xs), g.ks_distance(&shuffled));
    }

    #[test]
    fn matches_brute_force_with_ties_and_atoms() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        for basis in [Basis::Number, Basis::Mass, Basis::Mass3d] {
            let g = Grading::from_table(TABLE_4_1, Interpolation::Log, basis).expect("ok");
            for _ in 0..200 {
                let n = rng.gen_range(1..40);
                // a few values from a coarse grid (ties, the atom, outside the
                // range) mixed with exact draws
                let xs: Vec<f64> = (0..n)
                    .map(|_| {
                        if rng.r#gen::<bool>() {
                            [1.0, 1.2, 2.0, 2.4, 2.4, 3.0, 6.0, 7.0][rng.gen_range(0..8)]
                        } else {
                            g.sample(rng.r#gen())
                        }
                    })
                    .collect();
                let fast = g.ks_distance(&xs);
                let slow = ks_brute_force(&g, &xs, &[2.4]);
                assert!(
                    (fast - slow).abs() < 1e-9,
                    "{basis:?} {xs:?}: {fast} vs {slow}"
                );
            }
        }
    }
}
