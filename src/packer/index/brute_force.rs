//! Brute-force scan: the reference the real indexes are tested against.

use super::SpatialIndex;
use crate::geometry::Point;
use std::ops::ControlFlow;

/// Every item in one list; a query tests them all. Exact: visits only items in the box.
#[derive(Debug, Clone, Default)]
pub struct BruteForce {
    points: Vec<Point>,
}

impl SpatialIndex for BruteForce {
    /// Unused: brute force has no buckets.
    const BUCKET_DIAMETERS: f64 = 1.0;

    fn new(_min: Point, _max: Point, _bucket: f64) -> Self {
        BruteForce::default()
    }

    fn insert(&mut self, id: u32, p: Point) {
        debug_assert_eq!(id as usize, self.points.len());
        self.points.push(p);
    }

    fn try_visit_box(
        &self,
        min: Point,
        max: Point,
        mut f: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        for (id, p) in self.points.iter().enumerate() {
            if p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y {
                f(id as u32)?;
            }
        }
        ControlFlow::Continue(())
    }
}
