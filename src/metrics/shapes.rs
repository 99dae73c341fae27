//! Measures of particles that are not disks: the shape of each outline
//! (aspect ratio, sphericity, roundness), the orientation of a packing's
//! particles (the fabric tensor), and their sizes.
//!
//! - **Sphericity** is Riley's, √(D_i / D_c), D_i the diameter of the
//!   largest circle inscribed in the outline and D_c that of the smallest
//!   circle enclosing it (each about any centre): 1 for a disk, √(1/A) for
//!   an ellipse of aspect A. Krumbein's chart, the usual reference of the
//!   geotechnical literature, is read by eye against pictures; Riley's is
//!   the plane measure that is computed from the outline alone, and is the
//!   one the chart's sphericity axis approximates.
//! - **Roundness** is Wadell's: the mean radius of the outline's corners
//!   over the radius of its largest inscribed circle, the corners being the
//!   parts of the outline curved more sharply than that circle (radius of
//!   curvature below it); 1 when there is none (a disk, an ellipse of low
//!   aspect), 0 for sharp corners (a rhombus, a polygon not rounded). A
//!   corner's radius is its length over the angle it turns through — the
//!   radius of the circular arc of the same length and turn, the
//!   length-weighted harmonic mean of its radius of curvature — so that a
//!   sharp corner (turning with no length) counts with radius 0.
//! - **Fabric**: F = mean of n⊗n over the particles, n the unit vector of a
//!   particle's long axis; its eigenvalues λ1 ≥ λ2 (summing to 1), the
//!   anisotropy λ1 − λ2 (0: no preferred direction, 1: all aligned) and the
//!   principal direction, the eigenvector of λ1.
//!
//! Each measure but the sizes is the same for an outline at any scale, so
//! a packing's particles are measured once per distinct outline up to
//! scale ([`ShapeMemo`]): a packing of fixed parameters costs one outline's
//! measures plus a pass over its grains.

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use crate::geometry::{Grain, Outline, Point};
use crate::scene::{Family, Orientation, ShapeSpec, SizeMeasure};

/// Outward normal directions sampled around an outline to find its
/// corners (a multiple of 4: one quadrant is measured and mirrored).
const CORNER_SAMPLES: usize = 1024;

/// A step of the outline counts as a corner when its radius of curvature
/// is below the inscribed radius by more than this share (a disk's steps,
/// all at the inscribed radius up to rounding, are then no corner).
const CORNER_REL: f64 = 1e-9;

/// Radius of the largest circle inscribed in `outline` (mm).
///
/// # Behavior
/// A superellipse is symmetric about its centre, and so is its largest
/// inscribed circle: its radius is half the least width. A rounded polygon's
/// is the polygon's (the Chebyshev centre: the point farthest from every
/// edge line, equidistant from three of them) plus the rounding.
pub fn inscribed_radius(outline: &Outline) -> f64 {
    match outline {
        Outline::Superellipse { .. } => 0.5 * outline.least_width(),
        Outline::Polygon {
            vertices, rounding, ..
        } => chebyshev_radius(vertices) + rounding,
    }
}

/// Radius of the smallest circle enclosing `outline` (mm).
///
/// # Behavior
/// A superellipse's is centred (it is symmetric about its centre): half
/// its greatest width. A rounded polygon's is the smallest circle enclosing
/// its vertices (Welzl's construction) grown by the rounding.
pub fn enclosing_radius(outline: &Outline) -> f64 {
    match outline {
        Outline::Superellipse { .. } => 0.5 * outline.widths().1,
        Outline::Polygon {
            vertices, rounding, ..
        } => smallest_enclosing_radius(vertices) + rounding,
    }
}

/// Riley's sphericity √(D_i / D_c) (see the module's notes), in (0, 1].
pub fn sphericity(outline: &Outline) -> f64 {
    (inscribed_radius(outline) / enclosing_radius(outline))
        .sqrt()
        .min(1.0)
}

/// Wadell's roundness (see the module's notes), in [0, 1].
///
/// # Behavior
/// A rounded polygon's corners are its arcs, all of radius `rounding`:
/// rounding / inscribed radius. A superellipse's are found along
/// `CORNER_SAMPLES` outward normals (`sampled_roundness`).
pub fn roundness(outline: &Outline) -> f64 {
    match outline {
        Outline::Superellipse { .. } => sampled_roundness(outline),
        Outline::Polygon { rounding, .. } => (rounding / inscribed_radius(outline)).min(1.0),
    }
}

/// Wadell's roundness found along the outline: the support points at
/// [`CORNER_SAMPLES`] evenly turned outward normals cut the outline into
/// steps each turning through the same angle Δ, of radius of curvature
/// chord / (2 sin(Δ/2)) (exact on a circular arc); the runs of steps below
/// the inscribed radius are the corners, each of radius its length over
/// its turn.
///
/// # Behavior
/// Exact for a disk (no corner: 1) and for sharp corners (a support point
/// that stays put while its normal turns: radius 0). The outline must be
/// symmetric about both its axes (a superellipse): one quadrant of normals
/// is evaluated and mirrored.
fn sampled_roundness(outline: &Outline) -> f64 {
    sampled_roundness_within(outline, inscribed_radius(outline))
}

/// [`sampled_roundness`] of an outline of inscribed radius `r_in`.
fn sampled_roundness_within(outline: &Outline, r_in: f64) -> f64 {
    let q = CORNER_SAMPLES / 4;
    let step = TAU / CORNER_SAMPLES as f64;
    let quadrant: Vec<Point> = (0..=q)
        .map(|k| {
            let t = k as f64 * step;
            outline.support_point(Vector2::new(t.cos(), t.sin()))
        })
        .collect();
    let at = |k: usize| -> Point {
        let (j, i) = (k / q % 4, k % q);
        match j {
            0 => quadrant[i],
            1 => {
                let p = quadrant[q - i];
                Point::new(-p.x, p.y)
            }
            2 => Point::new(-quadrant[i].x, -quadrant[i].y),
            _ => {
                let p = quadrant[q - i];
                Point::new(p.x, -p.y)
            }
        }
    };
    let chord_to_arc = (0.5 * step) / (0.5 * step).sin();
    // Length of each step, as the circular arc through its chord.
    let lengths: Vec<f64> = (0..CORNER_SAMPLES)
        .map(|k| (at(k + 1) - at(k)).norm() * chord_to_arc)
        .collect();
    let corner = |len: f64| len / step < r_in * (1.0 - CORNER_REL);
    // Start the walk at a step that is no corner, so no run is cut in two.
    let Some(start) = lengths.iter().position(|&l| !corner(l)) else {
        // Every step a corner: one corner round the whole outline.
        return (lengths.iter().sum::<f64>() / TAU / r_in).min(1.0);
    };
    let (mut corners, mut sum) = (0usize, 0.0f64);
    let (mut run_len, mut run_steps) = (0.0f64, 0usize);
    for k in 0..=CORNER_SAMPLES {
        let l = lengths[(start + k) % CORNER_SAMPLES];
        if k < CORNER_SAMPLES && corner(l) {
            run_len += l;
            run_steps += 1;
        } else if run_steps > 0 {
            corners += 1;
            sum += run_len / (run_steps as f64 * step);
            run_len = 0.0;
            run_steps = 0;
        }
    }
    if corners == 0 {
        1.0
    } else {
        (sum / corners as f64 / r_in).min(1.0)
    }
}

/// Direction of an outline's long axis in its own axes (radians, in
/// [0, π)): a superellipse's own x axis when a ≥ b, its y axis otherwise;
/// a polygon's direction of greatest width (its longest vertex pair).
pub fn long_axis(outline: &Outline) -> f64 {
    match outline {
        Outline::Superellipse { a, b, .. } => {
            if a >= b {
                0.0
            } else {
                FRAC_PI_2
            }
        }
        Outline::Polygon { vertices, .. } => {
            let mut best = (0.0, 0.0);
            for (i, p) in vertices.iter().enumerate() {
                for q in &vertices[i + 1..] {
                    let d = q - p;
                    let l = d.norm_squared();
                    if l > best.0 {
                        best = (l, d.y.atan2(d.x).rem_euclid(PI));
                    }
                }
            }
            best.1
        }
    }
}

/// The radius of the largest circle inside the convex polygon `v`
/// (counter-clockwise): the best of the points equidistant from three edge
/// lines that lie inside every edge line.
fn chebyshev_radius(v: &[Point]) -> f64 {
    let m = v.len();
    // Edge i: inward unit normal n_i and offset c_i, inside n_i·x ≥ c_i.
    let edges: Vec<(Vector2<f64>, f64)> = (0..m)
        .map(|i| {
            let e = v[(i + 1) % m] - v[i];
            let n = Vector2::new(-e.y, e.x).normalize();
            (n, n.dot(&v[i].coords))
        })
        .collect();
    let size = v.iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
    let mut best = 0.0f64;
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                // n·x − r = c for the three edges: x, y, r.
                let rows = [edges[i], edges[j], edges[k]];
                let a = nalgebra::Matrix3::from_fn(|r, c| match c {
                    0 => rows[r].0.x,
                    1 => rows[r].0.y,
                    _ => -1.0,
                });
                let b = nalgebra::Vector3::new(rows[0].1, rows[1].1, rows[2].1);
                let Some(x) = a.lu().solve(&b) else {
                    continue;
                };
                let (p, r) = (Vector2::new(x.x, x.y), x.z);
                if !(r.is_finite() && r > best) {
                    continue;
                }
                if edges.iter().all(|(n, c)| n.dot(&p) - c >= r - 1e-12 * size) {
                    best = r;
                }
            }
        }
    }
    best
}

/// Radius of the smallest circle holding the points `v` (Welzl's
/// incremental construction, deterministic: O(m³) at worst for m points,
/// a polygon template's few).
fn smallest_enclosing_radius(v: &[Point]) -> f64 {
    let inside = |c: Point, r: f64, p: Point| (p - c).norm() <= r * (1.0 + 1e-12);
    let mut c = v[0];
    let mut r = 0.0;
    for i in 1..v.len() {
        if inside(c, r, v[i]) {
            continue;
        }
        c = v[i];
        r = 0.0;
        for j in 0..i {
            if inside(c, r, v[j]) {
                continue;
            }
            c = nalgebra::center(&v[i], &v[j]);
            r = 0.5 * (v[i] - v[j]).norm();
            for k in 0..j {
                if inside(c, r, v[k]) {
                    continue;
                }
                (c, r) = circumcircle(v[i], v[j], v[k]);
            }
        }
    }
    r
}

/// The circle through three points (the widest pair's when collinear).
fn circumcircle(a: Point, b: Point, c: Point) -> (Point, f64) {
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * (ab.x * ac.y - ab.y * ac.x);
    if d == 0.0 {
        let pairs = [(a, b), (a, c), (b, c)];
        let (p, q) = pairs
            .into_iter()
            .max_by(|x, y| (x.0 - x.1).norm().total_cmp(&(y.0 - y.1).norm()))
            .unwrap_or((a, b));
        return (nalgebra::center(&p, &q), 0.5 * (p - q).norm());
    }
    let (b2, c2) = (ab.norm_squared(), ac.norm_squared());
    let u = Vector2::new(ac.y * b2 - ab.y * c2, ab.x * c2 - ac.x * b2) / d;
    (a + u, u.norm())
}

/// Mean, sample standard deviation, least and greatest of one measure
/// over a packing's particles (fields in alphabetical order, as every
/// object of a job's summary).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Figures {
    /// Greatest value.
    pub max: f64,
    /// Mean.
    pub mean: f64,
    /// Least value.
    pub min: f64,
    /// Sample standard deviation (n − 1; 0 for one particle).
    pub sd: f64,
}

/// Running mean and variance (Welford), least and greatest.
#[derive(Debug, Clone, Copy)]
struct Running {
    n: usize,
    mean: f64,
    m2: f64,
    min: f64,
    max: f64,
}

impl Running {
    /// Nothing seen.
    fn new() -> Self {
        Running {
            n: 0,
            mean: 0.0,
            m2: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }

    /// Add `x`.
    fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
        self.min = self.min.min(x);
        self.max = self.max.max(x);
    }

    /// The figures of the values seen (at least one).
    fn figures(&self) -> Figures {
        Figures {
            mean: self.mean,
            sd: (self.m2.max(0.0) / (self.n as f64 - 1.0).max(1.0)).sqrt(),
            min: self.min,
            max: self.max,
        }
    }
}

/// The fabric tensor of a set of directions and what it says.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fabric {
    /// λ1 − λ2: 0 with no preferred direction, 1 all aligned.
    pub anisotropy: f64,
    /// Direction of the eigenvector of λ1 (degrees counter-clockwise from
    /// the x axis, in [0, 180)); 0 when isotropic.
    pub direction: f64,
    /// Its eigenvalues, greatest first.
    pub eigenvalues: [f64; 2],
    /// F = mean of n⊗n: [F_xx, F_xy, F_yy] (F_xx + F_yy = 1).
    pub tensor: [f64; 3],
}

impl Fabric {
    /// The fabric of the axes at `angles` (radians; an axis and its
    /// opposite are the same); `None` for no angle.
    pub fn of(angles: impl IntoIterator<Item = f64>) -> Option<Fabric> {
        let (mut n, mut xx, mut xy, mut yy) = (0usize, 0.0, 0.0, 0.0);
        for t in angles {
            let (s, c) = t.sin_cos();
            n += 1;
            xx += c * c;
            xy += c * s;
            yy += s * s;
        }
        (n > 0).then(|| Fabric::from_tensor([xx / n as f64, xy / n as f64, yy / n as f64]))
    }

    /// The fabric of the mean tensor `[F_xx, F_xy, F_yy]`.
    fn from_tensor(t: [f64; 3]) -> Fabric {
        let [xx, xy, yy] = t;
        let half = 0.5 * (xx + yy);
        let root = (0.25 * (xx - yy).powi(2) + xy * xy).sqrt();
        let direction = if root == 0.0 {
            0.0
        } else {
            (0.5 * (2.0 * xy).atan2(xx - yy))
                .to_degrees()
                .rem_euclid(180.0)
        };
        Fabric {
            tensor: t,
            eigenvalues: [half + root, half - root],
            anisotropy: 2.0 * root,
            direction,
        }
    }
}

/// What a packing's particles measure, over all of them (`ShapeStats`
/// of no particle is never made: a packing of disks has none).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct ShapeStats {
    /// What the scene's `[shape]` asked (`None`: not measured against a scene).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub asked: Option<ShapeAsked>,
    /// Aspect ratio: greatest over least width (≥ 1).
    pub aspect: Figures,
    /// Orientation of the particles' long axes.
    pub fabric: Fabric,
    /// Mean diameter of the disk of the same area (mm), as DEM codes size.
    pub mean_equivalent_diameter: f64,
    /// Mean least width (mm): the sieve size.
    pub mean_least_width: f64,
    /// Particles measured.
    pub particles: usize,
    /// Wadell's roundness: mean corner radius over the inscribed radius, in [0, 1].
    pub roundness: Figures,
    /// The size of a particle the grading gives (`None`: not measured
    /// against a scene).
    #[serde(
        default,
        with = "size_measure_name",
        skip_serializing_if = "Option::is_none"
    )]
    pub size_measure: Option<SizeMeasure>,
    /// Riley's sphericity √(D_inscribed / D_enclosing), in (0, 1].
    pub sphericity: Figures,
}

/// What a `[shape]` asked, as a summary records it: the ranges of its
/// parameters and the orientation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct ShapeAsked {
    /// Superellipses: least and greatest exponent α.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<[f64; 2]>,
    /// Superellipses: least and greatest aspect a/b.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aspect: Option<[f64; 2]>,
    /// Superellipses: least and greatest exponent β.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<[f64; 2]>,
    /// `superellipse` or `polygons`.
    pub family: AskedFamily,
    /// `random` or `aligned`.
    pub orientation: AskedOrientation,
    /// Aligned: the mean angle (degrees counter-clockwise from the x axis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation_mean: Option<f64>,
    /// Aligned: the standard deviation of the angle (degrees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation_spread: Option<f64>,
    /// Polygons: how many templates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub templates: Option<usize>,
}

/// The outline family a `[shape]` asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AskedFamily {
    /// Superellipses.
    Superellipse,
    /// Rounded polygons.
    Polygons,
}

/// The orientation a `[shape]` asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AskedOrientation {
    /// Uniformly at random.
    Random,
    /// About a mean angle.
    Aligned,
}

impl ShapeAsked {
    /// What `spec` asked.
    pub fn of(spec: &ShapeSpec) -> ShapeAsked {
        let (mean, spread) = match spec.orientation {
            Orientation::Random => (None, None),
            Orientation::Aligned { mean, spread } => {
                (Some(mean.to_degrees()), Some(spread.to_degrees()))
            }
        };
        let bounds = |s: &crate::scene::Spread| {
            let (lo, hi) = s.bounds();
            [lo, hi]
        };
        let mut asked = ShapeAsked {
            family: AskedFamily::Superellipse,
            aspect: None,
            alpha: None,
            beta: None,
            templates: None,
            orientation: if mean.is_some() {
                AskedOrientation::Aligned
            } else {
                AskedOrientation::Random
            },
            orientation_mean: mean,
            orientation_spread: spread,
        };
        match &spec.family {
            Family::Superellipse {
                aspect,
                alpha,
                beta,
            } => {
                asked.aspect = Some(bounds(aspect));
                asked.alpha = Some(bounds(alpha));
                asked.beta = Some(bounds(beta));
            }
            Family::Polygons { templates } => {
                asked.family = AskedFamily::Polygons;
                asked.templates = Some(templates.len());
            }
        }
        asked
    }
}

/// `size_measure` as its config name (`sieve`, `equivalent`).
mod size_measure_name {
    use serde::{Deserialize, Deserializer, Serializer};

    use crate::scene::SizeMeasure;

    /// Write the name.
    pub(super) fn serialize<S: Serializer>(
        m: &Option<SizeMeasure>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match m {
            Some(m) => s.serialize_str(m.name()),
            None => s.serialize_none(),
        }
    }

    /// Read the name back.
    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<SizeMeasure>, D::Error> {
        let name = Option::<String>::deserialize(d)?;
        name.map(|n| match n.as_str() {
            "sieve" => Ok(SizeMeasure::Sieve),
            "equivalent" => Ok(SizeMeasure::Equivalent),
            other => Err(serde::de::Error::unknown_variant(
                other,
                &["sieve", "equivalent"],
            )),
        })
        .transpose()
    }
}

/// The scale-free measures of one outline, and its sizes and reach over
/// its scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Unit {
    /// Greatest over least width.
    pub(crate) aspect: f64,
    /// Riley's sphericity.
    pub(crate) sphericity: f64,
    /// Wadell's roundness.
    pub(crate) roundness: f64,
    /// Long axis in the outline's own axes (radians).
    pub(crate) axis: f64,
    /// Least width over the scale.
    pub(crate) least_width: f64,
    /// Area-equivalent diameter over the scale.
    pub(crate) equivalent_diameter: f64,
    /// [`Outline::circumradius`] over the scale.
    pub(crate) circumradius: f64,
}

/// An outline up to scale: a superellipse's aspect and exponents, a
/// polygon's template, rounding and vertices over its scale, each ratio to
/// 2⁻³² (outlines that differ by less share their measures).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(super) enum UnitKey {
    /// a/b, α, β.
    Superellipse(i64, u64, u64),
    /// Template, then rounding and each vertex's coordinates over the scale.
    Polygon(u16, Vec<i64>),
}

/// A ratio to 2⁻³².
fn quantise(x: f64) -> i64 {
    (x * 4_294_967_296.0).round() as i64
}

/// The key and scale of `outline`: b for a superellipse, the distance of
/// its first vertex for a polygon.
pub(super) fn key_of(outline: &Outline) -> (UnitKey, f64) {
    match outline {
        Outline::Superellipse { a, b, alpha, beta } => (
            UnitKey::Superellipse(quantise(a / b), alpha.to_bits(), beta.to_bits()),
            *b,
        ),
        Outline::Polygon {
            template,
            vertices,
            rounding,
        } => {
            let s = vertices[0].coords.norm();
            let mut key = Vec::with_capacity(2 * vertices.len() + 1);
            key.push(quantise(rounding / s));
            for v in vertices.iter() {
                key.push(quantise(v.x / s));
                key.push(quantise(v.y / s));
            }
            (UnitKey::Polygon(*template, key), s)
        }
    }
}

/// Each distinct outline's measures, computed once (see the module's notes).
#[derive(Debug, Default)]
pub(crate) struct ShapeMemo {
    units: HashMap<UnitKey, Unit>,
}

impl ShapeMemo {
    /// The measures of `outline` up to scale, and its scale.
    ///
    /// # Performance
    /// The first outline of a kind costs a few thousand support
    /// evaluations; every other of the same kind a hash lookup.
    pub(crate) fn unit(&mut self, outline: &Outline) -> (Unit, f64) {
        let (key, scale) = key_of(outline);
        let unit = *self.units.entry(key).or_insert_with(|| {
            let (lo, hi) = outline.widths();
            // A superellipse's inscribed and enclosing radii are half its
            // widths: searched once here, not once per measure.
            let (sphericity, roundness) = match outline {
                Outline::Superellipse { .. } => {
                    let (r_in, r_out) = (0.5 * lo, 0.5 * hi);
                    (
                        (r_in / r_out).sqrt().min(1.0),
                        sampled_roundness_within(outline, r_in),
                    )
                }
                Outline::Polygon { .. } => (sphericity(outline), roundness(outline)),
            };
            Unit {
                aspect: hi / lo,
                sphericity,
                roundness,
                axis: long_axis(outline),
                least_width: lo / scale,
                equivalent_diameter: 2.0 * outline.equivalent_radius() / scale,
                circumradius: outline.circumradius() / scale,
            }
        });
        (unit, scale)
    }

    /// The size of `outline` that `measure` gives (as
    /// [`ShapeSpec::measure`], through the memo).
    pub(crate) fn size(&mut self, outline: &Outline, measure: SizeMeasure) -> f64 {
        let (unit, scale) = self.unit(outline);
        match measure {
            SizeMeasure::Sieve => unit.least_width * scale,
            SizeMeasure::Equivalent => unit.equivalent_diameter * scale,
        }
    }
}

/// The shape measures of `grains` over `memo`; `None` for no grain.
pub(crate) fn stats_with(grains: &[Grain], memo: &mut ShapeMemo) -> Option<ShapeStats> {
    let (mut aspect, mut sphericity, mut roundness) =
        (Running::new(), Running::new(), Running::new());
    let (mut least, mut equivalent) = (0.0, 0.0);
    let mut axes = Vec::with_capacity(grains.len());
    for g in grains {
        let (u, s) = memo.unit(&g.outline);
        aspect.push(u.aspect);
        sphericity.push(u.sphericity);
        roundness.push(u.roundness);
        least += u.least_width * s;
        equivalent += u.equivalent_diameter * s;
        axes.push(g.angle + u.axis);
    }
    let n = grains.len();
    Some(ShapeStats {
        particles: n,
        aspect: aspect.figures(),
        sphericity: sphericity.figures(),
        roundness: roundness.figures(),
        fabric: Fabric::of(axes)?,
        mean_least_width: least / n as f64,
        mean_equivalent_diameter: equivalent / n as f64,
        size_measure: None,
        asked: None,
    })
}

/// The shape measures of `grains` (a packing's), with what `spec` asked
/// when given; `None` for no grain.
pub fn shape_stats(grains: &[Grain], spec: Option<&ShapeSpec>) -> Option<ShapeStats> {
    stats_for(grains, spec, &mut ShapeMemo::default())
}

/// [`shape_stats`] through `memo`.
pub(crate) fn stats_for(
    grains: &[Grain],
    spec: Option<&ShapeSpec>,
    memo: &mut ShapeMemo,
) -> Option<ShapeStats> {
    let mut stats = stats_with(grains, memo)?;
    stats.size_measure = spec.map(|s| s.size);
    stats.asked = spec.map(ShapeAsked::of);
    Some(stats)
}

/// Each particle's aspect ratio, sphericity and long-axis angle (radians,
/// counter-clockwise from the x axis), for the shape chart and the rose;
/// each distinct outline up to scale measured once.
pub fn shape_series(grains: &[Grain]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut memo = ShapeMemo::default();
    let mut aspects = Vec::with_capacity(grains.len());
    let mut sphericities = Vec::with_capacity(grains.len());
    let mut axes = Vec::with_capacity(grains.len());
    for g in grains {
        let (unit, _) = memo.unit(&g.outline);
        aspects.push(unit.aspect);
        sphericities.push(unit.sphericity);
        axes.push(g.angle + unit.axis);
    }
    (aspects, sphericities, axes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn superellipse(a: f64, b: f64, e: f64) -> Outline {
        Outline::superellipse(a, b, e, e).unwrap()
    }

    fn square(side: f64, rounding: f64) -> Outline {
        let h = side / 2.0;
        Outline::polygon(
            0,
            &[
                Point::new(-h, -h),
                Point::new(h, -h),
                Point::new(h, h),
                Point::new(-h, h),
            ],
            rounding,
        )
        .unwrap()
    }

    #[test]
    fn a_circle_is_round_and_spherical() {
        let c = superellipse(1.5, 1.5, 2.0);
        assert!((c.aspect() - 1.0).abs() < 1e-9);
        assert!((sphericity(&c) - 1.0).abs() < 1e-9, "{}", sphericity(&c));
        assert!((roundness(&c) - 1.0).abs() < 1e-9, "{}", roundness(&c));
        assert!((inscribed_radius(&c) - 1.5).abs() < 1e-9);
    }

    #[test]
    fn an_ellipse_of_aspect_two() {
        let e = superellipse(2.0, 1.0, 2.0);
        assert!((e.aspect() - 2.0).abs() < 1e-9);
        assert!((sphericity(&e) - 0.5f64.sqrt()).abs() < 1e-9);
        // Its ends (radius of curvature b²/a = 0.5 at the tips) are the
        // corners, its flanks (up to a²/b = 4) are not.
        let r = roundness(&e);
        assert!(r > 0.5 && r < 1.0, "{r}");
        // Blunter ends round it more.
        assert!(roundness(&superellipse(1.2, 1.0, 2.0)) > r);
    }

    #[test]
    fn a_rounded_square_is_as_round_as_its_rounding() {
        let s = square(2.0, 0.25);
        // Inscribed radius: 1 + 0.25; enclosing: √2 + 0.25.
        assert!((inscribed_radius(&s) - 1.25).abs() < 1e-12);
        assert!((enclosing_radius(&s) - (2f64.sqrt() + 0.25)).abs() < 1e-12);
        assert!((roundness(&s) - 0.25 / 1.25).abs() < 1e-12);
        assert!((sphericity(&s) - (1.25 / (2f64.sqrt() + 0.25)).sqrt()).abs() < 1e-12);
        // The walk along the outline finds the same corners.
        assert!(
            (sampled_roundness(&s) - 0.2).abs() < 1e-3,
            "{}",
            sampled_roundness(&s)
        );
        // Sharp corners: 0.
        assert_eq!(roundness(&square(2.0, 0.0)), 0.0);
    }

    #[test]
    fn polygon_circles_on_a_triangle() {
        // The 3-4-5 right triangle: inradius (3 + 4 − 5)/2 = 1, its
        // smallest enclosing circle on the hypotenuse, radius 2.5.
        let t = Outline::polygon(
            0,
            &[
                Point::new(0.0, 0.0),
                Point::new(4.0, 0.0),
                Point::new(0.0, 3.0),
            ],
            0.0,
        )
        .unwrap();
        assert!((inscribed_radius(&t) - 1.0).abs() < 1e-12);
        assert!((enclosing_radius(&t) - 2.5).abs() < 1e-12);
        // An obtuse triangle's enclosing circle is its longest side's.
        let o = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(5.0, 1.0),
        ];
        assert!((smallest_enclosing_radius(&o) - 5.0).abs() < 1e-12);
        // The long axis is the hypotenuse's direction.
        let axis = long_axis(&t);
        assert!(
            (axis - (PI - (3.0f64 / 4.0).atan())).abs() < 1e-12,
            "{axis}"
        );
    }

    #[test]
    fn a_rhombus_has_sharp_corners() {
        let r = superellipse(2.0, 1.0, 1.0);
        assert!(roundness(&r) < 1e-9, "{}", roundness(&r));
        // Nearly sharp: nearly 0, but above.
        let near = Outline::superellipse(2.0, 1.0, 1.2, 1.2).unwrap();
        let rn = roundness(&near);
        assert!(rn > 0.0 && rn < 0.3, "{rn}");
    }

    #[test]
    fn fabric_of_aligned_and_spread_axes() {
        let aligned = Fabric::of([0.3; 50]).unwrap();
        assert!((aligned.anisotropy - 1.0).abs() < 1e-12);
        assert!((aligned.direction - 0.3f64.to_degrees()).abs() < 1e-9);
        // Opposite directions are one axis.
        let opposite = Fabric::of([0.3, 0.3 + PI]).unwrap();
        assert!((opposite.anisotropy - 1.0).abs() < 1e-12);
        let spread = Fabric::of((0..36).map(|k| k as f64 * PI / 36.0)).unwrap();
        assert!(spread.anisotropy < 1e-12, "{spread:?}");
        assert!((spread.eigenvalues[0] - 0.5).abs() < 1e-12);
        assert!(Fabric::of([]).is_none());
    }

    #[test]
    fn stats_of_aligned_ellipses_and_their_memo() {
        let grains: Vec<Grain> = (1..=4)
            .map(|k| Grain::new(superellipse(2.0 * k as f64, k as f64, 2.0), FRAC_PI_2))
            .collect();
        let spec = ShapeSpec::ellipses(2.0);
        let s = shape_stats(&grains, Some(&spec)).unwrap();
        assert_eq!(s.particles, 4);
        assert!((s.aspect.mean - 2.0).abs() < 1e-9 && s.aspect.sd < 1e-12);
        assert!((s.sphericity.max - 0.5f64.sqrt()).abs() < 1e-9);
        assert!((s.fabric.anisotropy - 1.0).abs() < 1e-12);
        assert!((s.fabric.direction - 90.0).abs() < 1e-9);
        // Least widths 2, 4, 6, 8; equivalent diameters 2√2 times k.
        assert!((s.mean_least_width - 5.0).abs() < 1e-9);
        assert!((s.mean_equivalent_diameter - 2.5 * 2.0 * 2f64.sqrt()).abs() < 1e-9);
        assert_eq!(s.size_measure, Some(SizeMeasure::Sieve));
        let asked = s.asked.unwrap();
        assert_eq!(asked.aspect, Some([2.0, 2.0]));
        assert_eq!(asked.orientation, AskedOrientation::Random);
        // One outline up to scale: measured once.
        let mut memo = ShapeMemo::default();
        stats_with(&grains, &mut memo);
        assert_eq!(memo.units.len(), 1);
        // The memo's sizes are the spec's measure.
        for g in &grains {
            let m = memo.size(&g.outline, SizeMeasure::Sieve);
            assert!((m - spec.measure(&g.outline)).abs() < 1e-12 * m);
        }
        assert!(shape_stats(&[], None).is_none());
        // Read back from its JSON.
        let json = serde_json::to_string(&s).unwrap();
        assert!(json.contains("\"size_measure\":\"sieve\""), "{json}");
        let back: ShapeStats = serde_json::from_str(&json).unwrap();
        assert_eq!(back.asked, s.asked);
        assert!((back.aspect.mean - s.aspect.mean).abs() < 1e-12);
    }
}
