//! The disk, the one particle shape gapack packs.

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
}
