//! Domains (rectangle, simple polygon, circle, trapezoid) and their walls.
//!
//! A [`Domain`] is validated once when it is built and precomputes what the
//! packer asks of it (walls, reflex corners, area, inradius), so the queries
//! are cheap. Polygon routines live in `polygon.rs`, the largest inscribed
//! disk of a polygon in `inscribed.rs`.

use std::f64::consts::TAU;

use nalgebra::Vector2;

use super::inscribed::max_inscribed_radius_polygon;
use super::polygon::{
    Edge, bounds_of, centroid_of, edges_of, reflex_vertices_of, signed_area,
    signed_distance_point_polygon, validate_polygon,
};
use super::predicates::{area_disk_box, area_polygon_box};
use super::{Disk, Point};

/// How the boundary is modelled while packing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WallMode {
    /// Straight and circular walls as they are (default).
    #[default]
    Exact,
    /// The boundary discretised into touching disks centred on it, as the thesis does.
    Disks,
    /// No walls: a rectangle as a periodic cell, each disk crossing an edge
    /// present again, as its image, across the opposite edge (see
    /// [`Domain::periodic_rectangle`]).
    Periodic,
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
    /// A polygon with more vertices than [`Domain::MAX_POLYGON_VERTICES`].
    #[error(
        "a polygon may have at most {max} vertices, got {count}: the packer tests a disk near the boundary against every edge, so each vertex slows every placement along the walls; simplify the outline (vertices closer than the smallest diameter change nothing a disk can feel)"
    )]
    TooManyVertices {
        /// Vertices given.
        count: usize,
        /// The most allowed.
        max: usize,
    },
    /// A polygon vertex is NaN or infinite.
    #[error("polygon vertex {index} is not finite")]
    NonFiniteVertex {
        /// Zero-based vertex index.
        index: usize,
    },
    /// A circle centre is NaN or infinite.
    #[error("circle centre ({x}, {y}) is not finite")]
    NonFiniteCenter {
        /// Abscissa given.
        x: f64,
        /// Ordinate given.
        y: f64,
    },
    /// A polygon with (near) zero area, repeated vertices or a spike folding
    /// back on itself; or any domain whose area is not a finite positive
    /// number (sizes so large or small that it overflows or underflows).
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
///
/// # Behavior
/// Built by [`Domain::rectangle`], [`Domain::polygon`], [`Domain::circle`]
/// or [`Domain::trapezoid`], which validate their input; every query after
/// that is infallible. Straight boundaries are stored counter-clockwise.
///
/// # Example
/// ```
/// use gapack::{Domain, Point};
/// let d = Domain::rectangle(40.0, 10.0).unwrap();
/// assert_eq!(d.area(), 400.0);
/// assert_eq!(d.inradius(), 5.0);
/// assert_eq!(d.signed_distance(Point::new(3.0, 5.0)), 3.0);
/// assert_eq!(d.signed_distance(Point::new(-3.0, -4.0)), -5.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    shape: Shape,
    /// Boundary vertices, counter-clockwise; empty for a circle.
    vertices: Vec<Point>,
    /// `vertices` as edges (vertex `i` to `i + 1`); empty for a circle.
    edges: Vec<Edge>,
    walls: Vec<Wall>,
    reflex: Vec<Point>,
    area: f64,
    centroid: Point,
    bounds: (Point, Point),
    inradius: f64,
    /// A periodic cell: its edges are not walls (see [`Domain::period`]).
    periodic: bool,
}

impl Domain {
    /// Most disks [`Domain::boundary_disks`] will produce (2²², about 4·10⁶,
    /// 100 MB); a finer discretisation yields no disks at all.
    pub const MAX_BOUNDARY_DISKS: usize = 1 << 22;

    /// Most vertices [`Domain::polygon`] accepts (4,096).
    ///
    /// # Behavior
    /// The advancing front tests a disk near the boundary against every
    /// edge (its distance to the walls, its tangencies to them, and for the
    /// seed disk every pair of edges), and the self-intersection check of a
    /// polygon is quadratic: 100,000 vertices took 74 s to validate and did
    /// not pack in 300 s. At this cap a 40 mm star-shaped outline packs its
    /// 2,200 disks in 4 s (1,000 vertices: 0.4 s); 10,000 vertices reach the
    /// packer's work budget. A DEM outline needs no vertex closer to the next
    /// than the smallest diameter (a disk cannot feel the difference), and a
    /// fracture or core outline a few hundred diameters around does not
    /// come near the cap.
    pub const MAX_POLYGON_VERTICES: usize = 4096;

    /// Rectangle `width` × `height`, lower-left corner at the origin.
    ///
    /// # Returns
    /// [`GeometryError::BadSize`] naming `"width"` or `"height"` unless both
    /// are positive and finite; [`GeometryError::Degenerate`] if the area
    /// overflows or underflows.
    pub fn rectangle(width: f64, height: f64) -> Result<Self, GeometryError> {
        let width = positive("width", width)?;
        let height = positive("height", height)?;
        let vertices = vec![
            Point::new(0.0, 0.0),
            Point::new(width, 0.0),
            Point::new(width, height),
            Point::new(0.0, height),
        ];
        let shape = Shape::Rectangle { width, height };
        let mut domain = Self::polygonal(shape, vertices, Some(0.5 * width.min(height)))?;
        domain.centroid = Point::new(0.5 * width, 0.5 * height);
        Ok(domain)
    }

    /// Periodic cell `width` × `height`, lower-left corner at the origin: a
    /// rectangle whose edges are not walls. A disk may cross an edge; it is
    /// then present, as its image shifted by ±`width` or ±`height`, across
    /// the opposite one (`walls = "periodic"`).
    ///
    /// # Behavior
    /// The same rectangle as [`Domain::rectangle`] (shape, area, bounds,
    /// inradius, signed distance to its outline), marked periodic: see
    /// [`Domain::period`], [`Domain::wrap`] and [`Domain::image_shifts`].
    /// A packing of it stores each centre in `[0, width) × [0, height)`.
    ///
    /// # Returns
    /// As [`Domain::rectangle`].
    ///
    /// # Example
    /// ```
    /// use gapack::{Domain, Point};
    /// let cell = Domain::periodic_rectangle(10.0, 4.0).unwrap();
    /// assert_eq!(cell.period().map(|p| (p.x, p.y)), Some((10.0, 4.0)));
    /// assert_eq!(cell.wrap(Point::new(-1.0, 9.0)), Point::new(9.0, 1.0));
    /// assert!(Domain::rectangle(10.0, 4.0).unwrap().period().is_none());
    /// ```
    pub fn periodic_rectangle(width: f64, height: f64) -> Result<Self, GeometryError> {
        Ok(Domain {
            periodic: true,
            ..Self::rectangle(width, height)?
        })
    }

    /// This domain as a periodic cell if `periodic` (and it is a rectangle),
    /// else with walls; a domain of any other shape is returned as it is,
    /// with walls.
    ///
    /// # Example
    /// ```
    /// use gapack::{Domain, Point};
    /// let square = Domain::rectangle(4.0, 4.0).unwrap();
    /// assert!(square.with_periodic(true).period().is_some());
    /// assert_eq!(square.with_periodic(true).with_periodic(false), square);
    /// let disk = Domain::circle(Point::new(0.0, 0.0), 2.0).unwrap();
    /// assert!(disk.with_periodic(true).period().is_none());
    /// ```
    #[must_use]
    pub fn with_periodic(&self, periodic: bool) -> Domain {
        let periodic = periodic && matches!(self.shape, Shape::Rectangle { .. });
        Domain {
            periodic,
            ..self.clone()
        }
    }

    /// The periods of a periodic cell along x and y (its width and height),
    /// or `None` for a domain with walls.
    #[inline]
    pub fn period(&self) -> Option<Vector2<f64>> {
        self.periodic.then(|| self.bounds.1 - self.bounds.0)
    }

    /// Whether the domain is a periodic cell.
    #[inline]
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// `p` moved by whole periods into the cell `[min, max)` along each
    /// axis (a periodic cell); `p` itself for a domain with walls.
    ///
    /// # Behavior
    /// A point already in the cell is returned unchanged, bit for bit. A
    /// coordinate that rounds onto the upper edge goes to the lower one
    /// (the same point, one period away), so the result is always in the
    /// half-open cell.
    #[inline]
    pub fn wrap(&self, p: Point) -> Point {
        if !self.periodic {
            return p;
        }
        let (lo, hi) = self.bounds;
        Point::new(wrap_axis(p.x, lo.x, hi.x), wrap_axis(p.y, lo.y, hi.y))
    }

    /// The lattice shifts `s` (whole periods along x and y) whose images
    /// may meet the box `lo`–`hi`: every centre `c` stored in the cell
    /// whose image `c + s` lies in the box is found by searching the box
    /// `lo − s`–`hi − s`, and no other shift gives one. A domain with walls
    /// gives the zero shift alone.
    ///
    /// # Behavior
    /// Shifts come row by row (y, then x), lowest first; a box inside the
    /// cell gives the zero shift alone, one across an edge two, one across
    /// a corner four. A box wider than the cell gives more (each image once).
    ///
    /// # Example
    /// ```
    /// use gapack::{Domain, Point};
    /// let cell = Domain::periodic_rectangle(10.0, 10.0).unwrap();
    /// let shifts: Vec<(f64, f64)> = cell
    ///     .image_shifts(Point::new(-1.0, 4.0), Point::new(1.0, 6.0))
    ///     .map(|s| (s.x, s.y))
    ///     .collect();
    /// assert_eq!(shifts, [(-10.0, 0.0), (0.0, 0.0)]);
    /// ```
    pub fn image_shifts(&self, lo: Point, hi: Point) -> ImageShifts {
        let Some(period) = self.period() else {
            return ImageShifts::single();
        };
        let (cell_lo, cell_hi) = self.bounds;
        // Shift k along an axis when [a − k·w, b − k·w] meets [lo, hi].
        let range = |a: f64, b: f64, lo: f64, hi: f64, w: f64| {
            let first = ((a - hi) / w).ceil();
            let last = ((b - lo) / w).floor();
            if first.is_finite() && last.is_finite() && first <= last {
                // A box spanning absurdly many periods is cut to what the
                // cell's neighbours hold; no caller asks for more.
                let first = first.max(-MAX_SHIFT);
                let last = last.min(MAX_SHIFT);
                (first as i64, last as i64)
            } else {
                (1, 0)
            }
        };
        let kx = range(lo.x, hi.x, cell_lo.x, cell_hi.x, period.x);
        let ky = range(lo.y, hi.y, cell_lo.y, cell_hi.y, period.y);
        ImageShifts {
            period,
            kx,
            ky,
            next: (kx.0, ky.0),
        }
    }

    /// Simple polygon (either orientation, stored counter-clockwise).
    ///
    /// # Behavior
    /// A last vertex exactly equal to the first (an explicitly closed ring)
    /// is dropped silently. A vertex in the middle of a straight edge is kept
    /// (it is neither reflex nor an error). Vertex and edge indices in errors
    /// refer to the input order; edge `i` runs from vertex `i` to `i + 1`.
    ///
    /// # Returns
    /// In the order checked: [`GeometryError::NonFiniteVertex`];
    /// [`GeometryError::TooFewVertices`] (fewer than 3 after dropping a
    /// closing vertex); [`GeometryError::Degenerate`] for consecutive
    /// vertices closer than 1e-12 of the bounding-box diagonal, or a spike
    /// (two adjacent edges folding back on each other, within 1e-12 rad);
    /// [`GeometryError::SelfIntersecting`] for two non-adjacent edges that
    /// cross, touch or overlap (exact orientation tests); and
    /// [`GeometryError::Degenerate`] for an area at most 1e-10 of the
    /// bounding-box area.
    ///
    /// # Performance
    /// O(n²) validation; the inradius is precomputed here, O(n³) up to
    /// 200 edges + reflex corners, a bounded branch and bound above.
    ///
    /// # Example
    /// ```
    /// use gapack::{Domain, GeometryError, Point};
    /// let bow_tie = [(0.0, 0.0), (2.0, 2.0), (2.0, 0.0), (0.0, 2.0)].map(|(x, y)| Point::new(x, y));
    /// assert!(matches!(
    ///     Domain::polygon(&bow_tie),
    ///     Err(GeometryError::SelfIntersecting { first: 0, second: 2, .. })
    /// ));
    /// ```
    pub fn polygon(vertices: &[Point]) -> Result<Self, GeometryError> {
        let vertices = validate_polygon(vertices)?;
        let shape = Shape::Polygon {
            vertices: vertices.clone(),
        };
        Self::polygonal(shape, vertices, None)
    }

    /// Circle of `radius` around `center`.
    ///
    /// # Returns
    /// [`GeometryError::NonFiniteCenter`], [`GeometryError::BadSize`]
    /// naming `"radius"`, or [`GeometryError::Degenerate`] if the area
    /// overflows or underflows.
    pub fn circle(center: Point, radius: f64) -> Result<Self, GeometryError> {
        if !center.x.is_finite() || !center.y.is_finite() {
            return Err(GeometryError::NonFiniteCenter {
                x: center.x,
                y: center.y,
            });
        }
        let radius = positive("radius", radius)?;
        let area = finite_area(std::f64::consts::PI * radius * radius)?;
        let half = Vector2::new(radius, radius);
        Ok(Domain {
            shape: Shape::Circle { center, radius },
            vertices: Vec::new(),
            edges: Vec::new(),
            walls: vec![Wall::Circle { center, radius }],
            reflex: Vec::new(),
            area,
            centroid: center,
            bounds: (center - half, center + half),
            inradius: radius,
            periodic: false,
        })
    }

    /// Trapezoid: bottom edge (0,0)-(bottom,0), top edge centred at y = height.
    ///
    /// # Behavior
    /// Vertices `(0, 0)`, `(bottom, 0)`, `(bottom/2 + top/2, height)`,
    /// `(bottom/2 − top/2, height)`; either base may be the longer. The
    /// inradius is exact: the smaller of `height/2` and the inradius of the
    /// triangle formed by the longer base and the extended legs.
    ///
    /// # Returns
    /// [`GeometryError::BadSize`] naming `"bottom"`, `"top"` or `"height"`
    /// unless all are positive and finite; [`GeometryError::Degenerate`] if
    /// the sizes are so disparate that vertices coincide in floating point,
    /// or the area overflows.
    pub fn trapezoid(bottom: f64, top: f64, height: f64) -> Result<Self, GeometryError> {
        let bottom = positive("bottom", bottom)?;
        let top = positive("top", top)?;
        let height = positive("height", height)?;
        let (mid, half_top) = (0.5 * bottom, 0.5 * top);
        let vertices = validate_polygon(&[
            Point::new(0.0, 0.0),
            Point::new(bottom, 0.0),
            Point::new(mid + half_top, height),
            Point::new(mid - half_top, height),
        ])?;
        let shape = Shape::Trapezoid {
            bottom,
            top,
            height,
        };
        let inradius = inradius_trapezoid(bottom, top, height);
        Self::polygonal(shape, vertices, Some(inradius))
    }

    /// The domain mirrored in the line y = x (coordinates swapped).
    ///
    /// # Behavior
    /// A packing of the mirror with its coordinates swapped back is a packing
    /// of this domain: the packer fills along x by filling the mirror along y.
    /// Rectangles stay rectangles (width and height swapped) and circles
    /// circles; trapezoids become polygons. The boundary keeps its first
    /// vertex and turns counter-clockwise, so wall disks land on the same
    /// points mirrored.
    pub fn transposed(&self) -> Domain {
        let swap = |p: Point| Point::new(p.y, p.x);
        let vertices: Vec<Point> = self
            .vertices
            .iter()
            .take(1)
            .chain(self.vertices.iter().skip(1).rev())
            .map(|&p| swap(p))
            .collect();
        let shape = match &self.shape {
            Shape::Rectangle { width, height } => Shape::Rectangle {
                width: *height,
                height: *width,
            },
            Shape::Circle { center, radius } => Shape::Circle {
                center: swap(*center),
                radius: *radius,
            },
            Shape::Polygon { .. } | Shape::Trapezoid { .. } => Shape::Polygon {
                vertices: vertices.clone(),
            },
        };
        let edges = edges_of(&vertices);
        let walls = match &shape {
            Shape::Circle { center, radius } => vec![Wall::Circle {
                center: *center,
                radius: *radius,
            }],
            _ => edges
                .iter()
                .map(|e| Wall::Segment { a: e.a, b: e.b })
                .collect(),
        };
        Domain {
            shape,
            reflex: reflex_vertices_of(&vertices),
            vertices,
            edges,
            walls,
            area: self.area,
            centroid: swap(self.centroid),
            bounds: (swap(self.bounds.0), swap(self.bounds.1)),
            inradius: self.inradius,
            periodic: self.periodic,
        }
    }

    /// The domain moved by `v`.
    ///
    /// # Behavior
    /// Every point moves by `v`, rounded to the nearest representable point
    /// (exactly by [`Domain::local_offset`]'s). Circles stay circles and
    /// polygons polygons; a rectangle or trapezoid moved by a non-zero `v`
    /// becomes a polygon (their shapes are anchored at the origin). Area and
    /// inradius are kept as they are.
    pub fn translated(&self, v: Vector2<f64>) -> Domain {
        if v == Vector2::zeros() {
            return self.clone();
        }
        let vertices: Vec<Point> = self.vertices.iter().map(|&p| p + v).collect();
        let shape = match &self.shape {
            Shape::Circle { center, radius } => Shape::Circle {
                center: center + v,
                radius: *radius,
            },
            _ => Shape::Polygon {
                vertices: vertices.clone(),
            },
        };
        let walls = self
            .walls
            .iter()
            .map(|w| match *w {
                Wall::Segment { a, b } => Wall::Segment { a: a + v, b: b + v },
                Wall::Circle { center, radius } => Wall::Circle {
                    center: center + v,
                    radius,
                },
            })
            .collect();
        Domain {
            shape,
            edges: edges_of(&vertices),
            vertices,
            walls,
            reflex: self.reflex.iter().map(|&p| p + v).collect(),
            area: self.area,
            centroid: self.centroid + v,
            bounds: (self.bounds.0 + v, self.bounds.1 + v),
            inradius: self.inradius,
            periodic: self.periodic,
        }
    }

    /// The move that brings a domain far from the origin next to it,
    /// exactly: along each axis where the domain lies more than twice its
    /// extent from the origin, minus its lowest coordinate; zero along the
    /// others (every shape anchored at the origin stays where it is).
    ///
    /// # Behavior
    /// Rounding error in a computed point grows with its coordinates, not
    /// with the disks: at 10⁶ mm an ulp is 1.2·10⁻¹⁰ mm. Packed where it
    /// was, a domain that far out lost candidates tangent to two disks to
    /// `FEASIBLE_REL` and the packer
    /// stopped after a few disks. Moved by this offset, its coordinates
    /// start at 0 along that axis. The move is exact: every coordinate `x`
    /// of the domain and the lowest `lo` are within a factor of two of each
    /// other, so `x − lo` is a floating-point number (Sterbenz's lemma).
    /// So a domain whose lowest corner is the origin packs to the same disks
    /// wherever it is moved (as long as its vertices move exactly), but for
    /// one rounding of each centre moved back.
    ///
    /// # Example
    /// ```
    /// use gapack::{Domain, Point};
    /// let far = Domain::circle(Point::new(1e6 + 3.0, -2e6), 10.0).unwrap();
    /// let v = far.local_offset();
    /// assert_eq!((v.x, v.y), (-999_993.0, 2_000_010.0));
    /// assert_eq!(far.translated(v).bounds().0, Point::origin());
    /// assert_eq!(Domain::rectangle(4.0, 3.0).unwrap().local_offset().norm(), 0.0);
    /// ```
    pub fn local_offset(&self) -> Vector2<f64> {
        let (lo, hi) = self.bounds;
        let extent = (hi.x - lo.x).max(hi.y - lo.y);
        let axis = |lo: f64, hi: f64| {
            if lo >= 2.0 * extent || hi <= -2.0 * extent {
                -lo
            } else {
                0.0
            }
        };
        Vector2::new(axis(lo.x, hi.x), axis(lo.y, hi.y))
    }

    /// The shape the domain was built from.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// Area (mm²).
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Length of the boundary (mm).
    pub fn perimeter(&self) -> f64 {
        match self.shape {
            Shape::Circle { radius, .. } => TAU * radius,
            _ => self.edges.iter().map(|e| e.d.norm()).sum(),
        }
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Point, Point) {
        self.bounds
    }

    /// Area centroid.
    pub fn centroid(&self) -> Point {
        self.centroid
    }

    /// Walls, counter-clockwise (segments) or the one circle.
    ///
    /// # Behavior
    /// Rectangle, trapezoid, polygon: one [`Wall::Segment`] per edge, in
    /// boundary order starting at the first vertex, the domain on the left of
    /// `a → b` and each `b` the next wall's `a`. Circle: one [`Wall::Circle`].
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// Reflex (concave) polygon corners: point obstacles for exact walls.
    ///
    /// # Behavior
    /// Vertices whose interior angle exceeds 180°, decided with an exact
    /// orientation test, in boundary order; empty for rectangles,
    /// trapezoids, convex polygons and circles.
    pub fn reflex_vertices(&self) -> &[Point] {
        &self.reflex
    }

    /// Signed distance from `p` to the boundary: positive inside, negative outside.
    ///
    /// # Behavior
    /// Zero on the boundary. `p` must be finite (otherwise the value is
    /// meaningless, but there is no panic). Rectangle and circle: closed
    /// forms, correctly rounded up to one or two operations. Trapezoid and
    /// polygon: floating-point distance to the nearest edge (error a few ulps
    /// of the coordinates) with the sign from an exact winding-number test,
    /// so the sign is right for every point off the boundary.
    ///
    /// # Performance
    /// Rectangle: two subtractions and a few comparisons inside (a square
    /// root only outside); circle: one square root; polygon: O(edges).
    #[inline]
    pub fn signed_distance(&self, p: Point) -> f64 {
        match self.shape {
            Shape::Rectangle { width, height } => signed_distance_point_rectangle(p, width, height),
            Shape::Circle { center, radius } => radius - (p - center).norm(),
            Shape::Polygon { .. } | Shape::Trapezoid { .. } => {
                signed_distance_point_polygon(p, &self.edges)
            }
        }
    }

    /// Area of the domain inside the axis-aligned box `[x0, x1] × [y0, y1]` (mm²).
    ///
    /// # Behavior
    /// Exact up to rounding for every shape: a circle through
    /// `area_disk_box`, straight-edged
    /// shapes by clipping the boundary to the box
    /// (`area_polygon_box`). 0 for an
    /// empty box or one that misses the domain.
    ///
    /// # Performance
    /// Circle: O(1); straight-edged shapes: O(vertices).
    pub fn area_in_box(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
        let (lo, hi) = self.bounds;
        if x1 <= lo.x || x0 >= hi.x || y1 <= lo.y || y0 >= hi.y {
            return 0.0;
        }
        match self.shape {
            Shape::Circle { center, radius } => area_disk_box(center, radius, x0, x1, y0, y1),
            _ => area_polygon_box(&self.vertices, x0, x1, y0, y1),
        }
    }

    /// Radius of the largest disk that fits inside the domain.
    ///
    /// # Behavior
    /// Precomputed by the constructor. Exact for rectangles
    /// (`min(width, height)/2`), circles and trapezoids (closed form).
    /// Polygons: the best of all medial-axis vertex candidates (points
    /// equidistant from three edge lines or reflex corners), exact up to
    /// rounding (relative ~1e-12) for up to 200 edges + reflex corners;
    /// above, a branch and bound with relative precision 1e-4 within a
    /// fixed work budget — should that run out, a lower bound. Never an
    /// overestimate beyond rounding.
    pub fn inradius(&self) -> f64 {
        self.inradius
    }

    /// Outline for drawing: the polygon's vertices, or the circle as a polygon.
    ///
    /// # Behavior
    /// Straight-edged shapes: their vertices, counter-clockwise, no closing
    /// repeat; `segments_per_circle` is ignored. Circle: `segments_per_circle`
    /// points (at least 3) on the circle, counter-clockwise from angle 0.
    pub fn outline(&self, segments_per_circle: usize) -> Vec<Point> {
        match self.shape {
            Shape::Circle { center, radius } => {
                let n = segments_per_circle.max(3);
                let step = TAU / n as f64;
                (0..n)
                    .map(|i| {
                        let a = step * i as f64;
                        center + Vector2::new(radius * a.cos(), radius * a.sin())
                    })
                    .collect()
            }
            _ => self.vertices.clone(),
        }
    }

    /// The boundary discretised into touching disks of `diameter`, centred on it.
    ///
    /// # Behavior
    /// Straight-edged shapes: a disk on every vertex and, along each edge of
    /// length `L`, `ceil(L/diameter)` equal gaps, so consecutive centres are
    /// at most `diameter` apart and every boundary point lies within
    /// `diameter/2` of a centre (no gap a particle could leave through).
    /// Order: counter-clockwise from the first vertex; no vertex repeated.
    /// Circle: `ceil(2πR/diameter)` disks evenly spaced counter-clockwise
    /// from angle 0. Every disk has radius `diameter/2`.
    ///
    /// # Returns
    /// An empty vector if `diameter` is not positive and finite, or if more
    /// than [`Domain::MAX_BOUNDARY_DISKS`] disks would be needed (see
    /// [`Domain::boundary_disk_count`] to tell the cases apart beforehand).
    ///
    /// # Example
    /// ```
    /// use gapack::Domain;
    /// let d = Domain::rectangle(10.0, 4.0).unwrap();
    /// // 10 mm edges: 4 gaps of 2.5 mm; 4 mm edges: 2 gaps of 2 mm.
    /// assert_eq!(d.boundary_disks(3.0).len(), 12);
    /// assert!(d.boundary_disks(0.0).is_empty());
    /// ```
    pub fn boundary_disks(&self, diameter: f64) -> Vec<Disk> {
        let Some(count) = self.boundary_disk_count(diameter) else {
            return Vec::new();
        };
        let r = 0.5 * diameter;
        let mut disks = Vec::with_capacity(count);
        if let Shape::Circle { center, radius } = self.shape {
            let step = TAU / count as f64;
            disks.extend((0..count).map(|i| {
                let a = step * i as f64;
                Disk {
                    c: center + Vector2::new(radius * a.cos(), radius * a.sin()),
                    r,
                }
            }));
        } else {
            for e in &self.edges {
                let m = gaps(e.d.norm(), diameter);
                // `m` ≤ the checked total, so the cast is exact.
                disks.extend((0..m as usize).map(|k| Disk {
                    c: e.a + e.d * (k as f64 / m),
                    r,
                }));
            }
        }
        disks
    }

    /// For each disk of [`Domain::boundary_disks`], the straight edge it
    /// starts or lies on (0 = the edge from the first vertex); empty for a
    /// circle. The disks of one edge are consecutive.
    pub fn boundary_disk_edges(&self, diameter: f64) -> Vec<u32> {
        if self.boundary_disk_count(diameter).is_none() || self.edges.is_empty() {
            return Vec::new();
        }
        self.edges
            .iter()
            .zip(0u32..)
            .flat_map(|(e, i)| std::iter::repeat_n(i, gaps(e.d.norm(), diameter) as usize))
            .collect()
    }

    /// How many disks [`Domain::boundary_disks`] returns for `diameter`:
    /// `None` if `diameter` is not positive and finite or more than
    /// [`Domain::MAX_BOUNDARY_DISKS`] would be needed.
    pub fn boundary_disk_count(&self, diameter: f64) -> Option<usize> {
        if !(diameter > 0.0 && diameter.is_finite()) {
            return None;
        }
        let total: f64 = match self.shape {
            Shape::Circle { radius, .. } => gaps(TAU * radius, diameter),
            _ => self.edges.iter().map(|e| gaps(e.d.norm(), diameter)).sum(),
        };
        // Also false for an infinite total.
        (total <= Self::MAX_BOUNDARY_DISKS as f64).then_some(total as usize)
    }

    /// Builds a straight-edged domain from counter-clockwise, validated
    /// `vertices`; the inradius is computed unless given.
    fn polygonal(
        shape: Shape,
        vertices: Vec<Point>,
        inradius: Option<f64>,
    ) -> Result<Self, GeometryError> {
        let area = finite_area(signed_area(&vertices))?;
        let edges = edges_of(&vertices);
        let reflex = reflex_vertices_of(&vertices);
        let walls = edges
            .iter()
            .map(|e| Wall::Segment { a: e.a, b: e.b })
            .collect();
        let inradius =
            inradius.unwrap_or_else(|| max_inscribed_radius_polygon(&vertices, &edges, &reflex));
        Ok(Domain {
            centroid: centroid_of(&vertices),
            bounds: bounds_of(&vertices),
            shape,
            vertices,
            edges,
            walls,
            reflex,
            area,
            inradius,
            periodic: false,
        })
    }
}

/// Most whole periods [`Domain::image_shifts`] goes along an axis either way.
const MAX_SHIFT: f64 = 1024.0;

/// `v` moved by whole periods into `[lo, hi)`.
#[inline]
fn wrap_axis(v: f64, lo: f64, hi: f64) -> f64 {
    if v >= lo && v < hi {
        return v;
    }
    let w = hi - lo;
    let moved = lo + (v - lo).rem_euclid(w);
    if moved < hi && moved >= lo { moved } else { lo }
}

/// The shifts of [`Domain::image_shifts`], as vectors (mm).
#[derive(Debug, Clone)]
pub struct ImageShifts {
    period: Vector2<f64>,
    /// Whole periods along x, first to last (an empty range when first > last).
    kx: (i64, i64),
    ky: (i64, i64),
    /// The next (x, y) shift in periods.
    next: (i64, i64),
}

impl ImageShifts {
    /// The zero shift alone (a domain with walls).
    fn single() -> Self {
        ImageShifts {
            period: Vector2::zeros(),
            kx: (0, 0),
            ky: (0, 0),
            next: (0, 0),
        }
    }
}

impl Iterator for ImageShifts {
    type Item = Vector2<f64>;

    fn next(&mut self) -> Option<Vector2<f64>> {
        let (i, j) = self.next;
        if j > self.ky.1 || self.kx.0 > self.kx.1 {
            return None;
        }
        self.next = if i < self.kx.1 {
            (i + 1, j)
        } else {
            (self.kx.0, j + 1)
        };
        Some(Vector2::new(
            i as f64 * self.period.x,
            j as f64 * self.period.y,
        ))
    }
}

/// `value` if it is positive and finite, else [`GeometryError::BadSize`].
fn positive(what: &'static str, value: f64) -> Result<f64, GeometryError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(GeometryError::BadSize { what, value })
    }
}

/// `area` if it is positive and finite, else [`GeometryError::Degenerate`].
fn finite_area(area: f64) -> Result<f64, GeometryError> {
    if area > 0.0 && area.is_finite() {
        Ok(area)
    } else {
        Err(GeometryError::Degenerate(format!(
            "the area {area} is not a positive finite number (sizes overflow or underflow)"
        )))
    }
}

/// Signed distance to the boundary of `[0, width] × [0, height]`.
#[inline]
fn signed_distance_point_rectangle(p: Point, width: f64, height: f64) -> f64 {
    let dx = p.x.min(width - p.x);
    let dy = p.y.min(height - p.y);
    if dx >= 0.0 && dy >= 0.0 {
        dx.min(dy)
    } else {
        let (ox, oy) = (dx.min(0.0), dy.min(0.0));
        -(ox * ox + oy * oy).sqrt()
    }
}

/// Inradius of the trapezoid of [`Domain::trapezoid`]: the disk touching the
/// longer base and both legs is the incircle of the triangle they form,
/// unless it is taller than the trapezoid, whose inradius is then
/// `height/2`.
fn inradius_trapezoid(bottom: f64, top: f64, height: f64) -> f64 {
    let (long, short) = (bottom.max(top), bottom.min(top));
    // k = 1 / (height of the triangle's apex above the longer base).
    let k = (long - short) / (height * long);
    let lk = long * k;
    // Incircle of an isosceles triangle of base L and height 1/k:
    // r = L / (L·k + 2·√((L·k/2)² + 1)), which tends to L/2 as k → 0.
    let triangle = long / (lk + 2.0 * (0.25 * lk * lk + 1.0).sqrt());
    triangle.min(0.5 * height)
}

/// Number of equal gaps, each at most `diameter`, along `length` (≥ 1).
fn gaps(length: f64, diameter: f64) -> f64 {
    let m = (length / diameter).ceil().max(1.0);
    // Guard the rounding of `length / diameter` just below an integer.
    if length / m > diameter { m + 1.0 } else { m }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    fn pts(v: &[(f64, f64)]) -> Vec<Point> {
        v.iter().map(|&(x, y)| Point::new(x, y)).collect()
    }

    #[test]
    fn a_polygon_over_the_vertex_cap_is_refused_before_its_quadratic_checks() {
        // 100,000 vertices took 74 s to validate and did not pack in 300 s.
        let ring = |n: usize| -> Vec<Point> {
            (0..n)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as f64 / n as f64;
                    let r = 20.0 * (1.0 + 0.03 * (37.0 * t).sin());
                    Point::new(r * t.cos(), r * t.sin())
                })
                .collect()
        };
        let max = Domain::MAX_POLYGON_VERTICES;
        assert_eq!(
            Domain::polygon(&ring(100_000)).unwrap_err(),
            GeometryError::TooManyVertices {
                count: 100_000,
                max
            }
        );
        assert!(matches!(
            Domain::polygon(&ring(max + 1)),
            Err(GeometryError::TooManyVertices { .. })
        ));
        // The cap itself passes, with or without a closing repeat.
        let mut at_cap = ring(max);
        assert!(Domain::polygon(&at_cap).is_ok());
        at_cap.push(at_cap[0]);
        assert!(Domain::polygon(&at_cap).is_ok());
    }

    fn l_shape() -> Domain {
        Domain::polygon(&pts(&[
            (0., 0.),
            (20., 0.),
            (20., 8.),
            (8., 8.),
            (8., 20.),
            (0., 20.),
        ]))
        .expect("L-shape is simple")
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1.0)
    }

    /// Independent reference: nearest-edge distance by projection, sign by
    /// even-odd ray casting (fine off the boundary, which random points are).
    fn brute_signed_distance(v: &[Point], p: Point) -> f64 {
        let n = v.len();
        let mut best = f64::INFINITY;
        let mut inside = false;
        for i in 0..n {
            let (a, b) = (v[i], v[(i + 1) % n]);
            let ab = b - a;
            let t = ((p - a).dot(&ab) / ab.dot(&ab)).clamp(0.0, 1.0);
            best = best.min((a + ab * t - p).norm());
            if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * ab.x / ab.y {
                inside = !inside;
            }
        }
        if inside { best } else { -best }
    }

    fn assert_matches_brute_force(d: &Domain, seed: u64) {
        let v = d.outline(0);
        let (lo, hi) = d.bounds();
        let margin = 0.3 * (hi - lo).norm();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        for _ in 0..4000 {
            let p = Point::new(
                rng.gen_range(lo.x - margin..hi.x + margin),
                rng.gen_range(lo.y - margin..hi.y + margin),
            );
            let (got, want) = (d.signed_distance(p), brute_signed_distance(&v, p));
            assert!(close(got, want, 1e-12), "{p}: {got} vs {want}");
        }
    }

    #[test]
    fn area_in_box_tiles_to_the_area() {
        let circle = Domain::circle(Point::new(3.0, -2.0), 5.0).unwrap();
        let domains = [
            Domain::rectangle(40.0, 10.0).unwrap(),
            circle.clone(),
            Domain::trapezoid(4.0, 10.0, 6.0).unwrap(),
            l_shape(),
        ];
        for d in &domains {
            // A 7 × 5 tiling of a box wider than the bounds sums to the area.
            let (lo, hi) = d.bounds();
            let (w, h) = ((hi.x - lo.x + 2.0) / 7.0, (hi.y - lo.y + 2.0) / 5.0);
            let mut sum = 0.0;
            for i in 0..7 {
                for j in 0..5 {
                    let (x0, y0) = (lo.x - 1.0 + w * f64::from(i), lo.y - 1.0 + h * f64::from(j));
                    let a = d.area_in_box(x0, x0 + w, y0, y0 + h);
                    assert!(a >= 0.0 && a <= w * h * (1.0 + 1e-12), "{a}");
                    sum += a;
                }
            }
            assert!(close(sum, d.area(), 1e-12), "{:?}: {sum}", d.shape());
        }
        // The L's notch is empty; a box beside the circle misses it.
        assert_eq!(l_shape().area_in_box(10.0, 20.0, 10.0, 20.0), 0.0);
        assert_eq!(l_shape().area_in_box(6.0, 10.0, 6.0, 10.0), 12.0);
        assert_eq!(circle.area_in_box(9.0, 10.0, -2.0, 0.0), 0.0);
    }

    #[test]
    fn a_periodic_cell_wraps_points_into_itself_and_lists_the_images_near_a_box() {
        let cell = Domain::periodic_rectangle(10.0, 4.0).unwrap();
        assert_eq!(cell.shape(), Domain::rectangle(10.0, 4.0).unwrap().shape());
        assert_eq!(cell.area(), 40.0);
        // Inside: unchanged, bit for bit; on the upper edge: the lower one.
        let inside = Point::new(0.1 + 0.2, 3.999_999_999_999_999);
        assert_eq!(cell.wrap(inside), inside);
        assert_eq!(cell.wrap(Point::new(10.0, 4.0)), Point::new(0.0, 0.0));
        assert_eq!(cell.wrap(Point::new(-2.5, 9.0)), Point::new(7.5, 1.0));
        // A tiny negative coordinate rounds onto the upper edge: the lower one.
        let p = cell.wrap(Point::new(-1e-17, -1e-17));
        assert!(p.x >= 0.0 && p.x < 10.0 && p.y >= 0.0 && p.y < 4.0, "{p:?}");
        // A domain with walls wraps nothing and has one shift, zero.
        let walled = Domain::rectangle(10.0, 4.0).unwrap();
        assert_eq!(walled.wrap(Point::new(-2.5, 9.0)), Point::new(-2.5, 9.0));
        let far = (Point::new(-30.0, -30.0), Point::new(30.0, 30.0));
        assert_eq!(
            walled.image_shifts(far.0, far.1).collect::<Vec<_>>(),
            [Vector2::zeros()]
        );
        let shifts = |lo: (f64, f64), hi: (f64, f64)| -> Vec<(f64, f64)> {
            cell.image_shifts(Point::new(lo.0, lo.1), Point::new(hi.0, hi.1))
                .map(|v| (v.x, v.y))
                .collect()
        };
        assert_eq!(shifts((4.0, 1.0), (6.0, 3.0)), [(0.0, 0.0)]);
        // Across the right edge: the centres stored near x = 0 are images at x + 10.
        assert_eq!(shifts((9.0, 1.0), (11.0, 3.0)), [(0.0, 0.0), (10.0, 0.0)]);
        assert_eq!(
            shifts((-1.0, -1.0), (1.0, 1.0)),
            [(-10.0, -4.0), (0.0, -4.0), (-10.0, 0.0), (0.0, 0.0)]
        );
        // A box wider than two cells: the images at −10 (of x near 10) to
        // +20 (of x near 0) may lie in it, each once.
        assert_eq!(shifts((-1.0, 1.0), (21.0, 2.0)).len(), 4);
        // Brute force: every centre of the cell whose image lies in a box is found.
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        for _ in 0..2000 {
            let c = Point::new(rng.gen_range(0.0..10.0), rng.gen_range(0.0..4.0));
            let (x, y) = (rng.gen_range(-15.0..25.0), rng.gen_range(-6.0..10.0));
            let half = rng.gen_range(0.0..6.0);
            let (lo, hi) = (
                Point::new(x - half, y - half),
                Point::new(x + half, y + half),
            );
            for kx in -4..=4 {
                for ky in -4..=4 {
                    let v = Vector2::new(10.0 * f64::from(kx), 4.0 * f64::from(ky));
                    let q = c + v;
                    if q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y {
                        assert!(cell.image_shifts(lo, hi).any(|s| s == v), "{c:?} {v:?}");
                    }
                }
            }
        }
        // Transposed, it stays a periodic cell; with walls again, a rectangle.
        let t = cell.transposed();
        assert_eq!(t.period(), Some(Vector2::new(4.0, 10.0)));
        assert_eq!(cell.with_periodic(false), walled);
    }

    #[test]
    fn rectangle_area_centroid_bounds_walls() {
        let d = Domain::rectangle(40.0, 10.0).unwrap();
        assert_eq!(d.area(), 400.0);
        assert_eq!(d.centroid(), Point::new(20.0, 5.0));
        assert_eq!(d.bounds(), (Point::new(0.0, 0.0), Point::new(40.0, 10.0)));
        assert_eq!(d.inradius(), 5.0);
        assert!(d.reflex_vertices().is_empty());
        assert_eq!(
            d.walls()[0],
            Wall::Segment {
                a: Point::new(0.0, 0.0),
                b: Point::new(40.0, 0.0)
            }
        );
        assert_eq!(d.walls().len(), 4);
    }

    #[test]
    fn circle_area_centroid_bounds_walls_outline() {
        let c = Point::new(3.0, -2.0);
        let d = Domain::circle(c, 5.0).unwrap();
        assert!(close(d.area(), 25.0 * std::f64::consts::PI, 1e-15));
        assert_eq!(d.centroid(), c);
        assert_eq!(d.bounds(), (Point::new(-2.0, -7.0), Point::new(8.0, 3.0)));
        assert_eq!(d.inradius(), 5.0);
        assert_eq!(
            d.walls(),
            &[Wall::Circle {
                center: c,
                radius: 5.0
            }]
        );
        assert!(d.reflex_vertices().is_empty());
        let outline = d.outline(64);
        assert_eq!(outline.len(), 64);
        assert!(outline.iter().all(|p| close((p - c).norm(), 5.0, 1e-14)));
        assert!(signed_area(&outline) > 0.0);
        assert_eq!(d.outline(1).len(), 3);
        assert_eq!(d.signed_distance(c), 5.0);
        assert_eq!(d.signed_distance(Point::new(3.0, 6.0)), -3.0);
    }

    #[test]
    fn trapezoid_area_centroid_bounds_vertices() {
        let (b, t, h) = (10.0, 4.0, 6.0);
        let d = Domain::trapezoid(b, t, h).unwrap();
        assert!(close(d.area(), 0.5 * (b + t) * h, 1e-15));
        let want = Point::new(0.5 * b, h * (b + 2.0 * t) / (3.0 * (b + t)));
        assert!((d.centroid() - want).norm() < 1e-12);
        assert_eq!(d.bounds(), (Point::new(0.0, 0.0), Point::new(10.0, 6.0)));
        assert_eq!(
            d.outline(0),
            pts(&[(0., 0.), (10., 0.), (7., 6.), (3., 6.)])
        );
        // Wider top: bounds reach out beyond the bottom edge.
        let inverted = Domain::trapezoid(4.0, 10.0, 6.0).unwrap();
        assert_eq!(
            inverted.bounds(),
            (Point::new(-3.0, 0.0), Point::new(7.0, 6.0))
        );
        assert!(inverted.reflex_vertices().is_empty());
    }

    #[test]
    fn polygon_area_centroid_bounds_of_the_l_shape() {
        let d = l_shape();
        assert_eq!(d.area(), 256.0);
        assert!((d.centroid() - Point::new(7.75, 7.75)).norm() < 1e-12);
        assert_eq!(d.bounds(), (Point::new(0.0, 0.0), Point::new(20.0, 20.0)));
    }

    #[test]
    fn clockwise_polygon_is_stored_counter_clockwise() {
        let cw = pts(&[
            (0., 0.),
            (0., 20.),
            (8., 20.),
            (8., 8.),
            (20., 8.),
            (20., 0.),
        ]);
        let d = Domain::polygon(&cw).unwrap();
        let Shape::Polygon { vertices } = d.shape() else {
            panic!("not a polygon")
        };
        assert!(signed_area(vertices) > 0.0);
        assert_eq!(d.area(), 256.0);
        assert_eq!(vertices.len(), 6);
        assert!(cw.iter().all(|p| vertices.contains(p)));
        assert_eq!(d.reflex_vertices(), &[Point::new(8.0, 8.0)]);
        // Every wall has the domain on its left.
        for w in d.walls() {
            let Wall::Segment { a, b } = *w else {
                panic!("circle wall")
            };
            let left = Vector2::new(a.y - b.y, b.x - a.x).normalize();
            assert!(d.signed_distance(a + (b - a) * 0.5 + left * 0.1) > 0.0);
        }
    }

    #[test]
    fn walls_of_straight_shapes_are_a_closed_ccw_chain() {
        for d in [
            Domain::rectangle(3.0, 2.0).unwrap(),
            Domain::trapezoid(4.0, 9.0, 2.0).unwrap(),
            l_shape(),
        ] {
            let walls = d.walls();
            for (i, w) in walls.iter().enumerate() {
                let (Wall::Segment { a, b }, Wall::Segment { a: next, .. }) =
                    (*w, walls[(i + 1) % walls.len()])
                else {
                    panic!("circle wall")
                };
                assert_eq!(b, next);
                let left = Vector2::new(a.y - b.y, b.x - a.x).normalize();
                assert!(d.signed_distance(a + (b - a) * 0.5 + left * 1e-3) > 0.0);
                assert!(d.signed_distance(a + (b - a) * 0.5 - left * 1e-3) < 0.0);
            }
        }
    }

    #[test]
    fn closing_vertex_equal_to_first_is_dropped() {
        let d = Domain::polygon(&pts(&[(0., 0.), (4., 0.), (0., 3.), (0., 0.)])).unwrap();
        assert_eq!(d.outline(0).len(), 3);
        assert_eq!(d.area(), 6.0);
    }

    #[test]
    fn bow_tie_is_refused() {
        let r = Domain::polygon(&pts(&[(0., 0.), (2., 2.), (2., 0.), (0., 2.)]));
        assert_eq!(
            r,
            Err(GeometryError::SelfIntersecting {
                first: 0,
                first_from: 0,
                first_to: 1,
                second: 2
            })
        );
    }

    #[test]
    fn polygon_touching_itself_at_a_vertex_is_refused() {
        // Two triangles joined at (1, 1), walked as one ring.
        let r = Domain::polygon(&pts(&[
            (0., 0.),
            (2., 0.),
            (1., 1.),
            (2., 2.),
            (0., 2.),
            (1., 1.),
        ]));
        assert!(
            matches!(
                r,
                Err(GeometryError::SelfIntersecting {
                    first: 1,
                    second: 4,
                    ..
                })
            ),
            "{r:?}"
        );
        // A vertex lying inside a non-adjacent edge.
        let r = Domain::polygon(&pts(&[(0., 0.), (6., 0.), (6., 4.), (3., 0.), (0., 4.)]));
        assert!(
            matches!(
                r,
                Err(GeometryError::SelfIntersecting {
                    first: 0,
                    second: 2,
                    ..
                })
            ),
            "{r:?}"
        );
    }

    #[test]
    fn degenerate_polygons_are_refused() {
        let degenerate = |v: &[(f64, f64)]| {
            let r = Domain::polygon(&pts(v));
            assert!(
                matches!(r, Err(GeometryError::Degenerate(_))),
                "{v:?}: {r:?}"
            );
        };
        degenerate(&[(0., 0.), (1., 0.), (2., 0.)]);
        degenerate(&[(0., 0.), (1., 1.), (3., 3.), (2., 2.)]);
        degenerate(&[(0., 0.), (1., 0.), (1., 0.), (0., 1.)]);
        degenerate(&[(0., 0.), (4., 0.), (2., 0.), (2., 3.)]);
        degenerate(&[(0., 0.), (1., 1.), (2., 2. + 1e-11)]);
        assert_eq!(
            Domain::polygon(&pts(&[(0., 0.), (1., 0.)])),
            Err(GeometryError::TooFewVertices(2))
        );
        assert_eq!(
            Domain::polygon(&pts(&[(0., 0.), (1., 0.), (0., 0.)])),
            Err(GeometryError::TooFewVertices(2))
        );
        assert_eq!(
            Domain::polygon(&pts(&[(0., 0.), (1., 0.), (f64::NAN, 1.)])),
            Err(GeometryError::NonFiniteVertex { index: 2 })
        );
        assert_eq!(
            Domain::polygon(&pts(&[(0., 0.), (f64::INFINITY, 0.), (0., 1.)])),
            Err(GeometryError::NonFiniteVertex { index: 1 })
        );
        assert!(matches!(
            Domain::polygon(&pts(&[(0., 0.), (1e200, 0.), (1e200, 1e200)])),
            Err(GeometryError::Degenerate(_))
        ));
    }

    #[test]
    fn bad_sizes_are_refused_by_name() {
        let what = |r: Result<Domain, GeometryError>| match r {
            Err(GeometryError::BadSize { what, .. }) => what,
            other => panic!("{other:?}"),
        };
        assert_eq!(what(Domain::rectangle(0.0, 1.0)), "width");
        assert_eq!(what(Domain::rectangle(1.0, f64::NAN)), "height");
        assert_eq!(what(Domain::circle(Point::origin(), -1.0)), "radius");
        assert_eq!(what(Domain::trapezoid(f64::INFINITY, 1.0, 1.0)), "bottom");
        assert_eq!(what(Domain::trapezoid(1.0, 0.0, 1.0)), "top");
        assert_eq!(what(Domain::trapezoid(1.0, 1.0, -0.0)), "height");
        assert!(matches!(
            Domain::circle(Point::new(f64::NAN, 0.0), 1.0),
            Err(GeometryError::NonFiniteCenter { .. })
        ));
        assert!(matches!(
            Domain::rectangle(1e200, 1e200),
            Err(GeometryError::Degenerate(_))
        ));
        assert!(matches!(
            Domain::trapezoid(1.0, 1e-300, 1.0),
            Err(GeometryError::Degenerate(_))
        ));
    }

    #[test]
    fn l_shape_reflex_vertex_and_signed_distances() {
        let d = l_shape();
        assert_eq!(d.reflex_vertices(), &[Point::new(8.0, 8.0)]);
        let sd = |x, y| d.signed_distance(Point::new(x, y));
        assert_eq!(sd(4.0, 4.0), 4.0);
        assert_eq!(sd(2.0, 15.0), 2.0);
        assert_eq!(sd(15.0, 5.0), 3.0);
        // In the notch: outside, nearest the two walls of the notch.
        assert_eq!(sd(14.0, 14.0), -6.0);
        assert_eq!(sd(9.0, 9.0), -1.0);
        // In the notch, diagonal to the reflex corner.
        assert_eq!(sd(11.0, 12.0), -3.0);
        assert_eq!(sd(-3.0, -4.0), -5.0);
        assert_eq!(sd(25.0, 4.0), -5.0);
        assert_eq!(sd(10.0, 0.0), 0.0);
        assert_eq!(sd(8.0, 8.0), 0.0);
        assert_matches_brute_force(&d, 11);
    }

    #[test]
    fn rectangle_signed_distance_matches_brute_force() {
        let d = Domain::rectangle(40.0, 10.0).unwrap();
        assert_matches_brute_force(&d, 1);
        let sd = |x, y| d.signed_distance(Point::new(x, y));
        assert_eq!(sd(0.0, 0.0), 0.0);
        assert_eq!(sd(40.0, 3.0), 0.0);
        assert_eq!(sd(43.0, 14.0), -5.0);
        assert_eq!(sd(20.0, -2.0), -2.0);
        assert_eq!(sd(39.0, 5.0), 1.0);
    }

    #[test]
    fn trapezoid_signed_distance_matches_brute_force() {
        assert_matches_brute_force(&Domain::trapezoid(10.0, 4.0, 6.0).unwrap(), 2);
        assert_matches_brute_force(&Domain::trapezoid(3.0, 12.0, 30.0).unwrap(), 3);
    }

    #[test]
    fn inradius_of_l_shape_and_trapezoids() {
        let exact = 8.0 * (2.0 - std::f64::consts::SQRT_2);
        assert!(close(l_shape().inradius(), exact, 1e-12));
        // Tangential trapezoid (8 + 2 = 2 × leg 5): the disk touches all sides.
        assert!(close(
            Domain::trapezoid(8.0, 2.0, 4.0).unwrap().inradius(),
            2.0,
            1e-15
        ));
        // Tall and narrowing: the disk touches the legs and the longer base,
        // the incircle of the triangle base 10, height 12.5.
        let leg = (5.0f64 * 5.0 + 12.5 * 12.5).sqrt();
        let triangle = 10.0 * 12.5 / (10.0 + 2.0 * leg);
        for (b, t) in [(10.0, 2.0), (2.0, 10.0)] {
            let d = Domain::trapezoid(b, t, 10.0).unwrap();
            assert!(close(d.inradius(), triangle, 1e-14), "{b} {t}");
        }
        // Equal bases: a rectangle.
        assert_eq!(Domain::trapezoid(3.0, 3.0, 10.0).unwrap().inradius(), 1.5);
        // The closed form agrees with the polygon computation.
        for (b, t, h) in [(10.0, 4.0, 6.0), (1.0, 30.0, 5.0), (7.0, 7.5, 100.0)] {
            let d = Domain::trapezoid(b, t, h).unwrap();
            let p = Domain::polygon(&d.outline(0)).unwrap();
            assert!(close(d.inradius(), p.inradius(), 1e-12), "{b} {t} {h}");
        }
    }

    /// Checks the wall-disk invariants for `d` and `diameter`.
    fn assert_boundary_disks(d: &Domain, diameter: f64) -> Vec<Disk> {
        let disks = d.boundary_disks(diameter);
        assert_eq!(Some(disks.len()), d.boundary_disk_count(diameter));
        assert!(disks.iter().all(|k| k.r == 0.5 * diameter));
        let n = disks.len();
        for i in 0..n {
            let gap = (disks[(i + 1) % n].c - disks[i].c).norm();
            assert!(gap <= diameter * (1.0 + 1e-12), "gap {gap} after disk {i}");
            assert!(gap > 0.0 || n == 1, "repeated disk {i}");
        }
        let samples: Vec<Point> = match *d.shape() {
            Shape::Circle { center, radius } => (0..20_000)
                .map(|i| {
                    let a = TAU * f64::from(i) / 20_000.0;
                    center + Vector2::new(radius * a.cos(), radius * a.sin())
                })
                .collect(),
            _ => d
                .walls()
                .iter()
                .flat_map(|w| {
                    let Wall::Segment { a, b } = *w else {
                        panic!("circle wall")
                    };
                    (0..=2000).map(move |k| a + (b - a) * (f64::from(k) / 2000.0))
                })
                .collect(),
        };
        for p in samples {
            let nearest = disks
                .iter()
                .map(|k| (k.c - p).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest <= 0.5 * diameter * (1.0 + 1e-9),
                "{p} is {nearest} from the nearest wall disk"
            );
        }
        for v in d.outline(0) {
            if !matches!(d.shape(), Shape::Circle { .. }) {
                assert_eq!(disks.iter().filter(|k| k.c == v).count(), 1, "vertex {v}");
            }
        }
        disks
    }

    #[test]
    fn boundary_disks_cover_the_boundary() {
        let rect = Domain::rectangle(10.0, 4.0).unwrap();
        let disks = assert_boundary_disks(&rect, 3.0);
        assert_eq!(disks.len(), 12);
        assert_eq!(disks[0].c, Point::origin());
        assert_eq!(disks[1].c, Point::new(2.5, 0.0));
        // Exact multiples: 10/2.5 and 4/2.5 → 4 + 2 gaps per pair of sides.
        assert_eq!(assert_boundary_disks(&rect, 2.5).len(), 12);
        assert_boundary_disks(&l_shape(), 3.3);
        assert_boundary_disks(&Domain::trapezoid(10.0, 4.0, 6.0).unwrap(), 1.7);
        assert_boundary_disks(&Domain::trapezoid(0.3, 4.0, 6.0).unwrap(), 0.7);
        let circle = Domain::circle(Point::new(1.0, 2.0), 5.0).unwrap();
        let disks = assert_boundary_disks(&circle, 0.9);
        assert_eq!(disks.len(), (TAU * 5.0 / 0.9).ceil() as usize);
        assert_eq!(assert_boundary_disks(&circle, 100.0).len(), 1);
    }

    #[test]
    fn boundary_disks_of_bad_or_absurd_diameters_are_empty() {
        let rect = Domain::rectangle(10.0, 4.0).unwrap();
        let circle = Domain::circle(Point::origin(), 1.0).unwrap();
        for d in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-9, 1e-320] {
            assert!(rect.boundary_disks(d).is_empty(), "{d}");
            assert!(circle.boundary_disks(d).is_empty(), "{d}");
            assert_eq!(rect.boundary_disk_count(d), None);
        }
    }
}
