//! Packing metrics: porosity, grading fidelity, overlaps, clearance,
//! contacts, uniformity, and the porosity map.
//!
//! Every porosity in the crate is [`porosity`] of a solid area (a
//! [`solid_area`] when whole disks count), and every coordination number
//! is a [`coordination`] of contacts found by one neighbour visit.
//!
//! A periodic cell ([`crate::Domain::periodic_rectangle`]) is measured with
//! the images of its disks: contacts and overlaps across the edges count,
//! windows and holes near an edge see the disks across it, and each disk's
//! area counts once.

mod bands;
mod contacts;
mod grading;
mod grains;
pub mod meshless;
pub(crate) mod near;
mod porosity_map;
mod shapes;
mod voids;

pub use bands::{Zone, zones};
pub use contacts::coordination;
pub(crate) use contacts::visit_near;
pub use grading::{Blend, curve_diameters, grading_sizes, psd_ks, psd_ks_blend, psd_ks_by_curve};
pub use meshless::H6Stats;
pub use porosity_map::{PorosityMap, porosity_map};
pub use shapes::{
    AskedFamily, AskedOrientation, Fabric, Figures, ShapeAsked, ShapeStats, enclosing_radius,
    inscribed_radius, long_axis, roundness, shape_series, shape_stats, sphericity,
};

use std::borrow::Cow;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
use crate::geometry::predicates::{CONTACT_REL, area_disk_box, overlap_disk_disk};
use nalgebra::Vector2;

use crate::geometry::{Disk, Point};
use crate::packer::Packing;
use near::{ByRadius, SharedIndex};

/// Disks or samples between two polls of the cancel token.
const POLL_EVERY: usize = 1024;

/// Side of the local-porosity windows, in largest diameters.
const WINDOW_DIAMETERS: f64 = 5.0;

/// Least share of a window's area inside the domain for it to count in
/// `local_porosity_std` (a quarter: a slot a little over a diameter wide
/// is measured; a corner cut thin by a wall is not).
const MIN_WINDOW_INSIDE: f64 = 0.25;

/// What a packing achieved.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub struct Metrics {
    /// Number of packed disks (wall disks excluded).
    pub particles: usize,
    /// Domain area (mm²).
    pub domain_area: f64,
    /// Total area of the packed disks (mm²).
    pub solid_area: f64,
    /// 1 − solid_area / domain_area.
    pub porosity: f64,
    /// Kolmogorov–Smirnov distance of the packed sizes to the grading, in its
    /// basis (size-graded: the larger of each material's to its own curve).
    pub psd_ks: f64,
    /// Largest overlap between two disks (packed or wall), relative to the sum of their radii; 0 if none.
    pub max_overlap: f64,
    /// Smallest distance from a disk's edge to the domain boundary (mm);
    /// negative means outside. NaN in a periodic cell, which has no walls.
    pub min_wall_clearance: f64,
    /// Mean number of disk–disk contacts per packed disk (gap within 1e-6
    /// of the radii sum), contacts across a periodic cell's edges included.
    pub coordination: f64,
    /// Packed disks that float: touching no other disk (packed or wall disk)
    /// and no wall, within the contact gap.
    pub isolated: usize,
    /// Standard deviation of local porosity over square windows of about
    /// 5·d_max that lie wholly inside the domain (in a periodic cell, with
    /// the images of the disks across its edges), or, where fewer than two
    /// fit, over windows clipped to the domain (`local_windows_clipped`);
    /// NaN when even those are fewer than two. Particles that are not
    /// disks count their area in a window within 3·10⁻⁵ of the area of
    /// each one its edges cut (`voids.rs`), d_max their largest
    /// area-equivalent diameter.
    pub local_porosity_std: f64,
    /// Number of local-porosity windows.
    pub local_windows: usize,
    /// Whether the windows were clipped to the domain (fewer than two fit
    /// wholly inside): they then measure the walls' effect too.
    pub local_windows_clipped: bool,
    /// Diameter of the largest empty circle left in the domain (mm), found on a
    /// grid of spacing d_min/2 (coarser where that would give more than 256
    /// points per packed disk) and refined locally. Among particles that
    /// are not disks, a certified empty circle: its radius is the least
    /// lower bound of the GJK distances from its centre.
    pub largest_hole: f64,
    /// The distribution of h6 / d: each particle's meshless support size
    /// (the distance from its centre to its 6th nearest neighbour's, the
    /// minimum image in a periodic cell) over its own diameter
    /// (area-equivalent for particles that are not disks), with the h5 and
    /// h7 means ([`meshless`]); `None` with fewer than 7 particles.
    pub h6_over_d: Option<H6Stats>,
    /// The particles' shapes, when they are not disks ([`Packing::grains`]);
    /// `None` for disks. Not in this struct's own JSON: `summary.json`
    /// records it as its `particle_shape` object.
    #[serde(skip)]
    pub shapes: Option<ShapeStats>,
}

/// Porosity of a region of area `area` (mm²) holding `solid` mm² of disks:
/// 1 − solid / area.
pub fn porosity(solid: f64, area: f64) -> f64 {
    1.0 - solid / area
}

/// Total area of `disks` (mm²), summed in their order.
pub fn solid_area<'a>(disks: impl IntoIterator<Item = &'a Disk>) -> f64 {
    disks.into_iter().map(Disk::area).sum()
}

/// Measure a packing of `scene` against the scene's grading.
///
/// # Performance
/// The disks bucketed by size class serve every neighbour query: O(n)
/// overall in a dense packing, whatever the grading's width.
pub fn measure(packing: &Packing, scene: &Scene) -> Metrics {
    match measure_cancellable(packing, scene, &Cancel::new()) {
        Ok(metrics) => metrics,
        Err(_) => unreachable!("a new token is never raised"),
    }
}

/// [`measure`], stopped by `cancel`: its loops poll the token every
/// [`POLL_EVERY`] disks or samples, so a cancel is honoured within
/// milliseconds however large the packing.
///
/// # Errors
/// [`Cancelled`] once `cancel` is raised or its deadline passes.
pub fn measure_cancellable(
    packing: &Packing,
    scene: &Scene,
    cancel: &Cancel,
) -> Result<Metrics, Cancelled> {
    measure_sharing(packing, scene, None, cancel)
}

/// [`measure_cancellable`] with the disks' neighbour index taken from
/// `shared` when it is theirs (a packing without wall disks), and built
/// there for the check beside it if not yet.
///
/// # Errors
/// [`Cancelled`] once `cancel` is raised or its deadline passes.
pub(crate) fn measure_sharing(
    packing: &Packing,
    scene: &Scene,
    shared: Option<&SharedIndex<'_>>,
    cancel: &Cancel,
) -> Result<Metrics, Cancelled> {
    cancel.check()?;
    if !packing.grains.is_empty() {
        return measure_grains(packing, scene, cancel);
    }
    let disks = &packing.disks;
    let domain = &packing.domain;
    let domain_area = domain.area();
    let solid_area = solid_area(disks);
    let r_max = disks
        .iter()
        .chain(&packing.boundary)
        .fold(0.0f64, |m, d| m.max(d.r));

    // First, while the measure holds no index of its own: it sorts a list
    // of the diameters (a check beside it builds the shared index then).
    let psd_ks = psd_ks(packing, scene);

    // One index over wall disks then packed disks: the packed disks
    // themselves without wall disks, no copy of the packing.
    let all: Cow<'_, [Disk]> = if packing.boundary.is_empty() {
        Cow::Borrowed(disks)
    } else {
        Cow::Owned(packing.boundary.iter().chain(disks).copied().collect())
    };
    let nb = packing.boundary.len();

    // Neighbours by size class: a grid sized by the largest radius makes a
    // wide grading's fine disks visit cells full of fine disks.
    let own;
    let near = match shared.and_then(|s| s.of(&all)) {
        Some(near) => near,
        None => {
            own = ByRadius::new(&all, 0..all.len());
            &own
        }
    };
    let touched = Bits::new(all.len());
    let periodic = domain.is_periodic();
    // Fixed runs of the disks in cell order (neighbours in space near in
    // memory), combined in run order: the largest, smallest and counts
    // are the same whatever the threads.
    let parts = near
        .runs(CHUNK)
        .into_par_iter()
        .map(|run| {
            let mut part = (0.0f64, 0usize, f64::INFINITY);
            for (k, &i) in run.iter().enumerate() {
                let i = i as usize;
                if k % POLL_EVERY == 0 {
                    cancel.check()?;
                }
                if i < nb {
                    continue;
                }
                let d = all[i];
                if !periodic {
                    let clearance = domain.signed_distance(d.c) - d.r;
                    part.2 = part.2.min(clearance);
                    if clearance <= CONTACT_REL * d.r {
                        touched.set(i);
                    }
                }
                // Each packed pair once (j < i); wall disks against every
                // packed disk. In a periodic cell, every image of the disks
                // of lower index that reaches this one, and its own images
                // once per opposite pair.
                for v in images_near(domain, d.c, d.r + r_max) {
                    let zero = v == Vector2::zeros();
                    near.visit(d.c - v, d.r, |j| {
                        if j > i || (j == i && (zero || (v.y, v.x) < (0.0, 0.0))) {
                            return;
                        }
                        let o = all[j];
                        let at = if zero { o.c } else { o.c + v };
                        let overlap = overlap_disk_disk(d.c, d.r, at, o.r);
                        part.0 = part.0.max(overlap);
                        if overlap >= -CONTACT_REL {
                            touched.set(i);
                            touched.set(j);
                            part.1 += usize::from(j >= nb);
                        }
                    });
                }
            }
            Ok(part)
        })
        .collect::<Result<Vec<_>, Cancelled>>()?;
    let (max_overlap, contacts, mut min_wall_clearance) = parts.into_iter().fold(
        (0.0f64, 0usize, f64::INFINITY),
        |(o, c, w), (po, pc, pw)| (o.max(po), c + pc, w.min(pw)),
    );
    if periodic {
        min_wall_clearance = f64::NAN;
    }
    let n = disks.len();
    let isolated = (nb..all.len()).filter(|&i| !touched.get(i)).count();
    drop(touched);
    cancel.check()?;
    let (local_porosity_std, local_windows, local_windows_clipped) =
        local_porosity(packing, r_max, |boxes| {
            boxes
                .par_iter()
                .map(|&b| disks_in_box(domain, near, &all, nb, r_max, b))
                .collect()
        });
    let clear = DiskClearance {
        packing,
        near,
        all: &all,
        r_max,
        settler: (usize::MAX, Vector2::zeros()),
    };
    let largest_hole = largest_hole_of_disks(packing, clear, scene.d_min(), cancel)?;
    let h6_over_d = meshless::h6_stats_with(domain, &all, near, nb, cancel)?;
    Ok(Metrics {
        particles: n,
        domain_area,
        solid_area,
        porosity: porosity(solid_area, domain_area),
        psd_ks,
        max_overlap,
        min_wall_clearance: if n == 0 && !periodic {
            0.0
        } else {
            min_wall_clearance
        },
        // Each pair has two ends.
        coordination: coordination(2 * contacts, n),
        isolated,
        local_porosity_std,
        local_windows,
        local_windows_clipped,
        largest_hole,
        h6_over_d,
        shapes: None,
    })
}

/// [`measure_cancellable`] of a packing of grains: contacts, overlaps and
/// wall clearances between the outlines (`grains.rs`), the shape measures,
/// the grading's fidelity on the size the grading gives, and the local
/// porosity windows and largest hole with each particle's area in a window
/// and distance from a point (`voids.rs`). The windows are those of disks
/// of the particles' area-equivalent radii.
fn measure_grains(packing: &Packing, scene: &Scene, cancel: &Cancel) -> Result<Metrics, Cancelled> {
    let disks = &packing.disks;
    let domain_area = packing.domain.area();
    let solid_area = solid_area(disks);
    let mut memo = shapes::ShapeMemo::default();
    let psd_ks = grading::psd_ks_with(packing, scene, &mut memo);
    let c = grains::grain_contacts(packing, &mut memo, cancel)?;
    let r_max = disks
        .iter()
        .chain(&packing.boundary)
        .fold(0.0f64, |m, d| m.max(d.r));
    let mut areas = voids::GrainAreas::new(packing, &mut memo);
    let (local_porosity_std, local_windows, local_windows_clipped) =
        local_porosity(packing, r_max, |boxes| {
            boxes
                .iter()
                .map(|&[x0, x1, y0, y1]| areas.in_box(x0, x1, y0, y1))
                .collect()
        });
    cancel.check()?;
    let mut clear = voids::GrainClearance::new(packing, &mut memo);
    let largest_hole = largest_hole(packing, &mut clear, scene.d_min(), cancel)?;
    let stats = shapes::stats_for(&packing.grains, scene.shape.as_ref(), &mut memo);
    // The particles' centres and area-equivalent radii, indexed as disks.
    let near = ByRadius::new(disks, 0..disks.len());
    let h6_over_d = meshless::h6_stats_with(&packing.domain, disks, &near, 0, cancel)?;
    let n = disks.len();
    Ok(Metrics {
        particles: n,
        domain_area,
        solid_area,
        porosity: porosity(solid_area, domain_area),
        psd_ks,
        max_overlap: c.max_overlap,
        min_wall_clearance: c.min_wall_clearance,
        coordination: coordination(2 * c.contacts, n),
        isolated: c.isolated,
        local_porosity_std,
        local_windows,
        local_windows_clipped,
        largest_hole,
        h6_over_d,
        shapes: stats,
    })
}

/// What a part of a packing of grains ([`Packing::grains`], not empty)
/// measures, outline by outline as [`measure`] does: the solid area inside
/// each box `[x0, x1, y0, y1]` of `boxes` (`voids.rs`) and each packed
/// particle's contacts with other packed particles (`grains.rs`, the rule
/// of [`Metrics::coordination`]). A fracture window measures its core with these.
pub(crate) fn grain_parts(packing: &Packing, boxes: &[[f64; 4]]) -> (Vec<f64>, Vec<u32>) {
    let mut memo = shapes::ShapeMemo::default();
    // A token nobody else holds is never raised: no contacts is never the answer.
    let ends = grains::grain_contacts(packing, &mut memo, &Cancel::new())
        .map(|c| c.ends)
        .unwrap_or_default();
    (solid_in(packing, boxes, &mut memo), ends)
}

/// The solid area of a packing of grains inside each box `[x0, x1, y0, y1]`
/// of `boxes`, outline by outline (a large scene's search windows measure
/// their cores with it).
pub(crate) fn grain_solid(packing: &Packing, boxes: &[[f64; 4]]) -> Vec<f64> {
    solid_in(packing, boxes, &mut shapes::ShapeMemo::default())
}

/// [`grain_solid`] through `memo`.
fn solid_in(packing: &Packing, boxes: &[[f64; 4]], memo: &mut shapes::ShapeMemo) -> Vec<f64> {
    let mut areas = voids::GrainAreas::new(packing, memo);
    boxes
        .iter()
        .map(|&[x0, x1, y0, y1]| areas.in_box(x0, x1, y0, y1))
        .collect()
}

/// Standard deviation of porosity over square windows of side
/// [`WINDOW_DIAMETERS`] largest diameters (`r_max` the largest radius),
/// how many, and whether they were clipped: windows tiling the domain
/// wholly inside it, the interior's scatter, when at least two fit;
/// otherwise (a small circle, a slot narrower than a window) windows tiling
/// the bounds clipped to the domain, each its porosity over its exact area
/// inside, those with at least [`MIN_WINDOW_INSIDE`] of it inside counted,
/// so every domain is measured. `solids(boxes)` is the solid area inside
/// each box `[x0, x1, y0, y1]` of `boxes`, in their order.
fn local_porosity(
    packing: &Packing,
    r_max: f64,
    mut solids: impl FnMut(&[[f64; 4]]) -> Vec<f64>,
) -> (f64, usize, bool) {
    let w = WINDOW_DIAMETERS * 2.0 * r_max;
    if w <= 0.0 {
        return (f64::NAN, 0, false);
    }
    let inside = window_porosities(packing, w, false, &mut solids);
    let (values, clipped) = if inside.len() >= 2 {
        (inside, false)
    } else {
        (window_porosities(packing, w, true, &mut solids), true)
    };
    if values.len() < 2 {
        return (f64::NAN, values.len(), clipped);
    }
    (mean_sd(&values).1, values.len(), clipped)
}

/// The solid area of the packed disks of `all` (wall disks first, `nb` of
/// them, not solid) inside the box [x0, x1] × [y0, y1], in closed form
/// ([`area_disk_box`]), summed in the order `near` (an index of `all`)
/// visits them; `r_max` their largest radius. In a periodic cell, the
/// images of the disks too.
fn disks_in_box(
    domain: &crate::Domain,
    near: &ByRadius,
    all: &[Disk],
    nb: usize,
    r_max: f64,
    [x0, x1, y0, y1]: [f64; 4],
) -> f64 {
    let mut solid = 0.0;
    let (qlo, qhi) = (
        Point::new(x0 - r_max, y0 - r_max),
        Point::new(x1 + r_max, y1 + r_max),
    );
    // The images of the disks across a periodic cell's edges too.
    for v in domain.image_shifts(qlo, qhi) {
        let (lo, hi) = (Point::new(x0, y0) - v, Point::new(x1, y1) - v);
        near.visit_box(lo, hi, |j| {
            if j >= nb {
                let (d, c) = (all[j], image(all[j].c, v));
                // Most disks lie wholly in or wholly out of the window; one
                // inside is π r², which the closed form only comes near
                // (some 10⁻⁸ of it lost where the bounds round off its sides).
                solid += if c.x - d.r >= x0 && c.x + d.r <= x1 && c.y - d.r >= y0 && c.y + d.r <= y1
                {
                    std::f64::consts::PI * d.r * d.r
                } else {
                    area_disk_box(c, d.r, x0, x1, y0, y1)
                };
            }
        });
    }
    solid
}

/// Mean and sample standard deviation (n − 1) of `values` (the deviation
/// is 0 for one value; both are NaN for none).
pub fn mean_sd(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// The porosities of the windows of side `w` centred on the domain's
/// bounds: wholly inside it (`clipped` false), or covering the bounds and
/// clipped to the domain (`clipped` true; see [`local_porosity`]), the
/// windows' solid areas from `solids`, all at once.
fn window_porosities(
    packing: &Packing,
    w: f64,
    clipped: bool,
    solids: &mut impl FnMut(&[[f64; 4]]) -> Vec<f64>,
) -> Vec<f64> {
    let domain = &packing.domain;
    let (lo, hi) = domain.bounds();
    let count = |extent: f64| {
        let k = extent / w;
        (if clipped {
            k.ceil().max(1.0)
        } else {
            k.floor()
        }) as usize
    };
    let (nx, ny) = (count(hi.x - lo.x), count(hi.y - lo.y));
    let x_start = lo.x + 0.5 * ((hi.x - lo.x) - nx as f64 * w);
    let y_start = lo.y + 0.5 * ((hi.y - lo.y) - ny as f64 * w);
    let (mut boxes, mut areas) = (Vec::new(), Vec::new());
    for iy in 0..ny {
        for ix in 0..nx {
            let (x0, y0) = (x_start + ix as f64 * w, y_start + iy as f64 * w);
            let (x1, y1) = (x0 + w, y0 + w);
            let area = if clipped {
                let inside = domain.area_in_box(x0, x1, y0, y1);
                if inside < MIN_WINDOW_INSIDE * w * w {
                    continue;
                }
                inside
            } else {
                let corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)];
                let wholly = corners
                    .iter()
                    .all(|&(x, y)| domain.signed_distance(Point::new(x, y)) >= 0.0)
                    && !domain
                        .reflex_vertices()
                        .iter()
                        .any(|v| v.x > x0 && v.x < x1 && v.y > y0 && v.y < y1);
                if !wholly {
                    continue;
                }
                w * w
            };
            boxes.push([x0, x1, y0, y1]);
            areas.push(area);
        }
    }
    solids(&boxes)
        .into_iter()
        .zip(areas)
        .map(|(solid, area)| porosity(solid, area))
        .collect()
}

/// Clearance at `p`: distance to the nearest disk edge or wall (negative
/// inside a disk), exact when above `floor`; at or below `floor` the search
/// stops at the first disk or wall that proves it and returns that distance.
///
/// # Performance
/// The largest-hole search only keeps a sample that beats the best so far,
/// so it passes that best as `floor`: most samples lie nearer than it to
/// some disk and are settled by one or two candidates instead of every disk
/// in reach (a wide grading's thousands of fine disks). The disk that
/// settles a sample is left in `settler`, for the caller to try first at
/// the next sample.
fn clearance_above(
    packing: &Packing,
    near: &ByRadius,
    all: &[Disk],
    r_max: f64,
    p: Point,
    floor: f64,
    settler: &mut (usize, Vector2<f64>),
) -> f64 {
    search_clearance(
        &packing.domain,
        near,
        r_max,
        p,
        floor,
        settler,
        |j, v, _| {
            #[cfg(test)]
            tests::CANDIDATES.with(|c| c.set(c.get() + 1));
            let d = all[j];
            let at = if v == Vector2::zeros() { d.c } else { d.c + v };
            let found = (p - at).norm() - d.r;
            (found, found <= floor)
        },
    )
}

/// The search both clearances share: the wall's distance, then the
/// particles indexed in `near` (bounding radii at most `r_max`) in boxes
/// about `p` doubling from the finest class's size until the nearest one
/// found is within the box. `probe(j, v, bar)` gives particle `j`'s image
/// shifted by `v`: a distance (none below `bar` found so far need be exact
/// above it) and whether it settles the sample (at or below `floor`); the
/// one that settles is left in `settler`.
pub(super) fn search_clearance(
    domain: &crate::Domain,
    near: &ByRadius,
    r_max: f64,
    p: Point,
    floor: f64,
    settler: &mut (usize, Vector2<f64>),
    mut probe: impl FnMut(usize, Vector2<f64>, f64) -> (f64, bool),
) -> f64 {
    // A periodic cell has no wall.
    let wall = if domain.is_periodic() {
        f64::INFINITY
    } else {
        domain.signed_distance(p)
    };
    if wall <= floor {
        return wall;
    }
    let mut best = wall;
    // Every centre lies within the domain's bounds: a box of half side
    // `reach` around a point of the domain holds them all.
    let (lo, hi) = domain.bounds();
    let reach = (hi - lo).norm() + r_max;
    // The finest class's size settles most samples of a dense packing in
    // one query; each class is searched as far as its own largest radius asks.
    let mut half = near.finest_r_max().max(reach / 1024.0);
    loop {
        let mut found = f64::INFINITY;
        let mut settled = ControlFlow::Continue(());
        for v in images_near(domain, p, half + r_max) {
            settled = near.try_visit(p - v, half, |j| {
                let (d, settles) = probe(j, v, found.min(best));
                found = found.min(d);
                if settles {
                    *settler = (j, v);
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            });
            if settled.is_break() {
                break;
            }
        }
        best = best.min(found);
        // A particle not visited lies farther than `half` plus its class's
        // largest bounding radius from `p` along an axis: it is beyond
        // `half`.
        if settled.is_break() || best <= half || half > reach {
            return best;
        }
        half *= 2.0;
    }
}

/// The lattice shifts whose images of the disks may reach within `reach`
/// of `p` along each axis ([`crate::Domain::image_shifts`]): the zero shift
/// alone in a domain with walls.
fn images_near(domain: &crate::Domain, p: Point, reach: f64) -> crate::geometry::ImageShifts {
    domain.image_shifts(
        Point::new(p.x - reach, p.y - reach),
        Point::new(p.x + reach, p.y + reach),
    )
}

/// `c` shifted by `v`; `c` itself for the zero shift.
fn image(c: Point, v: Vector2<f64>) -> Point {
    if v == Vector2::zeros() { c } else { c + v }
}

/// Grid points per packed disk the largest-hole search samples at most.
const HOLE_SAMPLES_PER_DISK: f64 = 256.0;

/// Spacing of the largest-hole search's grid over bounds of size `extent`
/// holding `disks` packed disks.
///
/// # Performance
/// d_min/2, but never finer than 1/4096 of the bounds nor than
/// [`HOLE_SAMPLES_PER_DISK`] points per packed disk: a wide grading (d_min
/// tiny beside the domain) must not make a few hundred disks cost 16
/// million clearance queries. The shipped configs sample at most about 150
/// points per disk, so the bound leaves them unchanged; at 256 samples per
/// disk a hole of the mean disk's size still spans about 16 grid steps
/// before the local refinement.
fn hole_step(extent: nalgebra::Vector2<f64>, disks: usize, d_min: f64) -> f64 {
    let per_disk = (extent.x * extent.y / (HOLE_SAMPLES_PER_DISK * disks.max(1) as f64)).sqrt();
    (d_min / 2.0)
        .max(extent.x.max(extent.y) / 4096.0)
        .max(per_disk)
}

/// One row in this many of the largest-hole grid gives the search its
/// first clearance to beat.
const HOLE_SEED_STRIDE: usize = if cfg!(test) { 3 } else { 32 };

/// Sample rows of the largest-hole grid one task scans.
const HOLE_STRIP_ROWS: usize = 8;

/// Packed disks one task of the contact loop (or the hole search's
/// covering) takes; a few in tests, so that small packings are split.
const CHUNK: usize = if cfg!(test) { 64 } else { 4096 };

/// One bit per item, set from any thread: setting is an OR, so the bits
/// are the same whatever the order of the threads.
struct Bits(Vec<AtomicU64>);

impl Bits {
    /// `n` bits, all clear: an eighth of a byte each.
    fn new(n: usize) -> Self {
        Bits((0..n.div_ceil(64)).map(|_| AtomicU64::new(0)).collect())
    }

    /// Set bit `i`.
    fn set(&self, i: usize) {
        self.0[i / 64].fetch_or(1 << (i % 64), Ordering::Relaxed);
    }

    /// Whether bit `i` is set (false beyond the bits).
    fn get(&self, i: usize) -> bool {
        self.0
            .get(i / 64)
            .is_some_and(|w| w.load(Ordering::Relaxed) & (1 << (i % 64)) != 0)
    }
}

/// The best exact clearance at least 0 that any strip of the hole search
/// has found so far: only a bound that lets the strips skip samples that
/// cannot win, never their result.
#[derive(Default)]
struct Found(AtomicU64);

impl Found {
    /// The best so far, if any (the bits of a non-negative value order as
    /// the value; 0 stands for none).
    fn get(&self) -> Option<f64> {
        match self.0.load(Ordering::Relaxed) {
            0 => None,
            bits => Some(f64::from_bits(bits - 1)),
        }
    }

    /// Offer the exact clearance `c`, at least 0, of some sample.
    fn offer(&self, c: f64) {
        self.0.fetch_max(c.to_bits() + 1, Ordering::Relaxed);
    }
}

/// The largest-hole search's grid of samples: `nx + 1` by `ny + 1` from
/// `lo`, `step` apart, row by row.
struct Samples<'a> {
    packing: &'a Packing,
    lo: Point,
    step: f64,
    nx: usize,
    ny: usize,
    /// Which samples lie nearer than the cover's gap to a disk (none
    /// known: no bits).
    inside: Bits,
}

impl<'a> Samples<'a> {
    /// The grid over `packing`'s bounds ([`hole_step`]), none known to be
    /// inside a disk; `None` when the step is not a positive number.
    fn new(packing: &'a Packing, d_min: f64) -> Option<Self> {
        let (lo, hi) = packing.domain.bounds();
        let step = hole_step(hi - lo, packing.disks.len(), d_min);
        if step <= 0.0 || !step.is_finite() {
            return None;
        }
        Some(Samples {
            packing,
            lo,
            step,
            nx: ((hi.x - lo.x) / step).ceil() as usize,
            ny: ((hi.y - lo.y) / step).ceil() as usize,
            inside: Bits::new(0),
        })
    }

    /// Mark the samples nearer than `gap` (at least 0) to a disk of the
    /// packing, whose clearance is then below `gap` (disks only: a sample
    /// inside an area-equivalent disk may lie outside the particle), in
    /// one parallel pass over the disks; at most about 4097² samples
    /// ([`hole_step`]'s floor), a bit each.
    fn cover(&mut self, gap: f64, cancel: &Cancel) -> Result<(), Cancelled> {
        let (lo, step, nx, ny) = (self.lo, self.step, self.nx, self.ny);
        let inside = Bits::new((nx + 1) * (ny + 1));
        let index = |v: f64, n: usize| (v.max(0.0) as usize).min(n);
        let disks = &self.packing.disks;
        disks.par_chunks(CHUNK).try_for_each(|chunk| {
            cancel.check()?;
            for d in chunk {
                let reach = d.r + gap;
                let (x0, x1) = ((d.c.x - reach - lo.x) / step, (d.c.x + reach - lo.x) / step);
                let (y0, y1) = ((d.c.y - reach - lo.y) / step, (d.c.y + reach - lo.y) / step);
                if x1 < 0.0 || y1 < 0.0 {
                    continue;
                }
                for iy in index(y0.ceil(), ny)..=index(y1.floor(), ny) {
                    for ix in index(x0.ceil(), nx)..=index(x1.floor(), nx) {
                        let p = Point::new(lo.x + ix as f64 * step, lo.y + iy as f64 * step);
                        // The clearance's own expression: at most this.
                        if (p - d.c).norm() - d.r < gap {
                            inside.set(iy * (nx + 1) + ix);
                        }
                    }
                }
            }
            Ok(())
        })?;
        self.inside = inside;
        Ok(())
    }

    /// The sample of rows `rows` with the largest clearance (the first in
    /// row order of equals) and that clearance, exact when it exceeds
    /// what `found` held at any time; otherwise at most that, and
    /// `(-∞, lo)` when every sample was skipped.
    fn scan(
        &self,
        clear: &mut impl Clearance,
        rows: std::ops::Range<usize>,
        found: &Found,
        cancel: &Cancel,
    ) -> Result<(f64, Point), Cancelled> {
        let periodic = self.packing.domain.is_periodic();
        let mut best = (f64::NEG_INFINITY, self.lo);
        for iy in rows {
            for ix in 0..=self.nx {
                if ix % POLL_EVERY == 0 {
                    cancel.check()?;
                }
                // No sample at or below `floor` can win: this strip's best,
                // or just below the best any strip has found (a sample
                // equal to that may still come first in row order).
                let known = found.get();
                let floor = known.map_or(best.0, |g| best.0.max(g.next_down()));
                // A covered sample's clearance is below the cover's gap
                // (0, or the seed that `found` then holds): once a sample
                // has a clearance of that or more, it cannot win.
                if (best.0 >= 0.0 || known.is_some()) && self.inside.get(iy * (self.nx + 1) + ix) {
                    continue;
                }
                let p = Point::new(
                    self.lo.x + ix as f64 * self.step,
                    self.lo.y + iy as f64 * self.step,
                );
                // Neighbouring samples are mostly settled by the same disk:
                // trying it first skips the grid query (a skipped sample is
                // no better than `floor`).
                if clear.settled_by_last(p, floor) {
                    continue;
                }
                if !periodic && self.packing.domain.signed_distance(p) <= 0.0 {
                    continue;
                }
                let c = clear.above(p, floor);
                if c > best.0 {
                    best = (c, p);
                    if c > floor && c >= 0.0 {
                        found.offer(c);
                    }
                }
            }
        }
        Ok(best)
    }
}

/// What the largest-hole search asks of the particles at a point.
trait Clearance {
    /// Whether the particle that settled the last sample shows, at little
    /// cost, that `p` is no farther than `best` from it.
    fn settled_by_last(&self, p: Point, best: f64) -> bool;

    /// The clearance at `p`, exact (for disks) or a certified lower bound
    /// of it (for other particles) when above `floor`; at or below `floor`,
    /// some value at or below `floor`.
    fn above(&mut self, p: Point, floor: f64) -> f64;
}

/// The clearance among disks ([`clearance_above`]).
#[derive(Clone)]
struct DiskClearance<'a> {
    packing: &'a Packing,
    near: &'a ByRadius,
    all: &'a [Disk],
    r_max: f64,
    /// The disk (and image shift) that settled the last sample.
    settler: (usize, Vector2<f64>),
}

impl Clearance for DiskClearance<'_> {
    fn settled_by_last(&self, p: Point, best: f64) -> bool {
        self.all
            .get(self.settler.0)
            .is_some_and(|d| (p - image(d.c, self.settler.1)).norm() - d.r <= best)
    }

    fn above(&mut self, p: Point, floor: f64) -> f64 {
        clearance_above(
            self.packing,
            self.near,
            self.all,
            self.r_max,
            p,
            floor,
            &mut self.settler,
        )
    }
}

/// Diameter of the largest empty circle among particles: grid search,
/// then local refinement; serial.
fn largest_hole(
    packing: &Packing,
    clear: &mut impl Clearance,
    d_min: f64,
    cancel: &Cancel,
) -> Result<f64, Cancelled> {
    let Some(samples) = Samples::new(packing, d_min) else {
        return Ok(0.0);
    };
    let best = samples.scan(clear, 0..samples.ny + 1, &Found::default(), cancel)?;
    Ok(refine(best, clear, samples.step, d_min))
}

/// [`largest_hole`] among disks, the samples nearer to a disk than a
/// first clearance found on a few rows skipped and the rows scanned in
/// strips of [`HOLE_STRIP_ROWS`] in parallel: the strips' best samples are combined in row order (the first of equals),
/// so the hole is the serial scan's, bit for bit, whatever the threads.
fn largest_hole_of_disks(
    packing: &Packing,
    mut clear: DiskClearance<'_>,
    d_min: f64,
    cancel: &Cancel,
) -> Result<f64, Cancelled> {
    let Some(mut samples) = Samples::new(packing, d_min) else {
        return Ok(0.0);
    };
    let rows = samples.ny + 1;
    // A first exact clearance from every HOLE_SEED_STRIDE-th row: no
    // sample nearer than it to a disk can win, so the cover marks those
    // too and the scan skips them without a query.
    let seeding = Found::default();
    // The middle row among them: the first and last lie on a wall.
    let seeds = ((rows / 2) % HOLE_SEED_STRIDE..rows)
        .into_par_iter()
        .step_by(HOLE_SEED_STRIDE)
        .map(|iy| samples.scan(&mut clear.clone(), iy..iy + 1, &seeding, cancel))
        .collect::<Result<Vec<_>, Cancelled>>()?;
    // The largest of the rows' bests is the exact clearance of some
    // sample: the hole is at least that (see `Samples::scan`).
    let seed = seeds.iter().fold(f64::NEG_INFINITY, |m, s| m.max(s.0));
    let found = Found::default();
    if seed >= 0.0 {
        found.offer(seed);
    }
    samples.cover(seed.max(0.0), cancel)?;
    let strips = (0..rows.div_ceil(HOLE_STRIP_ROWS))
        .into_par_iter()
        .map(|k| {
            let strip = k * HOLE_STRIP_ROWS..((k + 1) * HOLE_STRIP_ROWS).min(rows);
            samples.scan(&mut clear.clone(), strip, &found, cancel)
        })
        .collect::<Result<Vec<_>, Cancelled>>()?;
    let best = strips
        .into_iter()
        .fold((f64::NEG_INFINITY, samples.lo), |best, strip| {
            if strip.0 > best.0 { strip } else { best }
        });
    Ok(refine(best, &mut clear, samples.step, d_min))
}

/// The largest-hole diameter from the best grid sample `best` (clearance,
/// point; `step` the grid's spacing): a pattern search about it down to
/// `d_min`·10⁻⁴; 0 when no sample has a positive clearance.
fn refine(best: (f64, Point), clear: &mut impl Clearance, step: f64, d_min: f64) -> f64 {
    if best.0 <= 0.0 {
        return 0.0;
    }
    let (mut value, mut p) = best;
    let mut h = step / 2.0;
    while h > d_min * 1e-4 {
        let mut moved = false;
        for (dx, dy) in [
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 1.0),
            (0.0, -1.0),
            (1.0, 1.0),
            (-1.0, -1.0),
            (1.0, -1.0),
            (-1.0, 1.0),
        ] {
            let q = Point::new(p.x + dx * h, p.y + dy * h);
            let c = clear.above(q, value);
            if c > value {
                value = c;
                p = q;
                moved = true;
            }
        }
        if !moved {
            h /= 2.0;
        }
    }
    2.0 * value
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use super::*;

    thread_local! {
        /// Disks the clearance queries of this thread visited.
        pub(super) static CANDIDATES: Cell<u64> = const { Cell::new(0) };
    }

    #[test]
    fn hole_search_settles_most_samples_with_one_disk() {
        // A wide grading (d from 0.1 µm to 3 mm, found by fuzzing): every
        // sample used to visit every disk within 2 r_max, 0.87 s for a
        // packing made in a few ms. A sample no better than the best so far
        // now stops at the first disk proving it, and the disk that settled
        // the previous sample is tried first; the hole found is the same.
        let text = "[domain]\nshape = \"rectangle\"\nwidth = 40\nheight = 20\n\
                    [grading]\ntable = [[0.0001, 0], [0.001, 0.0001], [3, 100]]\n";
        // Forced: its upper bound (area / smallest disk area) is 10¹¹ disks.
        let force = crate::config::ParseOptions { force: true };
        let scene = crate::config::parse_with(text, "t", force).unwrap().scene;
        let packing = crate::pack(&scene).unwrap();
        // On a pool of one thread: the visits are counted per thread.
        let (m, visited) = on_threads(1, || {
            CANDIDATES.with(|c| c.set(0));
            let m = measure(&packing, &scene);
            (m, CANDIDATES.with(Cell::get) as f64)
        });
        let (lo, hi) = packing.domain.bounds();
        let step = hole_step(hi - lo, packing.disks.len(), scene.d_min());
        let per_sample = visited / samples(hi - lo, step);
        // About 2.8, against 128 when every sample ran a full query.
        assert!(per_sample < 10.0, "{per_sample} disks visited per sample");
        assert!(m.largest_hole > 0.0 && m.largest_hole < scene.d_max());
    }

    #[test]
    fn local_porosity_is_measured_on_every_domain() {
        let measured = |domain: &str| {
            let text = format!("[domain]\n{domain}\n[grading]\nuniform = [1.0, 1.5]\n");
            let scene = crate::config::parse_with(&text, "t", Default::default())
                .unwrap()
                .scene;
            measure(&crate::pack(&scene).unwrap(), &scene)
        };
        // A square holds windows wholly inside: the interior's scatter.
        let m = measured("shape = \"rectangle\"\nwidth = 40\nheight = 40");
        assert!(!m.local_windows_clipped && m.local_windows == 25, "{m:?}");
        assert!(m.local_porosity_std > 0.0 && m.local_porosity_std < 0.05);
        // A slot narrower than a window (7.5 mm), and a small circle: the
        // windows are clipped to the domain, measured on their exact area.
        for domain in [
            "shape = \"rectangle\"\nwidth = 200\nheight = 3",
            "shape = \"circle\"\nradius = 8",
        ] {
            let m = measured(domain);
            assert!(m.local_windows_clipped, "{domain}: {m:?}");
            assert!(m.local_windows >= 2, "{domain}: {m:?}");
            assert!(
                m.local_porosity_std.is_finite() && m.local_porosity_std < 0.2,
                "{domain}: {m:?}"
            );
        }
    }

    #[test]
    fn wide_grading_neighbours_are_found_by_size_class() {
        // 5 mm square, d 0.02–2 mm by mass (thousands of fine disks beside
        // a few coarse ones). A grid of cells sized by the largest radius
        // made every fine disk visit cells full of fine disks: about 1 000
        // disks per contact query and 50 per hole sample.
        let text = "[domain]\nshape = \"rectangle\"\nwidth = 5\nheight = 5\n\
                    [grading]\nuniform = [0.02, 2.0]\nbasis = \"mass3d\"\n";
        let scene = crate::config::parse_with(text, "t", Default::default())
            .unwrap()
            .scene;
        let packing = crate::pack(&scene).unwrap();
        let n = packing.disks.len();
        assert!(n > 2000, "{n} disks");
        // On a pool of one thread: the visits are counted per thread.
        let (m, visited) = on_threads(1, || {
            near::VISITED.with(|c| c.set(0));
            let m = measure(&packing, &scene);
            (m, near::VISITED.with(Cell::get))
        });
        let per_disk = visited as f64 / n as f64;
        assert!(per_disk < 200.0, "{per_disk} disks visited per packed disk");
        // The same contacts as a test of every pair.
        let mut contacts = 0;
        for (i, a) in packing.disks.iter().enumerate() {
            for b in &packing.disks[..i] {
                contacts += usize::from(overlap_disk_disk(a.c, a.r, b.c, b.r) >= -CONTACT_REL);
            }
        }
        assert_eq!(m.coordination, coordination(2 * contacts, n));
    }

    #[test]
    fn a_raised_token_stops_measure() {
        let scene = crate::config::parse(crate::config::DEFAULT_CONFIG, "t")
            .unwrap()
            .scene;
        let packing = crate::pack(&scene).unwrap();
        let cancel = Cancel::new();
        let measured = measure_cancellable(&packing, &scene, &cancel);
        // Debug text: a NaN local spread is equal to itself there.
        assert_eq!(
            format!("{measured:?}"),
            format!("{:?}", Ok::<_, Cancelled>(measure(&packing, &scene)))
        );
        cancel.cancel();
        assert_eq!(
            measure_cancellable(&packing, &scene, &cancel),
            Err(Cancelled::Flag)
        );
    }

    /// Grid points the largest-hole search visits for these bounds and step.
    fn samples(extent: nalgebra::Vector2<f64>, step: f64) -> f64 {
        ((extent.x / step).ceil() + 1.0) * ((extent.y / step).ceil() + 1.0)
    }

    #[test]
    fn wide_grading_hole_search_scales_with_the_disks() {
        // 20 × 20 mm, d from 0.1 µm to 5 mm: about 450 disks. A d_min/2 grid
        // capped at 4096 per side took 16.8 million clearance queries (20 s
        // to measure a packing made in 6 ms).
        let extent = nalgebra::Vector2::new(20.0, 20.0);
        let step = hole_step(extent, 451, 1e-4);
        let n = samples(extent, step);
        assert!(n <= 1.1 * HOLE_SAMPLES_PER_DISK * 451.0, "{n} samples");
        // An empty packing still gets a grid.
        assert!(hole_step(extent, 0, 1e-4).is_finite());
    }

    #[test]
    fn reference_scenes_keep_the_half_d_min_grid() {
        // The thesis fracture (8.6 × 62.5 mm, d_min 1.2 mm, about 350 disks)
        // and configs/wide_uniform.toml (100 × 100 mm, d 0.5 to 5 mm).
        assert_eq!(hole_step(nalgebra::Vector2::new(8.6, 62.5), 350, 1.2), 0.6);
        assert_eq!(
            hole_step(nalgebra::Vector2::new(100.0, 100.0), 1101, 0.5),
            0.25
        );
    }

    /// `f` run on a pool of `threads` threads.
    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    /// The scene of a 30 × 20 mm rectangle (`walls` its wall model) and
    /// its packing (disks 0.4 to 1.6 mm).
    fn packed(walls: &str, seed: u64) -> (Scene, Packing) {
        let text = format!(
            "seed = {seed}\n[domain]\nshape = \"rectangle\"\nwidth = 30\nheight = 20\n\
             walls = \"{walls}\"\n[grading]\nuniform = [0.4, 1.6]\n"
        );
        let scene = crate::config::parse_with(&text, "t", Default::default())
            .unwrap()
            .scene;
        let packing = crate::pack(&scene).unwrap();
        (scene, packing)
    }

    /// `n` disks of radii 0.1 to 0.8 mm dropped at random in the bounds of
    /// `domain` (overlapping one another and the walls).
    pub(super) fn scattered(domain: crate::Domain, n: usize, seed: u64) -> Packing {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let (lo, hi) = domain.bounds();
        let disks = (0..n)
            .map(|_| {
                Disk::new(
                    rng.gen_range(lo.x..hi.x),
                    rng.gen_range(lo.y..hi.y),
                    rng.gen_range(0.1..0.8),
                )
            })
            .collect();
        Packing::of_disks(domain, disks)
    }

    #[test]
    fn measure_is_the_same_on_one_and_four_threads() {
        let mut cases = Vec::new();
        for seed in 0..3 {
            for walls in ["exact", "disks", "periodic"] {
                cases.push(packed(walls, seed));
            }
        }
        let (scene, _) = packed("exact", 0);
        for seed in 0..6 {
            for domain in [
                crate::Domain::rectangle(30.0, 20.0).unwrap(),
                crate::Domain::periodic_rectangle(30.0, 20.0).unwrap(),
                crate::Domain::circle(Point::new(10.0, 10.0), 10.0).unwrap(),
            ] {
                let n = 300 + 300 * seed as usize;
                cases.push((scene.clone(), scattered(domain, n, seed)));
            }
        }
        assert!(cases.iter().any(|(_, p)| !p.boundary.is_empty()));
        assert!(cases.iter().any(|(_, p)| p.domain.is_periodic()));
        for (scene, packing) in &cases {
            assert!(packing.disks.len() > 4 * CHUNK, "{}", packing.disks.len());
            let one = on_threads(1, || measure(packing, scene));
            let four = on_threads(4, || measure(packing, scene));
            // Debug text: NaN is equal to itself there, and every bit of
            // each figure is printed.
            assert_eq!(format!("{one:?}"), format!("{four:?}"));
            assert!(one.largest_hole > 0.0, "{one:?}");
        }
    }

    #[test]
    fn the_cover_marks_the_samples_nearer_than_its_gap() {
        let (scene, packing) = packed("exact", 3);
        for gap in [0.0, 0.05, 0.3] {
            let mut samples = Samples::new(&packing, scene.d_min()).unwrap();
            samples.cover(gap, &Cancel::new()).unwrap();
            let (nx, ny) = (samples.nx, samples.ny);
            let mut marked = 0;
            for iy in 0..=ny {
                for ix in 0..=nx {
                    let p = Point::new(
                        samples.lo.x + ix as f64 * samples.step,
                        samples.lo.y + iy as f64 * samples.step,
                    );
                    let near = packing.disks.iter().any(|d| (p - d.c).norm() - d.r < gap);
                    assert_eq!(samples.inside.get(iy * (nx + 1) + ix), near, "{gap} {p:?}");
                    marked += usize::from(near);
                }
            }
            let all = (nx + 1) * (ny + 1);
            assert!(marked > all / 2 && marked < all, "{gap}: {marked} of {all}");
        }
    }

    #[test]
    fn the_hole_found_in_strips_is_the_serial_scans() {
        // Every sample of the grid queried against every disk, in row
        // order, the first of the largest kept: the strips and their
        // skipping must find that sample, and so the same hole.
        let (scene, dense) = packed("exact", 3);
        let sparse = scattered(crate::Domain::rectangle(30.0, 20.0).unwrap(), 300, 9);
        for packing in [&dense, &sparse] {
            let (lo, hi) = packing.domain.bounds();
            let step = hole_step(hi - lo, packing.disks.len(), scene.d_min());
            let nx = ((hi.x - lo.x) / step).ceil() as usize;
            let ny = ((hi.y - lo.y) / step).ceil() as usize;
            let mut best = (f64::NEG_INFINITY, lo);
            for iy in 0..=ny {
                for ix in 0..=nx {
                    let p = Point::new(lo.x + ix as f64 * step, lo.y + iy as f64 * step);
                    let wall = packing.domain.signed_distance(p);
                    if wall <= 0.0 {
                        continue;
                    }
                    let c = packing
                        .disks
                        .iter()
                        .map(|d| (p - d.c).norm() - d.r)
                        .fold(wall, f64::min);
                    if c > best.0 {
                        best = (c, p);
                    }
                }
            }
            let r_max = packing.disks.iter().fold(0.0f64, |m, d| m.max(d.r));
            let near = ByRadius::new(&packing.disks, 0..packing.disks.len());
            let mut clear = DiskClearance {
                packing,
                near: &near,
                all: &packing.disks,
                r_max,
                settler: (usize::MAX, Vector2::zeros()),
            };
            let serial = refine(best, &mut clear, step, scene.d_min());
            assert!(serial > 0.0);
            for threads in [1, 4] {
                let m = on_threads(threads, || measure(packing, &scene));
                assert_eq!(m.largest_hole.to_bits(), serial.to_bits(), "{threads}");
            }
        }
    }

    #[test]
    fn contacts_overlaps_and_windows_match_every_pair_and_disk() {
        let (scene, _) = packed("exact", 0);
        let packing = scattered(crate::Domain::rectangle(30.0, 20.0).unwrap(), 700, 5);
        let m = on_threads(4, || measure(&packing, &scene));
        let disks = &packing.disks;
        let (mut contacts, mut max_overlap) = (0, 0.0f64);
        let mut touched = vec![false; disks.len()];
        for (i, a) in disks.iter().enumerate() {
            let wall = packing.domain.signed_distance(a.c) - a.r;
            touched[i] |= wall <= CONTACT_REL * a.r;
            for (j, b) in disks[..i].iter().enumerate() {
                let overlap = overlap_disk_disk(a.c, a.r, b.c, b.r);
                max_overlap = max_overlap.max(overlap);
                if overlap >= -CONTACT_REL {
                    contacts += 1;
                    touched[i] = true;
                    touched[j] = true;
                }
            }
        }
        assert_eq!(m.coordination, coordination(2 * contacts, disks.len()));
        assert_eq!(m.max_overlap, max_overlap);
        assert_eq!(m.isolated, touched.iter().filter(|&&t| !t).count());
        assert!(m.isolated > 0 && contacts > 0, "{m:?}");
        // The windows: every disk's area in each, summed in any order (a
        // disk wholly inside, π r²: the closed form loses some 10⁻⁸ of it
        // where its bounds round off the disk's sides).
        let w = WINDOW_DIAMETERS * 2.0 * disks.iter().fold(0.0f64, |m, d| m.max(d.r));
        let every = window_porosities(&packing, w, false, &mut |boxes: &[[f64; 4]]| {
            boxes
                .iter()
                .map(|&[x0, x1, y0, y1]| {
                    disks
                        .iter()
                        .map(|d| {
                            let inside = d.c.x - d.r >= x0
                                && d.c.x + d.r <= x1
                                && d.c.y - d.r >= y0
                                && d.c.y + d.r <= y1;
                            if inside {
                                std::f64::consts::PI * d.r * d.r
                            } else {
                                area_disk_box(d.c, d.r, x0, x1, y0, y1)
                            }
                        })
                        .sum()
                })
                .collect()
        });
        assert_eq!(m.local_windows, every.len());
        let sd = mean_sd(&every).1;
        assert!((m.local_porosity_std - sd).abs() < 1e-12 * sd, "{m:?} {sd}");
    }
}
