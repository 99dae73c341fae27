//! Packer settings chosen by name in the config.

use crate::geometry::predicates::OVERLAP_REL;

/// Spatial index used for neighbour search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndexKind {
    /// MX quadtree: regular subdivision into leaf cells laid out in Morton order, data in leaves (default).
    #[default]
    MxQuadtree,
    /// Uniform grid of cells, for comparison.
    Grid,
}

/// Largest [`PackerSettings::gap`] accepted, in radii of the new disk. Wider
/// gaps strangle the chain of one-contact disks instead of loosening it
/// (measured: gap 1.5 on a 20 mm square of 1.2 mm disks stops at 4 disks;
/// gap 1 still fills it evenly, porosity 0.62).
pub const MAX_GAP: f64 = 1.0;

/// Largest [`PackerSettings::max_deferred`] accepted, and its default.
pub const MAX_DEFERRED: usize = 8;

/// How a packing is generated: the advancing front, or one of the methods
/// users compare it with (PFC's and YADE's generators and deposition).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Each disk tangent to two obstacles at the lowest spot of the front (default).
    #[default]
    AdvancingFront,
    /// Random sequential addition: random positions, kept when clear
    /// (PFC's trial generation, YADE's random cloud).
    Rsa,
    /// Ballistic deposition: dropped at a random abscissa, each disk rolls
    /// down the bed until two obstacles hold it.
    Deposition,
    /// Disks placed overlapping at a set porosity, then pushed apart
    /// (PFC's explosive repulsion, geometric separation).
    Relaxation,
    /// Disks of the drawn sizes placed at a target porosity below the
    /// advancing front's, their overlap energy minimised (FIRE) to zero:
    /// dense packings up to near the jamming limit of the grading.
    Densify,
}

/// Default of [`PackerSettings::attempts`]: PFC's 20,000 tries.
pub const DEFAULT_ATTEMPTS: usize = 20_000;

/// Settings of the relaxation method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relaxation {
    /// Porosity the overlapping disks are placed at: their number is the
    /// domain area × (1 − porosity) / the mean disk area.
    pub porosity: f64,
    /// Sweeps of pushing apart, at most.
    pub iterations: usize,
    /// Stop once the largest overlap, relative to the sum of the radii, is below this.
    /// A packing is written only if no overlap exceeds
    /// [`OVERLAP_REL`] (the write
    /// check): a larger tolerance stops the sweeps with overlaps the check refuses.
    pub tolerance: f64,
}

/// Default of [`Relaxation::tolerance`]: half the overlap the write check
/// allows, so that a relaxation that converges leaves a packing that passes
/// it, rounding included. (It was 1e-4: a loose scene, porosity 0.5,
/// stopped at overlaps of 1e-4 and was refused, every time.)
const RELAXATION_TOLERANCE: f64 = 0.5 * OVERLAP_REL;

impl Default for Relaxation {
    fn default() -> Self {
        Relaxation {
            porosity: 0.2,
            iterations: 2000,
            tolerance: RELAXATION_TOLERANCE,
        }
    }
}

/// Settings of the densify method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Densify {
    /// Target porosity, of the area inside the walls (less a strip half a
    /// wall disk wide with wall disks, as relaxation counts it): the disks
    /// are the first sizes drawn whose area comes nearest to that area ×
    /// (1 − porosity), about that over the grading's mean disk area.
    pub porosity: f64,
    /// Minimisation steps at most, over the whole run (the search for the
    /// densest porosity reached, when the target is not, included).
    pub iterations: usize,
}

impl Default for Densify {
    fn default() -> Self {
        Densify {
            porosity: 0.17,
            iterations: 200_000,
        }
    }
}

/// Settings of the packer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PackerSettings {
    /// The generator.
    pub method: Method,
    /// Random sequential addition: positions tried per disk before the run
    /// stops (the domain is full at this effort).
    pub attempts: usize,
    /// The relaxation method's settings.
    pub relaxation: Relaxation,
    /// The densify method's settings.
    pub densify: Densify,
    /// Neighbour-search structure.
    pub index: IndexKind,
    /// What happens to fronts and sizes that fail.
    pub rules: FrontRules,
    /// Share of placements, in [0, 1], that touch the front only, at a random
    /// free angle, instead of the front and one more obstacle at the lowest
    /// spot: 0 = dense (the thesis), 1 = every disk touches one obstacle
    /// (loose). Each placement draws its kind from the seeded stream.
    pub one_contact_share: f64,
    /// Clearance a one-contact disk keeps from every disk it does not touch,
    /// in its own radii, in [0, [`MAX_GAP`]]: looser packs still, each disk
    /// touching at least its front (walls get no gap: a disk may rest on one).
    pub gap: f64,
    /// Robust rules: sizes that may wait for a place (deferred) while the
    /// run goes on, in [0, [`MAX_DEFERRED`]]. When one more size fits nowhere
    /// with this many waiting, the domain is full for the grading and the run
    /// stops. More fills the last gaps with the smaller sizes that still fit
    /// (denser, but the placed sizes lean small); 0 stops at the first size
    /// that fits nowhere (the placed sizes are exactly the ones drawn before it).
    pub max_deferred: usize,
    /// Which way the front advances through the domain.
    pub fill: Fill,
    /// Whether the advancing front packs the domain in strips, on every core.
    pub strips: Strips,
}

impl Default for PackerSettings {
    fn default() -> Self {
        PackerSettings {
            method: Method::default(),
            attempts: DEFAULT_ATTEMPTS,
            relaxation: Relaxation::default(),
            densify: Densify::default(),
            index: IndexKind::default(),
            rules: FrontRules::default(),
            one_contact_share: 0.0,
            gap: 0.0,
            max_deferred: MAX_DEFERRED,
            fill: Fill::default(),
            strips: Strips::default(),
        }
    }
}

/// Whether the advancing front packs one domain in strips of tiles, a
/// diagonal of tiles at a time on every core (the packing depends on the
/// strips, never on the threads; see `packer::strips`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strips {
    /// In strips when the scene holds more than about 200,000 disks and
    /// allows them (a rectangle, exact walls, dense robust packs); else in one piece.
    Auto,
    /// In this many strips of equal width; 1: in one piece.
    Count(u32),
}

/// [`Strips::Auto`]: a scene of more than about 200,000 disks packs in
/// strips, whose seams cannot be told from the bulk (within 3 largest
/// diameters of them the porosity within ±0.002 of the bulk's and the
/// cells' spread within 20 % of it, Tables 3.1 and 3.4; docs/results.md,
/// "Strips: the seams"); smaller ones in one piece, as before.
impl Default for Strips {
    fn default() -> Self {
        Strips::Auto
    }
}

/// Front-list rules: the thesis' as written, or the robust ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrontRules {
    /// A front that fails for a size is parked and retried for smaller sizes; a
    /// size that fits at no front is deferred instead of emptying the list (default).
    #[default]
    Robust,
    /// The thesis to the letter: a failing front is dropped, and the run stops
    /// when the front list empties.
    Thesis,
}

/// Which way the front advances: which spot counts as the lowest.
///
/// The packing grows from where the front starts and fills the domain in
/// that direction. In a fracture the two give different structures: `Up`
/// settles the proppant along the fracture height, `Right` builds layers
/// parallel to the fracture faces, as the thesis' fracture packs did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Fill {
    /// Lowest ordinate first, then lowest abscissa: deposition under gravity along −y (default).
    #[default]
    Up,
    /// Lowest abscissa first, then lowest ordinate: the same along −x.
    Right,
}
