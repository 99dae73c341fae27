//! Particles that are not disks: superellipses and rounded convex polygons,
//! each known to the packer and the check through its support function.
//!
//! A particle's outline is given in its own axes, centred on its centre:
//! a superellipse |x/a|^α + |y/b|^β ≤ 1 (α, β ≥ 1: convex; ellipses at
//! α = β = 2, rhombi at 1, near-rectangles as they grow), or a convex
//! polygon with its corners rounded by a radius ρ (the polygon's Minkowski
//! sum with a disk of radius ρ). A [`Grain`] is an outline turned by an
//! angle, counter-clockwise from the x axis.
//!
//! Everything here goes through the **support function** h(u) = max over
//! the particle of u·x and its **support point** s(u) (the point of the
//! outline whose outward normal is u): in closed form for α = β (the dual
//! norm) and for polygons, by a bisection of a concave function otherwise.
//! [`Outline::support`] returns an upper bound of h, never less (the
//! rounding of the closed forms and the bisection's bracket are added), so
//! that a separating line found with it separates the exact particles:
//! this is what makes the check a certificate ([`separation`]).

use std::sync::Arc;

use nalgebra::Vector2;

use super::Point;

/// Relative margin added to every support value: several times the
/// rounding of the closed forms (a few ulps each), so that
/// [`Outline::support`] bounds the exact support function from above.
pub const SUPPORT_REL: f64 = 1e-13;

/// A particle's outline in its own axes, centred on its centre (mm).
#[derive(Debug, Clone, PartialEq)]
pub enum Outline {
    /// |x/a|^alpha + |y/b|^beta ≤ 1, with alpha, beta ≥ 1.
    Superellipse {
        /// Semi-axis along the particle's own x axis (mm).
        a: f64,
        /// Semi-axis along the particle's own y axis (mm).
        b: f64,
        /// Exponent of x (≥ 1).
        alpha: f64,
        /// Exponent of y (≥ 1).
        beta: f64,
    },
    /// A convex polygon, counter-clockwise about its centroid, its corners
    /// rounded by `rounding` (the polygon grown by a disk of that radius).
    Polygon {
        /// Index of the config's template it was scaled from.
        template: u16,
        /// The vertices (mm), counter-clockwise, centroid at the origin.
        vertices: Arc<[Point]>,
        /// Radius of the rounded corners (mm, ≥ 0).
        rounding: f64,
    },
}

/// Why an outline cannot be a particle.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OutlineError {
    /// A semi-axis, exponent or rounding radius is not finite and positive.
    #[error("{name} = {value} must be finite and positive")]
    NotPositive {
        /// The quantity.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// An exponent below 1: the superellipse is not convex.
    #[error(
        "{name} = {value} is below 1: such a superellipse is not convex (its sides curve inwards), and gapack certifies no overlap only between convex particles; use exponents of 1 (a rhombus) or more"
    )]
    NotConvex {
        /// The exponent.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A polygon that is not strictly convex, or has fewer than 3 vertices.
    #[error("polygon template: {0}")]
    Polygon(String),
}

impl Outline {
    /// The superellipse |x/a|^alpha + |y/b|^beta ≤ 1.
    ///
    /// # Errors
    /// A semi-axis not finite and positive, or an exponent below 1 (not convex).
    pub fn superellipse(a: f64, b: f64, alpha: f64, beta: f64) -> Result<Outline, OutlineError> {
        for (name, value) in [("a", a), ("b", b), ("alpha", alpha), ("beta", beta)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(OutlineError::NotPositive { name, value });
            }
        }
        for (name, value) in [("alpha", alpha), ("beta", beta)] {
            if value < 1.0 {
                return Err(OutlineError::NotConvex { name, value });
            }
        }
        Ok(Outline::Superellipse { a, b, alpha, beta })
    }

    /// The convex polygon `vertices` (in any order of a convex outline,
    /// counter-clockwise or not), moved so that its centroid is the
    /// origin, with its corners rounded by `rounding`.
    ///
    /// # Errors
    /// Fewer than 3 vertices, a non-finite one, a polygon that is not
    /// strictly convex (a reflex or straight corner, or self-crossing), or
    /// a negative or non-finite rounding.
    pub fn polygon(
        template: u16,
        vertices: &[Point],
        rounding: f64,
    ) -> Result<Outline, OutlineError> {
        if vertices.len() < 3 {
            return Err(OutlineError::Polygon(format!(
                "needs at least 3 vertices, has {}",
                vertices.len()
            )));
        }
        if vertices
            .iter()
            .any(|v| !(v.x.is_finite() && v.y.is_finite()))
        {
            return Err(OutlineError::Polygon("a vertex is not finite".into()));
        }
        if !(rounding.is_finite() && rounding >= 0.0) {
            return Err(OutlineError::Polygon(format!(
                "rounding = {rounding} must be finite and at least 0"
            )));
        }
        let signed = signed_area(vertices);
        let mut v: Vec<Point> = vertices.to_vec();
        if signed < 0.0 {
            v.reverse();
        }
        let n = v.len();
        let scale = v.iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
        let mut turn = 0.0;
        for i in 0..n {
            let (p, q, r) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
            let e1 = q - p;
            let e2 = r - q;
            let cross = e1.x * e2.y - e1.y * e2.x;
            if cross <= 1e-12 * scale * scale {
                return Err(OutlineError::Polygon(format!(
                    "is not strictly convex at vertex {} ({}, {}): every corner must turn left, by more than a straight angle's rounding",
                    (i + 1) % n + 1,
                    q.x,
                    q.y
                )));
            }
            turn += e1.angle(&e2);
        }
        if (turn - std::f64::consts::TAU).abs() > 1e-6 {
            return Err(OutlineError::Polygon(
                "crosses itself: its corners turn more than once around".into(),
            ));
        }
        let c = centroid(&v);
        let v: Vec<Point> = v.iter().map(|p| Point::from(p - c)).collect();
        Ok(Outline::Polygon {
            template,
            vertices: v.into(),
            rounding,
        })
    }

    /// This outline scaled by `k` (> 0) about its centre.
    #[must_use]
    pub fn scaled(&self, k: f64) -> Outline {
        match self {
            Outline::Superellipse { a, b, alpha, beta } => Outline::Superellipse {
                a: a * k,
                b: b * k,
                alpha: *alpha,
                beta: *beta,
            },
            Outline::Polygon {
                template,
                vertices,
                rounding,
            } => Outline::Polygon {
                template: *template,
                vertices: vertices.iter().map(|p| Point::from(p.coords * k)).collect(),
                rounding: rounding * k,
            },
        }
    }

    /// Area (mm²): 4ab·Γ(1+1/α)Γ(1+1/β)/Γ(1+1/α+1/β) for a superellipse;
    /// polygon area + perimeter·ρ + πρ² for a rounded polygon.
    pub fn area(&self) -> f64 {
        match self {
            Outline::Superellipse { a, b, alpha, beta } => {
                let (ia, ib) = (1.0 / alpha, 1.0 / beta);
                4.0 * a
                    * b
                    * (ln_gamma(1.0 + ia) + ln_gamma(1.0 + ib) - ln_gamma(1.0 + ia + ib)).exp()
            }
            Outline::Polygon {
                vertices, rounding, ..
            } => {
                signed_area(vertices)
                    + perimeter(vertices) * rounding
                    + std::f64::consts::PI * rounding * rounding
            }
        }
    }

    /// Radius of the disk of the same area (mm).
    pub fn equivalent_radius(&self) -> f64 {
        (self.area() / std::f64::consts::PI).sqrt()
    }

    /// Perimeter (mm): exact for polygons, that of a fine polygonisation
    /// ([`Outline::boundary`] with 1,024 points, within 10⁻⁵) for superellipses.
    pub fn perimeter(&self) -> f64 {
        match self {
            Outline::Polygon {
                vertices, rounding, ..
            } => perimeter(vertices) + std::f64::consts::TAU * rounding,
            Outline::Superellipse { .. } => perimeter(&self.boundary(1024)),
        }
    }

    /// The support function h(u) = max over the outline of u·x, for `u` in
    /// the particle's own axes (any length), bounded from above: the exact
    /// value plus [`SUPPORT_REL`] of the outline's size. `None` never: a
    /// zero `u` gives 0.
    pub fn support(&self, u: Vector2<f64>) -> f64 {
        let (h, _) = self.support_both(u);
        h
    }

    /// The support point s(u), the point of the outline whose outward
    /// normal is `u` (one of them on a flat side or at a corner), in the
    /// particle's own axes.
    pub fn support_point(&self, u: Vector2<f64>) -> Point {
        self.support_both(u).1
    }

    /// The support value (an upper bound, see [`Outline::support`]) and point.
    pub fn support_both(&self, u: Vector2<f64>) -> (f64, Point) {
        match self {
            Outline::Superellipse { a, b, alpha, beta } => {
                superellipse_support(*a, *b, *alpha, *beta, u)
            }
            Outline::Polygon {
                vertices, rounding, ..
            } => {
                let mut best = vertices[0];
                let mut h = best.coords.dot(&u);
                for v in vertices.iter().skip(1) {
                    let d = v.coords.dot(&u);
                    if d > h {
                        h = d;
                        best = *v;
                    }
                }
                let n = u.norm();
                let size = self.reach_hint();
                if n == 0.0 {
                    return (0.0, best);
                }
                let p = best + u * (rounding / n);
                (h + rounding * n + SUPPORT_REL * size * n, p)
            }
        }
    }

    /// The support value (an upper bound, as [`Outline::support`]), point
    /// and radius of curvature ρ = h + h'' in the unit direction `u` (own
    /// axes), for the outlines whose support point moves smoothly with the
    /// direction: superellipses with α = β > 1, ellipses among them. The
    /// support point then moves by ρ·dθ along the tangent as `u` turns by
    /// dθ, which lets a contact be solved by Newton on the normal's angle.
    /// `None` for polygons, rhombi and α ≠ β.
    ///
    /// # Behavior
    /// With h = ‖(a·uₓ, b·u_y)‖_r, r = α/(α − 1), and P, Q the two terms of
    /// the r-norm's sum S: ρ = (r − 1)·h·P·Q / (S²·uₓ²·u_y²) (for an ellipse
    /// a²b²/h³). Along an own axis it is capped at 10⁸ times the size (an
    /// outline with α > 2 is flat there).
    pub fn support_curved(&self, u: Vector2<f64>) -> Option<(f64, Point, f64)> {
        let Outline::Superellipse { a, b, alpha, beta } = *self else {
            return None;
        };
        if alpha != beta || alpha <= 1.0 {
            return None;
        }
        let cap = 1e8 * a.max(b);
        let (ux, uy) = (u.x.abs(), u.y.abs());
        let (sx, sy) = (u.x.signum(), u.y.signum());
        let margin = SUPPORT_REL * a.max(b);
        if ux == 0.0 || uy == 0.0 {
            let (h, point) = if uy == 0.0 {
                (a * ux, Point::new(a * sx, 0.0))
            } else {
                (b * uy, Point::new(0.0, b * sy))
            };
            let rho = match alpha {
                2.0 if uy == 0.0 => b * b / a,
                2.0 => a * a / b,
                x if x > 2.0 => cap,
                _ => 0.0,
            };
            return Some((h + margin, point, rho));
        }
        let (h, x, y, rho) = round_support(a, b, alpha, ux, uy);
        Some((
            h * (1.0 + 4.0 * f64::EPSILON) + margin,
            Point::new(sx * x, sy * y),
            rho.min(cap),
        ))
    }

    /// A length of the outline's size, for relative tolerances: the
    /// largest semi-axis, or the largest vertex distance plus the rounding.
    fn reach_hint(&self) -> f64 {
        match self {
            Outline::Superellipse { a, b, .. } => a.max(*b),
            Outline::Polygon {
                vertices, rounding, ..
            } => vertices.iter().map(|p| p.coords.norm()).fold(0.0, f64::max) + rounding,
        }
    }

    /// Radius of a disk about the centre holding the whole outline (mm): an
    /// upper bound of the farthest point, within 5·10⁻⁶ of it.
    ///
    /// # Behavior
    /// The outline lies inside the polygon of its tangent lines at 1,024
    /// evenly spaced directions, whose corners are at most max h / cos(π/1024)
    /// from the centre.
    pub fn circumradius(&self) -> f64 {
        if let Outline::Polygon {
            vertices, rounding, ..
        } = self
        {
            return (vertices.iter().map(|p| p.coords.norm()).fold(0.0, f64::max) + rounding)
                * (1.0 + SUPPORT_REL);
        }
        const N: usize = 1024;
        let mut h_max = 0.0f64;
        for k in 0..N / 4 + 1 {
            // A superellipse is symmetric about both axes: one quadrant.
            let t = std::f64::consts::TAU * k as f64 / N as f64;
            h_max = h_max.max(self.support(Vector2::new(t.cos(), t.sin())));
        }
        h_max / (std::f64::consts::PI / N as f64).cos()
    }

    /// Least width (mm): the narrowest strip between two parallel lines the
    /// outline fits in, min over u of h(u) + h(−u); the opening of the
    /// finest square mesh a grain passes flat, its sieve size.
    pub fn least_width(&self) -> f64 {
        self.widths().0
    }

    /// Least and greatest width (mm) (the Feret diameters), over 720
    /// directions refined by golden sections around the extremes.
    pub fn widths(&self) -> (f64, f64) {
        let w = |t: f64| {
            let u = Vector2::new(t.cos(), t.sin());
            self.support(u) + self.support(-u)
        };
        const N: usize = 720;
        let step = std::f64::consts::PI / N as f64;
        let (mut imin, mut imax) = (0, 0);
        let (mut wmin, mut wmax) = (f64::INFINITY, 0.0f64);
        for k in 0..N {
            let v = w(k as f64 * step);
            if v < wmin {
                wmin = v;
                imin = k;
            }
            if v > wmax {
                wmax = v;
                imax = k;
            }
        }
        let refine = |k: usize, sign: f64| {
            let (mut lo, mut hi) = ((k as f64 - 1.0) * step, (k as f64 + 1.0) * step);
            let g = 0.618_033_988_749_895;
            for _ in 0..60 {
                let m1 = hi - g * (hi - lo);
                let m2 = lo + g * (hi - lo);
                if sign * w(m1) < sign * w(m2) {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
            w(0.5 * (lo + hi))
        };
        (wmin.min(refine(imin, 1.0)), wmax.max(refine(imax, -1.0)))
    }

    /// Aspect ratio: greatest over least width (≥ 1).
    pub fn aspect(&self) -> f64 {
        let (lo, hi) = self.widths();
        hi / lo
    }

    /// The outline as a counter-clockwise polygon of about `n` points in the
    /// particle's own axes, for drawing and export: points *on* the outline
    /// (the polygon is inscribed: it lies inside the particle).
    pub fn boundary(&self, n: usize) -> Vec<Point> {
        let n = n.max(8);
        match self {
            Outline::Superellipse { a, b, alpha, beta } => (0..n)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / n as f64;
                    let (c, s) = (t.cos(), t.sin());
                    Point::new(
                        a * c.signum() * c.abs().powf(2.0 / alpha),
                        b * s.signum() * s.abs().powf(2.0 / beta),
                    )
                })
                .collect(),
            Outline::Polygon {
                vertices, rounding, ..
            } => {
                let m = vertices.len();
                if *rounding == 0.0 {
                    return vertices.to_vec();
                }
                let per = (n / m).max(2);
                let mut out = Vec::with_capacity(per * m);
                for i in 0..m {
                    let (p, v, q) = (
                        vertices[(i + m - 1) % m],
                        vertices[i],
                        vertices[(i + 1) % m],
                    );
                    let n0 = outward(v - p);
                    let n1 = outward(q - v);
                    let t0 = n0.y.atan2(n0.x);
                    let mut t1 = n1.y.atan2(n1.x);
                    if t1 < t0 {
                        t1 += std::f64::consts::TAU;
                    }
                    for j in 0..per {
                        let t = t0 + (t1 - t0) * j as f64 / (per - 1) as f64;
                        out.push(v + Vector2::new(t.cos(), t.sin()) * *rounding);
                    }
                }
                out
            }
        }
    }
}

/// Outward unit normal of a counter-clockwise edge `e`.
fn outward(e: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(e.y, -e.x).normalize()
}

/// A particle's outline turned by `angle` (radians, counter-clockwise from
/// the x axis): the outline's own x axis points along `angle`.
#[derive(Debug, Clone, PartialEq)]
pub struct Grain {
    /// The outline in the particle's own axes.
    pub outline: Outline,
    /// Orientation (radians, counter-clockwise).
    pub angle: f64,
}

impl Grain {
    /// `outline` turned by `angle`.
    pub fn new(outline: Outline, angle: f64) -> Self {
        Grain { outline, angle }
    }

    /// The grain with its rotation precomputed, for repeated queries.
    pub fn turned(&self) -> Turned<'_> {
        let (s, c) = self.angle.sin_cos();
        Turned {
            outline: &self.outline,
            cos: c,
            sin: s,
        }
    }
}

/// A grain's outline with the cosine and sine of its angle: support
/// queries in world axes.
#[derive(Debug, Clone, Copy)]
pub struct Turned<'a> {
    /// The outline in its own axes.
    pub outline: &'a Outline,
    /// cos(angle).
    pub cos: f64,
    /// sin(angle).
    pub sin: f64,
}

impl Turned<'_> {
    /// World direction `u` in the grain's own axes.
    fn to_local(self, u: Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            self.cos * u.x + self.sin * u.y,
            -self.sin * u.x + self.cos * u.y,
        )
    }

    /// A point in the grain's own axes, in world axes about its centre.
    pub fn to_world(self, p: Point) -> Vector2<f64> {
        Vector2::new(
            self.cos * p.x - self.sin * p.y,
            self.sin * p.x + self.cos * p.y,
        )
    }

    /// Support value (an upper bound) and support point (relative to the
    /// centre) in world direction `u`.
    pub fn support_both(&self, u: Vector2<f64>) -> (f64, Vector2<f64>) {
        let (h, p) = self.outline.support_both(self.to_local(u));
        (h, self.to_world(p))
    }
}

/// How far apart two convex sets are, as the support maps see them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Separation {
    /// A certified lower bound of the distance: `dir`·d − h_K(`dir`), with
    /// h_K bounded from above. Positive: the sets are certainly apart.
    pub lower: f64,
    /// An upper bound of the distance (0 when the sets were found to meet).
    pub upper: f64,
    /// The unit direction of `lower`: from the set towards the point.
    pub dir: Vector2<f64>,
}

/// Most iterations of [`separation`].
const SEPARATION_ITERATIONS: usize = 64;

/// The distance from the point `d` to the convex set K given by its
/// support map `support(u) = (h_K(u) bounded from above, s_K(u))`, by GJK
/// in the plane: the simplex of support points nearest `d` is moved
/// towards it until the lower and upper bounds meet within `tol` (or
/// `upper` falls to 0: `d` is in K, as far as the support points tell).
///
/// For two particles A (centre a) and B (centre b), K = A ⊕ (−B) about the
/// origin (h_K(u) = h_A(u) + h_B(−u)) and `d` = b − a: the distance between
/// the particles. A positive [`Separation::lower`] certifies them apart.
pub fn separation(
    d: Vector2<f64>,
    tol: f64,
    support: impl Fn(Vector2<f64>) -> (f64, Vector2<f64>),
) -> Separation {
    gjk(d, None, support, |s| s.upper - s.lower <= tol)
}

/// [`separation`] started from the direction `guess` (the direction of a
/// nearby query's answer): far fewer iterations when the answer moved little.
pub fn separation_from(
    d: Vector2<f64>,
    guess: Vector2<f64>,
    tol: f64,
    support: impl Fn(Vector2<f64>) -> (f64, Vector2<f64>),
) -> Separation {
    gjk(d, Some(guess), support, |s| s.upper - s.lower <= tol)
}

/// Whether the point `d` is certainly outside the convex set K of
/// [`separation`]: GJK stopped as soon as its lower bound is positive
/// (apart, certified) or the point is found inside (not apart). Undecided
/// after its iterations, it says not apart.
pub fn apart(d: Vector2<f64>, support: impl Fn(Vector2<f64>) -> (f64, Vector2<f64>)) -> bool {
    gjk(d, None, support, |s| s.lower > 0.0).lower > 0.0
}

/// GJK of [`separation`], stopping when `done` says so.
fn gjk(
    d: Vector2<f64>,
    guess: Option<Vector2<f64>>,
    support: impl Fn(Vector2<f64>) -> (f64, Vector2<f64>),
    done: impl Fn(&Separation) -> bool,
) -> Separation {
    let n = d.norm();
    let mut dir = match guess {
        Some(g) if g.norm_squared() > 0.0 => g.normalize(),
        _ if n > 0.0 => d / n,
        _ => Vector2::new(1.0, 0.0),
    };
    let (h, w) = support(dir);
    let mut best = Separation {
        lower: dir.dot(&d) - h,
        upper: f64::INFINITY,
        dir,
    };
    if done(&best) {
        return best;
    }
    // The simplex: one or two support points; its point nearest d is `x`.
    let mut simplex: [Vector2<f64>; 2] = [w, w];
    let mut len = 1;
    for _ in 0..SEPARATION_ITERATIONS {
        let x = if len == 1 {
            simplex[0]
        } else {
            nearest_on_segment(simplex[0], simplex[1], d)
        };
        let gap = d - x;
        let dist = gap.norm();
        best.upper = best.upper.min(dist);
        if dist == 0.0 {
            best.upper = 0.0;
            return best;
        }
        dir = gap / dist;
        let (h, w) = support(dir);
        let lower = dir.dot(&d) - h;
        if lower > best.lower {
            best.lower = lower;
            best.dir = dir;
        }
        if done(&best) {
            return best;
        }
        // A support point already held: the simplex cannot come nearer.
        if w == simplex[0] || (len == 2 && w == simplex[1]) {
            return best;
        }
        // Add w; keep the pair (or point) of the three nearest d.
        if len == 1 {
            simplex[1] = w;
            len = 2;
        } else {
            let (p, q) = (simplex[0], simplex[1]);
            if inside_triangle(p, q, w, d) {
                best.upper = 0.0;
                return best;
            }
            let cp = nearest_on_segment(p, w, d);
            let cq = nearest_on_segment(q, w, d);
            simplex = if (d - cp).norm_squared() <= (d - cq).norm_squared() {
                [p, w]
            } else {
                [q, w]
            };
        }
    }
    best
}

/// The point of segment pq nearest to d.
fn nearest_on_segment(p: Vector2<f64>, q: Vector2<f64>, d: Vector2<f64>) -> Vector2<f64> {
    let e = q - p;
    let l2 = e.norm_squared();
    if l2 == 0.0 {
        return p;
    }
    let t = ((d - p).dot(&e) / l2).clamp(0.0, 1.0);
    p + e * t
}

/// Whether d lies in the closed triangle pqr.
fn inside_triangle(p: Vector2<f64>, q: Vector2<f64>, r: Vector2<f64>, d: Vector2<f64>) -> bool {
    let cross = |a: Vector2<f64>, b: Vector2<f64>| a.x * b.y - a.y * b.x;
    let s1 = cross(q - p, d - p);
    let s2 = cross(r - q, d - q);
    let s3 = cross(p - r, d - r);
    (s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0)
}

/// The distance between two grains at centres `a` and `b` (see
/// [`separation`]), to within `tol`.
pub fn grain_separation(a: &Turned, ca: Point, b: &Turned, cb: Point, tol: f64) -> Separation {
    separation(cb - ca, tol, |u| {
        let (ha, pa) = a.support_both(u);
        let (hb, pb) = b.support_both(-u);
        (ha + hb, pa - pb)
    })
}

/// Support value (bounded from above) and point of the superellipse
/// |x/a|^α + |y/b|^β ≤ 1 in direction `u` (its own axes).
fn superellipse_support(a: f64, b: f64, alpha: f64, beta: f64, u: Vector2<f64>) -> (f64, Point) {
    let (ux, uy) = (u.x.abs(), u.y.abs());
    let (sx, sy) = (u.x.signum(), u.y.signum());
    let margin = SUPPORT_REL * a.max(b) * u.norm();
    if uy == 0.0 {
        return (a * ux + margin, Point::new(a * sx, 0.0));
    }
    if ux == 0.0 {
        return (b * uy + margin, Point::new(0.0, b * sy));
    }
    let (h, x, y) = if alpha == beta {
        let (p, q) = (a * ux, b * uy);
        if alpha == 1.0 {
            // A rhombus: the support point is a corner.
            if p >= q { (p, a, 0.0) } else { (q, 0.0, b) }
        } else {
            let (h, x, y, _) = round_support(a, b, alpha, ux, uy);
            (h, x, y)
        }
    } else {
        // Maximise g(X) = a·X·ux + b·(1 − X^α)^(1/β)·uy over X in [0, 1]:
        // concave; bisect on the sign of g'.
        let g = |x: f64| a * x * ux + b * (1.0 - x.powf(alpha)).max(0.0).powf(1.0 / beta) * uy;
        let dg = |x: f64| {
            let rest = (1.0 - x.powf(alpha)).max(0.0);
            if rest == 0.0 {
                return f64::NEG_INFINITY;
            }
            a * ux - b * uy * (alpha / beta) * x.powf(alpha - 1.0) * rest.powf(1.0 / beta - 1.0)
        };
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        if dg(0.0) <= 0.0 {
            hi = 0.0;
        } else {
            for _ in 0..64 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if dg(mid) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
        }
        // The maximum over [lo, hi] is at most the tangent at lo there.
        let slope = dg(lo).max(0.0);
        let bound = g(lo) + slope * (hi - lo);
        let x = lo;
        let y = (1.0 - x.powf(alpha)).max(0.0).powf(1.0 / beta);
        (bound.max(g(hi)), a * x, b * y)
    };
    (
        h * (1.0 + 4.0 * f64::EPSILON) + margin,
        Point::new(sx * x, sy * y),
    )
}

/// Support value h, support point (x, y) and radius of curvature ρ of the
/// superellipse |x/a|^α + |y/b|^α ≤ 1 (α > 1) in the direction (ux, uy),
/// both positive: h = ‖(a·ux, b·uy)‖_r, the dual norm, r = α/(α − 1);
/// x/a = (P/S)^(1/α), y/b = (Q/S)^(1/α) with P, Q the norm's two terms and
/// S their sum; ρ = (r − 1)·h·P·Q / (S²·ux²·uy²). The powers are taken
/// through two logarithms and two exponentials (the larger term scaled to
/// 1), cheaper than `powf` and within a few units in the last place.
#[inline]
fn round_support(a: f64, b: f64, alpha: f64, ux: f64, uy: f64) -> (f64, f64, f64, f64) {
    let (p, q) = (a * ux, b * uy);
    if alpha == 2.0 {
        // An ellipse: h = |(a·ux, b·uy)|, s = (a·p, b·q) / h, ρ = a²b²/h³.
        let h = (p * p + q * q).sqrt();
        return (h, a * p / h, b * q / h, a * a * b * b / (h * h * h));
    }
    let r = alpha / (alpha - 1.0);
    // With t the smaller of p, q over the larger: the terms over the
    // larger's are 1 and t^r = t·T, T = t^(1/(α−1)); S = 1 + t·T and
    // E = S^(−1/α) give h = max(p, q)·S·E, and the coordinates E along the
    // larger term's axis and T·E along the other's (in semi-axes).
    let (big, t) = if p >= q { (p, q / p) } else { (q, p / q) };
    let tee = if t > 0.0 {
        (t.ln() / (alpha - 1.0)).exp()
    } else {
        0.0
    };
    let small = t * tee;
    let s = 1.0 + small;
    let e = (-small.ln_1p() / alpha).exp();
    let h = big * s * e;
    let (x, y) = if p >= q {
        (a * e, b * e * tee)
    } else {
        (a * e * tee, b * e)
    };
    let rho = (r - 1.0) * h * small / (s * s * ux * ux * uy * uy);
    (h, x, y, rho)
}

/// Signed area of a polygon (positive counter-clockwise).
fn signed_area(v: &[Point]) -> f64 {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (p, q) = (v[i], v[(i + 1) % n]);
            p.x * q.y - q.x * p.y
        })
        .sum::<f64>()
        / 2.0
}

/// Perimeter of a closed polygon.
fn perimeter(v: &[Point]) -> f64 {
    let n = v.len();
    (0..n).map(|i| (v[(i + 1) % n] - v[i]).norm()).sum()
}

/// Centroid of a polygon of non-zero area.
fn centroid(v: &[Point]) -> Vector2<f64> {
    let n = v.len();
    let a = signed_area(v);
    let mut c = Vector2::zeros();
    for i in 0..n {
        let (p, q) = (v[i], v[(i + 1) % n]);
        let cross = p.x * q.y - q.x * p.y;
        c += (p.coords + q.coords) * cross;
    }
    c / (6.0 * a)
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, n = 9: within 10⁻¹⁵ relative).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1−x) = π / sin(πx).
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut s = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        s += c / (x + i as f64);
    }
    let t = x + G + 0.5;
    0.5 * (std::f64::consts::TAU).ln() + (x + 0.5) * t.ln() - t + s.ln()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn areas_in_closed_form_match_known_shapes() {
        let ellipse = Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
        assert!((ellipse.area() - 2.0 * PI).abs() < 1e-12);
        let rhombus = Outline::superellipse(2.0, 1.0, 1.0, 1.0).unwrap();
        assert!((rhombus.area() - 4.0).abs() < 1e-12);
        // α = β → ∞ tends to the 2a × 2b rectangle.
        let box_like = Outline::superellipse(2.0, 1.0, 400.0, 400.0).unwrap();
        assert!((box_like.area() - 8.0).abs() < 0.05);
        let square = Outline::polygon(
            0,
            &[
                Point::new(0.0, 0.0),
                Point::new(2.0, 0.0),
                Point::new(2.0, 2.0),
                Point::new(0.0, 2.0),
            ],
            0.5,
        )
        .unwrap();
        assert!((square.area() - (4.0 + 8.0 * 0.5 + PI * 0.25)).abs() < 1e-12);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-13);
    }

    #[test]
    fn support_bounds_every_boundary_point_and_is_attained() {
        let shapes = [
            Outline::superellipse(3.0, 1.0, 2.0, 2.0).unwrap(),
            Outline::superellipse(2.0, 1.5, 4.0, 4.0).unwrap(),
            Outline::superellipse(2.0, 1.0, 1.0, 1.0).unwrap(),
            Outline::superellipse(2.0, 1.0, 1.5, 7.0).unwrap(),
            Outline::superellipse(1.0, 2.0, 10.0, 1.0).unwrap(),
            Outline::polygon(
                0,
                &[
                    Point::new(0.0, 0.0),
                    Point::new(3.0, 0.0),
                    Point::new(1.0, 2.0),
                ],
                0.2,
            )
            .unwrap(),
        ];
        for s in &shapes {
            let boundary = s.boundary(2000);
            for k in 0..360 {
                let t = k as f64 * PI / 180.0 + 0.01;
                let u = Vector2::new(t.cos(), t.sin());
                let (h, p) = s.support_both(u);
                let on = boundary
                    .iter()
                    .map(|q| q.coords.dot(&u))
                    .fold(f64::MIN, f64::max);
                assert!(h >= on - 1e-12, "{s:?} {t}: {h} < {on}");
                assert!(
                    (p.coords.dot(&u) - h).abs() < 1e-9 * s.circumradius(),
                    "{s:?} {t}"
                );
            }
            let r = s.circumradius();
            let far = boundary.iter().map(|q| q.coords.norm()).fold(0.0, f64::max);
            assert!(r >= far && r <= far * (1.0 + 1e-4), "{s:?}: {r} vs {far}");
        }
    }

    #[test]
    fn curvature_radius_is_the_turn_rate_of_the_support_point() {
        let shapes = [
            Outline::superellipse(3.0, 1.0, 2.0, 2.0).unwrap(),
            Outline::superellipse(2.0, 1.0, 4.0, 4.0).unwrap(),
            Outline::superellipse(1.0, 1.7, 1.5, 1.5).unwrap(),
            Outline::superellipse(2.0, 1.0, 9.0, 9.0).unwrap(),
        ];
        for s in &shapes {
            for k in 0..72 {
                let t = k as f64 * PI / 36.0 + 0.013;
                let u = |t: f64| Vector2::new(t.cos(), t.sin());
                let (h, p, rho) = s.support_curved(u(t)).unwrap();
                let (h0, p0) = s.support_both(u(t));
                assert_eq!((h, p), (h0, p0), "{s:?} {t}");
                let dt = 1e-6;
                let ahead = s.support_point(u(t + dt)).coords;
                let behind = s.support_point(u(t - dt)).coords;
                let tangent = Vector2::new(-t.sin(), t.cos());
                let turned = tangent.dot(&(ahead - behind)) / (2.0 * dt);
                assert!(
                    (rho - turned).abs() <= 1e-5 * (1.0 + rho),
                    "{s:?} {t}: {rho} vs {turned}"
                );
            }
        }
        let rhombus = Outline::superellipse(2.0, 1.0, 1.0, 1.0).unwrap();
        assert!(rhombus.support_curved(Vector2::new(0.6, 0.8)).is_none());
        let uneven = Outline::superellipse(2.0, 1.0, 2.0, 3.0).unwrap();
        assert!(uneven.support_curved(Vector2::new(0.6, 0.8)).is_none());
    }

    #[test]
    fn widths_of_an_ellipse_and_a_rhombus() {
        let e = Outline::superellipse(3.0, 1.0, 2.0, 2.0).unwrap();
        let (lo, hi) = e.widths();
        assert!((lo - 2.0).abs() < 1e-9 && (hi - 6.0).abs() < 1e-9);
        let r = Outline::superellipse(1.0, 1.0, 1.0, 1.0).unwrap();
        assert!((r.least_width() - 2f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn separation_certifies_apart_and_finds_meeting_pairs() {
        let e = Grain::new(Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap(), 0.3);
        let f = Grain::new(Outline::superellipse(1.5, 0.5, 4.0, 4.0).unwrap(), -1.1);
        let (te, tf) = (e.turned(), f.turned());
        for k in 0..200 {
            let t = k as f64 * 0.0314;
            let dir = Vector2::new(t.cos(), t.sin());
            // Distance along a brute-force polygonisation.
            for dist in [4.5, 3.0, 2.0, 1.0] {
                let cb = Point::from(dir * dist);
                let s = grain_separation(&te, Point::origin(), &tf, cb, 1e-12);
                let pe: Vec<_> = e
                    .outline
                    .boundary(1500)
                    .iter()
                    .map(|p| te.to_world(*p))
                    .collect();
                let pf: Vec<_> = f
                    .outline
                    .boundary(1500)
                    .iter()
                    .map(|p| tf.to_world(*p) + cb.coords)
                    .collect();
                let brute = pe
                    .iter()
                    .flat_map(|p| pf.iter().map(move |q| (p - q).norm()))
                    .fold(f64::MAX, f64::min);
                assert!(s.lower <= brute + 1e-9, "lower bound above the distance");
                if s.lower > 0.0 {
                    assert!((s.lower - brute).abs() < 1e-2, "{} vs {brute}", s.lower);
                } else {
                    assert!(s.upper < 1e-6 || brute < 1e-2, "{s:?} vs {brute}");
                }
            }
        }
    }
}
