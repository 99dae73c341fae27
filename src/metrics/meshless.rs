//! Meshless support sizes: each particle's h_k, the distance from its
//! centre to the centre of its k-th nearest neighbour (k = 6 for `h6`),
//! which point discretisations built from a packing use as the local
//! support size, and the distribution of h6 over each particle's own
//! diameter for `summary.json`.
//!
//! Particles that are not disks count by their centres, and are
//! normalised by their area-equivalent diameter (`Packing::disks` holds
//! both). Wall disks are not particles and are never neighbours. In a
//! periodic cell each other particle counts once, at its minimum-image
//! distance (its own images are not neighbours).
//!
//! The neighbour index is the measure's own (`ByRadius`, `near.rs`), not
//! the packer's MX quadtree: [`super::measure`] has already built it over
//! the finished packing (no third index, no second copy), it buckets
//! each size class by its own largest radius so that a coarse particle
//! among fine ones does not sweep cells sized for the coarse (the MX
//! quadtree's leaves are sized by the largest diameter, for the packer's
//! fixed-radius queries, and the packer drops it when it returns), and
//! it is independent of the generator, as every measure is.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::near::ByRadius;
use super::{CHUNK, POLL_EVERY, images_near};
use crate::cancel::{Cancel, Cancelled};
use crate::geometry::{Disk, Domain, Point};
use crate::packer::Packing;

/// The neighbour `summary.json` reports: h6.
pub const H6: usize = 6;

/// Particles the summary's distribution is taken over at most: above it,
/// every `stride`-th packed particle in placement order (`stride` =
/// ⌈n / SUMMARY_PARTICLES⌉), so the measure's cost stays bounded (a
/// systematic sample of 10⁵ puts a mean within about 0.3 % of its
/// standard deviation of the whole's); `H6Stats::stride` says which.
/// The per-particle values ([`hk`]) are always every particle's.
#[cfg(not(test))]
pub const SUMMARY_PARTICLES: usize = 100_000;
/// A small sample in the unit tests, so that their packings are sampled.
#[cfg(test)]
pub const SUMMARY_PARTICLES: usize = 40;

/// Doublings of the search box at most: it starts at least 1/1024 of the
/// farthest any neighbour can be, so about 11 suffice.
const MAX_ROUNDS: usize = 64;

/// The distribution of h6 / d over a packing's particles (d its own
/// diameter, area-equivalent for particles that are not disks), with the
/// means of h5 / d and h7 / d beside it to show how much the choice of the
/// 6th neighbour matters (fields in alphabetical order, as every object of
/// a summary). `summary.json` records it as `h6_over_d`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct H6Stats {
    /// Particles with a finite h6 / d the figures are taken over: every
    /// `stride`-th particle once there are 7.
    pub count: usize,
    /// Mean of h5 / d (NaN, `null` in JSON, with fewer than 6 particles),
    /// summed in the neighbour index's order: the same bits whatever the
    /// threads.
    pub h5_mean: f64,
    /// Mean of h7 / d (NaN, `null` in JSON, with fewer than 8 particles),
    /// summed as `h5_mean`.
    pub h7_mean: f64,
    /// Greatest h6 / d.
    pub max: f64,
    /// Mean h6 / d.
    pub mean: f64,
    /// Least h6 / d.
    pub min: f64,
    /// 5th percentile of h6 / d (linear between order statistics, as
    /// numpy's default `percentile`).
    pub p5: f64,
    /// Median of h6 / d (as `p5`).
    pub p50: f64,
    /// 95th percentile of h6 / d (as `p5`).
    pub p95: f64,
    /// Sample standard deviation of h6 / d (n − 1).
    pub sd: f64,
    /// Every how many packed particles (in placement order) the figures
    /// are taken over: 1 (every particle) up to [`SUMMARY_PARTICLES`].
    pub stride: usize,
}

/// Each packed particle's h_k (mm): the distance from its centre to the
/// centre of its `k`-th nearest other packed particle, in the order of
/// `packing.disks`; NaN for every particle when the packing holds `k`
/// particles or fewer (h_k undefined), and for `k = 0`. In a periodic cell
/// the distances are minimum-image distances.
///
/// The same packing gives the same bits whatever the number of threads:
/// each value is the `k`-th smallest of exactly computed distances.
///
/// # Performance
/// One index over the particles (`ByRadius`) and a search per particle
/// in boxes doubling from about two of its diameters: O(n) in a dense
/// packing, in parallel.
pub fn hk(packing: &Packing, k: usize) -> Vec<f64> {
    // A new token is never raised; were it, every value would be undefined.
    hk_cancellable(packing, k, &Cancel::new())
        .unwrap_or_else(|_| vec![f64::NAN; packing.disks.len()])
}

/// [`hk`] with `k` = 6: the meshless support size h6 of each particle.
pub fn h6(packing: &Packing) -> Vec<f64> {
    hk(packing, H6)
}

/// [`hk`], stopped by `cancel` (polled every 1024 particles).
///
/// # Errors
/// [`Cancelled`] once `cancel` is raised or its deadline passes.
pub fn hk_cancellable(packing: &Packing, k: usize, cancel: &Cancel) -> Result<Vec<f64>, Cancelled> {
    let disks = &packing.disks;
    let near = ByRadius::new(disks, 0..disks.len());
    let search = Search::new(&packing.domain, disks, &near, 0);
    let out = nan_slots(disks.len());
    search.pass(
        k,
        1,
        cancel,
        || (),
        |(), i, best| {
            out[i].store(kth(best, k).to_bits(), Ordering::Relaxed);
        },
    )?;
    Ok(out
        .into_iter()
        .map(|v| f64::from_bits(v.into_inner()))
        .collect())
}

/// The distribution of h6 / d over `packing` ([`H6Stats`]); `None` with
/// fewer than 7 particles (h6 undefined for all).
pub fn h6_stats(packing: &Packing) -> Option<H6Stats> {
    let disks = &packing.disks;
    let near = ByRadius::new(disks, 0..disks.len());
    let search = Search::new(&packing.domain, disks, &near, 0);
    search.stats(&Cancel::new()).ok().flatten()
}

/// [`h6_stats`] of the packed particles `all[first..]` of a packing of
/// `domain` (wall disks before them), through the measure's index `near`
/// of `all`.
pub(super) fn h6_stats_with(
    domain: &Domain,
    all: &[Disk],
    near: &ByRadius,
    first: usize,
    cancel: &Cancel,
) -> Result<Option<H6Stats>, Cancelled> {
    Search::new(domain, all, near, first).stats(cancel)
}

/// `n` slots holding NaN, written from any thread.
fn nan_slots(n: usize) -> Vec<AtomicU64> {
    (0..n).map(|_| AtomicU64::new(f64::NAN.to_bits())).collect()
}

/// The `k`-th of the ascending distances `best` (NaN when there are fewer).
fn kth(best: &[(f64, u32)], k: usize) -> f64 {
    k.checked_sub(1)
        .and_then(|m| best.get(m))
        .map_or(f64::NAN, |e| e.0)
}

/// A k-nearest search among the packed particles `all[first..]`.
struct Search<'a> {
    domain: &'a Domain,
    all: &'a [Disk],
    near: &'a ByRadius,
    first: usize,
    /// Largest radius in `all`: how far beyond a box the index's classes reach.
    r_max: f64,
    /// A reach (mm) past which every particle (its nearest image in a
    /// periodic cell) has been visited.
    limit: f64,
}

impl<'a> Search<'a> {
    /// The search over `all[first..]`, `near` an index of `all`.
    fn new(domain: &'a Domain, all: &'a [Disk], near: &'a ByRadius, first: usize) -> Self {
        let r_max = all.iter().fold(0.0f64, |m, d| m.max(d.r));
        let limit = match domain.period() {
            // The nearest image lies within half a period along each axis.
            Some(p) => 0.5 * p.x.max(p.y),
            None => {
                let (lo, hi) = domain.bounds();
                let (lo, hi) = all.iter().fold((lo, hi), |(lo, hi), d| {
                    (
                        Point::new(lo.x.min(d.c.x), lo.y.min(d.c.y)),
                        Point::new(hi.x.max(d.c.x), hi.y.max(d.c.y)),
                    )
                });
                (hi - lo).norm()
            }
        };
        Search {
            domain,
            all,
            near,
            first,
            r_max,
            limit,
        }
    }

    /// The distances from particle `i` to its `k` nearest other packed
    /// particles, ascending, with their indices, in `best` (fewer when the
    /// packing holds fewer).
    ///
    /// Boxes about the centre double from about two diameters (its own
    /// and the finest class's) until the `k`-th distance found lies within
    /// the box (a particle not visited lies farther than the box's half
    /// side), or the box holds every particle.
    fn nearest(&self, i: usize, k: usize, best: &mut Vec<(f64, u32)>) {
        best.clear();
        if k == 0 {
            return;
        }
        let periodic = self.domain.is_periodic();
        let p = self.all[i].c;
        let start = 2.0 * (self.all[i].r + self.near.finest_r_max());
        let mut reach = start.max(self.limit / 1024.0);
        if !(reach > 0.0 && reach.is_finite()) {
            reach = self.limit;
        }
        for _ in 0..MAX_ROUNDS {
            best.clear();
            for v in images_near(self.domain, p, reach + self.r_max) {
                let zero = v.x == 0.0 && v.y == 0.0;
                self.near.visit(p - v, reach, |j| {
                    if j < self.first || j == i {
                        return;
                    }
                    let c = self.all[j].c;
                    let at = if zero { c } else { c + v };
                    offer(best, k, (p - at).norm(), j as u32, periodic);
                });
            }
            let done = best.len() == k && best[k - 1].0 <= reach;
            if done || reach >= self.limit {
                return;
            }
            reach *= 2.0;
        }
    }

    /// `visit(acc, i, best)` for every `stride`-th packed particle `i`
    /// (counted from `first`) with its `k` nearest ([`Search::nearest`]), in fixed runs
    /// of the index's cell order on all cores; each run's accumulator
    /// (from `init`), in run order, so that combining them in order gives
    /// the same bits whatever the threads.
    fn pass<A: Send>(
        &self,
        k: usize,
        stride: usize,
        cancel: &Cancel,
        init: impl Fn() -> A + Sync + Send,
        visit: impl Fn(&mut A, usize, &[(f64, u32)]) + Sync + Send,
    ) -> Result<Vec<A>, Cancelled> {
        self.near
            .runs(CHUNK)
            .into_par_iter()
            .map(|run| {
                let mut acc = init();
                let mut best = Vec::with_capacity(k.min(self.all.len()));
                for (n, &i) in run.iter().enumerate() {
                    if n % POLL_EVERY == 0 {
                        cancel.check()?;
                    }
                    let i = i as usize;
                    if i < self.first || !(i - self.first).is_multiple_of(stride) {
                        continue;
                    }
                    self.nearest(i, k, &mut best);
                    visit(&mut acc, i - self.first, &best);
                }
                Ok(acc)
            })
            .collect()
    }

    /// The distribution of h6 / d ([`H6Stats`]); `None` with fewer than
    /// 7 particles. One pass for h5, h6 and h7 (the 7 nearest); h6 / d
    /// kept per particle (8 bytes a particle) for its percentiles.
    fn stats(&self, cancel: &Cancel) -> Result<Option<H6Stats>, Cancelled> {
        let n = self.all.len().saturating_sub(self.first);
        if n <= H6 {
            return Ok(None);
        }
        let stride = n.div_ceil(SUMMARY_PARTICLES);
        let ratios = nan_slots(n.div_ceil(stride));
        // Sums and counts of the finite h5 / d and h7 / d of each run.
        let parts = self.pass(
            H6 + 1,
            stride,
            cancel,
            || [(0.0f64, 0usize); 2],
            |acc, i, best| {
                let d = 2.0 * self.all[self.first + i].r;
                ratios[i / stride].store((kth(best, H6) / d).to_bits(), Ordering::Relaxed);
                for (slot, k) in acc.iter_mut().zip([H6 - 1, H6 + 1]) {
                    let h = kth(best, k) / d;
                    if h.is_finite() {
                        *slot = (slot.0 + h, slot.1 + 1);
                    }
                }
            },
        )?;
        let mean_of = |m: usize| {
            let (sum, count) = parts
                .iter()
                .fold((0.0, 0usize), |(s, c), p| (s + p[m].0, c + p[m].1));
            if count == 0 {
                f64::NAN
            } else {
                sum / count as f64
            }
        };
        let mut values: Vec<f64> = ratios
            .into_iter()
            .map(|v| f64::from_bits(v.into_inner()))
            .filter(|v| v.is_finite())
            .collect();
        cancel.check()?;
        Ok(distribution(&mut values).map(|d| H6Stats {
            count: values.len(),
            h5_mean: mean_of(0),
            h7_mean: mean_of(1),
            stride,
            ..d
        }))
    }
}

/// Offer particle `j` at distance `dist` to the `k` nearest so far
/// (`best`, ascending by distance then index). `once`: a particle may be
/// offered again (another periodic image) and keeps its least distance.
fn offer(best: &mut Vec<(f64, u32)>, k: usize, dist: f64, j: u32, once: bool) {
    if once && let Some(at) = best.iter().position(|e| e.1 == j) {
        if dist < best[at].0 {
            best.remove(at);
        } else {
            return;
        }
    }
    if best.len() == k {
        // Not nearer (or NaN): not among the k.
        if dist.partial_cmp(&best[k - 1].0) != Some(std::cmp::Ordering::Less) {
            return;
        }
        best.pop();
    }
    let at = best.partition_point(|e| e.0 < dist || (e.0 == dist && e.1 < j));
    best.insert(at, (dist, j));
}

/// Mean, sample deviation, least, greatest and percentiles of `values`
/// (finite, at least one; reordered), the counts and h5 / h7 means left
/// to the caller.
fn distribution(values: &mut [f64]) -> Option<H6Stats> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n as f64 - 1.0).max(1.0);
    let (min, max) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    Some(H6Stats {
        count: n,
        h5_mean: f64::NAN,
        h7_mean: f64::NAN,
        max,
        mean,
        min,
        p5: percentile(values, 0.05),
        p50: percentile(values, 0.5),
        p95: percentile(values, 0.95),
        sd: var.sqrt(),
        stride: 1,
    })
}

/// The `q` quantile of `values` (not empty; reordered), linear between
/// the order statistics at `q·(n − 1)`: numpy's default.
fn percentile(values: &mut [f64], q: f64) -> f64 {
    let pos = q * (values.len() - 1) as f64;
    let lo = (pos.floor() as usize).min(values.len() - 1);
    let frac = pos - lo as f64;
    let (_, &mut a, above) = values.select_nth_unstable_by(lo, f64::total_cmp);
    if frac > 0.0 {
        let b = above.iter().copied().fold(f64::INFINITY, f64::min);
        a + frac * (b - a)
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Every pair against the index: `hk_is_the_brute_force_kth_nearest`
    // in the integration tests (random, packed and periodic, k 1 to 12).
    use crate::metrics::tests::scattered;

    #[test]
    fn h6_is_undefined_below_seven_particles() {
        let domain = Domain::rectangle(30.0, 20.0).unwrap();
        for n in 0..=7 {
            let packing = scattered(domain.clone(), n, 1);
            let h = h6(&packing);
            assert_eq!(h.len(), n);
            assert!(h.iter().all(|v| v.is_nan() == (n < 7)), "{n}: {h:?}");
            assert_eq!(h6_stats(&packing).is_some(), n >= 7, "{n}");
        }
        let seven = h6_stats(&scattered(domain, 7, 1)).unwrap();
        assert_eq!(seven.count, 7);
        assert!(seven.h5_mean.is_finite() && seven.h7_mean.is_nan());
        assert!(
            hk(&scattered(Domain::rectangle(9.0, 9.0).unwrap(), 9, 0), 0)
                .iter()
                .all(|v| v.is_nan())
        );
    }

    #[test]
    fn a_hexagonal_lattice_has_h6_of_one_diameter() {
        // Touching disks of diameter 1 on a lattice that tiles the cell:
        // six neighbours at 1, the next at √3.
        let (cols, rows) = (8usize, 6usize);
        let (w, h) = (cols as f64, rows as f64 * 3f64.sqrt() / 2.0);
        let domain = Domain::periodic_rectangle(w, h).unwrap();
        let disks = (0..rows)
            .flat_map(|r| {
                (0..cols).map(move |c| {
                    let x = c as f64 + 0.5 * (r % 2) as f64 + 0.25;
                    Disk::new(x, (r as f64 + 0.5) * 3f64.sqrt() / 2.0, 0.5)
                })
            })
            .collect();
        let packing = Packing::of_disks(domain, disks);
        let s = h6_stats(&packing).unwrap();
        assert_eq!(s.count, (cols * rows).div_ceil(s.stride));
        for v in [s.mean, s.min, s.max, s.p5, s.p50, s.p95, s.h5_mean] {
            assert!((v - 1.0).abs() < 1e-12, "{s:?}");
        }
        assert!((s.h7_mean - 3f64.sqrt()).abs() < 1e-12, "{s:?}");
        assert!(s.sd < 1e-12);
    }

    #[test]
    fn stats_are_the_same_on_one_and_four_threads() {
        let packing = scattered(Domain::periodic_rectangle(40.0, 30.0).unwrap(), 3000, 4);
        let on = |t: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
                .install(|| (format!("{:?}", h6_stats(&packing)), hk(&packing, 6)))
        };
        let (one, four) = (on(1), on(4));
        assert_eq!(one.0, four.0);
        let bits = |h: &[f64]| h.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one.1), bits(&four.1));
    }

    #[test]
    fn percentiles_are_numpys_linear_ones() {
        // numpy.percentile([1, 2, 3, 4, 10], [5, 50, 95]) = [1.2, 3, 8.8].
        let mut v = [10.0, 3.0, 1.0, 4.0, 2.0];
        let d = distribution(&mut v).unwrap();
        assert!((d.p5 - 1.2).abs() < 1e-12 && d.p50 == 3.0, "{d:?}");
        assert!((d.p95 - 8.8).abs() < 1e-12, "{d:?}");
        assert_eq!((d.min, d.max, d.mean), (1.0, 10.0, 4.0));
        assert!((d.sd - 12.5f64.sqrt()).abs() < 1e-12, "{d:?}");
    }

    #[test]
    fn measure_records_the_stats_of_hk() {
        let text = "[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n\
                    walls = \"disks\"\n[grading]\nuniform = [0.8, 1.6]\n";
        let scene = crate::config::parse_with(text, "t", Default::default())
            .unwrap()
            .scene;
        let packing = crate::pack(&scene).unwrap();
        assert!(!packing.boundary.is_empty());
        let m = crate::measure(&packing, &scene);
        // The measure's index holds the wall disks too: the same h6 / d
        // figures, the h5 and h7 means summed in another order.
        let (s, alone) = (m.h6_over_d.unwrap(), h6_stats(&packing).unwrap());
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b;
        assert!(close(s.h5_mean, alone.h5_mean) && close(s.h7_mean, alone.h7_mean));
        assert_eq!(
            H6Stats {
                h5_mean: alone.h5_mean,
                h7_mean: alone.h7_mean,
                ..s
            },
            alone
        );
        // Every stride-th particle in placement order, no more than
        // SUMMARY_PARTICLES of them (40 in the tests: sampled here).
        let h = h6(&packing);
        let n = packing.disks.len();
        assert!(
            s.stride > 1 && s.stride == n.div_ceil(SUMMARY_PARTICLES),
            "{s:?}"
        );
        let ratios: Vec<f64> = h
            .iter()
            .zip(&packing.disks)
            .map(|(h, d)| h / (2.0 * d.r))
            .step_by(s.stride)
            .collect();
        assert!(ratios.len() <= SUMMARY_PARTICLES);
        assert_eq!(s.count, ratios.len());
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        assert_eq!(s.mean.to_bits(), mean.to_bits());
        assert!(s.h5_mean <= s.mean && s.mean <= s.h7_mean, "{s:?}");
        // A dense packing: the sixth neighbour a little over a diameter away.
        assert!(s.p50 > 0.9 && s.p50 < 2.0, "{s:?}");
    }
}
