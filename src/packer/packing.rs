//! The one `Packing` type every generator returns and every metric and writer takes.

use crate::geometry::predicates::RESOLUTION_REL;
use crate::geometry::{Disk, Domain, Grain, Point, WallMode};

/// A packing: the domain, the packed disks and, for `walls = "disks"`, the wall disks.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Packing {
    /// The domain that was filled.
    pub domain: Domain,
    /// How the walls were modelled.
    pub walls: WallMode,
    /// Wall disks (empty for exact walls); not counted as solid.
    pub boundary: Vec<Disk>,
    /// The packed disks, in placement order.
    pub disks: Vec<Disk>,
    /// The outline and orientation of each packed particle, when they are not
    /// disks (a config's `[shape]`); empty for disks. With grains, each of
    /// `disks` is the particle's centre and **area-equivalent radius** (so
    /// that every area, the porosity among them, is exact), and the grain
    /// is the particle itself.
    pub grains: Vec<Grain>,
    /// Material of each packed disk, as an index into the scene's materials;
    /// empty when the packing carries none.
    pub materials: Vec<u16>,
    /// Counters of the generator's work.
    pub stats: PackStats,
}

impl Packing {
    /// Disks placed elsewhere (read from a table, or built by hand) in
    /// `domain`, as a packing: exact walls, no wall disks, no materials, no
    /// generator counters. Struct update syntax sets the rest.
    pub fn of_disks(domain: Domain, disks: Vec<Disk>) -> Self {
        Packing {
            domain,
            walls: WallMode::Exact,
            boundary: Vec::new(),
            disks,
            grains: Vec::new(),
            materials: Vec::new(),
            stats: PackStats::default(),
        }
    }
}

impl Packing {
    /// This packing with `grains`, one per packed particle: particles that
    /// are not disks, `disks` holding their centres and area-equivalent
    /// radii (a table read back, a packing built by hand).
    #[must_use]
    pub fn with_grains(self, grains: Vec<Grain>) -> Self {
        Packing { grains, ..self }
    }

    /// A packing of `grains` centred at `centres` (one each) in `domain`,
    /// each disk the centre and the grain's area-equivalent radius.
    pub fn of_grains(domain: Domain, grains: Vec<Grain>, centres: &[Point]) -> Self {
        let disks = grains
            .iter()
            .zip(centres)
            .map(|(g, c)| Disk::new(c.x, c.y, g.outline.equivalent_radius()))
            .collect();
        Packing::of_disks(domain, disks).with_grains(grains)
    }
}

/// Counters of the generator's work, for reports and benchmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct PackStats {
    /// Sizes drawn from the grading.
    pub sizes_drawn: u64,
    /// Sizes put aside because they fitted nowhere when drawn.
    pub sizes_deferred: u64,
    /// Deferred sizes that were never placed.
    pub sizes_unplaced: u64,
    /// Front attempts (placements tried around a front).
    pub front_attempts: u64,
    /// One-contact sizes placed at two contacts because no free arc kept their gap.
    pub fallbacks: u64,
    /// Witness checks: a returning front's remembered spot tested instead of a full attempt.
    pub witness_checks: u64,
    /// Work done by the advancing front: neighbours visited in the index and
    /// tested against candidates, candidates made, walls tested (see
    /// [`work_budget`](crate::packer::work_budget)). Not counted by the
    /// comparison generators.
    pub work: u64,
}

/// Packing rate assumed by the time estimates of the limits (disks/s): the
/// MX quadtree's measured rate on 10⁵–10⁶ disks (`gapack bench`), rounded down.
pub const PACK_RATE: f64 = 400_000.0;

/// The end of a densify error: the target to ask for instead, found by
/// packing it (`advice`), or that none of the looser targets tried packed.
fn advise(advice: Option<std::num::NonZeroU16>) -> String {
    match advice {
        Some(t) => format!(
            "; ask for a porosity of {:.3} or more: these sizes were packed at it",
            f64::from(t.get()) / 1000.0
        ),
        None => "; no looser target tried (up to 0.031 looser) packed".to_owned(),
    }
}

/// Why a scene cannot be packed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PackError {
    /// No disk of the grading fits inside the domain.
    #[error(
        "the domain is too narrow: the largest disk that fits inside its walls has diameter {inscribed:.4} mm, smaller than the smallest disk ({d_min:.4} mm)"
    )]
    DomainTooNarrow {
        /// Diameter of the largest disk that fits inside the walls (mm), see
        /// [`crate::Scene::inscribed_diameter`].
        inscribed: f64,
        /// Smallest diameter of the grading (mm).
        d_min: f64,
    },
    /// The wall disks would be too many (`walls = "disks"` with a tiny wall-disk diameter).
    #[error(
        "walls = \"disks\" with wall disks of {diameter:.4} mm would need more than {max} disks on the boundary; use larger wall disks or walls = \"exact\""
    )]
    TooManyWallDisks {
        /// The wall-disk diameter (mm).
        diameter: f64,
        /// The most wall disks allowed.
        max: usize,
    },
    /// `walls = "periodic"` on a domain that is not a periodic cell (a
    /// rectangle: [`Domain::periodic_rectangle`]).
    #[error(
        "walls = \"periodic\" needs a rectangle, the periodic cell; a {shape} has walls (use walls = \"exact\" or \"disks\", or a rectangle)"
    )]
    NotPeriodic {
        /// The domain's shape, as a config names it.
        shape: &'static str,
    },
    /// A periodic cell ([`Domain::periodic_rectangle`]) packed with walls.
    #[error(
        "the domain is a periodic cell but walls = \"{walls}\": a periodic cell has no walls; set walls = \"periodic\" (Scene::with_walls)"
    )]
    PeriodicWalls {
        /// The wall model given, as a config names it.
        walls: &'static str,
    },
    /// A periodic cell narrower than twice the largest diameter.
    #[error(
        "the periodic cell's shorter side, {side} mm, is less than twice the largest diameter ({d_max} mm): a disk could then touch another disk and its image at once, or its own image; pack a larger cell or smaller disks"
    )]
    PeriodicCellTooSmall {
        /// The cell's shorter side (mm).
        side: f64,
        /// Largest diameter of the grading (mm).
        d_max: f64,
    },
    /// A method that packs against walls asked to pack a periodic cell.
    #[error(
        "method \"{method}\" packs against walls and does not pack periodic cells; use method = \"advancing-front\", \"rsa\", \"relaxation\" or \"densify\" with walls = \"periodic\""
    )]
    PeriodicMethod {
        /// The method, as a config names it.
        method: &'static str,
    },
    /// The run was cancelled, or its time cap passed, before it finished.
    #[error("{0}")]
    Cancelled(#[from] crate::cancel::Cancelled),
    /// The scene could hold more disks than allowed.
    #[error(
        "the scene holds up to an estimated {disks:.3e} disks (about {:.1} s to pack at {:.1e} disks/s), over the limit of {limit} disks",
        .disks / PACK_RATE,
        PACK_RATE
    )]
    TooManyParticles {
        /// Estimated disks (an upper bound: the domain filled solid with disks of the mean area).
        disks: f64,
        /// The limit.
        limit: u64,
    },
    /// The smallest disk is too small for floating point to keep it apart
    /// from its neighbours where the domain lies: its diameter is less than
    /// `RESOLUTION_REL` of the largest |coordinate|.
    #[error(
        "the smallest diameter, {d_min} mm, is less than {RESOLUTION_REL} of the largest coordinate, {coordinate} mm: floating point spaces coordinates there {:.1e} mm apart, too coarse to keep disks from overlapping",
        .coordinate.next_up() - .coordinate
    )]
    Unresolvable {
        /// Smallest diameter of the grading (mm).
        d_min: f64,
        /// Largest |coordinate| of the domain (mm).
        coordinate: f64,
    },
    /// The run reached the particle ceiling ([`crate::Limits::max_particles`])
    /// before the domain was full.
    #[error(
        "the packing reached the particle limit of {limit} disks before the domain was full (limits.max_particles); raise it to pack this scene whole, or pack a smaller domain or coarser sizes"
    )]
    ParticleLimit {
        /// The limit (disks).
        limit: u64,
    },
    /// The run reached the memory ceiling ([`crate::Limits::max_memory_bytes`])
    /// before the domain was full.
    #[error(
        "the packing reached the memory limit of {limit_mb:.0} MB (about {disks} disks) before the domain was full (limits.max_memory_mb); raise it to pack this scene whole"
    )]
    MemoryLimit {
        /// The limit (MB).
        limit_mb: f64,
        /// The disks that fit in it, wall disks aside.
        disks: u64,
    },
    /// The advancing front did all the work its scene allows
    /// ([`work_budget`](crate::packer::work_budget)) before the domain was
    /// full: a grading so wide, or a boundary of so many edges, that each
    /// size is tried against thousands of neighbours or walls, where the run
    /// would go on for many minutes more. No packing is returned: one cut
    /// short is not a sample of the grading (its upper part is missing).
    #[error(
        "the packer stopped after the work this scene allows ({budget:.3e} neighbour tests), with {disks} disks placed from {sizes_drawn} sizes drawn and the domain not yet full: each size was tried against thousands of neighbours or walls (a grading this wide for this domain, or a boundary of thousands of edges); narrow the grading (d_max / d_min), pack a smaller domain, or simplify the boundary"
    )]
    WorkBudget {
        /// The work allowed.
        budget: u64,
        /// Disks placed when it stopped.
        disks: u64,
        /// Sizes drawn when it stopped.
        sizes_drawn: u64,
    },
    /// The densify method did not pack its disks at the target porosity
    /// without overlap: the target is denser than this grading packs in this
    /// domain (past its jamming limit: the disks jammed), or needs more
    /// steps than allowed. No packing is returned (one with overlaps is
    /// never written); `reached` says which target to ask for instead.
    #[error(
        "packer.densify_porosity = {target} was not reached without overlap ({}, after {steps} minimisation steps): these disks (porosity {:.4} at their size) were packed without overlap only at {scale:.4} of their size, porosity {reached:.4}{}{}",
        if *.jammed { "the disks jammed: their overlaps are held in balance" } else { "the step budget ran out" },
        1.0 - (1.0 - .reached) / (.scale * .scale),
        advise(*.advice),
        if *.jammed { "" } else { ", or raise packer.densify_iterations" }
    )]
    DensityUnreached {
        /// The target porosity.
        target: f64,
        /// The densest porosity the same disks were packed at without
        /// overlap, with their radii scaled by `scale`: of the area the
        /// target is (inside the walls, less the wall disks' strip).
        reached: f64,
        /// The scale of the radii at `reached` (< 1).
        scale: f64,
        /// Minimisation steps taken, the search for `reached` included (at
        /// most `packer.densify_iterations`, 10⁶).
        steps: u32,
        /// Whether the disks jammed at the target (rather than running out of steps).
        jammed: bool,
        /// A looser target at which the same method packed these sizes, to
        /// ask for instead, in thousandths (162 for 0.162; looser than the
        /// target, so not 0, and below 1000; kept small so that the error
        /// stays small); `None` when none of those tried packed, or none
        /// was tried.
        advice: Option<std::num::NonZeroU16>,
    },
    /// Particles that are not disks (a `[shape]`) asked of something that
    /// packs disks only.
    #[error(
        "particles that are not disks ([shape]) are not packed with {what}: use method = \"advancing-front\" (two or one contact) or \"rsa\", with exact walls or a periodic cell"
    )]
    NotForShapes {
        /// What was asked, as a config names it.
        what: String,
    },
    /// The scene would need more memory than allowed.
    #[error(
        "the scene needs an estimated {estimate_mb:.0} MB ({disks:.3e} disks), over the limit of {limit_mb:.0} MB"
    )]
    TooLarge {
        /// Estimated disks.
        disks: f64,
        /// Estimated peak memory (MB).
        estimate_mb: f64,
        /// The limit (MB).
        limit_mb: f64,
    },
}
