//! Long runs on a real process: SIGINT and SIGTERM stop `gapack optimise`
//! cleanly with the best packing so far and a checkpoint; `--resume` goes on
//! to the same result as a run never stopped.

use crate::common;

use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use common::{gapack, scratch};

/// A search that cannot reach its target and runs its 20 generations (about
/// 2 s): long enough to be stopped part-way.
const LONG: &str = "seed = 2\n[domain]\nshape = \"rectangle\"\nwidth = 30\nheight = 30\n[grading]\nuniform = [1.0, 2.0]\n[optimise]\ntarget_porosity = 0.95\npopulation = 32\ngenerations = 20\nstagnation = 1000\ntime_limit_s = 600\n[output]\nformats = [\"csv\"]\n";

/// Start `gapack optimise long.toml --out <out>` in `dir`, send `signal` once
/// its first checkpoint is on disk, and wait for it; the exit code.
fn stopped_by(dir: &Path, out: &str, signal: &str) -> Option<i32> {
    let args = [
        "optimise",
        "long.toml",
        "--out",
        out,
        "--checkpoint-every",
        "1",
    ];
    // Wait for generation 1's checkpoint: the search is under way.
    let ready = || dir.join(out).join("checkpoint.json").exists();
    signalled(dir, &args, signal, ready).0
}

/// Run gapack with `args` in `dir`, send it `signal` once `ready` holds (or
/// after 60 s), and return its exit code and what it printed on stderr.
fn signalled(
    dir: &Path,
    args: &[&str],
    signal: &str,
    ready: impl Fn() -> bool,
) -> (Option<i32>, String) {
    let child = Command::new(env!("CARGO_BIN_EXE_gapack"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start gapack");
    let deadline = Instant::now() + Duration::from_secs(60);
    while !ready() && Instant::now() < deadline {
        sleep(Duration::from_millis(20));
    }
    let sent = Command::new("sh")
        .args(["-c", &format!("kill -{signal} {}", child.id())])
        .status()
        .expect("run kill");
    assert!(sent.success());
    let output = child.wait_with_output().expect("wait for gapack");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn summary(path: &Path) -> serde_json::Value {
    serde_json::from_str(&fs::read_to_string(path).unwrap()).unwrap()
}

/// `convergence.csv` without its seconds column.
fn history(path: &Path) -> Vec<String> {
    fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_owned())
        .collect()
}

#[test]
fn sigint_stops_with_the_best_so_far_and_resume_reaches_the_uninterrupted_result() {
    let dir = scratch("sigint");
    fs::write(dir.join("long.toml"), LONG).unwrap();
    let whole = gapack(
        &dir,
        &["optimise", "long.toml", "--out", "whole", "--quiet"],
    );
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    assert!(
        !dir.join("whole/checkpoint.json").exists(),
        "a finished search leaves no checkpoint"
    );

    assert_eq!(
        stopped_by(&dir, "parts", "INT"),
        Some(0),
        "a clean stop exits 0"
    );
    let stopped = summary(&dir.join("parts/summary.json"));
    assert_eq!(stopped["interrupted"], true);
    let generations = stopped["generations"].as_u64().unwrap();
    assert!(generations < 20, "stopped part-way, at {generations}");
    assert!(
        dir.join("parts/packing.csv").exists(),
        "the best so far is written"
    );
    assert!(dir.join("parts/checkpoint.json").exists());

    let resumed = gapack(
        &dir,
        &[
            "optimise",
            "long.toml",
            "--out",
            "parts",
            "--resume",
            "--quiet",
        ],
    );
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(
        fs::read(dir.join("parts/packing.csv")).unwrap(),
        fs::read(dir.join("whole/packing.csv")).unwrap(),
        "the resumed search ends on the same packing"
    );
    assert_eq!(
        history(&dir.join("parts/convergence.csv")),
        history(&dir.join("whole/convergence.csv"))
    );
    let (a, b) = (
        summary(&dir.join("whole/summary.json")),
        summary(&dir.join("parts/summary.json")),
    );
    for key in [
        "porosity",
        "evaluations",
        "generations",
        "stop",
        "particles",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert!(!dir.join("parts/checkpoint.json").exists());
}

#[test]
fn sigterm_stops_cleanly_too() {
    let dir = scratch("sigterm");
    fs::write(dir.join("long.toml"), LONG).unwrap();
    assert_eq!(stopped_by(&dir, "out", "TERM"), Some(0));
    assert_eq!(summary(&dir.join("out/summary.json"))["interrupted"], true);
    assert!(dir.join("out/checkpoint.json").exists());
    // No temporary file is left behind.
    let leftovers: Vec<_> = fs::read_dir(dir.join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn resume_refuses_a_checkpoint_of_another_run_or_none() {
    let dir = scratch("resume-other");
    fs::write(dir.join("long.toml"), LONG).unwrap();
    let none = gapack(&dir, &["optimise", "long.toml", "--out", "out", "--resume"]);
    assert_eq!(none.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&none.stderr)
            .starts_with("error: there is no checkpoint.json in out to resume from")
    );

    assert_eq!(stopped_by(&dir, "out", "INT"), Some(0));
    let other_seed = gapack(
        &dir,
        &[
            "optimise",
            "long.toml",
            "--out",
            "out",
            "--resume",
            "--seed",
            "7",
        ],
    );
    assert_eq!(other_seed.status.code(), Some(2));
    let message = String::from_utf8_lossy(&other_seed.stderr);
    assert!(
        message.contains("belongs to another run")
            && message.contains("seed 2")
            && message.contains("seed 7"),
        "{message}"
    );

    fs::write(dir.join("out/checkpoint.json"), "{ not json").unwrap();
    let garbled = gapack(&dir, &["optimise", "long.toml", "--out", "out", "--resume"]);
    assert_eq!(garbled.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&garbled.stderr).contains("is not a gapack checkpoint"));
}

#[test]
fn a_failed_write_leaves_the_earlier_outputs_intact() {
    let dir = scratch("earlier-intact");
    fs::write(
        dir.join("long.toml"),
        LONG.replace("generations = 20", "generations = 1"),
    )
    .unwrap();
    let first = gapack(&dir, &["optimise", "long.toml", "--out", "out", "--quiet"]);
    assert!(first.status.success());
    let before: Vec<(String, Vec<u8>)> = {
        let mut files: Vec<_> = fs::read_dir(dir.join("out"))
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                (
                    e.file_name().to_string_lossy().into_owned(),
                    fs::read(e.path()).unwrap(),
                )
            })
            .collect();
        files.sort();
        files
    };
    // A second run with another seed: its convergence.csv cannot replace
    // the old one (a directory is in the way), so no file may change.
    fs::remove_file(dir.join("out/convergence.csv")).unwrap();
    fs::create_dir(dir.join("out/convergence.csv")).unwrap();
    let second = gapack(
        &dir,
        &[
            "optimise",
            "long.toml",
            "--out",
            "out",
            "--seed",
            "9",
            "--quiet",
        ],
    );
    assert_eq!(second.status.code(), Some(1));
    let message = String::from_utf8_lossy(&second.stderr);
    assert!(
        message.contains(
            "error: cannot write the outputs: cannot replace out/convergence.csv: a directory is in the way"
        ),
        "{message}"
    );
    for (name, bytes) in before.iter().filter(|(n, _)| n != "convergence.csv") {
        assert_eq!(
            &fs::read(dir.join("out").join(name)).unwrap(),
            bytes,
            "{name} changed"
        );
    }
    let names: Vec<String> = fs::read_dir(dir.join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.starts_with('.')),
        "temporary files left: {names:?}"
    );
}

/// Start gapack with `args` in `dir`, send SIGINT once `ready` holds (or
/// after 60 s), and wait; the exit code and what it printed on stderr.
fn interrupted(dir: &Path, args: &[&str], ready: impl Fn() -> bool) -> (Option<i32>, String) {
    signalled(dir, args, "INT", ready)
}

#[test]
fn the_resume_hint_runs_as_printed() {
    let dir = scratch("hint");
    fs::write(dir.join("long.toml"), LONG).unwrap();
    let whole = gapack(
        &dir,
        &[
            "optimise",
            "long.toml",
            "--out",
            "whole",
            "--seed",
            "7",
            "--quiet",
        ],
    );
    assert!(whole.status.success());
    let args = [
        "optimise",
        "long.toml",
        "--out",
        "elsewhere/parts",
        "--seed",
        "7",
        "--checkpoint-every",
        "1",
    ];
    let checkpoint = dir.join("elsewhere/parts/checkpoint.json");
    let (code, stderr) = interrupted(&dir, &args, || checkpoint.exists());
    assert_eq!(code, Some(0), "{stderr}");
    let hinted = stderr
        .split('`')
        .nth(1)
        .unwrap_or_else(|| panic!("a hint between backquotes: {stderr}"));
    let words: Vec<&str> = hinted.split_whitespace().collect();
    assert_eq!(words[0], "gapack", "{hinted}");
    let resumed = gapack(&dir, &words[1..]);
    assert!(
        resumed.status.success(),
        "`{hinted}` failed: {}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(
        fs::read(dir.join("elsewhere/parts/packing.csv")).unwrap(),
        fs::read(dir.join("whole/packing.csv")).unwrap(),
        "the hinted command ends on the uninterrupted result"
    );
}

#[test]
fn an_interrupted_stability_sweep_writes_the_runs_it_finished() {
    let dir = scratch("sweep");
    let config = concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
        "/configs/default.toml"
    );
    let start = Instant::now();
    let (code, stderr) = interrupted(&dir, &["stability", config, "--out", "s"], || {
        start.elapsed() > Duration::from_secs(2)
    });
    assert_eq!(code, Some(0), "{stderr}");
    let table = fs::read_to_string(dir.join("s/stability.csv")).expect("the table is written");
    let manifest = summary(&dir.join("s/manifest.json"));
    assert_eq!(manifest["interrupted"], true);
    assert!(table.lines().count() > 1, "some runs finished: {table}");
    assert!(stderr.contains("stopped"), "{stderr}");
}

// ---------------------------------------------------------------------------
// No debris: a signal while a run's files are being written leaves no
// temporary file; a failed batch leaves nothing of its own.
// ---------------------------------------------------------------------------

/// About 1.1 million disks of the thesis' Table 3.4 sizes: a packing.csv
/// of some 70 MB, whose writing takes long enough to be signalled.
const HUGE: &str = "[domain]\nshape = \"rectangle\"\nwidth = 1280\nheight = 1280\n[grading]\ntable = [[1.200, 0], [1.215, 11], [1.225, 21], [1.235, 31], [1.245, 43], [1.255, 54], [1.265, 65], [1.275, 77], [1.285, 89], [1.295, 100]]\n[output]\nformats = [\"csv\"]\n";

/// The hidden files (temporaries, backups) anywhere under `dir`. A run
/// still writing makes and removes them while this looks: what is gone by
/// the time it is read is not there.
fn hidden(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let Ok(entries) = fs::read_dir(dir) else {
        return found;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            found.push(entry.path().display().to_string());
        }
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            found.extend(hidden(&entry.path()));
        }
    }
    found
}

#[test]
fn sigterm_while_a_huge_packing_is_written_leaves_no_temporary_file() {
    let dir = scratch("sigterm-write");
    fs::write(dir.join("huge.toml"), HUGE).unwrap();
    let out = dir.join("out");
    // Signalled once a temporary file is on disk: the write is under way.
    let writing = || out.exists() && !hidden(&out).is_empty();
    let args = ["pack", "huge.toml", "--out", "out", "--quiet"];
    let (code, stderr) = signalled(&dir, &args, "TERM", writing);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(hidden(&out), Vec::<String>::new(), "temporary files left");
    // The packing's own files are staged while it is measured: a signal
    // then cancels the run, which writes nothing (130) and leaves no file.
    if code == Some(130) {
        assert!(stderr.contains("nothing was written"), "{stderr}");
        let left: Vec<_> = fs::read_dir(&out)
            .map(|d| d.flatten().map(|e| e.path()).collect())
            .unwrap_or_default();
        assert!(left.is_empty(), "a cancelled run left {left:?}");
        let _ = fs::remove_dir_all(&dir);
        return;
    }
    // Signalled after the measures: its files are committed whole, then the
    // process exits by itself (it never exits from the signal handler).
    assert_eq!(code, Some(0), "{stderr}");
    let manifest = summary(&out.join("manifest.json"));
    for file in manifest["files"].as_array().unwrap() {
        assert!(out.join(file.as_str().unwrap()).is_file(), "{file}");
    }
    let particles = summary(&out.join("summary.json"))["particles"]
        .as_u64()
        .unwrap();
    assert!(particles > 1_000_000, "{particles} disks");
    let rows = fs::read_to_string(out.join("packing.csv"))
        .unwrap()
        .lines()
        .count();
    assert_eq!(rows as u64, particles + 1, "packing.csv is whole");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_batch_whose_second_well_folder_is_taken_fails_and_leaves_the_folder_as_it_was() {
    let dir = scratch("batch-taken");
    let batch = "seed = 2\n[fracture]\nextent = \"full\"\nheight_m = 0.1\n\
        [[fracture.wells]]\nname = \"A-1\"\nwidth_mm = 2.6\n\
        [[fracture.wells]]\nname = \"B-2\"\nwidth_mm = 4.2\n\
        [grading]\npreset = \"20/40\"\nbasis = \"mass\"\n[output]\nformats = [\"csv\"]\n";
    fs::write(dir.join("batch.toml"), batch).unwrap();
    let first = gapack(&dir, &["pack", "batch.toml", "--out", "out", "--quiet"]);
    assert!(first.status.success());
    let listing = |d: &Path| -> Vec<(String, Vec<u8>)> {
        let mut all: Vec<_> = fs::read_dir(d)
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                let bytes = if e.file_type().unwrap().is_file() {
                    fs::read(e.path()).unwrap()
                } else {
                    Vec::new()
                };
                (e.file_name().to_string_lossy().into_owned(), bytes)
            })
            .collect();
        all.sort();
        all
    };
    // The second well's folder cannot be written: a file has taken its name.
    fs::remove_dir_all(dir.join("out/B-2")).unwrap();
    fs::write(dir.join("out/B-2"), "mine").unwrap();
    let (top, a1) = (listing(&dir.join("out")), listing(&dir.join("out/A-1")));
    let second = gapack(
        &dir,
        &[
            "pack",
            "batch.toml",
            "--out",
            "out",
            "--seed",
            "5",
            "--quiet",
        ],
    );
    assert_eq!(second.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(
        stderr.starts_with(
            "error: cannot write the outputs: cannot create directory out/B-2: a file is in the way"
        ),
        "{stderr}"
    );
    assert_eq!(
        listing(&dir.join("out")),
        top,
        "the earlier run is as it was"
    );
    assert_eq!(
        listing(&dir.join("out/A-1")),
        a1,
        "A-1 keeps the earlier run's files"
    );
    let _ = fs::remove_dir_all(&dir);
}
