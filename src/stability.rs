//! Where methods break: every method variant over a sweep of gradings,
//! domain widths and shapes, each run checked for finishing, filling,
//! overlaps and grading fidelity.
//!
//! # Behavior
//! A case is a shape, a grading width d_max/d_min (sizes uniform between
//! d_min and the scene's d_max, in its basis) and a domain width in d_max:
//! a rectangle `w` × 3`w`, a circle of diameter `w`, an isosceles triangle
//! with a 20° apex over a base `w`, and an L of arms `w` wide in a 3`w`
//! square. A run passes when it finishes within the time cap, leaves no
//! overlap (1e-9 relative), leaves at most [`MAX_EMPTY`] of the domain
//! farther than d_max from every disk (counting only where a smallest disk
//! could be centred: the tip of a wedge narrower than d_min holds none),
//! and keeps the sizes within the sampling noise of their number plus
//! [`crate::check::KS_MARGIN`] of the grading. A case no disk fits in is refused, not failed.

use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::Scene;
use crate::cancel::{Cancel, Cancelled};
use crate::compare::Variant;
use crate::farm::{self, Farm};
use crate::geometry::predicates::OVERLAP_REL;
use crate::geometry::{Domain, GeometryError, Grain, Point, Turned, WallMode, separation};
use crate::grading::Grading;
use crate::metrics::measure;
use crate::packer::index::{Grid, SpatialIndex};
use crate::packer::{Method, PackError, Packing, pack_observed};

/// Grading widths d_max/d_min swept.
pub const RATIOS: [f64; 6] = [1.0, 1.1, 2.0, 4.0, 8.0, 16.0];

/// Domain widths swept, in largest diameters.
pub const WIDTHS: [f64; 6] = [1.2, 1.5, 2.0, 3.0, 5.0, 20.0];

/// Largest share of the domain left farther than d_max from every disk in a pass.
pub const MAX_EMPTY: f64 = 0.02;

/// The shapes swept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseShape {
    /// `w` × 3`w`.
    Rectangle,
    /// Diameter `w`.
    Circle,
    /// Isosceles, 20° at the apex, base `w`.
    Triangle,
    /// Arms `w` wide in a 3`w` square (concave).
    LShape,
}

impl CaseShape {
    /// All shapes, in the order reports list them.
    pub const ALL: [CaseShape; 4] = [
        CaseShape::Rectangle,
        CaseShape::Circle,
        CaseShape::Triangle,
        CaseShape::LShape,
    ];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            CaseShape::Rectangle => "rectangle",
            CaseShape::Circle => "circle",
            CaseShape::Triangle => "triangle-20deg",
            CaseShape::LShape => "l-shape",
        }
    }

    /// The domain of width `w` (mm).
    ///
    /// # Errors
    /// The constructor's, for a width that is not positive and finite.
    fn domain(self, w: f64) -> Result<Domain, GeometryError> {
        let pts = |v: &[(f64, f64)]| v.iter().map(|&(x, y)| Point::new(x, y)).collect::<Vec<_>>();
        match self {
            CaseShape::Rectangle => Domain::rectangle(w, 3.0 * w),
            CaseShape::Circle => Domain::circle(Point::new(0.0, 0.0), w / 2.0),
            CaseShape::Triangle => {
                let h = w / 2.0 / 10f64.to_radians().tan();
                Domain::polygon(&pts(&[(0.0, 0.0), (w, 0.0), (w / 2.0, h)]))
            }
            CaseShape::LShape => Domain::polygon(&pts(&[
                (0.0, 0.0),
                (3.0 * w, 0.0),
                (3.0 * w, w),
                (w, w),
                (w, 3.0 * w),
                (0.0, 3.0 * w),
            ])),
        }
    }
}

/// One case of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// The shape.
    pub shape: CaseShape,
    /// d_max / d_min.
    pub ratio: f64,
    /// Domain width in d_max.
    pub width: f64,
}

impl Case {
    /// Every case: shapes × ratios × widths.
    pub fn all() -> Vec<Case> {
        let mut out = Vec::new();
        for shape in CaseShape::ALL {
            for ratio in RATIOS {
                for width in WIDTHS {
                    out.push(Case {
                        shape,
                        ratio,
                        width,
                    });
                }
            }
        }
        out
    }

    /// The case's scene: `base` with this domain and grading. The sweep's
    /// shapes have walls: a periodic base sweeps them with exact walls.
    ///
    /// # Errors
    /// The domain's, for a base whose d_max makes a size overflow.
    pub fn scene(&self, base: &Scene) -> Result<Scene, GeometryError> {
        let d_max = base.d_max();
        let grading = if self.ratio <= 1.0 {
            Grading::constant(d_max)
        } else {
            Grading::uniform(d_max / self.ratio, d_max, base.grading.basis())
        }
        .unwrap_or_else(|_| base.grading.clone());
        let walls = match base.walls {
            WallMode::Periodic => WallMode::Exact,
            walls => walls,
        };
        Ok(Scene {
            gradient: None,
            grading,
            ..base.clone()
        }
        .with_walls(walls)
        .with_domain(self.shape.domain(self.width * d_max)?))
    }
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Status {
    /// It finished; see the checks.
    Finished,
    /// No disk of the grading fits the domain: refused before packing.
    Refused,
    /// Still running at the time cap.
    TimedOut,
}

/// One method variant on one case.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct StabilityRun {
    /// The case.
    pub case: Case,
    /// The method variant.
    pub variant: Variant,
    /// The seed it ran with.
    pub seed: u64,
    /// How it ended.
    pub status: Status,
    /// Time (s), up to the cap.
    pub seconds: f64,
    /// Disks packed.
    pub particles: usize,
    /// Share of the domain farther than d_max from every disk.
    pub empty: f64,
    /// Largest overlap relative to the sum of the radii.
    pub max_overlap: f64,
    /// KS distance of the sizes to the grading.
    pub psd_ks: f64,
}

impl StabilityRun {
    /// The run of `variant` on `case` with `seed` that found `c`.
    fn found(case: Case, variant: Variant, seed: u64, c: Checked) -> Self {
        StabilityRun {
            case,
            variant,
            seed,
            status: c.status,
            seconds: c.seconds,
            particles: c.particles,
            empty: c.empty,
            max_overlap: c.max_overlap,
            psd_ks: c.psd_ks,
        }
    }

    /// Whether the run passes: finished, no overlap, filled, grading kept.
    pub fn passed(&self) -> bool {
        self.status == Status::Finished && self.reasons().is_empty()
    }

    /// Why a finished run fails, in [`Reason::ALL`] order: none for a pass
    /// (or a run that did not finish), two or three when several checks fail.
    pub fn reasons(&self) -> Vec<Reason> {
        if self.status != Status::Finished {
            return Vec::new();
        }
        Reason::ALL
            .into_iter()
            .filter(|reason| match reason {
                Reason::Overlap => self.max_overlap > OVERLAP_REL,
                Reason::Empty => self.empty > MAX_EMPTY,
                Reason::Grading => self.grading_bent(),
            })
            .collect()
    }

    /// Whether the sizes lie farther from the grading than the sampling
    /// noise of their number explains (plus [`crate::check::KS_MARGIN`]).
    pub fn grading_bent(&self) -> bool {
        self.psd_ks > crate::check::ks_limit(self.particles)
    }
}

/// Why a finished run fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Reason {
    /// Two disks overlap by more than 1e-9 of their radii sum.
    Overlap,
    /// More than [`MAX_EMPTY`] of the domain is left empty.
    Empty,
    /// The sizes are farther from the grading than sampling noise explains.
    Grading,
}

impl Reason {
    /// Every reason, in the order reports list them.
    pub const ALL: [Reason; 3] = [Reason::Overlap, Reason::Empty, Reason::Grading];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Reason::Overlap => "overlap",
            Reason::Empty => "empty",
            Reason::Grading => "KS",
        }
    }
}

/// How a set of runs ended, each run counted once: every failing run
/// under the one set of reasons it fails for.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tally {
    /// Runs that passed.
    pub pass: usize,
    /// Runs that finished and failed.
    pub fail: usize,
    /// The failing runs by their reasons (one, two or three), in
    /// [`Reason::ALL`] order, single reasons first; the counts sum to `fail`.
    pub by_reasons: Vec<(Vec<Reason>, usize)>,
    /// Runs refused (no disk fits).
    pub refused: usize,
    /// Runs still going at the time cap.
    pub timed_out: usize,
}

impl Tally {
    /// The tally of `runs`.
    pub fn of<'a>(runs: impl IntoIterator<Item = &'a StabilityRun>) -> Tally {
        let mut tally = Tally::default();
        for run in runs {
            match run.status {
                Status::Refused => tally.refused += 1,
                Status::TimedOut => tally.timed_out += 1,
                Status::Finished if run.passed() => tally.pass += 1,
                Status::Finished => {
                    tally.fail += 1;
                    let reasons = run.reasons();
                    match tally.by_reasons.iter_mut().find(|(r, _)| *r == reasons) {
                        Some((_, n)) => *n += 1,
                        None => tally.by_reasons.push((reasons, 1)),
                    }
                }
            }
        }
        tally
            .by_reasons
            .sort_by(|a, b| (a.0.len(), &a.0).cmp(&(b.0.len(), &b.0)));
        tally
    }
}

/// Run `variants` on `cases` (all of them: [`Case::all`]) with each of
/// `seeds` (the three given together), spread over `farm`, each run stopped at `cap` (a deadline the
/// generators honour), calling `done` after each in order. Once `cancel` is
/// raised the runs finished so far are returned.
pub fn sweep(
    base: &Scene,
    (cases, variants, seeds): (&[Case], &[Variant], &[u64]),
    cap: Duration,
    cancel: &Cancel,
    farm: &dyn Farm,
    mut done: impl FnMut(&StabilityRun),
) -> Vec<StabilityRun> {
    let scenes: Vec<_> = cases.iter().map(|case| case.scene(base)).collect();
    let mut plan = Vec::new();
    for c in 0..cases.len() {
        for &seed in seeds {
            for &variant in variants {
                plan.push((c, seed, variant));
            }
        }
    }
    let mut runs = Vec::new();
    farm::waves(
        farm,
        plan.len(),
        || cancel.is_raised(),
        |i| {
            let (c, seed, variant) = plan[i];
            match &scenes[c] {
                Ok(scene) => run_one(&variant.apply(scene, seed), &cancel.with_deadline(cap)),
                Err(_) => Some(Checked {
                    status: Status::Refused,
                    ..Checked::NONE
                }),
            }
        },
        |i, checked| {
            let (c, seed, variant) = plan[i];
            let Some(found) = checked else {
                return false;
            };
            let run = StabilityRun::found(cases[c], variant, seed, found);
            done(&run);
            runs.push(run);
            true
        },
    );
    runs
}

/// What one run found: what travels between processes.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
struct Checked {
    status: Status,
    seconds: f64,
    particles: usize,
    empty: f64,
    max_overlap: f64,
    psd_ks: f64,
}

impl Checked {
    /// A run that placed nothing in no time (timed out until told otherwise).
    const NONE: Checked = Checked {
        status: Status::TimedOut,
        seconds: 0.0,
        particles: 0,
        empty: 1.0,
        max_overlap: 0.0,
        psd_ks: 1.0,
    };
}

/// One run, stopped at `capped`'s deadline (timed out); `None` when its flag is raised.
fn run_one(scene: &Scene, capped: &Cancel) -> Option<Checked> {
    let start = Instant::now();
    let mut run = Checked::NONE;
    match pack_observed(scene, &mut |_| {}, capped) {
        Ok(packing) => {
            run.seconds = start.elapsed().as_secs_f64();
            let m = measure(&packing, scene);
            run.status = Status::Finished;
            run.particles = m.particles;
            run.max_overlap = m.max_overlap;
            run.psd_ks = m.psd_ks;
            run.empty = empty_share(&packing, scene.d_min(), scene.d_max());
        }
        Err(PackError::DomainTooNarrow { .. }) => {
            run.status = Status::Refused;
            run.seconds = start.elapsed().as_secs_f64();
        }
        Err(PackError::Cancelled(Cancelled::Flag)) => return None,
        Err(_) => run.seconds = start.elapsed().as_secs_f64(),
    }
    Some(run)
}

/// Share of the domain where a disk of `d_min` could be centred (sampled on
/// a grid of spacing d_max/4) that lies farther than `d_max` from every
/// particle's edge (a disk's, or a shape's outline by its support function).
pub fn empty_share(packing: &Packing, d_min: f64, d_max: f64) -> f64 {
    let domain = &packing.domain;
    let (lo, hi) = domain.bounds();
    let step = d_max / 4.0;
    // Each particle's bounding circle: its radius, or a shape's circumradius.
    let reach: Vec<f64> = if packing.grains.is_empty() {
        packing.disks.iter().map(|d| d.r).collect()
    } else {
        packing
            .grains
            .iter()
            .map(|g| g.outline.circumradius())
            .collect()
    };
    let turned: Vec<Turned> = packing.grains.iter().map(Grain::turned).collect();
    let r_max = reach.iter().fold(0.0f64, |m, &r| m.max(r));
    let reach_max = d_max + r_max;
    let margin = Point::new(reach_max, reach_max).coords;
    let mut grid = Grid::new(lo - margin, hi + margin, (2.0 * r_max).max(step));
    for (id, d) in packing.disks.iter().enumerate() {
        grid.insert(id as u32, d.c);
    }
    // Within d_max of particle `id`'s edge (a shape's distance to
    // within a thousandth of d_max).
    let near = |id: usize, p: Point| {
        let d = p - packing.disks[id].c;
        let centre = d.norm();
        if centre - reach[id] > d_max {
            return false;
        }
        match turned.get(id) {
            None => centre - packing.disks[id].r <= d_max,
            Some(t) => separation(d, 1e-3 * d_max, |u| t.support_both(u)).lower <= d_max,
        }
    };
    let (nx, ny) = (
        ((hi.x - lo.x) / step).ceil() as usize,
        ((hi.y - lo.y) / step).ceil() as usize,
    );
    let (mut inside, mut empty) = (0usize, 0usize);
    for iy in 0..=ny {
        for ix in 0..=nx {
            let p = Point::new(lo.x + ix as f64 * step, lo.y + iy as f64 * step);
            if domain.signed_distance(p) < d_min / 2.0 {
                continue;
            }
            inside += 1;
            let found = grid.any_in_box(
                Point::new(p.x - reach_max, p.y - reach_max),
                Point::new(p.x + reach_max, p.y + reach_max),
                |id| near(id as usize, p),
            );
            if !found {
                empty += 1;
            }
        }
    }
    if inside == 0 {
        0.0
    } else {
        empty as f64 / inside as f64
    }
}

/// The method variants a sweep runs for `methods` (as `gapack compare` does).
pub fn variants(methods: &[Method]) -> Vec<Variant> {
    Variant::expand(methods)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases_cover_the_sweep_and_build_their_domains() {
        let cases = Case::all();
        assert_eq!(cases.len(), 4 * 6 * 6);
        let t = CaseShape::Triangle.domain(10.0).unwrap();
        // The 20° apex: the inradius of a tall, thin triangle.
        let h = 5.0 / 10f64.to_radians().tan();
        let side = (25.0 + h * h).sqrt();
        let r = 10.0 * h / 2.0 / ((10.0 + 2.0 * side) / 2.0);
        assert!((t.inradius() - r).abs() < 1e-9);
        assert_eq!(
            CaseShape::LShape
                .domain(1.0)
                .unwrap()
                .reflex_vertices()
                .len(),
            1
        );
    }

    fn base() -> Scene {
        Scene::new(
            Domain::rectangle(10.0, 10.0).unwrap(),
            Grading::constant(1.0).unwrap(),
        )
        .with_packer(crate::packer::PackerSettings {
            attempts: 500,
            relaxation: crate::packer::Relaxation {
                iterations: 200,
                ..Default::default()
            },
            ..Default::default()
        })
        .with_seed(1)
    }

    #[test]
    fn a_wide_case_passes_for_the_advancing_front_and_relaxation_shows_its_overlap() {
        let case = Case {
            shape: CaseShape::Rectangle,
            ratio: 2.0,
            width: 20.0,
        };
        let variants = Variant::expand(&[Method::AdvancingFront, Method::Relaxation]);
        let runs = sweep(
            &base(),
            (&[case], &variants, &[1, 2]),
            Duration::from_secs(60),
            &Cancel::new(),
            &crate::farm::Local,
            |_| {},
        );
        // Each seed runs every variant.
        assert_eq!(runs.len(), 10);
        for (k, seed) in [1, 2].into_iter().enumerate() {
            let mine = &runs[5 * k..5 * k + 5];
            assert!(mine.iter().all(|r| r.seed == seed));
            for r in &mine[..4] {
                assert!(r.passed(), "{r:?}");
            }
            let relax = mine[4];
            assert_eq!(relax.status, Status::Finished);
            assert!(
                relax.max_overlap > OVERLAP_REL && !relax.passed(),
                "{relax:?}"
            );
        }
        // Another seed packs other disks.
        assert_ne!(runs[0].particles + runs[1].particles, 0);
        assert!(runs[0].psd_ks != runs[5].psd_ks || runs[0].particles != runs[5].particles);
    }

    #[test]
    fn a_run_over_the_cap_is_not_finished() {
        let case = Case {
            shape: CaseShape::Circle,
            ratio: 16.0,
            width: 20.0,
        };
        let variants = Variant::expand(&[Method::Relaxation]);
        let runs = sweep(
            &base(),
            (&[case], &variants, &[1]),
            Duration::from_nanos(1),
            &Cancel::new(),
            &crate::farm::Local,
            |_| {},
        );
        assert_eq!(runs[0].status, Status::TimedOut);
        assert!(!runs[0].passed());
    }

    /// A run of `case` that ended as `status` with these checks' values.
    fn ended(status: Status, empty: f64, max_overlap: f64, psd_ks: f64) -> StabilityRun {
        StabilityRun {
            status,
            particles: 100,
            empty,
            max_overlap,
            psd_ks,
            ..StabilityRun::found(
                Case::all()[0],
                Variant::expand(&[Method::Rsa])[0],
                1,
                Checked::NONE,
            )
        }
    }

    /// Each failing run counted once, under all its reasons: the printed
    /// counts of each reason added up to more than the failures when a run
    /// failed two checks.
    #[test]
    fn a_tally_counts_each_run_once_and_its_parts_add_up() {
        let runs = [
            ended(Status::Finished, 0.0, 0.0, 0.0),
            ended(Status::Finished, 0.5, 0.0, 0.0),
            ended(Status::Finished, 0.0, 0.0, 0.9),
            ended(Status::Finished, 0.5, 0.0, 0.9),
            ended(Status::Finished, 0.5, 0.1, 0.9),
            ended(Status::Finished, 0.0, 0.1, 0.0),
            ended(Status::Refused, 1.0, 0.0, 1.0),
            ended(Status::TimedOut, 1.0, 0.0, 1.0),
        ];
        assert_eq!(runs[3].reasons(), [Reason::Empty, Reason::Grading]);
        assert!(runs[6].reasons().is_empty() && !runs[6].passed());
        let t = Tally::of(&runs);
        assert_eq!((t.pass, t.fail, t.refused, t.timed_out), (1, 5, 1, 1));
        assert_eq!(t.pass + t.fail + t.refused + t.timed_out, runs.len());
        assert_eq!(t.by_reasons.iter().map(|(_, n)| n).sum::<usize>(), t.fail);
        assert_eq!(
            t.by_reasons,
            [
                (vec![Reason::Overlap], 1),
                (vec![Reason::Empty], 1),
                (vec![Reason::Grading], 1),
                (vec![Reason::Empty, Reason::Grading], 1),
                (vec![Reason::Overlap, Reason::Empty, Reason::Grading], 1),
            ]
        );
    }

    #[test]
    fn empty_share_counts_the_unfilled_part() {
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        // One disk in the lower-left corner: most of the square is empty.
        let packing = Packing::of_disks(
            domain,
            vec![crate::geometry::Disk {
                c: Point::new(0.5, 0.5),
                r: 0.5,
            }],
        );
        let share = empty_share(&packing, 1.0, 1.0);
        assert!(share > 0.9 && share < 1.0, "{share}");
    }

    #[test]
    fn empty_share_measures_from_a_shape_s_outline() {
        // A needle across a 10 × 2 strip, 9 mm long and 0.2 mm wide: its
        // area-equivalent disk (radius 0.67 mm) leaves the strip's ends
        // empty, the needle itself does not.
        let domain = Domain::rectangle(10.0, 2.0).unwrap();
        let outline = crate::geometry::Outline::superellipse(4.5, 0.1, 2.0, 2.0).unwrap();
        let r = outline.equivalent_radius();
        let disk = crate::geometry::Disk {
            c: Point::new(5.0, 1.0),
            r,
        };
        let as_disk = Packing::of_disks(domain.clone(), vec![disk]);
        let as_needle =
            Packing::of_disks(domain, vec![disk]).with_grains(vec![Grain::new(outline, 0.0)]);
        let (d_min, d_max) = (0.2, 1.0);
        let (disk_share, needle_share) = (
            empty_share(&as_disk, d_min, d_max),
            empty_share(&as_needle, d_min, d_max),
        );
        assert!(disk_share > 0.4, "{disk_share}");
        assert_eq!(needle_share, 0.0);
    }
}
