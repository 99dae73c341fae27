//! The check of particles that are not disks: each close pair proved apart
//! and each particle proved inside the domain, from the support functions
//! alone (bounded from above, [`Outline::support`]).
//!
//! # Tolerance
//! The policy of the disks ([`OVERLAP_REL`]): a pair counts as apart when a
//! certified lower bound of its distance is at least `−OVERLAP_REL · (R_i +
//! R_j)`, R the circumradius ([`Outline::circumradius`]: for a disk, its
//! radius, so that disks are judged as [`check`](super::check) judges
//! them); a particle counts as inside when it reaches beyond the boundary
//! by at most `OVERLAP_REL · 2 · R_max`, R_max the largest circumradius.
//!
//! # Bounds
//! Every quantity compared with a tolerance is an upper bound of a depth
//! (or a lower bound of a distance) built from support values, each itself
//! an upper bound: a particle the check passes is, up to the tolerance,
//! apart from its neighbours and inside, whatever the rounding of the
//! search that found the bound. A pair or particle the search could not
//! clear is counted as overlapping or outside (never the reverse).

use std::f64::consts::TAU;

use nalgebra::Vector2;

use crate::cancel::{Cancel, Cancelled};
use crate::geometry::predicates::OVERLAP_REL;
use crate::geometry::{Disk, Domain, Grain, Outline, Point, Turned, Wall, grain_separation};
use crate::geometry::{Separation, separation};
use crate::metrics::near::ByRadius;
use std::ops::ControlFlow;

use super::Search;

/// Directions of the scan that sharpens a lower bound the GJK search left
/// below the tolerance (overlapping or barely touching sets).
const SCAN: usize = 64;

/// Golden-section steps refining the scan's best direction (the bracket
/// shrinks by 0.618 each: 60 steps take ±0.1 rad to 10⁻¹⁴ rad).
const GOLDEN_STEPS: usize = 60;

/// Directions of the first tangent polygon about a circular wall's centre
/// (see [`farthest_from`]).
const CIRCLE_DIRECTIONS: usize = 256;

/// Deepest bisection of an arc of [`farthest_from`]: arcs of 2π/256/2²⁶
/// (3.7·10⁻¹⁰ rad) leave a slack of 1.7·10⁻²⁰ of the distance.
const CIRCLE_DEPTH: u32 = 26;

/// Most support evaluations of one [`farthest_from`].
const CIRCLE_BUDGET: usize = 4096;

/// Whether `d` (centre, area-equivalent radius) and `g` describe a particle:
/// finite centre, angle and positive radius, and an outline its own
/// constructor accepts (a convex superellipse, a strictly convex polygon
/// with a finite rounding of at least 0).
pub(super) fn well_formed(d: &Disk, g: &Grain) -> bool {
    let outline = match &g.outline {
        Outline::Superellipse { a, b, alpha, beta } => {
            Outline::superellipse(*a, *b, *alpha, *beta).is_ok()
        }
        Outline::Polygon {
            template,
            vertices,
            rounding,
        } => Outline::polygon(*template, vertices, *rounding).is_ok(),
    };
    // A bound of the circumradius, finite: a superellipse lies in its
    // bounding box (the circumradius's own loop over support values costs
    // more than the rest of the check of a particle).
    let reach_finite = match &g.outline {
        Outline::Superellipse { a, b, .. } => (2.0 * a.hypot(*b)).is_finite(),
        Outline::Polygon { .. } => g.outline.circumradius().is_finite(),
    };
    outline
        && d.c.x.is_finite()
        && d.c.y.is_finite()
        && d.r.is_finite()
        && d.r > 0.0
        && g.angle.is_finite()
        && reach_finite
}

/// What a pair test found (the particles' or the disks').
pub(super) struct Pairs {
    /// Pairs not proved apart.
    pub(super) overlaps: usize,
    /// The deepest of them: indices and depth relative to R_i + R_j.
    pub(super) worst: Option<(usize, usize, f64)>,
    /// Pairs whose bounding circles meet, proved apart.
    pub(super) certified: usize,
    /// Whether every pair within reach was tested (no search stopped
    /// short after an overlap: [`Search`]).
    pub(super) complete: bool,
}

/// Test every pair of `ok` particles whose bounding circles (centre,
/// circumradius `reach[i]`) meet, at every periodic image as the disks are.
///
/// # Performance
/// The bounding circles are bucketed by size class ([`ByRadius`]): each
/// particle meets the candidates of its neighbourhood only; a GJK search
/// (a few support evaluations) per candidate pair.
///
/// # Errors
/// [`Cancelled`] when `cancel` stops it (polled once per particle).
pub(super) fn pairs(
    disks: &[Disk],
    turned: &[Turned],
    reach: &[Disk],
    ok: &[u32],
    domain: &Domain,
    cancel: &Cancel,
) -> Result<Pairs, Cancelled> {
    let mut out = Pairs {
        overlaps: 0,
        worst: None,
        certified: 0,
        complete: true,
    };
    if ok.len() < 2 && !domain.is_periodic() {
        return Ok(out);
    }
    let ids = || ok.iter().map(|&i| i as usize);
    let near = ByRadius::new(reach, ids());
    let r_max = ids().fold(0.0f64, |m, i| m.max(reach[i].r));
    let mut search = Search::default();
    for a in ids() {
        cancel.check()?;
        let (ca, ra) = (disks[a].c, reach[a].r);
        let (lo, hi) = Disk::new(ca.x, ca.y, ra + r_max).bounds();
        search.start();
        for v in domain.image_shifts(lo, hi) {
            let zero = v == Vector2::zeros();
            let stopped = near.try_visit(ca - v, ra, |b| {
                search.visit()?;
                // Each pair once, as the disks' test takes them.
                if b > a || (b == a && (zero || (v.y, v.x) < (0.0, 0.0))) {
                    return ControlFlow::Continue(());
                }
                let cb = if zero { disks[b].c } else { disks[b].c + v };
                let sum = ra + reach[b].r;
                if (cb - ca).norm() > sum * (1.0 + 4.0 * f64::EPSILON) {
                    return ControlFlow::Continue(());
                }
                let tol = OVERLAP_REL * sum;
                let lower = pair_lower(&turned[a], ca, &turned[b], cb, tol);
                if lower >= -tol {
                    out.certified += 1;
                    return ControlFlow::Continue(());
                }
                search.overlapped = true;
                out.overlaps += 1;
                let depth = -lower / sum;
                let pair = (b, a);
                if out
                    .worst
                    .is_none_or(|(x, y, w)| depth > w || (depth == w && pair < (x, y)))
                {
                    out.worst = Some((b, a, depth));
                }
                ControlFlow::Continue(())
            });
            if stopped.is_break() {
                break;
            }
        }
    }
    out.complete = search.complete;
    Ok(out)
}

/// A certified lower bound of the distance between two grains (negative:
/// at least minus their penetration depth), sharp to well within `tol`
/// when they are apart or touch.
pub(super) fn pair_lower(a: &Turned, ca: Point, b: &Turned, cb: Point, tol: f64) -> f64 {
    let s = grain_separation(a, ca, b, cb, 0.1 * tol);
    if s.lower >= -tol {
        return s.lower;
    }
    sharpen(cb - ca, &s, |u| {
        let (ha, pa) = a.support_both(u);
        let (hb, pb) = b.support_both(-u);
        (ha + hb, pa - pb)
    })
}

/// The best lower bound of the signed distance from `d` to the convex set
/// K (support map `support`, bounded from above) found by a scan of
/// [`SCAN`] directions starting at GJK's best one, refined by golden
/// sections about the best: max over the directions u tried of u·d − h_K(u),
/// each a certified bound. For `d` inside K it approaches minus the depth
/// of `d` in K (the pair's penetration depth).
fn sharpen(
    d: Vector2<f64>,
    s: &Separation,
    support: impl Fn(Vector2<f64>) -> (f64, Vector2<f64>),
) -> f64 {
    let f = |t: f64| {
        let u = Vector2::new(t.cos(), t.sin());
        u.dot(&d) - support(u).0
    };
    let t0 = s.dir.y.atan2(s.dir.x);
    let step = TAU / SCAN as f64;
    let (mut best, mut at) = (s.lower, t0);
    for k in 1..SCAN {
        let t = t0 + step * k as f64;
        let v = f(t);
        if v > best {
            (best, at) = (v, t);
        }
    }
    let (mut lo, mut hi) = (at - step, at + step);
    let g = 0.618_033_988_749_895;
    for _ in 0..GOLDEN_STEPS {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (v1, v2) = (f(m1), f(m2));
        best = best.max(v1).max(v2);
        if v1 > v2 {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    best
}

/// How far particle `t` at centre `c` (circumradius `reach`) reaches
/// beyond the domain's boundary (mm; an upper bound, at most `tol` when it
/// is proved inside to within `tol`).
///
/// # Behavior
/// - A periodic cell: how far the centre lies outside the cell, as for disks.
/// - Any domain with walls: a particle whose bounding circle is inside is
///   inside.
/// - A circular wall: the particle's farthest point from the wall's
///   centre ([`farthest_from`]) minus the radius.
/// - Straight walls: each wall within `reach` of the centre (the others
///   cannot meet the particle), and the centre inside. In a convex domain
///   the particle must lie behind each such wall's line: h(n) ≤ the line's
///   offset, n its outward normal, which is exact. In a domain with reflex
///   corners a particle may stand beyond a wall's line past its end, so a
///   wall it does not lie behind must instead not be crossed: the
///   particle–segment distance's certified lower bound at least `−tol`.
///   Near a convex corner of such a domain the segments' tolerance lets a
///   sharp particle corner of half-angle φ poke out by up to `tol`/tan φ
///   (5·`tol` for a rhombus of aspect 5): far below any length that
///   matters, and none at all in convex domains.
pub(super) fn beyond(t: &Turned, c: Point, reach: f64, domain: &Domain, tol: f64) -> f64 {
    if domain.is_periodic() {
        let (lo, hi) = domain.bounds();
        return (lo.x - c.x).max(c.x - hi.x).max(lo.y - c.y).max(c.y - hi.y);
    }
    let inner = domain.signed_distance(c);
    if reach - inner <= tol {
        return reach - inner;
    }
    let convex = domain.reflex_vertices().is_empty();
    let mut worst = -inner;
    for wall in domain.walls() {
        let by = match *wall {
            Wall::Circle { center, radius } => farthest_from(t, c - center, radius + tol) - radius,
            Wall::Segment { a, b } => {
                let e = b - a;
                let len = e.norm();
                if len == 0.0 || distance_to_segment(c, a, b) >= reach {
                    continue;
                }
                let n = Vector2::new(e.y, -e.x) / len;
                let behind = t.support_both(n).0 + n.dot(&(c - a));
                if behind <= tol || convex {
                    behind
                } else {
                    -segment_lower(t, c, a, b, tol)
                }
            }
        };
        worst = worst.max(by);
    }
    worst
}

/// Distance from `p` to the segment `a`–`b`.
fn distance_to_segment(p: Point, a: Point, b: Point) -> f64 {
    let e = b - a;
    let l2 = e.norm_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(&e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + e * s)).norm()
}

/// A certified lower bound of the distance between particle `t` at `c` and
/// the segment `a`–`b` (negative: at least minus the depth of the crossing).
///
/// # Behavior
/// The segment about its midpoint m is {s·e/2 : |s| ≤ 1}, e = b − a, with
/// support |u·e|/2, raised by 4 ulps of the endpoints' size for the
/// rounding of e and m; the distance is that of m − c to the particle
/// grown by the mirrored segment ([`separation`]).
fn segment_lower(t: &Turned, c: Point, a: Point, b: Point, tol: f64) -> f64 {
    let e = b - a;
    let m = Point::from((a.coords + b.coords) * 0.5);
    let slack = 4.0 * f64::EPSILON * (a.coords.abs().max() + b.coords.abs().max());
    let support = |u: Vector2<f64>| {
        let (h, p) = t.support_both(u);
        let along = 0.5 * u.dot(&e);
        // The segment's point of most −u·x, mirrored: the one of least u·x.
        let q = if along >= 0.0 { -e * 0.5 } else { e * 0.5 };
        (h + along.abs() + slack * u.norm(), p - q)
    };
    let d = m - c;
    let s = separation(d, 0.1 * tol, support);
    if s.lower >= -tol {
        return s.lower;
    }
    sharpen(d, &s, support)
}

/// An upper bound of the distance from a wall's centre O to the farthest
/// point of particle `t`, `off` = its centre − O, sharpened until it is at
/// most `target` if it can be.
///
/// # Behavior
/// The farthest distance is max over unit u of u·`off` + h(u). The particle
/// lies in the tangent polygon of its support lines at any set of
/// directions; within the cone between two neighbouring directions u₀, u₁
/// (angle Δ) its points lie in the quadrilateral of O, the two rays' points
/// min(h₀, h₁/cos Δ)·u₀ and min(h₁, h₀/cos Δ)·u₁, and the lines' corner
/// when it lies in the cone, whose farthest vertex bounds the arc. The
/// first polygon has [`CIRCLE_DIRECTIONS`] (256) directions, a slack of up
/// to 1/cos(π/256) − 1 = 7.5·10⁻⁵ of the distance (which a particle
/// touching the wall would fail); each arc whose bound exceeds `target`
/// while neither end does is bisected, down to [`CIRCLE_DEPTH`] levels
/// (a slack below 10⁻¹⁹ of the distance) or [`CIRCLE_BUDGET`] support
/// evaluations in all, which touching particles do not approach (a few
/// arcs a level about the farthest point).
pub(super) fn farthest_from(t: &Turned, off: Vector2<f64>, target: f64) -> f64 {
    let h = |th: f64| {
        let u = Vector2::new(th.cos(), th.sin());
        u.dot(&off) + t.support_both(u).0
    };
    let step = TAU / CIRCLE_DIRECTIONS as f64;
    let first: Vec<f64> = (0..=CIRCLE_DIRECTIONS)
        .map(|k| {
            if k == CIRCLE_DIRECTIONS {
                0.0
            } else {
                step * k as f64
            }
        })
        .map(h)
        .collect();
    let mut budget = CIRCLE_BUDGET;
    let mut worst = f64::NEG_INFINITY;
    // Arcs (start angle, h there, h at its end, its width, depth).
    let mut stack: Vec<(f64, f64, f64, f64, u32)> = (0..CIRCLE_DIRECTIONS)
        .map(|k| (step * k as f64, first[k], first[k + 1], step, 0))
        .collect();
    while let Some((t0, h0, h1, width, depth)) = stack.pop() {
        let bound = arc_bound(h0, h1, width);
        if bound > target && h0.max(h1) <= target && depth < CIRCLE_DEPTH && budget > 0 {
            budget -= 1;
            let half = 0.5 * width;
            let hm = h(t0 + half);
            stack.push((t0, h0, hm, half, depth + 1));
            stack.push((t0 + half, hm, h1, half, depth + 1));
        } else {
            worst = worst.max(bound);
        }
    }
    worst
}

/// The farthest point from O of the region of a cone of angle `width`
/// (< π/2) between unit directions u₀, u₁ below the lines u₀·x = h0 and
/// u₁·x = h1, raised by 8 ulps for rounding (see [`farthest_from`]).
fn arc_bound(h0: f64, h1: f64, width: f64) -> f64 {
    let (s, c) = width.sin_cos();
    let ray0 = h0.min(h1 / c);
    let ray1 = h1.min(h0 / c);
    // The corner in the frame u₀ = (1, 0), u₁ = (cos Δ, sin Δ).
    let (x, y) = (h0, (h1 - h0 * c) / s);
    let corner = if y >= 0.0 && x * s - y * c >= 0.0 {
        x.hypot(y)
    } else {
        0.0
    };
    ray0.max(ray1).max(corner).max(0.0) * (1.0 + 8.0 * f64::EPSILON)
}
