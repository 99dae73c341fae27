//! Scene builders shared by the integration tests.
#![allow(dead_code)]

pub mod json_edit;
pub mod postgres;
pub mod server;
pub mod stopped_search;
pub mod webdriver;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use gapack::{Domain, Grading, Scene, WallMode};
use proptest::test_runner::RngSeed;

/// The seed of a property test's draws: `default`, the same on every run so
/// that CI is repeatable, or `PROPTEST_RNG_SEED=N` to explore others.
pub fn rng_seed(default: u64) -> RngSeed {
    let seed = std::env::var("PROPTEST_RNG_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default);
    RngSeed::Fixed(seed)
}

/// A fresh, empty scratch directory for one test, under `target/`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// Run `gapack` with `args` in `dir`.
pub fn gapack(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gapack"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run gapack")
}

/// `f`'s result, run on a pool of `threads` threads: for the tests that a
/// result does not depend on how many threads computed it.
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// Run `gapack` with `args` in `dir` on `threads` threads
/// (`RAYON_NUM_THREADS`), writing to `--out <threads>`; checks that it
/// succeeds and returns that output directory.
pub fn gapack_on_threads(dir: &Path, args: &[&str], threads: usize) -> PathBuf {
    let out = threads.to_string();
    let run = Command::new(env!("CARGO_BIN_EXE_gapack"))
        .args(args)
        .args(["--out", &out])
        .env("RAYON_NUM_THREADS", &out)
        .current_dir(dir)
        .output()
        .expect("run gapack");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    dir.join(out)
}

/// Table 3.4 of the thesis: the proppant grading of the fracture case.
pub fn table_3_4() -> Grading {
    Grading::from_table(
        gapack::THESIS_TABLE_3_4,
        Default::default(),
        Default::default(),
    )
    .unwrap()
}

/// A scene with default packer settings.
pub fn scene(domain: Domain, grading: Grading, walls: WallMode, seed: u64) -> Scene {
    Scene::new(domain, grading)
        .with_walls(walls)
        .with_seed(seed)
}

/// Porosity of a packing without the full metrics.
pub fn porosity(p: &gapack::Packing) -> f64 {
    1.0 - p.disks.iter().map(|d| d.area()).sum::<f64>() / p.domain.area()
}

/// Write `config` as `bad.toml` in a scratch dir, run `gapack pack bad.toml`,
/// and check it fails with exit code 2, one `error:` line naming `key` and
/// `line:column`, no panic and no output at all.
pub fn refuses(name: &str, config: &str, key: &str, line_col: &str) {
    let dir = scratch(name);
    fs::write(dir.join("bad.toml"), config).expect("write config");
    let out = gapack(&dir, &["pack", "bad.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
    assert!(!stderr.contains("panicked"), "{name}: {stderr}");
    assert_eq!(
        stderr.lines().count(),
        1,
        "{name}: one line expected: {stderr}"
    );
    let expected = format!("error: bad.toml:{line_col}: {key}: ");
    assert!(
        stderr.starts_with(&expected),
        "{name}: expected {expected:?}, got {stderr}"
    );
    assert!(out.stdout.is_empty(), "{name}: stdout {:?}", out.stdout);
    assert!(
        !dir.join("out").exists(),
        "{name}: an output directory was created"
    );
    let _ = fs::remove_dir_all(&dir);
}

/// A deterministic number in [0, 1) from a seed and an index.
pub fn frac(s: u64, i: usize) -> f64 {
    let x = s.wrapping_add(i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    ((x ^ (x >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9) >> 11) as f64 / (1u64 << 53) as f64
}

/// The records of a CSV file, header first.
pub fn records(path: &Path) -> Vec<Vec<String>> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(path)
        .expect("a csv file")
        .records()
        .map(|r| r.expect("a record").iter().map(str::to_owned).collect())
        .collect()
}

/// The CSV without the columns named `seconds` (timings differ run to run).
pub fn untimed(csv: &[u8]) -> Vec<Vec<String>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(csv);
    let rows: Vec<Vec<String>> = reader
        .records()
        .map(|r| r.expect("a CSV record").iter().map(str::to_owned).collect())
        .collect();
    let header = rows.first().cloned().unwrap_or_default();
    rows.into_iter()
        .map(|row| {
            row.into_iter()
                .zip(&header)
                .filter(|(_, h)| *h != "seconds")
                .map(|(cell, _)| cell)
                .collect()
        })
        .collect()
}

/// Run the CLI on `config` (as `config.toml`) with `seed` into `dir/cli`.
pub fn cli_run(dir: &Path, kind: &str, config: &str, seed: u64) -> PathBuf {
    std::fs::write(dir.join("config.toml"), config).expect("config");
    let seed = seed.to_string();
    let out = gapack(
        dir,
        &[
            kind,
            "config.toml",
            "--out",
            "cli",
            "--seed",
            &seed,
            "--quiet",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("cli")
}
