//! Jobs under `mpirun` (the `mpi` feature): an optimise (of disks, and of
//! shapes with their shape searched), a layering GA, a wells batch, a
//! compare and a sweep give the same files, byte for byte
//! (times aside), on 1, 2 and 3 ranks as a plain run; a search resumed
//! under another number of ranks reaches the plain run's result; a job that
//! fails under MPI ends every rank with one message.
//!
//! Run with `cargo test --features mpi --test integration mpi::` on a machine with Open
//! MPI (`mpirun` on the PATH); CI does.
#![cfg(feature = "mpi")]

use crate::common;
use crate::common::stopped_search;

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use common::{gapack, scratch};
use gapack::jobs;

/// A search that runs its 6 generations (the target is out of reach).
const OPTIMISE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 30\nheight = 30\n[grading]\nuniform = [1.0, 1.6]\n[optimise]\ntarget_porosity = 0.2412\ntolerance = 0.00001\npopulation = 16\ngenerations = 6\nstagnation = 100\ntime_limit_s = 600\n";

/// The layering GA on two materials, 8 generations.
const LAYER: &str = "seed = 2\n[domain]\nshape = \"rectangle\"\nwidth = 30\nheight = 30\n[grading]\nuniform = [1.0, 1.5]\n[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\naxis = \"y\"\nbins = 6\nprofile = \"linear\"\npopulation = 16\ngenerations = 8\nstagnation = 100\ntime_limit_s = 600\n";

/// A batch of three wells, a folder each.
const WELLS: &str = "seed = 0\n[fracture]\nwalls = \"disks\"\nextent = \"full\"\n[[fracture.wells]]\nname = \"w1\"\nwidth_mm = 6\nheight_m = 0.04\n[[fracture.wells]]\nname = \"w2\"\nwidth_mm = 8\nheight_m = 0.03\n[[fracture.wells]]\nname = \"w3\"\nwidth_mm = 5\nheight_m = 0.05\n[grading]\nuniform = [1.0, 1.5]\n";

/// Every generator, two seeds each, with a target.
const COMPARE: &str = "seed = 4\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 1.5]\n[compare]\nrepeats = 2\n[optimise]\ntarget_porosity = 0.2\n";

/// `mpirun -np <ranks> gapack <args>` in `dir`, ended after 5 minutes at most.
fn mpirun(dir: &Path, ranks: usize, args: &[&str]) -> Output {
    Command::new("timeout")
        .args(["300", "mpirun", "--allow-run-as-root", "--oversubscribe"])
        .args(["--bind-to", "none", "-np", &ranks.to_string()])
        .arg(env!("CARGO_BIN_EXE_gapack"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run mpirun (Open MPI installed?)")
}

fn ok(output: &Output, what: &str) {
    assert!(
        output.status.success(),
        "{what}: {:?}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Every CSV file under `dir` by its path, its `seconds` column (a
/// measured time) taken out, and `summary.json`'s counts.
fn results(dir: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d).expect("read the run's folder") {
            let path = entry.expect("entry").path();
            let name = path
                .strip_prefix(dir)
                .expect("under dir")
                .display()
                .to_string();
            if path.is_dir() {
                stack.push(path);
            } else if name.ends_with(".csv") {
                out.insert(name, timeless(&fs::read_to_string(&path).expect("csv")));
            } else if name.ends_with("summary.json") {
                let s: serde_json::Value =
                    serde_json::from_str(&fs::read_to_string(&path).expect("json")).expect("json");
                let counts = [
                    "particles",
                    "porosity",
                    "evaluations",
                    "generations",
                    "stop",
                ]
                .map(|k| format!("{k}={}", s[k]));
                out.insert(name, counts.join(" "));
            }
        }
    }
    out
}

/// A CSV table without its `seconds` column, a line per record.
fn timeless(text: &str) -> String {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes());
    let mut records = reader.records().map(|r| r.expect("a CSV record"));
    let Some(header) = records.next() else {
        return String::new();
    };
    let drop = header.iter().position(|h| h == "seconds");
    std::iter::once(header)
        .chain(records)
        .map(|r| {
            r.iter()
                .enumerate()
                .filter(|(i, _)| Some(*i) != drop)
                .map(|(_, f)| f)
                .collect::<Vec<_>>()
                .join("|")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The job `job` on `config` gives the same files on 1, 2 and 3 ranks as a
/// plain run.
fn same_on_any_ranks(name: &str, job: &str, config: &str, expect_files: usize) {
    let dir = scratch(&format!("mpi-{name}"));
    fs::write(dir.join("case.toml"), config).expect("write config");
    ok(
        &gapack(&dir, &[job, "case.toml", "--out", "plain", "--quiet"]),
        "plain run",
    );
    let plain = results(&dir.join("plain"));
    assert!(
        plain.len() >= expect_files,
        "{name}: the plain run wrote {plain:?}"
    );
    for ranks in [1, 2, 3] {
        let out = format!("np{ranks}");
        let run = mpirun(&dir, ranks, &[job, "case.toml", "--out", &out, "--quiet"]);
        ok(&run, &format!("{name} on {ranks} ranks"));
        assert_eq!(
            results(&dir.join(&out)),
            plain,
            "{name}: {ranks} ranks against the plain run"
        );
        // Only rank 0 writes, once: the manifest lists exactly the files there.
        let manifest: serde_json::Value = serde_json::from_str(
            &fs::read_to_string(dir.join(&out).join("manifest.json")).expect("manifest"),
        )
        .expect("json");
        let listed = manifest["files"].as_array().map_or(0, Vec::len);
        let plain_listed: serde_json::Value = serde_json::from_str(
            &fs::read_to_string(dir.join("plain/manifest.json")).expect("manifest"),
        )
        .expect("json");
        assert_eq!(
            listed,
            plain_listed["files"].as_array().map_or(0, Vec::len),
            "{name}: {ranks} ranks"
        );
    }
}

#[test]
fn optimise_is_the_same_on_any_number_of_ranks() {
    same_on_any_ranks("optimise", "optimise", OPTIMISE, 3);
}

#[test]
fn the_layering_ga_is_the_same_on_any_number_of_ranks() {
    same_on_any_ranks("layer", "layer", LAYER, 3);
}

#[test]
fn a_wells_batch_is_the_same_on_any_number_of_ranks() {
    same_on_any_ranks("wells", "pack", WELLS, 4);
}

#[test]
fn compare_is_the_same_on_any_number_of_ranks() {
    same_on_any_ranks("compare", "compare", COMPARE, 1);
}

#[test]
fn a_sweep_is_the_same_on_any_number_of_ranks() {
    let study = include_str!("../../configs/sweep_wells.toml")
        .replace("keep = \"summary\"", "keep = \"all\"");
    same_on_any_ranks("sweep", "sweep", &study, 31);
}

#[test]
fn studies_of_shapes_are_the_same_on_any_number_of_ranks() {
    // Each run's packing.csv (angles, axes, exponents) byte for byte.
    let study = include_str!("../../configs/sweep_shapes.toml")
        .replace("seeds = 3", "seeds = 1\nkeep = \"all\"")
        .replace("width = 60 ", "width = 25 ")
        .replace("height = 60 ", "height = 25 ");
    same_on_any_ranks("sweep-shapes", "sweep", &study, 17);
    let compare =
        include_str!("../../configs/compare_shapes.toml").replace("repeats = 3", "repeats = 2");
    same_on_any_ranks("compare-shapes", "compare", &compare, 1);
}

#[test]
fn a_search_of_shapes_is_the_same_on_any_number_of_ranks() {
    // Sizes, packing rules and the particles' shape searched: the same
    // packing.csv, summary.json (shape_found) and convergence on any ranks.
    let search = include_str!("../../configs/optimise_shapes.toml")
        .replace("width = 20 ", "width = 14 ")
        .replace("height = 20 ", "height = 14 ")
        .replace("population = 6", "population = 8")
        .replace("max_evaluations = 12 ", "max_evaluations = 16 ");
    assert!(search.contains("width = 14 ") && search.contains("max_evaluations = 16 "));
    same_on_any_ranks("optimise-shapes", "optimise", &search, 3);
}

#[test]
fn a_search_stopped_on_one_process_resumes_on_two_and_three_ranks_to_the_same_result() {
    let dir = scratch("mpi-resume");
    fs::write(dir.join("case.toml"), OPTIMISE).expect("write config");
    ok(
        &gapack(
            &dir,
            &["optimise", "case.toml", "--out", "plain", "--quiet"],
        ),
        "plain run",
    );
    let plain = results(&dir.join("plain"));
    for (ranks, after) in [(2, 2), (3, 4)] {
        let out = format!("resumed{ranks}");
        fs::create_dir_all(dir.join(&out)).expect("out dir");
        fs::write(
            dir.join(&out).join(jobs::CHECKPOINT_JSON),
            stopped_search::checkpoint_of(OPTIMISE, "case.toml", after),
        )
        .expect("write checkpoint");
        let run = mpirun(
            &dir,
            ranks,
            &[
                "optimise",
                "case.toml",
                "--out",
                &out,
                "--resume",
                "--quiet",
            ],
        );
        ok(&run, &format!("resume on {ranks} ranks"));
        assert_eq!(results(&dir.join(&out)), plain, "resumed on {ranks} ranks");
        assert!(
            !dir.join(&out).join(jobs::CHECKPOINT_JSON).exists(),
            "a search that ends by itself removes its checkpoint"
        );
    }
}

#[test]
fn a_job_that_fails_under_mpi_ends_every_rank_with_one_message() {
    let dir = scratch("mpi-fails");
    // A domain narrower than every disk of the grading: the packer refuses.
    let config = "[domain]\nshape = \"rectangle\"\nwidth = 0.5\nheight = 10\n[grading]\nconstant = 1.0\n[optimise]\ntarget_porosity = 0.3\n";
    fs::write(dir.join("case.toml"), config).expect("write config");
    let run = mpirun(&dir, 2, &["optimise", "case.toml", "--out", "out"]);
    assert_ne!(run.status.code(), Some(0));
    assert_ne!(run.status.code(), Some(124), "ended by the timeout: a hang");
    let said = String::from_utf8_lossy(&run.stderr);
    assert_eq!(said.matches("error:").count(), 1, "{said}");
    assert!(!dir.join("out/packing.csv").exists());
}
