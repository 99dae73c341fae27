//! The jobs layer as a front end sees it: events in order with the right
//! totals, every job kind cancelled part-way keeping what it finished, a
//! reused output folder left holding only the new run's files.

mod common;

use std::fs;
use std::time::{Duration, Instant};

use gapack::check;
use gapack::jobs::{
    self, Cancel, DirStore, Event, JobError, JobKind, MemoryStore, Outcome, Plan, Report, Request,
    Stage,
};
use gapack::output::read_packing_csv;

use common::scratch;

const SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n";

fn plan(text: &str, kind: JobKind) -> Plan {
    Plan::load(text, "t.toml", &Request::new(kind)).expect("plans")
}

/// Run `plan` into `store`, recording every event; `stop_when` may raise the cancel token.
fn recorded(
    plan: &Plan,
    store: &mut MemoryStore,
    mut stop_when: impl FnMut(&Event) -> bool,
) -> (Result<Outcome, JobError>, Vec<Event>) {
    let cancel = Cancel::new();
    let mut events = Vec::new();
    let mut observer = |e: &Event| {
        if stop_when(e) {
            cancel.cancel();
        }
        events.push(e.clone());
    };
    let outcome = jobs::run(plan, &mut observer, &cancel, store);
    (outcome, events)
}

/// The disks of `packing.csv` in `store` under `folder` pass the independent check.
fn valid_packing(store: &MemoryStore, folder: &str, plan: &Plan) -> usize {
    let bytes = &store.files[&format!("{folder}packing.csv")];
    let table = read_packing_csv(std::str::from_utf8(bytes).unwrap(), "packing.csv").unwrap();
    let scene = match &plan.config.fracture {
        Some(run) if !folder.is_empty() => {
            &run.wells
                .iter()
                .find(|w| format!("{}/", w.name) == folder)
                .unwrap()
                .scene
        }
        _ => &plan.config.scene,
    };
    let c = check(&table.disks, &scene.domain, None);
    assert!(c.valid(), "{folder}packing.csv fails the check");
    table.disks.len()
}

fn manifest(store: &MemoryStore) -> serde_json::Value {
    serde_json::from_slice(&store.files["manifest.json"]).unwrap()
}

#[test]
fn a_pack_reports_its_stage_progress_and_files_in_order() {
    let text = format!("{SQUARE}[optimise]\ntarget_porosity = 0.2\n");
    let plan = plan(&text, JobKind::Pack);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&plan, &mut store, |_| false);
    let outcome = outcome.expect("packs");
    assert_eq!(events[0], Event::Started { job: JobKind::Pack });
    assert!(
        matches!(&events[1], Event::Warning(w) if w.message.contains("[optimise]")),
        "the ignored table is said first: {:?}",
        events[1]
    );
    let estimated = plan.config.scene.estimated_disks().round() as u64;
    assert_eq!(
        events[2],
        Event::Stage {
            stage: Stage::Pack,
            total: Some(estimated)
        }
    );
    assert_eq!(
        events[3],
        Event::Progress {
            stage: Stage::Pack,
            done: 0
        }
    );
    let Some(Event::Written { files }) = events.last() else {
        panic!("the last event is the files written: {:?}", events.last());
    };
    for name in files {
        assert!(store.files.contains_key(name), "{name}");
    }
    assert_eq!(outcome.files, {
        let mut all: Vec<String> = store.files.keys().cloned().collect();
        all.sort();
        all
    });
    assert_eq!(manifest(&store)["interrupted"], false);
    assert!(!outcome.interrupted);
    valid_packing(&store, "", &plan);
}

#[test]
fn a_search_reports_every_generation_and_its_total() {
    let text = format!(
        "{SQUARE}[optimise]\ntarget_porosity = 0.05\npopulation = 8\ngenerations = 4\nstagnation = 100\n"
    );
    let plan = plan(&text, JobKind::Optimise);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&plan, &mut store, |_| false);
    let outcome = outcome.expect("searches");
    assert!(events.contains(&Event::Stage {
        stage: Stage::Optimise,
        total: Some(4)
    }));
    let indices: Vec<usize> = events
        .iter()
        .filter_map(|e| match e {
            Event::Generation { index, .. } => Some(*index),
            _ => None,
        })
        .collect();
    assert_eq!(indices, [0, 1, 2, 3, 4]);
    let Report::Optimise { history, .. } = &outcome.report else {
        panic!("an optimise report");
    };
    assert_eq!(history.len(), indices.len());
    assert!(
        events
            .iter()
            .any(|e| matches!(e, Event::Warning(w) if w.message.contains("out of reach"))),
        "a finished search that missed its target says so"
    );
}

#[test]
fn a_cancelled_pack_of_a_million_disks_returns_at_once_and_writes_nothing() {
    // 1000 × 1000 mm of the thesis' Table 3.4 sizes: about 10⁶ disks.
    let text = "[domain]\nshape = \"rectangle\"\nwidth = 1000\nheight = 1000\n[grading]\ntable = [[1.200, 0], [1.215, 11], [1.225, 21], [1.235, 31], [1.245, 43], [1.255, 54], [1.265, 65], [1.275, 77], [1.285, 89], [1.295, 100]]\n";
    let plan = plan(text, JobKind::Pack);
    assert!(plan.config.scene.estimated_disks() > 5e5);
    let mut store = MemoryStore::default();
    let mut raised = None;
    let (outcome, _) = recorded(&plan, &mut store, |e| {
        let stop = matches!(e, Event::Progress { done, .. } if *done >= 200_000);
        if stop && raised.is_none() {
            raised = Some(Instant::now());
        }
        stop
    });
    let latency = raised.expect("raised").elapsed();
    assert!(matches!(outcome, Err(JobError::Cancelled)), "{outcome:?}");
    assert!(store.files.is_empty(), "nothing is written");
    assert!(
        latency < Duration::from_millis(100),
        "returned {latency:?} after the cancel"
    );
}

#[test]
fn a_cancelled_search_keeps_its_best_and_resumes_to_the_uninterrupted_result() {
    let text = format!(
        "{SQUARE}[optimise]\ntarget_porosity = 0.05\npopulation = 8\ngenerations = 6\nstagnation = 100\n"
    );
    let whole_plan = plan(&text, JobKind::Optimise);
    let mut whole = MemoryStore::default();
    recorded(&whole_plan, &mut whole, |_| false)
        .0
        .expect("searches");

    let mut parts = MemoryStore::default();
    let (outcome, events) = recorded(&whole_plan, &mut parts, |e| {
        matches!(e, Event::Generation { index: 2, .. })
    });
    let outcome = outcome.expect("keeps the best so far");
    assert!(outcome.interrupted);
    assert!(matches!(
        outcome.report,
        Report::Optimise {
            resumable: true,
            ..
        }
    ));
    assert!(parts.files.contains_key("checkpoint.json"));
    assert!(outcome.files.contains(&"checkpoint.json".to_owned()));
    assert!(
        !events
            .iter()
            .any(|e| matches!(e, Event::Warning(w) if w.message.contains("out of reach"))),
        "an interrupted search gives no verdict"
    );
    assert_eq!(manifest(&parts)["interrupted"], true);
    valid_packing(&parts, "", &whole_plan);

    let resume = Request {
        resume: true,
        ..Request::new(JobKind::Optimise)
    };
    let again = Plan::load(&text, "t.toml", &resume).expect("plans");
    let (outcome, _) = recorded(&again, &mut parts, |_| false);
    assert!(!outcome.expect("resumes").interrupted);
    assert_eq!(parts.files["packing.csv"], whole.files["packing.csv"]);
    assert!(
        !parts.files.contains_key("checkpoint.json"),
        "a finished search keeps none"
    );

    let other_seed = Request {
        seed: Some(99),
        ..resume
    };
    let mut stopped = MemoryStore::default();
    let _ = recorded(&whole_plan, &mut stopped, |e| {
        matches!(e, Event::Generation { index: 1, .. })
    });
    let other = Plan::load(&text, "t.toml", &other_seed).expect("plans");
    let err = recorded(&other, &mut stopped, |_| false)
        .0
        .expect_err("another seed");
    assert!(err.is_input());
    let message = err.to_string();
    assert!(
        message.contains("seed 3") && message.contains("seed 99"),
        "{message}"
    );
}

#[test]
fn a_cancelled_layering_writes_its_best_assignment() {
    let text = format!(
        "{SQUARE}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\naxis = \"y\"\nbins = 10\nprofile = \"steps\"\nlayers = [[\"a\", 0.5], [\"b\", 0.5]]\npopulation = 16\ngenerations = 50\ntolerance = 0.0\n"
    );
    let plan = plan(&text, JobKind::Layer);
    let mut store = MemoryStore::default();
    let (outcome, _) = recorded(&plan, &mut store, |e| {
        matches!(
            e,
            Event::Generation {
                stage: Stage::Layering,
                index: 1,
                ..
            }
        )
    });
    let outcome = outcome.expect("keeps the layering so far");
    assert!(outcome.interrupted);
    assert_eq!(manifest(&store)["interrupted"], true);
    valid_packing(&store, "", &plan);
}

#[test]
fn a_cancelled_batch_keeps_the_wells_it_finished() {
    let text = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/wells.toml"))
        .expect("shipped config");
    let plan = plan(&text, JobKind::Pack);
    let total = plan.config.fracture.as_ref().unwrap().wells.len();
    assert!(total > 1);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&plan, &mut store, |e| matches!(e, Event::Well { .. }));
    assert!(events.contains(&Event::Stage {
        stage: Stage::Wells,
        total: Some(total as u64)
    }));
    let outcome = outcome.expect("keeps the finished well");
    assert!(outcome.interrupted);
    let Report::Wells { wells, .. } = &outcome.report else {
        panic!("a wells report");
    };
    assert_eq!(wells.len(), 1);
    let rows = String::from_utf8(store.files["wells.csv"].clone()).unwrap();
    assert_eq!(rows.lines().count(), 2, "a header and the one well: {rows}");
    valid_packing(&store, &wells[0].folder, &plan);
}

#[test]
fn a_cancelled_comparison_or_sweep_writes_the_runs_it_finished() {
    for (kind, table) in [
        (JobKind::Compare, "compare.csv"),
        (JobKind::Stability, "stability.csv"),
    ] {
        let text =
            format!("{SQUARE}[compare]\nmethods = [\"advancing-front\", \"rsa\"]\nrepeats = 3\n");
        let plan = plan(&text, kind);
        let mut store = MemoryStore::default();
        let mut runs = 0;
        let (outcome, events) = recorded(&plan, &mut store, |e| {
            runs += usize::from(matches!(e, Event::Run { .. }));
            runs == 2
        });
        let Some(Event::Stage {
            total: Some(total), ..
        }) = events.iter().find(|e| matches!(e, Event::Stage { .. }))
        else {
            panic!("a stage with its total");
        };
        assert!(*total > 2);
        let outcome = outcome.expect("keeps the runs");
        assert!(outcome.interrupted, "{kind:?}");
        let csv = String::from_utf8(store.files[table].clone()).unwrap();
        assert_eq!(csv.lines().count(), 3, "{kind:?}: a header and two runs");
        assert_eq!(manifest(&store)["interrupted"], true);
    }
}

#[test]
fn a_reused_output_folder_holds_only_the_new_runs_files() {
    let dir = scratch("stale");
    let out = dir.join("out");
    let run = |text: &str| {
        let plan = plan(text, JobKind::Pack);
        jobs::run(
            &plan,
            &mut jobs::Silent,
            &Cancel::new(),
            &mut DirStore::new(&out),
        )
        .expect("runs")
    };
    let many = format!("{SQUARE}[output]\nformats = [\"csv\", \"vtk\", \"lammps\"]\n");
    let first = run(&many);
    assert!(out.join("packing.lammps").exists());
    assert!(first.files.contains(&"packing.vtk".to_owned()));
    let few = format!("{SQUARE}[output]\nformats = [\"csv\"]\n");
    let second = run(&few);
    let mut left: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, second.files, "only the second run's files are left");
    assert!(!out.join("packing.lammps").exists());
    assert!(!out.join("boundary.vtk").exists());

    // A batch's well folders go when a plain pack takes the folder over.
    let wells = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/wells.toml"))
        .expect("shipped config");
    let batch = run(&wells);
    let folder = batch
        .files
        .iter()
        .find(|f| f.contains('/'))
        .unwrap()
        .clone();
    assert!(out.join(&folder).exists());
    run(&few);
    let well_dir = out.join(folder.split('/').next().unwrap());
    assert!(!well_dir.exists(), "{} is left", well_dir.display());

    // A folder an earlier version wrote, without a manifest: the output
    // names of ours go, a file of the user's stays.
    fs::remove_file(out.join("manifest.json")).unwrap();
    fs::write(out.join("packing.lammps"), "old").unwrap();
    fs::write(out.join("notes.txt"), "mine").unwrap();
    run(&few);
    assert!(!out.join("packing.lammps").exists());
    assert!(out.join("notes.txt").exists());
}

// ---------------------------------------------------------------------------
// Whole-run atomicity: a run that fails leaves nothing of its own, and the
// earlier run's files as they were; links inside the folder are never
// followed.
// ---------------------------------------------------------------------------

/// Two small full fractures: a batch of two wells, `A-1/` and `B-2/`.
const BATCH: &str = "seed = 2\n[fracture]\nextent = \"full\"\nheight_m = 0.1\n\
    [[fracture.wells]]\nname = \"A-1\"\nwidth_mm = 2.6\n\
    [[fracture.wells]]\nname = \"B-2\"\nwidth_mm = 4.2\n\
    [grading]\npreset = \"20/40\"\nbasis = \"mass\"\n[output]\nformats = [\"csv\"]\n";

/// A store in memory that refuses any set holding a file under `refused`:
/// a write failure injected in the middle of a batch.
struct Refusing {
    inner: MemoryStore,
    refused: &'static str,
}

impl jobs::Store for Refusing {
    fn write(&mut self, files: &[(String, Vec<u8>)]) -> Result<(), jobs::StoreError> {
        if files.iter().any(|(name, _)| name.starts_with(self.refused)) {
            // Any store error will do: the job must write nothing at all.
            return Err(jobs::StoreError::Name(self.refused.to_owned()));
        }
        self.inner.write(files)
    }

    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, jobs::StoreError> {
        self.inner.read(name)
    }

    fn remove(&mut self, name: &str) -> Result<(), jobs::StoreError> {
        self.inner.remove(name)
    }

    fn location(&self) -> String {
        "refusing".to_owned()
    }
}

/// Every file under `dir` with its length and a hash of its bytes (a
/// link with its target, a folder with a `/`).
fn tree(dir: &std::path::Path) -> Vec<(String, String)> {
    use std::hash::{Hash, Hasher};
    let mut all = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let name = path.strip_prefix(dir).unwrap().display().to_string();
            let meta = fs::symlink_metadata(&path).unwrap();
            if meta.file_type().is_symlink() {
                let target = fs::read_link(&path).unwrap();
                all.push((name, format!("-> {}", target.display())));
            } else if meta.is_dir() {
                all.push((format!("{name}/"), String::new()));
                stack.push(path);
            } else {
                let bytes = fs::read(&path).unwrap();
                let mut h = std::collections::hash_map::DefaultHasher::new();
                bytes.hash(&mut h);
                all.push((name, format!("{} bytes, {:016x}", bytes.len(), h.finish())));
            }
        }
    }
    all.sort();
    all
}

#[test]
fn a_batch_whose_second_well_cannot_be_stored_leaves_nothing() {
    let plan = plan(BATCH, JobKind::Pack);
    let mut store = Refusing {
        inner: MemoryStore::default(),
        refused: "B-2/",
    };
    let err = jobs::run(&plan, &mut jobs::Silent, &Cancel::new(), &mut store)
        .expect_err("the second well cannot be stored");
    assert!(matches!(err, JobError::Store(_)), "{err:?}");
    assert!(!err.is_input());
    let left: Vec<&String> = store.inner.files.keys().collect();
    assert!(left.is_empty(), "a failed batch left {left:?}");

    // The same store takes the whole batch when nothing is refused.
    store.refused = "no such folder/";
    let outcome = jobs::run(&plan, &mut jobs::Silent, &Cancel::new(), &mut store).expect("runs");
    assert!(outcome.files.contains(&"A-1/packing.csv".to_owned()));
    assert!(outcome.files.contains(&"B-2/packing.csv".to_owned()));
    assert!(outcome.files.contains(&"wells.csv".to_owned()));
}

#[test]
fn a_failed_batch_leaves_the_earlier_run_as_it_was() {
    let dir = scratch("batch-blocked");
    let out = dir.join("out");
    let single = format!("{SQUARE}[output]\nformats = [\"csv\"]\n");
    jobs::run(
        &plan(&single, JobKind::Pack),
        &mut jobs::Silent,
        &Cancel::new(),
        &mut DirStore::new(&out),
    )
    .expect("the earlier run");
    // The second well's folder cannot be made: a file has its name.
    fs::write(out.join("B-2"), "mine").unwrap();
    let before = tree(&out);
    let err = jobs::run(
        &plan(BATCH, JobKind::Pack),
        &mut jobs::Silent,
        &Cancel::new(),
        &mut DirStore::new(&out),
    )
    .expect_err("B-2 cannot be a folder");
    assert!(!err.is_input(), "{err:?}");
    assert_eq!(
        tree(&out),
        before,
        "the folder is as the earlier run left it: no A-1/, no wells.csv, no temporary file"
    );
}

#[test]
fn a_symlinked_well_folder_is_never_written_or_removed_through() {
    let dir = scratch("batch-symlink");
    let out = dir.join("out");
    let elsewhere = dir.join("elsewhere");
    fs::create_dir_all(&out).unwrap();
    fs::create_dir_all(&elsewhere).unwrap();
    std::os::unix::fs::symlink("../elsewhere", out.join("A-1")).unwrap();
    let run = |text: &str| {
        jobs::run(
            &plan(text, JobKind::Pack),
            &mut jobs::Silent,
            &Cancel::new(),
            &mut DirStore::new(&out),
        )
    };
    let err = run(BATCH).expect_err("A-1 is a link");
    let message = format!("{:#}", anyhow::Error::from(err));
    let link = out.join("A-1");
    assert!(
        message.contains(&format!(
            "will not write through {}: it is a symbolic link",
            link.display()
        )),
        "{message}"
    );
    assert!(
        fs::read_dir(&elsewhere).unwrap().next().is_none(),
        "nothing is written out of the folder"
    );
    assert_eq!(
        tree(&out),
        [("A-1".to_owned(), "-> ../elsewhere".to_owned())]
    );

    // A batch written, then its well folder swapped for a link to a folder
    // holding a file of the same name: the next run's stale files are
    // never removed through the link.
    fs::remove_file(&link).unwrap();
    run(BATCH).expect("the batch");
    fs::remove_dir_all(&link).unwrap();
    fs::write(elsewhere.join("packing.csv"), "not gapack's").unwrap();
    std::os::unix::fs::symlink("../elsewhere", &link).unwrap();
    let before = tree(&out);
    let single = format!("{SQUARE}[output]\nformats = [\"csv\"]\n");
    let err = run(&single).expect_err("A-1 is a link");
    let message = format!("{:#}", anyhow::Error::from(err));
    assert!(message.contains("will not remove through"), "{message}");
    assert_eq!(
        fs::read(elsewhere.join("packing.csv")).unwrap(),
        b"not gapack's"
    );
    assert_eq!(tree(&out), before, "the failed run changed nothing");
}
