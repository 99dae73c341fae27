//! Propped hydraulic fractures: the fracture as a domain, batches of wells,
//! and representative windows.
//!
//! A fracture is a slot `width` wide (x, the aperture) and `length` long (y,
//! the fracture height of a well, or the length of a normalised cell), its
//! lower-left corner at the origin; a tapered fracture narrows linearly from
//! `width` at the wellbore (y = 0) to `tip_width` at y = `length`. The
//! config builds one [`Scene`] per well; [`window::settle`] packs only as
//! much of a fracture as its porosity and coordination need.

mod window;

pub use window::{FIRST_DIAMETERS, Window, WindowError, WindowStep, settle};

use crate::Scene;
use crate::geometry::{Domain, GeometryError};

/// `window_tolerance` when not given: porosity settled to half a percent.
pub const DEFAULT_WINDOW_TOLERANCE: f64 = 0.005;

/// Millimetres in a metre: wells give their height in metres (`height_m`).
pub const MM_PER_M: f64 = 1000.0;

/// A fracture's geometry (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fracture {
    /// Aperture at the wellbore, along x (mm).
    pub width: f64,
    /// Extent along y: the fracture height (mm).
    pub length: f64,
    /// Aperture at the tip (y = `length`) of a tapered fracture (mm); `None`
    /// for parallel walls.
    pub tip_width: Option<f64>,
}

impl Fracture {
    /// A parallel-walled fracture of the normalised form of Asgian et al.:
    /// W = (W_r + 2)·d_p wide and L = L_r·d_p long.
    pub fn normalised(width_ratio: f64, length_ratio: f64, mean_diameter: f64) -> Self {
        Fracture {
            width: (width_ratio + 2.0) * mean_diameter,
            length: length_ratio * mean_diameter,
            tip_width: None,
        }
    }

    /// The domain: a rectangle, or for a tapered fracture a trapezoid whose
    /// bottom (the wellbore) is the wider base.
    ///
    /// # Errors
    /// The domain constructor's, for sizes that are not positive and finite.
    pub fn domain(&self) -> Result<Domain, GeometryError> {
        match self.tip_width {
            None => Domain::rectangle(self.width, self.length),
            Some(tip) => Domain::trapezoid(self.width, tip, self.length),
        }
    }

    /// The same fracture cut to its first `length` mm (a window from the wellbore).
    pub fn cut(&self, length: f64) -> Fracture {
        Fracture { length, ..*self }
    }
}

/// How much of a fracture is packed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Extent {
    /// The whole fracture (default).
    #[default]
    Full,
    /// A window that grows until porosity and coordination settle within
    /// `tolerance` (see [`settle`]).
    Window {
        /// Settling tolerance: absolute on porosity, relative on coordination.
        tolerance: f64,
    },
}

/// One fracture to pack: a well of a batch, or the config's single fracture.
#[derive(Debug, Clone)]
pub struct Well {
    /// The well's name (its output sub-directory in a batch).
    pub name: String,
    /// Its geometry.
    pub fracture: Fracture,
    /// The scene that packs it: the fracture's domain, the config's grading,
    /// walls, packer and seed.
    pub scene: Scene,
}

/// A `[fracture]` run: what to pack of each fracture, and the fractures.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct FractureRun {
    /// Full fractures or representative windows.
    pub extent: Extent,
    /// Whether the config lists wells (`[[fracture.wells]]`): a batch writes
    /// one sub-directory per well and a table of them.
    pub batch: bool,
    /// The fractures, in config order; one when `batch` is false.
    pub wells: Vec<Well>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Point, Shape};

    #[test]
    fn normalised_cell_is_asgian_s() {
        let f = Fracture::normalised(4.88, 50.0, 1.25);
        assert!((f.width - 8.6).abs() < 1e-12);
        assert!((f.length - 62.5).abs() < 1e-12);
    }

    #[test]
    fn tapered_fracture_is_wider_at_the_wellbore() {
        let f = Fracture {
            width: 4.0,
            length: 100.0,
            tip_width: Some(1.0),
        };
        let d = f.domain().unwrap();
        assert!(matches!(d.shape(), Shape::Trapezoid { .. }));
        assert_eq!(d.bounds().0, Point::new(0.0, 0.0));
        // Inside near the wellbore's corners, outside beside the tip.
        assert!(d.signed_distance(Point::new(0.1, 0.1)) > 0.0);
        assert!(d.signed_distance(Point::new(0.1, 99.0)) < 0.0);
        assert!(d.signed_distance(Point::new(2.0, 99.0)) > 0.0);
        assert!((d.area() - 250.0).abs() < 1e-9);
    }

    #[test]
    fn a_cut_keeps_the_aperture() {
        let f = Fracture {
            width: 2.6,
            length: 8000.0,
            tip_width: None,
        };
        let w = f.cut(50.0).domain().unwrap();
        assert_eq!(
            w.shape(),
            &Shape::Rectangle {
                width: 2.6,
                height: 50.0
            }
        );
    }
}
