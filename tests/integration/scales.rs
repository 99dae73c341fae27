//! Geometry at every scale: the same scenes scaled from 10⁻⁶ to 10⁶ (mm),
//! moved far from the origin, and domains whose far end lies 10⁵–2·10⁶
//! diameters from the origin.
//!
//! The algorithm is scale-free, and so is every tolerance (see the module
//! doc of `geometry::predicates`): a scene scaled by a power of two packs
//! to the same disks scaled, and one scaled by a power of ten to the same
//! packing up to rounding, which can send a packing down another branch
//! (figures in `powers_of_ten_pack_alike`). Every packing, at every scale
//! and offset, is checked by `gapack::check`: no overlap beyond
//! `OVERLAP_REL` of the radii sum, nothing outside beyond `OVERLAP_REL`
//! of the largest diameter.
//!
//! The scenes drawn are the same on every run (a fixed seed);
//! `PROPTEST_RNG_SEED=N cargo test --test integration scales::` explores others.

use crate::common;

use gapack::check;
use gapack::{
    Domain, Fill, FrontRules, Grading, Interpolation, Method, Packing, Point, Scene, WallMode, pack,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// The scenes drawn: the same on every run, so that CI is repeatable.
fn rng_seed() -> RngSeed {
    common::rng_seed(0x7363_616C_6573)
}

/// A domain's shape before it is scaled and moved (unit: about a diameter).
#[derive(Debug, Clone)]
enum Shape {
    /// `Domain::rectangle`, anchored at the origin (not moved).
    Rectangle(f64, f64),
    /// `Domain::trapezoid`, anchored at the origin (not moved).
    Trapezoid(f64, f64, f64),
    /// Circle of this radius, its lowest corner at the origin before moving.
    Circle(f64),
    /// Any polygon.
    Polygon(Vec<(f64, f64)>),
}

impl Shape {
    /// The domain scaled by `s` and moved by `(o, o)` (only shapes that can move).
    fn domain(&self, s: f64, o: (f64, f64)) -> Domain {
        let moved = |x: f64, y: f64| Point::new(x * s + o.0, y * s + o.1);
        match *self {
            Shape::Rectangle(w, h) => Domain::rectangle(w * s, h * s).unwrap(),
            Shape::Trapezoid(b, t, h) => Domain::trapezoid(b * s, t * s, h * s).unwrap(),
            Shape::Circle(r) => Domain::circle(moved(r, r), r * s).unwrap(),
            Shape::Polygon(ref v) => {
                Domain::polygon(&v.iter().map(|&(x, y)| moved(x, y)).collect::<Vec<_>>()).unwrap()
            }
        }
    }

    /// The same place as a polygon (rectangles and trapezoids can then move).
    fn movable(&self) -> Shape {
        match *self {
            Shape::Rectangle(w, h) => Shape::Polygon(vec![(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]),
            Shape::Trapezoid(b, t, h) => Shape::Polygon(vec![
                (0.0, 0.0),
                (b, 0.0),
                (0.5 * (b + t), h),
                (0.5 * (b - t), h),
            ]),
            ref other => other.clone(),
        }
    }
}

/// The shapes every deterministic test runs: convex and not, slivers,
/// collinear vertices, a circle.
fn shapes() -> Vec<(&'static str, Shape)> {
    vec![
        ("rectangle", Shape::Rectangle(20.0, 14.0)),
        ("trapezoid", Shape::Trapezoid(25.0, 8.0, 12.0)),
        ("circle", Shape::Circle(9.0)),
        (
            "L",
            Shape::Polygon(vec![
                (0.0, 0.0),
                (20.0, 0.0),
                (20.0, 8.0),
                (8.0, 8.0),
                (8.0, 20.0),
                (0.0, 20.0),
            ]),
        ),
        // A wedge of 4.8°: its tip takes no disk.
        (
            "sliver",
            Shape::Polygon(vec![(0.0, 0.0), (60.0, 0.0), (60.0, 5.0)]),
        ),
        // A strip 1.625 to 2.25 diameters wide, 80 long.
        (
            "strip",
            Shape::Polygon(vec![(0.0, 0.0), (80.0, 0.0), (80.0, 2.25), (0.0, 1.625)]),
        ),
        // A rectangle with vertices in the middle of its edges.
        (
            "collinear",
            Shape::Polygon(vec![
                (0.0, 0.0),
                (7.0, 0.0),
                (18.0, 0.0),
                (18.0, 9.0),
                (18.0, 15.0),
                (9.0, 15.0),
                (0.0, 15.0),
                (0.0, 5.0),
            ]),
        ),
    ]
}

/// A grading before it is scaled (unit: about a diameter).
#[derive(Debug, Clone, Copy)]
enum Curve {
    Constant,
    Uniform,
    /// Steps: 80 % of the disks at one size, the rest spread below and above.
    Steps,
    /// Log-interpolated sieve table (the thesis' Table 3.4, scaled to 1).
    Log,
}

impl Curve {
    fn grading(self, s: f64) -> Grading {
        match self {
            Curve::Constant => Grading::constant(s).unwrap(),
            Curve::Uniform => Grading::uniform(0.5 * s, 1.5 * s, Default::default()).unwrap(),
            Curve::Steps => Grading::from_table(
                &[
                    (0.4 * s, 0.0),
                    (0.8 * s, 10.0),
                    (0.8 * s, 90.0),
                    (2.0 * s, 100.0),
                ],
                Default::default(),
                Default::default(),
            )
            .unwrap(),
            Curve::Log => {
                let rows: Vec<(f64, f64)> = gapack::THESIS_TABLE_3_4
                    .iter()
                    .map(|&(d, p)| (d / 1.25 * s, p))
                    .collect();
                Grading::from_table(&rows, Interpolation::Log, Default::default()).unwrap()
            }
        }
    }
}

const CURVES: [Curve; 4] = [Curve::Constant, Curve::Uniform, Curve::Steps, Curve::Log];

/// A scene before scaling.
#[derive(Debug, Clone)]
struct Spec {
    shape: Shape,
    curve: Curve,
    walls: WallMode,
    method: Method,
    rules: FrontRules,
    one_contact_share: f64,
    gap: f64,
    fill: Fill,
    seed: u64,
}

impl Spec {
    fn simple(shape: Shape, curve: Curve, walls: WallMode) -> Self {
        Spec {
            shape,
            curve,
            walls,
            method: Method::AdvancingFront,
            rules: FrontRules::Robust,
            one_contact_share: 0.0,
            gap: 0.0,
            fill: Fill::Up,
            seed: 1,
        }
    }

    fn scene(&self, s: f64, o: (f64, f64)) -> Scene {
        let mut scene = common::scene(
            self.shape.domain(s, o),
            self.curve.grading(s),
            self.walls,
            self.seed,
        );
        let p = &mut scene.packer;
        p.method = self.method;
        p.rules = self.rules;
        p.one_contact_share = self.one_contact_share;
        p.gap = self.gap;
        p.fill = self.fill;
        p.attempts = 300;
        scene
    }
}

/// Pack `scene`; panics with the scene if the packing is not valid.
fn valid_packing(scene: &Scene, what: &str) -> (Packing, f64) {
    let p = pack(scene).unwrap_or_else(|e| panic!("{what}: {e}"));
    let c = check(&p.disks, &p.domain, None);
    assert!(c.valid(), "{what}: {c:?}");
    (p, c.porosity)
}

/// Whether two packings of scenes scaled apart by a power of two agree:
/// the same disk count, porosity within 1e-6.
fn assert_alike(a: &(Packing, f64), b: &(Packing, f64), what: &str) {
    assert_eq!(a.0.disks.len(), b.0.disks.len(), "{what}: disk count");
    assert!(
        (a.1 - b.1).abs() <= 1e-6,
        "{what}: porosity {} vs {}",
        a.1,
        b.1
    );
}

/// 2⁻²⁰ (about 10⁻⁶) to 2²⁰ (about 10⁶): the same packing, scaled.
#[test]
fn powers_of_two_pack_the_same_disks_scaled() {
    for (name, shape) in shapes() {
        for curve in CURVES {
            for walls in [WallMode::Exact, WallMode::Disks] {
                let spec = Spec::simple(shape.clone(), curve, walls);
                let what = format!("{name} {curve:?} {walls:?}");
                let unit = valid_packing(&spec.scene(1.0, (0.0, 0.0)), &what);
                assert!(
                    unit.0.disks.len() > 20,
                    "{what}: {} disks",
                    unit.0.disks.len()
                );
                for k in [-20, -10, 10, 20] {
                    let s = 2f64.powi(k);
                    let what = format!("{what} × 2^{k}");
                    let scaled = valid_packing(&spec.scene(s, (0.0, 0.0)), &what);
                    assert_alike(&unit, &scaled, &what);
                }
            }
        }
    }
}

/// 10⁻⁶ to 10⁶: every packing valid; the figures agree up to rounding,
/// which can send a packing down another branch where equal disks meet in
/// ties. Measured (seed 1, the 56 scenes here × 4 scales): the same disk
/// count in 215 of 224, porosity then equal within 1e-14; the other 9 (the
/// step grading with wall disks) within 11 disks of 184 and 0.019 in
/// porosity. `cargo test --test integration scales:: -- --nocapture` prints them.
#[test]
fn powers_of_ten_pack_alike() {
    let (mut report, mut same, mut runs) = (Vec::new(), 0, 0);
    for (name, shape) in shapes() {
        for curve in CURVES {
            for walls in [WallMode::Exact, WallMode::Disks] {
                let spec = Spec::simple(shape.clone(), curve, walls);
                let what = format!("{name} {curve:?} {walls:?}");
                let (unit, phi) = valid_packing(&spec.scene(1.0, (0.0, 0.0)), &what);
                let n = unit.disks.len() as f64;
                for k in [-6, -3, 3, 6] {
                    let what = format!("{what} × 1e{k}");
                    let (p, psi) = valid_packing(&spec.scene(10f64.powi(k), (0.0, 0.0)), &what);
                    let dn = p.disks.len() as f64 - n;
                    runs += 1;
                    if dn == 0.0 {
                        same += 1;
                        assert!(
                            (psi - phi).abs() <= 1e-12,
                            "{what}: porosity {psi} vs {phi}"
                        );
                    }
                    report.push(format!("{what}: {dn:+} disks, porosity {:+.1e}", psi - phi));
                    assert!(dn.abs() <= 0.08 * n, "{what}: {dn} disks of {n}");
                    assert!((psi - phi).abs() <= 0.03, "{what}: porosity {psi} vs {phi}");
                }
            }
        }
    }
    println!(
        "{}\n{same} of {runs} with the same disk count",
        report.join("\n")
    );
    assert!(
        same * 10 >= runs * 9,
        "only {same} of {runs} with the same disk count"
    );
}

/// Moved 10⁵ and 10⁶ from the origin (both signs, and each axis alone):
/// the packing of the scene at the origin, moved. Every shape here has its
/// lowest corner at the origin and vertices that move exactly, so the
/// packings match disk for disk, but for one rounding of each centre.
#[test]
fn far_from_the_origin_the_packing_is_the_same_moved() {
    for (name, shape) in shapes() {
        let shape = shape.movable();
        for curve in CURVES {
            for walls in [WallMode::Exact, WallMode::Disks] {
                let spec = Spec::simple(shape.clone(), curve, walls);
                let what = format!("{name} {curve:?} {walls:?}");
                let (near, _) = valid_packing(&spec.scene(1.0, (0.0, 0.0)), &what);
                for o in [(1e6, 1e6), (-1e6, 2e6), (1e5, 0.0), (0.0, -1e6)] {
                    let what = format!("{what} at {o:?}");
                    let (far, _) = valid_packing(&spec.scene(1.0, o), &what);
                    assert_eq!(far.disks.len(), near.disks.len(), "{what}");
                    for (a, b) in far.disks.iter().zip(&near.disks) {
                        // One rounding of each moved centre.
                        let moved = Point::new(b.c.x + o.0, b.c.y + o.1);
                        assert!((a.c - moved).norm() <= 4e-10, "{what}: {} vs {moved}", a.c);
                        assert_eq!(a.r, b.r, "{what}");
                    }
                }
            }
        }
    }
}

/// Two 20 × 20 pockets joined by a corridor too narrow for any disk, the
/// second `x` from the origin. The far pocket must pack as it does near:
/// with coordinates rounded to 10⁻¹⁰ mm there, candidates tangent to a disk
/// (or a wall) were refused for a penetration of rounding, and the pocket
/// packed 5 % fewer disks at 10⁶ (or none, a square turned 30°, at 2·10⁶).
#[test]
fn a_pocket_far_along_the_domain_packs_as_one_near_it() {
    let w = 0.3;
    let pockets = |x: f64| {
        vec![
            (0.0, 0.0),
            (x + 20.0, 0.0),
            (x + 20.0, 20.0),
            (x, 20.0),
            (x, w),
            (20.0, w),
            (20.0, 20.0),
            (0.0, 20.0),
        ]
    };
    // The far pocket a square turned 30°, standing on its lowest corner.
    let turned = |x: f64| {
        let (s, c) = 30f64.to_radians().sin_cos();
        vec![
            (0.0, 0.0),
            (x, 0.0),
            (x + 20.0 * c, 20.0 * s),
            (x + 20.0 * (c - s), 20.0 * (s + c)),
            (x - 20.0 * s, 20.0 * c),
            (x - w * s / c, w),
            (20.0, w),
            (20.0, 20.0),
            (0.0, 20.0),
        ]
    };
    for curve in [Curve::Constant, Curve::Uniform, Curve::Steps] {
        let far_disks = |v: Vec<(f64, f64)>, x: f64, what: &str| {
            let spec = Spec::simple(Shape::Polygon(v), curve, WallMode::Exact);
            let (p, _) = valid_packing(&spec.scene(1.0, (0.0, 0.0)), what);
            p.disks.iter().filter(|d| d.c.x > x - 30.0).count()
        };
        let near = far_disks(pockets(100.0), 100.0, "near");
        let near_turned = far_disks(turned(100.0), 100.0, "near turned");
        assert!(near > 300 && near_turned > 300, "{near} {near_turned}");
        for x in [1e5, 1e6, 2e6] {
            let what = format!("{curve:?}, pocket at {x:e}");
            assert_eq!(far_disks(pockets(x), x, &what), near, "{what}");
            // Slanted walls round differently along the way; within 5 %.
            let got = far_disks(turned(x), x, &format!("{what}, turned"));
            assert!(
                got.abs_diff(near_turned) * 20 <= near_turned,
                "{what}, turned: {got} disks against {near_turned}"
            );
        }
    }
}

fn shape_strategy() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (4.0..30.0f64, 4.0..30.0f64).prop_map(|(w, h)| Shape::Rectangle(w, h)),
        (4.0..25.0f64, 0.5..25.0f64, 4.0..25.0f64).prop_map(|(b, t, h)| Shape::Trapezoid(b, t, h)),
        (3.0..12.0f64).prop_map(Shape::Circle),
        // L shapes with arms from 0.2 to 0.8 of the side.
        (6.0..25.0f64, 0.2..0.8f64).prop_map(|(s, a)| {
            let a = a * s;
            Shape::Polygon(vec![(0.0, 0.0), (s, 0.0), (s, a), (a, a), (a, s), (0.0, s)])
        }),
        // Wedges of 3° to 20°, 30 to 70 long.
        (3.0..20.0f64, 30.0..70.0f64).prop_map(|(deg, len)| {
            let t: f64 = deg.to_radians().tan();
            Shape::Polygon(vec![(0.0, 0.0), (len, 0.0), (len, len * t)])
        }),
        // Strips 2.1 to 4 diameters wide (at least the largest, 2).
        (2.1..4.0f64, 2.1..4.0f64, 20.0..80.0f64).prop_map(|(h0, h1, len)| Shape::Polygon(vec![
            (0.0, 0.0),
            (len, 0.0),
            (len, h1),
            (0.0, h0)
        ])),
    ]
}

fn spec_strategy() -> impl Strategy<Value = Spec> {
    (
        shape_strategy(),
        prop::sample::select(CURVES.to_vec()),
        prop_oneof![Just(WallMode::Exact), Just(WallMode::Disks)],
        prop_oneof![8 => Just(Method::AdvancingFront), 1 => Just(Method::Rsa), 1 => Just(Method::Deposition)],
        prop_oneof![3 => Just(FrontRules::Robust), 1 => Just(FrontRules::Thesis)],
        prop_oneof![2 => Just((0.0, 0.0)), 1 => (0.0..=1.0f64, 0.0..=gapack::MAX_GAP)],
        prop_oneof![3 => Just(Fill::Up), 1 => Just(Fill::Right)],
        any::<u64>(),
    )
        .prop_map(
            |(shape, curve, walls, method, rules, (one_contact_share, gap), fill, seed)| Spec {
                shape,
                curve,
                walls,
                method,
                rules,
                one_contact_share,
                gap,
                fill,
                seed,
            },
        )
        // The largest disk (2 units with the steps) must fit.
        .prop_filter("the largest disk must fit", |s| {
            s.scene(1.0, (0.0, 0.0)).domain.inradius() > 1.0
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, rng_seed: rng_seed(), ..ProptestConfig::default() })]

    /// Random scenes scaled by 2^k, k from −20 to 20: valid, and the same
    /// disk count and porosity as at scale 1.
    #[test]
    fn random_scenes_scaled_by_powers_of_two_pack_alike(spec in spec_strategy(), k in -20i32..=20) {
        let what = format!("{spec:?} × 2^{k}");
        let unit = valid_packing(&spec.scene(1.0, (0.0, 0.0)), &what);
        let scaled = valid_packing(&spec.scene(2f64.powi(k), (0.0, 0.0)), &what);
        assert_alike(&unit, &scaled, &what);
    }

    /// Random scenes scaled by 10^k, k from −6 to 6, and moved anywhere up
    /// to 3·10⁵ diameters away (to within the config's resolution limit,
    /// `RESOLUTION_REL`, for the smallest disks here): valid.
    #[test]
    fn random_scenes_at_any_scale_and_place_are_valid(
        spec in spec_strategy(),
        k in -6i32..=6,
        o in prop_oneof![Just((0.0, 0.0)), (-3e5..3e5f64, -3e5..3e5f64)],
    ) {
        let mut spec = spec;
        spec.shape = spec.shape.movable();
        let s = 10f64.powi(k);
        let scene = spec.scene(s, (o.0 * s, o.1 * s));
        valid_packing(&scene, &format!("{spec:?} × 1e{k} at {o:?}"));
    }
}
