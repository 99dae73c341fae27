//! Where each size comes from: a gene U through the grading's inverse CDF,
//! or, in size-graded mode, through one of two curves chosen along the axis.

use crate::Scene;
use crate::geometry::Point;
use crate::grading::Grading;
use crate::scene::{Frame, Profile};

/// Turns genes into diameters (and materials, in size-graded mode).
pub(super) struct Sizer<'a> {
    grading: &'a Grading,
    graded: Option<Graded<'a>>,
}

/// Size-graded mode: the second curve, the profile of its area fraction,
/// and the error carried between draws.
struct Graded<'a> {
    second: &'a Grading,
    profile: &'a Profile,
    frame: Frame,
    /// Mean disk area of each curve (mm²).
    areas: [f64; 2],
    /// Draws of the second curve owed (positive) or ahead (negative).
    carry: f64,
}

impl<'a> Sizer<'a> {
    /// The sizer of `scene`: its grading, and its size gradient if it has one.
    /// With particle shapes, each curve's mean area is its mean disk area
    /// times its material's shape's mean area ratio (an inclusion of aspect
    /// 3 sized by sieve covers about 3 times its disk).
    pub fn new(scene: &'a Scene) -> Self {
        Sizer {
            grading: &scene.grading,
            graded: scene.gradient.as_ref().map(|g| {
                let mut areas = [scene.grading.mean_disk_area(), g.second.mean_disk_area()];
                if let Some(first) = &scene.shape {
                    let second = g.second_shape.as_ref().unwrap_or(first);
                    areas[0] *= first.mean_area_ratio();
                    areas[1] *= second.mean_area_ratio();
                }
                Graded {
                    second: &g.second,
                    profile: &g.profile,
                    frame: Frame::new(g.axis, &scene.domain),
                    areas,
                    carry: 0.0,
                }
            }),
        }
    }

    /// Whether sizes come with materials (size-graded mode).
    pub fn graded(&self) -> bool {
        self.graded.is_some()
    }

    /// The diameter drawn by gene `u`, and its material (0 or 1; 0 without a
    /// gradient), for a disk about to be placed near `at`.
    ///
    /// # Behavior
    /// In size-graded mode the profile's area fraction p of the second
    /// material at `at` becomes the probability q of drawing from its curve
    /// (q weighs p by the curves' mean disk areas, so that the expected area
    /// share is p), and the choice is made by error diffusion along the
    /// draws: the second curve whenever the draws owed to it reach one half.
    /// The placement order follows the growing front, so the local shares
    /// follow the profile without the noise of independent draws.
    pub fn size(&mut self, u: f64, at: Point) -> (f64, u16) {
        let Some(g) = self.graded.as_mut() else {
            return (self.grading.sample(u), 0);
        };
        let mut f = [0.0; 2];
        g.profile.fractions(g.frame.s(at), &mut f);
        let (na, nb) = (f[0] / g.areas[0], f[1] / g.areas[1]);
        let q = if na + nb > 0.0 { nb / (na + nb) } else { 0.0 };
        g.carry += q;
        if g.carry >= 0.5 {
            g.carry -= 1.0;
            (g.second.sample(u), 1)
        } else {
            (self.grading.sample(u), 0)
        }
    }
}
