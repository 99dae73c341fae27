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

/// How many obstacles a new disk must touch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Contacts {
    /// Tangent to the front and one more obstacle (dense; default).
    #[default]
    Two,
    /// Tangent to the front only, at a random free angle (loose packs).
    One,
}

/// Settings of the advancing-front packer.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PackerSettings {
    /// Neighbour-search structure.
    pub index: IndexKind,
    /// Contact rule for new disks.
    pub contacts: Contacts,
    /// What happens to fronts and sizes that fail.
    pub rules: FrontRules,
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
