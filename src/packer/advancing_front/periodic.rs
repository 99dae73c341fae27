//! Periodic cells (see "Periodic cells" in [`super`]): every index query
//! met once per lattice image of the obstacles, and the rank that grows the
//! pack out from its first disk. With walls, one query with the zero shift
//! and rank 0 everywhere: the same packings as without them.

use std::ops::ControlFlow;

use nalgebra::Vector2;

use super::{Front, Indexed};
use crate::geometry::{Domain, Point};
use crate::packer::index::SpatialIndex;

impl<I: SpatialIndex> Front<'_, I> {
    /// The rank of a candidate at `p`, lower first (then lowest, then leftmost:
    /// `candidates::first_of`): 0 everywhere with walls, so the lowest goes
    /// first and the pack deposits layer on layer from the bottom. In a
    /// periodic cell (`o` the first disk's centre, the cell's centre; `W`,
    /// `H` the periods; `dx`, `dy` from `o` to `p`) it is
    /// `−W²·cos(2π·dx/W) − H²·cos(2π·dy/H)`: about `2π²·(dx² + dy²)` near
    /// `o`, so the pack grows out from its first disk as a round cluster,
    /// but flat across the cell's edges, where the pack closes on its own
    /// images. There the lines of equal rank cross the edge at right
    /// angles: each layer of the front runs on across the edge into its
    /// own image, as a row continues, instead of two fronts meeting face to
    /// face along it. The rank is greatest at the cell's corner, where the
    /// front closes last.
    ///
    /// The 1 mm bands along the edges (`gapack bench --periodic-edges`,
    /// seeds 1–20, 50 × 100 mm of 1–1.66 mm): porosity 0.196–0.216 against
    /// 0.187 inside (+0.018), where ranking by the squared distance to the
    /// first disk (a round cluster to the end, its fronts meeting face to
    /// face along the edges) left 0.275–0.334 against 0.183 (+0.112).
    /// Tried too: flatter ranks (`|sin|` or `sin²/(sin² + κ)` per axis)
    /// brought the edges within 0.003–0.008 of the inside but laid a dense
    /// row along the lines through the first disk (porosity 0.137–0.157 in
    /// 1 mm bands, against 0.182 with this rank); filling lowest first (x
    /// wrapping), the last layers met the first row like a wall of disks
    /// (0.41–0.51 in the 1 mm under it), and a rough first row loosened the
    /// whole cell (0.194–0.218); grown as a horizontal band (nearest in y
    /// only), a row formed along the middle (two bands of 0.13 flanked by
    /// 0.22). Figures: docs/results.md, "Periodic cells: the edges".
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
}

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
