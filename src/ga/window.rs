//! Large scenes by windows: the porosity search runs on a representative
//! window of a large rectangle, and the whole is packed with the packing
//! rules the window found, tuned on the whole until its porosity is the
//! target.
//!
//! # Why
//! The genome holds one grading gene per size the scene can draw, and the
//! search packs the scene once per genome: on 10⁵ disks or more a
//! generation costs minutes and the population's genomes hundreds of
//! megabytes. The porosity of a large packing is a bulk property plus a wall
//! effect along the edges; a window many disks wide has the same bulk, so
//! the rules that reach a porosity there reach it on the whole, up to the
//! difference in wall effect, which is measured and taken out.
//!
//! # Behavior
//! - **The window** ([`settle`]): a rectangle of the domain's proportions
//!   and walls, from about [`FIRST_DISKS`] disks, its area doubled until
//!   two windows in a row, packed with the scene's own rules and seed, agree
//!   in the porosity of their cores (the bulk, away from the window's own
//!   walls) within the search's tolerance, or it reaches [`MAX_SHARE`] of
//!   the domain (then it is reported as not settled). The whole is packed once
//!   with the scene's own rules too: the window's porosity less the whole's
//!   is the wall effect's difference (`offset`), and the search on the
//!   window aims at the target plus it.
//! - **The whole** ([`fit_whole`]): packed with the window's best rules,
//!   scaled along the line from the scene's dense rules (t = 0, the packing
//!   [`settle`] made) to them (t = 1) and beyond, by regula falsi on t
//!   (the porosity of a large packing moves smoothly with the rules), at
//!   most [`WHOLE_PACKS`] packs; the packing nearest the target that keeps
//!   the grading is kept, so the target is verified on the whole.

use super::porosity::RULE_GENES;
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::predicates::area_disk_box;
use crate::geometry::{Domain, Shape};
use crate::metrics::{porosity, psd_ks, solid_area};
use crate::packer::{MAX_DEFERRED, MAX_GAP, PackError, Packing, pack_observed};

/// Disks (estimated) in the first window.
pub const FIRST_DISKS: f64 = 4_000.0;

/// The largest window, as a share of the domain's area.
pub const MAX_SHARE: f64 = 0.25;

/// Largest diameters left out of a window's core at each of its edges.
pub const EDGE_DIAMETERS: f64 = 3.0;

/// Packs of the whole at most while tuning its rules (the first, at t = 1, included).
pub const WHOLE_PACKS: u32 = 8;

/// Whether `scene` is searched on a window: a rectangle (walled or
/// periodic) estimated at `min_disks` disks or more (`min_disks` 0: never),
/// large enough that the first window is a small part of it.
pub fn windowed(scene: &Scene, min_disks: u64) -> bool {
    min_disks > 0
        && matches!(scene.domain.shape(), Shape::Rectangle { .. })
        && scene.estimated_disks() >= min_disks as f64
        && FIRST_DISKS / scene.estimated_disks() <= 0.5 * MAX_SHARE
}

/// One window packed with the scene's own rules.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowStep {
    /// Width and height (mm).
    pub size: [f64; 2],
    /// Disks packed.
    pub disks: usize,
    /// Its porosity.
    pub porosity: f64,
    /// The porosity of its core: the window less [`EDGE_DIAMETERS`] largest
    /// diameters along each edge, where its walls loosen the pack.
    pub core: f64,
}

/// The window the search runs on (see the module documentation).
#[derive(Debug, Clone)]
pub struct Window {
    /// The scene over the window.
    pub scene: Scene,
    /// Every window packed, the last the one chosen.
    pub steps: Vec<WindowStep>,
    /// Whether the last two windows agreed within the tolerance.
    pub settled: bool,
    /// The whole packed with the scene's own rules, and its porosity.
    pub whole: (Packing, f64),
    /// The chosen window's porosity less the whole's, both with the scene's own rules.
    pub offset: f64,
}

impl Window {
    /// The window's area as a share of the domain's.
    pub fn share(&self, scene: &Scene) -> f64 {
        self.scene.domain.area() / scene.domain.area()
    }
}

/// Grow the window of `scene` until its porosity settles within
/// `tolerance` (see the module documentation).
///
/// # Errors
/// The packer's errors on the whole or a window ([`PackError::Cancelled`]
/// when `cancel` is raised).
pub fn settle(scene: &Scene, tolerance: f64, cancel: &Cancel) -> Result<Window, PackError> {
    let (lo, hi) = scene.domain.bounds();
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let whole = pack_observed(scene, &mut |_| {}, cancel)?;
    let whole_porosity = porosity(solid_area(&whole.disks), whole.domain.area());
    let mut share = (FIRST_DISKS / scene.estimated_disks()).min(MAX_SHARE);
    let mut steps: Vec<WindowStep> = Vec::new();
    loop {
        let k = share.sqrt();
        // Positive fractions of a valid rectangle's sides make a rectangle.
        let domain = Domain::rectangle(w * k, h * k).map_err(|_| PackError::DomainTooNarrow {
            inscribed: w.min(h) * k,
            d_min: scene.d_min(),
        })?;
        let window = scene.clone().with_domain(domain);
        let packing = pack_observed(&window, &mut |_| {}, cancel)?;
        let step = WindowStep {
            size: [w * k, h * k],
            disks: packing.disks.len(),
            porosity: porosity(solid_area(&packing.disks), packing.domain.area()),
            core: core_porosity(&packing, EDGE_DIAMETERS * scene.d_max()),
        };
        let settled = steps
            .last()
            .is_some_and(|last| (last.core - step.core).abs() <= tolerance);
        steps.push(step);
        if settled || share >= MAX_SHARE {
            return Ok(Window {
                offset: step.porosity - whole_porosity,
                scene: window,
                steps,
                settled,
                whole: (whole, whole_porosity),
            });
        }
        share = (2.0 * share).min(MAX_SHARE);
    }
}

/// The porosity of `packing`'s bounds less `edge` along each side (its
/// bounds' own porosity if that leaves nothing), the disks' (or grains')
/// exact areas inside it counted.
fn core_porosity(packing: &Packing, edge: f64) -> f64 {
    let (lo, hi) = packing.domain.bounds();
    let (x0, x1, y0, y1) = (lo.x + edge, hi.x - edge, lo.y + edge, hi.y - edge);
    if x0 >= x1 || y0 >= y1 {
        return porosity(solid_area(&packing.disks), packing.domain.area());
    }
    let solid: f64 = if packing.grains.is_empty() {
        packing
            .disks
            .iter()
            .map(|d| area_disk_box(d.c, d.r, x0, x1, y0, y1))
            .sum()
    } else {
        crate::metrics::grain_solid(packing, &[[x0, x1, y0, y1]])
            .first()
            .copied()
            .unwrap_or(0.0)
    };
    porosity(solid, (x1 - x0) * (y1 - y0))
}

/// The whole packed near `target`: see the module documentation.
#[derive(Debug, Clone)]
pub struct Whole {
    /// The packing nearest the target that keeps the grading (else the nearest).
    pub packing: Packing,
    /// The scene with the rules that packed it.
    pub scene: Scene,
    /// Its porosity.
    pub porosity: f64,
    /// Packs of the whole made while tuning (the one [`settle`] made aside).
    pub packs: u32,
}

/// Pack the whole of `scene` with `rules` (the window's best packing-rule
/// genes) scaled by t, tuning t until the porosity is within `tolerance`
/// of `target` with the grading within `max_psd_ks`, starting from the
/// dense packing `dense` (t = 0) that [`settle`] made.
///
/// # Errors
/// The packer's errors ([`PackError::Cancelled`] when `cancel` is raised).
pub fn fit_whole(
    scene: &Scene,
    rules: [f64; RULE_GENES],
    dense: (Packing, f64),
    [target, tolerance, max_psd_ks]: [f64; 3],
    cancel: &Cancel,
) -> Result<Whole, PackError> {
    // The share and the gap scale with t (1: the window's); t stops where
    // either gene would pass 1. The deferred sizes stay the window's.
    let t_max = rules[..2]
        .iter()
        .filter(|&&g| g > 0.0)
        .map(|&g| 1.0 / g)
        .fold(f64::INFINITY, f64::min);
    let at = |t: f64| {
        let mut s = scene.clone();
        s.packer.one_contact_share = (rules[0] * t).min(1.0);
        s.packer.gap = (rules[1] * t).min(1.0) * MAX_GAP;
        s.packer.max_deferred = ((1.0 - rules[2]) * MAX_DEFERRED as f64).round() as usize;
        s
    };
    let mut best = {
        let ks = psd_ks(&dense.0, scene);
        (dense.1, ks, dense.0, scene.clone())
    };
    let better = |a: (f64, f64), b: (f64, f64)| {
        // Keeping the grading first, then nearer the target.
        let fits = |ks: f64| ks <= max_psd_ks;
        (fits(a.1), -(a.0 - target).abs()) > (fits(b.1), -(b.0 - target).abs())
    };
    let done = |p: f64, ks: f64| (p - target).abs() <= tolerance && ks <= max_psd_ks;
    if done(best.0, best.1) || !t_max.is_finite() {
        return Ok(Whole {
            packing: best.2,
            scene: best.3,
            porosity: best.0,
            packs: 0,
        });
    }
    // Regula falsi on f(t) = porosity − target, rising with t: `lo` the
    // largest t seen too dense, `hi` the smallest too loose; each new t cut
    // a tenth of the bracket clear of its ends, so it shrinks every pack.
    let mut lo = (0.0, best.0 - target);
    if lo.1 >= 0.0 {
        // Denser rules than the scene's own are not in this line.
        return Ok(Whole {
            packing: best.2,
            scene: best.3,
            porosity: best.0,
            packs: 0,
        });
    }
    let mut hi: Option<(f64, f64)> = None;
    let mut t = t_max.min(1.0);
    let mut packs = 0;
    while packs < WHOLE_PACKS {
        let s = at(t);
        let packing = pack_observed(&s, &mut |_| {}, cancel)?;
        packs += 1;
        let p = porosity(solid_area(&packing.disks), packing.domain.area());
        let ks = psd_ks(&packing, &s);
        if better((p, ks), (best.0, best.1)) {
            best = (p, ks, packing, s);
        }
        if done(best.0, best.1) {
            break;
        }
        let f = p - target;
        if f < 0.0 {
            lo = (t, f);
        } else {
            hi = Some((t, f));
        }
        t = match hi {
            Some(h) => {
                let cut = lo.0 + (h.0 - lo.0) * (-lo.1) / (h.1 - lo.1);
                let edge = 0.1 * (h.0 - lo.0);
                cut.clamp(lo.0 + edge, h.0 - edge)
            }
            // The loosest rules on this line are still too dense.
            None if lo.0 >= t_max => break,
            None => (2.0 * lo.0).min(t_max),
        };
    }
    Ok(Whole {
        packing: best.2,
        scene: best.3,
        porosity: best.0,
        packs,
    })
}
