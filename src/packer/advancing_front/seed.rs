//! Where a run's first disks go, before there is a front to place them
//! at: with exact walls the lowest wall–wall tangency (a part's lowest spot,
//! on its side if need be), in a periodic cell the rank's origin (see
//! `Front::rank`) and then beside the first disk.

use super::periodic::{any_image, image};
use super::{Front, PackError, lowest_first};
use crate::geometry::predicates::{clear_disk_disk, clear_disk_walls};
use crate::geometry::{Point, Wall};
use crate::packer::index::SpatialIndex;

impl<I: SpatialIndex> Front<'_, I> {
    /// Exact walls: put a disk of radius `r` at the lowest feasible wall–wall
    /// tangency; `false` if none is clear.
    ///
    /// # Errors
    /// As [`Front::place`].
    pub(super) fn seed(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
        if self.periodic {
            return self.seed_cell(r, tag);
        }
        let mut spots = Vec::new();
        let walls = self.walls.len() as u64;
        self.stats.work += walls * walls.saturating_sub(1) / 2;
        for (i, a) in self.walls.iter().enumerate() {
            for b in &self.walls[i + 1..] {
                wall_wall_spots(a, b, r, &mut spots);
            }
            if let Wall::Circle { center, radius } = *a {
                spots.push(Point::new(center.x, center.y - (radius - r)));
            }
            // A part's lowest spots may lie on its sides, on one wall.
            if let Some(region) = self.region {
                for &plane in &region.planes {
                    wall_spot_on_line(a, r, plane, &mut spots);
                }
            }
        }
        if let Some(region) = self.region {
            spots.retain(|&p| region.contains(p));
        }
        spots.sort_unstable_by(|a, b| lowest_first(*a, *b));
        for p in spots {
            let half = r + self.r_max;
            let (lo, hi) = (
                Point::new(p.x - half, p.y - half),
                Point::new(p.x + half, p.y + half),
            );
            let mut clear = clear_disk_walls(&self.scene.domain, p, r);
            let (obs, tests) = (&self.obs, &self.tests);
            tests.set(tests.get() + 1 + walls);
            self.index.visit_box(lo, hi, |id| {
                tests.set(tests.get() + 1);
                let o = &obs[id as usize];
                clear &= clear_disk_disk(p, r, o.c, o.r);
            });
            if clear {
                self.place(p, r, tag)?;
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Periodic cell: put a disk of radius `r` at the rank's origin (a
    /// quarter period from the cell's low corner) when it is empty, or touching the first disk on its right when that is
    /// the only one; `false` otherwise, or if the spot is not clear of
    /// every image.
    ///
    /// # Errors
    /// As [`Front::place`].
    fn seed_cell(&mut self, r: f64, tag: u16) -> Result<bool, PackError> {
        let p = match &self.obs[self.first_packed..] {
            [] => self
                .origin
                .map_or_else(|| self.scene.domain.centroid(), |(o, _)| o),
            [first] => Point::new(first.c.x + first.r + r, first.c.y),
            _ => return Ok(false),
        };
        let half = r + self.r_max;
        let (lo, hi) = (
            Point::new(p.x - half, p.y - half),
            Point::new(p.x + half, p.y + half),
        );
        let (obs, tests) = (&self.obs, &self.tests);
        let blocked = any_image(&self.index, &self.scene.domain, lo, hi, |id, v| {
            tests.set(tests.get() + 1);
            let o = &obs[id as usize];
            !clear_disk_disk(p, r, image(o.c, v), o.r)
        });
        if blocked {
            return Ok(false);
        }
        self.place(p, r, tag)?;
        Ok(true)
    }
}

/// The centre of a disk of radius `r` tangent to straight `wall` (inside)
/// on the line `a·x + b·y = c` of `plane` (`[a, b, c]`), if there is one: a
/// part's lowest spot where its side meets a wall.
fn wall_spot_on_line(wall: &Wall, r: f64, [a, b, c]: [f64; 3], out: &mut Vec<Point>) {
    let Wall::Segment { a: p, b: q } = *wall else {
        return;
    };
    let len = (q - p).norm();
    let (ux, uy) = ((q.x - p.x) / len, (q.y - p.y) / len);
    let o = Point::new(p.x - uy * r, p.y + ux * r); // offset inward (left) by r
    let along = a * ux + b * uy;
    if along.abs() > 1e-12 {
        let t = (c - a * o.x - b * o.y) / along;
        if (0.0..=len).contains(&t) {
            out.push(Point::new(o.x + ux * t, o.y + uy * t));
        }
    }
}

/// Centres of disks of radius `r` tangent to both walls (inside), for seeding.
fn wall_wall_spots(a: &Wall, b: &Wall, r: f64, out: &mut Vec<Point>) {
    let Some(c) = offset_crossing(a, b, r) else {
        return;
    };
    let (ta, sa) = (c.len_a * 1e-12, c.len_b * 1e-12);
    if c.t >= -ta && c.t <= c.len_a + ta && c.s >= -sa && c.s <= c.len_b + sa {
        out.push(c.at);
    }
}

/// Where the lines of two straight walls offset inwards by `r` cross.
pub(crate) struct OffsetCrossing {
    /// The crossing: the centre of a disk of radius `r` touching both lines.
    pub at: Point,
    /// Its distance along the first wall from its start, and that wall's length.
    pub t: f64,
    pub len_a: f64,
    /// Its distance along the second wall from its start, and that wall's length.
    pub s: f64,
    pub len_b: f64,
}

/// The crossing of the two walls' lines offset inwards by `r` (`None` for
/// a circular wall or parallel walls); the callers decide how far beyond
/// the walls' ends it may lie.
pub(crate) fn offset_crossing(a: &Wall, b: &Wall, r: f64) -> Option<OffsetCrossing> {
    let offset = |w: &Wall| match *w {
        Wall::Segment { a, b } => {
            let len = (b - a).norm();
            let u = (b - a) / len;
            Some((Point::new(a.x - u.y * r, a.y + u.x * r), u, len))
        }
        Wall::Circle { .. } => None,
    };
    let ((p, u, len_a), (q, v, len_b)) = (offset(a)?, offset(b)?);
    let det = u.x * (-v.y) - u.y * (-v.x);
    if det.abs() < 1e-12 {
        return None;
    }
    let w = q - p;
    let t = (w.x * (-v.y) - w.y * (-v.x)) / det;
    let s = (u.x * w.y - u.y * w.x) / det;
    Some(OffsetCrossing {
        at: p + u * t,
        t,
        len_a,
        s,
        len_b,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_spot_is_tangent_to_both_walls() {
        let bottom = Wall::Segment {
            a: Point::new(0.0, 0.0),
            b: Point::new(10.0, 0.0),
        };
        let left = Wall::Segment {
            a: Point::new(0.0, 10.0),
            b: Point::new(0.0, 0.0),
        };
        let mut out = Vec::new();
        wall_wall_spots(&bottom, &left, 0.5, &mut out);
        assert_eq!(out.len(), 1);
        assert!((out[0] - Point::new(0.5, 0.5)).norm() < 1e-12);
    }
}
