//! The disk, the one particle shape gapack packs.

use std::borrow::Borrow;

/// A point in the plane (mm).
pub type Point = nalgebra::Point2<f64>;

/// A disk: centre `c` and radius `r` (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disk {
    /// Centre (mm).
    pub c: Point,
    /// Radius (mm).
    pub r: f64,
}

impl Disk {
    /// A disk of centre `(x, y)` and radius `r`.
    pub fn new(x: f64, y: f64, r: f64) -> Self {
        Disk {
            c: Point::new(x, y),
            r,
        }
    }

    /// Area of the disk (mm²).
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * self.r * self.r
    }

    /// The disk's axis-aligned bounding box `(min, max)` (mm).
    pub fn bounds(&self) -> (Point, Point) {
        (
            Point::new(self.c.x - self.r, self.c.y - self.r),
            Point::new(self.c.x + self.r, self.c.y + self.r),
        )
    }
}

/// The smallest axis-aligned box `(min, max)` holding the box `start` and
/// every disk of `disks` whole (mm).
///
/// # Behavior
/// Start from a domain's bounds to frame the domain and its disks, or from
/// corners at `+∞` and `−∞` for the disks alone (which an empty `disks`
/// leaves as they are).
pub fn bounds_of_disks(
    start: (Point, Point),
    disks: impl IntoIterator<Item = impl Borrow<Disk>>,
) -> (Point, Point) {
    disks.into_iter().fold(start, |(lo, hi), disk| {
        let (a, b) = disk.borrow().bounds();
        (
            Point::new(lo.x.min(a.x), lo.y.min(a.y)),
            Point::new(hi.x.max(b.x), hi.y.max(b.y)),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_hold_the_start_and_every_disk_whole() {
        let disks = [Disk::new(1.0, 2.0, 0.5), Disk::new(-3.0, 4.0, 1.0)];
        let start = (Point::new(0.0, 0.0), Point::new(1.0, 1.0));
        assert_eq!(
            bounds_of_disks(start, disks),
            (Point::new(-4.0, 0.0), Point::new(1.5, 5.0))
        );
        assert_eq!(bounds_of_disks(start, &[] as &[Disk]), start);
        assert_eq!(
            disks[0].bounds(),
            (Point::new(0.5, 1.5), Point::new(1.5, 2.5))
        );
    }
}
