//! MX quadtree (Samet), linear: the leaf cells of a regular subdivision
//! stored in Morton (Z-order) within tiles, each leaf a bucket of its items.

use super::{NIL, SpatialIndex, box_span, bucket_of, walk_list};
use crate::geometry::Point;
use std::ops::ControlFlow;

/// The quadtree's lowest levels, laid out in Morton order in one tile: a
/// tile is a complete subtree of 2^TILE_LEVELS × 2^TILE_LEVELS leaves. Three:
/// a tile's 64 slots are four cache lines, and a 4 × 4 block of leaves one.
const TILE_LEVELS: u32 = 3;
/// Leaves on a tile's side.
const TILE_SIDE: u32 = 1 << TILE_LEVELS;
/// Leaves in a tile.
const TILE_LEAVES: usize = (TILE_SIDE * TILE_SIDE) as usize;
/// A leaf coordinate's bits within its tile.
const TILE_MASK: u32 = TILE_SIDE - 1;

/// `SPREAD[v]`: the bits of `v` (below [`TILE_SIDE`]) spread to the even bit
/// positions, so a leaf's Morton code in its tile is `SPREAD[x] | SPREAD[y] << 1`.
const SPREAD: [u32; TILE_SIDE as usize] = {
    let mut t = [0u32; TILE_SIDE as usize];
    let mut v = 0;
    while v < TILE_SIDE as usize {
        let mut bit = 0;
        while bit < TILE_LEVELS {
            t[v] |= ((v as u32 >> bit) & 1) << (2 * bit);
            bit += 1;
        }
        v += 1;
    }
    t
};

/// Linear MX quadtree: regular subdivision of the domain into square leaf
/// cells of the bucket's side; only leaves hold data, so the tree's shape
/// does not depend on insertion order.
///
/// # Behavior
/// A leaf is known by its Morton code: the bits of its column and row
/// interleaved, so each node of the tree is a range of codes and the four
/// children of a node are its four quarters. The tree is implicit: the
/// leaves of each tile (a node `TILE_SIDE` leaves on a side, the lowest
/// `TILE_LEVELS` levels) are consecutive in Morton order, and the tiles
/// follow one another row by row over the domain's bounding rectangle, so
/// a leaf's slot is computed, not found by descending. Each slot heads the
/// leaf's bucket, a list through `next` (one entry per item), newest first.
///
/// # Performance
/// A query visits the box's leaves row by row, as the grid visits its
/// cells, so the packer sees its neighbours in the same order and does the
/// same work with either index. It skips the leaves above their column's
/// highest item (`top`, one entry per column): the front packs lowest
/// first, so nearly half the leaves a neighbour search covers lie above
/// it, empty. Per leaf, three instructions step the Morton offset of its
/// column (its row's is computed once per row); per item, one load of
/// `next`. The other forms tried (a pointer tree, contiguous leaf ids,
/// occupancy bits, inline pairs, branch-free buffers, circle-cut
/// rows, other leaf sizes) were slower in whole packings, and other tile
/// sizes no faster; docs/performance.md (spatial indexes) has their times, and the
/// quadtree's against the grid's, which does without the column tops.
/// Memory: 4 bytes per leaf of the bounding rectangle (its sides rounded up
/// to whole tiles), 4 per item, as the grid, and 4 per column.
#[derive(Debug, Clone)]
pub struct MxQuadtree {
    origin: Point,
    inv_side: f64,
    /// Leaves on the bounding rectangle's sides.
    nx: u32,
    ny: u32,
    /// Leaves in a row of tiles: `tiles_x` × [`TILE_LEAVES`].
    tile_row: u32,
    /// Each leaf's newest item, or `NIL`: tile by tile, Morton order within.
    head: Vec<u32>,
    /// Each item's next older item in its leaf, or `NIL`.
    next: Vec<u32>,
    /// Per leaf column: one past its highest leaf holding an item (0: none).
    top: Vec<u32>,
}

impl MxQuadtree {
    /// The part of a leaf's slot its row gives.
    #[inline]
    fn row_offset(&self, iy: u32) -> u32 {
        (iy >> TILE_LEVELS) * self.tile_row + (SPREAD[(iy & TILE_MASK) as usize] << 1)
    }

    /// The part of a leaf's slot its column gives.
    #[inline]
    fn column_offset(ix: u32) -> u32 {
        ((ix >> TILE_LEVELS) << (2 * TILE_LEVELS)) | SPREAD[(ix & TILE_MASK) as usize]
    }
}

/// The column offset of the next column: the row bits of the tile's code
/// set so the carry runs through them (into the tile's number past the
/// tile's last column), then cleared.
#[inline]
fn next_column(column: u32) -> u32 {
    const ROW_BITS: u32 = (SPREAD[TILE_MASK as usize]) << 1;
    ((column | ROW_BITS) + 1) & !ROW_BITS
}

impl SpatialIndex for MxQuadtree {
    /// Leaves of one diameter: a query visits about 5 × 5 leaves, each a
    /// short list (two-diameter leaves visit 3 × 3 leaves but half as many
    /// items again).
    const BUCKET_DIAMETERS: f64 = 1.0;

    fn new(min: Point, max: Point, bucket: f64) -> Self {
        let cells = |extent: f64| ((extent / bucket).ceil() as u32).max(1);
        let (nx, ny) = (cells(max.x - min.x), cells(max.y - min.y));
        let (tiles_x, tiles_y) = (nx.div_ceil(TILE_SIDE), ny.div_ceil(TILE_SIDE));
        MxQuadtree {
            origin: min,
            inv_side: 1.0 / bucket,
            nx,
            ny,
            tile_row: tiles_x * TILE_LEAVES as u32,
            head: vec![NIL; tiles_x as usize * tiles_y as usize * TILE_LEAVES],
            next: Vec::new(),
            top: vec![0; nx as usize],
        }
    }

    fn insert(&mut self, id: u32, p: Point) {
        debug_assert_eq!(id as usize, self.next.len());
        let ix = bucket_of(p.x, self.origin.x, self.inv_side, self.nx);
        let iy = bucket_of(p.y, self.origin.y, self.inv_side, self.ny);
        let leaf = (self.row_offset(iy) + Self::column_offset(ix)) as usize;
        self.next.push(self.head[leaf]);
        self.head[leaf] = id;
        let top = &mut self.top[ix as usize];
        *top = (*top).max(iy + 1);
    }

    #[inline]
    fn try_visit_box(
        &self,
        min: Point,
        max: Point,
        mut f: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let Some((x0, x1, y0, y1)) =
            box_span(min, max, self.origin, self.inv_side, (self.nx, self.ny))
        else {
            return ControlFlow::Continue(());
        };
        // Rows above every column's highest item hold nothing.
        let tops = &self.top[x0 as usize..=x1 as usize];
        let end = (y1 + 1).min(tops.iter().fold(0, |m, &t| m.max(t)));
        let first_column = Self::column_offset(x0);
        for iy in y0..end {
            let row = self.row_offset(iy);
            let mut column = first_column;
            for &t in tops {
                if iy < t {
                    walk_list(self.head[(row + column) as usize], &self.next, &mut f)?;
                }
                column = next_column(column);
            }
        }
        ControlFlow::Continue(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stepping a column offset gives the offset of the next column, across tiles too.
    #[test]
    fn next_column_steps_through_tiles() {
        for ix in 0..40 {
            assert_eq!(
                next_column(MxQuadtree::column_offset(ix)),
                MxQuadtree::column_offset(ix + 1)
            );
        }
    }

    #[test]
    fn spread_interleaves_bits() {
        assert_eq!(SPREAD[0b101], 0b10001);
        assert_eq!(SPREAD[0b111], 0b10101);
    }

    /// A leaf's slot: Morton order within its tile, tiles row by row; its
    /// bucket lists the newest item first.
    #[test]
    fn leaves_in_morton_order_within_tiles() {
        // 20 × 20 leaves: 3 × 3 tiles of 64 leaves.
        let mut t = MxQuadtree::new(Point::new(0.0, 0.0), Point::new(20.0, 20.0), 1.0);
        let pts = [(9.5, 2.5), (3.5, 10.5), (9.2, 2.7), (19.5, 19.5)];
        for (id, &(x, y)) in pts.iter().enumerate() {
            t.insert(id as u32, Point::new(x, y));
        }
        // Column 9, row 2: tile (1, 0), Morton code 0b1001 (x bits 01, y bits 10).
        assert_eq!(t.head[64 + 9], 2);
        assert_eq!(t.next[2], 0);
        assert_eq!(t.next[0], NIL);
        // Column 3, row 10: tile (0, 1), code 0b1101 (x bits 11, y bits 10).
        assert_eq!(t.head[3 * 64 + 0b1101], 1);
        // Column 19, row 19: tile (2, 2), the last; code 0b1111.
        assert_eq!(t.head[8 * 64 + 15], 3);
        assert_eq!(t.head.iter().filter(|&&h| h != NIL).count(), 3);
        let mut got = Vec::new();
        t.visit_box(Point::new(9.1, 2.1), Point::new(9.9, 2.9), |id| {
            got.push(id)
        });
        assert_eq!(got, [2, 0]);
    }

    /// Boxes that cover whole tiles and boxes that cut them: every item once.
    #[test]
    fn boxes_cover_whole_and_cut_tiles() {
        let (min, max) = (Point::new(0.0, 0.0), Point::new(20.0, 20.0));
        let mut t = MxQuadtree::new(min, max, 1.0);
        let mut id = 0;
        for iy in 0..20 {
            for ix in 0..20 {
                t.insert(id, Point::new(f64::from(ix) + 0.5, f64::from(iy) + 0.5));
                id += 1;
            }
        }
        let mut all = Vec::new();
        t.visit_box(min, max, |id| all.push(id));
        all.sort_unstable();
        assert_eq!(all, (0..400).collect::<Vec<_>>());
        // Leaves 3..=12 by 5..=9: ten columns across two tiles, five rows.
        let mut cut = Vec::new();
        t.visit_box(Point::new(3.2, 5.2), Point::new(12.8, 9.8), |id| {
            cut.push(id)
        });
        cut.sort_unstable();
        let want: Vec<u32> = (5..=9)
            .flat_map(|y| (3..=12).map(move |x| y * 20 + x))
            .collect();
        assert_eq!(cut, want);
    }
}
