//! Invariants of every packing of particles that are not disks, over
//! random scenes (proptest): zero overlaps and every particle inside, as
//! the independent check proves them (`check_particles`), and no empty
//! region a largest particle would fit in, turned any way.

use crate::common;

use gapack::{
    Basis, Domain, Family, Grading, Method, Orientation, Outline, Packing, Point, Scene, ShapeSpec,
    SizeMeasure, Spread, WallMode, check_particles, pack, separation,
};
use proptest::prelude::*;
use proptest::test_runner::{RngSeed, TestCaseError};

/// The scenes drawn: the same on every run (see `packing_properties`).
fn rng_seed() -> RngSeed {
    common::rng_seed(0x7368_6170_6573)
}

/// Every domain shape: rectangle, L-shaped polygon, circle, trapezoid,
/// periodic cell, 9–16 mm across.
fn domain_strategy() -> impl Strategy<Value = Domain> {
    prop_oneof![
        (9.0..13.0f64, 9.0..13.0f64).prop_map(|(w, h)| Domain::rectangle(w, h).unwrap()),
        (11.0..14.0f64).prop_map(|s| {
            let v = [
                (0.0, 0.0),
                (s, 0.0),
                (s, s / 2.0),
                (s / 2.0, s / 2.0),
                (s / 2.0, s),
                (0.0, s),
            ];
            Domain::polygon(&v.map(|(x, y)| Point::new(x, y))).unwrap()
        }),
        (5.0..7.0f64).prop_map(|r| Domain::circle(Point::new(1.0, -2.0), r).unwrap()),
        (11.0..14.0f64, 5.0..9.0f64, 9.0..12.0f64)
            .prop_map(|(b, t, h)| Domain::trapezoid(b, t, h).unwrap()),
        (13.0..16.0f64, 13.0..16.0f64).prop_map(|(w, h)| Domain::periodic_rectangle(w, h).unwrap()),
    ]
}

/// Ellipses, superellipses (fixed or drawn parameters, rhombi to
/// near-rectangles) and rounded polygons, sized by sieve or area.
fn shape_strategy() -> impl Strategy<Value = ShapeSpec> {
    let polygons = (0.0..0.3f64, 0.0..0.2f64).prop_map(|(r1, r2)| {
        let triangle = [(0.0, 0.0), (2.0, 0.0), (0.7, 1.5)].map(|(x, y)| Point::new(x, y));
        let hexagon: Vec<Point> = (0..6)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 6.0;
                Point::new(1.6 * t.cos(), t.sin())
            })
            .collect();
        ShapeSpec {
            family: Family::Polygons {
                templates: vec![
                    (Outline::polygon(0, &triangle, r1).unwrap(), 0.5),
                    (Outline::polygon(1, &hexagon, r2).unwrap(), 0.5),
                ],
            },
            orientation: Orientation::Random,
            size: SizeMeasure::Sieve,
        }
    });
    prop_oneof![
        (1.0..5.0f64).prop_map(ShapeSpec::ellipses),
        (1.0..3.0f64, 1.0..10.0f64).prop_map(|(a, e)| ShapeSpec::superellipses(a, e)),
        Just(ShapeSpec {
            family: Family::Superellipse {
                aspect: Spread::Range(1.0, 3.0),
                alpha: Spread::Range(1.0, 6.0),
                beta: Spread::Range(1.0, 6.0),
            },
            orientation: Orientation::Aligned {
                mean: 0.3,
                spread: 0.5
            },
            size: SizeMeasure::Equivalent,
        }),
        polygons,
    ]
}

/// The three placement rules: the advancing front at two contacts, at one,
/// and random sequential addition.
#[derive(Debug, Clone, Copy)]
enum Rule {
    TwoContacts,
    OneContact,
    Rsa,
}

fn scene_strategy() -> impl Strategy<Value = (Scene, Rule)> {
    (
        domain_strategy(),
        shape_strategy(),
        prop_oneof![
            Just(Rule::TwoContacts),
            Just(Rule::OneContact),
            Just(Rule::Rsa)
        ],
        (0.8..1.2f64, 1.0..2.0f64),
        any::<u64>(),
    )
        .prop_map(|(domain, shape, rule, (lo, k), seed)| {
            let grading = Grading::uniform(lo, lo * k, Basis::Number).unwrap();
            let periodic = domain.is_periodic();
            let mut scene = Scene::new(domain, grading)
                .with_seed(seed)
                .with_shape(shape);
            if periodic {
                scene = scene.with_walls(WallMode::Periodic);
            }
            match rule {
                Rule::TwoContacts => scene.packer.one_contact_share = 0.0,
                Rule::OneContact => scene.packer.one_contact_share = 1.0,
                Rule::Rsa => {
                    scene = scene.with_method(Method::Rsa);
                    scene.packer.attempts = 3000;
                }
            }
            (scene, rule)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, rng_seed: rng_seed(), ..ProptestConfig::default() })]

    #[test]
    fn shape_packings_are_certified_and_leave_no_hole((scene, rule) in scene_strategy()) {
        certified_and_full(&scene, rule)?;
    }
}

/// The invariants of a packing of `scene`: particles, each with its grain,
/// no overlap and none outside as `check_particles` proves them, and no
/// empty disk wider than the largest particle's bounding circle.
fn certified_and_full(scene: &Scene, rule: Rule) -> Result<(), TestCaseError> {
    // A cell narrower than four bounding radii is refused, as documented.
    let packing = match pack(scene) {
        Err(gapack::PackError::PeriodicCellTooSmall { .. }) => return Ok(()),
        other => other.unwrap(),
    };
    prop_assert!(!packing.disks.is_empty());
    prop_assert_eq!(packing.grains.len(), packing.disks.len());
    let c = check_particles(&packing.disks, &packing.grains, &packing.domain, None);
    prop_assert!(c.valid(), "{:?}: {:?}", rule, c);
    prop_assert!(c.porosity > 0.0 && c.porosity < 1.0);
    let reach = packing
        .grains
        .iter()
        .map(|g| g.outline.circumradius())
        .fold(0.0, f64::max);
    let (at, hole) = largest_hole(&packing, reach);
    prop_assert!(
        hole <= 2.0 * reach,
        "{:?}: an empty disk of diameter {} mm at {:?}, the largest particle {} mm across",
        rule,
        hole,
        at,
        2.0 * reach
    );
    Ok(())
}

/// The largest empty disk among the particles (and walls) centred on a
/// grid of points 1/8 of the largest circumradius `reach` apart: its centre
/// and diameter, capped at 2·`reach` + one step (enough to tell a hole a
/// largest particle fits in).
///
/// # Behavior
/// At each grid point inside the domain, the distance to the nearest
/// particle (an upper bound from [`separation`] with the point; particles
/// whose bounding circles are farther are not asked) and, with walls, to
/// the boundary; in a periodic cell, to every particle's nearest image.
fn largest_hole(packing: &Packing, reach: f64) -> (Point, f64) {
    let domain = &packing.domain;
    let step = reach / 8.0;
    let cap = reach + step;
    let (lo, hi) = domain.bounds();
    let period = domain.period();
    let turned: Vec<_> = packing.grains.iter().map(|g| g.turned()).collect();
    let mut best = (lo, 0.0f64);
    let (nx, ny) = (
        ((hi.x - lo.x) / step).ceil() as usize,
        ((hi.y - lo.y) / step).ceil() as usize,
    );
    for j in 0..=ny {
        for i in 0..=nx {
            let p = Point::new(lo.x + step * i as f64, lo.y + step * j as f64);
            let mut empty = if period.is_some() {
                cap
            } else {
                domain.signed_distance(p).min(cap)
            };
            if empty <= best.1 {
                continue;
            }
            for (d, t) in packing.disks.iter().zip(&turned) {
                let mut off = p - d.c;
                if let Some(w) = period {
                    off.x -= w.x * (off.x / w.x).round();
                    off.y -= w.y * (off.y / w.y).round();
                }
                if off.norm() >= empty + reach {
                    continue;
                }
                let s = separation(off, 1e-9 * reach, |u| t.support_both(u));
                empty = empty.min(s.upper);
                if empty <= best.1 {
                    break;
                }
            }
            if empty > best.1 {
                best = (p, empty);
            }
        }
    }
    (best.0, 2.0 * best.1)
}

/// A packing of shapes and every file made of it, the same bytes with one
/// and two threads (the files are rendered on every thread): a small
/// square of ellipses with the exports that draw, measure and clump.
#[test]
fn shapes_give_the_same_files_on_one_or_two_threads() {
    let dir = common::scratch("shapes-threads");
    std::fs::write(
        dir.join("e.toml"),
        "seed = 4\n[domain]\nshape = \"rectangle\"\nwidth = 16\nheight = 16\n[grading]\nuniform = [1, 2]\n[shape]\nkind = \"superellipse\"\naspect = 1.8\n[output]\nformats = [\"csv\", \"json\", \"vtk\", \"lammps\", \"lammps-clumps\", \"liggghts-clumps\", \"yade\", \"pfc\", \"svg\", \"png\"]\n",
    )
    .unwrap();
    let run = |threads| common::gapack_on_threads(&dir, &["pack", "e.toml", "--quiet"], threads);
    let (one, two) = (run(1), run(2));
    let mut names: Vec<_> = std::fs::read_dir(&one)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.iter().any(|n| n == "orientation.png"), "{names:?}");
    // The JSON files hold the run's time: compared without it.
    let timeless = |bytes: Vec<u8>| -> Vec<u8> {
        String::from_utf8_lossy(&bytes)
            .lines()
            .filter(|l| !l.contains("\"seconds\"") && !l.contains("\"started\""))
            .collect::<Vec<_>>()
            .join("\n")
            .into_bytes()
    };
    for name in names {
        if name == "manifest.json" {
            continue;
        }
        let read = |dir: &std::path::Path| std::fs::read(dir.join(&name)).unwrap();
        let (a, b) = (read(&one), read(&two));
        let same = if name.to_string_lossy().ends_with(".json") {
            timeless(a) == timeless(b)
        } else {
            a == b
        };
        assert!(same, "{name:?} differs between one and two threads");
    }
}
