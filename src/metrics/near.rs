//! Disks bucketed by size class, for neighbour queries over wide gradings.
//!
//! One grid of cells sized by the largest radius makes every query near a
//! fine disk visit cells full of fine disks: O(n²) on a wide grading (a
//! 20 mm square, d 0.02–4 mm by mass: 18 s of measure and check). Here the
//! disks are split into classes of radii within a factor of two, each
//! bucketed by cells sized by its own largest radius (or coarser when the
//! class is sparse); a query looks in each class around the point as far
//! as that class's own largest radius asks. Nothing here uses the
//! generator's spatial indexes: the independent check relies on it too.

use std::ops::ControlFlow;
use std::sync::OnceLock;

use crate::geometry::{Disk, Point};

/// Most size classes (radii spanning 2⁶³ share the last).
const MAX_CLASSES: usize = 64;

/// Radii within this factor of the finest are all of the first class: the
/// logarithm of a ratio this far below 2 never rounds up to 1.
const ONE_CLASS: f64 = 1.999;

/// `x.floor() as i64`, exactly (saturating, 0 for NaN), without the call
/// to the C library's `floor` a baseline x86-64 build makes: the cell of
/// every disk and query.
#[inline]
fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    t.saturating_sub(i64::from((t as f64) > x))
}

#[cfg(test)]
thread_local! {
    /// Disks the queries of this thread visited.
    pub(crate) static VISITED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// One size class: its largest radius and its disks in cell order.
struct Class {
    r_max: f64,
    side: f64,
    origin: (f64, f64),
    /// The last row and column (cells past them are clamped to them).
    rows: i64,
    cols: i64,
    /// The class's disks, cell by cell (row, then column), each cell's by
    /// index: 4 bytes a disk.
    ids: Vec<u32>,
    /// Where each cell's disks begin in `ids` (cells row by row), and the
    /// end last: at most about 4 cells a disk, 1 in a dense class.
    cell_start: Vec<u32>,
}

/// The index of a packing's disks, all of them in order, that its measure
/// and its check share: built once, by the first to ask, while the other
/// waits for it (at 10⁸ disks, 10 s and about 1 GB spared).
pub(crate) struct SharedIndex<'a> {
    disks: &'a [Disk],
    index: OnceLock<ByRadius>,
}

impl<'a> SharedIndex<'a> {
    /// The index of `disks`, not built yet.
    pub(crate) fn new(disks: &'a [Disk]) -> Self {
        SharedIndex {
            disks,
            index: OnceLock::new(),
        }
    }

    /// The index of `disks` when they are this index's own (the same
    /// slice), built on the first ask; `None` for any other disks.
    pub(crate) fn of(&self, disks: &[Disk]) -> Option<&ByRadius> {
        std::ptr::eq(self.disks, disks).then(|| {
            self.index
                .get_or_init(|| ByRadius::new(self.disks, 0..self.disks.len()))
        })
    }
}

/// Disks bucketed by size class and position.
pub(crate) struct ByRadius {
    classes: Vec<Class>,
}

impl ByRadius {
    /// Bucket `disks[i]` for each `i` of `ids` (finite centres and radii;
    /// fewer than 2³² disks).
    ///
    /// # Performance
    /// Walks `ids` three times per size class present, and holds 4 bytes a
    /// disk and 4 a cell (no list of the ids or of the classes' members on
    /// the way).
    pub(crate) fn new(disks: &[Disk], ids: impl Iterator<Item = usize> + Clone) -> Self {
        let (r_min, r_max) = ids
            .clone()
            .map(|i| disks[i].r)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (if r > 0.0 { lo.min(r) } else { lo }, hi.max(r))
            });
        let class_of = |r: f64| {
            let k = (r / r_min).log2().floor();
            if k.is_finite() && k > 0.0 {
                (k as usize).min(MAX_CLASSES - 1)
            } else {
                0
            }
        };
        let mut counts = [0usize; MAX_CLASSES];
        if r_max / r_min < ONE_CLASS {
            // Every disk in the first class, without a logarithm each.
            counts[0] = ids.clone().count();
        } else {
            for i in ids.clone() {
                counts[class_of(disks[i].r)] += 1;
            }
        }
        let total: usize = counts.iter().sum();
        let classes = (0..MAX_CLASSES)
            .filter(|&k| counts[k] > 0)
            .map(|k| {
                if counts[k] == total {
                    // One class: its members without a class test each.
                    Class::new(disks, ids.clone(), total)
                } else {
                    let members = ids.clone().filter(|&i| class_of(disks[i].r) == k);
                    Class::new(disks, members, counts[k])
                }
            })
            .collect();
        ByRadius { classes }
    }

    /// The largest radius of the finest class (0 with no disk).
    pub(crate) fn finest_r_max(&self) -> f64 {
        self.classes.first().map_or(0.0, |c| c.r_max)
    }

    /// Visit every disk whose centre lies within `reach` plus its class's
    /// largest radius of `p` along each axis, and perhaps a few beyond,
    /// until `f` breaks.
    pub(crate) fn try_visit(
        &self,
        p: Point,
        reach: f64,
        mut f: impl FnMut(usize) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        for class in &self.classes {
            class.try_visit(p, reach + class.r_max, &mut f)?;
        }
        ControlFlow::Continue(())
    }

    /// The indexed disks in runs of at most `chunk`: class by class, each
    /// class's in cell order (row, then column), so that disks near in
    /// space are near in this order.
    pub(crate) fn runs(&self, chunk: usize) -> Vec<&[u32]> {
        self.classes
            .iter()
            .flat_map(|c| c.ids.chunks(chunk))
            .collect()
    }

    /// [`ByRadius::try_visit`] without a break.
    pub(crate) fn visit(&self, p: Point, reach: f64, mut f: impl FnMut(usize)) {
        let _ = self.try_visit(p, reach, |j| {
            f(j);
            ControlFlow::Continue(())
        });
    }

    /// Visit every disk whose centre lies in the box `[lo, hi]` widened by
    /// its class's largest radius on each side (every disk that may reach
    /// into the box), and perhaps a few beyond: class by class, each
    /// class's cells row by row, and the disks of a cell by index.
    pub(crate) fn visit_box(&self, lo: Point, hi: Point, mut f: impl FnMut(usize)) {
        for class in &self.classes {
            let r = class.r_max;
            let _ = class.try_visit_span((lo.x - r, hi.x + r), (lo.y - r, hi.y + r), &mut |j| {
                f(j);
                ControlFlow::Continue(())
            });
        }
    }
}

impl Class {
    /// The class of the `count` disks `disks[i]`, `i` of `ids` (in
    /// increasing order, so that each cell's disks come by index).
    ///
    /// # Performance
    /// A counting sort by cell: two walks of `ids`, no comparison sort.
    fn new(disks: &[Disk], ids: impl Iterator<Item = usize> + Clone, count: usize) -> Self {
        let r_max = ids.clone().fold(0.0f64, |m, i| m.max(disks[i].r));
        let (mut x0, mut y0, mut x1, mut y1) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        for i in ids.clone() {
            let c = disks[i].c;
            (x0, y0, x1, y1) = (x0.min(c.x), y0.min(c.y), x1.max(c.x), y1.max(c.y));
        }
        // Cells of a sparse class hold about one disk each, and no class
        // spans more rows or columns than it has disks.
        let n = count as f64;
        let sparse = ((x1 - x0) * (y1 - y0) / n).sqrt();
        let mut side = (2.0 * r_max).max(sparse).max((x1 - x0).max(y1 - y0) / n);
        if !(side > 0.0 && side.is_finite()) {
            side = 1.0;
        }
        // The last row and column: at most n each, and at most about 4n
        // cells in all (only a centre that is not finite, which no query
        // could find anyway, could ask for more: it is clamped to the last).
        let last = |extent: f64| ((extent / side).floor().max(0.0)).min(n) as i64;
        let (mut rows, mut cols) = (last(y1 - y0), last(x1 - x0));
        let most = 4 * count as i64 + 4;
        if (rows + 1).saturating_mul(cols + 1) > most {
            let root = (n.sqrt().ceil() as i64).max(1);
            (rows, cols) = (rows.min(root), cols.min(root));
        }
        let class = Class {
            r_max,
            side,
            origin: (x0, y0),
            rows,
            cols,
            ids: Vec::new(),
            cell_start: Vec::new(),
        };
        let cell_of = |i: usize| {
            let c = disks[i].c;
            let row = class.cell(c.y, y0).clamp(0, rows) as usize;
            let col = class.cell(c.x, x0).clamp(0, cols) as usize;
            row * (cols as usize + 1) + col
        };
        let cells = (rows as usize + 1) * (cols as usize + 1);
        let mut cell_start = vec![0u32; cells + 1];
        for i in ids.clone() {
            cell_start[cell_of(i) + 1] += 1;
        }
        for k in 1..cell_start.len() {
            cell_start[k] += cell_start[k - 1];
        }
        let mut ids_sorted = vec![0u32; count];
        let mut next = cell_start.clone();
        for i in ids {
            let slot = &mut next[cell_of(i)];
            ids_sorted[*slot as usize] = i as u32;
            *slot += 1;
        }
        Class {
            ids: ids_sorted,
            cell_start,
            ..class
        }
    }

    /// The cell along one axis of coordinate `v`, origin `o` (not clamped).
    fn cell(&self, v: f64, o: f64) -> i64 {
        floor_i64((v - o) / self.side)
    }

    /// Visit the disks whose centres lie within `half` of `p` along each
    /// axis, and perhaps a few beyond, until `f` breaks.
    fn try_visit(
        &self,
        p: Point,
        half: f64,
        f: &mut impl FnMut(usize) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        self.try_visit_span((p.x - half, p.x + half), (p.y - half, p.y + half), f)
    }

    /// Visit the disks whose centres lie in `[x.0, x.1] × [y.0, y.1]`, and
    /// perhaps a few beyond, until `f` breaks.
    fn try_visit_span(
        &self,
        x: (f64, f64),
        y: (f64, f64),
        f: &mut impl FnMut(usize) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let (x0, y0) = self.origin;
        let (r0, r1) = (self.cell(y.0, y0).max(0), self.cell(y.1, y0).min(self.rows));
        let (c0, c1) = (self.cell(x.0, x0).max(0), self.cell(x.1, x0).min(self.cols));
        if r0 > r1 || c0 > c1 {
            return ControlFlow::Continue(());
        }
        let width = self.cols as usize + 1;
        for row in r0 as usize..=r1 as usize {
            let base = row * width;
            let (lo, hi) = (
                self.cell_start[base + c0 as usize] as usize,
                self.cell_start[base + c1 as usize + 1] as usize,
            );
            for &j in &self.ids[lo..hi] {
                #[cfg(test)]
                VISITED.with(|v| v.set(v.get() + 1));
                f(j as usize)?;
            }
        }
        ControlFlow::Continue(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_floor_is_floor() {
        let edges = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.5,
            -2.5,
            1e300,
            -1e300,
            9.3e18,
            -9.3e18,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            4503599627370495.5,
            -4503599627370495.5,
            1.0 - f64::EPSILON,
            -1.0 + f64::EPSILON,
        ];
        let mut bits = 0x9e37_79b9_7f4a_7c15u64;
        let random = (0..100_000).map(|_| {
            bits ^= bits << 13;
            bits ^= bits >> 7;
            bits ^= bits << 17;
            f64::from_bits(bits)
        });
        for x in edges.into_iter().chain(random) {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        }
    }

    #[test]
    fn far_apart_tiny_disks_keep_the_rows_few() {
        // Cells of 2·r would make 5·10¹¹ rows of a table indexed by row.
        let disks = [Disk::new(0.0, 0.0, 1e-9), Disk::new(0.0, 1000.0, 1e-9)];
        let near = ByRadius::new(&disks, 0..2);
        assert!(near.classes.iter().all(|c| c.rows <= 2 && c.cols <= 2));
        assert!(near.classes.iter().all(|c| c.cell_start.len() <= 4 * 2 + 5));
        let mut seen = Vec::new();
        near.visit(Point::new(0.0, 500.0), 600.0, |j| seen.push(j));
        seen.sort_unstable();
        assert_eq!(seen, [0, 1]);
        let mut seen = Vec::new();
        near.visit(Point::new(0.0, 999.0), 2.0, |j| seen.push(j));
        assert_eq!(seen, [1]);
        // A centre that is not finite is bucketed without a huge table.
        let odd = [
            Disk::new(0.0, 0.0, 1.0),
            Disk::new(f64::INFINITY, 1e300, 1.0),
        ];
        let near = ByRadius::new(&odd, 0..2);
        let mut seen = Vec::new();
        near.visit(Point::new(0.0, 0.0), 1.0, |j| seen.push(j));
        assert!(seen.contains(&0));
    }
}
