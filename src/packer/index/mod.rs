//! Spatial indexes for the packer's fixed-size range search.
//!
//! Items are disk centres with dense ids `0, 1, 2, …` inserted in order; an
//! item costs its 4-byte id beyond its bucket's 4 bytes. Both keep each
//! bucket as an intrusive singly linked list (`next[id]`), newest first; the
//! MX quadtree lays its leaves out in Morton order (see [`MxQuadtree`]), the
//! grid its cells row by row.

#[cfg(test)]
mod brute_force;
mod grid;
mod mx_quadtree;

#[cfg(test)]
use brute_force::BruteForce;
pub use grid::Grid;
pub use mx_quadtree::MxQuadtree;

use crate::geometry::Point;
use std::ops::ControlFlow;

/// End-of-list marker in the buckets' lists (an empty bucket's head).
pub(crate) const NIL: u32 = u32::MAX;

/// A spatial index of points for box queries.
///
/// # Behavior
/// [`try_visit_box`](SpatialIndex::try_visit_box) visits every item whose point lies in
/// the closed box, and may also visit items of the buckets the box touches
/// (no farther than one bucket side outside it): callers filter by exact
/// distance anyway, so the index does not test points twice.
pub trait SpatialIndex {
    /// Bucket (leaf or cell) side that suits the packer's queries, in largest
    /// diameters: measured with `gapack bench`.
    const BUCKET_DIAMETERS: f64;
    /// An empty index over `min`–`max` with buckets of about `bucket` side (mm).
    fn new(min: Point, max: Point, bucket: f64) -> Self
    where
        Self: Sized;
    /// Add item `id` at `p` (inside the index's bounds); ids must come in order 0, 1, 2, …
    fn insert(&mut self, id: u32, p: Point);
    /// Call `f` with the id of every item in the box `min`–`max` (and perhaps a
    /// few beyond) until it breaks; returns whether it broke.
    fn try_visit_box(
        &self,
        min: Point,
        max: Point,
        f: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()>;

    /// Call `f` with the id of every item in the box `min`–`max` (and perhaps a few beyond).
    #[inline]
    fn visit_box(&self, min: Point, max: Point, mut f: impl FnMut(u32)) {
        let _ = self.try_visit_box(min, max, |id| {
            f(id);
            ControlFlow::Continue(())
        });
    }

    /// Whether `pred` holds for some item in the box `min`–`max` (or a few
    /// beyond), stopping at the first that does.
    #[inline]
    fn any_in_box(&self, min: Point, max: Point, mut pred: impl FnMut(u32) -> bool) -> bool {
        self.try_visit_box(min, max, |id| {
            if pred(id) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .is_break()
    }
}

/// Buckets `lo..=hi` covered by the interval `[a, b]` along one axis, or `None` if it misses `0..n`.
///
/// # Performance
/// Truncation instead of `floor` (a library call on baseline x86-64): the
/// bucket coordinates it converts are checked non-negative first, and
/// `as u32` saturates. NaN misses.
#[inline]
fn bucket_span(a: f64, b: f64, origin: f64, inv_side: f64, n: u32) -> Option<(u32, u32)> {
    let ka = (a - origin) * inv_side;
    let kb = (b - origin) * inv_side;
    if !(kb >= 0.0 && ka < f64::from(n)) {
        return None;
    }
    let lo = if ka > 0.0 { ka as u32 } else { 0 };
    Some((lo, (kb as u32).min(n - 1)))
}

/// The buckets `(x0, x1, y0, y1)` (inclusive) covered by the box
/// `min`–`max` in an `nx` × `ny` array of square buckets from `origin`, or
/// `None` if the box misses it.
#[inline]
pub(crate) fn box_span(
    min: Point,
    max: Point,
    origin: Point,
    inv_side: f64,
    (nx, ny): (u32, u32),
) -> Option<(u32, u32, u32, u32)> {
    let (x0, x1) = bucket_span(min.x, max.x, origin.x, inv_side, nx)?;
    let (y0, y1) = bucket_span(min.y, max.y, origin.y, inv_side, ny)?;
    Some((x0, x1, y0, y1))
}

/// Call `f` with each item of the bucket list that starts at `id`, through
/// `next`, until it breaks.
#[inline]
pub(crate) fn walk_list(
    mut id: u32,
    next: &[u32],
    f: &mut impl FnMut(u32) -> ControlFlow<()>,
) -> ControlFlow<()> {
    while id != NIL {
        f(id)?;
        id = next[id as usize];
    }
    ControlFlow::Continue(())
}

/// Bucket coordinate of `v` along one axis, clamped to `0..n` (NaN gives 0).
#[inline]
pub(crate) fn bucket_of(v: f64, origin: f64, inv_side: f64, n: u32) -> u32 {
    let k = (v - origin) * inv_side;
    if k > 0.0 { (k as u32).min(n - 1) } else { 0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;
    use std::collections::BTreeSet;

    /// Compare an index against the brute-force scan on seeded random points
    /// and boxes; the points lie below the height `front(x)` (a share of the
    /// box's height), as a packing's do while its front rises.
    fn check_against_brute_force<I: SpatialIndex>(
        bucket: f64,
        w: f64,
        h: f64,
        front: impl Fn(f64) -> f64,
    ) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let (min, max) = (Point::new(-1.0, 2.0), Point::new(-1.0 + w, 2.0 + h));
        let mut index = I::new(min, max, bucket);
        let mut brute = BruteForce::new(min, max, bucket);
        let mut pts = Vec::new();
        // The empty index visits nothing.
        let mut none = 0;
        index.visit_box(min, max, |_| none += 1);
        assert_eq!(none, 0);
        for id in 0..3000u32 {
            let x = rng.gen_range(min.x..max.x);
            let p = Point::new(x, min.y + h * front((x - min.x) / w) * rng.r#gen::<f64>());
            index.insert(id, p);
            brute.insert(id, p);
            pts.push(p);
        }
        for _ in 0..500 {
            let c = Point::new(
                rng.gen_range(min.x - 2.0..max.x + 2.0),
                rng.gen_range(min.y - 2.0..max.y + 2.0),
            );
            let half = rng.gen_range(0.0..3.0 * bucket);
            let (lo, hi) = (
                Point::new(c.x - half, c.y - half),
                Point::new(c.x + half, c.y + half),
            );
            let mut want = BTreeSet::new();
            brute.visit_box(lo, hi, |id| {
                want.insert(id);
            });
            let mut got = BTreeSet::new();
            index.visit_box(lo, hi, |id| {
                assert!(got.insert(id), "item {id} visited twice");
            });
            assert!(got.is_superset(&want), "missed items");
            // The early-exit query finds an item of the box that matches, if there is one.
            let pick = |id: u32| id % 5 == 2;
            let mut hit = None;
            let any = index.any_in_box(lo, hi, |id| {
                hit = Some(id);
                pick(id)
            });
            assert_eq!(any, hit.is_some_and(pick));
            if want.iter().any(|&id| pick(id)) {
                assert!(any, "early exit missed a matching item");
            }
            let slack = bucket * 1.000001;
            for &id in &got {
                let p = pts[id as usize];
                assert!(
                    p.x >= lo.x - slack
                        && p.x <= hi.x + slack
                        && p.y >= lo.y - slack
                        && p.y <= hi.y + slack
                );
            }
        }
    }

    #[test]
    fn mx_quadtree_matches_brute_force() {
        check_against_brute_force::<MxQuadtree>(1.3, 40.0, 40.0, |_| 1.0);
        check_against_brute_force::<MxQuadtree>(0.7, 8.6, 62.5, |_| 1.0);
        // A ragged front: the columns' tops differ, leaves above them are skipped.
        check_against_brute_force::<MxQuadtree>(1.3, 40.0, 40.0, |t| {
            0.3 + 0.4 * t + 0.2 * (17.0 * t).sin()
        });
        check_against_brute_force::<MxQuadtree>(0.7, 8.6, 62.5, |t| 0.1 + 0.5 * t * t);
    }

    #[test]
    fn grid_matches_brute_force() {
        check_against_brute_force::<Grid>(1.3, 40.0, 40.0, |_| 1.0);
        check_against_brute_force::<Grid>(0.7, 8.6, 62.5, |_| 1.0);
    }
}
