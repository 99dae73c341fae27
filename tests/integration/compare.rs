//! `gapack compare`: every generator on one scene, the table and the chart.

use crate::common;

use std::fs;

use common::{gapack, refuses, scratch};

const SCENE: &str = "seed = 4\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 12\n\
    [grading]\nuniform = [1.0, 1.5]\n[packer]\nattempts = 2000\nrelaxation_iterations = 300\n";

#[test]
fn compare_writes_one_row_per_run_and_the_chart() {
    let dir = scratch("compare");
    let text = format!("{SCENE}[optimise]\ntarget_porosity = 0.3\n[compare]\nrepeats = 2\n");
    fs::write(dir.join("c.toml"), text).unwrap();
    let out = gapack(&dir, &["compare", "c.toml", "--out", "out"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Seven variants (the advancing front four times) and the file line.
    assert_eq!(stdout.lines().count(), 8, "{stdout}");
    let table = fs::read_to_string(dir.join("out/compare.csv")).unwrap();
    let mut lines = table.lines();
    assert_eq!(
        lines.next(),
        Some(
            "method,seed,seconds,particles,porosity,target_error,psd_ks,max_overlap,coordination,local_porosity_std"
        )
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 14);
    for row in &rows {
        let porosity: f64 = row[4].parse().unwrap();
        let error: f64 = row[5].parse().unwrap();
        assert!((error - (porosity - 0.3).abs()).abs() < 1e-12, "{row:?}");
        let overlap: f64 = row[7].parse().unwrap();
        if !row[0].starts_with("relaxation") {
            assert!(overlap <= 1e-9, "{row:?}");
        }
    }
    let seeds: Vec<&str> = rows.iter().take(2).map(|r| r[1]).collect();
    assert_eq!(seeds, ["4", "5"]);
    let svg = fs::read_to_string(dir.join("out/compare.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("Pareto front"));
    let png = fs::read(dir.join("out/compare.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn compare_without_a_target_leaves_the_error_empty() {
    let dir = scratch("compare-no-target");
    let text = format!("{SCENE}[compare]\nmethods = [\"rsa\"]\nrepeats = 1\n");
    fs::write(dir.join("c.toml"), text).unwrap();
    let out = gapack(&dir, &["compare", "c.toml", "--out", "out", "--quiet"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    let table = fs::read_to_string(dir.join("out/compare.csv")).unwrap();
    let row: Vec<&str> = table.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[0], "rsa");
    assert_eq!(row[5], "");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn refuses_bad_compare_tables() {
    refuses(
        "compare-unknown",
        &format!("{SCENE}[compare]\nmethods = [\"rsa\", \"dem\"]\n"),
        "compare.methods[1]",
        "12:19",
    );
    refuses(
        "compare-twice",
        &format!("{SCENE}[compare]\nmethods = [\"rsa\", \"rsa\"]\n"),
        "compare.methods[1]",
        "12:19",
    );
    refuses(
        "compare-repeats",
        &format!("{SCENE}[compare]\nrepeats = 0\n"),
        "compare.repeats",
        "12:11",
    );
}

/// The scene of particle shapes: ellipses of aspect 1.5.
const SHAPES: &str = "seed = 4\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 12\n\
    [grading]\nuniform = [1.0, 1.5]\n[shape]\nkind = \"superellipse\"\naspect = 1.5\n";

#[test]
fn compare_with_shapes_runs_the_methods_that_pack_them() {
    let dir = scratch("compare-shapes");
    fs::write(
        dir.join("c.toml"),
        format!("{SHAPES}[compare]\nrepeats = 2\n"),
    )
    .unwrap();
    let out = gapack(&dir, &["compare", "c.toml", "--out", "out"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The advancing front four times and rsa; deposition and relaxation
    // pack disks only and are left out of the default methods.
    assert_eq!(stdout.lines().count(), 6, "{stdout}");
    let table = fs::read_to_string(dir.join("out/compare.csv")).unwrap();
    let rows: Vec<Vec<String>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    assert_eq!(rows.len(), 10);
    assert!(rows.iter().all(|r| r[7] == "0"), "{rows:?}");
    assert_eq!(rows[8][0], "rsa");
    let mean = |k: usize| {
        (rows[k][4].parse::<f64>().unwrap() + rows[k + 1][4].parse::<f64>().unwrap()) / 2.0
    };
    // One contact packs looser than two, rsa loosest.
    assert!(mean(0) < mean(4) && mean(4) < mean(8), "{rows:?}");
    // The first run is the pack of the scene, particle for particle.
    fs::write(dir.join("p.toml"), SHAPES).unwrap();
    let packed = gapack(&dir, &["pack", "p.toml", "--out", "p"]);
    let packed = String::from_utf8_lossy(&packed.stdout);
    assert!(
        packed.contains(&format!("{} particles", rows[0][3])),
        "{packed} vs {:?}",
        rows[0]
    );
    let _ = fs::remove_dir_all(&dir);
    refuses(
        "compare-shapes-deposition",
        &format!("{SHAPES}[compare]\nmethods = [\"rsa\", \"deposition\"]\n"),
        "compare.methods[1]",
        "12:19",
    );
}
