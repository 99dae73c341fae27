//! Square cells over the domain's bounds, for the densify method's
//! neighbour search: the disks are sorted by cell (a counting sort), so the
//! disks of a cell are one slice and neighbours lie near each other in memory.

use nalgebra::Vector2;

type V2 = Vector2<f64>;

/// Most cells per disk (and a few more for tiny scenes): a domain whose
/// bounding box is mostly empty (a thin slanted strip) gets wider cells
/// rather than a grid of millions.
const MAX_CELLS_PER_DISK: usize = 4;

/// Disks binned by cell, in the order of the cells (rows from the bottom,
/// then columns from the left).
#[derive(Debug, Clone)]
pub(super) struct Cells {
    origin: V2,
    hi: V2,
    inv_side: f64,
    nx: usize,
    ny: usize,
    /// The disks of cell `c` are the slots `start[c]..start[c + 1]`.
    start: Vec<u32>,
}

impl Cells {
    /// Cells of at least `side` over `lo`–`hi` widened by a cell each way,
    /// and the order that sorts `pos` by cell: `order[slot]` is the index of
    /// the disk that goes to `slot`. Centres beyond the widened bounds count
    /// in the cells at its edge.
    pub fn sort(pos: &[V2], lo: V2, hi: V2, side: f64) -> (Cells, Vec<u32>) {
        let cells_of = |side: f64| {
            let count = |extent: f64| (extent / side).ceil().max(1.0) + 2.0;
            (count(hi.x - lo.x), count(hi.y - lo.y))
        };
        let most = (MAX_CELLS_PER_DISK * pos.len() + 64) as f64;
        let mut side = side;
        let (mut fx, mut fy) = cells_of(side);
        while fx * fy > most {
            side *= 1.5;
            (fx, fy) = cells_of(side);
        }
        let (nx, ny) = (fx as usize, fy as usize);
        let margin = V2::new(side, side);
        let mut cells = Cells {
            origin: lo - margin,
            hi: hi + margin,
            inv_side: 1.0 / side,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
        };
        for p in pos {
            let c = cells.index(*p);
            cells.start[c + 1] += 1;
        }
        for c in 0..nx * ny {
            cells.start[c + 1] += cells.start[c];
        }
        let mut next = cells.start.clone();
        let mut order = vec![0u32; pos.len()];
        for (i, p) in pos.iter().enumerate() {
            let c = cells.index(*p);
            order[next[c] as usize] = i as u32;
            next[c] += 1;
        }
        (cells, order)
    }

    /// The cell of `p`, clamped into the grid: (column, row).
    #[inline]
    pub fn cell(&self, p: V2) -> (usize, usize) {
        let k = |v: f64, o: f64, n: usize| {
            let k = (v - o) * self.inv_side;
            if k > 0.0 { (k as usize).min(n - 1) } else { 0 }
        };
        (
            k(p.x, self.origin.x, self.nx),
            k(p.y, self.origin.y, self.ny),
        )
    }

    /// The number of cells.
    pub fn count(&self) -> usize {
        self.nx * self.ny
    }

    /// The side of a cell.
    pub fn side(&self) -> f64 {
        1.0 / self.inv_side
    }

    /// The centre of cell `c` (an index of [`Cells::index`]).
    pub fn centre(&self, c: usize) -> V2 {
        let (x, y) = ((c % self.nx) as f64 + 0.5, (c / self.nx) as f64 + 0.5);
        self.origin + V2::new(x, y) * self.side()
    }

    /// The index of the cell of `p`, clamped into the grid.
    #[inline]
    pub fn index(&self, p: V2) -> usize {
        let (x, y) = self.cell(p);
        y * self.nx + x
    }

    /// `p` clamped into the grid's bounds: near points stay near.
    #[inline]
    pub fn clamp(&self, p: V2) -> V2 {
        V2::new(
            p.x.clamp(self.origin.x, self.hi.x),
            p.y.clamp(self.origin.y, self.hi.y),
        )
    }

    /// Call `f` with every slot in the 3 × 3 cells around the cell of `p`.
    #[inline]
    pub fn visit_around(&self, p: V2, mut f: impl FnMut(usize)) {
        let (x, y) = self.cell(p);
        let (x0, x1) = (x.saturating_sub(1), (x + 1).min(self.nx - 1));
        for row in y.saturating_sub(1)..=(y + 1).min(self.ny - 1) {
            let a = self.start[row * self.nx + x0] as usize;
            let b = self.start[row * self.nx + x1 + 1] as usize;
            (a..b).for_each(&mut f);
        }
    }
}

/// Apply `order` (`new[slot] = old[order[slot]]`) to each array in place,
/// walking the permutation's cycles; `order` is left as it was.
pub(super) fn permute(order: &mut [u32], mut swap: impl FnMut(usize, usize)) {
    const DONE: u32 = 1 << 31;
    for first in 0..order.len() {
        if order[first] & DONE != 0 {
            continue;
        }
        // new[s] = old[order[s]]: moving along the cycle s → order[s],
        // each slot takes the value of the next, the last the first's.
        let mut s = first;
        loop {
            let src = (order[s] & !DONE) as usize;
            order[s] |= DONE;
            if src == first {
                break;
            }
            swap(s, src);
            s = src;
        }
    }
    order.iter_mut().for_each(|o| *o &= !DONE);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorting_by_cell_groups_each_cell_and_permute_applies_the_order() {
        let pos: Vec<V2> = (0..200)
            .map(|i| {
                let t = i as f64 * 0.7548776662;
                V2::new(
                    (t * 13.1).fract() * 10.0 - 1.0,
                    (t * 7.3).fract() * 6.0 + 0.5,
                )
            })
            .collect();
        let (cells, mut order) = Cells::sort(&pos, V2::new(0.0, 0.0), V2::new(9.0, 7.0), 1.3);
        let mut sorted = pos.clone();
        permute(&mut order, |a, b| sorted.swap(a, b));
        for (slot, &i) in order.iter().enumerate() {
            assert_eq!(sorted[slot], pos[i as usize]);
        }
        // Slots come cell by cell, and every slot of a cell is in it.
        let keys: Vec<(usize, usize)> = sorted
            .iter()
            .map(|p| {
                let (x, y) = cells.cell(*p);
                (y, x)
            })
            .collect();
        assert!(keys.windows(2).all(|w| w[0] <= w[1]));
        // Every pair within a cell side is found around either disk.
        for (i, p) in sorted.iter().enumerate() {
            let mut seen = Vec::new();
            cells.visit_around(*p, |j| seen.push(j));
            for (j, q) in sorted.iter().enumerate() {
                if (p - q).norm() < 1.3 {
                    assert!(seen.contains(&j), "{i} {j}");
                }
            }
        }
    }
}
