//! Wall disks on straight edges as runs: evenly spaced disks of one radius
//! along a line, found by their position along it instead of through the
//! spatial index.
//!
//! # Behavior
//! A disk touching wall disk `k` of a run clears its neighbours `k ± 1`
//! only in a narrow *zone* (within half a spacing of `k` along the line, at
//! nearly the halo's full height): elsewhere it lies inside one of their
//! halos. So, for a front's halo, the only wall disks that give feasible
//! candidates are those whose zone the halo crosses ([`WallRuns::sources`],
//! a few per edge instead of every wall disk in reach), and a point is clear
//! of a run exactly when it is clear of the run's disks nearest it along the
//! line ([`WallRuns::nearest`]: all have the same radius and lie on one
//! line). The end disks of a run (the corners) are always sources.
//!
//! # Performance
//! The thesis' wells hold 160,000 to 500,000 wall disks: in the index, every
//! front near a wall visited and tested about 40 of them per edge, and they
//! cost 98 % of the run. As runs they cost O(1) per edge and query.

use std::ops::ControlFlow;

use nalgebra::Vector2;

use crate::geometry::{Disk, Domain, Point, Wall};

/// Relative margin on a zone's width and height and on a halo's radius:
/// far above rounding and the feasibility slack (a wider zone only adds
/// candidates that are then tested exactly).
const ZONE_REL: f64 = 1e-6;

/// The wall disks of one straight edge.
#[derive(Debug, Clone)]
struct Run {
    /// The edge's start: the centre of its first disk.
    a: Point,
    /// Unit vector along the edge.
    u: Vector2<f64>,
    /// Unit normal (left of `u`).
    n: Vector2<f64>,
    /// Spacing of the centres along the edge.
    step: f64,
    /// Length of the edge.
    len: f64,
    /// Disks on the edge (`k = 0..count`); `k = count` is the next edge's first.
    count: u32,
    /// Id of the disk at `k = 0`.
    first: u32,
    /// Id of the disk at `k = count`.
    end: u32,
}

/// The wall disks of a straight-edged domain, edge by edge; empty with exact
/// walls, a periodic cell or a circle (whose wall disks stay in the index).
#[derive(Debug, Clone, Default)]
pub(super) struct WallRuns {
    runs: Vec<Run>,
    /// Per wall disk: its run.
    run_of: Vec<u32>,
    /// Radius of every wall disk.
    r: f64,
}

impl WallRuns {
    /// Runs of `disks` (as [`Domain::boundary_disks`] makes them) on the
    /// edges `edges` gives them ([`Domain::boundary_disk_edges`]); empty if
    /// `edges` is.
    pub fn new(domain: &Domain, disks: &[Disk], edges: Vec<u32>) -> Self {
        let mut runs = Vec::new();
        let walls = domain.walls();
        let mut first = 0usize;
        while first < edges.len() {
            let edge = edges[first];
            let count = edges[first..].iter().take_while(|&&e| e == edge).count();
            let Some(&Wall::Segment { a, b }) = walls.get(edge as usize) else {
                return WallRuns::default();
            };
            let len = (b - a).norm();
            let u = (b - a) / len;
            runs.push(Run {
                a: disks[first].c,
                u,
                n: Vector2::new(-u.y, u.x),
                step: len / count as f64,
                len,
                count: count as u32,
                first: first as u32,
                end: 0,
            });
            first += count;
        }
        let starts: Vec<u32> = runs.iter().map(|run| run.first).collect();
        for (i, run) in runs.iter_mut().enumerate() {
            run.end = starts[(i + 1) % starts.len()];
        }
        WallRuns {
            runs,
            run_of: edges,
            r: disks.first().map_or(0.0, |d| d.r),
        }
    }

    /// Whether there is no run (the wall disks, if any, are in the index).
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// The run of wall disk `id`, if it is in one.
    pub fn run_of(&self, id: u32) -> Option<usize> {
        self.run_of.get(id as usize).map(|&i| i as usize)
    }

    /// Radius of the wall disks.
    pub fn radius(&self) -> f64 {
        self.r
    }

    /// Number of runs (edges).
    pub fn len(&self) -> usize {
        self.runs.len()
    }

    /// Id of disk `k` (`0..=count`) of run `i`.
    #[inline]
    fn id(&self, run: &Run, k: u32) -> u32 {
        if k < run.count {
            run.first + k
        } else {
            run.end
        }
    }

    /// Into `out`, the runs with a disk centre within `reach` of `c` (and perhaps a few more).
    pub fn near(&self, c: Point, reach: f64, out: &mut Vec<u32>) {
        out.clear();
        let reach = reach * (1.0 + ZONE_REL) + self.r * ZONE_REL;
        for (i, run) in self.runs.iter().enumerate() {
            let v = c - run.a;
            let t = v.dot(&run.u).clamp(0.0, run.len);
            if (v - run.u * t).norm_squared() <= reach * reach {
                out.push(i as u32);
            }
        }
    }

    /// Call `f` once with each disk of run `i` that may give a feasible
    /// candidate on the halo (`c`, `rf`) of a front for a disk of radius
    /// `r`: the run's first disk, and the disks whose zone the halo crosses.
    ///
    /// # Behavior
    /// A disk touching disk `k` (`0 < k < count`) at `x` along the line from
    /// its centre clears disk `k + 1` only if `x ≤ step/2` (to within the
    /// slack of [`FEASIBLE_REL`](crate::geometry::predicates::FEASIBLE_REL)),
    /// and `k − 1` only if `x ≥ −step/2`: so its centre lies at a height of
    /// at least `√(R² − step²/4)` from the line, `R = r + r_wall`, on
    /// either side. The halo's points in those two bands span at most two
    /// ranges along the line each; the disks within half a step of them are
    /// the sources (widened by [`ZONE_REL`]).
    pub fn sources(&self, i: u32, c: Point, rf: f64, r: f64, mut f: impl FnMut(u32)) {
        let run = &self.runs[i as usize];
        let big_r = r + self.r;
        let w = 0.5 * run.step + ZONE_REL * (run.step + big_r);
        let h_hi = big_r * (1.0 + ZONE_REL);
        let h_lo = (big_r * big_r - w * w).max(0.0).sqrt() * (1.0 - ZONE_REL);
        let v = c - run.a;
        let (tc, hc) = (v.dot(&run.u), v.dot(&run.n));
        let (outer, inner) = (rf * (1.0 + ZONE_REL), rf * (1.0 - ZONE_REL));
        let g = |rad: f64, h: f64| (rad * rad - (h - hc) * (h - hc)).max(0.0).sqrt();
        let mut ranges = [(0u32, 0u32); 4];
        let mut len = 0;
        for (lo, hi) in [(h_lo, h_hi), (-h_hi, -h_lo)] {
            let (lo, hi) = (lo.max(hc - outer), hi.min(hc + outer));
            if lo > hi {
                continue;
            }
            let g_max = if lo <= hc && hc <= hi {
                outer
            } else {
                g(outer, lo).max(g(outer, hi))
            };
            let g_min = g(inner, lo).min(g(inner, hi));
            for (t0, t1) in [(tc + g_min, tc + g_max), (tc - g_max, tc - g_min)] {
                if let Some(range) = k_range(run.step, t0 - w, t1 + w, 1, run.count - 1) {
                    ranges[len] = range;
                    len += 1;
                }
            }
        }
        f(run.first);
        let ranges = &mut ranges[..len];
        ranges.sort_unstable();
        let mut next = 0;
        for &(k0, k1) in ranges.iter() {
            for k in k0.max(next)..=k1 {
                f(run.first + k);
            }
            next = next.max(k1 + 1);
        }
    }

    /// Whether `blocks` holds for one of the disks of run `i` nearest `p`
    /// along its line (the nearest and the one each side of it, the next
    /// edge's first disk included): of a run's disks, these are the nearest
    /// `p`, so if none blocks a disk at `p`, none does. `reach` bounds the
    /// distance from `p` of the centres `blocks` can hold for: a point
    /// farther than that from the line is not tested.
    #[inline]
    pub fn nearest(
        &self,
        i: u32,
        p: Point,
        reach: f64,
        mut blocks: impl FnMut(u32) -> bool,
    ) -> bool {
        let run = &self.runs[i as usize];
        let v = p - run.a;
        if v.dot(&run.n).abs() > reach * (1.0 + ZONE_REL) + ZONE_REL * run.step {
            return false;
        }
        // Rounded to nearest by truncation, the value being clamped non-negative first.
        let t = v.dot(&run.u) / run.step + 0.5;
        let k = t.clamp(0.0, f64::from(run.count)) as u32;
        blocks(self.id(run, k))
            || (k > 0 && blocks(self.id(run, k - 1)))
            || (k < run.count && blocks(self.id(run, k + 1)))
    }

    /// Call `f` with every wall disk whose centre lies in the box `lo`–`hi`
    /// until it breaks.
    pub fn try_visit_box(
        &self,
        disks: &[Disk],
        lo: Point,
        hi: Point,
        mut f: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        for run in &self.runs {
            let mut t = (0.0f64, run.len);
            let slack = ZONE_REL * run.step;
            for (a, u, lo, hi) in [
                (run.a.x, run.u.x, lo.x, hi.x),
                (run.a.y, run.u.y, lo.y, hi.y),
            ] {
                if u == 0.0 {
                    if a < lo - slack || a > hi + slack {
                        t = (1.0, 0.0);
                    }
                } else {
                    let (s0, s1) = ((lo - a) / u, (hi - a) / u);
                    t = (t.0.max(s0.min(s1)), t.1.min(s0.max(s1)));
                }
            }
            // One disk more each way: the centres lie on the line only to within rounding.
            let (t0, t1) = (t.0 - run.step, t.1 + run.step);
            let Some((k0, k1)) = k_range(run.step, t0, t1, 0, run.count - 1) else {
                continue;
            };
            for k in k0..=k1 {
                let id = run.first + k;
                let c = disks[id as usize].c;
                if c.x >= lo.x && c.x <= hi.x && c.y >= lo.y && c.y <= hi.y {
                    f(id)?;
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// Whether `pred` holds for a wall disk whose centre lies in the box `lo`–`hi`.
    pub fn any_in_box(
        &self,
        disks: &[Disk],
        lo: Point,
        hi: Point,
        mut pred: impl FnMut(u32) -> bool,
    ) -> bool {
        self.try_visit_box(disks, lo, hi, |id| {
            if pred(id) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .is_break()
    }

    /// For wall disk `id` centred at `q` and not at an end of its run: two
    /// triangles, one each side of its line, that hold every point where a
    /// disk of radius `rho` touching it clears its two neighbours (its
    /// zones, see [`WallRuns::sources`]), with a margin of [`ZONE_REL`];
    /// `None` for an end disk, or zones too wide to bound this way.
    pub fn zones(&self, id: u32, q: Point, rho: f64) -> Option<[[Point; 3]; 2]> {
        let i = *self.run_of.get(id as usize)?;
        let run = &self.runs[i as usize];
        if id == run.first {
            return None;
        }
        let big_r = rho + self.r;
        let margin = ZONE_REL * (run.step + big_r);
        let w = 0.5 * run.step + margin;
        if w > 0.5 * big_r {
            return None;
        }
        // The arc |x| ≤ w of the halo lies in the triangle of its ends and
        // the crossing of its tangents there (at R²/h from the centre).
        let h = (big_r * big_r - w * w).sqrt();
        let tip = big_r * big_r / h;
        let zone = |n: Vector2<f64>| {
            [
                q + run.u * (w + margin) + n * (h - margin),
                q - run.u * (w + margin) + n * (h - margin),
                q + n * (tip + margin),
            ]
        };
        Some([zone(run.n), zone(-run.n)])
    }
}

/// Disks `k0..=k1`, within `lo..=hi`, of a run of spacing `step` whose
/// positions `k·step` lie in `[t0, t1]`; `None` if none.
///
/// # Performance
/// Truncation instead of `floor` and `ceil` (library calls on baseline
/// x86-64), on values clamped non-negative first.
#[inline]
fn k_range(step: f64, t0: f64, t1: f64, lo: u32, hi: u32) -> Option<(u32, u32)> {
    let k0 = (t0 / step).max(f64::from(lo));
    let k1 = (t1 / step).min(f64::from(hi));
    // `max` and `min` drop a NaN: a NaN end is the bound.
    if k0 > k1 {
        return None;
    }
    let first = k0 as u32;
    let first = if f64::from(first) < k0 {
        first + 1
    } else {
        first
    };
    let last = k1 as u32;
    (first <= last).then_some((first, last))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The runs of a 10 × 4 rectangle lined with disks of `d`.
    fn rectangle(d: f64) -> (Vec<Disk>, WallRuns) {
        let domain = Domain::rectangle(10.0, 4.0).unwrap();
        let disks = domain.boundary_disks(d);
        let runs = WallRuns::new(&domain, &disks, domain.boundary_disk_edges(d));
        (disks, runs)
    }

    #[test]
    fn a_box_visits_exactly_the_wall_disks_in_it() {
        let (disks, runs) = rectangle(0.1);
        for (lo, hi) in [
            (Point::new(-1.0, -1.0), Point::new(0.35, 0.25)),
            (Point::new(2.0, 3.9), Point::new(7.5, 4.0)),
            (Point::new(9.95, 1.0), Point::new(12.0, 3.0)),
            (Point::new(3.0, 1.0), Point::new(4.0, 2.0)),
        ] {
            let mut got = Vec::new();
            let _ = runs.try_visit_box(&disks, lo, hi, |id| {
                got.push(id);
                ControlFlow::Continue(())
            });
            got.sort_unstable();
            let want: Vec<u32> = (0..disks.len() as u32)
                .filter(|&id| {
                    let c = disks[id as usize].c;
                    c.x >= lo.x && c.x <= hi.x && c.y >= lo.y && c.y <= hi.y
                })
                .collect();
            assert_eq!(got, want, "{lo:?}–{hi:?}");
        }
    }

    #[test]
    fn the_nearest_disks_block_whenever_any_does() {
        let (disks, runs) = rectangle(0.1);
        let (r, clear) = (0.6, 0.65);
        for i in 0..2000 {
            let p = Point::new(
                f64::from(i % 50) * 0.21 - 0.3,
                f64::from(i / 50) * 0.11 - 0.2,
            );
            let blocks = |id: u32| (disks[id as usize].c - p).norm() < clear;
            let any = disks.iter().any(|d| (d.c - p).norm() < clear);
            let mut near = Vec::new();
            runs.near(p, r + 0.05, &mut near);
            let found = near.iter().any(|&run| runs.nearest(run, p, clear, blocks));
            assert_eq!(found, any, "{p:?}");
        }
    }
}
