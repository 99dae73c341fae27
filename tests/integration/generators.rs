//! The comparison generators (random sequential addition, ballistic
//! deposition, relaxation): each one's invariants on many scenes.

use crate::common;

use gapack::OVERLAP_REL;
use gapack::{
    Domain, Grading, Method, PackerSettings, Point, Scene, WallMode, measure, pack, psd_ks,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

fn scene(domain: Domain, grading: Grading, walls: WallMode, method: Method, seed: u64) -> Scene {
    common::scene(domain, grading, walls, seed).with_packer(PackerSettings {
        method,
        attempts: 2000,
        ..PackerSettings::default()
    })
}

fn domains() -> Vec<(&'static str, Domain)> {
    let pts = |v: &[(f64, f64)]| v.iter().map(|&(x, y)| Point::new(x, y)).collect::<Vec<_>>();
    vec![
        ("rectangle", Domain::rectangle(30.0, 20.0).unwrap()),
        (
            "circle",
            Domain::circle(Point::new(0.0, 0.0), 12.0).unwrap(),
        ),
        ("trapezoid", Domain::trapezoid(30.0, 12.0, 15.0).unwrap()),
        (
            "l-shape",
            Domain::polygon(&pts(&[
                (0.0, 0.0),
                (24.0, 0.0),
                (24.0, 10.0),
                (10.0, 10.0),
                (10.0, 24.0),
                (0.0, 24.0),
            ]))
            .unwrap(),
        ),
    ]
}

/// Random sequential addition and deposition: no overlap, every disk
/// inside; deposition's disks all rest on something.
#[test]
fn rsa_and_deposition_leave_no_overlap_and_stay_inside() {
    for (name, domain) in domains() {
        for walls in [WallMode::Exact, WallMode::Disks] {
            for method in [Method::Rsa, Method::Deposition] {
                let s = scene(
                    domain.clone(),
                    Grading::uniform(1.0, 2.0, Default::default()).unwrap(),
                    walls,
                    method,
                    3,
                );
                let p = pack(&s).unwrap();
                let m = measure(&p, &s);
                let what = format!("{name} {walls:?} {method:?}");
                println!(
                    "{what}: {} disks, porosity {:.3}, KS {:.3}, coordination {:.2}",
                    m.particles, m.porosity, m.psd_ks, m.coordination
                );
                assert!(m.particles > 20, "{what}: {} disks", m.particles);
                assert!(
                    m.max_overlap <= OVERLAP_REL,
                    "{what}: overlap {}",
                    m.max_overlap
                );
                assert!(
                    m.min_wall_clearance >= -OVERLAP_REL * 2.0,
                    "{what}: outside"
                );
                if method == Method::Deposition {
                    assert_eq!(m.isolated, 0, "{what}: floating disks");
                    assert!(m.porosity < 0.4, "{what}: porosity {}", m.porosity);
                } else {
                    assert!(m.porosity > 0.4, "{what}: porosity {}", m.porosity);
                }
            }
        }
    }
}

/// The sizes placed follow the grading: every method draws them from the
/// curve in `pack`'s order (RSA and deposition place them in that order,
/// relaxation takes the first ones).
#[test]
fn every_method_honours_the_grading_on_a_large_domain() {
    for method in [Method::Rsa, Method::Deposition, Method::Relaxation] {
        let s = scene(
            Domain::rectangle(80.0, 80.0).unwrap(),
            Grading::uniform(1.0, 2.0, Default::default()).unwrap(),
            WallMode::Exact,
            method,
            1,
        );
        let p = pack(&s).unwrap();
        let ks = psd_ks(&p, &s);
        assert!(ks < 0.05, "{method:?}: KS {ks}");
    }
}

/// Relaxation reaches its porosity with the overlap it reports: the
/// residual falls as the target porosity rises, and is the metric's.
#[test]
fn relaxation_reports_its_residual_overlap() {
    let mut residuals = Vec::new();
    for porosity in [0.2, 0.35] {
        let mut s = scene(
            Domain::rectangle(30.0, 30.0).unwrap(),
            common::table_3_4(),
            WallMode::Exact,
            Method::Relaxation,
            2,
        );
        s.packer.relaxation.porosity = porosity;
        let p = pack(&s).unwrap();
        let m = measure(&p, &s);
        println!(
            "relaxation at {porosity}: {} disks, porosity {:.4}, max overlap {:.2e}, stats {:?}",
            m.particles, m.porosity, m.max_overlap, p.stats
        );
        assert!(
            (m.porosity - porosity).abs() < 0.02,
            "porosity {}",
            m.porosity
        );
        residuals.push(m.max_overlap);
    }
    assert!(residuals[1] <= s_tolerance() * 1.01, "{residuals:?}");
    assert!(residuals[0] > residuals[1], "{residuals:?}");
}

fn s_tolerance() -> f64 {
    PackerSettings::default().relaxation.tolerance
}

/// More attempts per disk place at least as many disks (the same sizes, in order).
#[test]
fn rsa_places_more_with_more_attempts() {
    let count = |attempts| {
        let mut s = scene(
            Domain::rectangle(62.5, 8.6).unwrap(),
            common::table_3_4(),
            WallMode::Exact,
            Method::Rsa,
            0,
        );
        s.packer.attempts = attempts;
        pack(&s).unwrap().disks.len()
    };
    let (few, many) = (count(200), count(20_000));
    assert!(many > few, "{few} then {many}");
}

#[test]
fn same_seed_same_packing_for_every_method() {
    for method in [Method::Rsa, Method::Deposition, Method::Relaxation] {
        let s = scene(
            Domain::rectangle(20.0, 20.0).unwrap(),
            common::table_3_4(),
            WallMode::Exact,
            method,
            5,
        );
        assert_eq!(pack(&s).unwrap(), pack(&s).unwrap(), "{method:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, rng_seed: RngSeed::Fixed(0x7273_6164), ..ProptestConfig::default() })]

    /// Random rectangles, circles and trapezoids, gradings up to 1:4, both
    /// wall models: RSA and deposition never overlap nor leave the domain.
    #[test]
    fn rsa_and_deposition_are_valid_on_random_scenes(
        w in 4.0..40.0f64,
        h in 4.0..40.0f64,
        shape in 0..3u8,
        d in 0.5..1.5f64,
        spread in 1.0..4.0f64,
        disks in any::<bool>(),
        deposition in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let domain = match shape {
            0 => Domain::rectangle(w, h).unwrap(),
            1 => Domain::circle(Point::new(0.0, 0.0), w / 2.0).unwrap(),
            _ => Domain::trapezoid(w, h / 2.0, h).unwrap(),
        };
        prop_assume!(2.0 * domain.inradius() > 2.0 * d * spread);
        let walls = if disks { WallMode::Disks } else { WallMode::Exact };
        let method = if deposition { Method::Deposition } else { Method::Rsa };
        let grading = Grading::uniform(d, d * spread, Default::default()).unwrap();
        let s = scene(domain, grading, walls, method, seed);
        let p = pack(&s).unwrap();
        let m = measure(&p, &s);
        prop_assert!(m.particles > 0);
        prop_assert!(m.max_overlap <= OVERLAP_REL, "overlap {}", m.max_overlap);
        prop_assert!(m.min_wall_clearance >= -OVERLAP_REL * d * spread, "outside by {}", m.min_wall_clearance);
        if deposition {
            prop_assert_eq!(m.isolated, 0);
        }
    }
}
