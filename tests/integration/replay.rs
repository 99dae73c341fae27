//! Every input that ever made gapack misbehave (hang, blow up memory,
//! panic, pass a wrong result), replayed through the real binary, and
//! random tables and edited checkpoints in the same harness.
//!
//! Each run happens in its own process under an address-space limit
//! (`ulimit -v`, 4 GB) and a wall-clock bound ([`BOUND`]): an input that
//! makes gapack allocate without bound aborts it, one that makes it spin is
//! killed, and either fails the test. The oracle: exit code 0, 1 or 2 (never
//! a panic's 101, an abort, or a signal), no panic text, and where an input
//! names what must happen (`# expect: exit N`), that exit code.
//!
//! Inputs live in `tests/data/replay/`: `config/*.toml` (validated, then run
//! with the job their `# Run:` line names, else `pack`), `table/*.csv` (given
//! to `verify` and `plot`), `checkpoint/*.json` (resumed by `optimise` over
//! `optimise.toml`; `refused_*` ones must be refused with exit 2). Add the
//! input of every new fault there.

use crate::common;
use crate::common::json_edit;
use crate::common::stopped_search;

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use common::scratch;
use gapack::jobs;
use proptest::prelude::*;
use proptest::test_runner::{Config as RunnerConfig, TestRunner};

/// Longest one run may take: far beyond what any of these inputs needs now.
const BOUND: Duration = Duration::from_secs(120);

/// Address-space limit of one run (KiB).
const MEMORY_KB: u64 = 4 * 1024 * 1024;

fn replay_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tests/data/replay")
}

/// How one run ended.
struct Ended {
    code: Option<i32>,
    stderr: String,
}

/// Run gapack with `args` in `dir` under the memory limit; kill it and fail
/// if it outlives [`BOUND`].
fn bounded(dir: &Path, args: &[&str]) -> Ended {
    let script = format!("ulimit -v {MEMORY_KB}; exec \"$0\" \"$@\"");
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_gapack"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start gapack");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait for gapack") {
            let mut stderr = String::new();
            if let Some(mut e) = child.stderr.take() {
                let _ = e.read_to_string(&mut stderr);
            }
            return Ended {
                code: status.code(),
                stderr,
            };
        }
        if start.elapsed() > BOUND {
            let _ = child.kill();
            let _ = child.wait();
            panic!("gapack {args:?} did not finish within {BOUND:?}");
        }
        sleep(Duration::from_millis(20));
    }
}

/// The oracle every run must pass; `expect` is the exit code the input names.
fn judge(what: &str, ended: &Ended, expect: Option<i32>) {
    let Ended { code, stderr } = ended;
    assert!(
        matches!(code, Some(0..=2)),
        "{what}: exit {code:?} (a panic, an abort or a signal)\n{stderr}"
    );
    for sign in ["panicked", "memory allocation of", "RUST_BACKTRACE"] {
        assert!(!stderr.contains(sign), "{what}: {sign}\n{stderr}");
    }
    if let Some(expect) = expect {
        assert_eq!(*code, Some(expect), "{what}\n{stderr}");
    }
}

/// The `# expect: exit N` an input names, if any.
fn expected(text: &str) -> Option<i32> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix("# expect: exit "))
        .and_then(|n| n.trim().parse().ok())
}

/// The files of one kind, sorted.
fn inputs(kind: &str, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(replay_dir().join(kind))
        .expect("replay folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no {kind} inputs");
    files
}

#[test]
fn every_config_that_ever_failed_is_refused_or_runs_within_bounds() {
    let dir = scratch("replay-config");
    for path in inputs("config", "toml") {
        let text = fs::read_to_string(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        fs::copy(&path, dir.join(&name)).unwrap();
        let validated = bounded(&dir, &["validate", &name]);
        judge(&format!("validate {name}"), &validated, None);
        // The job its `# Run: … -- JOB file` line names, else `pack`.
        let job = text
            .lines()
            .find_map(|l| l.strip_prefix("# Run:"))
            .and_then(|run| run.split("-- ").nth(1))
            .and_then(|args| args.split_whitespace().next())
            .unwrap_or("pack");
        let ran = bounded(&dir, &[job, &name, "--out", "out", "--quiet"]);
        judge(&format!("{job} {name}"), &ran, expected(&text));
        if ran.code == Some(2) {
            assert_eq!(
                validated.code,
                Some(2),
                "{name}: validate passed what the run refused"
            );
            assert!(
                !dir.join("out").exists(),
                "{name}: a refused run left its folder"
            );
        }
        let _ = fs::remove_dir_all(dir.join("out"));
    }
}

/// `verify` (against the shipped default scene) and `plot` (framed by the
/// disks) of one table file in `dir`.
fn inspect(dir: &Path, name: &str, expect: Option<i32>) {
    let default =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("configs/default.toml");
    let default = default.to_str().expect("a UTF-8 path");
    let verified = bounded(dir, &["verify", name, "--config", default]);
    judge(&format!("verify {name}"), &verified, expect);
    let plotted = bounded(dir, &["plot", name, "--out", "pictures"]);
    judge(&format!("plot {name}"), &plotted, None);
    let _ = fs::remove_dir_all(dir.join("pictures"));
}

#[test]
fn every_table_that_ever_failed_is_refused_or_checked_within_bounds() {
    let dir = scratch("replay-table");
    for path in inputs("table", "csv") {
        let text = fs::read_to_string(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        fs::copy(&path, dir.join(&name)).unwrap();
        inspect(&dir, &name, expected(&text));
    }
}

/// A number as a table may hold it: ordinary sizes and coordinates, and the
/// values that broke readers and plots (zero, subnormal, huge, not finite).
fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0.1f64..10.0).prop_map(|v| format!("{v}")),
        2 => (-1e4f64..1e4).prop_map(|v| format!("{v}")),
        1 => prop::sample::select(vec![
            "0", "-0", "5e-324", "1e-300", "1e300", "1.7976931348623157e308", "inf", "-inf",
            "nan", "", "x", "1e-7", "1e7",
        ])
        .prop_map(str::to_owned),
    ]
}

#[test]
fn random_tables_end_within_bounds() {
    let dir = scratch("replay-random-table");
    let rows = prop::collection::vec((cell(), cell(), cell()), 0..40);
    let header = prop::sample::select(vec!["x,y,r", "x,y,d", "y,x,r", "x,y,r,material"]);
    let mut runner = TestRunner::new_with_rng(
        RunnerConfig {
            cases: 24,
            ..RunnerConfig::default()
        },
        proptest::test_runner::TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &[7; 32],
        ),
    );
    runner
        .run(&(header, rows), |(header, rows)| {
            let mut text = format!("{header}\n");
            for (i, (a, b, c)) in rows.iter().enumerate() {
                let material = if header.ends_with("material") {
                    format!(",m{}", i % 3)
                } else {
                    String::new()
                };
                text.push_str(&format!("{a},{b},{c}{material}\n"));
            }
            fs::write(dir.join("t.csv"), &text).unwrap();
            inspect(&dir, "t.csv", None);
            Ok(())
        })
        .unwrap();
}

/// Resume the fixture's search from `checkpoint` in `dir`.
fn resume(dir: &Path, checkpoint: &[u8]) -> Ended {
    let _ = fs::remove_dir_all(dir.join("out"));
    fs::create_dir_all(dir.join("out")).unwrap();
    fs::write(dir.join("out").join(jobs::CHECKPOINT_JSON), checkpoint).unwrap();
    bounded(
        dir,
        &[
            "optimise",
            "optimise.toml",
            "--out",
            "out",
            "--resume",
            "--quiet",
        ],
    )
}

fn checkpoint_dir(name: &str) -> PathBuf {
    let dir = scratch(name);
    fs::copy(
        replay_dir().join("optimise.toml"),
        dir.join("optimise.toml"),
    )
    .unwrap();
    dir
}

#[test]
fn every_checkpoint_that_ever_failed_is_refused_or_resumed_within_bounds() {
    let dir = checkpoint_dir("replay-checkpoint");
    let real = resume(&dir, &stopped_search::checkpoint_after(1));
    judge("a real checkpoint", &real, Some(0));
    for path in inputs("checkpoint", "json") {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        // `refused_*` checkpoints must be refused as bad input.
        let expect = name.starts_with("refused_").then_some(2);
        judge(&name, &resume(&dir, &fs::read(&path).unwrap()), expect);
    }
}

#[test]
fn edited_checkpoints_are_refused_or_resumed_within_bounds() {
    let dir = checkpoint_dir("replay-random-checkpoint");
    let real: serde_json::Value =
        serde_json::from_slice(&stopped_search::checkpoint_after(2)).unwrap();
    let places = json_edit::places(&real);
    let mut runner = TestRunner::new_with_rng(
        RunnerConfig {
            cases: 32,
            ..RunnerConfig::default()
        },
        proptest::test_runner::TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &[11; 32],
        ),
    );
    let edits = prop::collection::vec((0..places, any::<u32>()), 1..4);
    runner
        .run(&edits, |edits| {
            let mut value = real.clone();
            for (place, kind) in edits {
                let place = place % json_edit::places(&value);
                json_edit::edit_at(&mut value, place, kind);
            }
            let bytes = serde_json::to_vec(&value).unwrap();
            judge("an edited checkpoint", &resume(&dir, &bytes), None);
            Ok(())
        })
        .unwrap();
}
