//! Periodic cells (see "Periodic cells" in [`super`]): every index query
//! met once per lattice image of the obstacles, and the key that grows the
//! pack out from its first disk. With walls, one query with the zero shift
//! and key 0 everywhere: the same packings as without them.

use std::ops::ControlFlow;

use nalgebra::Vector2;

use super::candidates::Cand;
use super::{Front, Indexed};
use crate::geometry::{Domain, Point};
use crate::packer::index::SpatialIndex;

impl<I: SpatialIndex> Front<'_, I> {
    /// The rank of a point `p`: 0 everywhere with walls. In a periodic cell
    /// (`o` the first disk's centre; `W`, `H` the periods; `dx`, `dy` from
    /// `o` to `p`) it is `w²·(1 − (1 − u)^k)·2/k` summed over the two axes,
    /// `u = (1 − cos(2π·d/w))/2` (0 at `o`, 1 half a period away): about
    /// `2π²·(dx² + dy²)` near `o`, so the pack grows out from its first
    /// disk as a round cluster, but flat to order `2k` across the lines
    /// half a period from `o` (the closure lines), where the pack closes
    /// on its own images. Where they cross a line through `o`, the rank
    /// has a saddle; the lines of equal rank through it meet the closure
    /// line at right angles, not at 45° as with `k = 1` (`−w²·cos`), so the
    /// two sides of the front zip up as one row runs on rather than face
    /// to face. `k` is 2 across the longer period and 1.5 across the
    /// shorter (x when they are equal): 2 on both axes closes the seam as
    /// well but loosens the bulk (the whole cell of 1–1.66 mm 0.0005 looser
    /// over 100 seeds), the shorter period being closed across while the
    /// cluster is still growing round. The rank is greatest half a period
    /// from `o` in both x and y, where the front closes last.
    ///
    /// `o` lies a quarter period from the cell's low corner in x and y, so
    /// the lines through the first disk (where a row may form) and the
    /// closure lines all lie a quarter period from the cell's edges: the
    /// edges of the cell exported cut the packing where it is as the bulk.
    /// `gapack bench --periodic-edges`, 20 seeds, 1 mm bands, 1–1.66 mm /
    /// Table 3.4: the closure lines +0.003 / +0.007 from the inside's
    /// porosity (+0.017 / +0.024 with `k = 1` on both axes), the edges
    /// −0.002 / −0.000. With `o` at the cell's centre the front closed on
    /// itself along the edges (0.018 and 0.024 above the inside); a
    /// periodic cell has no physical edge, so only where its edges fall
    /// changes.
    ///
    /// Tried before: ranking by the squared distance to the first disk (a
    /// round cluster to the end, its fronts meeting face to face) left the
    /// edges 0.11 looser than the inside; ranks kinked or saturating at
    /// `o` (`|sin|` or `sin²/(sin² + κ)` per axis) laid a dense row along
    /// the lines through the first disk (porosity 0.137–0.157 in 1 mm
    /// bands, against 0.182); `k` = 2 or 3 on both axes closed the seam as
    /// well but loosened the whole cell (0.1877 / 0.1791 and 0.1884 /
    /// 0.1796 over 100 seeds, against 0.1872 / 0.1793), flattening one
    /// axis only left it (+0.016 to +0.033); filling lowest first (x
    /// wrapping), the last layers met the first row like a wall of disks
    /// (0.41–0.51 in the 1 mm under it); grown as a horizontal band
    /// (nearest in y only), a row formed along the middle. Figures:
    /// docs/results.md, "Periodic cells: the edges".
    #[inline]
    pub(super) fn rank(&self, p: Point) -> f64 {
        match self.origin {
            None => 0.0,
            Some((o, period)) => cell_rank(p - o, period),
        }
    }

    /// The key of a feasible candidate of radius `r`, lower first (then
    /// lowest, then leftmost: `candidates::first_of`): 0 with walls, so the
    /// lowest goes first and the pack deposits layer on layer from the
    /// bottom. In a periodic cell, the rank over `2π²` (about the squared
    /// distance to the first disk, in mm²) plus [`NEST_WEIGHT`] times the
    /// gap the disk would leave to its nearest disk but the two it touches
    /// (the front and the neighbour), among the front's neighbours and at
    /// most its diameter: where
    /// the rank is steep, near the first disk, the front grows in rank
    /// order; where it is flat, where the front closes on itself, the spot
    /// that nests deepest goes first.
    #[inline]
    pub(super) fn key(&self, cand: &Cand, r: f64) -> f64 {
        if self.origin.is_none() {
            return 0.0;
        }
        // The least gap to a neighbour other than the one it touches, at
        // most a diameter: a neighbour whose centre is farther than that
        // gap reaches needs no square root.
        let mut gap = 2.0 * r;
        for (i, n) in self.near.iter().enumerate() {
            let (dx, dy) = (cand.off.x - n.rel.x, cand.off.y - n.rel.y);
            let reach = gap + n.disk.r + r;
            let d2 = dx * dx + dy * dy;
            if d2 < reach * reach && i != cand.src as usize {
                gap = gap.min(d2.sqrt() - n.disk.r - r);
            }
        }
        self.tests.set(self.tests.get() + self.near.len() as u64);
        let pi2 = 2.0 * std::f64::consts::PI * std::f64::consts::PI;
        self.rank(cand.at) / pi2 + NEST_WEIGHT * gap
    }
}

/// [`Front::rank`] of a point `d` from the first disk's centre in a cell of
/// periods `period`.
fn cell_rank(d: Vector2<f64>, period: Vector2<f64>) -> f64 {
    let near = |d: f64, w: f64| d - w * (d / w).round();
    let (dx, dy) = (near(d.x, period.x), near(d.y, period.y));
    let tau = std::f64::consts::TAU;
    // `1 − u` on each axis, and the flatter exponent across the longer period.
    let v = |d: f64, w: f64| (1.0 + (tau * d / w).cos()) / 2.0;
    let (vx, vy) = (v(dx, period.x), v(dy, period.y));
    let flat = |v: f64| (1.0 - v * v) / 2.0;
    let mild = |v: f64| (1.0 - v * v.sqrt()) / 1.5;
    let (gx, gy) = if period.x <= period.y {
        (mild(vx), flat(vy))
    } else {
        (flat(vx), mild(vy))
    };
    2.0 * (period.x * period.x * gx + period.y * period.y * gy)
}

/// Weight (mm) of a candidate's gap to its nearest disk but the two it
/// touches in its key ([`Front::key`]), against its rank over `2π²` (mm²):
/// 0.1 mm of gap outweighs the rank's difference between two spots a
/// diameter apart about 0.4 mm from the first disk, and more wherever the
/// rank is flat. With 3, 10 and 30 mm the whole cell's porosity came out
/// 0.1878, 0.1874 and 0.1878 (1–1.66 mm) and 0.1814, 0.1788 and 0.1788
/// (Table 3.4) against 0.1879 and 0.1806 by the rank alone (the cells of
/// `gapack bench --periodic-edges`, seeds 1–5, the rank `−w²·cos` per
/// axis; docs/results.md). With the flatter rank of [`Front::rank`], 5,
/// 10 and 20 mm: 0.1874, 0.1873 and 0.1879, and 0.1798, 0.1791 and 0.1788
/// (seeds 1–100), the closure lines 0.003–0.004 and 0.007–0.010 above the
/// inside; a weight growing towards the closure lines widened the seam, one
/// shrinking there loosened the whole cell.
const NEST_WEIGHT: f64 = 10.0;

/// `c` moved by the lattice shift `v`; `c` itself, bit for bit, for the
/// zero shift (every obstacle of a domain with walls).
#[inline]
pub(super) fn image(c: Point, v: Vector2<f64>) -> Point {
    if v == Vector2::zeros() { c } else { c + v }
}

/// Visit every obstacle in the box `lo`–`hi` (and perhaps a few beyond)
/// until `f` breaks: `f(id, v)` for obstacle `id` met as its image shifted
/// by `v`. A domain with walls makes one query with `v` zero; a periodic
/// cell one per lattice shift whose images may meet the box
/// ([`Domain::image_shifts`]), so an obstacle may come once per image.
#[inline]
pub(super) fn visit_images<I: SpatialIndex>(
    index: &Indexed<I>,
    domain: &Domain,
    lo: Point,
    hi: Point,
    mut f: impl FnMut(u32, Vector2<f64>) -> ControlFlow<()>,
) -> ControlFlow<()> {
    if !domain.is_periodic() {
        return index.try_visit_box(lo, hi, |id| f(id, Vector2::zeros()));
    }
    for v in domain.image_shifts(lo, hi) {
        index.try_visit_box(lo - v, hi - v, |id| f(id, v))?;
    }
    ControlFlow::Continue(())
}

/// Whether `pred(id, v)` holds for some obstacle image in the box `lo`–`hi`
/// (see [`visit_images`]), stopping at the first that does.
#[inline]
pub(super) fn any_image<I: SpatialIndex>(
    index: &Indexed<I>,
    domain: &Domain,
    lo: Point,
    hi: Point,
    mut pred: impl FnMut(u32, Vector2<f64>) -> bool,
) -> bool {
    visit_images(index, domain, lo, hi, |id, v| {
        if pred(id, v) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    })
    .is_break()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Near the first disk the rank is `2π²` times the squared distance,
    /// whatever the direction: the cluster grows round.
    #[test]
    fn the_rank_is_round_near_the_first_disk() {
        let pi2 = 2.0 * std::f64::consts::PI * std::f64::consts::PI;
        for period in [Vector2::new(50.0, 100.0), Vector2::new(100.0, 50.0)] {
            for k in 0..8 {
                let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
                let d = Vector2::new(a.cos(), a.sin()) * 0.5;
                let rank = cell_rank(d, period) / pi2;
                assert!((rank / 0.25 - 1.0).abs() < 0.01, "{period:?} {a}: {rank}");
            }
        }
    }

    /// At each saddle (half a period from the first disk along one axis),
    /// the rank changes far less across the closure line than along it: the
    /// lines of equal rank through the saddle cross the closure line at
    /// right angles (with `−w²·cos` per axis both changes are equal, 45°).
    #[test]
    fn the_rank_is_flat_across_the_closure_lines() {
        for period in [Vector2::new(50.0, 100.0), Vector2::new(100.0, 50.0)] {
            let e = 1.0;
            let saddles = [
                Vector2::new(period.x / 2.0, 0.0),
                Vector2::new(0.0, period.y / 2.0),
            ];
            for (axis, s) in saddles.into_iter().enumerate() {
                let (normal, tangent) = match axis {
                    0 => (Vector2::new(e, 0.0), Vector2::new(0.0, e)),
                    _ => (Vector2::new(0.0, e), Vector2::new(e, 0.0)),
                };
                let at = cell_rank(s, period);
                let across = (cell_rank(s + normal, period) - at).abs();
                let along = cell_rank(s + tangent, period) - at;
                assert!(along > 0.0, "{period:?} {s:?}");
                assert!(
                    across < 0.05 * along,
                    "{period:?} {s:?}: {across} against {along}"
                );
                // One period on, the same point.
                let wrapped = cell_rank(s + tangent + period, period) - at;
                assert!((wrapped - along).abs() < 1e-9 * along, "{period:?} {s:?}");
            }
        }
    }
}
