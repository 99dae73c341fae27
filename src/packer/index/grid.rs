//! Uniform grid: the simplest index, kept to compare the MX quadtree against.

use super::{NIL, SpatialIndex, box_span, bucket_of, walk_list};
use crate::geometry::Point;
use std::ops::ControlFlow;

/// A dense grid of square cells over the domain's bounds, each cell a linked list.
#[derive(Debug, Clone)]
pub struct Grid {
    origin: Point,
    inv_side: f64,
    nx: u32,
    ny: u32,
    head: Vec<u32>,
    next: Vec<u32>,
}

impl SpatialIndex for Grid {
    /// Cells of one diameter: a query visits about 5 × 5 cells, each one load.
    const BUCKET_DIAMETERS: f64 = 1.0;

    fn new(min: Point, max: Point, bucket: f64) -> Self {
        let cells = |extent: f64| ((extent / bucket).ceil() as u32).max(1);
        let (nx, ny) = (cells(max.x - min.x), cells(max.y - min.y));
        Grid {
            origin: min,
            inv_side: 1.0 / bucket,
            nx,
            ny,
            head: vec![NIL; nx as usize * ny as usize],
            next: Vec::new(),
        }
    }

    fn insert(&mut self, id: u32, p: Point) {
        debug_assert_eq!(id as usize, self.next.len());
        let ix = bucket_of(p.x, self.origin.x, self.inv_side, self.nx);
        let iy = bucket_of(p.y, self.origin.y, self.inv_side, self.ny);
        let cell = (iy * self.nx + ix) as usize;
        self.next.push(self.head[cell]);
        self.head[cell] = id;
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
        for iy in y0..=y1 {
            let row = (iy * self.nx) as usize;
            for ix in x0..=x1 {
                walk_list(self.head[row + ix as usize], &self.next, &mut f)?;
            }
        }
        ControlFlow::Continue(())
    }
}
