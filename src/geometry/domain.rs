//! Domains (rectangle, simple polygon, circle, trapezoid) and their walls.
//!
//! STUB: the geometry helper replaces the `todo!()` bodies; signatures are fixed.

use super::{Disk, Point};

/// How the boundary is modelled while packing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WallMode {
    /// Straight and circular walls as they are (default).
    #[default]
    Exact,
    /// The boundary discretised into touching disks centred on it, as the thesis does.
    Disks,
}

/// The shape a domain was built from, kept for reporting and drawing.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Axis-aligned rectangle with its lower-left corner at the origin.
    Rectangle {
        /// Extent along x (mm).
        width: f64,
        /// Extent along y (mm).
        height: f64,
    },
    /// Simple polygon, vertices stored counter-clockwise.
    Polygon {
        /// Vertices, counter-clockwise, no repeated closing vertex.
        vertices: Vec<Point>,
    },
    /// Circle.
    Circle {
        /// Centre (mm).
        center: Point,
        /// Radius (mm).
        radius: f64,
    },
    /// Trapezoid: bottom edge (0,0)-(bottom,0), top edge of length `top` centred at y = height.
    Trapezoid {
        /// Bottom edge length (mm).
        bottom: f64,
        /// Top edge length (mm).
        top: f64,
        /// Height (mm).
        height: f64,
    },
}

/// One wall of a domain, as the packer sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wall {
    /// Straight wall from `a` to `b`; the domain lies on its left (boundary counter-clockwise).
    Segment {
        /// Start point.
        a: Point,
        /// End point.
        b: Point,
    },
    /// Circular wall; the domain lies inside it.
    Circle {
        /// Centre.
        center: Point,
        /// Radius.
        radius: f64,
    },
}

/// Why a domain cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GeometryError {
    /// A size is zero, negative, NaN or infinite.
    #[error("{what} must be a positive finite number, got {value}")]
    BadSize {
        /// Which size.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A polygon with fewer than three vertices.
    #[error("a polygon needs at least 3 vertices, got {0}")]
    TooFewVertices(usize),
    /// A polygon vertex is NaN or infinite.
    #[error("polygon vertex {index} is not finite")]
    NonFiniteVertex {
        /// Zero-based vertex index.
        index: usize,
    },
    /// A polygon with (near) zero area or repeated vertices.
    #[error("polygon is degenerate: {0}")]
    Degenerate(String),
    /// A polygon whose edges cross.
    #[error(
        "polygon crosses itself: edge {first} ({first_from} -> {first_to}) meets edge {second}"
    )]
    SelfIntersecting {
        /// Zero-based index of the first edge.
        first: usize,
        /// Start vertex index of the first edge.
        first_from: usize,
        /// End vertex index of the first edge.
        first_to: usize,
        /// Zero-based index of the second edge.
        second: usize,
    },
}

/// A region to fill, with its walls precomputed.
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    shape: Shape,
}

impl Domain {
    /// Rectangle `width` × `height`, lower-left corner at the origin.
    pub fn rectangle(width: f64, height: f64) -> Result<Self, GeometryError> {
        todo!("{width}{height}")
    }
    /// Simple polygon (either orientation, stored counter-clockwise).
    pub fn polygon(vertices: &[Point]) -> Result<Self, GeometryError> {
        todo!("{vertices:?}")
    }
    /// Circle of `radius` around `center`.
    pub fn circle(center: Point, radius: f64) -> Result<Self, GeometryError> {
        todo!("{center}{radius}")
    }
    /// Trapezoid: bottom edge (0,0)-(bottom,0), top edge centred at y = height.
    pub fn trapezoid(bottom: f64, top: f64, height: f64) -> Result<Self, GeometryError> {
        todo!("{bottom}{top}{height}")
    }
    /// The shape the domain was built from.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }
    /// Area (mm²).
    pub fn area(&self) -> f64 {
        todo!()
    }
    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Point, Point) {
        todo!()
    }
    /// Area centroid.
    pub fn centroid(&self) -> Point {
        todo!()
    }
    /// Walls, counter-clockwise (segments) or the one circle.
    pub fn walls(&self) -> &[Wall] {
        todo!()
    }
    /// Reflex (concave) polygon corners: point obstacles for exact walls.
    pub fn reflex_vertices(&self) -> &[Point] {
        todo!()
    }
    /// Signed distance from `p` to the boundary: positive inside, negative outside.
    pub fn signed_distance(&self, p: Point) -> f64 {
        todo!("{p}")
    }
    /// Radius of the largest disk that fits inside the domain.
    pub fn inradius(&self) -> f64 {
        todo!()
    }
    /// Outline for drawing: the polygon's vertices, or the circle as a polygon.
    pub fn outline(&self, segments_per_circle: usize) -> Vec<Point> {
        todo!("{segments_per_circle}")
    }
    /// The boundary discretised into touching disks of `diameter`, centred on it.
    pub fn boundary_disks(&self, diameter: f64) -> Vec<Disk> {
        todo!("{diameter}")
    }
}
