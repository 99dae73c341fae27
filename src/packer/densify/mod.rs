//! Densify: disks of the drawn sizes placed at a target porosity below the
//! advancing front's, their overlap energy minimised to zero with FIRE.
//!
//! # Behavior
//! The disks are the first sizes `pack` draws, never shrunk, as many as
//! bring their area nearest to the target's solid area: the area inside the
//! walls (less a strip half a wall disk wide with `walls = "disks"`, as
//! relaxation counts it) × (1 − porosity), about that area over the
//! grading's mean disk area. Centres start uniform inside the domain. The
//! energy is harmonic in the overlaps: ½·δ² for each pair of disks
//! (δ = r₁ + r₂ − distance), each disk and wall disk, and each disk and
//! exact wall ([`walls`]), every contact distance widened by [`MARGIN`] of
//! itself. FIRE (Bitzek et al. 2006, with the corrections of Guénolé et al.
//! 2020) minimises it over Verlet lists (cells, rebuilt once a disk has
//! moved half the skin). Below the jamming limit the minimum is zero: the
//! run stops once no widened contact overlaps by more than half the margin,
//! so every pair ends at least [`MARGIN`]/2 of its radii sum apart and every
//! disk as far inside its walls; an exact recount (a fresh neighbour search,
//! the domain's own signed distance) confirms it before the packing is
//! returned.
//!
//! Where the target is denser than the disks pack (they jam: the minimum is
//! above zero, the overlaps held in balance) or the step budget runs out, no
//! packing is returned: [`PackError::DensityUnreached`] gives the densest
//! porosity the same disks were packed at without overlap, found by
//! bisecting a common scale of their radii from the jammed state (O'Hern et
//! al. 2003), so the user knows which target to ask for.
//!
//! See `docs/densify.md` for the choice of algorithm and measurements.

mod cells;
mod system;
mod walls;

use std::cell::Cell;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::placed::{POSITION_STREAM, Placed, check_fits, radii};
use super::{PackError, Packing};
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::{Domain, Point};
use system::{Outcome, STALL_WINDOW, System};

/// Relative widening of every contact distance in the energy: a minimum
/// of zero leaves each pair at least half of it (relative to its radii sum)
/// apart, and each disk as far (relative to its radius) inside its walls.
/// Far above the write check's rounding, far below anything a porosity or
/// a DEM contact model feels (and within [`CONTACT_REL`], so touching disks
/// still count as contacts).
///
/// [`CONTACT_REL`]: crate::geometry::predicates::CONTACT_REL
pub const MARGIN: f64 = 4e-7;

/// The minimisation succeeds once no widened overlap exceeds this (relative).
const STOP: f64 = 0.5 * MARGIN;

/// Draws of a starting centre that keep the whole disk inside, then that
/// keep its centre inside, before a centre outside is taken (the walls pull
/// it in).
const START_DRAWS: usize = 64;

/// The squeezes of [`squeeze`]: how much denser than the target (in solid
/// fraction) the disks are packed before they are let out to their size.
const SQUEEZES: [(f64, u64); 3] = [(0.08, 250), (0.04, 1000), (0.02, 2500)];

/// Bisection steps of the scale in the search for the densest porosity reached.
const SEARCH_STEPS: u32 = 10;

/// Looser targets packed, at most, to find one to suggest ([`advice`]):
/// up to 0.031 looser than the densest reached.
const ADVICE_TRIES: u32 = 6;

/// Pack `scene` by densification at `packer.densify.porosity`.
///
/// # Errors
/// [`PackError::DomainTooNarrow`], [`PackError::TooManyWallDisks`], the
/// scene's particle and memory limits, [`PackError::Cancelled`], and
/// [`PackError::DensityUnreached`] when the target porosity is not reached
/// without overlap within `packer.densify.iterations` steps.
pub fn pack_densify(scene: &Scene, cancel: &Cancel) -> Result<Packing, PackError> {
    densify(scene, cancel, None, true)
}

/// The convergence of a densify run ([`densify_traced`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DensifyTrace {
    /// Disks packed (the sizes drawn for the target).
    pub disks: usize,
    /// Every 100 minimisation steps: (steps, the porosity at which the
    /// disks would be free of overlap at the centres they have then, their
    /// radii scaled by the largest factor those centres allow), on the
    /// target's area.
    pub points: Vec<[f64; 2]>,
}

/// `pack_densify`, and its convergence.
///
/// # Errors
/// As `pack_densify`; the trace is returned either way (without points
/// if the run stopped before its first step).
pub fn densify_traced(
    scene: &Scene,
    cancel: &Cancel,
) -> (Result<Packing, PackError>, DensifyTrace) {
    let mut trace = DensifyTrace::default();
    let result = densify(scene, cancel, Some(&mut trace), true);
    (result, trace)
}

/// [`pack_densify`] without the search for a target that packs when the
/// target is not reached (its error's `advice` is `None`): for callers that
/// step through targets themselves.
///
/// # Errors
/// As [`pack_densify`].
pub(crate) fn pack_densify_unadvised(scene: &Scene, cancel: &Cancel) -> Result<Packing, PackError> {
    densify(scene, cancel, None, false)
}

/// [`pack_densify`], its trace into `trace` when given; when the target is
/// not reached and `advise`, looser targets are packed ([`advice`]) until
/// one is, to name it.
fn densify(
    scene: &Scene,
    cancel: &Cancel,
    mut trace: Option<&mut DensifyTrace>,
    advise: bool,
) -> Result<Packing, PackError> {
    check_fits(scene)?;
    let settings = scene.packer.densify;
    let placed = Placed::new(scene);
    let free = (scene.domain.area() - scene.domain.perimeter() * placed.wall_r).max(0.0);
    let Run {
        mut sys,
        outcome,
        mut steps,
        n,
        solid,
    } = run(
        scene,
        &placed,
        free,
        settings.porosity,
        cancel,
        trace.is_some(),
    )?;
    let mut record = |sys: &System<'_>| {
        if let Some(t) = trace.as_deref_mut() {
            t.disks = n;
            t.points.extend(sys.trace().iter().map(|&(k, c)| {
                let c = c.clamp(0.0, 1.0);
                [k as f64, 1.0 - c * c * solid / free]
            }));
        }
    };
    // The exact recount: converged means every gap is at least MARGIN / 2.
    if packed(&sys, outcome) {
        record(&sys);
        let disks = sys.disks();
        drop(sys);
        let mut stats = placed.stats;
        stats.sizes_drawn = n as u64;
        stats.front_attempts = steps;
        let mut packing = placed.into_packing();
        packing.disks = disks;
        packing.stats = stats;
        return Ok(packing);
    }
    let jammed = outcome == Outcome::Jammed;
    let budget = settings.iterations as u64;
    let scale = densest_scale(&mut sys, budget, &mut steps, cancel)?;
    record(&sys);
    drop(sys);
    // Of the same area as the target, so that asking for it packs as many disks.
    let reached = 1.0 - scale * scale * solid / free;
    let advice = if advise {
        advice(scene, &placed, free, reached, cancel)?
    } else {
        None
    };
    Err(PackError::DensityUnreached {
        target: settings.porosity,
        reached,
        scale,
        steps: u32::try_from(steps).unwrap_or(u32::MAX),
        jammed,
        advice,
    })
}

/// A minimisation of the drawn sizes at a porosity ([`run`]).
struct Run<'a> {
    /// The disks where it ended.
    sys: System<'a>,
    /// How it ended.
    outcome: Outcome,
    /// Steps taken.
    steps: u64,
    /// Disks drawn.
    n: usize,
    /// The disks' area.
    solid: f64,
}

/// Draw the sizes for `porosity` of the area `free`, start them at random
/// centres and squeeze them to it ([`squeeze`]): the whole of a densify run
/// but its search for the densest scale, the same for the same scene and
/// porosity. `trace`: record the convergence.
///
/// # Errors
/// The scene's particle and memory limits, [`PackError::Cancelled`].
fn run<'a>(
    scene: &'a Scene,
    placed: &'a Placed<'a>,
    free: f64,
    porosity: f64,
    cancel: &Cancel,
    trace: bool,
) -> Result<Run<'a>, PackError> {
    let r = sizes(scene, free * (1.0 - porosity), cancel)?;
    let n = r.len();
    let solid: f64 = r.iter().map(|x| std::f64::consts::PI * x * x).sum();
    let centres = start(&scene.domain, &r, scene.seed);
    let mut sys = System::new(
        &scene.domain,
        &centres,
        r,
        (&placed.disks, &placed.grid, placed.wall_r),
    );
    drop(centres);
    if trace {
        sys.start_trace();
    }
    let mut steps = 0u64;
    let budget = scene.packer.densify.iterations as u64;
    let outcome = squeeze(&mut sys, 1.0 - porosity, budget, &mut steps, cancel)?;
    Ok(Run {
        sys,
        outcome,
        steps,
        n,
        solid,
    })
}

/// Whether a minimisation packed its disks: converged, and the exact
/// recount finds every gap at least [`MARGIN`]/2.
fn packed(sys: &System<'_>, outcome: Outcome) -> bool {
    outcome == Outcome::Converged && sys.clearance() > 1.0
}

/// The target to suggest after a run reached `reached` but not its target:
/// the first of [`ADVICE_TRIES`] looser targets that packs, each packed as
/// asking for it would pack it ([`run`]). The first is `reached` rounded up
/// to 0.001 (and looser than the target: the disks drawn for a target lie
/// within one disk of it, so the densest reached may round below it); each
/// next one is looser by twice the last step (0.001, 0.002, 0.004, …). A
/// fresh run from random centres may jam looser than the densest scale
/// found from the jammed state, hence the tries. `None` when none packs
/// (or the next would not be below 1).
///
/// # Errors
/// [`PackError::Cancelled`], the scene's limits.
fn advice(
    scene: &Scene,
    placed: &Placed<'_>,
    free: f64,
    reached: f64,
    cancel: &Cancel,
) -> Result<Option<std::num::NonZeroU16>, PackError> {
    let target = scene.packer.densify.porosity;
    let up = (reached.max(target) * 1000.0).ceil();
    let mut thousandths = if up / 1000.0 > target { up } else { up + 1.0 };
    for k in 0..ADVICE_TRIES {
        let porosity = thousandths / 1000.0;
        if porosity >= 1.0 {
            break;
        }
        let Run { sys, outcome, .. } = run(scene, placed, free, porosity, cancel, false)?;
        if packed(&sys, outcome) {
            // Above the target and below 1: 1 to 999 thousandths.
            return Ok(std::num::NonZeroU16::new(thousandths as u16));
        }
        thousandths += f64::from(1u32 << k);
    }
    Ok(None)
}

/// The radii: the first sizes `pack` draws whose area comes nearest to
/// `solid` (at least one).
///
/// # Errors
/// The scene's particle or memory limit when they would pass it;
/// [`PackError::Cancelled`].
fn sizes(scene: &Scene, solid: f64, cancel: &Cancel) -> Result<Vec<f64>, PackError> {
    let stopped = Cell::new(None);
    let ceiling = super::disk_ceiling(scene);
    let mut r: Vec<f64> = Vec::new();
    let mut sum = 0.0;
    for x in radii(scene, cancel, &stopped) {
        let a = std::f64::consts::PI * x * x;
        if !r.is_empty() && sum + 0.5 * a > solid {
            break;
        }
        if let Some((max, error)) = &ceiling
            && r.len() as u64 >= *max
        {
            return Err(error.clone());
        }
        r.push(x);
        sum += a;
    }
    match stopped.get() {
        Some(why) => Err(why.into()),
        None => Ok(r),
    }
}

/// Uniform random centres inside `domain`, one per radius, drawn from the
/// positions' stream of `seed`: each the first of [`START_DRAWS`] draws
/// that keeps its disk inside the walls, else the first of as many that
/// keeps its centre inside, else the last draw (in a periodic cell, the
/// first draw).
fn start(domain: &Domain, r: &[f64], seed: u64) -> Vec<Point> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ POSITION_STREAM);
    let (lo, hi) = domain.bounds();
    let mut draw = || {
        Point::new(
            lo.x + (hi.x - lo.x) * rng.r#gen::<f64>(),
            lo.y + (hi.y - lo.y) * rng.r#gen::<f64>(),
        )
    };
    r.iter()
        .map(|&r| {
            let mut last = draw();
            if domain.is_periodic() {
                return last;
            }
            for need in [r, 0.0] {
                for _ in 0..START_DRAWS {
                    if domain.signed_distance(last) >= need {
                        return last;
                    }
                    last = draw();
                }
            }
            last
        })
        .collect()
}

/// Pack the disks at their size (solid fraction `solid`), squeezed first:
/// each squeeze minimises the energy with the radii scaled up to a solid
/// fraction [`SQUEEZES`] denser (the disks jam there, in a few thousand
/// steps), then at their size, from the jammed centres; the next squeeze,
/// gentler, runs only if the disks jam at their size.
///
/// # Behavior
/// Quenched from random centres at their size, the disks jam at a lower
/// density than from centres jammed at a higher one (Chaudhuri, Berthier and
/// Sastry 2010: the jamming density grows with the density the quench
/// starts from). Measured on the 50 × 100 mm box of 1–1.66 mm disks: from
/// random centres the disks jam at porosity 0.166–0.168, squeezed first by
/// 0.08 at 0.162–0.164, and a target of 0.17 is reached in 2,000–3,000
/// steps instead of 5,000–20,000.
fn squeeze(
    sys: &mut System<'_>,
    solid: f64,
    budget: u64,
    steps: &mut u64,
    cancel: &Cancel,
) -> Result<Outcome, PackError> {
    let mut outcome = Outcome::OutOfSteps;
    for (extra, w) in SQUEEZES {
        let scale = ((solid + extra) / solid).sqrt();
        if sys.minimise(scale, budget, w, steps, cancel)? == Outcome::OutOfSteps {
            break;
        }
        outcome = sys.minimise(1.0, budget, STALL_WINDOW, steps, cancel)?;
        if outcome != Outcome::Jammed {
            break;
        }
    }
    Ok(outcome)
}

/// The largest scale of the radii at which the disks were packed without
/// overlap, from the current (jammed or unfinished) state: a bisection
/// between the scale the current centres allow as they are and 1, each
/// trial minimised from the centres of the last, within what is left of
/// `budget`.
fn densest_scale(
    sys: &mut System<'_>,
    budget: u64,
    steps: &mut u64,
    cancel: &Cancel,
) -> Result<f64, PackError> {
    let mut lo = (sys.clearance() / (1.0 + MARGIN)).clamp(0.0, 1.0);
    let mut hi = 1.0;
    for round in 0..SEARCH_STEPS {
        let left = budget.saturating_sub(*steps);
        if left == 0 || hi - lo < 1e-4 {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let share = *steps + left / u64::from(SEARCH_STEPS - round);
        if sys.minimise(mid, share, STALL_WINDOW, steps, cancel)? == Outcome::Converged
            && sys.clearance() >= mid
        {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::WallMode;
    use crate::grading::{Basis, Grading};
    use crate::packer::{Method, pack};

    /// 1–1.66 mm disks (PFC's genesis grading) in a `w` × `h` box at `porosity`.
    fn scene(w: f64, h: f64, porosity: f64) -> Scene {
        let mut s = Scene::new(
            Domain::rectangle(w, h).unwrap(),
            Grading::uniform(1.0, 1.66, Basis::Number).unwrap(),
        )
        .with_method(Method::Densify)
        .with_seed(7);
        s.packer.densify.porosity = porosity;
        s
    }

    #[test]
    fn a_dense_target_packs_the_drawn_sizes_without_overlap() {
        let s = scene(20.0, 30.0, 0.18);
        let packing = pack(&s).unwrap();
        let c = crate::check::check(&packing.disks, &packing.domain, Some(&s.grading));
        assert!(c.valid(), "{c:?}");
        assert!((c.porosity - 0.18).abs() < 0.003, "{}", c.porosity);
        // The sizes are the first drawn, in order: those of relaxation.
        let stopped = Cell::new(None);
        let drawn: Vec<f64> = radii(&s, &Cancel::new(), &stopped)
            .take(packing.disks.len())
            .collect();
        let got: Vec<f64> = packing.disks.iter().map(|d| d.r).collect();
        assert_eq!(got, drawn);
        // Every gap keeps half the margin: the write check passes with room.
        let least = packing
            .disks
            .iter()
            .enumerate()
            .flat_map(|(i, a)| packing.disks[i + 1..].iter().map(move |b| (a, b)))
            .map(|(a, b)| (a.c - b.c).norm() / (a.r + b.r))
            .fold(f64::INFINITY, f64::min);
        assert!(least >= 1.0 + 0.5 * MARGIN * 0.999, "{least}");
    }

    #[test]
    fn wall_disks_and_a_concave_domain_are_kept_clear() {
        let mut s = scene(20.0, 20.0, 0.2).with_walls(WallMode::Disks);
        let packing = pack(&s).unwrap();
        let m = crate::metrics::measure(&packing, &s);
        assert!(m.max_overlap <= 0.0, "{}", m.max_overlap);
        assert!(!packing.boundary.is_empty());
        let l = [
            (0., 0.),
            (24., 0.),
            (24., 10.),
            (10., 10.),
            (10., 24.),
            (0., 24.),
        ];
        s = s
            .with_walls(WallMode::Exact)
            .with_domain(Domain::polygon(&l.map(|(x, y)| Point::new(x, y))).unwrap());
        let packing = pack(&s).unwrap();
        let c = crate::check::check(&packing.disks, &packing.domain, None);
        assert!(c.valid(), "{c:?}");
        assert!(
            packing
                .disks
                .iter()
                .all(|d| s.domain.signed_distance(d.c) >= d.r)
        );
    }

    #[test]
    fn a_periodic_cell_is_packed_without_overlap_across_its_edges() {
        let mut s = scene(20.0, 30.0, 0.165).with_walls(WallMode::Periodic);
        s.domain = s.domain.with_periodic(true);
        let packing = pack(&s).unwrap();
        let c = crate::check::check(&packing.disks, &packing.domain, Some(&s.grading));
        assert!(c.valid(), "{c:?}");
        assert!((c.porosity - 0.165).abs() < 0.003, "{}", c.porosity);
        let (lo, hi) = s.domain.bounds();
        assert!(
            packing
                .disks
                .iter()
                .all(|d| { (lo.x..hi.x).contains(&d.c.x) && (lo.y..hi.y).contains(&d.c.y) })
        );
        // Some disks cross an edge (no wall keeps them in), and the nearest
        // images of every pair keep the margin.
        assert!(
            packing
                .disks
                .iter()
                .any(|d| s.domain.signed_distance(d.c) < d.r)
        );
        let w = s.domain.period().unwrap();
        let least = packing
            .disks
            .iter()
            .enumerate()
            .flat_map(|(i, a)| packing.disks[i + 1..].iter().map(move |b| (a, b)))
            .map(|(a, b)| {
                let d = b.c - a.c;
                let d = d - w.component_mul(&d.component_div(&w).map(f64::round));
                d.norm() / (a.r + b.r)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(least >= 1.0 + 0.5 * MARGIN * 0.999, "{least}");
    }

    #[test]
    fn an_unreachable_target_names_the_densest_porosity_reached() {
        let s = scene(15.0, 15.0, 0.05);
        match pack(&s) {
            Err(PackError::DensityUnreached {
                target,
                reached,
                scale,
                jammed,
                ..
            }) => {
                assert_eq!(target, 0.05);
                assert!(jammed);
                assert!(
                    scale < 1.0 && (0.12..0.3).contains(&reached),
                    "{reached} {scale}"
                );
                // Asking for what it reached (rounded up) packs.
                let again = scene(15.0, 15.0, (reached * 1000.0).ceil() / 1000.0 + 0.01);
                assert!(pack(&again).is_ok());
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn the_trace_ends_at_the_densest_porosity_reached() {
        let mut s = scene(12.0, 12.0, 0.05).with_walls(WallMode::Periodic);
        s.domain = s.domain.with_periodic(true);
        let (result, trace) = densify_traced(&s, &Cancel::new());
        let Err(PackError::DensityUnreached { reached, steps, .. }) = result else {
            panic!("{result:?}");
        };
        assert!(trace.disks > 10, "{}", trace.disks);
        assert!(trace.points.len() as u64 >= u64::from(steps) / 100 - 1);
        assert!(trace.points.windows(2).all(|w| w[0][0] < w[1][0]));
        assert!(trace.points.iter().all(|p| (0.0..=1.0).contains(&p[1])));
        // The densest seen is no denser than what the search confirmed
        // (it may have been seen between the points).
        let seen = trace.points.iter().map(|p| p[1]).fold(1.0, f64::min);
        assert!(seen >= reached - 1e-9, "{seen} {reached}");
        assert!(seen - reached < 0.02, "{seen} {reached}");
        // Tracing changes nothing: the same error untraced.
        assert_eq!(
            pack(&s).unwrap_err(),
            densify_traced(&s, &Cancel::new()).0.unwrap_err()
        );
    }

    #[test]
    fn a_domain_that_holds_one_disk_packs_it() {
        let mut s = scene(1.1, 1.1, 0.17);
        s.grading = Grading::constant(1.0).unwrap();
        let packing = pack(&s).unwrap();
        assert_eq!(packing.disks.len(), 1);
        let d = packing.disks[0];
        assert!(s.domain.signed_distance(d.c) >= d.r, "{d:?}");
        // Two disks of 1 mm cannot fit in it: jammed, with what one reaches.
        s.packer.densify.porosity = 0.0;
        s.domain = Domain::rectangle(1.9, 1.1).unwrap();
        assert!(matches!(
            pack(&s),
            Err(PackError::DensityUnreached { jammed: true, .. })
        ));
    }

    #[test]
    fn the_step_budget_and_the_cancel_token_stop_the_run() {
        let mut s = scene(30.0, 30.0, 0.17);
        s.packer.densify.iterations = 10;
        assert!(matches!(
            pack(&s),
            Err(PackError::DensityUnreached {
                jammed: false,
                steps: 10,
                ..
            })
        ));
        let cancel = Cancel::new();
        cancel.cancel();
        s.packer.densify.iterations = 100_000;
        assert!(matches!(
            pack_densify(&s, &cancel),
            Err(PackError::Cancelled(_))
        ));
    }

    /// The porosity the error's message asks for, as a user would read it.
    fn asked_for(error: &PackError) -> Option<f64> {
        let text = error.to_string();
        let (_, rest) = text.split_once("ask for a porosity of ")?;
        rest.split_whitespace()
            .next()?
            .trim_end_matches(':')
            .parse()
            .ok()
    }

    #[test]
    fn the_porosity_advised_packs_in_a_small_periodic_cell_and_a_small_box() {
        // Seeds whose densest reached, rounded up, does not pack afresh:
        // the disks jam looser from random centres than from the jammed ones.
        let mut cell = scene(8.0, 8.0, 0.1)
            .with_walls(WallMode::Periodic)
            .with_seed(1);
        cell.domain = cell.domain.with_periodic(true);
        let boxed = scene(10.0, 10.0, 0.1).with_seed(2);
        for s in [cell, boxed] {
            let error = pack(&s).unwrap_err();
            let PackError::DensityUnreached {
                reached, advice, ..
            } = error
            else {
                panic!("{error:?}");
            };
            let asked = asked_for(&error).unwrap_or_else(|| panic!("{error}"));
            assert_eq!(Some(asked), advice.map(|t| f64::from(t.get()) / 1000.0));
            assert!(asked > reached && asked < 1.0, "{asked} {reached}");
            let mut again = s.clone();
            again.packer.densify.porosity = asked;
            let packing = pack(&again).unwrap_or_else(|e| panic!("{asked}: {e}"));
            let c = crate::check::check(&packing.disks, &packing.domain, None);
            assert!(c.valid(), "{c:?}");
        }
    }

    #[test]
    fn no_porosity_is_advised_when_none_tried_packs() {
        // One step packs nothing: no target is advised (not 1.000).
        let mut s = scene(10.0, 10.0, 0.3);
        s.packer.densify.iterations = 1;
        let error = pack(&s).unwrap_err();
        assert!(
            matches!(error, PackError::DensityUnreached { advice: None, .. }),
            "{error:?}"
        );
        assert_eq!(asked_for(&error), None, "{error}");
    }
}
