//! `gapack stability`: the whole sweep for one method, its table and its map.

use crate::common;

use std::fs;

use common::{gapack, scratch};

#[test]
fn the_sweep_finishes_within_its_caps_and_writes_its_table_and_map() {
    let dir = scratch("stability");
    let text = "seed = 1\n[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n\
        [grading]\nconstant = 1.0\n[packer]\nattempts = 200\n[compare]\nmethods = [\"rsa\"]\nrepeats = 2\n";
    fs::write(dir.join("s.toml"), text).unwrap();
    let out = gapack(
        &dir,
        &["stability", "s.toml", "--out", "out", "--time-cap", "20"],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.starts_with("rsa"), "{stdout}");
    // "pass P, fail F (overlap a, empty b, KS c[, empty + KS d]), refused R, timed out T":
    // each case counted once, so the parts add up.
    let line = stdout.lines().next().unwrap();
    let number = |after: &str| -> usize {
        let rest = &line[line.find(after).unwrap() + after.len()..];
        rest.trim_start()
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let fail = number("fail");
    let inside = &line[line.find('(').unwrap() + 1..line.find(')').unwrap()];
    let parts: usize = inside
        .split(", ")
        .map(|part| part.rsplit(' ').next().unwrap().parse::<usize>().unwrap())
        .sum();
    assert_eq!(parts, fail, "{line}");
    assert_eq!(
        number("pass") + fail + number("refused") + number("timed out"),
        288,
        "{line}"
    );
    let table = fs::read_to_string(dir.join("out/stability.csv")).unwrap();
    let mut lines = table.lines();
    assert_eq!(
        lines.next(),
        Some(
            "shape,ratio,width,method,seed,status,seconds,particles,empty,max_overlap,psd_ks,pass"
        )
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 4 shapes × 6 gradings × 6 widths, each with seeds 1 and 2 (repeats = 2).
    assert_eq!(rows.len(), 288);
    for seed in ["1", "2"] {
        assert_eq!(rows.iter().filter(|r| r[4] == seed).count(), 144, "{seed}");
    }
    for row in &rows {
        assert_eq!(row[5], "finished", "{row:?}");
        let seconds: f64 = row[6].parse().unwrap();
        assert!(seconds < 20.0, "{row:?}");
        let overlap: f64 = row[9].parse().unwrap();
        assert!(overlap <= 1e-9, "{row:?}");
    }
    assert!(rows.iter().any(|r| r[11] == "true"));
    // The pass rates with their spread over the seeds, per method and width.
    assert!(stdout.contains("per seed"), "{stdout}");
    assert!(stdout.contains("by width"), "{stdout}");
    let svg = fs::read_to_string(dir.join("out/stability.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("triangle-20deg"));
    let png = fs::read(dir.join("out/stability.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn refuses_a_time_cap_that_is_not_positive() {
    let dir = scratch("stability-cap");
    let out = gapack(&dir, &["stability", "none.toml", "--time-cap", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--time-cap"));
    assert!(!dir.join("out").exists());
}
