//! A packing measured near given lines and away from them: whether the
//! seams of a packing made in parts (`packer.strips`) differ from its bulk.

use super::contacts::{coordination, visit_near};
use super::{mean_sd, porosity};
use crate::Scene;
use crate::geometry::Point;
use crate::geometry::predicates::area_disk_box;
use crate::packer::Packing;
use crate::packer::index::{Grid, SpatialIndex};

/// The figures of one zone of a packing: near the lines, or away from them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct Zone {
    /// Porosity of the zone: 1 − the solid in its cells over their area.
    pub porosity: f64,
    /// Standard deviation of the porosity of its cells (side: one largest
    /// diameter): how much the local porosity varies within the zone.
    pub cell_sd: f64,
    /// Disks centred in the zone.
    pub disks: usize,
    /// Mean contacts of those disks (contacts with disks outside count).
    pub coordination: f64,
    /// Kolmogorov–Smirnov distance of those disks' sizes to the grading.
    pub psd_ks: f64,
}

/// The zones `[near, away]` of `packing`: points within `half` mm of a
/// segment of `lines`, and the others; both leave out what lies within
/// `margin` mm of the domain's bounds (the walls' own disturbance).
///
/// # Behavior
/// The porosity is measured on square cells one largest diameter wide, each
/// counted whole in the zone its centre lies in, each disk's area clipped to
/// the cells exactly ([`area_disk_box`]); a disk belongs to the zone its
/// centre lies in.
pub fn zones(
    packing: &Packing,
    scene: &Scene,
    lines: &[[Point; 2]],
    half: f64,
    margin: f64,
) -> [Zone; 2] {
    let (lo, hi) = packing.domain.bounds();
    let (lo, hi) = (
        Point::new(lo.x + margin, lo.y + margin),
        Point::new(hi.x - margin, hi.y - margin),
    );
    let disks = &packing.disks;
    let r_max = disks.iter().fold(0.0f64, |m, d| m.max(d.r));
    let cell = (2.0 * r_max).max(f64::MIN_POSITIVE);
    let near = Near::new(lines, half, lo, hi);
    let (cols, rows) = (
        ((hi.x - lo.x) / cell).floor().max(0.0) as usize,
        ((hi.y - lo.y) / cell).floor().max(0.0) as usize,
    );
    let mut solid = vec![0.0; cols * rows];
    let mut grid = Grid::new(
        packing.domain.bounds().0,
        packing.domain.bounds().1,
        Grid::BUCKET_DIAMETERS * cell,
    );
    for (i, d) in disks.iter().enumerate() {
        grid.insert(i as u32, d.c);
    }
    // Disks by zone: sizes, contact ends.
    let mut sizes = [Vec::new(), Vec::new()];
    let mut ends = [0usize; 2];
    for (i, d) in disks.iter().enumerate() {
        let (c0, c1) = (
            ((d.c.x - d.r - lo.x) / cell).floor().max(0.0) as usize,
            ((d.c.x + d.r - lo.x) / cell).floor().max(0.0) as usize,
        );
        let (r0, r1) = (
            ((d.c.y - d.r - lo.y) / cell).floor().max(0.0) as usize,
            ((d.c.y + d.r - lo.y) / cell).floor().max(0.0) as usize,
        );
        for row in r0..=r1.min(rows.saturating_sub(1)) {
            for col in c0..=c1.min(cols.saturating_sub(1)) {
                let (x0, y0) = (lo.x + col as f64 * cell, lo.y + row as f64 * cell);
                solid[row * cols + col] += area_disk_box(d.c, d.r, x0, x0 + cell, y0, y0 + cell);
            }
        }
        let inside = d.c.x >= lo.x && d.c.x <= hi.x && d.c.y >= lo.y && d.c.y <= hi.y;
        if inside {
            let z = usize::from(!near.is_near(d.c));
            sizes[z].push(2.0 * d.r);
            visit_near(
                &grid,
                disks,
                r_max,
                i,
                |_| true,
                |_, _, touching| {
                    ends[z] += usize::from(touching);
                },
            );
        }
    }
    let mut cells: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for row in 0..rows {
        for col in 0..cols {
            let centre = Point::new(
                lo.x + (col as f64 + 0.5) * cell,
                lo.y + (row as f64 + 0.5) * cell,
            );
            let z = usize::from(!near.is_near(centre));
            cells[z].push(porosity(solid[row * cols + col], cell * cell));
        }
    }
    [0, 1].map(|z| {
        let (mean, sd) = mean_sd(&cells[z]);
        Zone {
            porosity: mean,
            cell_sd: sd,
            disks: sizes[z].len(),
            coordination: coordination(ends[z], sizes[z].len()),
            psd_ks: scene.grading.ks_distance(&sizes[z]),
        }
    })
}

/// Segments bucketed on a coarse grid, to tell whether a point lies within
/// `half` of one.
struct Near<'a> {
    lines: &'a [[Point; 2]],
    half: f64,
    origin: Point,
    side: f64,
    cols: usize,
    buckets: Vec<Vec<u32>>,
}

impl<'a> Near<'a> {
    fn new(lines: &'a [[Point; 2]], half: f64, lo: Point, hi: Point) -> Self {
        let side = (8.0 * half)
            .max((hi.x - lo.x).max(hi.y - lo.y) / 512.0)
            .max(f64::MIN_POSITIVE);
        let cols = (((hi.x - lo.x) / side).ceil() as usize).max(1);
        let rows = (((hi.y - lo.y) / side).ceil() as usize).max(1);
        let mut buckets = vec![Vec::new(); cols * rows];
        let at = |v: f64, o: f64, n: usize| (((v - o) / side).floor().max(0.0) as usize).min(n - 1);
        for (k, [a, b]) in lines.iter().enumerate() {
            let (c0, c1) = (
                at(a.x.min(b.x) - half, lo.x, cols),
                at(a.x.max(b.x) + half, lo.x, cols),
            );
            let (r0, r1) = (
                at(a.y.min(b.y) - half, lo.y, rows),
                at(a.y.max(b.y) + half, lo.y, rows),
            );
            for row in r0..=r1 {
                for col in c0..=c1 {
                    buckets[row * cols + col].push(k as u32);
                }
            }
        }
        Near {
            lines,
            half,
            origin: lo,
            side,
            cols,
            buckets,
        }
    }

    fn is_near(&self, p: Point) -> bool {
        let rows = self.buckets.len() / self.cols;
        let at =
            |v: f64, o: f64, n: usize| (((v - o) / self.side).floor().max(0.0) as usize).min(n - 1);
        let (col, row) = (
            at(p.x, self.origin.x, self.cols),
            at(p.y, self.origin.y, rows),
        );
        self.buckets[row * self.cols + col].iter().any(|&k| {
            let [a, b] = self.lines[k as usize];
            let (ab, ap) = (b - a, p - a);
            let t = (ap.dot(&ab) / ab.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            (ap - ab * t).norm() <= self.half
        })
    }
}
