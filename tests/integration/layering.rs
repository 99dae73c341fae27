//! Functionally graded materials: profiles against their formulas, the GA
//! against the baseline it starts from, size-graded packing, determinism,
//! and bad `[layering]` input refused.

use crate::common;

use gapack::Cancel;
use std::fs;
use std::path::Path;

use common::{gapack, scratch};
use gapack::OVERLAP_REL;
use gapack::config;
use gapack::ga::lay_out;
use gapack::layering::{Axis, LayeringMode, Profile};
use gapack::{measure, pack};

fn shipped(name: &str) -> String {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("configs")
        .join(name);
    fs::read_to_string(path).expect("read shipped config")
}

/// Fractions of every profile kind add up to one at every s, and stay in [0, 1].
#[test]
fn every_profile_gives_fractions_that_add_up_to_one() {
    let profiles = [
        (Profile::Linear, 2),
        (Profile::Power(0.5), 2),
        (Profile::Power(3.0), 2),
        (Profile::Sigmoid(2.0), 2),
        (Profile::Steps(vec![(2, 0.2), (0, 0.3), (1, 0.5)]), 3),
        (
            Profile::Table(vec![
                (0.0, vec![1.0, 0.0, 0.0]),
                (0.4, vec![0.2, 0.5, 0.3]),
                (1.0, vec![0.0, 0.1, 0.9]),
            ]),
            3,
        ),
    ];
    for (profile, n) in profiles {
        profile.check(n).unwrap();
        let mut f = vec![0.0; n];
        for k in 0..=1000 {
            profile.fractions(k as f64 / 1000.0, &mut f);
            let sum: f64 = f.iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "{profile:?} at {k}: {sum}");
            assert!(
                f.iter().all(|x| (0.0..=1.0).contains(x)),
                "{profile:?}: {f:?}"
            );
        }
        for axis in [Axis::X, Axis::Y, Axis::Radial] {
            let t = profile.bin_targets(axis, 7, n);
            for bin in t.chunks(n) {
                assert!((bin.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            }
        }
    }
}

/// The thesis' MGF scenes and the 50 mm power-law and sigmoid plates: the GA
/// ends no worse than the baseline it starts from, and within RMS 0.03 of
/// the profile on the 50 mm scenes (10 bins).
#[test]
fn ga_is_never_worse_than_its_baseline_and_meets_the_goal() {
    println!("scene          disks  baseline RMS  GA RMS   evaluations");
    for name in ["mgf1", "mgf2", "mgf3", "fgm_power", "fgm_sigmoid"] {
        let cfg = config::parse(&shipped(&format!("{name}.toml")), name).unwrap();
        let settings = cfg.layering.expect("[layering]");
        let packing = pack(&cfg.scene).unwrap();
        let l = lay_out(
            &packing,
            &settings,
            cfg.materials.len(),
            cfg.scene.seed,
            &Cancel::new(),
            &gapack::farm::Local,
            |_| {},
        );
        println!(
            "{name:14} {:5}  {:.4}        {:.4}   {}",
            packing.disks.len(),
            l.baseline_rms,
            l.rms,
            l.evaluations
        );
        assert!(
            l.rms <= l.baseline_rms,
            "{name}: GA {} vs baseline {}",
            l.rms,
            l.baseline_rms
        );
        assert_eq!(l.assignment.len(), packing.disks.len());
        assert!((l.fractions.iter().sum::<f64>() - 1.0).abs() < 1e-9);
        if name.starts_with("fgm") {
            assert!(l.rms <= 0.03, "{name}: RMS {}", l.rms);
        }
    }
}

/// Size-graded packing follows its profile along the axis, each material
/// true to its own curve, with no overlap.
#[test]
fn size_graded_packing_follows_its_profile() {
    let cfg = config::parse(&shipped("fgm_sizes.toml"), "fgm_sizes").unwrap();
    let settings = cfg.layering.expect("[layering]");
    assert_eq!(settings.mode, LayeringMode::Sizes);
    for seed in 1..4 {
        let mut scene = cfg.scene.clone();
        scene.seed = seed;
        let packing = pack(&scene).unwrap();
        assert_eq!(packing.materials.len(), packing.disks.len());
        let l = lay_out(
            &packing,
            &settings,
            2,
            seed,
            &Cancel::new(),
            &gapack::farm::Local,
            |_| {},
        );
        let m = measure(&packing, &scene);
        println!(
            "seed {seed}: {} disks, RMS {:.4}, KS {:.3}",
            m.particles, l.rms, m.psd_ks
        );
        assert!(l.rms <= 0.05, "seed {seed}: RMS {}", l.rms);
        assert!(m.psd_ks <= 0.1, "seed {seed}: KS {}", m.psd_ks);
        assert!(m.max_overlap <= OVERLAP_REL);
        assert_eq!(m.isolated, 0);
    }
}

/// `gapack layer` on a size-graded config: `psd.svg` shows each material's
/// KS distance to its own curve and the whole packing's to the blend, the
/// very numbers `summary.json` records, and in its title the largest, which
/// is `psd_ks` (it showed 0.8711 against the coarse curve alone, the
/// summary 0.0826).
#[test]
fn size_graded_grading_chart_and_summary_agree() {
    let dir = scratch("layer-psd");
    fs::write(dir.join("fgm_sizes.toml"), shipped("fgm_sizes.toml")).unwrap();
    let out = gapack(&dir, &["layer", "fgm_sizes.toml", "--out", "out"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("out/summary.json")).unwrap()).unwrap();
    let svg = fs::read_to_string(dir.join("out/psd.svg")).unwrap();
    let lines: Vec<&str> = svg.lines().map(str::trim).collect();
    let by = summary["psd_ks_by_material"]
        .as_array()
        .expect("per material");
    let names: Vec<&str> = by.iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["coarse", "fine"]);
    let mut largest = 0.0f64;
    for m in by {
        let (name, ks) = (m["name"].as_str().unwrap(), m["ks"].as_f64().unwrap());
        largest = largest.max(ks);
        let shown = format!("KS {ks:.4}");
        assert!(
            lines
                .iter()
                .any(|l| l.starts_with(&format!("{name} packed,")) && l.ends_with(&shown)),
            "{name}: {shown} in the chart"
        );
    }
    let psd_ks = summary["psd_ks"].as_f64().unwrap();
    assert_eq!(psd_ks, largest);
    assert!(svg.contains(&format!("KS = {psd_ks:.4}")), "title");
    let blend = summary["psd_ks_blend"].as_f64().expect("blend");
    assert!(
        blend <= largest + 1e-12,
        "a blend is no farther than its worst part"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("packed, ") && l.ends_with(&format!("KS {blend:.4}")))
    );
    let _ = fs::remove_dir_all(&dir);
}

/// `gapack layer` writes the profile outputs; the same seed gives the same
/// bytes with 1 or 2 threads.
#[test]
fn layer_writes_its_outputs_identically_with_one_or_two_threads() {
    let dir = scratch("layer-threads");
    fs::write(dir.join("mgf3.toml"), shipped("mgf3.toml")).unwrap();
    let run = |threads| common::gapack_on_threads(&dir, &["layer", "mgf3.toml"], threads);
    let (one, two) = (run(1), run(2));
    for file in ["packing.csv", "profile.csv"] {
        assert_eq!(
            fs::read(one.join(file)).unwrap(),
            fs::read(two.join(file)).unwrap(),
            "{file}"
        );
    }
    let csv = fs::read_to_string(one.join("packing.csv")).unwrap();
    assert!(csv.starts_with("id,x,y,r,material\n0,"));
    assert!(csv.contains(",metal\n") && csv.contains(",cermet\n") && csv.contains(",ceramic\n"));
    let profile = fs::read_to_string(one.join("profile.csv")).unwrap();
    assert!(profile.starts_with(
        "bin,s,target_ceramic,target_cermet,target_metal,achieved_ceramic,achieved_cermet,achieved_metal\n"
    ));
    assert_eq!(&fs::read(one.join("profile.png")).unwrap()[..4], b"\x89PNG");
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(one.join("summary.json")).unwrap()).unwrap();
    assert!(
        summary["profile_rms_error"].as_f64().unwrap()
            <= summary["baseline_rms_error"].as_f64().unwrap()
    );
    assert_eq!(summary["materials"][2]["id"], 3);
    assert_eq!(summary["materials"][2]["properties"]["density"], 7800.0);
    let _ = fs::remove_dir_all(&dir);
}

/// Bad `[layering]` input: exit code 2, one line naming the key, nothing written.
#[test]
fn bad_layering_input_is_refused() {
    let mgf2 = shipped("mgf2.toml");
    let power = shipped("fgm_power.toml");
    let cases = [
        ("unknown-material", mgf2.replace(r#"["metal", 0.5]"#, r#"["steel", 0.5]"#), "layering.layers[0]"),
        ("thickness-sum", mgf2.replace(r#"["metal", 0.5]"#, r#"["metal", 0.4]"#), "layering.layers"),
        ("exponent-zero", power.replace("exponent = 2.0", "exponent = 0"), "layering.exponent"),
        ("exponent-negative", power.replace("exponent = 2.0", "exponent = -1"), "layering.exponent"),
        ("bins-zero", power.replace("bins = 10", "bins = 0"), "layering.bins"),
        ("bins-too-many", power.replace("bins = 10", "bins = 100000"), "layering.bins"),
        (
            "table-sum",
            power.replace("profile = \"power\"", "profile = \"table\"\ntable = [[0.0, 0.5, 0.4], [1.0, 0.0, 1.0]]").replace("exponent = 2.0\n", ""),
            "layering.table[0]",
        ),
        (
            "power-three-materials",
            shipped("mgf3.toml").replace("profile = \"steps\"", "profile = \"power\"\nexponent = 2").replace(
                "layers = [[\"metal\", 0.333333], [\"cermet\", 0.333334], [\"ceramic\", 0.333333]]\n",
                "",
            ),
            "layering.profile",
        ),
        ("no-materials", power.replace("[[materials]]\nname = \"ceramic\"\ndensity = 3900.0\n\n[[materials]]\nname = \"metal\"\ndensity = 7800.0\n", ""), "materials"),
        ("text-property", mgf2.replace("density = 7800.0", "density = \"heavy\""), "materials[1].density"),
        ("duplicate-name", mgf2.replace("name = \"metal\"", "name = \"ceramic\""), "materials[1].name"),
    ];
    for (name, text, key) in cases {
        let dir = scratch(&format!("layer-bad-{name}"));
        fs::write(dir.join("bad.toml"), &text).unwrap();
        let out = gapack(&dir, &["layer", "bad.toml"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        assert!(stderr.starts_with("error: bad.toml:"), "{name}: {stderr}");
        assert!(
            stderr.contains(&format!(": {key}: ")),
            "{name}: expected {key}: {stderr}"
        );
        assert!(!dir.join("out").exists(), "{name}: output written");
        let _ = fs::remove_dir_all(&dir);
    }
}

/// `[layering]` inside an `optimise` config: the porosity search runs as
/// without it, then the best packing's particles get their materials; the
/// grading check still covers every particle.
#[test]
fn optimise_lays_out_materials_on_its_best_packing() {
    let dir = scratch("optimise-layering");
    let ap3 = shipped("ap3.toml");
    let layering = "\n[[materials]]\nname = \"ceramic\"\n\n[[materials]]\nname = \"metal\"\n\n[layering]\naxis = \"y\"\nbins = 5\nprofile = \"linear\"\n";
    fs::write(dir.join("plain.toml"), &ap3).unwrap();
    fs::write(dir.join("layered.toml"), format!("{ap3}{layering}")).unwrap();
    for name in ["plain", "layered"] {
        let out = gapack(&dir, &["optimise", &format!("{name}.toml"), "--out", name]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let summary = |name: &str| -> serde_json::Value {
        serde_json::from_str(&fs::read_to_string(dir.join(name).join("summary.json")).unwrap())
            .unwrap()
    };
    let (plain, layered) = (summary("plain"), summary("layered"));
    for key in ["porosity", "psd_ks", "evaluations"] {
        assert_eq!(plain[key], layered[key], "{key}");
    }
    assert!(
        layered["profile_rms_error"].as_f64().unwrap()
            <= layered["baseline_rms_error"].as_f64().unwrap()
    );
    let read = |name: &str| fs::read_to_string(dir.join(name).join("packing.csv")).unwrap();
    let (layered_csv, plain_csv) = (read("layered"), read("plain"));
    let stripped: Vec<&str> = layered_csv
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0)
        .collect();
    assert_eq!(stripped, plain_csv.lines().collect::<Vec<_>>());
    assert!(dir.join("layered").join("profile.csv").exists());
    assert!(dir.join("layered").join("convergence.csv").exists());
    let _ = fs::remove_dir_all(&dir);
}
