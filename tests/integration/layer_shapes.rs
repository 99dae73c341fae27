//! Layering with particle shapes: the shipped size-graded config of a round
//! matrix and elongated inclusions run by the layer job (each material's
//! particles of its own shape in packing.csv, `gapack verify` passing, the
//! profile followed), and a common `[shape]` laid out by the GA.

use crate::common;

use std::fs;
use std::path::Path;

use common::{gapack, scratch};

/// The path of a shipped config.
fn shipped(name: &str) -> String {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("configs")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// packing.csv's rows as (a, b, material), read by its header's names.
fn shapes_by_row(csv: &str) -> Vec<(f64, f64, String)> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let (a, b, m) = (col("a"), col("b"), col("material"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[a].parse().expect("a number"),
                f[b].parse().expect("a number"),
                f[m].to_owned(),
            )
        })
        .collect()
}

/// Run `gapack layer config --out dir` and `gapack verify` on its packing.
fn layer_and_verify(dir: &Path, config: &str) {
    let out = dir.to_str().unwrap();
    let run = gapack(dir, &["layer", config, "--out", out, "--quiet"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let csv = dir.join("packing.csv");
    let verify = gapack(dir, &["verify", csv.to_str().unwrap(), "--config", config]);
    assert!(
        verify.status.success(),
        "{}{}",
        String::from_utf8_lossy(&verify.stdout),
        String::from_utf8_lossy(&verify.stderr)
    );
}

#[test]
fn the_shipped_layer_shapes_config_packs_each_material_with_its_shape() {
    let dir = scratch("layer_shapes");
    layer_and_verify(&dir, &shipped("layer_shapes.toml"));
    let rows = shapes_by_row(&fs::read_to_string(dir.join("packing.csv")).unwrap());
    let (mut matrix, mut inclusions) = (0, 0);
    for (a, b, material) in &rows {
        match material.as_str() {
            "matrix" => {
                matrix += 1;
                assert!((a / b - 1.0).abs() < 1e-9, "a round matrix grain: {a} {b}");
            }
            "inclusions" => {
                inclusions += 1;
                let aspect = a / b;
                assert!(
                    (2.5 - 1e-9..=3.0 + 1e-9).contains(&aspect),
                    "an inclusion of aspect {aspect}"
                );
            }
            other => panic!("unknown material {other}"),
        }
    }
    assert!(matrix > 100 && inclusions > 50, "{matrix} {inclusions}");
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    // Measured 0.0257 (seed 1).
    let rms = summary["profile_rms_error"].as_f64().unwrap();
    assert!(rms < 0.05, "profile RMS {rms}");
    assert!(summary["particle_shape"]["particles"].as_u64() == Some(rows.len() as u64));
    let materials = summary["materials"].as_array().unwrap();
    let mean_aspect = |i: usize| materials[i]["particle_shape"]["aspect"]["mean"].as_f64();
    assert!((mean_aspect(0).unwrap() - 1.0).abs() < 1e-9);
    assert!((2.5..=3.0).contains(&mean_aspect(1).unwrap()));
}

#[test]
fn one_shape_for_all_materials_is_laid_out_by_the_ga() {
    let dir = scratch("layer_one_shape");
    let config = dir.join("one_shape.toml");
    fs::write(
        &config,
        "seed = 2\n[domain]\nshape = \"rectangle\"\nwidth = 25\nheight = 25\n\
         [grading]\nuniform = [1, 1.6]\n\
         [shape]\nkind = \"superellipse\"\naspect = 2\n\
         [[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n\
         [layering]\naxis = \"y\"\nbins = 5\nprofile = \"linear\"\npopulation = 16\ngenerations = 10\n",
    )
    .unwrap();
    layer_and_verify(&dir, config.to_str().unwrap());
    let rows = shapes_by_row(&fs::read_to_string(dir.join("packing.csv")).unwrap());
    assert!(rows.iter().all(|(a, b, _)| (a / b - 2.0).abs() < 1e-9));
    assert!(rows.iter().any(|r| r.2 == "a") && rows.iter().any(|r| r.2 == "b"));
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let (rms, baseline) = (
        summary["profile_rms_error"].as_f64().unwrap(),
        summary["baseline_rms_error"].as_f64().unwrap(),
    );
    assert!(rms <= baseline && rms < 0.1, "{rms} {baseline}");
}
