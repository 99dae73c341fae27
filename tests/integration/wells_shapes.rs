//! Wells of shaped proppant through the binary: `configs/wells_shapes.toml`
//! (a `[shape]` preset in a batch of windows) writes the shape columns of
//! `wells.csv` and of each well's `packing.csv`, measures what the preset
//! asks, verifies, and packs the same bytes again; a preset beside the keys
//! of an outline is refused at the key.

use crate::common;

use std::fs;
use std::path::Path;

use common::{gapack, refuses, scratch};

/// The shipped config of shaped wells.
fn shipped() -> String {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("configs/wells_shapes.toml")
        .to_string_lossy()
        .into_owned()
}

/// The value of `column` in each row of a CSV `table`.
fn column(table: &str, column: &str) -> Vec<String> {
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let at = header
        .iter()
        .position(|h| *h == column)
        .unwrap_or_else(|| panic!("no column {column} in {header:?}"));
    lines
        .map(|l| l.split(',').nth(at).expect("a full row").to_owned())
        .collect()
}

#[test]
fn a_batch_of_shaped_wells_gives_the_shapes_and_verifies() {
    let dir = scratch("wells-shapes");
    let config = shipped();
    let run = gapack(&dir, &["pack", &config, "--out", "out", "--quiet"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = dir.join("out");
    let table = fs::read_to_string(out.join("wells.csv")).expect("wells.csv");
    assert!(
        table.starts_with("well,width_mm,height_m,particles,porosity,psd_ks,coordination,seconds,aspect_mean,sphericity_mean,roundness_mean,fabric_anisotropy\n"),
        "{table}"
    );
    let wells = column(&table, "well");
    assert_eq!(wells, ["7-CP-0370-SE", "7-CP-0037-SE"]);
    let number = |name: &str| -> Vec<f64> {
        column(&table, name)
            .iter()
            .map(|v| v.parse().expect("a number"))
            .collect()
    };
    // The ceramic preset is made to sphericity and roundness 0.9.
    for (s, r) in number("sphericity_mean")
        .into_iter()
        .zip(number("roundness_mean"))
    {
        assert!((s - 0.9).abs() <= 0.05, "sphericity {s}");
        assert!((r - 0.9).abs() <= 0.05, "roundness {r}");
    }
    for a in number("aspect_mean") {
        assert!((1.1..=1.35).contains(&a), "aspect {a}");
    }
    // Turned at random: no strong preferred direction.
    for f in number("fabric_anisotropy") {
        assert!((0.0..0.3).contains(&f), "anisotropy {f}");
    }
    // Porosity and coordination of a pack, measured on the outlines:
    // the particles touch (area-equivalent disks of ellipses would not).
    for (p, c) in number("porosity").into_iter().zip(number("coordination")) {
        assert!((0.15..0.5).contains(&p), "porosity {p}");
        assert!((1.5..5.0).contains(&c), "coordination {c}");
    }
    for well in &wells {
        let packing = out.join(well).join("packing.csv");
        let text = fs::read_to_string(&packing).expect("packing.csv");
        assert!(
            text.starts_with("id,x,y,r,angle,a,b,alpha,beta\n"),
            "{well}: {}",
            text.lines().next().unwrap_or("")
        );
        let summary = fs::read_to_string(out.join(well).join("summary.json")).expect("summary");
        assert!(summary.contains("\"particle_shape\""), "{well}");
        assert!(summary.contains("\"extent\": \"window\""), "{well}");
        let verify = gapack(
            &out,
            &[
                "verify",
                packing.to_str().expect("a path"),
                "--config",
                &config,
                "--well",
                well,
            ],
        );
        let said = String::from_utf8_lossy(&verify.stdout);
        assert!(verify.status.success(), "{well}: {said}");
        assert!(said.contains("overlaps: none"), "{well}: {said}");
    }
    // The same config and seed, the same particles.
    let again = gapack(&dir, &["pack", &config, "--out", "again", "--quiet"]);
    assert!(again.status.success());
    for well in &wells {
        let a = fs::read(out.join(well).join("packing.csv")).expect("first");
        let b = fs::read(dir.join("again").join(well).join("packing.csv")).expect("second");
        assert!(a == b, "{well}: packed differently the second time");
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_preset_beside_an_outline_s_keys_is_refused_at_the_key() {
    let wells = "[fracture]\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 2.6\nheight_m = 0.05\n[grading]\nconstant = 1.2\n[shape]\npreset = \"ceramic\"\n";
    refuses(
        "wells-preset-aspect",
        &format!("{wells}aspect = 1.5\n"),
        "shape.aspect",
        "10:10",
    );
    refuses(
        "wells-preset-unknown",
        &wells.replace("\"ceramic\"", "\"glass\""),
        "shape.preset",
        "9:10",
    );
    refuses(
        "wells-shape-fill-right",
        &wells.replace("height_m = 0.05\n", "height_m = 0.05\nfill = \"right\"\n"),
        "fracture.wells[0].fill",
        "6:8",
    );
}
