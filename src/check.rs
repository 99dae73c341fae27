//! An independent check of a packing, for packings from any tool: overlaps,
//! containment, porosity and grading fidelity.
//!
//! Nothing here uses the generator's bookkeeping or its spatial indexes: the
//! disks are bucketed afresh by size class and cell ([`ByRadius`]; a run
//! shares that bucketing with its measure, built once for both), and
//! every pair within reach is tested. A packing that passes has no two disks
//! overlapping by more than [`OVERLAP_REL`] of their radii sum and no disk
//! outside the domain by more than [`OVERLAP_REL`] of the largest diameter.
//!
//! In a periodic cell ([`Domain::periodic_rectangle`]) a disk may cross the
//! edges: overlaps are counted with every image of the other disks (and of
//! the disk itself), and a disk is outside when its centre is outside the
//! cell.
//!
//! Particles that are not disks ([`check_particles`]) are judged from their
//! support functions: each pair whose bounding circles meet is proved apart
//! by a certified lower bound of its distance, and each particle proved
//! inside the walls (see the `particles` module's tolerance policy, the
//! disks' one).

#[cfg(test)]
mod particle_tests;
mod particles;

use std::collections::HashMap;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::geometry::predicates::OVERLAP_REL;
use nalgebra::Vector2;
use rayon::prelude::*;

use crate::cancel::{Cancel, Cancelled};
use crate::geometry::{Disk, Domain, Grain, Outline, Turned};
use crate::grading::Grading;
use crate::metrics::near::{ByRadius, SharedIndex};
use crate::metrics::{porosity, solid_area};

/// The KS distance beyond the sampling noise of n sizes (1.36/√n, the 95 %
/// quantile of the KS statistic) that still counts as following the grading.
pub const KS_MARGIN: f64 = 0.05;

/// Fewest well-formed disks a grading check needs: below it the sampling
/// noise of their number ([`ks_limit`]) is at least 1, the largest KS
/// distance there is, so no sizes at all could fail it. Such a check is
/// not made ([`GradingCheck::TooFewDisks`]) rather than passed.
pub const MIN_GRADING_DISKS: usize = 3;

/// Partners a disk (particle) visits, once it has found an overlap, before
/// its search stops: the packing is then known to fail, and a pile of
/// 10⁶ nearly coincident disks (each one's partners all in one cell)
/// costs 10⁶ · this many visits rather than 5·10¹¹ tests. A disk that
/// overlaps nothing searches on to the end, so a packing that passes is
/// certified pair by pair.
pub(crate) const VISITS_AFTER_OVERLAP: usize = 256;

/// What became of the grading part of a [`check`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum GradingCheck {
    /// No grading was given.
    NotAsked,
    /// Fewer than [`MIN_GRADING_DISKS`] well-formed disks (the number
    /// held): the check could not fail, so it is not made.
    TooFewDisks(usize),
    /// The KS distance of the diameters to the grading, in its basis.
    Measured(f64),
}

impl GradingCheck {
    /// The verdict on `disks` well-formed disks whose KS distance to the
    /// grading is `ks()` (evaluated only when there are enough of them).
    pub fn of(disks: usize, ks: impl FnOnce() -> f64) -> Self {
        if disks < MIN_GRADING_DISKS {
            GradingCheck::TooFewDisks(disks)
        } else {
            GradingCheck::Measured(ks())
        }
    }

    /// The KS distance, when it was measured.
    pub fn ks(&self) -> Option<f64> {
        match *self {
            GradingCheck::Measured(ks) => Some(ks),
            _ => None,
        }
    }
}

/// The result of [`check`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Check {
    /// Disks (particles) checked.
    pub particles: usize,
    /// Disks whose centre or radius is not finite, or whose radius is not
    /// positive (particles: see [`check_particles`]).
    pub malformed: usize,
    /// Pairs overlapping by more than [`OVERLAP_REL`] of their radii sum
    /// (particles: pairs not proved apart to within [`OVERLAP_REL`] of the
    /// sum of their circumradii).
    pub overlaps: usize,
    /// Whether `overlaps` counts every overlapping pair: false when disks
    /// pile up and a disk's search for partners stopped short (256
    /// partners after its first overlap), `overlaps` then a lower bound and
    /// `worst_overlap` the deepest of the pairs tested. Always true of a
    /// packing with no overlap.
    pub overlaps_complete: bool,
    /// The deepest overlap: the two disks' indices and the overlap relative
    /// to their radii sum (particles: a bound of the penetration depth
    /// relative to the sum of their circumradii).
    pub worst_overlap: Option<(usize, usize, f64)>,
    /// Pairs within reach proved apart (not overlapping beyond the
    /// tolerance): disks that meet, particles whose bounding circles meet.
    pub pairs_certified: usize,
    /// Disks reaching outside the domain by more than the tolerance (in a
    /// periodic cell: whose centre lies outside the cell by more than it).
    pub outside: usize,
    /// The disk reaching farthest outside: its index and how far (mm).
    pub worst_outside: Option<(usize, f64)>,
    /// Domain area (mm²).
    pub domain_area: f64,
    /// Total area of the disks (mm²).
    pub solid_area: f64,
    /// 1 − solid_area / domain_area.
    pub porosity: f64,
    /// The grading check: not asked, not made (too few disks), or the KS
    /// distance of the diameters to the grading.
    pub grading: GradingCheck,
    /// Largest KS distance that sampling noise explains for this many disks, plus [`KS_MARGIN`].
    pub ks_limit: f64,
}

impl Check {
    /// No malformed disk, no overlap, nothing outside.
    pub fn valid(&self) -> bool {
        self.malformed == 0 && self.overlaps == 0 && self.outside == 0
    }

    /// Whether the sizes follow the grading within sampling noise (true
    /// when it was not checked: see [`Check::grading`]).
    pub fn grading_kept(&self) -> bool {
        self.grading.ks().is_none_or(|ks| ks <= self.ks_limit)
    }
}

/// Check `disks` in `domain`; with a `grading`, their sizes against it too.
///
/// # Behavior
/// Overlap of two disks: `(r1 + r2 − |c1 − c2|) / (r1 + r2)`, counted when
/// above [`OVERLAP_REL`]. Containment: the centre's signed distance to the
/// boundary minus the radius, counted when below `−OVERLAP_REL · d_max`.
/// Malformed disks are counted and left out of the other tests.
///
/// A periodic cell has no walls: each pair is tested at every image of
/// the second disk shifted by whole periods (an overlap that exists only
/// across an edge counts, once per image overlapped; a disk overlapping
/// its own image counts too), and containment asks the centre to lie in
/// the cell, to within the same tolerance. The porosity is the cell's:
/// every disk counts once, whole.
///
/// # Performance
/// O(n log n): one sort of the disks by cell, then the pairs of each cell
/// and its neighbours. Identical disks (centre and radius equal bit for
/// bit) are counted together, their pairs by their number: 10⁵ copies of
/// one disk cost one sort, not 5·10⁹ tests. A disk that overlaps another
/// stops its search 256 partners later (the verdict is known): nearly
/// coincident disks (10⁶ within a nanometre) cost that many visits a disk,
/// and [`Check::overlaps`] is then a lower bound
/// ([`Check::overlaps_complete`]).
pub fn check(disks: &[Disk], domain: &Domain, grading: Option<&Grading>) -> Check {
    never_stopped(run(disks, &[], domain, grading, None, None, &Cancel::new()))
}

/// Check particles of any shape in `domain`: `disks[i]` the centre and
/// area-equivalent radius of particle i, `grains[i]` its outline and
/// angle; with `grains` empty, exactly [`check`]. With a `grading`, the
/// sizes checked are the area-equivalent diameters 2·r, right for a
/// grading that measures that size; [`check_particles_sized`] takes the
/// sizes a grading measures otherwise (the least widths, for sieve sizes).
///
/// # Behavior
/// Pairs: every pair whose bounding circles (centre, circumradius R)
/// meet — found by size class and position, as the disks' — is proved
/// apart when a certified lower bound of its distance (a GJK search on the
/// support functions, sharpened by a scan of directions when it is not
/// enough) is at least `−OVERLAP_REL · (R_i + R_j)`; otherwise it counts as
/// an overlap, of depth that bound's opposite relative to `R_i + R_j`.
/// [`Check::pairs_certified`] counts the pairs proved apart.
///
/// Containment: an upper bound of how far each particle reaches beyond
/// the walls, counted when above `OVERLAP_REL · 2 · R_max`: behind every
/// straight wall within reach in a convex domain, not across any in a
/// domain with reflex corners (the centre inside), within a circular wall
/// by the farthest point of its tangent polygon about the wall's centre,
/// refined about the farthest point until it proves the particle inside or
/// 2π/256/2²⁶ is reached. In a periodic cell the centre must lie in the
/// cell, and the pairs are tested at every image, as for disks.
///
/// Malformed: a centre, radius or angle not finite, a radius not positive,
/// an outline its constructor refuses, or a disk without its grain (or a
/// grain without its disk); they are counted and left out of the rest.
/// Porosity: from the disks' areas, the particles' exact areas.
///
/// # Performance
/// O(n log n) as [`check`], with a GJK search (tens of support
/// evaluations) per pair of meeting bounding circles and per particle
/// near a wall.
pub fn check_particles(
    disks: &[Disk],
    grains: &[Grain],
    domain: &Domain,
    grading: Option<&Grading>,
) -> Check {
    never_stopped(run(
        disks,
        grains,
        domain,
        grading,
        None,
        None,
        &Cancel::new(),
    ))
}

/// [`check_particles`] with the grading checked on `sizes[i]`, the size of
/// particle i that the grading measures (its least width for sieve sizes).
/// A size that is missing, not finite or not positive makes its particle
/// malformed.
pub fn check_particles_sized(
    disks: &[Disk],
    grains: &[Grain],
    domain: &Domain,
    grading: Option<&Grading>,
    sizes: &[f64],
) -> Check {
    never_stopped(run(
        disks,
        grains,
        domain,
        grading,
        Some(sizes),
        None,
        &Cancel::new(),
    ))
}

/// [`check_particles_sized`] (with `sizes` `None`, the diameters 2·r:
/// [`check_particles`]; with `grains` empty too, [`check`]) that stops when
/// `cancel` is raised: a front end's check of a large table a user may
/// interrupt.
///
/// # Errors
/// [`Cancelled`] when `cancel` stops it (polled once per particle in the
/// pair search, the one part that may take long).
pub fn check_cancellable(
    disks: &[Disk],
    grains: &[Grain],
    domain: &Domain,
    grading: Option<&Grading>,
    sizes: Option<&[f64]>,
    cancel: &Cancel,
) -> Result<Check, Cancelled> {
    run(disks, grains, domain, grading, sizes, None, cancel)
}

/// [`check_cancellable`] without a grading, whose pair search of disks
/// takes its index from `shared` when it is theirs and every disk is
/// well formed: the index a measure of the same packing uses, built once
/// for both. The search itself stays the check's own.
///
/// # Errors
/// [`Cancelled`] when `cancel` stops it.
pub(crate) fn check_sharing(
    disks: &[Disk],
    grains: &[Grain],
    domain: &Domain,
    shared: &SharedIndex<'_>,
    cancel: &Cancel,
) -> Result<Check, Cancelled> {
    run(disks, grains, domain, None, None, Some(shared), cancel)
}

/// The result of a check whose token is never raised and has no deadline.
fn never_stopped(check: Result<Check, Cancelled>) -> Check {
    match check {
        Ok(check) => check,
        Err(_) => unreachable!("a fresh token without a deadline never stops a check"),
    }
}

/// The check of [`check`], [`check_particles`] and
/// [`check_particles_sized`]: grains empty for disks, sizes `None` for
/// the diameters 2·r, the disks' index from `shared` where it serves.
fn run(
    disks: &[Disk],
    grains: &[Grain],
    domain: &Domain,
    grading: Option<&Grading>,
    sizes: Option<&[f64]>,
    shared: Option<&SharedIndex<'_>>,
    cancel: &Cancel,
) -> Result<Check, Cancelled> {
    let shaped = !grains.is_empty();
    let particles = if shaped {
        disks.len().max(grains.len())
    } else {
        disks.len()
    };
    let well_formed = |i: usize| {
        let d = &disks[i];
        let size = sizes.is_none_or(|s| s.get(i).is_some_and(|v| v.is_finite() && *v > 0.0));
        size && if shaped {
            grains.get(i).is_some_and(|g| particles::well_formed(d, g))
        } else {
            d.c.x.is_finite() && d.c.y.is_finite() && d.r.is_finite() && d.r > 0.0
        }
    };
    // The well-formed disks, 4 bytes each (ids below 2³², as every index's).
    let mut ok: Vec<u32> = Vec::with_capacity(disks.len());
    ok.extend(
        (0..disks.len())
            .filter(|&i| well_formed(i))
            .map(|i| i as u32),
    );
    let ok_ids = || ok.iter().map(|&i| i as usize);

    // Particles: their bounding circles (radius 0 where malformed, never
    // looked at) and their turned outlines.
    // A superellipse's circumradius is b times its unit outline's (support
    // values scale with it; the rounding is far inside the bound's own
    // slack), computed once per aspect and exponents.
    let mut unit_reach: HashMap<[u64; 3], f64> = HashMap::new();
    let mut reach_of = |o: &Outline| match *o {
        Outline::Superellipse { a, b, alpha, beta } => {
            let key = [(a / b).to_bits(), alpha.to_bits(), beta.to_bits()];
            let unit = unit_reach.entry(key).or_insert_with(|| {
                Outline::Superellipse {
                    a: a / b,
                    b: 1.0,
                    alpha,
                    beta,
                }
                .circumradius()
            });
            b * *unit
        }
        Outline::Polygon { .. } => o.circumradius(),
    };
    let reach: Vec<Disk> = if shaped {
        (0..disks.len())
            .map(|i| Disk {
                c: disks[i].c,
                r: grains.get(i).map_or(0.0, |g| reach_of(&g.outline)),
            })
            .collect()
    } else {
        Vec::new()
    };
    let turned: Vec<Turned> = grains.iter().map(Grain::turned).collect();
    let p = if shaped {
        particles::pairs(disks, &turned, &reach, &ok, domain, cancel)?
    } else {
        overlapping_pairs(disks, &ok, domain, shared, cancel)?
    };
    let (overlaps, worst_overlap, pairs_certified) = (p.overlaps, p.worst, p.certified);
    let overlaps_complete = p.complete;

    let sized = if shaped { &reach } else { disks };
    let r_max = ok_ids().fold(0.0f64, |m, i| m.max(sized[i].r));
    let tolerance = OVERLAP_REL * 2.0 * r_max;
    let mut outside = 0;
    let mut worst_outside: Option<(usize, f64)> = None;
    let (lo, hi) = domain.bounds();
    for i in ok_ids() {
        let d = &disks[i];
        let beyond = if shaped {
            particles::beyond(&turned[i], d.c, reach[i].r, domain, tolerance)
        } else if domain.is_periodic() {
            (lo.x - d.c.x)
                .max(d.c.x - hi.x)
                .max(lo.y - d.c.y)
                .max(d.c.y - hi.y)
        } else {
            d.r - domain.signed_distance(d.c)
        };
        if beyond > tolerance {
            outside += 1;
            if worst_outside.is_none_or(|(_, w)| beyond > w) {
                worst_outside = Some((i, beyond));
            }
        }
    }

    let domain_area = domain.area();
    let solid_area = solid_area(ok_ids().map(|i| &disks[i]));
    Ok(Check {
        particles,
        malformed: particles - ok.len(),
        overlaps,
        overlaps_complete,
        worst_overlap,
        pairs_certified,
        outside,
        worst_outside,
        domain_area,
        solid_area,
        porosity: porosity(solid_area, domain_area),
        grading: grading.map_or(GradingCheck::NotAsked, |g| {
            // Listed only when asked for, and sorted where they are.
            GradingCheck::of(ok.len(), || {
                let size = |i: usize| sizes.map_or(2.0 * disks[i].r, |s| s[i]);
                let mut sizes = ok_ids().map(size).collect::<Vec<_>>();
                // Sorted on every thread first, to the order the sort
                // inside asks (sizes equal by value are equal bit for bit
                // when positive; any other makes the distance 1 anyway).
                sizes.par_sort_unstable_by(f64::total_cmp);
                g.ks_distance_sorting(&mut sizes)
            })
        }),
        ks_limit: ks_limit(ok.len()),
    })
}

/// The largest KS distance `n` sizes may lie from their grading and still
/// follow it: the sampling noise of their number (1.36/√n, the 95 % quantile
/// of the KS statistic) plus [`KS_MARGIN`].
pub fn ks_limit(n: usize) -> f64 {
    1.36 / (n.max(1) as f64).sqrt() + KS_MARGIN
}

/// Whether `n` well-formed sizes at KS distance `ks` from their grading
/// follow it, as `gapack verify` judges a packing table: within
/// [`ks_limit`]`(n)`, or too few to check ([`MIN_GRADING_DISKS`]). The
/// one rule for a run's `grading_kept` and its warning.
pub fn grading_kept(n: usize, ks: f64) -> bool {
    GradingCheck::of(n, || ks)
        .ks()
        .is_none_or(|ks| ks <= ks_limit(n))
}

/// Count the overlapping pairs among `disks[ok]` and find the deepest (of
/// equally deep pairs, the first by index); count too the pairs that meet
/// without overlapping beyond the tolerance.
///
/// A disk stops its search [`VISITS_AFTER_OVERLAP`] partners after its
/// first overlap ([`Search`]): the count is then a lower bound, the
/// deepest pair the deepest tested; a disk that overlaps nothing tests
/// every partner within reach.
///
/// Identical disks (centre and radius equal bit for bit) are tested as one
/// ([`Groups`]): a group of k overlaps itself in k(k − 1)/2 pairs, and each
/// pair of groups (or a group and its own image) found below stands for the
/// product of their sizes. Without it, n copies of one disk cost n²/2 tests.
///
/// The disks are bucketed by size class ([`ByRadius`]): each looks for
/// partners in every class as far as its own radius plus that class's
/// largest radius, and tests those of lower index. Cells sized by the
/// largest radius made each fine disk of a wide grading test thousands.
///
/// In a periodic cell each disk looks around itself shifted back by every
/// lattice shift whose images reach it ([`Domain::image_shifts`]), and
/// tests the partners found there at their shifted image; a disk meets its
/// own images (each pair of opposite shifts once) as a pair with itself.
///
/// # Errors
/// [`Cancelled`] when `cancel` stops it (polled once per disk).
fn overlapping_pairs(
    disks: &[Disk],
    ok: &[u32],
    domain: &Domain,
    shared: Option<&SharedIndex<'_>>,
    cancel: &Cancel,
) -> Result<particles::Pairs, Cancelled> {
    if ok.len() < 2 && !domain.is_periodic() {
        return Ok(particles::Pairs {
            overlaps: 0,
            worst: None,
            certified: 0,
            complete: true,
        });
    }
    // First with each disk on its own: a packing with no two identical
    // disks (the usual one) needs no sort of them. When that search meets
    // a copy, or stops short (it may have missed one), the disks are
    // searched again with the copies grouped.
    // Every disk well formed: the shared index is the one this search
    // would build (every disk, in order).
    let shared = shared
        .filter(|_| ok.len() == disks.len())
        .and_then(|s| s.of(disks));
    let (pairs, copies) = search_pairs(disks, ok, None, domain, shared, cancel)?;
    if !copies && pairs.complete {
        return Ok(pairs);
    }
    let groups = Groups::of(disks, ok);
    Ok(search_pairs(disks, &groups.firsts, Some(&groups), domain, None, cancel)?.0)
}

/// The pair search of [`overlapping_pairs`] over the disks `firsts`
/// (each standing for its group in `groups`, or for itself alone), and
/// whether it met two identical disks (always false with groups). With
/// each disk alone, the first copy met stops the search: its other
/// figures are then of no use. `near`, when given, indexes `firsts`.
fn search_pairs(
    disks: &[Disk],
    firsts: &[u32],
    groups: Option<&Groups>,
    domain: &Domain,
    near: Option<&ByRadius>,
    cancel: &Cancel,
) -> Result<(particles::Pairs, bool), Cancelled> {
    let ids = || firsts.iter().map(|&i| i as usize);
    let own;
    let near = match near {
        Some(near) => near,
        None => {
            own = ByRadius::new(disks, ids());
            &own
        }
    };
    let r_max = ids().fold(0.0f64, |m, i| m.max(disks[i].r));
    let met = AtomicBool::new(false);
    // Fixed chunks of the groups, each with its own counts: sums
    // (saturating, of counts), the deepest pair (a total order), whether
    // every search went to its end and whether a copy was met are the
    // same whatever the number of threads.
    let parts = firsts
        .par_chunks(PAIR_CHUNK)
        .map(|chunk| {
            let mut part = particles::Pairs {
                overlaps: 0,
                worst: None,
                certified: 0,
                complete: true,
            };
            let mut search = Search::default();
            let mut copies = false;
            for &a in chunk {
                cancel.check()?;
                // Once a copy is met, the rest of this search is not used.
                if met.load(Ordering::Relaxed) {
                    break;
                }
                let a = a as usize;
                let at = Partners {
                    disks,
                    groups,
                    near,
                    r_max,
                    domain,
                };
                if at.pairs_of(a, &mut search, &mut part) {
                    copies = true;
                    met.store(groups.is_none(), Ordering::Relaxed);
                }
            }
            part.complete = search.complete;
            Ok((part, copies))
        })
        .collect::<Result<Vec<_>, Cancelled>>()?;
    let (inner_pairs, inner_worst) = groups.map_or((0, None), |g| (g.inner_pairs, g.inner_worst));
    Ok(parts.into_iter().fold(
        (
            particles::Pairs {
                overlaps: inner_pairs,
                worst: inner_worst,
                certified: 0,
                complete: true,
            },
            false,
        ),
        |(mut all, copies), (part, met)| {
            all.overlaps = all.overlaps.saturating_add(part.overlaps);
            all.certified = all.certified.saturating_add(part.certified);
            if let Some(pair) = part.worst {
                deeper(&mut all.worst, pair);
            }
            all.complete &= part.complete;
            (all, copies || met)
        },
    ))
}

/// Groups of disks one task of [`overlapping_pairs`] takes; a few in
/// tests, so that small packings are split.
const PAIR_CHUNK: usize = if cfg!(test) { 64 } else { 4096 };

/// What a disk's search for partners looks in: `near` indexes the disks
/// searched (each the first of its group in `groups`, or itself alone),
/// `r_max` their largest radius.
struct Partners<'a> {
    disks: &'a [Disk],
    groups: Option<&'a Groups>,
    near: &'a ByRadius,
    r_max: f64,
    domain: &'a Domain,
}

impl Partners<'_> {
    /// Disks disk (group) `a` stands for.
    fn size(&self, a: usize) -> usize {
        self.groups.map_or(1, |g| g.size[a] as usize)
    }

    /// The pairs of disk (group) `a` with those of lower index and its own
    /// images, added to `part`; whether one of them is a copy of `a`
    /// (centre and radius equal bit for bit), which stops the search of
    /// disks alone (with no groups).
    fn pairs_of(&self, a: usize, search: &mut Search, part: &mut particles::Pairs) -> bool {
        let p = &self.disks[a];
        let ka = self.size(a);
        let mut copy = false;
        // The box of every centre within reach of an overlap with `p`.
        let (lo, hi) = Disk::new(p.c.x, p.c.y, p.r + self.r_max).bounds();
        search.start();
        for v in self.domain.image_shifts(lo, hi) {
            let zero = v == Vector2::zeros();
            let stopped = self.near.try_visit(p.c - v, p.r, |b| {
                search.visit()?;
                let q = &self.disks[b];
                // A copy met either way round (not the disk itself).
                if zero
                    && b != a
                    && [p.c.x, p.c.y, p.r].map(f64::to_bits)
                        == [q.c.x, q.c.y, q.r].map(f64::to_bits)
                {
                    copy = true;
                    // Disks alone: the search is made again with groups.
                    if self.groups.is_none() {
                        return ControlFlow::Break(());
                    }
                }
                // Each pair once: the partner of lower index, or the disk's
                // own image of the shift that comes first.
                if b > a || (b == a && (zero || (v.y, v.x) < (0.0, 0.0))) {
                    return ControlFlow::Continue(());
                }
                // The member pairs this pair stands for: every member of one
                // group with every member of the other; a group with its own
                // image at ±v, k² (each member with its own image once, and
                // with each other member's at v and at −v).
                let members = ka.saturating_mul(self.size(b));
                let sum = p.r + q.r;
                let at = if zero { q.c } else { q.c + v };
                let overlap = (sum - (p.c - at).norm()) / sum;
                if (0.0..=OVERLAP_REL).contains(&overlap) {
                    part.certified = part.certified.saturating_add(members);
                }
                if overlap > OVERLAP_REL {
                    search.overlapped = true;
                    part.overlaps = part.overlaps.saturating_add(members);
                    // The groups' first members: the first pair of these
                    // groups by index.
                    deeper(&mut part.worst, (b, a, overlap));
                }
                ControlFlow::Continue(())
            });
            if stopped.is_break() {
                break;
            }
        }
        copy
    }
}

/// One disk's search for partners at a time: it stops
/// [`VISITS_AFTER_OVERLAP`] visits after the disk's first overlap, and
/// says whether any search stopped short.
pub(crate) struct Search {
    /// Partners the current disk visited.
    visited: usize,
    /// Whether the current disk overlaps one of them.
    pub(crate) overlapped: bool,
    /// Whether every search so far went to its end.
    pub(crate) complete: bool,
}

impl Default for Search {
    fn default() -> Self {
        Search {
            visited: 0,
            overlapped: false,
            complete: true,
        }
    }
}

impl Search {
    /// A new disk's search.
    pub(crate) fn start(&mut self) {
        self.visited = 0;
        self.overlapped = false;
    }

    /// One more partner visited: break once the disk has overlapped one
    /// and visited [`VISITS_AFTER_OVERLAP`] more than that.
    pub(crate) fn visit(&mut self) -> ControlFlow<()> {
        self.visited += 1;
        if self.overlapped && self.visited > VISITS_AFTER_OVERLAP {
            self.complete = false;
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

/// Make `worst` the deeper of itself and `pair` (of equally deep pairs,
/// the first by index).
fn deeper(worst: &mut Option<(usize, usize, f64)>, pair: (usize, usize, f64)) {
    let (b, a, overlap) = pair;
    if worst.is_none_or(|(x, y, w)| overlap > w || (overlap == w && (b, a) < (x, y))) {
        *worst = Some(pair);
    }
}

/// The well-formed disks with identical ones (centre and radius equal bit
/// for bit) taken together, found by one sort: O(n log n).
struct Groups {
    /// The first member (lowest index) of each group, in index order.
    firsts: Vec<u32>,
    /// Per disk index, the size of the group it is the first of (0 for
    /// the others).
    size: Vec<u32>,
    /// The overlapping pairs inside the groups: k(k − 1)/2 for k copies.
    inner_pairs: usize,
    /// The first pair inside a group by index (overlap 1, the deepest
    /// there is), if any group has two members.
    inner_worst: Option<(usize, usize, f64)>,
}

impl Groups {
    /// The groups of `disks[ok]`.
    fn of(disks: &[Disk], ok: &[u32]) -> Self {
        let key = |i: u32| {
            let d = &disks[i as usize];
            (d.c.x.to_bits(), d.c.y.to_bits(), d.r.to_bits())
        };
        let mut sorted = ok.to_vec();
        // The keys are distinct (each ends with its disk's index): the
        // order is the same whatever the number of threads.
        sorted.par_sort_unstable_by_key(|&i| (key(i), i));
        let mut firsts = Vec::new();
        let mut size = vec![0u32; disks.len()];
        let mut inner_pairs = 0usize;
        let mut inner_worst = None;
        for group in sorted.chunk_by(|&i, &j| key(i) == key(j)) {
            let first = group[0];
            let k = group.len();
            firsts.push(first);
            size[first as usize] = k as u32;
            if let [g0, g1, ..] = *group {
                // Concentric: overlap (sum − 0) / sum = 1.
                let pairs = k as u64 * (k as u64 - 1) / 2;
                inner_pairs =
                    inner_pairs.saturating_add(usize::try_from(pairs).unwrap_or(usize::MAX));
                deeper(&mut inner_worst, (g0 as usize, g1 as usize, 1.0));
            }
        }
        firsts.par_sort_unstable();
        Groups {
            firsts,
            size,
            inner_pairs,
            inner_worst,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn disk(x: f64, y: f64, r: f64) -> Disk {
        Disk {
            c: Point::new(x, y),
            r,
        }
    }

    /// Every pair by brute force: the reference the cell sweep must match.
    fn brute_force(disks: &[Disk]) -> usize {
        let mut n = 0;
        for i in 0..disks.len() {
            for j in i + 1..disks.len() {
                let sum = disks[i].r + disks[j].r;
                if (sum - (disks[i].c - disks[j].c).norm()) / sum > OVERLAP_REL {
                    n += 1;
                }
            }
        }
        n
    }

    #[test]
    fn finds_every_overlap_the_brute_force_finds() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let domain = Domain::rectangle(30.0, 20.0).unwrap();
        for _ in 0..20 {
            let disks: Vec<Disk> = (0..300)
                .map(|_| {
                    disk(
                        rng.gen_range(0.0..30.0),
                        rng.gen_range(0.0..20.0),
                        rng.gen_range(0.05..1.0),
                    )
                })
                .collect();
            let c = check(&disks, &domain, None);
            assert_eq!(c.overlaps, brute_force(&disks));
            assert!(c.overlaps > 0);
        }
    }

    /// The deepest pair by brute force (of equally deep, the first by index).
    fn brute_worst(disks: &[Disk]) -> Option<(usize, usize, f64)> {
        let mut worst = None;
        for j in 0..disks.len() {
            for i in 0..j {
                let sum = disks[i].r + disks[j].r;
                let overlap = (sum - (disks[i].c - disks[j].c).norm()) / sum;
                if overlap > OVERLAP_REL {
                    deeper(&mut worst, (i, j, overlap));
                }
            }
        }
        worst
    }

    #[test]
    fn copies_of_disks_count_as_the_brute_force_counts() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
        let domain = Domain::rectangle(30.0, 20.0).unwrap();
        for _ in 0..20 {
            let mut disks: Vec<Disk> = (0..200)
                .map(|_| {
                    disk(
                        rng.gen_range(0.0..30.0),
                        rng.gen_range(0.0..20.0),
                        rng.gen_range(0.05..0.6),
                    )
                })
                .collect();
            // Copies of some, anywhere in the list.
            for _ in 0..100 {
                let copy = disks[rng.gen_range(0..disks.len())];
                disks.insert(rng.gen_range(0..=disks.len()), copy);
            }
            let c = check(&disks, &domain, None);
            assert_eq!(c.overlaps, brute_force(&disks));
            assert_eq!(c.worst_overlap, brute_worst(&disks));
            assert_eq!(c.worst_overlap.map(|w| w.2), Some(1.0));
        }
    }

    #[test]
    fn copies_count_as_near_copies_do_in_a_periodic_cell() {
        // Copies against copies moved by 10⁻⁹ mm, which the pair search
        // tests one by one: the same pairs overlap and meet, at every
        // image; the disk at (0.3, 5) overlaps its own images across the
        // edge of the 1.6 mm wide cell.
        let domain = Domain::periodic_rectangle(1.6, 10.0).unwrap();
        let base = [
            disk(0.3, 5.0, 1.0),
            disk(1.2, 2.0, 0.4),
            disk(1.2, 8.0, 0.3),
        ];
        let copies: Vec<Disk> = (0..5).flat_map(|_| base).collect();
        let near: Vec<Disk> = copies
            .iter()
            .enumerate()
            .map(|(k, d)| disk(d.c.x + 1e-9 * k as f64, d.c.y, d.r))
            .collect();
        let (a, b) = (check(&copies, &domain, None), check(&near, &domain, None));
        assert!(a.overlaps > 5 * 4 / 2 * 3, "{a:?}");
        assert_eq!(
            (a.overlaps, a.pairs_certified),
            (b.overlaps, b.pairs_certified)
        );
        assert_eq!(a.worst_overlap, Some((0, 3, 1.0)));
    }

    #[test]
    fn copies_of_one_disk_are_counted_without_testing_each_pair() {
        // 20 000 copies: 2·10⁸ pairs, all overlapping, counted from one group.
        let n = 20_000;
        let disks = vec![disk(5.0, 5.0, 1.0); n];
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        // On a pool of one thread: the visits are counted per thread.
        let (c, visited) = on_threads(1, || {
            crate::metrics::near::VISITED.with(|v| v.set(0));
            let c = check(&disks, &domain, None);
            (c, crate::metrics::near::VISITED.with(std::cell::Cell::get))
        });
        assert!(visited < 10, "{visited} disks visited");
        assert!(!c.valid());
        assert_eq!(c.overlaps, n * (n - 1) / 2);
        assert_eq!(c.worst_overlap, Some((0, 1, 1.0)));
        // And one other disk beside them overlaps each copy.
        let mut more = disks;
        more.push(disk(6.0, 5.0, 1.0));
        let c = check(&more, &domain, None);
        assert_eq!(c.overlaps, n * (n - 1) / 2 + n);
    }

    #[test]
    fn nearly_coincident_disks_are_judged_without_testing_each_pair() {
        // 5 000 disks a nanometre apart: 1.25·10⁷ pairs, all overlapping,
        // all in one cell. Each disk stops a bounded number of visits
        // after its first overlap.
        let n = 5_000;
        let disks: Vec<Disk> = (0..n)
            .map(|k| {
                let t = k as f64;
                disk(
                    5.0 + 1e-9 * (t * 0.37).sin(),
                    5.0 + 1e-9 * (t * 0.61).cos(),
                    1.0,
                )
            })
            .collect();
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        // On a pool of one thread: the visits are counted per thread.
        let (c, visited) = on_threads(1, || {
            crate::metrics::near::VISITED.with(|v| v.set(0));
            let c = check(&disks, &domain, None);
            (c, crate::metrics::near::VISITED.with(std::cell::Cell::get))
        });
        // Twice: a search that stops short may have missed a copy, so the
        // disks are searched again with the copies grouped.
        assert!(
            visited < 2 * (n * (VISITS_AFTER_OVERLAP + 2)) as u64,
            "{visited} disks visited"
        );
        assert!(!c.valid());
        assert!(!c.overlaps_complete);
        assert!(c.overlaps >= n - 1, "{c:?}");
        let (a, b, depth) = c.worst_overlap.expect("an overlap");
        assert!(a < b && depth > 0.999_999, "{c:?}");
        // The deepest pair tested is as deep as the brute force's to
        // within the jitter.
        let best = brute_worst(&disks).expect("an overlap").2;
        assert!(best - depth < 1e-9, "{best} {depth}");
        // Spread out into a valid packing, every pair is tested as before.
        let apart: Vec<Disk> = (0..n)
            .map(|k| {
                disk(
                    1.0 + 2.0 * (k % 100) as f64,
                    1.0 + 2.0 * (k / 100) as f64,
                    1.0,
                )
            })
            .collect();
        let domain = Domain::rectangle(200.0, 100.0).unwrap();
        let c = check(&apart, &domain, None);
        assert!(c.valid() && c.overlaps_complete, "{c:?}");
        assert_eq!(c.pairs_certified, 99 * 50 + 100 * 49);
    }

    #[test]
    fn a_raised_token_stops_the_check() {
        let disks = vec![disk(5.0, 5.0, 1.0), disk(6.0, 5.0, 1.0)];
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        let cancel = Cancel::new();
        let told = check_cancellable(&disks, &[], &domain, None, None, &cancel);
        assert_eq!(told.map(|c| c.overlaps), Ok(1));
        cancel.cancel();
        let told = check_cancellable(&disks, &[], &domain, None, None, &cancel);
        assert_eq!(told, Err(Cancelled::Flag));
    }

    #[test]
    fn fine_disks_beside_a_coarse_one_test_only_their_neighbours() {
        // A wide grading: 10 000 touching disks of radius 0.01 mm on a
        // lattice, and one of radius 1 mm touching the lattice's corner
        // disk. Cells sized by the largest radius (2 mm) put the whole
        // lattice in a few cells: each fine disk tested thousands.
        let mut disks: Vec<Disk> = (0..100 * 100)
            .map(|k| {
                disk(
                    0.01 + 0.02 * (k % 100) as f64,
                    0.01 + 0.02 * (k / 100) as f64,
                    0.01,
                )
            })
            .collect();
        let gap = 0.01 + 1.0;
        disks.push(disk(
            1.99 + gap / 2f64.sqrt(),
            1.99 + gap / 2f64.sqrt(),
            1.0,
        ));
        let domain = Domain::rectangle(4.0, 4.0).unwrap();
        // On a pool of one thread: the visits are counted per thread.
        let (c, visited) = on_threads(1, || {
            crate::metrics::near::VISITED.with(|v| v.set(0));
            let c = check(&disks, &domain, None);
            (c, crate::metrics::near::VISITED.with(std::cell::Cell::get))
        });
        assert!(c.valid(), "{c:?}");
        let per_disk = visited as f64 / disks.len() as f64;
        assert!(per_disk < 30.0, "{per_disk} disks visited per disk");
        // The coarse disk still meets a fine one it overlaps.
        disks.push(disk(1.99 + 0.3, 1.99 + 0.3, 0.01));
        let c = check(&disks, &domain, None);
        assert_eq!(
            (c.overlaps, c.worst_overlap.map(|w| (w.0, w.1))),
            (1, Some((10_000, 10_001)))
        );
    }

    #[test]
    fn tangent_disks_inside_pass() {
        let domain = Domain::rectangle(4.0, 2.0).unwrap();
        let disks = [disk(1.0, 1.0, 1.0), disk(3.0, 1.0, 1.0)];
        let c = check(&disks, &domain, Some(&Grading::constant(2.0).unwrap()));
        assert!(c.valid(), "{c:?}");
        assert!(c.grading_kept());
        assert_eq!(c.grading, GradingCheck::TooFewDisks(2));
        assert!((c.porosity - (1.0 - std::f64::consts::PI / 4.0)).abs() < 1e-12);
    }

    #[test]
    fn overlap_outside_and_malformed_are_each_caught() {
        let domain = Domain::rectangle(4.0, 2.0).unwrap();
        let overlap = [disk(1.0, 1.0, 1.0), disk(2.9, 1.0, 1.0)];
        let c = check(&overlap, &domain, None);
        assert_eq!((c.overlaps, c.outside), (1, 0));
        let (a, b, w) = c.worst_overlap.unwrap();
        assert_eq!((a, b), (0, 1));
        assert!((w - 0.05).abs() < 1e-12);

        let out = [disk(1.0, 1.0, 1.0), disk(3.5, 1.0, 0.6)];
        let c = check(&out, &domain, None);
        assert_eq!((c.overlaps, c.outside), (0, 1));
        let (i, by) = c.worst_outside.unwrap();
        assert_eq!(i, 1);
        assert!((by - 0.1).abs() < 1e-12);

        let bad = [
            disk(1.0, 1.0, 1.0),
            disk(f64::NAN, 1.0, 0.5),
            disk(3.0, 1.0, 0.0),
        ];
        let c = check(&bad, &domain, None);
        assert_eq!(c.malformed, 2);
        assert!(!c.valid());
    }

    #[test]
    fn min_grading_disks_is_the_fewest_a_grading_check_can_fail_with() {
        // The KS distance is at most 1: with fewer disks the limit is out of reach.
        assert!(ks_limit(MIN_GRADING_DISKS - 1) >= 1.0);
        assert!(ks_limit(MIN_GRADING_DISKS) < 1.0);
        // Two disks far off a 1–2 mm grading are not checked, three are failed.
        let domain = Domain::rectangle(100.0, 100.0).unwrap();
        let grading = Grading::uniform(1.0, 2.0, crate::Basis::Number).unwrap();
        let disks: Vec<Disk> = (0..3)
            .map(|i| disk(10.0 + 20.0 * f64::from(i), 50.0, 5.0))
            .collect();
        let two = check(&disks[..2], &domain, Some(&grading));
        assert_eq!(two.grading, GradingCheck::TooFewDisks(2));
        let three = check(&disks, &domain, Some(&grading));
        assert!(
            matches!(three.grading, GradingCheck::Measured(ks) if ks > 0.99),
            "{three:?}"
        );
        assert!(!three.grading_kept());
        assert_eq!(check(&disks, &domain, None).grading, GradingCheck::NotAsked);
    }

    #[test]
    fn sizes_off_the_grading_are_flagged() {
        let domain = Domain::rectangle(100.0, 100.0).unwrap();
        let disks: Vec<Disk> = (0..100)
            .map(|i| {
                disk(
                    5.0 + 10.0 * (i % 10) as f64,
                    5.0 + 10.0 * (i / 10) as f64,
                    1.0,
                )
            })
            .collect();
        let grading = Grading::uniform(1.0, 4.0, crate::Basis::Number).unwrap();
        let c = check(&disks, &domain, Some(&grading));
        assert!(c.valid());
        assert!(!c.grading_kept(), "{c:?}");
    }

    /// `f` run on a pool of `threads` threads.
    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    #[test]
    fn the_check_is_the_same_on_one_and_four_threads() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(17);
        let grading = Grading::uniform(0.2, 1.2, crate::Basis::Number).unwrap();
        for round in 0..12 {
            let domain = if round % 2 == 0 {
                Domain::rectangle(30.0, 20.0).unwrap()
            } else {
                Domain::periodic_rectangle(30.0, 20.0).unwrap()
            };
            let mut disks: Vec<Disk> = (0..400 + 100 * round)
                .map(|_| {
                    disk(
                        rng.gen_range(-0.5..30.5),
                        rng.gen_range(-0.5..20.5),
                        rng.gen_range(0.1..0.6),
                    )
                })
                .collect();
            for _ in 0..50 {
                let copy = disks[rng.gen_range(0..disks.len())];
                disks.insert(rng.gen_range(0..=disks.len()), copy);
            }
            disks.push(disk(f64::NAN, 1.0, 0.5));
            let one = on_threads(1, || check(&disks, &domain, Some(&grading)));
            let four = on_threads(4, || check(&disks, &domain, Some(&grading)));
            assert_eq!(format!("{one:?}"), format!("{four:?}"));
            assert!(one.overlaps > 50 && one.malformed == 1, "{one:?}");
            if !domain.is_periodic() {
                assert_eq!(one.overlaps, brute_force(&disks[..disks.len() - 1]));
                assert_eq!(one.worst_overlap, brute_worst(&disks[..disks.len() - 1]));
                assert!(one.outside > 0, "{one:?}");
            }
        }
    }

    #[test]
    fn a_planted_overlap_copy_or_disk_outside_is_caught_among_many() {
        // 250 × 200 disks of radius 0.45 on a 1 mm lattice: a valid
        // packing of 50 000 disks, in many chunks.
        let (nx, ny) = (250, 200);
        let lattice: Vec<Disk> = (0..nx * ny)
            .map(|k| disk(0.5 + (k % nx) as f64, 0.5 + (k / nx) as f64, 0.45))
            .collect();
        let domain = Domain::rectangle(nx as f64, ny as f64).unwrap();
        let run = |disks: &[Disk]| on_threads(4, || check(disks, &domain, None));
        let c = run(&lattice);
        assert!(c.valid() && c.overlaps_complete, "{c:?}");
        assert_eq!(c.pairs_certified, 0);
        let planted = 31_337;
        // One disk moved half a millimetre onto its right neighbour.
        let mut moved = lattice.clone();
        moved[planted].c.x += 0.5;
        let c = run(&moved);
        assert_eq!(
            (c.overlaps, c.outside, c.worst_overlap.map(|w| (w.0, w.1))),
            (1, 0, Some((planted, planted + 1)))
        );
        // A copy of one disk, last: it overlaps its original, wholly.
        let mut copied = lattice.clone();
        copied.push(lattice[planted]);
        let c = run(&copied);
        assert_eq!(
            (c.overlaps, c.outside, c.worst_overlap),
            (1, 0, Some((planted, nx * ny, 1.0)))
        );
        // A disk of the last row pushed through the top wall.
        let mut out = lattice.clone();
        let top = nx * ny - 7;
        out[top].c.y += 0.3;
        let c = run(&out);
        assert_eq!((c.overlaps, c.outside), (0, 1), "{c:?}");
        assert_eq!(c.worst_outside.map(|w| w.0), Some(top));
    }
}
