//! Every config shipped in `configs/` runs, so none rots: each one names its
//! command in a `# Run: cargo run --release -- <command> configs/<file>`
//! line; the test runs that command, then checks every packing it wrote with
//! `gapack verify` (an independent check of overlaps, containment and grading).

use crate::common;

use std::fs;
use std::path::{Path, PathBuf};

use common::{gapack, scratch};

/// The shipped configs, sorted.
fn shipped() -> Vec<PathBuf> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("configs");
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .expect("configs/ exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// The command of a config's `# Run:` line (`pack`, `optimise`, `layer`, `compare`, `sweep`).
fn command_of(path: &Path) -> String {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let text = fs::read_to_string(path).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("# Run: cargo run --release -- "))
        .unwrap_or_else(|| {
            panic!("{name} has no `# Run: cargo run --release -- <command> configs/{name}` line")
        });
    let words: Vec<&str> = line.split_whitespace().collect();
    // "#", "Run:", "cargo", "run", "--release", "--", command, path
    assert_eq!(
        words.get(7).copied(),
        Some(format!("configs/{name}").as_str()),
        "{name}: its Run line names another file: {line}"
    );
    words[6].to_owned()
}

/// Every `packing.csv` under `dir`, with the well it belongs to (its sub-directory in a batch).
fn packings(dir: &Path) -> Vec<(PathBuf, Option<String>)> {
    let mut found = Vec::new();
    if dir.join("packing.csv").exists() {
        found.push((dir.join("packing.csv"), None));
    }
    for entry in fs::read_dir(dir).unwrap() {
        let sub = entry.unwrap().path();
        if sub.join("packing.csv").exists() {
            let well = sub.file_name().unwrap().to_string_lossy().into_owned();
            found.push((sub.join("packing.csv"), Some(well)));
        }
    }
    found
}

#[test]
fn every_shipped_config_runs_and_its_packings_verify() {
    let configs = shipped();
    assert!(configs.len() >= 20, "only {} configs found", configs.len());
    let root = scratch("configs");
    for config in &configs {
        let name = config.file_stem().unwrap().to_string_lossy().into_owned();
        let command = command_of(config);
        let out = root.join(&name);
        let config_arg = config.to_str().unwrap();
        let run = gapack(
            &root,
            &[
                &command,
                config_arg,
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ],
        );
        assert!(
            run.status.success(),
            "gapack {command} {name}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        if command == "compare" {
            assert!(out.join("compare.csv").exists(), "{name}: no compare.csv");
            continue;
        }
        if command == "sweep" {
            // Every run of a shipped study finishes.
            let table = fs::read_to_string(out.join("sweep.csv"))
                .unwrap_or_else(|e| panic!("{name}: no sweep.csv: {e}"));
            let rows: Vec<&str> = table.lines().skip(1).collect();
            assert!(!rows.is_empty(), "{name}: an empty sweep.csv");
            for row in rows {
                assert!(row.ends_with(",finished"), "{name}: {row}");
            }
            continue;
        }
        assert!(out.join("summary.json").exists() || out.join("wells.csv").exists());
        let found = packings(&out);
        assert!(!found.is_empty(), "{name}: no packing.csv written");
        for (csv, well) in found {
            let mut args = vec!["verify", csv.to_str().unwrap(), "--config", config_arg];
            if let Some(w) = &well {
                args.extend(["--well", w]);
            }
            let verify = gapack(&root, &args);
            assert!(
                verify.status.success(),
                "gapack verify {name} {well:?}:\n{}{}",
                String::from_utf8_lossy(&verify.stdout),
                String::from_utf8_lossy(&verify.stderr)
            );
        }
    }
}
