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
    /// `o` to `p`) it is `−W²·cos(2π·dx/W) − H²·cos(2π·dy/H)`: about
    /// `2π²·(dx² + dy²)` near `o`, so the pack grows out from its first
    /// disk as a round cluster, but flat across the lines half a period
    /// from `o`, where the pack closes on its own images. There the lines
    /// of equal rank cross at right angles: each layer of the front runs on
    /// into its own image, as a row continues, instead of two fronts
    /// meeting face to face. The rank is greatest half a period from `o` in
    /// both x and y, where the front closes last.
    ///
    /// `o` lies a quarter period from the cell's low corner in x and y, so
    /// the lines through the first disk (where a row may form) and those
    /// where the front closes on itself all lie a quarter period from the
    /// cell's edges: the edges of the cell exported cut the packing where
    /// it is as the bulk (`gapack bench --periodic-edges`, 20 seeds, 1 mm
    /// bands: the edges −0.003 and 0.000 from the inside's porosity, the
    /// lines where the front closes 0.017 and 0.024 above it). With `o` at
    /// the cell's centre the front closed on itself along the edges (0.018
    /// and 0.024 above the inside), most at the corners (5 mm squares 0.068
    /// and 0.055 above it, seeds 1–5); a periodic cell has no physical
    /// edge, so only where its edges fall changes.
    ///
    /// Tried before: ranking by the squared distance to the first disk (a
    /// round cluster to the end, its fronts meeting face to face) left the
    /// edges 0.11 looser than the inside; flatter ranks (`|sin|` or
    /// `sin²/(sin² + κ)` per axis) laid a dense row along the lines through
    /// the first disk (porosity 0.137–0.157 in 1 mm bands, against 0.182);
    /// filling lowest first (x wrapping), the last layers met the first row
    /// like a wall of disks (0.41–0.51 in the 1 mm under it); grown as a
    /// horizontal band (nearest in y only), a row formed along the middle.
    /// Figures: docs/results.md, "Periodic cells: the edges".
    #[inline]
    pub(super) fn rank(&self, p: Point) -> f64 {
        match self.origin {
            None => 0.0,
            Some((o, period)) => {
                let near = |d: f64, w: f64| d - w * (d / w).round();
                let (dx, dy) = (near(p.x - o.x, period.x), near(p.y - o.y, period.y));
                let tau = std::f64::consts::TAU;
                -period.x * period.x * (tau * dx / period.x).cos()
                    - period.y * period.y * (tau * dy / period.y).cos()
            }
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

/// Weight (mm) of a candidate's gap to its nearest disk but the two it
/// touches in its key ([`Front::key`]), against its rank over `2π²` (mm²):
/// 0.1 mm of gap outweighs the rank's difference between two spots a
/// diameter apart about 0.4 mm from the first disk, and more wherever the
/// rank is flat. With 3, 10 and 30 mm the whole cell's porosity came out
/// 0.1878, 0.1874 and 0.1878 (1–1.66 mm) and 0.1814, 0.1788 and 0.1788
/// (Table 3.4) against 0.1879 and 0.1806 by the rank alone (the cells of
/// `gapack bench --periodic-edges`, seeds 1–5; docs/results.md).
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
