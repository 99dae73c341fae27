//! A packing measured near given lines and away from them: whether the
//! seams of a packing made in parts (`packer.strips`) differ from its bulk,
//! or a periodic cell's edges, where its front closes on itself, from its
//! inside.

use super::contacts::{coordination, visit_near};
use super::{mean_sd, porosity};
use crate::Scene;
use crate::geometry::predicates::area_disk_box;
use crate::geometry::{Disk, Point};
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
/// The porosity is measured on square cells one largest diameter wide (at
/// most `2·half`), each counted whole in the zone its centre lies in, each
/// disk's area clipped to the cells exactly (`area_disk_box`); a disk
/// belongs to the zone its centre lies in. In a periodic cell the cells
/// tile it exactly (their sides stretched to fit), so that a band of cells
/// lines each edge, and the images of the disks across its edges count, in
/// the solid and in the contacts.
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
    let domain = &packing.domain;
    let periodic = domain.is_periodic();
    let r_max = packing.disks.iter().fold(0.0f64, |m, d| m.max(d.r));
    let side = if periodic {
        (2.0 * r_max).min(2.0 * half)
    } else {
        2.0 * r_max
    }
    .max(f64::MIN_POSITIVE);
    let count = |extent: f64| {
        let n = (extent / side).max(0.0);
        (if periodic { n.ceil() } else { n.floor() }) as usize
    };
    let (cols, rows) = (count(hi.x - lo.x), count(hi.y - lo.y));
    let (cw, ch) = if periodic {
        (
            (hi.x - lo.x) / cols.max(1) as f64,
            (hi.y - lo.y) / rows.max(1) as f64,
        )
    } else {
        (side, side)
    };
    let near = Near::new(lines, half, lo, hi);
    // The packed disks, then (in a periodic cell) their images that reach
    // within a largest diameter of the cell.
    let real = packing.disks.len();
    let mut disks = packing.disks.clone();
    if periodic {
        for d in &packing.disks {
            let reach = d.r + 2.0 * r_max;
            let (qlo, qhi) = (
                Point::new(d.c.x - reach, d.c.y - reach),
                Point::new(d.c.x + reach, d.c.y + reach),
            );
            // The shifts `v` that bring the box into the cell: the image
            // at `c − v` reaches it.
            for v in domain.image_shifts(qlo, qhi) {
                if v != nalgebra::Vector2::zeros() {
                    disks.push(Disk { c: d.c - v, r: d.r });
                }
            }
        }
    }
    let (b_lo, b_hi) = domain.bounds();
    let pad = if periodic { 3.0 * r_max } else { 0.0 };
    let mut grid = Grid::new(
        Point::new(b_lo.x - pad, b_lo.y - pad),
        Point::new(b_hi.x + pad, b_hi.y + pad),
        Grid::BUCKET_DIAMETERS * side,
    );
    for (i, d) in disks.iter().enumerate() {
        grid.insert(i as u32, d.c);
    }
    let mut solid = vec![0.0; cols * rows];
    // Disks by zone: sizes, contact ends.
    let mut sizes = [Vec::new(), Vec::new()];
    let mut ends = [0usize; 2];
    for (i, d) in disks.iter().enumerate() {
        let at = |v: f64, o: f64, w: f64| ((v - o) / w).floor().max(0.0) as usize;
        let (c0, c1) = (at(d.c.x - d.r, lo.x, cw), at(d.c.x + d.r, lo.x, cw));
        let (r0, r1) = (at(d.c.y - d.r, lo.y, ch), at(d.c.y + d.r, lo.y, ch));
        for row in r0..=r1.min(rows.saturating_sub(1)) {
            for col in c0..=c1.min(cols.saturating_sub(1)) {
                let (x0, y0) = (lo.x + col as f64 * cw, lo.y + row as f64 * ch);
                solid[row * cols + col] += area_disk_box(d.c, d.r, x0, x0 + cw, y0, y0 + ch);
            }
        }
        let inside = i < real && d.c.x >= lo.x && d.c.x <= hi.x && d.c.y >= lo.y && d.c.y <= hi.y;
        if inside {
            let z = usize::from(!near.is_near(d.c));
            sizes[z].push(2.0 * d.r);
            visit_near(
                &grid,
                &disks,
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
                lo.x + (col as f64 + 0.5) * cw,
                lo.y + (row as f64 + 0.5) * ch,
            );
            let z = usize::from(!near.is_near(centre));
            cells[z].push(porosity(solid[row * cols + col], cw * ch));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::grading::{Basis, Grading};

    #[test]
    fn a_periodic_cell_counts_the_images_across_its_edges() {
        // Two unit disks touching across the edge x = 0 of a 10 mm cell:
        // one centred 0.3 mm from it (the band's), one 1.7 mm from x = 10.
        let domain = Domain::periodic_rectangle(10.0, 10.0).expect("cell");
        let packing = Packing::of_disks(
            domain.clone(),
            vec![Disk::new(0.3, 5.0, 1.0), Disk::new(8.3, 5.0, 1.0)],
        );
        let grading = Grading::uniform(1.0, 2.0, Basis::Number).expect("grading");
        let scene = Scene::new(domain, grading);
        let (lo, hi) = (Point::new(0.0, 0.0), Point::new(10.0, 10.0));
        let edges = [
            [lo, Point::new(hi.x, lo.y)],
            [Point::new(hi.x, lo.y), hi],
            [hi, Point::new(lo.x, hi.y)],
            [Point::new(lo.x, hi.y), lo],
        ];
        let [near, away] = zones(&packing, &scene, &edges, 0.5, 0.0);
        // 1 mm cells: the ring of 36 along the edges, 64 inside; the part
        // of the first disk beyond x = 0 is counted at x = 10.
        let solid = 36.0 * (1.0 - near.porosity) + 64.0 * (1.0 - away.porosity);
        assert!((solid - 2.0 * std::f64::consts::PI).abs() < 1e-9, "{solid}");
        // Each touches the other's image.
        assert_eq!((near.disks, away.disks), (1, 1));
        assert_eq!((near.coordination, away.coordination), (1.0, 1.0));
    }
}
