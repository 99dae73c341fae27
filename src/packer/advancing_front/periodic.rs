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
    /// periodic cell, the squared distance from the first disk's centre (the
    /// cell's centre) to the nearest image of `p`: the pack grows out from its
    /// first disk as a round cluster and closes on its own images along the
    /// cell's edges, two rough fronts meeting (the 1 mm bands along the edges:
    /// porosity 0.27 to 0.32, against 0.18 to 0.20 inside; 50 × 100 mm, 1–1.66
    /// mm, 20 seeds). Filled lowest first, the cell grew from a row of disks
    /// centred on its bottom edge, which the last layers met like a wall of
    /// disks: the band below the top edge reached 0.50. Grown as a horizontal
    /// band (nearest in y only), a row formed along the middle (two bands of
    /// 0.13 flanked by 0.22).
    #[inline]
    pub(super) fn rank(&self, p: Point) -> f64 {
        match self.origin {
            None => 0.0,
            Some((o, period)) => {
                let near = |d: f64, w: f64| d - w * (d / w).round();
                let (dx, dy) = (near(p.x - o.x, period.x), near(p.y - o.y, period.y));
                dx * dx + dy * dy
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
