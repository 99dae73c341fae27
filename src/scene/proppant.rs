//! Shapes of common proppants (`[shape] preset = "..."`): outlines whose
//! measured mean sphericity and roundness (Riley's and Wadell's, as
//! `metrics` measures them) are the figures each proppant is specified or
//! sold at.
//!
//! - [`Proppant::Ceramic`]: sintered ceramic proppant, sphericity and
//!   roundness 0.9 (the typical properties of manufacturers' data sheets,
//!   e.g. CARBO Ceramics' CARBOLITE). Superellipses of exponent 2.2 and
//!   aspect 1.1 to 1.35.
//! - [`Proppant::ResinCoatedSand`]: sand coated with resin, sphericity and
//!   roundness 0.7 (the least ISO 13503-2 / API RP 19C ask of resin-coated
//!   and ceramic proppant). Superellipses of exponent 3 and aspect 1.8 to 2.2.
//! - [`Proppant::AngularSand`]: the least rounded frac sand the
//!   specifications admit, sphericity and roundness 0.6 (API RP 19C /
//!   ISO 13503-2). Three rounded irregular polygons, each of sphericity and
//!   roundness 0.6 exactly.
//!
//! A rounded polygon's roundness is its rounding over its inscribed radius
//! and its sphericity √((r_c + ρ)/(R_c + ρ)) (r_c, R_c the polygon's
//! inscribed and enclosing radii, ρ the rounding): the templates below are
//! scaled to r_c = 1 with ρ = 1.5 (roundness 0.6) and stretched until
//! R_c = 49/9 (sphericity 0.6).

use super::shape::{Family, Orientation, ShapeSpec, SizeMeasure, Spread, template_vertices};
use crate::geometry::Outline;

/// The rounding of every angular-sand template (their inscribed radius
/// without it is 1): roundness 1.5 / 2.5 = 0.6.
const ANGULAR_ROUNDING: f64 = 1.5;

/// The angular-sand templates: irregular convex polygons of inscribed
/// radius 1 and enclosing radius 49/9 (to 6 decimals).
const ANGULAR_TEMPLATES: [&[[f64; 2]]; 3] = [
    &[
        [-5.644127, -0.263181],
        [-0.200127, -1.097400],
        [5.243874, -0.402217],
        [3.066274, 0.988149],
        [-2.922127, 0.849112],
    ],
    &[
        [-5.332065, 0.204057],
        [-0.978197, -1.159955],
        [5.552604, -0.099057],
        [0.654503, 1.113398],
    ],
    &[
        [-5.447737, -0.057783],
        [-2.181922, -1.052659],
        [2.716799, -0.928299],
        [5.438311, 0.190936],
        [2.172497, 1.061452],
        [-3.270527, 0.812733],
    ],
];

/// A common proppant whose shape a `[shape]` may name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Proppant {
    /// Sintered ceramic: sphericity and roundness 0.9.
    Ceramic,
    /// Resin-coated sand: sphericity and roundness 0.7.
    ResinCoatedSand,
    /// Angular frac sand at the specifications' least: sphericity and roundness 0.6.
    AngularSand,
}

impl Proppant {
    /// Every preset, in the order the docs list them.
    pub const ALL: [Proppant; 3] = [
        Proppant::Ceramic,
        Proppant::ResinCoatedSand,
        Proppant::AngularSand,
    ];

    /// The name a config gives it (`preset = "ceramic"`).
    pub fn name(self) -> &'static str {
        match self {
            Proppant::Ceramic => "ceramic",
            Proppant::ResinCoatedSand => "resin-coated-sand",
            Proppant::AngularSand => "angular-sand",
        }
    }

    /// The specified (or sold) mean sphericity and roundness the shape is
    /// made to measure.
    pub fn specified(self) -> (f64, f64) {
        match self {
            Proppant::Ceramic => (0.9, 0.9),
            Proppant::ResinCoatedSand => (0.7, 0.7),
            Proppant::AngularSand => (0.6, 0.6),
        }
    }

    /// Its outlines.
    pub fn family(self) -> Family {
        let superellipses = |lo: f64, hi: f64, exponent: f64| Family::Superellipse {
            aspect: Spread::Range(lo, hi),
            alpha: Spread::Fixed(exponent),
            beta: Spread::Fixed(exponent),
        };
        match self {
            Proppant::Ceramic => superellipses(1.1, 1.35, 2.2),
            Proppant::ResinCoatedSand => superellipses(1.8, 2.2, 3.0),
            Proppant::AngularSand => {
                let share = 1.0 / ANGULAR_TEMPLATES.len() as f64;
                let templates = ANGULAR_TEMPLATES
                    .iter()
                    .zip(0u16..)
                    .filter_map(|(v, i)| {
                        Outline::polygon(i, &template_vertices(v), ANGULAR_ROUNDING).ok()
                    })
                    .map(|o| (o, share))
                    .collect();
                Family::Polygons { templates }
            }
        }
    }

    /// Its shape turned at random and sized by sieve (a config may give
    /// another orientation or size measure).
    pub fn shape(self) -> ShapeSpec {
        ShapeSpec {
            family: self.family(),
            orientation: Orientation::Random,
            size: SizeMeasure::Sieve,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{roundness, sphericity};
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    #[test]
    fn each_preset_measures_its_specified_sphericity_and_roundness() {
        for p in Proppant::ALL {
            let spec = p.shape();
            if let Family::Polygons { templates } = &spec.family {
                assert_eq!(
                    templates.len(),
                    ANGULAR_TEMPLATES.len(),
                    "every template is convex"
                );
            }
            let drawer = spec.drawer();
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
            let n = 200;
            let (mut s, mut r) = (0.0, 0.0);
            for _ in 0..n {
                let g = drawer.draw(1.25, &mut rng);
                s += sphericity(&g.outline);
                r += roundness(&g.outline);
            }
            let (s, r) = (s / f64::from(n), r / f64::from(n));
            let (want_s, want_r) = p.specified();
            assert!((s - want_s).abs() <= 0.03, "{}: sphericity {s}", p.name());
            assert!((r - want_r).abs() <= 0.03, "{}: roundness {r}", p.name());
        }
    }

    #[test]
    fn angular_templates_sit_at_the_specified_least() {
        let Family::Polygons { templates } = Proppant::AngularSand.family() else {
            panic!("polygons");
        };
        for (t, share) in &templates {
            assert!((sphericity(t) - 0.6).abs() < 1e-5, "{}", sphericity(t));
            assert!((roundness(t) - 0.6).abs() < 1e-5, "{}", roundness(t));
            assert!((share - 1.0 / 3.0).abs() < 1e-12);
        }
    }
}
