//! Contacts, overlaps and wall clearances of a packing whose particles are
//! not disks ([`Packing::grains`]): found between the particles' outlines,
//! not their area-equivalent disks.
//!
//! Candidate pairs come from bounding circles (each outline's
//! circumradius); each is settled by the GJK distance of the two outlines
//! ([`grain_separation`]). Two particles touch when their gap (the
//! distance's upper bound) is at most [`CONTACT_REL`] of the sum of their
//! area-equivalent radii, the disks' rule with the same radii. An overlap
//! is the depth of the overlap (the shortest move that parts the two)
//! relative to that sum, as a disk pair's is.

use nalgebra::Vector2;

use super::near::ByRadius;
use super::shapes::ShapeMemo;
use super::{POLL_EVERY, images_near};
use crate::cancel::{Cancel, Cancelled};
use crate::geometry::predicates::CONTACT_REL;
use crate::geometry::{Disk, Grain, Outline, Point, Turned, Wall, grain_separation, separation};
use crate::packer::Packing;

/// Directions sampled around a pair (then refined) for an overlap's
/// depth, or around a grain for its farthest point from a circular wall.
const DIRECTIONS: usize = 360;

/// What the contacts of a packing of grains come to.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct GrainContacts {
    /// Largest overlap depth over the radii sum (0 if none).
    pub(super) max_overlap: f64,
    /// Contacts between packed particles.
    pub(super) contacts: usize,
    /// Each packed particle's contacts with other packed particles.
    pub(super) ends: Vec<u32>,
    /// Packed particles touching nothing.
    pub(super) isolated: usize,
    /// Smallest distance from a particle to a wall (NaN when periodic).
    pub(super) min_wall_clearance: f64,
}

/// The contacts, overlaps and wall clearances of `packing`'s grains (see
/// the module's notes), its wall disks counting as circles.
///
/// # Errors
/// [`Cancelled`] once `cancel` is raised.
pub(super) fn grain_contacts(
    packing: &Packing,
    memo: &mut ShapeMemo,
    cancel: &Cancel,
) -> Result<GrainContacts, Cancelled> {
    let domain = &packing.domain;
    let nb = packing.boundary.len();
    let walls: Vec<Grain> = packing
        .boundary
        .iter()
        .map(|d| Grain::new(circle(d.r), 0.0))
        .collect();
    // Each particle's centre, area-equivalent radius and bounding circle.
    let mut reach: Vec<Disk> = packing.boundary.clone();
    let mut radius: Vec<f64> = packing.boundary.iter().map(|d| d.r).collect();
    for (d, g) in packing.disks.iter().zip(&packing.grains) {
        let (unit, scale) = memo.unit(&g.outline);
        reach.push(Disk::new(d.c.x, d.c.y, unit.circumradius * scale));
        radius.push(d.r);
    }
    let grain = |i: usize| -> &Grain {
        if i < nb {
            &walls[i]
        } else {
            &packing.grains[i - nb]
        }
    };
    let r_max = reach.iter().fold(0.0f64, |m, d| m.max(d.r));
    let near = ByRadius::new(&reach, 0..reach.len());
    let periodic = domain.is_periodic();
    let mut touched = vec![false; reach.len()];
    let mut ends = vec![0u32; packing.disks.len()];
    let (mut max_overlap, mut contacts) = (0.0f64, 0usize);
    for i in nb..reach.len() {
        if i % POLL_EVERY == 0 {
            cancel.check()?;
        }
        let (d, ti) = (reach[i], grain(i).turned());
        let slack = CONTACT_REL * (radius[i] + r_max);
        for v in images_near(domain, d.c, d.r + r_max + slack) {
            let zero = v == Vector2::zeros();
            near.visit(d.c - v, d.r + slack, |j| {
                if j > i || (j == i && (zero || (v.y, v.x) < (0.0, 0.0))) {
                    return;
                }
                let o = reach[j];
                let at = if zero { o.c } else { o.c + v };
                let sum = radius[i] + radius[j];
                if (d.c - at).norm() > d.r + o.r + CONTACT_REL * sum {
                    return;
                }
                let tj = grain(j).turned();
                let sep = grain_separation(&ti, d.c, &tj, at, 0.1 * CONTACT_REL * sum);
                let overlap = if sep.upper > 0.0 {
                    -sep.upper / sum
                } else {
                    depth(&ti, &tj, at - d.c) / sum
                };
                max_overlap = max_overlap.max(overlap);
                if sep.upper <= CONTACT_REL * sum {
                    touched[i] = true;
                    touched[j] = true;
                    if j >= nb {
                        contacts += 1;
                        ends[i - nb] += 1;
                        ends[j - nb] += 1;
                    }
                }
            });
        }
    }
    let min_wall_clearance = if periodic {
        f64::NAN
    } else {
        wall_clearances(packing, &reach[nb..], &mut touched[nb..], cancel)?
    };
    Ok(GrainContacts {
        max_overlap,
        contacts,
        isolated: touched[nb..].iter().filter(|&&t| !t).count(),
        ends,
        min_wall_clearance,
    })
}

/// A circle of radius `r` as an outline (a wall disk).
fn circle(r: f64) -> Outline {
    Outline::Superellipse {
        a: r,
        b: r,
        alpha: 2.0,
        beta: 2.0,
    }
}

/// Depth of the overlap of two grains whose centres are `d` apart (b's
/// less a's): the least over directions u of h_K(u) − u·d, K = A ⊕ (−B),
/// over [`DIRECTIONS`] directions refined by golden sections about the
/// least (an upper bound of the depth where it is not exact).
fn depth(a: &Turned, b: &Turned, d: Vector2<f64>) -> f64 {
    let f = |t: f64| {
        let u = Vector2::new(t.cos(), t.sin());
        a.support_both(u).0 + b.support_both(-u).0 - u.dot(&d)
    };
    let step = std::f64::consts::TAU / DIRECTIONS as f64;
    let (k, _) =
        (0..DIRECTIONS)
            .map(|k| (k, f(k as f64 * step)))
            .fold(
                (0, f64::INFINITY),
                |best, x| if x.1 < best.1 { x } else { best },
            );
    let best = f(k as f64 * step);
    golden(f, k as f64 * step, step, 1.0).min(best).max(0.0)
}

/// The least (`sign` 1) or greatest (`sign` −1) of `f` about `t` within
/// `step` either side, by golden sections.
fn golden(f: impl Fn(f64) -> f64, t: f64, step: f64, sign: f64) -> f64 {
    let (mut lo, mut hi) = (t - step, t + step);
    let g = 0.618_033_988_749_895;
    for _ in 0..60 {
        let m1 = hi - g * (hi - lo);
        let m2 = lo + g * (hi - lo);
        if sign * f(m1) < sign * f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi))
}

/// The smallest wall clearance of the particles (`bounds` their bounding
/// circles), marking in `touched` those within the contact gap of a wall.
///
/// # Performance
/// A particle whose bounding circle clears the walls by more than the best
/// clearance so far and the contact gap is not measured further: only
/// those near a wall cost a distance per wall.
fn wall_clearances(
    packing: &Packing,
    bounds: &[Disk],
    touched: &mut [bool],
    cancel: &Cancel,
) -> Result<f64, Cancelled> {
    let domain = &packing.domain;
    let lower: Vec<f64> = bounds
        .iter()
        .map(|b| domain.signed_distance(b.c) - b.r)
        .collect();
    let mut order: Vec<usize> = (0..bounds.len()).collect();
    order.sort_unstable_by(|&i, &j| lower[i].total_cmp(&lower[j]));
    let widest = CONTACT_REL * packing.disks.iter().fold(0.0f64, |m, d| m.max(d.r));
    let mut best = f64::INFINITY;
    for (k, &i) in order.iter().enumerate() {
        if k % POLL_EVERY == 0 {
            cancel.check()?;
        }
        let gap = CONTACT_REL * packing.disks[i].r;
        if lower[i] > best && lower[i] > widest {
            // Every later one clears by more still.
            break;
        }
        let c = clearance(packing, &packing.grains[i], packing.disks[i].c);
        best = best.min(c);
        touched[i] |= c <= gap;
    }
    Ok(if bounds.is_empty() { 0.0 } else { best })
}

/// Distance from the grain at `c` to the nearest wall (mm): the GJK
/// distance to each straight wall, the circle's radius less the grain's
/// farthest reach from its centre for a circular wall; negative (how far
/// past the wall's line, or past the circle) when it crosses a wall, and
/// its centre's distance less its bounding radius when its centre lies
/// outside.
fn clearance(packing: &Packing, grain: &Grain, c: Point) -> f64 {
    let domain = &packing.domain;
    let t = grain.turned();
    let size = grain.outline.circumradius();
    if domain.signed_distance(c) < 0.0 {
        return domain.signed_distance(c) - size;
    }
    let mut best = f64::INFINITY;
    for wall in domain.walls() {
        let gap = match *wall {
            Wall::Segment { a, b } => {
                let m = nalgebra::center(&a, &b);
                let (ha, hb) = (a - m, b - m);
                let sep = separation(c - m, 1e-12 * size, |u| {
                    let (hs, ps) = if ha.dot(&u) >= hb.dot(&u) {
                        (ha.dot(&u), ha)
                    } else {
                        (hb.dot(&u), hb)
                    };
                    let (hg, pg) = t.support_both(-u);
                    (hs + hg, ps - pg)
                });
                if sep.upper > 0.0 {
                    sep.upper
                } else {
                    // Past the wall's line by the grain's reach beyond it.
                    let e = b - a;
                    let n = Vector2::new(-e.y, e.x).normalize();
                    n.dot(&(c - a)) - t.support_both(-n).0
                }
            }
            Wall::Circle { center, radius } => {
                let d = c - center;
                let f = |s: f64| {
                    let u = Vector2::new(s.cos(), s.sin());
                    t.support_both(u).0 + u.dot(&d)
                };
                let step = std::f64::consts::TAU / DIRECTIONS as f64;
                let (k, far) = (0..DIRECTIONS)
                    .map(|k| (k, f(k as f64 * step)))
                    .fold((0, f64::NEG_INFINITY), |b, x| if x.1 > b.1 { x } else { b });
                radius - far.max(golden(f, k as f64 * step, step, -1.0))
            }
        };
        best = best.min(gap);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::measure;
    use crate::{Domain, Scene, ShapeSpec, SizeMeasure};

    /// A scene of `uniform = [1, 3]` sizes in a `w` × `h` rectangle, its
    /// particles ellipses of aspect 2 sized by `size`.
    fn scene(w: f64, h: f64, size: SizeMeasure) -> Scene {
        let text = format!(
            "[domain]\nshape = \"rectangle\"\nwidth = {w}\nheight = {h}\n[grading]\nuniform = [1.0, 3.0]\n"
        );
        let scene = crate::config::parse_with(&text, "t", Default::default())
            .unwrap()
            .scene;
        let mut shape = ShapeSpec::ellipses(2.0);
        shape.size = size;
        scene.with_shape(shape)
    }

    /// An `nx` × `ny` lattice of ellipses a = 2, b = 1 along x, spaced
    /// `k` times their axes (k = 1: each touches its four neighbours),
    /// in a rectangle `margin` wider than the lattice on each side.
    fn lattice(nx: usize, ny: usize, k: f64, margin: f64) -> Packing {
        let (w, h) = (4.0 * k * nx as f64, 2.0 * k * ny as f64);
        let domain = Domain::rectangle(w + 2.0 * margin, h + 2.0 * margin).unwrap();
        let (lo, _) = domain.bounds();
        let mut centres = Vec::new();
        let mut grains = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                centres.push(Point::new(
                    lo.x + margin + 4.0 * k * (i as f64 + 0.5),
                    lo.y + margin + 2.0 * k * (j as f64 + 0.5),
                ));
                grains.push(Grain::new(
                    Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap(),
                    0.0,
                ));
            }
        }
        Packing::of_grains(domain, grains, &centres)
    }

    #[test]
    fn a_lattice_of_touching_ellipses_counts_its_contacts() {
        let s = scene(40.0, 20.0, SizeMeasure::Sieve);
        // 5 × 5, each touching its row and column neighbours, the outer
        // ones the walls: 2·(4·5 + 5·4) contact ends over 25.
        let touching = measure(&lattice(5, 5, 1.0, 0.0), &s);
        assert!(
            (touching.coordination - 80.0 / 25.0).abs() < 1e-12,
            "{touching:?}"
        );
        assert_eq!(touching.isolated, 0);
        assert!(touching.max_overlap <= crate::OVERLAP_REL, "{touching:?}");
        assert!(touching.min_wall_clearance.abs() < 1e-9, "{touching:?}");
        // The area-equivalent disks (radius √2 for centres 2 apart) would
        // overlap by 29 %: the outlines are what is measured.
        let shapes = touching.shapes.unwrap();
        assert_eq!(shapes.particles, 25);
        assert!((shapes.fabric.anisotropy - 1.0).abs() < 1e-12);
        assert!((shapes.aspect.mean - 2.0).abs() < 1e-9);
        // 1 % apart, away from the walls: no contact, every one floats.
        let apart = measure(&lattice(5, 5, 1.01, 0.5), &s);
        assert_eq!(apart.coordination, 0.0);
        assert_eq!(apart.isolated, 25);
        // The first row's flanks: 0.5 + 1.01 − 1 from the bottom wall.
        assert!((apart.min_wall_clearance - 0.51).abs() < 1e-9, "{apart:?}");
        assert_eq!(apart.max_overlap, 0.0);
        // Pushed 10 % into each other: overlaps found, by their depth.
        let pressed = measure(&lattice(5, 5, 0.9, 0.0), &s);
        // Along x the tips overlap by 0.4 mm, along y the flanks by 0.2 mm;
        // over the radii sum 2√2.
        let expected = 0.4 / (2.0 * 2f64.sqrt());
        assert!(
            (pressed.max_overlap - expected).abs() < 1e-6,
            "{} vs {expected}",
            pressed.max_overlap
        );
    }

    #[test]
    fn grading_fidelity_is_measured_on_the_size_the_grading_gives() {
        let s = scene(400.0, 400.0, SizeMeasure::Sieve);
        // Least widths at the grading's quantiles, well apart.
        let n = 200;
        let widths: Vec<f64> = (0..n)
            .map(|k| s.grading.sample((k as f64 + 0.5) / n as f64))
            .collect();
        let grains: Vec<Grain> = widths
            .iter()
            .map(|&w| Grain::new(Outline::superellipse(w, w / 2.0, 2.0, 2.0).unwrap(), 0.3))
            .collect();
        let centres: Vec<Point> = (0..n)
            .map(|k| {
                Point::new(
                    -180.0 + 20.0 * (k % 19) as f64,
                    -180.0 + 20.0 * (k / 19) as f64,
                )
            })
            .collect();
        let p = Packing::of_grains(s.domain.clone(), grains, &centres);
        let sieve = measure(&p, &s);
        assert!(sieve.psd_ks <= 0.5 / n as f64 + 1e-9, "{}", sieve.psd_ks);
        assert_eq!(sieve.coordination, 0.0);
        // The same particles against a grading of area-equivalent sizes
        // (√2 times larger): far off.
        let eq = measure(&p, &scene(400.0, 400.0, SizeMeasure::Equivalent));
        assert!(eq.psd_ks > 0.3, "{}", eq.psd_ks);
        // One function gives the sizes, the spec's measure.
        let sizes = crate::metrics::grading_sizes(&p, &s);
        let spec = s.shape.as_ref().unwrap();
        for (size, g) in sizes.iter().zip(&p.grains) {
            assert!((size - spec.measure(&g.outline)).abs() < 1e-12 * size);
        }
    }
}
