//! Every config shipped in `configs/` runs, so none rots: each one names its
//! command in a `# Run: cargo run --release -- <command> configs/<file>`
//! line; the test runs that command, then checks every packing it wrote with
//! `gapack verify` (an independent check of overlaps, containment and grading).
//! The `packing.csv` of every shipped `pack` config of disks (no `[shape]`)
//! is also held to its recorded fingerprint in `tests/data/disk_packings.txt`:
//! disks pack byte for byte as they did. `GAPACK_BLESS=1` records them anew
//! (say why in the commit).

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

/// The recorded fingerprints of the disk packings.
fn fingerprints_file() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tests/data/disk_packings.txt")
}

/// FNV-1a (64 bits) of `bytes`: a fingerprint, not a defence.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
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
    found.sort();
    found
}

#[test]
fn every_shipped_config_runs_and_its_packings_verify() {
    let configs = shipped();
    assert!(configs.len() >= 20, "only {} configs found", configs.len());
    let root = scratch("configs");
    // `<config>[/<well>] <fingerprint>` per disk packing, in order.
    let mut fingerprints = Vec::new();
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
        let disks = command == "pack" && !fs::read_to_string(config).unwrap().contains("[shape]");
        for (csv, well) in found {
            if disks {
                let bytes = fs::read(&csv).unwrap();
                let label = well
                    .as_ref()
                    .map_or(name.clone(), |w| format!("{name}/{w}"));
                fingerprints.push(format!("{label} {:016x}", fnv1a(&bytes)));
            }
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
    let now = fingerprints.join("\n") + "\n";
    if std::env::var("GAPACK_BLESS").as_deref() == Ok("1") {
        fs::write(fingerprints_file(), &now).unwrap();
        return;
    }
    let recorded = fs::read_to_string(fingerprints_file()).unwrap();
    for (was, is) in recorded.lines().zip(now.lines()) {
        assert_eq!(was, is, "a disk packing changed (or the configs did)");
    }
    assert_eq!(recorded.lines().count(), now.lines().count(), "{now}");
}
