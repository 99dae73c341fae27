//! Proppant packs for hydraulic fractures: `[fracture]` scenes, the thesis'
//! wells and fracture cell, representative windows, narrow and tapered
//! fractures, batches through the binary, and every bad input.

use crate::common;

use std::fs;
use std::path::Path;

use common::{gapack, refuses, scratch};
use gapack::OVERLAP_REL;
use gapack::Shape;
use gapack::config::{Config, parse};
use gapack::fracture::{Extent, settle};
use gapack::{Fill, Packing, Scene, measure, pack};

fn config(name: &str) -> Config {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("configs")
        .join(name);
    let text = fs::read_to_string(&path).expect("read config");
    parse(&text, name).unwrap_or_else(|e| panic!("{e}"))
}

/// Zero overlaps, every disk inside, no disk floating.
fn assert_valid(name: &str, packing: &Packing, scene: &Scene) {
    let m = measure(packing, scene);
    assert!(m.particles > 0, "{name}: empty");
    assert!(
        m.max_overlap <= OVERLAP_REL,
        "{name}: overlap {}",
        m.max_overlap
    );
    assert!(
        m.min_wall_clearance >= -OVERLAP_REL * scene.d_max(),
        "{name}: outside by {}",
        m.min_wall_clearance
    );
    assert_eq!(m.isolated, 0, "{name}: floating disks");
}

/// The thesis' wells (Tables 3.15–3.16), one row each.
fn thesis_wells() -> Vec<(String, f64, f64, usize, f64)> {
    include_str!("../data/thesis_wells.csv")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("well"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].to_owned(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[4].parse().unwrap(),
                f[5].parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn a_fracture_is_width_along_x_and_height_along_y_from_the_origin() {
    let c = config("narrow.toml");
    let run = c.fracture.expect("a fracture run");
    assert!(!run.batch);
    assert_eq!(run.extent, Extent::Full);
    assert_eq!(
        c.scene.domain.shape(),
        &Shape::Rectangle {
            width: 2.3,
            height: 1000.0
        }
    );
    assert_eq!(c.scene.domain.bounds().0, gapack::Point::new(0.0, 0.0));
}

/// The normalised cell W = (W_r + 2)·d_p by L = L_r·d_p is the thesis' 8.6 ×
/// 62.5 mm case: filled from one face it is the [domain] config's packing
/// mirrored, and its porosity is within 0.03 of the thesis' (0.224–0.227).
#[test]
fn the_normalised_cell_is_the_thesis_cell() {
    let cell = config("fracture_cell.toml");
    assert_eq!(
        cell.scene.domain.shape(),
        &Shape::Rectangle {
            width: (4.88 + 2.0) * 1.25,
            height: 50.0 * 1.25
        }
    );
    let a = pack(&cell.scene).unwrap();
    let b = pack(&config("thesis_fracture.toml").scene).unwrap();
    assert_eq!(a.disks.len(), b.disks.len());
    for (p, q) in a.disks.iter().zip(&b.disks) {
        assert_eq!((p.c.x, p.c.y, p.r), (q.c.y, q.c.x, q.r));
    }
    let phi = measure(&a, &cell.scene).porosity;
    assert!((phi - 0.225).abs() <= 0.03, "porosity {phi}");
}

/// The three wells with the thesis' set-up (disk walls): porosity within
/// ± 0.03 and disk count within 5 % of the thesis; the same wells with exact
/// walls are valid too. Then each well's window estimates its full pack's
/// porosity within 0.01 with at most half its disks.
#[test]
fn wells_match_the_thesis_and_windows_match_the_full_packs() {
    let thesis = thesis_wells();
    for name in ["wells.toml", "wells_exact.toml"] {
        let run = config(name).fracture.expect("a batch");
        assert!(run.batch);
        assert_eq!(run.wells.len(), 3);
        for (well, (t_name, width, height, t_disks, t_phi)) in run.wells.iter().zip(&thesis) {
            assert_eq!(&well.name, t_name);
            assert_eq!(well.fracture.width, *width);
            assert!((well.fracture.length - height * 1000.0).abs() < 1e-9);
            let full = pack(&well.scene).unwrap();
            assert_valid(&well.name, &full, &well.scene);
            let phi = measure(&full, &well.scene).porosity;
            if name == "wells.toml" {
                let disks = full.disks.len() as f64;
                println!(
                    "{}: {} disks (thesis {t_disks}), porosity {phi:.4} (thesis {t_phi})",
                    well.name,
                    full.disks.len()
                );
                assert!((phi - t_phi).abs() <= 0.03, "{}: porosity {phi}", well.name);
                assert!(
                    (disks / *t_disks as f64 - 1.0).abs() <= 0.05,
                    "{}: {disks} disks",
                    well.name
                );
            }
            let window = settle(well, 0.005, &gapack::Cancel::new()).unwrap();
            let last = window.last().unwrap();
            println!(
                "{name} {}: window {:.1} mm, porosity {:.4} ± {:.4} (full {phi:.4}), {} of {} disks",
                well.name,
                last.length,
                last.porosity,
                last.spread,
                last.particles,
                full.disks.len()
            );
            assert!(window.settled, "{}: not settled", well.name);
            assert!(
                (last.porosity - phi).abs() <= 0.01,
                "{}: window {} against full {phi}",
                well.name,
                last.porosity
            );
            assert!(last.particles * 2 < full.disks.len());
            assert_valid(&well.name, &window.packing, &window.scene);
        }
    }
}

/// 2.3 mm is less than two of the coarse 12/20 grains (2 d_max = 3.4 mm):
/// valid packs with either wall model and either fill, filled to the end.
#[test]
fn a_fracture_narrower_than_two_grains_packs_validly() {
    let c = config("narrow.toml");
    assert!(c.scene.domain.inradius() * 2.0 < 2.0 * c.scene.d_max());
    for walls in [gapack::WallMode::Exact, gapack::WallMode::Disks] {
        for fill in [Fill::Up, Fill::Right] {
            let mut scene = c.scene.clone();
            scene.walls = walls;
            scene.packer.fill = fill;
            let name = format!("{walls:?} {fill:?}");
            let p = pack(&scene).unwrap();
            assert_valid(&name, &p, &scene);
            let m = measure(&p, &scene);
            // A grain reaches the far end; no empty stretch of the slot.
            let top = p.disks.iter().map(|d| d.c.y + d.r).fold(0.0, f64::max);
            assert!(top > 1000.0 - 2.0 * scene.d_max(), "{name}: top at {top}");
            assert!(m.largest_hole < 2.3, "{name}: hole {}", m.largest_hole);
            assert!(m.psd_ks < 0.05, "{name}: KS {}", m.psd_ks);
        }
    }
}

/// A wedge wider at the wellbore than at the tip: a trapezoid with the wide
/// base at y = 0, packed validly, holding more proppant near the wellbore.
#[test]
fn a_tapered_fracture_is_a_trapezoid_packed_validly() {
    let c = config("tapered.toml");
    assert_eq!(
        c.scene.domain.shape(),
        &Shape::Trapezoid {
            bottom: 4.2,
            top: 0.6,
            height: 300.0
        }
    );
    let p = pack(&c.scene).unwrap();
    assert_valid("tapered", &p, &c.scene);
    let lower = p.disks.iter().filter(|d| d.c.y < 150.0).count();
    assert!(
        lower > 2 * (p.disks.len() - lower),
        "{lower} of {}",
        p.disks.len()
    );
    // Proppant reaches the tip, whose 0.6 mm aperture still takes the smallest grain.
    let top = p.disks.iter().map(|d| d.c.y).fold(0.0, f64::max);
    assert!(top > 300.0 - 5.0, "top disk at {top}");
}

/// A batch through the binary: one directory per well with its packing,
/// summary and window chart, and `wells.csv` with the contract's columns.
#[test]
fn a_batch_writes_wells_csv_and_one_directory_per_well() {
    let dir = scratch("wells-batch");
    let text = "seed = 2\n[fracture]\nextent = \"window\"\nwindow_tolerance = 0.01\nheight_m = 2.0\n\
        [[fracture.wells]]\nname = \"A-1\"\nwidth_mm = 2.6\n\
        [[fracture.wells]]\nname = \"B-2\"\nwidth_mm = 4.2\nheight_m = 1.5\n\
        [grading]\npreset = \"20/40\"\nbasis = \"mass\"\n";
    fs::write(dir.join("batch.toml"), text).unwrap();
    let out = gapack(&dir, &["pack", "batch.toml", "--out", "out"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(stdout.lines().count(), 3, "{stdout}");
    let table = fs::read_to_string(dir.join("out/wells.csv")).unwrap();
    let mut lines = table.lines();
    assert_eq!(
        lines.next(),
        Some("well,width_mm,height_m,particles,porosity,psd_ks,coordination,seconds")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0][..3], ["A-1", "2.6", "2"]);
    assert_eq!(rows[1][..3], ["B-2", "4.2", "1.5"]);
    for (row, well) in rows.iter().zip(["A-1", "B-2"]) {
        let phi: f64 = row[4].parse().unwrap();
        assert!(phi > 0.1 && phi < 0.5, "{well}: porosity {phi}");
        let well_dir = dir.join("out").join(well);
        for file in [
            "packing.csv",
            "summary.json",
            "packing.svg",
            "window.csv",
            "window.svg",
        ] {
            assert!(well_dir.join(file).is_file(), "{well}: no {file}");
        }
        let png = fs::read(well_dir.join("window.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let summary = fs::read_to_string(well_dir.join("summary.json")).unwrap();
        assert!(summary.contains("\"extent\": \"window\""), "{summary}");
        assert!(summary.contains("\"length_fraction\""), "{summary}");
        let disks = fs::read_to_string(well_dir.join("packing.csv"))
            .unwrap()
            .lines()
            .count()
            - 1;
        assert_eq!(row[3], disks.to_string(), "{well}: particles");
    }
    let _ = fs::remove_dir_all(&dir);
}

/// One full fracture may be optimised like any domain; its summary names the fracture.
#[test]
fn a_single_fracture_can_be_optimised() {
    let dir = scratch("fracture-optimise");
    let text = "seed = 1\n[fracture]\nwidth_mm = 4.2\nheight_m = 0.05\n\
        [grading]\npreset = \"20/40\"\n[optimise]\ntarget_porosity = 0.3\n";
    fs::write(dir.join("f.toml"), text).unwrap();
    let out = gapack(&dir, &["optimise", "f.toml", "--out", "out"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = fs::read_to_string(dir.join("out/summary.json")).unwrap();
    assert!(summary.contains("\"fracture\": {"), "{summary}");
    assert!(summary.contains("\"width_mm\": 4.2"), "{summary}");
    assert!(
        summary.contains("\"stop\": \"target reached\""),
        "{summary}"
    );
    let _ = fs::remove_dir_all(&dir);
}

fn fracture(keys: &str, grading: &str) -> String {
    format!("[fracture]\n{keys}\n[grading]\n{grading}\n")
}

const TABLE_3_4: &str = "preset = \"20/40\"";

#[test]
fn refuses_bad_fracture_sizes() {
    refuses(
        "zero-width",
        &fracture("width_mm = 0\nheight_m = 8", TABLE_3_4),
        "fracture.width_mm",
        "2:12",
    );
    refuses(
        "negative-height",
        &fracture("width_mm = 2.6\nheight_m = -8", TABLE_3_4),
        "fracture.height_m",
        "3:12",
    );
    refuses(
        "well-zero-width",
        &fracture(
            "[[fracture.wells]]\nname = \"w\"\nwidth_mm = 0.0\nheight_m = 1",
            TABLE_3_4,
        ),
        "fracture.wells[0].width_mm",
        "4:12",
    );
}

#[test]
fn refuses_a_fracture_narrower_than_the_smallest_grain() {
    // 20/40 mesh: 0.425–0.850 mm.
    refuses(
        "narrower-than-grain",
        &fracture("width_mm = 0.4\nheight_m = 1", TABLE_3_4),
        "fracture.width_mm",
        "2:12",
    );
}

#[test]
fn refuses_both_forms() {
    refuses(
        "both-forms",
        &fracture(
            "width_mm = 8.6\nheight_m = 0.0625\nwidth_ratio = 4.88",
            TABLE_3_4,
        ),
        "fracture.width_ratio",
        "4:15",
    );
    refuses(
        "incomplete-normalised",
        &fracture("width_ratio = 4.88\nlength_ratio = 50", TABLE_3_4),
        "fracture.mean_diameter",
        "1:1",
    );
}

#[test]
fn refuses_unknown_preset() {
    refuses(
        "unknown-preset",
        &fracture("width_mm = 2.6\nheight_m = 8", "preset = \"20/45\""),
        "grading.preset",
        "5:10",
    );
}

#[test]
fn refuses_inconsistent_fracture_tables() {
    refuses(
        "tip-wider",
        &fracture("width_mm = 2\ntip_width_mm = 3\nheight_m = 1", TABLE_3_4),
        "fracture.tip_width_mm",
        "3:16",
    );
    refuses(
        "window-tapered",
        &fracture(
            "width_mm = 2\ntip_width_mm = 1\nheight_m = 1\nextent = \"window\"",
            TABLE_3_4,
        ),
        "fracture.extent",
        "5:10",
    );
    refuses(
        "unknown-extent",
        &fracture("width_mm = 2\nheight_m = 1\nextent = \"half\"", TABLE_3_4),
        "fracture.extent",
        "4:10",
    );
    refuses(
        "domain-and-fracture",
        &format!(
            "[domain]\nshape = \"rectangle\"\nwidth = 2\nheight = 2\n{}",
            fracture("width_mm = 2\nheight_m = 1", TABLE_3_4)
        ),
        "domain",
        "1:1",
    );
    refuses(
        "twice-named",
        &fracture(
            "height_m = 1\nwidth_mm = 2\n[[fracture.wells]]\nname = \"w\"\n[[fracture.wells]]\nname = \"w\"",
            TABLE_3_4,
        ),
        "fracture.wells[1].name",
        "7:8",
    );
    refuses(
        "path-name",
        &fracture(
            "height_m = 1\nwidth_mm = 2\n[[fracture.wells]]\nname = \"../w\"",
            TABLE_3_4,
        ),
        "fracture.wells[0].name",
        "5:8",
    );
    refuses(
        "well-without-height",
        &fracture("[[fracture.wells]]\nname = \"w\"\nwidth_mm = 2", TABLE_3_4),
        "fracture.wells[0].height_m",
        "2:1",
    );
    refuses(
        "batch-optimise",
        &format!(
            "{}[optimise]\ntarget_porosity = 0.3\n",
            fracture(
                "[[fracture.wells]]\nname = \"w\"\nwidth_mm = 2\nheight_m = 0.1",
                TABLE_3_4
            )
        ),
        "optimise",
        "8:1",
    );
}
