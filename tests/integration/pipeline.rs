//! The whole pipeline on random config texts (proptest): TOML text →
//! `config::parse` → `pack` → `measure` → `check::check`.
//!
//! The texts are well-formed but otherwise random: every shape (rectangle,
//! circle, polygons including non-convex L shapes, thin strips and sliver
//! wedges, trapezoids, fractures with and without a tapered tip), every way
//! to give a grading (constant, uniform, tables with steps and gaps, the
//! proppant presets, both interpolations and all bases), both wall models and
//! every packer setting, sized to hold at most about 3000 disks. A text may
//! still describe a scene that cannot be packed (a sliver narrower than the
//! smallest disk): then the config or the packer must say so with a typed
//! error.
//!
//! What must hold for every text: parsing never panics; a config that parses
//! packs or returns a typed error, never panics, within [`TIME_CAP`]; the
//! packing is valid by the independent check (no overlap beyond
//! [`OVERLAP_REL`] of the radii sum, nothing outside), relaxation aside (it
//! reports the overlap it leaves); and the summary figures of `measure`
//! agree with the check's (particle count, porosity to 1e-12).
//!
//! The texts drawn are the same on every run (a fixed seed);
//! `PROPTEST_RNG_SEED=N cargo test --test integration pipeline::` explores others.

use crate::common;

use std::fmt::Write as _;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use gapack::OVERLAP_REL;
use gapack::check;
use gapack::{Basis, Grading, Interpolation, Method, measure, pack};
use proptest::prelude::*;
use proptest::test_runner::{RngSeed, TestRunner};

/// Longest a scene of at most ~3000 disks may take to pack and measure.
const TIME_CAP: Duration = Duration::from_secs(20);

/// Most disks a scene is sized for (domain area / mean disk area, solid).
const MAX_DISKS: f64 = 3000.0;

/// The texts drawn: the same on every run, so that CI is repeatable.
fn rng_seed() -> RngSeed {
    common::rng_seed(0x7069_7065_6C69_6E65)
}

/// A `[grading]` as written, and the curve it gives (for sizing the domain).
#[derive(Debug, Clone)]
struct GradingText {
    text: String,
    /// Mean disk area by number (mm²) and the smallest and largest diameters.
    mean_area: f64,
    d_min: f64,
    d_max: f64,
}

fn interpolation_name(i: Interpolation) -> &'static str {
    match i {
        Interpolation::Log => "log",
        Interpolation::Linear => "linear",
    }
}

fn basis_name(b: Basis) -> &'static str {
    match b {
        Basis::Number => "number",
        Basis::Mass => "mass",
        Basis::Mass3d => "mass3d",
    }
}

fn interpolation() -> impl Strategy<Value = Option<Interpolation>> {
    prop_oneof![
        2 => Just(None),
        1 => Just(Some(Interpolation::Log)),
        1 => Just(Some(Interpolation::Linear)),
    ]
}

fn basis() -> impl Strategy<Value = Option<Basis>> {
    prop_oneof![
        3 => Just(None),
        1 => Just(Some(Basis::Number)),
        1 => Just(Some(Basis::Mass)),
        1 => Just(Some(Basis::Mass3d)),
    ]
}

/// The optional `interpolation` and `basis` lines.
fn curve_keys(i: Option<Interpolation>, b: Option<Basis>) -> String {
    let mut s = String::new();
    if let Some(i) = i {
        writeln!(s, "interpolation = \"{}\"", interpolation_name(i)).unwrap();
    }
    if let Some(b) = b {
        writeln!(s, "basis = \"{}\"", basis_name(b)).unwrap();
    }
    s
}

fn described(text: String, g: &Grading) -> GradingText {
    GradingText {
        text,
        mean_area: g.mean_disk_area(),
        d_min: g.d_min(),
        d_max: g.d_max(),
    }
}

fn grading() -> impl Strategy<Value = GradingText> {
    // Diameters around a scale from 0.01 to 10 mm.
    let scale = prop_oneof![4 => Just(1.0), 1 => Just(0.01), 1 => Just(0.1), 1 => Just(10.0)];
    prop_oneof![
        (0.3..3.0f64, scale.clone()).prop_map(|(d, s)| {
            let d = d * s;
            let g = Grading::constant(d).unwrap();
            described(format!("[grading]\nconstant = {d:?}\n"), &g)
        }),
        (0.3..2.0f64, 1.0..8.0f64, basis(), scale.clone()).prop_map(|(a, k, b, s)| {
            let (a, hi) = (a * s, a * k * s);
            let g = Grading::uniform(a, hi, b.unwrap_or_default()).unwrap();
            let text = format!(
                "[grading]\nuniform = [{a:?}, {hi:?}]\n{}",
                curve_keys(None, b)
            );
            described(text, &g)
        }),
        // Tables: rising diameters with repeats (steps, atoms of the
        // distribution) and flat percents (gaps with no particles).
        (
            0.3..1.5f64,
            prop::collection::vec(
                (0.0..1.0f64, any::<bool>(), 0.0..1.0f64, any::<bool>()),
                1..7
            ),
            interpolation(),
            basis(),
            scale.clone(),
        )
            .prop_map(|(d0, rows, i, b, s)| {
                let mut table = vec![(d0 * s, 0.0)];
                let (mut d, mut p) = (d0 * s, 0.0);
                let n = rows.len();
                for (k, &(grow, step, rise, flat)) in rows.iter().enumerate() {
                    if !step || k == 0 {
                        d *= 1.05 + 0.6 * grow;
                    }
                    if k + 1 == n {
                        p = 100.0;
                    } else if !flat {
                        p = (p + (100.0 - p) * rise * 0.7).min(100.0);
                    }
                    table.push((d, p));
                }
                let rows_text: Vec<String> = table
                    .iter()
                    .map(|(d, p)| format!("[{d:?}, {p:?}]"))
                    .collect();
                let text = format!(
                    "[grading]\ntable = [{}]\n{}",
                    rows_text.join(", "),
                    curve_keys(i, b)
                );
                let g = Grading::from_table(&table, i.unwrap_or_default(), b.unwrap_or_default())
                    .expect("a well-formed table");
                described(text, &g)
            }),
        (
            prop::sample::select(Grading::preset_names()),
            interpolation(),
            basis()
        )
            .prop_map(|(name, i, b)| {
                let g =
                    Grading::preset(name, i.unwrap_or_default(), b.unwrap_or_default()).unwrap();
                let text = format!("[grading]\npreset = \"{name}\"\n{}", curve_keys(i, b));
                described(text, &g)
            }),
    ]
}

/// The shape of the place to fill, its size left to the grading.
#[derive(Debug, Clone)]
enum ShapeSpec {
    Rectangle {
        aspect: f64,
    },
    Circle {
        center: (f64, f64),
    },
    Trapezoid {
        aspect: f64,
        top_ratio: f64,
    },
    /// An L: outer square, arms `arm` of its side wide, rotated and moved.
    L {
        arm: f64,
        turn: f64,
        offset: (f64, f64),
    },
    /// A long thin quadrilateral: height `h0` at one end, `h1` at the other
    /// (in d_max; below 1, the smallest sizes may not fit).
    Strip {
        h0: f64,
        h1: f64,
        turn: f64,
    },
    /// A right triangle of small apex angle (degrees).
    Wedge {
        degrees: f64,
    },
    /// Star-shaped polygon, usually concave.
    Star {
        radii: Vec<f64>,
        jitter: Vec<f64>,
    },
    /// `[fracture]`: width in d_max (below 1, the smallest sizes may not
    /// fit), an optional tip width as a fraction of it.
    Fracture {
        width: f64,
        tip: Option<f64>,
    },
}

fn shape() -> impl Strategy<Value = ShapeSpec> {
    let turn = prop_oneof![Just(0.0), 0.0..std::f64::consts::TAU];
    let offset = prop_oneof![
        2 => Just((0.0, 0.0)),
        1 => (-1e3..1e3f64, -1e3..1e3f64),
        1 => (-1e5..1e5f64, -1e5..1e5f64),
    ];
    prop_oneof![
        3 => (0.1..10.0f64).prop_map(|aspect| ShapeSpec::Rectangle { aspect }),
        2 => offset.clone().prop_map(|center| ShapeSpec::Circle { center }),
        2 => (0.2..5.0f64, 0.02..3.0f64)
            .prop_map(|(aspect, top_ratio)| ShapeSpec::Trapezoid { aspect, top_ratio }),
        2 => (0.1..0.9f64, turn.clone(), offset)
            .prop_map(|(arm, turn, offset)| ShapeSpec::L { arm, turn, offset }),
        1 => (0.3..4.0f64, 0.3..4.0f64, turn)
            .prop_map(|(h0, h1, turn)| ShapeSpec::Strip { h0, h1, turn }),
        1 => (0.2..20.0f64).prop_map(|degrees| ShapeSpec::Wedge { degrees }),
        1 => (5usize..12).prop_flat_map(|n| (
                prop::collection::vec(0.5..1.0f64, n),
                prop::collection::vec(0.1..0.9f64, n),
            ))
            .prop_map(|(radii, jitter)| ShapeSpec::Star { radii, jitter }),
        2 => (0.5..8.0f64, prop::option::of(0.05..1.0f64))
            .prop_map(|(width, tip)| ShapeSpec::Fracture { width, tip }),
    ]
}

/// The `[domain]` (or `[fracture]`) for `shape` covering `area` mm², `d_max` the largest diameter.
fn place(shape: &ShapeSpec, area: f64, d_max: f64, walls: &str) -> String {
    let polygon = |v: Vec<(f64, f64)>| {
        let rows: Vec<String> = v.iter().map(|(x, y)| format!("[{x:?}, {y:?}]")).collect();
        format!(
            "[domain]\nshape = \"polygon\"\nvertices = [{}]\n{walls}",
            rows.join(", ")
        )
    };
    let moved = |v: Vec<(f64, f64)>, turn: f64, (ox, oy): (f64, f64)| {
        let (s, c) = turn.sin_cos();
        v.into_iter()
            .map(|(x, y)| (ox + c * x - s * y, oy + s * x + c * y))
            .collect::<Vec<_>>()
    };
    match shape {
        ShapeSpec::Rectangle { aspect } => {
            let w = (area * aspect).sqrt();
            format!(
                "[domain]\nshape = \"rectangle\"\nwidth = {w:?}\nheight = {:?}\n{walls}",
                area / w
            )
        }
        ShapeSpec::Circle { center: (x, y) } => format!(
            "[domain]\nshape = \"circle\"\nradius = {:?}\ncenter = [{:?}, {:?}]\n{walls}",
            (area / std::f64::consts::PI).sqrt(),
            x * d_max,
            y * d_max
        ),
        ShapeSpec::Trapezoid { aspect, top_ratio } => {
            let bottom = (area * aspect).sqrt();
            let top = bottom * top_ratio;
            let height = 2.0 * area / (bottom + top);
            format!(
                "[domain]\nshape = \"trapezoid\"\nbottom = {bottom:?}\ntop = {top:?}\nheight = {height:?}\n{walls}"
            )
        }
        ShapeSpec::L { arm, turn, offset } => {
            let s = (area / (1.0 - (1.0 - arm) * (1.0 - arm))).sqrt();
            let a = arm * s;
            let v = vec![(0.0, 0.0), (s, 0.0), (s, a), (a, a), (a, s), (0.0, s)];
            polygon(moved(v, *turn, (offset.0 * d_max, offset.1 * d_max)))
        }
        ShapeSpec::Strip { h0, h1, turn } => {
            let (h0, h1) = (h0 * d_max, h1 * d_max);
            let len = 2.0 * area / (h0 + h1);
            let v = vec![(0.0, 0.0), (len, 0.0), (len, h1), (0.0, h0)];
            polygon(moved(v, *turn, (0.0, 0.0)))
        }
        ShapeSpec::Wedge { degrees } => {
            let t = degrees.to_radians().tan();
            let len = (2.0 * area / t).sqrt();
            polygon(vec![(0.0, 0.0), (len, 0.0), (len, len * t)])
        }
        ShapeSpec::Star { radii, jitter } => {
            let n = radii.len();
            let angles: Vec<f64> = (0..n)
                .map(|i| (i as f64 + jitter[i]) * std::f64::consts::TAU / n as f64)
                .collect();
            // Area of the star with unit scale, then scaled to `area`.
            let unit: Vec<(f64, f64)> = angles
                .iter()
                .zip(radii)
                .map(|(a, r)| (r * a.cos(), r * a.sin()))
                .collect();
            let twice: f64 = (0..n)
                .map(|i| {
                    let (p, q) = (unit[i], unit[(i + 1) % n]);
                    p.0 * q.1 - q.0 * p.1
                })
                .sum();
            let k = (area / (0.5 * twice.abs())).sqrt();
            polygon(unit.into_iter().map(|(x, y)| (k * x, k * y)).collect())
        }
        ShapeSpec::Fracture { width, tip } => {
            let w = width * d_max;
            let tip_line = tip.map_or(String::new(), |t| {
                let tip = (t * w).max(1e-3 * w);
                let height = 2.0 * area / (w + tip);
                format!("tip_width_mm = {tip:?}\nheight_m = {:?}\n", height / 1000.0)
            });
            let height = if tip.is_none() {
                format!("height_m = {:?}\n", area / w / 1000.0)
            } else {
                String::new()
            };
            format!("[fracture]\nwidth_mm = {w:?}\n{height}{tip_line}{walls}")
        }
    }
}

/// `[packer]` settings as written; `None` leaves the table out.
#[derive(Debug, Clone)]
struct PackerText {
    text: Option<String>,
    method: Method,
}

fn packer() -> impl Strategy<Value = PackerText> {
    let method = prop_oneof![
        10 => Just(Method::AdvancingFront),
        2 => Just(Method::Rsa),
        2 => Just(Method::Deposition),
        1 => Just(Method::Relaxation),
        1 => Just(Method::Densify),
    ];
    (
        any::<bool>(),
        method,
        prop::option::of(prop_oneof![Just("mx-quadtree"), Just("grid")]),
        // Contacts: as `contacts`, as a share, or not given.
        prop_oneof![
            Just(String::new()),
            Just("contacts = 2\n".to_owned()),
            Just("contacts = 1\n".to_owned()),
            (0.0..=1.0f64).prop_map(|s| format!("one_contact_share = {s:?}\n")),
        ],
        prop::option::of(0.0..=gapack::MAX_GAP),
        prop::option::of(0..=gapack::MAX_DEFERRED),
        prop::option::of(prop_oneof![Just("robust"), Just("thesis")]),
        prop::option::of(prop_oneof![Just("up"), Just("right")]),
        (100i64..3000, 0.0..0.5f64, 20i64..300),
    )
        .prop_map(
            |(
                table,
                method,
                index,
                contacts,
                gap,
                max_deferred,
                rules,
                fill,
                (attempts, porosity, iterations),
            )| {
                let method_name = match method {
                    Method::AdvancingFront => "advancing-front",
                    Method::Rsa => "rsa",
                    Method::Deposition => "deposition",
                    Method::Relaxation => "relaxation",
                    Method::Densify => "densify",
                };
                if !table && method == Method::AdvancingFront {
                    return PackerText { text: None, method };
                }
                let mut s = format!("[packer]\nmethod = \"{method_name}\"\n");
                if let Some(i) = index {
                    writeln!(s, "index = \"{i}\"").unwrap();
                }
                s.push_str(&contacts);
                if let Some(g) = gap {
                    writeln!(s, "gap = {g:?}").unwrap();
                }
                if let Some(m) = max_deferred {
                    writeln!(s, "max_deferred = {m}").unwrap();
                }
                if let Some(r) = rules {
                    writeln!(s, "rules = \"{r}\"").unwrap();
                }
                if let Some(f) = fill {
                    writeln!(s, "fill = \"{f}\"").unwrap();
                }
                match method {
                    Method::Rsa => writeln!(s, "attempts = {attempts}").unwrap(),
                    Method::Relaxation => writeln!(
                        s,
                        "relaxation_porosity = {porosity:?}\nrelaxation_iterations = {iterations}"
                    )
                    .unwrap(),
                    Method::Densify => writeln!(
                        s,
                        "densify_porosity = {:?}\ndensify_iterations = {}",
                        0.2 + 0.4 * porosity,
                        iterations * 1000
                    )
                    .unwrap(),
                    _ => {}
                }
                PackerText {
                    text: Some(s),
                    method,
                }
            },
        )
}

/// A whole config text and what it was made for.
#[derive(Debug, Clone)]
struct ConfigText {
    text: String,
    method: Method,
}

fn config() -> impl Strategy<Value = ConfigText> {
    (
        grading(),
        shape(),
        // Disks the domain would hold solid: from a handful to the cap.
        prop_oneof![1 => 2.0..40.0f64, 3 => 40.0..MAX_DISKS],
        // Wall model: default, exact, disks, disks of a given fraction of d_min.
        prop_oneof![
            3 => Just((None, None)),
            2 => Just((Some("exact"), None)),
            2 => Just((Some("disks"), None)),
            1 => (0.02..0.5f64).prop_map(|f| (Some("disks"), Some(f))),
        ],
        packer(),
        prop::option::of(any::<u64>()),
    )
        .prop_map(|(g, shape, disks, walls, packer, seed)| {
            let mut walls_text = String::new();
            if let Some(mode) = walls.0 {
                writeln!(walls_text, "walls = \"{mode}\"").unwrap();
            }
            if let Some(f) = walls.1 {
                writeln!(walls_text, "wall_disk = {:?}", f * g.d_min).unwrap();
            }
            let area = disks * g.mean_area;
            let mut text = String::new();
            if let Some(seed) = seed {
                writeln!(text, "seed = {seed}").unwrap();
            }
            text.push_str(&place(&shape, area, g.d_max, &walls_text));
            text.push_str(&g.text);
            if let Some(p) = &packer.text {
                text.push_str(p);
            }
            ConfigText {
                text,
                method: packer.method,
            }
        })
}

/// What one packing of a config gave: its check against its measure, or the typed error.
type Outcome = Result<(gapack::Check, gapack::Metrics), gapack::PackError>;

/// Pack and measure `scene` on a thread; `None` if it took longer than [`TIME_CAP`].
fn pack_in_time(scene: gapack::Scene) -> Option<std::thread::Result<Outcome>> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let result = std::panic::catch_unwind(|| {
            pack(&scene).map(|p| {
                let m = measure(&p, &scene);
                (check(&p.disks, &p.domain, None), m)
            })
        });
        let _ = tx.send(result);
    });
    rx.recv_timeout(TIME_CAP).ok()
}

/// Texts each run draws.
const CASES: u32 = 200;

/// What became of the texts drawn.
static PACKED: AtomicUsize = AtomicUsize::new(0);
static REFUSED_BY_CONFIG: AtomicUsize = AtomicUsize::new(0);
static REFUSED_BY_PACKER: AtomicUsize = AtomicUsize::new(0);

#[test]
fn config_text_parses_packs_and_checks() {
    let mut runner = TestRunner::new(ProptestConfig {
        cases: CASES,
        rng_seed: rng_seed(),
        ..ProptestConfig::default()
    });
    if let Err(e) = runner.run(&config(), one_text) {
        panic!("{e}");
    }
    let (packed, config, packer) = (
        PACKED.load(Ordering::Relaxed),
        REFUSED_BY_CONFIG.load(Ordering::Relaxed),
        REFUSED_BY_PACKER.load(Ordering::Relaxed),
    );
    eprintln!(
        "{CASES} config texts: {packed} packed and checked, {config} refused by the config, {packer} by the packer"
    );
    // A generator that only produced refusals would check nothing.
    assert!(packed as f64 >= 0.9 * CASES as f64, "only {packed} packed");
}

/// One text through parse, pack, measure and check.
fn one_text(config: ConfigText) -> Result<(), TestCaseError> {
    let parsed = gapack::config::parse(&config.text, "random.toml");
    let Ok(parsed) = parsed else {
        // A typed error with a place to act: nothing more to check.
        let e = parsed.unwrap_err();
        prop_assert!(e.to_string().starts_with("random.toml:"), "{e}");
        REFUSED_BY_CONFIG.fetch_add(1, Ordering::Relaxed);
        return Ok(());
    };
    prop_assert_eq!(parsed.scene.packer.method, config.method);
    let outcome = pack_in_time(parsed.scene.clone());
    let Some(outcome) = outcome else {
        return Err(TestCaseError::fail(format!(
            "no packing within {TIME_CAP:?}"
        )));
    };
    let Ok(outcome) = outcome else {
        return Err(TestCaseError::fail("the packer panicked"));
    };
    let (c, m) = match outcome {
        Ok(pair) => pair,
        // A typed refusal (a domain no disk fits): nothing to check.
        Err(e) => {
            prop_assert!(!e.to_string().is_empty());
            REFUSED_BY_PACKER.fetch_add(1, Ordering::Relaxed);
            return Ok(());
        }
    };
    prop_assert_eq!(c.particles, m.particles);
    prop_assert!(
        (c.porosity - m.porosity).abs() <= 1e-12,
        "porosity: check {} vs measure {}",
        c.porosity,
        m.porosity
    );
    if config.method != Method::Relaxation {
        prop_assert!(c.valid(), "{c:?}");
        prop_assert!(
            m.max_overlap <= OVERLAP_REL,
            "measured overlap {}",
            m.max_overlap
        );
    }
    PACKED.fetch_add(1, Ordering::Relaxed);
    Ok(())
}
