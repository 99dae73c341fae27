//! `gapack sweep`: a parameter study's runs (the product of the swept
//! values over seeds), its table and chart, the files it keeps, its faults
//! placed at their `[sweep]` entry, the same rows whatever the threads,
//! and a stopped or truncated study resumed to the same rows.

use crate::common;

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use common::{gapack, records, scratch};
use gapack::jobs::{self, Cancel, Event, JobError, JobKind, MemoryStore, Plan, Report, Request};
use gapack::study::{Row, Status};

/// A fracture window, swept over three widths and two meshes, two seeds each.
const STUDY: &str = "seed = 5
[fracture]
width_mm = 2.0
height_m = 0.3
extent = \"window\"
[grading]
preset = \"20/40\"
[sweep]
\"fracture.width_mm\" = [1.5, 2.5, 3.5]
\"grading.preset\" = [\"20/40\", \"30/50\"]
seeds = 2
";

/// `gapack ARGS` in `dir` with `RAYON_NUM_THREADS` set when given.
fn gapack_threads(dir: &Path, args: &[&str], threads: Option<usize>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_gapack"));
    command.args(args).current_dir(dir);
    if let Some(n) = threads {
        command.env("RAYON_NUM_THREADS", n.to_string());
    }
    command.output().expect("run gapack")
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The records without the `seconds` column (times differ run to run).
fn untimed(records: &[Vec<String>]) -> Vec<Vec<String>> {
    let at = records[0]
        .iter()
        .position(|h| h == "seconds")
        .expect("a seconds column");
    records
        .iter()
        .map(|r| {
            let mut r = r.clone();
            r.remove(at);
            r
        })
        .collect()
}

/// Every file under `dir`, relative, sorted.
fn tree(dir: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for entry in fs::read_dir(dir).expect("a folder") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let name = path.strip_prefix(root).expect("inside");
                out.push(name.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

#[test]
fn the_runs_are_the_product_in_order_with_their_seeds() {
    let dir = scratch("sweep-product");
    fs::write(dir.join("s.toml"), STUDY).unwrap();
    let stdout = ok(&gapack(&dir, &["sweep", "s.toml", "--out", "out"]));
    let rows = records(&dir.join("out/sweep.csv"));
    assert_eq!(
        rows[0],
        [
            "run",
            "fracture.width_mm",
            "grading.preset",
            "seed",
            "particles",
            "porosity",
            "psd_ks",
            "coordination",
            "target_error",
            "seconds",
            "status"
        ]
    );
    let mut expected = Vec::new();
    for (width, w) in [("1.5", "1.5"), ("2.5", "2.5"), ("3.5", "3.5")] {
        for (preset, p) in [("20/40", "20-40"), ("30/50", "30-50")] {
            for seed in ["5", "6"] {
                expected.push(vec![
                    format!("width_mm={w},preset={p},seed={seed}"),
                    width.to_owned(),
                    preset.to_owned(),
                    seed.to_owned(),
                ]);
            }
        }
    }
    let got: Vec<Vec<String>> = rows[1..].iter().map(|r| r[..4].to_vec()).collect();
    assert_eq!(got, expected, "product order, the seeds fastest");
    for r in &rows[1..] {
        assert_eq!(r[10], "finished", "{r:?}");
        let porosity: f64 = r[5].parse().unwrap();
        assert!(porosity > 0.1 && porosity < 0.5, "{r:?}");
        assert_eq!(r[8], "", "no target, no error");
    }
    // Two seeds differ; the coarser mesh packs fewer disks in one window.
    assert_ne!(rows[1][5], rows[2][5], "the seeds give other packings");
    // One result line per point, then the files.
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 7, "{stdout}");
    assert!(
        lines[0].starts_with("width_mm=1.5,preset=20-40 "),
        "{stdout}"
    );
    assert!(lines[0].contains("2 of 2 runs"), "{stdout}");
    assert!(
        lines[6].ends_with("out: sweep.csv, sweep.svg, sweep.png: 12 runs, 12 finished, 0 failed"),
        "{stdout}"
    );
    // `validate` lists every point's disks, and the study's files.
    let plan = ok(&gapack(&dir, &["validate", "s.toml"]));
    assert!(
        plan.contains("job: sweep: 3 values of fracture.width_mm × 2 of grading.preset × 2 seeds = 12 pack runs, porosity charted against fracture.width_mm"),
        "{plan}"
    );
    assert_eq!(plan.matches("\n  point width_mm=").count(), 6, "{plan}");
    assert!(
        plan.contains("(sweep.csv, .svg, .png; manifest.json always)"),
        "{plan}"
    );
    // No files of the runs unless asked.
    assert_eq!(
        tree(&dir.join("out")),
        ["manifest.json", "sweep.csv", "sweep.png", "sweep.svg"]
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn the_chart_draws_a_series_per_value_of_the_second_key() {
    let dir = scratch("sweep-chart");
    let text = STUDY.replace("seeds = 2", "seeds = 1\nmeasure = \"coordination\"");
    fs::write(dir.join("s.toml"), text).unwrap();
    ok(&gapack(
        &dir,
        &["sweep", "s.toml", "--out", "out", "--quiet"],
    ));
    let svg = fs::read_to_string(dir.join("out/sweep.svg")).unwrap();
    // The legend: one entry per mesh, no other series.
    let legend: Vec<&str> = svg
        .split("</text>")
        .filter_map(|t| t.rsplit('>').next())
        .map(str::trim)
        .filter(|t| t.starts_with("preset "))
        .collect();
    assert_eq!(legend, ["preset 20/40", "preset 30/50"], "{svg}");
    for text in [
        "coordination against fracture.width_mm",
        "fracture.width_mm (mm)",
        "coordination (contacts per disk)",
    ] {
        assert!(svg.contains(text), "sweep.svg lacks {text}");
    }
    let png = fs::read(dir.join("out/sweep.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn keep_writes_exactly_the_files_asked() {
    let dir = scratch("sweep-keep");
    let one = STUDY
        .replace("[1.5, 2.5, 3.5]", "[2.5]")
        .replace("seeds = 2", "seeds = 2\nkeep = \"KEEP\"");
    let runs = [
        "runs/width_mm=2.5,preset=20-40,seed=5/",
        "runs/width_mm=2.5,preset=20-40,seed=6/",
        "runs/width_mm=2.5,preset=30-50,seed=5/",
        "runs/width_mm=2.5,preset=30-50,seed=6/",
    ];
    let study = ["manifest.json", "sweep.csv", "sweep.png", "sweep.svg"];
    for keep in ["none", "summary", "all"] {
        fs::write(dir.join("s.toml"), one.replace("KEEP", keep)).unwrap();
        let out = format!("out-{keep}");
        ok(&gapack(
            &dir,
            &["sweep", "s.toml", "--out", &out, "--quiet"],
        ));
        let mut expected: Vec<String> = study.iter().map(|s| (*s).to_owned()).collect();
        let per_run: &[&str] = match keep {
            "none" => &[],
            "summary" => &["summary.json"],
            _ => &[
                "manifest.json",
                "packing.csv",
                "packing.png",
                "packing.svg",
                "porosity_map.png",
                "porosity_map.svg",
                "psd.png",
                "psd.svg",
                "summary.json",
                "window.csv",
                "window.png",
                "window.svg",
            ],
        };
        for run in runs {
            expected.extend(per_run.iter().map(|f| format!("{run}{f}")));
        }
        expected.sort();
        assert_eq!(tree(&dir.join(&out)), expected, "keep = {keep}");
        // The manifest lists them all.
        let manifest: serde_json::Value =
            serde_json::from_slice(&fs::read(dir.join(&out).join("manifest.json")).unwrap())
                .unwrap();
        assert_eq!(manifest["files"].as_array().unwrap().len(), expected.len());
        if keep != "none" {
            // Each run's summary is its own: its seed, its grading.
            let summary: serde_json::Value = serde_json::from_slice(
                &fs::read(dir.join(&out).join(format!("{}summary.json", runs[0]))).unwrap(),
            )
            .unwrap();
            assert_eq!(summary["seed"], 5, "{summary}");
            let summary: serde_json::Value = serde_json::from_slice(
                &fs::read(dir.join(&out).join(format!("{}summary.json", runs[3]))).unwrap(),
            )
            .unwrap();
            assert_eq!(summary["seed"], 6, "{summary}");
            assert_eq!(summary["grading"]["d_max"], 0.6, "30/50: {summary}");
        }
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_key_or_value_is_placed_at_its_entry() {
    let dir = scratch("sweep-faults");
    // Line 9 holds the widths, line 10 the presets.
    let cases = [
        (
            STUDY.replace("[1.5, 2.5, 3.5]", "[1.5, 2.5, -3.5]"),
            "9:34: sweep.\"fracture.width_mm\"[2]: must be a positive finite number, got -3.5",
        ),
        (
            STUDY.replace("[1.5, 2.5, 3.5]", "[1.5, \"wide\", 3.5]"),
            "9:29: sweep.\"fracture.width_mm\"[1]: ",
        ),
        (
            STUDY.replace("\"30/50\"]", "\"30-50\"]"),
            "10:30: sweep.\"grading.preset\"[1]: ",
        ),
        (
            STUDY.replace("\"fracture.width_mm\"", "\"fracture.widthmm\""),
            "9:1: sweep.\"fracture.widthmm\": not a config key: unknown key `widthmm`",
        ),
        (
            STUDY.replace("\"fracture.width_mm\"", "\"packer.gap\""),
            "9:1: sweep.\"packer.gap\": the config has no [packer] table",
        ),
        (
            STUDY.replace("[1.5, 2.5, 3.5]", "[]"),
            "9:23: sweep.\"fracture.width_mm\": missing; give at least one value",
        ),
        (
            STUDY.replace("seeds = 2", "seeds = 2\n\"seed\" = [1, 2]"),
            "12:1: sweep.\"seed\": the seeds are the study's own",
        ),
        (
            STUDY.replace("seeds = 2", "seeds = 0"),
            "11:9: sweep.seeds: must be a whole number in [1, 10000], got 0",
        ),
        (
            STUDY.replace("seeds = 2", "seeds = 2\nmeasure = \"error\""),
            "12:1: sweep.measure: the pack runs have no target",
        ),
    ];
    for (text, said) in cases {
        fs::write(dir.join("bad.toml"), &text).unwrap();
        for args in [
            &["sweep", "bad.toml", "--out", "out"][..],
            &["validate", "bad.toml"][..],
        ] {
            let command = args[0];
            let out = gapack(&dir, args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{command}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            assert!(
                stderr.starts_with(&format!("error: bad.toml:{said}")),
                "{command}: expected bad.toml:{said}, got {stderr}"
            );
        }
        assert!(!dir.join("out").exists(), "nothing written");
    }
    // Without a [sweep] table the job has nothing to run.
    let plain = STUDY.split("[sweep]").next().unwrap();
    fs::write(dir.join("plain.toml"), plain).unwrap();
    let out = gapack(&dir, &["sweep", "plain.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing table [sweep]"));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_run_that_fails_is_a_row_with_its_reason() {
    let dir = scratch("sweep-fails");
    // 0.2 mm holds no grain of either mesh.
    let text = STUDY.replace("[1.5, 2.5, 3.5]", "[0.2, 2.5]");
    fs::write(dir.join("s.toml"), text).unwrap();
    let stdout = ok(&gapack(&dir, &["sweep", "s.toml", "--out", "out"]));
    let rows = records(&dir.join("out/sweep.csv"));
    assert_eq!(rows.len(), 9);
    for r in &rows[1..5] {
        assert!(r[10].starts_with("failed: "), "{r:?}");
        assert!(r[10].contains("too narrow"), "{r:?}");
        assert!(r[4..10].iter().all(String::is_empty), "no measures: {r:?}");
    }
    for r in &rows[5..] {
        assert_eq!(r[10], "finished", "{r:?}");
    }
    assert!(stdout.contains("8 runs, 4 finished, 4 failed"), "{stdout}");
    assert!(stdout.contains("width_mm=0.2,preset=20-40"), "{stdout}");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn the_rows_do_not_depend_on_the_threads() {
    let dir = scratch("sweep-threads");
    let text = STUDY.replace("seeds = 2", "seeds = 2\nkeep = \"all\"");
    fs::write(dir.join("s.toml"), text).unwrap();
    for threads in [1, 2] {
        let out = format!("out-{threads}");
        ok(&gapack_threads(
            &dir,
            &["sweep", "s.toml", "--out", &out, "--quiet"],
            Some(threads),
        ));
    }
    let (one, two) = (dir.join("out-1"), dir.join("out-2"));
    assert_eq!(
        untimed(&records(&one.join("sweep.csv"))),
        untimed(&records(&two.join("sweep.csv")))
    );
    assert_eq!(tree(&one), tree(&two));
    // The chart (of porosity) and every run's packing, byte for byte.
    for file in tree(&one) {
        if file == "sweep.svg" || file == "sweep.png" || file.ends_with("packing.csv") {
            assert!(
                fs::read(one.join(&file)).unwrap() == fs::read(two.join(&file)).unwrap(),
                "{file} differs with 1 and 2 threads"
            );
        }
    }
    let _ = fs::remove_dir_all(&dir);
}

fn plan(text: &str, resume: bool) -> Plan {
    let request = Request {
        resume,
        ..Request::new(JobKind::Sweep)
    };
    Plan::load(text, "s.toml", &request).expect("plans")
}

fn rows_of(outcome: &jobs::Outcome) -> Vec<Row> {
    match &outcome.report {
        Report::Sweep { rows, .. } => rows.clone(),
        other => panic!("not a study: {other:?}"),
    }
}

/// A row with its seconds set to zero.
fn untimed_row(row: &Row) -> Row {
    let mut row = row.clone();
    if let Status::Finished(m) = &mut row.status {
        m.seconds = 0.0;
    }
    row
}

#[test]
fn a_stopped_study_resumes_to_the_rows_of_one_never_stopped() {
    // One thread: the runs go in waves of two, and the stop comes after the first.
    common::on_threads(1, || {
        let mut whole = MemoryStore::default();
        let all = jobs::run(
            &plan(STUDY, false),
            &mut jobs::Silent,
            &Cancel::new(),
            &mut whole,
        )
        .expect("runs");
        assert!(!all.interrupted);

        let mut store = MemoryStore::default();
        let cancel = Cancel::new();
        let mut events = Vec::new();
        let mut observer = |e: &Event| {
            if matches!(e, Event::Run { .. }) {
                cancel.cancel();
            }
            events.push(e.clone());
        };
        let stopped = jobs::run(&plan(STUDY, false), &mut observer, &cancel, &mut store)
            .expect("keeps the runs finished");
        assert!(stopped.interrupted);
        let rows = rows_of(&stopped);
        let finished = rows
            .iter()
            .filter(|r| matches!(r.status, Status::Finished(_)))
            .count();
        assert_eq!(finished, 2, "the first wave");
        assert!(rows[2..].iter().all(|r| r.status == Status::NotRun));
        let table = String::from_utf8(store.files["sweep.csv"].clone()).unwrap();
        assert_eq!(table.matches(",not run\n").count(), 10, "{table}");
        assert!(
            stopped
                .lines()
                .last()
                .unwrap()
                .contains("(interrupted: 2 of 12 runs)")
        );

        // Resumed: the two rows kept as they were, the ten others run.
        let resumed = jobs::run(
            &plan(STUDY, true),
            &mut jobs::Silent,
            &Cancel::new(),
            &mut store,
        )
        .expect("resumes");
        assert!(!resumed.interrupted);
        let again = rows_of(&resumed);
        assert_eq!(&again[..2], &rows[..2], "kept to the bit, seconds too");
        let untimed_all: Vec<Row> = rows_of(&all).iter().map(untimed_row).collect();
        let untimed_again: Vec<Row> = again.iter().map(untimed_row).collect();
        assert_eq!(untimed_again, untimed_all);
        assert_eq!(store.files["sweep.svg"], whole.files["sweep.svg"]);
        assert!(
            resumed
                .lines()
                .last()
                .unwrap()
                .contains("(2 kept from the earlier sweep.csv)")
        );

        // A study of another config does not resume from it.
        let other = STUDY.replace("seed = 5", "seed = 6");
        let err = jobs::run(
            &plan(&other, true),
            &mut jobs::Silent,
            &Cancel::new(),
            &mut store,
        )
        .expect_err("another study");
        assert!(matches!(err, JobError::Input(_)), "{err}");
        assert!(err.to_string().contains("belongs to another run"), "{err}");
    });
}

#[test]
fn a_truncated_table_resumes_to_the_same_rows() {
    let dir = scratch("sweep-truncated");
    fs::write(
        dir.join("s.toml"),
        STUDY.replace("seeds = 2", "seeds = 2\nkeep = \"summary\""),
    )
    .unwrap();
    ok(&gapack(
        &dir,
        &["sweep", "s.toml", "--out", "out", "--quiet"],
    ));
    let table = dir.join("out/sweep.csv");
    let whole = records(&table);
    let files = tree(&dir.join("out"));
    // Cut in the middle of the sixth run's row.
    let text = fs::read_to_string(&table).unwrap();
    let sixth = text.match_indices('\n').nth(5).unwrap().0;
    fs::write(&table, &text[..sixth + 30]).unwrap();
    let stdout = ok(&gapack(
        &dir,
        &["sweep", "s.toml", "--out", "out", "--resume"],
    ));
    assert!(
        stdout.contains("(5 kept from the earlier sweep.csv)"),
        "{stdout}"
    );
    let again = records(&table);
    assert_eq!(&again[..6], &whole[..6], "the rows kept, to the bit");
    assert_eq!(untimed(&again), untimed(&whole));
    assert_eq!(
        tree(&dir.join("out")),
        files,
        "every run's summary is there"
    );
    // Without a study to resume, a resume is refused.
    let out = gapack(&dir, &["sweep", "s.toml", "--out", "elsewhere", "--resume"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("there is no study to resume"));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_study_of_searches_charts_their_error() {
    let dir = scratch("sweep-optimise");
    let text = "seed = 2
[domain]
shape = \"rectangle\"
width = 12
height = 12
[grading]
uniform = [1.0, 1.5]
[optimise]
target_porosity = 0.3
population = 8
generations = 2
[sweep]
\"optimise.target_porosity\" = [0.25, 0.35]
measure = \"error\"
";
    fs::write(dir.join("o.toml"), text).unwrap();
    let validate = ok(&gapack(&dir, &["validate", "o.toml"]));
    assert!(
        validate.contains("job: sweep: 2 values of optimise.target_porosity × 1 seed = 2 optimise runs, error charted"),
        "{validate}"
    );
    ok(&gapack(
        &dir,
        &["sweep", "o.toml", "--out", "out", "--quiet"],
    ));
    let rows = records(&dir.join("out/sweep.csv"));
    for (r, target) in rows[1..].iter().zip([0.25, 0.35]) {
        let porosity: f64 = r[4].parse().unwrap();
        let error: f64 = r[7].parse().unwrap();
        assert!((error - (porosity - target).abs()).abs() < 1e-12, "{r:?}");
    }
    let svg = fs::read_to_string(dir.join("out/sweep.svg")).unwrap();
    assert!(svg.contains("target error against optimise.target_porosity"));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_batch_of_wells_is_one_row_its_disks_summed_and_its_porosity_averaged() {
    let dir = scratch("sweep-wells");
    let text = "seed = 1
[fracture]
extent = \"full\"
[[fracture.wells]]
name = \"a\"
width_mm = 6
height_m = 0.03
[[fracture.wells]]
name = \"b\"
width_mm = 9
height_m = 0.04
[grading]
uniform = [1.0, 1.5]
[sweep]
\"fracture.width_mm\" = [4.0, 5.0]
keep = \"summary\"
";
    fs::write(dir.join("w.toml"), text).unwrap();
    ok(&gapack(
        &dir,
        &["sweep", "w.toml", "--out", "out", "--quiet"],
    ));
    let rows = records(&dir.join("out/sweep.csv"));
    assert_eq!(rows.len(), 3, "a row per run, not per well");
    for row in &rows[1..] {
        let run = dir.join("out/runs").join(&row[0]);
        let summaries: Vec<serde_json::Value> = ["a", "b"]
            .iter()
            .map(|w| {
                serde_json::from_slice(&fs::read(run.join(w).join("summary.json")).unwrap())
                    .unwrap()
            })
            .collect();
        // The swept width is every well's.
        let width = row[1].parse::<f64>().unwrap();
        for s in &summaries {
            assert_eq!(s["fracture"]["width_mm"].as_f64(), Some(width), "{s}");
        }
        let disks: u64 = summaries
            .iter()
            .map(|s| s["particles"].as_u64().unwrap())
            .sum();
        assert_eq!(row[3], disks.to_string(), "{row:?}");
        let mean = summaries
            .iter()
            .map(|s| s["porosity"].as_f64().unwrap())
            .sum::<f64>()
            / 2.0;
        let porosity: f64 = row[4].parse().unwrap();
        assert!((porosity - mean).abs() < 1e-12, "{porosity} against {mean}");
    }
    let _ = fs::remove_dir_all(&dir);
}

/// A study of particle shapes: aspect ratio and exponent swept over a
/// square of superellipses.
const SHAPES: &str = "seed = 1
[domain]
shape = \"rectangle\"
width = 25
height = 25
[grading]
uniform = [1, 2]
[shape]
kind = \"superellipse\"
aspect = 1.5
[sweep]
\"shape.aspect\" = [1.0, 2.0, 3.0]
\"shape.alpha\" = [2, 4]
keep = \"all\"
";

#[test]
fn a_study_of_shapes_runs_each_point_as_its_own_pack() {
    let dir = scratch("sweep-shapes");
    fs::write(dir.join("s.toml"), SHAPES).unwrap();
    let stdout = ok(&gapack(&dir, &["sweep", "s.toml", "--out", "out"]));
    assert!(stdout.contains("6 runs, 6 finished, 0 failed"), "{stdout}");
    let rows = records(&dir.join("out/sweep.csv"));
    assert_eq!(rows.len(), 7);
    // Looser as the particles grow longer, at each exponent.
    let porosity = |r: &Vec<String>| r[5].parse::<f64>().unwrap();
    for alpha in 0..2 {
        let by_aspect: Vec<f64> = (0..3).map(|a| porosity(&rows[1 + 2 * a + alpha])).collect();
        assert!(by_aspect[0] < by_aspect[2], "{by_aspect:?}");
    }
    // The point aspect = 2, alpha = 4 packed alone: the same packing.
    let alone = SHAPES
        .split("[sweep]")
        .next()
        .unwrap()
        .replace("aspect = 1.5", "aspect = 2.0\nalpha = 4");
    fs::write(dir.join("one.toml"), alone).unwrap();
    ok(&gapack(&dir, &["pack", "one.toml", "--out", "one"]));
    let run = dir.join("out/runs/aspect=2,alpha=4,seed=1/packing.csv");
    assert!(fs::read(run).unwrap() == fs::read(dir.join("one/packing.csv")).unwrap());
    // A non-convex exponent is placed at its entry, before anything runs.
    let bad = SHAPES.replace("[2, 4]", "[2, 0.5]");
    fs::write(dir.join("bad.toml"), bad).unwrap();
    let out = gapack(&dir, &["sweep", "bad.toml", "--out", "bad"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("bad.toml:13:21: sweep.\"shape.alpha\"[1]: must be at least 1"),
        "{stderr}"
    );
    assert!(!dir.join("bad/sweep.csv").exists());
    // Runs of every job take shapes: a study of searches plans each point.
    let searches = SHAPES.replace("keep = \"all\"", "job = \"optimise\"")
        + "[optimise]\ntarget_porosity = 0.3\n";
    fs::write(dir.join("opt.toml"), searches).unwrap();
    let out = gapack(&dir, &["validate", "opt.toml"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = fs::remove_dir_all(&dir);
}
