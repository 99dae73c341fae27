//! Packer settings chosen by name in the config.

/// Spatial index used for neighbour search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndexKind {
    /// MX quadtree: regular subdivision of a 2^N-cell square, data in leaves (default).
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

/// Settings of the advancing-front packer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PackerSettings {
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
}

impl Default for PackerSettings {
    fn default() -> Self {
        PackerSettings {
            index: IndexKind::default(),
            rules: FrontRules::default(),
            one_contact_share: 0.0,
            gap: 0.0,
            max_deferred: MAX_DEFERRED,
            fill: Fill::default(),
        }
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
