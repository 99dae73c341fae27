//! The target-porosity search as one call, [`optimise`]: it chooses the
//! route, runs it and gives its verdict on the target in one typed result,
//! [`Optimised`]. The jobs layer only calls it and writes what it found.
//!
//! # Behavior
//! Three routes, chosen from the scene and generation 0:
//! - **plain**: the GA over the scene itself ([`PorosityProblem`]);
//! - **window**: a large rectangle is searched on a representative window
//!   of it ([`window::settle`]), aiming at the target plus the window's
//!   extra wall effect, and the whole is then packed with the rules found
//!   there, tuned on the whole ([`window::fit_whole`]);
//! - **densify**: a target below every porosity the advancing front packed
//!   in generation 0, beyond the tolerance, is packed directly by the
//!   densify method (docs/densify.md); if the drawn disks jam before it,
//!   the densest packing of the true sizes found, stepping up from where
//!   they jammed (its tuning constants: `DENSE_STEPS`, `DENSE_STEP_MIN`,
//!   `DENSE_REFINE`).
//!
//! What the search tells while it runs (a warning before it, its
//! generations, its checkpoints) goes to an [`OptimiseObserver`]; it stops
//! when `stop` is raised and returns its best so far.

use std::time::Instant;

use super::checkpoint::{Checkpoint, ResumeError};
use super::engine::{Evolution, Generation, Limits, Search, StopReason};
use super::porosity::{CONCLUSIVE_POPULATION, PorosityProblem, Verdict};
use super::settings::OptimiseSettings;
use super::shapes::{AskedShape, ShapeMeasures};
use super::window::{self, Window};
use crate::cancel::{Cancel, Cancelled};
use crate::farm::Farm;
use crate::metrics::{measure, porosity, solid_area};
use crate::packer::{PackError, Packing, pack_densify_stepped, pack_observed};
use crate::{Method, Scene};

/// Tries of the densify route between the jamming point and the front's range.
const DENSE_STEPS: usize = 8;
/// Smallest step of porosity between those tries.
const DENSE_STEP_MIN: f64 = 0.001;
/// Halvings of the last step once the true sizes pack.
const DENSE_REFINE: usize = 2;

/// Where a search starts.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a> {
    /// A new search, its draws from this seed.
    Seed(u64),
    /// Going on from a checkpoint of the same search.
    Resume(&'a Checkpoint),
}

/// What a warning about the target says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum TargetWarningKind {
    /// The target lies outside the range of generation 0 (said before the search).
    OutsideInitialRange,
    /// The search ended without reaching it.
    NotReached,
    /// It is out of reach of this domain and grading.
    OutOfReach,
}

/// A warning about the target, in one sentence naming the config's keys.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct TargetWarning {
    /// What it says.
    pub kind: TargetWarningKind,
    /// The sentence.
    pub message: String,
}

/// What an optimisation tells while it runs.
pub trait OptimiseObserver {
    /// A warning about the target before the search runs.
    fn warning(&mut self, warning: TargetWarning);
    /// The search starts: at most `generations` generations (0 on the densify route).
    fn started(&mut self, generations: u64);
    /// A generation finished (generation 0 included).
    fn generation(&mut self, generation: &Generation);
    /// The search's state to keep: every `every` generations, and when stopped.
    fn checkpoint(&mut self, checkpoint: &Checkpoint);
}

/// Why an optimisation gave no packing.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OptimiseError {
    /// Stopped before generation 0 (or the window) was finished.
    #[error("cancelled before the search had a packing")]
    Cancelled,
    /// The checkpoint does not fit this search.
    #[error(transparent)]
    Resume(ResumeError),
    /// A scene of the route could not be packed.
    #[error("cannot pack {what}")]
    Pack {
        /// Which one: `the scene and its windows`, …
        what: &'static str,
        /// The packer's reason.
        source: PackError,
    },
    /// No genome of the search could be packed.
    #[error("no genome could be packed: the domain is too small for the grading")]
    NothingPacked,
}

/// What a search found, and its verdict on the target.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Optimised {
    /// The packing to write: the search's best, the whole packed with the
    /// window's rules, or the densify route's.
    pub packing: Packing,
    /// The scene it was packed from.
    pub scene: Scene,
    /// The verdict on the target.
    pub verdict: Verdict,
    /// The porosities seen that honour the grading, as the whole's.
    pub achievable_range: Option<[f64; 2]>,
    /// The range of generation 0, as the whole's.
    pub initial_range: Option<[f64; 2]>,
    /// The warning to give about the target after the search, if any.
    pub warning: Option<TargetWarning>,
    /// Packings made: the search's evaluations, the densify route's packs
    /// and the tuning packs of the whole.
    pub evaluations: u64,
    /// One record per generation.
    pub history: Vec<Generation>,
    /// Why the search stopped ([`StopReason::Densified`] on the densify route).
    pub stop: StopReason,
    /// The window searched on, for a large scene.
    pub window: Option<Window>,
    /// Packs of the whole made while tuning its rules (window route).
    pub whole_packs: u32,
    /// Wall-clock time (s): the search's own (summed over resumed runs),
    /// or all of this run's where windows or densify packed beside it.
    pub seconds: f64,
    /// With shape genes: the shape found, and its constraint measures on
    /// the packing written.
    pub shape: Option<(AskedShape, ShapeMeasures)>,
}

/// Search for `settings.target_porosity` on `scene` (see the module
/// documentation): events to `observer`, a checkpoint every `every`
/// generations (0: only when stopped), the work shared out to `farm`,
/// stopped by `stop` with its best so far.
///
/// # Errors
/// [`OptimiseError`]: stopped before anything was packed, a checkpoint of
/// another search, a scene of the route that cannot be packed.
pub fn optimise(
    scene: &Scene,
    settings: &OptimiseSettings,
    start: Start<'_>,
    every: usize,
    farm: &dyn Farm,
    stop: &Cancel,
    observer: &mut dyn OptimiseObserver,
) -> Result<Optimised, OptimiseError> {
    let started = Instant::now();
    let resume = matches!(start, Start::Resume(_));
    // A large scene is searched on a window of it, aiming at the target
    // plus the window's extra wall effect (ga::window).
    let window = if window::windowed(scene, settings.window_disks) {
        match window::settle(scene, settings.tolerance, stop) {
            Ok(w) => Some(w),
            Err(PackError::Cancelled(_)) => return Err(OptimiseError::Cancelled),
            Err(source) => {
                return Err(OptimiseError::Pack {
                    what: "the scene and its windows",
                    source,
                });
            }
        }
    } else {
        None
    };
    let offset = window.as_ref().map_or(0.0, |w| w.offset);
    let problem = PorosityProblem::new(
        window.as_ref().map_or(scene, |w| &w.scene),
        OptimiseSettings {
            target_porosity: settings.target_porosity + offset,
            ..*settings
        },
    );
    // The window's porosities as the whole's.
    let whole_range = |r: Option<[f64; 2]>| r.map(|[lo, hi]| [lo - offset, hi - offset]);
    let limits = Limits::from(settings);
    let search = match start {
        Start::Resume(checkpoint) => {
            Search::resume_on(&problem, limits, checkpoint, farm).map_err(OptimiseError::Resume)?
        }
        Start::Seed(seed) => Search::start_on(&problem, limits, seed, stop, farm)
            .map_err(|_| OptimiseError::Cancelled)?,
    };
    let searched_range = span(PorosityProblem::range(search.initial()));
    let initial_range = whole_range(searched_range);
    // A target below every porosity the advancing front packed in
    // generation 0, beyond its tolerance: the densify method packs the
    // drawn sizes at it directly (docs/densify.md), no search needed.
    // Particle shapes: densify packs disks only, so the search itself
    // finds the densest packing of the shapes, and the verdict gives it.
    let shapes = scene.shape.is_some();
    let dense_route = !resume
        && !shapes
        && initial_range.is_some_and(|[lo, _]| settings.target_porosity < lo - settings.tolerance);
    if !resume && searched_range.is_none_or(|r| !problem.feasible(r)) {
        observer.warning(initial_warning(
            settings,
            initial_range,
            dense_route,
            shapes,
        ));
    }
    observer.started(if dense_route {
        0
    } else {
        settings.stop.generations as u64
    });
    let mut dense = None;
    let evolution = if let Some(front) = initial_range.filter(|_| dense_route) {
        let mut evolution = search.ended(StopReason::Densified);
        for g in &evolution.history {
            observer.generation(g);
        }
        // The time limit counts from the start, as the search's does.
        let capped = stop.with_deadline(limits.time_limit.saturating_sub(started.elapsed()));
        let found = densify_to(scene, settings, front, &capped)?;
        evolution.stop = found.stop;
        dense = Some(found);
        evolution
    } else {
        // The observer is borrowed by both callbacks, one at a time.
        let observer = std::cell::RefCell::new(observer);
        search.run_saving(
            stop,
            |g| observer.borrow_mut().generation(g),
            every,
            |c| observer.borrow_mut().checkpoint(c),
        )
    };
    let mut whole_packs = 0;
    let (verdict, range, warning, packs, best) = match (dense, &window) {
        (Some(d), _) => (d.verdict, d.range, d.warning, d.packs, d.best),
        (None, None) => {
            let verdict = problem.verdict(&evolution);
            let range = span(evolution.explored);
            let warning = verdict_warning(settings, &evolution, verdict, range, shapes);
            (verdict, range, warning, 0, None)
        }
        (None, Some(w)) => {
            let searched = problem.verdict(&evolution);
            let range = whole_range(span(evolution.explored));
            // With shape genes the whole takes the shape found on the
            // window, and its dense end is packed again with that shape.
            let shaped = problem.asked_of(&evolution.genes).and_then(|asked| {
                let mut s = scene.clone();
                s.shape = Some(asked.applied_to(scene.shape.as_ref()?));
                Some(s)
            });
            let fitted = if searched == Verdict::Interrupted {
                Err(PackError::Cancelled(Cancelled::Flag))
            } else {
                let whole_scene = shaped.as_ref().unwrap_or(scene);
                let dense = match &shaped {
                    None => Ok(w.whole.clone()),
                    Some(s) => pack_observed(s, &mut |_| {}, stop).map(|p| {
                        let porosity = porosity(solid_area(&p.disks), p.domain.area());
                        (p, porosity)
                    }),
                };
                dense.and_then(|dense| {
                    window::fit_whole(
                        whole_scene,
                        problem.rules_of(&evolution.genes),
                        dense,
                        [
                            settings.target_porosity,
                            settings.tolerance,
                            settings.max_psd_ks,
                        ],
                        stop,
                    )
                })
            };
            let whole = match fitted {
                Ok(whole) => whole,
                // Interrupted: the whole packed with the scene's own rules is written.
                Err(PackError::Cancelled(_)) => window::Whole {
                    packing: w.whole.0.clone(),
                    scene: scene.clone(),
                    porosity: w.whole.1,
                    packs: 0,
                },
                Err(source) => {
                    return Err(OptimiseError::Pack {
                        what: "the scene with the rules found on its window",
                        source,
                    });
                }
            };
            let repacked = shaped.is_some() && searched != Verdict::Interrupted;
            whole_packs = whole.packs + u32::from(repacked);
            let (verdict, warning) = whole_verdict(settings, w, &whole, searched, range);
            let range = range.map(|[lo, hi]| [lo.min(whole.porosity), hi.max(whole.porosity)]);
            (
                verdict,
                range,
                warning,
                0,
                Some((whole.packing, whole.scene)),
            )
        }
    };
    let (packing, best_scene) = match best {
        Some(best) => best,
        None => {
            let Some(packing) = evolution.outcome else {
                return Err(OptimiseError::NothingPacked);
            };
            (packing, problem.scene_of(&evolution.genes))
        }
    };
    let seconds = if window.is_some() || dense_route {
        started.elapsed().as_secs_f64()
    } else {
        evolution.seconds
    };
    // The shape found, when the packing written has it (not the whole
    // packed with the config's own shape after an interrupted window).
    let shape = problem
        .shape_bounds()
        .zip(problem.asked_of(&evolution.genes))
        .filter(|(_, asked)| {
            let base = scene.shape.as_ref();
            best_scene.shape.as_ref() == base.map(|b| asked.applied_to(b)).as_ref()
        })
        .map(|(bounds, asked)| (asked, bounds.judge(&asked, &packing.grains)));
    Ok(Optimised {
        shape,
        packing,
        scene: best_scene,
        verdict,
        achievable_range: range,
        initial_range,
        warning,
        evaluations: evolution.evaluations + packs + u64::from(whole_packs),
        history: evolution.history,
        stop: evolution.stop,
        window,
        whole_packs,
        seconds,
    })
}

/// The warning given before the search when the target lies outside the
/// range of generation 0 (or nothing of it was packed).
fn initial_warning(
    settings: &OptimiseSettings,
    initial_range: Option<[f64; 2]>,
    dense_route: bool,
    shapes: bool,
) -> TargetWarning {
    TargetWarning {
        kind: TargetWarningKind::OutsideInitialRange,
        message: match initial_range {
            Some([lo, hi]) if dense_route => format!(
                "optimise.target_porosity = {} lies below the range of the initial population, [{lo:.4}, {hi:.4}]: the densify method packs the drawn sizes at it (docs/densify.md)",
                settings.target_porosity
            ),
            Some([lo, hi]) if shapes && settings.target_porosity < lo => format!(
                "optimise.target_porosity = {} lies below the range of the initial population, [{lo:.4}, {hi:.4}]: the densify method packs disks only, so the search looks for the densest packing of these particle shapes",
                settings.target_porosity
            ),
            Some([lo, hi]) => format!(
                "optimise.target_porosity = {} lies outside the range of the initial population, [{lo:.4}, {hi:.4}]; searching beyond it",
                settings.target_porosity
            ),
            None => format!(
                "optimise.target_porosity = {}: no genome of the initial population could be packed; searching on",
                settings.target_porosity
            ),
        },
    }
}

/// The verdict of the window route, on the whole packed with the rules
/// found on the window, and the warning to give when not reached.
fn whole_verdict(
    settings: &OptimiseSettings,
    w: &Window,
    whole: &window::Whole,
    searched: Verdict,
    range: Option<[f64; 2]>,
) -> (Verdict, Option<TargetWarning>) {
    let ks = crate::metrics::psd_ks(&whole.packing, &whole.scene);
    let hit = (whole.porosity - settings.target_porosity).abs() <= settings.tolerance
        && ks <= settings.max_psd_ks;
    let verdict = match searched {
        Verdict::Interrupted => Verdict::Interrupted,
        _ if hit => Verdict::Reached,
        Verdict::OutOfReach => Verdict::OutOfReach,
        _ => Verdict::NotReached,
    };
    let warning = (!matches!(verdict, Verdict::Reached | Verdict::Interrupted)).then(|| TargetWarning {
        kind: if verdict == Verdict::OutOfReach {
            TargetWarningKind::OutOfReach
        } else {
            TargetWarningKind::NotReached
        },
        message: format!(
            "optimise.target_porosity = {}: searched on a window of {:.0} × {:.0} mm, the whole packed with the rules found there (tuned over {} packs of it) reached porosity {:.4}, psd_ks {:.3} (optimise.tolerance {}, optimise.max_psd_ks {}){}",
            settings.target_porosity,
            w.steps.last().map_or(0.0, |s| s.size[0]),
            w.steps.last().map_or(0.0, |s| s.size[1]),
            whole.packs,
            whole.porosity,
            ks,
            settings.tolerance,
            settings.max_psd_ks,
            if verdict == Verdict::OutOfReach {
                denser_than(settings.target_porosity, range, whole.scene.shape.is_some())
            } else {
                String::new()
            }
        ),
    });
    (verdict, warning)
}

/// What the densify route found: the verdict on the target, the range
/// measured (its dense end the densest packing of the true sizes found),
/// the warning to give, the packings made, and the packing to write with
/// its scene (`None`: the search's best stands), and why it stopped
/// ([`StopReason::Densified`], or [`StopReason::TimeLimit`]).
struct Dense {
    verdict: Verdict,
    range: Option<[f64; 2]>,
    warning: Option<TargetWarning>,
    packs: u64,
    best: Option<(Packing, Scene)>,
    stop: StopReason,
}

/// Pack the drawn sizes at the target with the densify method; if the
/// disks jam before it, the densest packing of the true sizes found,
/// from just above the porosity at which they jammed. `front` is the
/// range the advancing front packed in generation 0. Stopped by `stop`'s
/// flag, the verdict is interrupted; by its deadline (the time limit), the
/// densest packing of the true sizes found so far is written, else the
/// search's best of generation 0, the target not reached.
fn densify_to(
    scene: &Scene,
    settings: &OptimiseSettings,
    front: [f64; 2],
    stop: &Cancel,
) -> Result<Dense, OptimiseError> {
    let target = settings.target_porosity;
    let at = |porosity: f64| {
        let mut scene = scene.clone();
        scene.packer.method = Method::Densify;
        scene.packer.densify.porosity = porosity;
        scene
    };
    let interrupted = || Dense {
        verdict: Verdict::Interrupted,
        range: Some(front),
        warning: None,
        packs: 1,
        best: None,
        stop: StopReason::Densified,
    };
    // Stopped by the time limit before the true sizes packed: the search's
    // best of generation 0 stands.
    let timed_out = |packs: u64, jammed: Option<f64>| Dense {
        verdict: Verdict::NotReached,
        range: Some(front),
        warning: Some(TargetWarning {
            kind: TargetWarningKind::NotReached,
            message: format!(
                "optimise.target_porosity = {target} was not reached: the time limit (optimise.time_limit_s = {}) passed while the densify method packed the drawn sizes{}, before they packed at or near it; the search's best packing of the initial population (whose porosities start at {:.4}) is written",
                settings.stop.time_limit_s,
                jammed.map_or(String::new(), |j| format!(" (they jam at porosity {j:.4})")),
                front[0]
            ),
        }),
        packs,
        best: None,
        stop: StopReason::TimeLimit,
    };
    let scene = at(target);
    let jammed = match pack_densify_stepped(&scene, stop) {
        Ok(packing) => {
            let m = measure(&packing, &scene);
            let reached = (m.porosity - target).abs() <= settings.tolerance
                && m.psd_ks <= settings.max_psd_ks;
            let warning = (!reached).then(|| TargetWarning {
                kind: TargetWarningKind::NotReached,
                message: format!(
                    "optimise.target_porosity = {target}: the densify method packed the drawn sizes at porosity {:.4}, psd_ks {:.3} (optimise.tolerance {}, optimise.max_psd_ks {})",
                    m.porosity, m.psd_ks, settings.tolerance, settings.max_psd_ks
                ),
            });
            return Ok(Dense {
                verdict: if reached {
                    Verdict::Reached
                } else {
                    Verdict::NotReached
                },
                range: Some([m.porosity.min(front[0]), front[1]]),
                warning,
                packs: 1,
                best: Some((packing, scene)),
                stop: StopReason::Densified,
            });
        }
        Err(PackError::DensityUnreached { reached, .. }) => reached,
        Err(PackError::Cancelled(Cancelled::Deadline)) => return Ok(timed_out(1, None)),
        Err(PackError::Cancelled(_)) => return Ok(interrupted()),
        Err(source) => return Err(dense_failure(source)),
    };
    // Step up from where the disks jammed until the true sizes pack,
    // then halve the last step twice towards the jamming point.
    let step = settings.tolerance.max(DENSE_STEP_MIN);
    for k in 1..=DENSE_STEPS {
        let porosity = jammed + k as f64 * step;
        if porosity >= front[0] {
            break;
        }
        let scene = at(porosity);
        match pack_densify_stepped(&scene, stop) {
            Ok(packing) => {
                let (mut packing, mut scene, mut packs) = (packing, scene, 1 + k as u64);
                let mut failed = porosity - step;
                let mut packed = porosity;
                let mut cut = None;
                for _ in 0..DENSE_REFINE {
                    let mid = 0.5 * (failed + packed);
                    let trial = at(mid);
                    packs += 1;
                    match pack_densify_stepped(&trial, stop) {
                        Ok(p) => (packing, scene, packed) = (p, trial, mid),
                        Err(PackError::DensityUnreached { .. }) => failed = mid,
                        Err(PackError::Cancelled(why)) => {
                            cut = Some(why);
                            break;
                        }
                        Err(source) => return Err(dense_failure(source)),
                    }
                }
                let m = measure(&packing, &scene);
                let (verdict, kind, stopped, because) = match cut {
                    None => (
                        Verdict::OutOfReach,
                        TargetWarningKind::OutOfReach,
                        StopReason::Densified,
                        String::new(),
                    ),
                    Some(Cancelled::Deadline) => (
                        Verdict::NotReached,
                        TargetWarningKind::NotReached,
                        StopReason::TimeLimit,
                        format!(
                            " (the time limit, optimise.time_limit_s = {}, passed before the search for it ended)",
                            settings.stop.time_limit_s
                        ),
                    ),
                    Some(Cancelled::Flag) => (
                        Verdict::Interrupted,
                        TargetWarningKind::NotReached,
                        StopReason::Densified,
                        " (interrupted before the search for it ended)".to_owned(),
                    ),
                };
                return Ok(Dense {
                    verdict,
                    range: Some([m.porosity, front[1]]),
                    warning: Some(TargetWarning {
                        kind,
                        message: format!(
                            "optimise.target_porosity = {target} is below the densest packing found for this grading and domain: the drawn disks jam at porosity {jammed:.4} (densify, their radii scaled down until no overlap is left; jammed polydisperse disks reach about 0.16, O'Hern et al. 2003); the densest packing of the true sizes found{because}, porosity {:.4}, is written",
                            m.porosity
                        ),
                    }),
                    packs,
                    best: Some((packing, scene)),
                    stop: stopped,
                });
            }
            Err(PackError::DensityUnreached { .. }) => {}
            Err(PackError::Cancelled(Cancelled::Deadline)) => {
                return Ok(timed_out(1 + k as u64, Some(jammed)));
            }
            Err(PackError::Cancelled(_)) => return Ok(interrupted()),
            Err(source) => return Err(dense_failure(source)),
        }
    }
    // Nothing between the jamming point and the front's range packed:
    // the front's densest packing of generation 0 stands.
    Ok(Dense {
        verdict: Verdict::OutOfReach,
        range: Some(front),
        warning: Some(TargetWarning {
            kind: TargetWarningKind::OutOfReach,
            message: format!(
                "optimise.target_porosity = {target} is below the densest packing found for this grading and domain: the drawn disks jam at porosity {jammed:.4} (densify), and no denser packing of the true sizes than the advancing front's {:.4} was found; that one is written",
                front[0]
            ),
        }),
        packs: 1 + DENSE_STEPS as u64,
        best: None,
        stop: StopReason::Densified,
    })
}

/// The densify route's packer failed for another reason than jamming.
fn dense_failure(source: PackError) -> OptimiseError {
    OptimiseError::Pack {
        what: "the scene with the densify method",
        source,
    }
}

/// A range of values, or none for the empty range `[inf, -inf]` (nothing
/// seen) or anything else that is not one: never an infinite range.
fn span([lo, hi]: [f64; 2]) -> Option<[f64; 2]> {
    (lo.is_finite() && hi.is_finite() && lo <= hi).then_some([lo, hi])
}

/// Where a target lies below every porosity the advancing front packed:
/// the method that packs denser than it, down to the grading's jamming
/// limit; with particle shapes (`shapes`), which densify does not pack,
/// the densest packing found is the measured limit.
fn denser_than(target: f64, range: Option<[f64; 2]>, shapes: bool) -> String {
    match range {
        Some([lo, _]) if target < lo && shapes => format!(
            "; it lies below the densest packing found for these particle shapes, porosity {lo:.4}, the measured limit (the densify method packs disks only; docs/optimise.md)"
        ),
        Some([lo, _]) if target < lo => {
            "; [packer] method = \"densify\" with densify_porosity packs the drawn sizes denser than the advancing front, down to near the grading's jamming limit (docs/densify.md)".to_owned()
        }
        _ => String::new(),
    }
}

/// The warning a finished search gives about its target, if any: out of
/// reach only after a conclusive search (`PorosityProblem::conclusive`),
/// else not reached in so many evaluations.
fn verdict_warning<O>(
    settings: &OptimiseSettings,
    evolution: &Evolution<O>,
    verdict: Verdict,
    range: Option<[f64; 2]>,
    shapes: bool,
) -> Option<TargetWarning> {
    let target = settings.target_porosity;
    let generations = evolution.history.len().saturating_sub(1);
    let effort = format!(
        "{} evaluations in {generations} generation{} of {} genomes ({})",
        evolution.evaluations,
        if generations == 1 { "" } else { "s" },
        settings.stop.population,
        evolution.stop.describe()
    );
    let seen = match range {
        Some([lo, hi]) => format!(
            "the packings that honour the grading span [{lo:.4}, {hi:.4}]; the nearest one, {:.4}, is written",
            evolution.best.value
        ),
        None => format!(
            "no packing honoured the grading (optimise.max_psd_ks = {}); the one nearest to it, porosity {:.4}, is written",
            settings.max_psd_ks, evolution.best.value
        ),
    };
    let longer = if settings.stop.population < CONCLUSIVE_POPULATION {
        format!(
            "a longer search may reach it (optimise.generations, optimise.stagnation, optimise.time_limit_s), and a population of at least {CONCLUSIVE_POPULATION} tries the loosest packing rules (optimise.population)"
        )
    } else {
        "a longer search may reach it (optimise.generations, optimise.stagnation, optimise.time_limit_s)".to_owned()
    };
    let (kind, message) = match verdict {
        Verdict::Reached | Verdict::Interrupted => return None,
        Verdict::OutOfReach => (
            TargetWarningKind::OutOfReach,
            format!(
                "optimise.target_porosity = {target} is out of reach: after {effort}, {seen}{}",
                denser_than(target, range, shapes)
            ),
        ),
        Verdict::InRange => (
            TargetWarningKind::NotReached,
            format!(
                "optimise.target_porosity = {target} was not reached in {effort}, though it lies within the range seen: {seen}; {longer}"
            ),
        ),
        _ => (
            TargetWarningKind::NotReached,
            format!(
                "optimise.target_porosity = {target} was not reached in {effort}: {seen}; {longer}{}",
                if shapes {
                    denser_than(target, range, shapes)
                } else {
                    String::new()
                }
            ),
        ),
    };
    Some(TargetWarning { kind, message })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::farm::Local;
    use crate::grading::Basis;
    use crate::{Domain, Grading};

    fn scene() -> Scene {
        Scene::new(
            Domain::rectangle(10.0, 10.0).expect("a domain"),
            Grading::uniform(1.0, 2.0, Basis::Number).expect("a grading"),
        )
    }

    /// Records what the search tells.
    #[derive(Default)]
    struct Told {
        warnings: Vec<TargetWarning>,
        started: Option<u64>,
        generations: usize,
    }

    impl OptimiseObserver for Told {
        fn warning(&mut self, warning: TargetWarning) {
            self.warnings.push(warning);
        }
        fn started(&mut self, generations: u64) {
            self.started = Some(generations);
        }
        fn generation(&mut self, _: &Generation) {
            self.generations += 1;
        }
        fn checkpoint(&mut self, _: &Checkpoint) {}
    }

    /// `optimise` from `seed`, on one thread, never stopped, its events dropped.
    fn search(scene: &Scene, settings: &OptimiseSettings, seed: u64) -> Optimised {
        optimise(
            scene,
            settings,
            Start::Seed(seed),
            0,
            &Local,
            &Cancel::new(),
            &mut Told::default(),
        )
        .expect("packs")
    }

    fn settings(target: f64) -> OptimiseSettings {
        let mut settings = OptimiseSettings::new(target);
        settings.stop.population = 4;
        settings.stop.generations = 2;
        settings
    }

    #[test]
    fn a_target_below_the_front_takes_the_densify_route_and_says_so_first() {
        let mut told = Told::default();
        let found = optimise(
            &scene(),
            &settings(0.02),
            Start::Seed(1),
            0,
            &Local,
            &Cancel::new(),
            &mut told,
        )
        .expect("packs");
        assert_eq!(found.stop, StopReason::Densified);
        assert_eq!(told.started, Some(0), "no generation is searched");
        assert_eq!(told.generations, found.history.len());
        assert_eq!(
            told.warnings[0].kind,
            TargetWarningKind::OutsideInitialRange
        );
        assert!(told.warnings[0].message.contains("densify"));
        // Far below any packing of these sizes: not reached, said after.
        assert_ne!(found.verdict, Verdict::Reached);
        assert!(found.warning.is_some());
        assert!(found.window.is_none());
    }

    #[test]
    fn the_plain_route_searches_its_generations_and_gives_a_verdict() {
        let mut told = Told::default();
        let found = optimise(
            &scene(),
            &settings(0.25),
            Start::Seed(1),
            0,
            &Local,
            &Cancel::new(),
            &mut told,
        )
        .expect("packs");
        assert_eq!(told.started, Some(2));
        assert_ne!(found.stop, StopReason::Densified);
        assert_eq!(told.generations, found.history.len());
        assert!(found.evaluations >= 4);
        assert_eq!(found.verdict == Verdict::Reached, found.warning.is_none());
    }

    #[test]
    fn a_search_stopped_before_generation_0_is_cancelled() {
        let stop = Cancel::new();
        stop.cancel();
        let got = optimise(
            &scene(),
            &settings(0.25),
            Start::Seed(1),
            0,
            &Local,
            &stop,
            &mut Told::default(),
        );
        assert!(matches!(got, Err(OptimiseError::Cancelled)), "{got:?}");
    }

    #[test]
    fn the_densify_route_stops_at_the_time_limit_with_what_it_has() {
        // Some 2,000 disks far below their jamming point: the route's packs
        // take much longer than the limit.
        let scene = Scene::new(
            Domain::rectangle(80.0, 80.0).expect("a domain"),
            Grading::uniform(1.0, 2.0, Basis::Number).expect("a grading"),
        );
        let mut settings = settings(0.02);
        settings.stop.time_limit_s = 0.5;
        let clock = Instant::now();
        let found = search(&scene, &settings, 1);
        let took = clock.elapsed().as_secs_f64();
        assert_eq!(found.stop, StopReason::TimeLimit, "after {took} s");
        assert!(!found.stop.reproducible());
        assert_eq!(found.verdict, Verdict::NotReached);
        let warning = found.warning.expect("said");
        assert!(
            warning.message.contains("time limit"),
            "{}",
            warning.message
        );
        assert!(took < 30.0, "{took}");
        // What it had is written: a packing without overlap.
        let c = crate::check::check(&found.packing.disks, &found.packing.domain, None);
        assert!(c.valid() && !found.packing.disks.is_empty(), "{c:?}");
    }

    /// A 16 mm square of superellipses whose aspect and exponent the
    /// search may move, their sphericity bounded.
    fn shaped() -> (Scene, OptimiseSettings) {
        let scene = Scene::new(
            Domain::rectangle(16.0, 16.0).expect("a domain"),
            Grading::uniform(1.0, 2.0, Basis::Number).expect("a grading"),
        )
        .with_seed(3);
        let scene = Scene {
            shape: Some(crate::ShapeSpec::superellipses(1.0, 2.0)),
            ..scene
        };
        let mut bounds = super::super::ShapeBounds::new([1.0, 3.0], [2.0, 4.0]);
        bounds.min_sphericity = 0.75;
        let settings = OptimiseSettings {
            shape: Some(bounds),
            ..settings(0.3)
        };
        (scene, settings)
    }

    #[test]
    fn shape_genes_move_the_shape_within_its_bounds_and_keep_them() {
        let (scene, settings) = shaped();
        let found = search(&scene, &settings, 2);
        let (asked, measures) = found.shape.expect("the shape found");
        let bounds = settings.shape.expect("bounds");
        assert!(bounds.aspect[0] <= asked.aspect[0] && asked.aspect[1] <= bounds.aspect[1]);
        assert!((2.0..=4.0).contains(&asked.exponent));
        // The scene written is the shape found, and the packing is of it.
        assert_eq!(
            found.scene.shape,
            Some(asked.applied_to(scene.shape.as_ref().expect("a shape")))
        );
        assert_eq!(found.packing.grains.len(), found.packing.disks.len());
        assert!(!found.packing.grains.is_empty());
        assert_eq!(measures.aspect_ks, asked.aspect_ks(&found.packing.grains));
        // The best genome keeps every constraint it can: the roundest
        // genomes of generation 0 keep them, so the best does too.
        assert!(measures.sphericity >= 0.75, "{measures:?}");
        assert!(measures.aspect_ks <= bounds.max_shape_ks, "{measures:?}");
        let p = &found.packing;
        let report = crate::check::check_particles(&p.disks, &p.grains, &p.domain, None);
        assert!(report.valid() && report.overlaps == 0 && report.outside == 0);
        // The same search again: the same packing.
        let again = search(&scene, &settings, 2);
        assert_eq!(again.packing.disks, found.packing.disks);
        assert_eq!(again.packing.grains, found.packing.grains);
    }

    #[test]
    fn a_target_below_every_shape_packing_gets_the_densest_found_not_densify() {
        let (scene, settings) = shaped();
        let mut told = Told::default();
        let found = optimise(
            &scene,
            &OptimiseSettings {
                target_porosity: 0.02,
                ..settings
            },
            Start::Seed(2),
            0,
            &Local,
            &Cancel::new(),
            &mut told,
        )
        .expect("packs");
        assert_ne!(
            found.stop,
            StopReason::Densified,
            "densify packs disks only"
        );
        assert!(
            told.warnings[0].message.contains("densest packing"),
            "{:?}",
            told.warnings
        );
        let warning = found.warning.expect("not reached");
        let [lo, _] = found.achievable_range.expect("a range");
        assert!(
            warning.message.contains(&format!("porosity {lo:.4}")),
            "{}",
            warning.message
        );
        assert!(found.packing.grains.len() == found.packing.disks.len());
    }
}
