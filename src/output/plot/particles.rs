//! What the drawings of a packing (`packing.svg`, `packing.png`) share about
//! particles that are not disks: their colours (`[output] colour`) and
//! their outlines as polygons fine enough for the picture.
//!
//! A particle is drawn as [`Outline::boundary`], a polygon inscribed in its
//! outline, turned by its angle and moved to its centre: its exact shape,
//! to within a fraction of a pixel. The number of points follows the
//! particle's size on the picture ([`boundary_points`]), so a million small
//! particles cost a few points each and a large one looks smooth.

use std::f64::consts::{PI, TAU};

use crate::geometry::{Disk, Grain, Outline, Point};
use crate::layering::Material;
use crate::names::{ConfigName, Names};
use crate::output::palette::{self, cyclic, diameter_colour};
use crate::packer::Packing;

/// How the packed particles of `packing.svg` and `packing.png` are filled
/// (`[output] colour`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Colouring {
    /// Light to dark by diameter (a particle that is not a disk: the
    /// diameter of the disk of the same area).
    #[default]
    Size,
    /// One palette colour per material (by size where the particles carry none).
    Material,
    /// A cyclic colour scale over the particle's orientation: the angle of
    /// a superellipse's long axis modulo 180° (it looks the same turned by
    /// a half turn), the angle of a polygon's template modulo 360° (a
    /// polygon has in general no such symmetry). Disks have none.
    Orientation,
}

/// The names `[output] colour` takes.
pub(crate) const COLOURINGS: Names<Colouring> = Names {
    what: "colouring",
    entries: &[
        ("size", Colouring::Size),
        ("material", Colouring::Material),
        ("orientation", Colouring::Orientation),
    ],
};

impl ConfigName for Colouring {
    fn config_name(&self) -> &'static str {
        COLOURINGS.name_of(*self)
    }
}

/// What the fills of a drawing show, settled from the colouring asked for
/// and what the packing carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Fills {
    /// Light to dark over these diameters (mm).
    Diameters((f64, f64)),
    /// Each material's palette colour; a particle without one by its
    /// diameter over these (mm).
    Materials((f64, f64)),
    /// The cyclic scale over the orientation, one turn of it per `period`
    /// (radians: π when every particle is a superellipse, else 2π).
    Orientation {
        /// The angle one turn of the scale spans (radians).
        period: f64,
    },
}

impl Fills {
    /// The fills of `packing`'s drawing: as `colour` asks, by material only
    /// when the particles carry materials and `materials` name them, by
    /// orientation only for particles that are not disks; `None` (no
    /// `[output] colour`) colours by material when it can, else by size, as
    /// disks always were. Disks are shaded over `diameters`; other
    /// particles over their own range of area-equivalent diameters (the
    /// grading may measure another size of them, their sieve width).
    pub(crate) fn of(
        packing: &Packing,
        materials: &[Material],
        diameters: (f64, f64),
        colour: Option<Colouring>,
    ) -> Fills {
        let diameters = if packing.grains.is_empty() {
            diameters
        } else {
            own_diameters(packing)
        };
        let by_material = !materials.is_empty() && !packing.materials.is_empty();
        match colour {
            Some(Colouring::Orientation) if !packing.grains.is_empty() => Fills::Orientation {
                period: orientation_period(&packing.grains),
            },
            Some(Colouring::Size) => Fills::Diameters(diameters),
            _ if by_material => Fills::Materials(diameters),
            _ => Fills::Diameters(diameters),
        }
    }

    /// Fill of packed particle `i`.
    pub(crate) fn of_particle(&self, packing: &Packing, i: usize) -> [u8; 3] {
        let by_size = |range| {
            packing
                .disks
                .get(i)
                .map_or(palette::ramp(0.5), |d| diameter_colour(2.0 * d.r, range))
        };
        match *self {
            Fills::Diameters(range) => by_size(range),
            Fills::Materials(range) => match packing.materials.get(i) {
                Some(&m) => palette::colour(usize::from(m)),
                None => by_size(range),
            },
            Fills::Orientation { period } => packing
                .grains
                .get(i)
                .map_or(cyclic(0.0), |g| cyclic(orientation(g) / period)),
        }
    }
}

/// The smallest and largest area-equivalent diameter of the packed
/// particles (mm); `(0, 0)` without any.
fn own_diameters(packing: &Packing) -> (f64, f64) {
    if packing.disks.is_empty() {
        return (0.0, 0.0);
    }
    packing
        .disks
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
            (lo.min(2.0 * d.r), hi.max(2.0 * d.r))
        })
}

/// The angle a particle's orientation is told by (radians): its long axis'
/// for a superellipse (its own x axis, or y when that is the longer), its
/// template's x axis for a polygon.
pub(crate) fn orientation(grain: &Grain) -> f64 {
    match grain.outline {
        Outline::Superellipse { a, b, .. } if b > a => grain.angle + 0.5 * PI,
        _ => grain.angle,
    }
}

/// The period of the orientations of `grains` (radians): π when every one
/// is a superellipse (the same shape after a half turn), else 2π.
pub(crate) fn orientation_period(grains: &[Grain]) -> f64 {
    if grains
        .iter()
        .all(|g| matches!(g.outline, Outline::Superellipse { .. }))
    {
        PI
    } else {
        TAU
    }
}

/// A bound of how far an outline reaches from its centre (mm), cheap
/// enough to take for every particle: the corner of a superellipse's
/// box (it lies in [−a, a] × [−b, b]), a polygon's farthest vertex plus
/// its rounding.
pub(crate) fn reach(outline: &Outline) -> f64 {
    match outline {
        Outline::Superellipse { a, b, .. } => a.hypot(*b),
        Outline::Polygon {
            vertices, rounding, ..
        } => vertices.iter().map(|p| p.coords.norm()).fold(0.0, f64::max) + rounding,
    }
}

/// The packed particles' bounding disks: centre and [`reach`], for the
/// drawings' panels and periodic images.
pub(crate) fn bounding_disks(packing: &Packing) -> Vec<Disk> {
    packing
        .grains
        .iter()
        .zip(&packing.disks)
        .map(|(g, d)| Disk {
            c: d.c,
            r: reach(&g.outline),
        })
        .collect()
}

/// Fewest and most points of a drawn outline.
const MIN_POINTS: usize = 8;
const MAX_POINTS: usize = 128;

/// Points of the polygon drawn for a particle reaching `px` pixels from its
/// centre: an arc of radius R cut into chords of angle 2π/n strays
/// R·(π/n)²/2 from them, at most 0.1 px for n = π·√(R/0.2) ≈ 7·√R; a
/// multiple of 4 (the polygon keeps an ellipse's symmetries), from 8 to 128.
pub(crate) fn boundary_points(px: f64) -> usize {
    let n = if px.is_finite() && px > 0.0 {
        (PI * (px / 0.2).sqrt()).ceil().min(MAX_POINTS as f64) as usize
    } else {
        MIN_POINTS
    };
    n.next_multiple_of(4).clamp(MIN_POINTS, MAX_POINTS)
}

/// `grain`'s outline at `centre` in world coordinates (mm): its polygon of
/// about `n` points ([`Outline::boundary`]) turned by its angle,
/// counter-clockwise.
pub(crate) fn outline_at(grain: &Grain, centre: Point, n: usize) -> Vec<Point> {
    let turned = grain.turned();
    grain
        .outline
        .boundary(n)
        .into_iter()
        .map(|p| centre + turned.to_world(p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;

    fn ellipse(angle: f64) -> Grain {
        Grain::new(
            Outline::superellipse(3.0, 1.0, 2.0, 2.0).expect("ellipse"),
            angle,
        )
    }

    #[test]
    fn points_follow_the_size_on_the_picture() {
        assert_eq!(boundary_points(0.5), 8);
        assert_eq!(boundary_points(f64::NAN), 8);
        assert_eq!(boundary_points(10.0), 24);
        assert_eq!(boundary_points(100.0), 72);
        assert_eq!(boundary_points(1e6), 128);
        // The chord error stays under 0.1 px below the cap.
        for px in [1.0, 5.0, 30.0, 300.0] {
            let n = boundary_points(px) as f64;
            assert!(px * (PI / n).powi(2) / 2.0 <= 0.1, "{px}");
        }
    }

    #[test]
    fn orientations_are_told_by_the_long_axis() {
        assert_eq!(orientation(&ellipse(0.3)), 0.3);
        let tall = Grain::new(
            Outline::superellipse(1.0, 3.0, 2.0, 2.0).expect("ellipse"),
            0.0,
        );
        assert_eq!(orientation(&tall), 0.5 * PI);
        let triangle = Grain::new(
            Outline::polygon(
                0,
                &[
                    Point::new(0.0, 0.0),
                    Point::new(1.0, 0.0),
                    Point::new(0.0, 1.0),
                ],
                0.0,
            )
            .expect("triangle"),
            1.0,
        );
        assert_eq!(orientation_period(&[ellipse(0.0)]), PI);
        assert_eq!(orientation_period(&[ellipse(0.0), triangle]), TAU);
    }

    #[test]
    fn fills_follow_the_colouring_and_what_the_packing_carries() {
        let disks = Packing::of_disks(
            Domain::rectangle(10.0, 10.0).expect("square"),
            vec![Disk::new(2.0, 2.0, 1.0), Disk::new(6.0, 6.0, 2.0)],
        );
        let named = [Material {
            name: "sand".to_owned(),
            properties: Vec::new(),
        }];
        // Disks: orientation is refused by the config; here the default rule.
        for colour in [None, Some(Colouring::Orientation), Some(Colouring::Size)] {
            assert_eq!(
                Fills::of(&disks, &named, (1.0, 5.0), colour),
                Fills::Diameters((1.0, 5.0))
            );
        }
        let mut with_materials = disks.clone();
        with_materials.materials = vec![0, 0];
        assert_eq!(
            Fills::of(&with_materials, &named, (1.0, 5.0), None),
            Fills::Materials((1.0, 5.0))
        );
        assert_eq!(
            Fills::of(&with_materials, &named, (1.0, 5.0), Some(Colouring::Size)),
            Fills::Diameters((1.0, 5.0))
        );
        // Grains: shaded over their own diameters, or by orientation.
        let grains = Packing {
            grains: vec![ellipse(0.0), ellipse(0.5 * PI)],
            ..disks
        };
        assert_eq!(
            Fills::of(&grains, &[], (1.0, 5.0), None),
            Fills::Diameters((2.0, 4.0))
        );
        let by_angle = Fills::of(&grains, &[], (1.0, 5.0), Some(Colouring::Orientation));
        assert_eq!(by_angle, Fills::Orientation { period: PI });
        assert_ne!(
            by_angle.of_particle(&grains, 0),
            by_angle.of_particle(&grains, 1)
        );
    }

    #[test]
    fn an_outline_is_turned_about_its_centre() {
        let points = outline_at(&ellipse(0.5 * PI), Point::new(10.0, 20.0), 8);
        // The long axis (3 mm) now points along y.
        assert!((points[0] - Point::new(10.0, 23.0)).norm() < 1e-12);
        assert!((points[2] - Point::new(9.0, 20.0)).norm() < 1e-12);
        assert!(reach(&ellipse(0.0).outline) >= 3.0);
    }
}
