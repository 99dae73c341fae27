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

use rayon::slice::ParallelSliceMut;

use crate::geometry::{Disk, Point};

/// Most size classes (radii spanning 2⁶³ share the last).
const MAX_CLASSES: usize = 64;

#[cfg(test)]
thread_local! {
    /// Disks the queries of this thread visited.
    pub(crate) static VISITED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// One size class: its largest radius and its disks keyed (row, column), sorted.
struct Class {
    r_max: f64,
    side: f64,
    origin: (f64, f64),
    rows: i64,
    cols: i64,
    /// (row, column, disk) of each disk of the class, sorted: 12 bytes a
    /// disk (rows and columns are at most the class's count).
    keyed: Vec<(u32, u32, u32)>,
    /// Where each row's keys begin in `keyed`, and its end last.
    row_start: Vec<u32>,
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
    /// Walks `ids` once per size class present, and holds 12 bytes a disk
    /// (no list of the ids or of the classes' members on the way).
    pub(crate) fn new(disks: &[Disk], ids: impl Iterator<Item = usize> + Clone) -> Self {
        let r_min = ids
            .clone()
            .map(|i| disks[i].r)
            .filter(|r| *r > 0.0)
            .fold(f64::INFINITY, f64::min);
        let class_of = |r: f64| {
            let k = (r / r_min).log2().floor();
            if k.is_finite() && k > 0.0 {
                (k as usize).min(MAX_CLASSES - 1)
            } else {
                0
            }
        };
        let mut counts = [0usize; MAX_CLASSES];
        for i in ids.clone() {
            counts[class_of(disks[i].r)] += 1;
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
    pub(crate) fn runs(&self, chunk: usize) -> Vec<&[(u32, u32, u32)]> {
        self.classes
            .iter()
            .flat_map(|c| c.keyed.chunks(chunk))
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
    /// The class of the `count` disks `disks[i]`, `i` of `ids`.
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
        // At most n rows and columns past the first (more only from a
        // centre that is not finite, which no query could find anyway).
        let last = count as i64;
        let cell = |v: f64, o: f64| (((v - o) / side).floor() as i64).clamp(0, last) as u32;
        let mut keyed = Vec::with_capacity(count);
        keyed.extend(ids.map(|i| {
            let c = disks[i].c;
            (cell(c.y, y0), cell(c.x, x0), i as u32)
        }));
        // The keys are distinct (one disk each): the order is the same
        // whatever the number of threads.
        keyed.par_sort_unstable();
        let (rows, cols) = keyed
            .iter()
            .fold((0, 0), |(r, c), &(kr, kc, _)| (r.max(kr), c.max(kc)));
        let (rows, cols) = (i64::from(rows), i64::from(cols));
        let row_start = (0..=rows + 1)
            .map(|row| keyed.partition_point(|&(r, _, _)| i64::from(r) < row) as u32)
            .collect();
        Class {
            r_max,
            side,
            origin: (x0, y0),
            rows,
            cols,
            keyed,
            row_start,
        }
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
        let cell = |v: f64, o: f64| ((v - o) / self.side).floor() as i64;
        let (r0, r1) = (cell(y.0, y0).max(0), cell(y.1, y0).min(self.rows));
        let (c0, c1) = (cell(x.0, x0).max(0), cell(x.1, x0).min(self.cols));
        if r0 > r1 || c0 > c1 {
            return ControlFlow::Continue(());
        }
        for row in r0..=r1 {
            let keys = &self.keyed
                [self.row_start[row as usize] as usize..self.row_start[row as usize + 1] as usize];
            let lo = keys.partition_point(|&(_, c, _)| i64::from(c) < c0);
            let hi = lo + keys[lo..].partition_point(|&(_, c, _)| i64::from(c) <= c1);
            for &(_, _, j) in &keys[lo..hi] {
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
    fn far_apart_tiny_disks_keep_the_rows_few() {
        // Cells of 2·r would make 5·10¹¹ rows of a table indexed by row.
        let disks = [Disk::new(0.0, 0.0, 1e-9), Disk::new(0.0, 1000.0, 1e-9)];
        let near = ByRadius::new(&disks, 0..2);
        assert!(near.classes.iter().all(|c| c.rows <= 2 && c.cols <= 2));
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
