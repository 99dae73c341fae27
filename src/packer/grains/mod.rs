//! Packing particles that are not disks (a scene with a [`ShapeSpec`]):
//! superellipses and rounded convex polygons, by the advancing front (two
//! contacts, or one by bisection) or by random sequential addition.
//!
//! The sizes are the disks' draws (the same genes, the same seed); each
//! size becomes a grain drawn from the shape's own stream ([`SHAPE_STREAM`])
//! and scaled so that the size the grading measures is the size drawn.
//! The MX quadtree (or grid) indexes the centres; neighbours are those
//! whose bounding circles (circumradius) may meet. Every placement is
//! certified clear of its neighbours and walls by support functions
//! (`contact`), so the packing has no overlap by construction; `check`
//! proves it again independently.
//!
//! # What is refused, and why
//! Wall disks (`walls = "disks"`: walls would have to be particles of the
//! same shape model), the methods that move disks (deposition, relaxation,
//! densify: their physics is written for disks), strips and filling right
//! (they cut or mirror the scene as disks), and size-graded scenes packed
//! by rsa (a size's material follows the profile where the front grows).
//!
//! # Size-graded scenes
//! As with disks, each size's curve (its material) is chosen at the front
//! on top by the profile's share ([`Scene::gradient`]); its grain is drawn
//! with that material's shape (the second material's own
//! `second_shape`, else the scene's), and `Packing::materials` records
//! each particle's material.
//!
//! [`ShapeSpec`]: crate::ShapeSpec
//! [`SHAPE_STREAM`]: crate::SHAPE_STREAM

mod contact;
mod front;
mod rsa;
mod screen;

use std::collections::HashMap;

use nalgebra::Vector2;

use super::{Fill, Method, PackError, Packing};
use crate::cancel::Cancel;
use crate::geometry::{Outline, Point, WallMode};
use crate::{Scene, ShapeSpec};

/// Upper bound of the peak memory per particle (bytes) when packing
/// particles that are not disks: `gapack bench --shapes` (built with
/// `count-alloc`) measures at most 455 from 10⁴ to 10⁶ particles, the
/// growing vectors' doublings included.
pub const PEAK_BYTES_PER_GRAIN: f64 = 520.0;

/// Pack `scene`, whose shape is `shape`, with its method.
///
/// # Errors
/// [`PackError::NotForShapes`] for what particles that are not disks do not
/// support (see the module's notes), and as the disk packers otherwise.
pub(super) fn pack(
    scene: &Scene,
    shape: &ShapeSpec,
    genes: &mut dyn Iterator<Item = f64>,
    progress: &mut dyn FnMut(u64),
    cancel: &Cancel,
) -> Result<Packing, PackError> {
    let refuse = |what: &str| {
        Err(PackError::NotForShapes {
            what: what.to_string(),
        })
    };
    if scene.walls == WallMode::Disks {
        return refuse("walls = \"disks\"");
    }
    if scene.gradient.is_some() && scene.packer.method != Method::AdvancingFront {
        // A size's material follows the profile where the front grows.
        return refuse("a size-graded scene by a method other than the advancing front");
    }
    if scene.packer.fill == Fill::Right {
        return refuse("packer.fill = \"right\"");
    }
    if let Some(why) = scene.shapes().chain([shape]).find_map(malformed) {
        return refuse(&why);
    }
    match scene.packer.method {
        Method::AdvancingFront => {
            super::near_origin(scene, |s| front::pack(s, shape, genes, progress, cancel))
        }
        Method::Rsa => super::near_origin(scene, |s| rsa::pack(s, shape, genes, cancel)),
        Method::Deposition => refuse("method = \"deposition\""),
        Method::Relaxation => refuse("method = \"relaxation\""),
        Method::Densify => refuse("method = \"densify\""),
    }
}

/// Why a shape built in code (a config's is validated) cannot be packed:
/// no polygon template, a template or exponent its constructor refuses, a
/// range or share that is not finite and at least 1 where it must be.
fn malformed(shape: &ShapeSpec) -> Option<String> {
    use crate::scene::{Family, Spread};
    let at_least_one = |s: &Spread| {
        let (lo, hi) = s.bounds();
        lo.is_finite() && hi.is_finite() && lo >= 1.0 && lo <= hi
    };
    match &shape.family {
        Family::Superellipse {
            aspect,
            alpha,
            beta,
        } => (![aspect, alpha, beta].iter().all(|s| at_least_one(s)))
            .then(|| "an aspect ratio or exponent below 1 or not finite".to_owned()),
        Family::Polygons { templates } if templates.is_empty() => {
            Some("no polygon template".to_owned())
        }
        Family::Polygons { templates } => templates.iter().find_map(|(t, share)| match t {
            Outline::Polygon {
                template,
                vertices,
                rounding,
            } if share.is_finite() && *share >= 0.0 => {
                Outline::polygon(*template, vertices, *rounding)
                    .err()
                    .map(|e| e.to_string())
            }
            _ => Some("a template that is not a polygon with a share".to_owned()),
        }),
    }
}

/// A placed particle as the packer keeps it.
pub(super) struct Body {
    /// Centre (mm; in a periodic cell, inside the cell).
    pub c: Point,
    /// The outline in its own axes.
    pub outline: Outline,
    /// Its angle's cosine and sine.
    pub cos: f64,
    pub sin: f64,
    /// Radius of a disk about the centre holding it (circumradius).
    pub reach: f64,
    /// Radius of a disk about the centre inside it.
    pub inner: f64,
}

impl Body {
    /// Support value and point (about the centre) in world direction `u`.
    #[inline]
    pub fn support(&self, u: Vector2<f64>) -> (f64, Vector2<f64>) {
        contact::support_turned(&self.outline, self.cos, self.sin, u)
    }
}

/// The reach (circumradius) and inner radius of outlines, computed once per
/// outline up to scale.
#[derive(Default)]
pub(super) struct Radii {
    known: HashMap<[u64; 3], (f64, f64)>,
}

impl Radii {
    /// Reach and inner radius of `outline`.
    pub fn of(&mut self, outline: &Outline) -> (f64, f64) {
        match outline {
            Outline::Superellipse { a, b, alpha, beta } => {
                let key = [(a / b).to_bits(), alpha.to_bits(), beta.to_bits()];
                let (reach, inner) = *self.known.entry(key).or_insert_with(|| {
                    let unit = Outline::Superellipse {
                        a: a / b,
                        b: 1.0,
                        alpha: *alpha,
                        beta: *beta,
                    };
                    (
                        unit.circumradius(),
                        superellipse_inner(a / b, 1.0, *alpha, *beta),
                    )
                });
                (reach * b, inner * b)
            }
            Outline::Polygon {
                vertices, rounding, ..
            } => {
                let reach = outline.circumradius();
                let n = vertices.len();
                // The centroid's distance to each edge's line, least.
                let inner = (0..n)
                    .map(|i| {
                        let (p, q) = (vertices[i], vertices[(i + 1) % n]);
                        let e = q - p;
                        (e.x * p.y - e.y * p.x).abs() / e.norm()
                    })
                    .fold(f64::INFINITY, f64::min);
                (reach, inner + rounding)
            }
        }
    }
}

/// Radius of a disk about the centre inside a superellipse: the inscribed
/// ellipse's least semi-axis when α, β ≥ 2 (the superellipse holds the
/// ellipse), else the inscribed rhombus' inradius ab/√(a² + b²).
fn superellipse_inner(a: f64, b: f64, alpha: f64, beta: f64) -> f64 {
    if alpha >= 2.0 && beta >= 2.0 {
        a.min(b)
    } else {
        a * b / (a * a + b * b).sqrt()
    }
}

#[cfg(test)]
mod tests;
