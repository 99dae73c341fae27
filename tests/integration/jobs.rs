//! The jobs layer as a front end sees it: events in order with the right
//! totals, every job kind cancelled part-way keeping what it finished, a
//! reused output folder left holding only the new run's files.

use crate::common;

use std::fs;
use std::time::{Duration, Instant};

use gapack::check;
use gapack::jobs::{
    self, Cancel, DirStore, Event, JobError, JobKind, Manifest, MemoryStore, Outcome, Plan, Report,
    Request, Stage, Summary, WarningKind,
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

/// `manifest.json` read back as a [`Manifest`] says what the run was, and
/// written again gives the same bytes.
#[test]
fn a_manifest_reads_back_and_writes_the_same_bytes() {
    let plan = plan(SQUARE, JobKind::Pack);
    let mut store = MemoryStore::default();
    let (outcome, _) = recorded(&plan, &mut store, |_| false);
    let outcome = outcome.expect("packs");
    let bytes = &store.files["manifest.json"];
    let read = Manifest::from_bytes(bytes).expect("a manifest");
    assert_eq!(read.job, JobKind::Pack);
    assert_eq!(read.seed, 3);
    assert_eq!(read.identity, plan.identity);
    assert_eq!(read.files, outcome.files);
    assert!(!read.interrupted);
    assert_eq!(&read.to_bytes().expect("json"), bytes);
    assert!(Manifest::from_bytes(b"{}").is_err());
}

/// A request that names no job plans the config's own: sweep with a
/// `[sweep]` table, else optimise with an `[optimise]` one, else pack.
#[test]
fn a_request_without_a_job_plans_the_config_s_own() {
    let own = |text: &str| {
        Plan::load(text, "t.toml", &Request::natural())
            .expect("plans")
            .kind
    };
    assert_eq!(own(SQUARE), JobKind::Pack);
    let search = format!("{SQUARE}[optimise]\ntarget_porosity = 0.2\n");
    assert_eq!(own(&search), JobKind::Optimise);
    let study = format!("{search}[sweep]\n\"domain.width\" = [20.0, 22.0]\n");
    assert_eq!(own(&study), JobKind::Sweep);
    // A job asked for is planned as asked.
    let asked = Plan::load(&study, "t.toml", &Request::new(JobKind::Pack)).expect("plans");
    assert_eq!(asked.kind, JobKind::Pack);
}

/// The summary of a finished job holds its lines, its files and the
/// figures of its packing; a search's, its effort too.
#[test]
fn a_summary_holds_the_figures_of_its_job() {
    let plan = plan(SQUARE, JobKind::Pack);
    let mut store = MemoryStore::default();
    let outcome = recorded(&plan, &mut store, |_| false).0.expect("packs");
    let summary = Summary::of(&outcome, "jobs/x");
    let Report::Pack { metrics, .. } = &outcome.report else {
        panic!("a pack report");
    };
    assert_eq!(summary.particles, Some(metrics.particles));
    assert_eq!(summary.porosity, Some(metrics.porosity));
    assert_eq!(summary.generations, None);
    assert_eq!(summary.files, outcome.files);
    assert!(
        summary.lines[0].starts_with("jobs/x: "),
        "{:?}",
        summary.lines
    );
    let json = summary.to_json().expect("json");
    assert!(!json.contains("generations"), "{json}");
    let read = Summary::from_json(&json).expect("reads");
    assert_eq!(
        (read.particles, &read.files, &read.lines),
        (summary.particles, &summary.files, &summary.lines)
    );
    assert!((read.porosity.unwrap() - metrics.porosity).abs() < 1e-12);
    let search =
        format!("{SQUARE}[optimise]\ntarget_porosity = 0.2\npopulation = 4\ngenerations = 1\n");
    let plan = self::plan(&search, JobKind::Optimise);
    let outcome = recorded(&plan, &mut MemoryStore::default(), |_| false)
        .0
        .expect("searches");
    let summary = Summary::of(&outcome, &outcome.location);
    let Report::Optimise { summary: s, .. } = &outcome.report else {
        panic!("an optimise report");
    };
    assert_eq!(summary.generations, Some(s.generations));
    assert_eq!(summary.evaluations, Some(s.evaluations));
    assert_eq!(summary.target_porosity, Some(0.2));
    assert_eq!(summary.lines, outcome.lines());
}

#[test]
fn a_search_reports_every_generation_and_its_total() {
    let text = format!(
        "{SQUARE}[optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 4\nstagnation = 100\n"
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
    // Four generations, fewer than `stagnation`: no verdict on the target.
    assert!(
        events.iter().any(|e| matches!(e, Event::Warning(w) if w.kind == WarningKind::TargetNotReached && w.message.contains("was not reached in"))),
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
        "{SQUARE}[optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 6\nstagnation = 100\n"
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
    let text = fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
        "/configs/wells.toml"
    ))
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
    let wells = fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
        "/configs/wells.toml"
    ))
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
// Hardening (h16-d): edited checkpoints refused at load, honest verdicts on a
// search's target, warnings for packings that bend their grading, compare on
// a batch of wells.
// ---------------------------------------------------------------------------

/// A search of `SQUARE` cancelled after generation 2: its store holds a checkpoint.
fn stopped_search() -> (String, MemoryStore) {
    let text = format!(
        "{SQUARE}[optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 6\nstagnation = 100\n"
    );
    let mut store = MemoryStore::default();
    let (outcome, _) = recorded(&plan(&text, JobKind::Optimise), &mut store, |e| {
        matches!(e, Event::Generation { index: 2, .. })
    });
    assert!(outcome.expect("keeps its best").interrupted);
    (text, store)
}

/// Resume the search of `text` from its checkpoint in `store` edited by `edit`.
fn resume_edited(
    text: &str,
    store: &MemoryStore,
    edit: impl FnOnce(&mut serde_json::Value),
) -> Result<Outcome, JobError> {
    let mut store = store.clone();
    let mut file: serde_json::Value =
        serde_json::from_slice(&store.files["checkpoint.json"]).unwrap();
    edit(&mut file["search"]);
    store.files.insert(
        "checkpoint.json".to_owned(),
        serde_json::to_vec(&file).unwrap(),
    );
    let resume = Request {
        resume: true,
        ..Request::new(JobKind::Optimise)
    };
    let plan = Plan::load(text, "t.toml", &resume).expect("plans");
    recorded(&plan, &mut store, |_| false).0
}

#[test]
fn an_edited_checkpoint_is_refused_at_load_naming_what_differs() {
    let (text, store) = stopped_search();
    resume_edited(&text, &store, |_| {}).expect("the untouched checkpoint resumes");
    let genes = {
        let file: serde_json::Value =
            serde_json::from_slice(&store.files["checkpoint.json"]).unwrap();
        file["search"]["best"][0].as_array().unwrap().len()
    };
    type Edit = Box<dyn FnOnce(&mut serde_json::Value)>;
    let cases: Vec<(Edit, String)> = vec![
        (
            // Spun for ever in the mutation's normal draws before.
            Box::new(|c| c["rng"]["s"] = serde_json::json!([0, 0, 0, 0])),
            "random generator's state is all zeros".to_owned(),
        ),
        (
            // Said "holds genomes of N genes, the search needs N" before.
            Box::new(|c| {
                c["best"][0].as_array_mut().unwrap().pop();
            }),
            format!(
                "the best genome holds {} genes, the search needs {genes}",
                genes - 1
            ),
        ),
        (
            Box::new(|c| c["population"][1][0][0] = serde_json::json!((-3.0f64).to_bits())),
            "gene 0 of genome 1 of the population is -3".to_owned(),
        ),
        (
            Box::new(|c| c["history"][2][6] = serde_json::json!(u64::MAX)),
            "history: generation 2 counts".to_owned(),
        ),
    ];
    for (edit, says) in cases {
        let err = resume_edited(&text, &store, edit).expect_err(&says);
        assert!(err.is_input(), "{err}");
        let message = err.to_string();
        assert!(message.contains(&says), "{message} does not say {says:?}");
    }
}

#[test]
fn a_short_search_is_not_reached_and_never_out_of_reach() {
    // AP-3's scene: 2 genomes for 1 generation span [0.2251, 0.2517], and
    // were called out of reach of 0.4, which a real search reaches (0.4005).
    let ap3 = fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
        "/configs/ap3.toml"
    ))
    .expect("shipped config")
    .replace("target_porosity = 0.5", "target_porosity = 0.4")
    .replace("population = 64", "population = 2")
    .replace("generations = 200", "generations = 1");
    let plan = plan(&ap3, JobKind::Optimise);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&plan, &mut store, |_| false);
    let outcome = outcome.expect("searches");
    let warnings: Vec<_> = events
        .iter()
        .filter_map(|e| match e {
            Event::Warning(w) => Some(w),
            _ => None,
        })
        .collect();
    assert!(
        !warnings.iter().any(|w| w.message.contains("out of reach")),
        "{warnings:?}"
    );
    let not_reached = warnings
        .iter()
        .find(|w| w.kind == WarningKind::TargetNotReached)
        .expect("a not-reached warning");
    assert!(
        not_reached
            .message
            .contains("was not reached in 4 evaluations in 1 generation of 2 genomes"),
        "{}",
        not_reached.message
    );
    let summary: serde_json::Value = serde_json::from_slice(&store.files["summary.json"]).unwrap();
    assert_eq!(summary["feasible"], serde_json::Value::Null);
    assert_eq!(summary["verdict"], "not reached");
    assert!(
        outcome.lines()[0].contains("target not reached"),
        "{:?}",
        outcome.lines()
    );
}

#[test]
fn a_search_where_no_packing_honours_the_grading_writes_no_infinite_range() {
    // A KS limit no packing of a few dozen disks meets.
    let text = format!(
        "{SQUARE}[optimise]\ntarget_porosity = 0.3\npopulation = 4\ngenerations = 2\nstagnation = 100\nmax_psd_ks = 0.001\n"
    );
    let plan = plan(&text, JobKind::Optimise);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&plan, &mut store, |_| false);
    let outcome = outcome.expect("writes the packing nearest to the grading");
    let summary_text = String::from_utf8(store.files["summary.json"].clone()).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary_text).unwrap();
    assert_eq!(summary["achievable_range"], serde_json::Value::Null);
    let said: Vec<String> = events
        .iter()
        .filter_map(|e| match e {
            Event::Warning(w) => Some(w.message.clone()),
            _ => None,
        })
        .chain(outcome.lines())
        .collect();
    assert!(
        said.iter()
            .any(|m| m.contains("no packing honoured the grading")),
        "{said:?}"
    );
    for text in said.iter().chain([&summary_text]) {
        assert!(!text.contains("inf"), "an infinite range: {text}");
    }
}

/// 66 disks of 0.5–5 mm in a 20 mm square, seed 0: the sizes left waiting
/// when the square is full are the large ones; KS 0.278 against a limit of
/// 0.217. Seed 1 keeps the grading (0.104 ≤ 0.248).
const BENT: &str = "seed = 0\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [0.5, 5.0]\n";

#[test]
fn a_packing_that_bends_its_grading_is_said_so_and_recorded() {
    for (seed, bent) in [(0, true), (1, false)] {
        let text = BENT.replace("seed = 0", &format!("seed = {seed}"));
        let plan = plan(&text, JobKind::Pack);
        let mut store = MemoryStore::default();
        let (outcome, events) = recorded(&plan, &mut store, |_| false);
        let outcome = outcome.expect("packs");
        // What `gapack verify` judges: the independent check against the grading.
        let bytes = &store.files["packing.csv"];
        let table = read_packing_csv(std::str::from_utf8(bytes).unwrap(), "packing.csv").unwrap();
        let scene = &plan.config.scene;
        let verified = check(&table.disks, &scene.domain, Some(&scene.grading));
        assert_eq!(verified.grading_kept(), !bent, "seed {seed}");
        let summary: serde_json::Value =
            serde_json::from_slice(&store.files["summary.json"]).unwrap();
        assert_eq!(summary["grading_kept"], !bent, "seed {seed}");
        let warned: Vec<_> = events
            .iter()
            .filter_map(|e| match e {
                Event::Warning(w) if w.kind == WarningKind::GradingBent => Some(&w.message),
                _ => None,
            })
            .collect();
        let line = &outcome.lines()[0];
        if bent {
            assert_eq!(warned.len(), 1, "{events:?}");
            for key in [
                "psd_ks 0.2778 exceeds 0.2174",
                "packer.max_deferred = 0",
                "seed",
            ] {
                assert!(warned[0].contains(key), "{} lacks {key}", warned[0]);
            }
            assert!(line.contains("grading bent"), "{line}");
        } else {
            assert!(warned.is_empty(), "{warned:?}");
            assert!(!line.contains("grading bent"), "{line}");
        }
    }
}

#[test]
fn every_well_of_a_batch_that_bends_its_grading_is_named() {
    // Well "a" is the bent square; well "b", twice as large, keeps it.
    let text = "seed = 0\n[fracture]\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 20\nheight_m = 0.02\n[[fracture.wells]]\nname = \"b\"\nwidth_mm = 40\nheight_m = 0.04\n[grading]\nuniform = [0.5, 5.0]\n";
    let plan = plan(text, JobKind::Pack);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&plan, &mut store, |_| false);
    outcome.expect("packs");
    let warned: Vec<_> = events
        .iter()
        .filter_map(|e| match e {
            Event::Warning(w) if w.kind == WarningKind::GradingBent => Some(&w.message),
            _ => None,
        })
        .collect();
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].starts_with("a/packing.csv bends the grading"),
        "{}",
        warned[0]
    );
    for (well, kept) in [("a", false), ("b", true)] {
        let summary: serde_json::Value =
            serde_json::from_slice(&store.files[&format!("{well}/summary.json")]).unwrap();
        assert_eq!(summary["grading_kept"], kept, "{well}");
    }
}

#[test]
fn compare_on_a_batch_names_the_wells_it_leaves_and_refuses_a_window() {
    let batch = "seed = 0\n[fracture]\nextent = \"EXTENT\"\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 8\nheight_m = 0.02\n[[fracture.wells]]\nname = \"b\"\nwidth_mm = 8\nheight_m = 0.03\n[grading]\nuniform = [1.0, 1.5]\n[compare]\nmethods = [\"advancing-front\"]\nrepeats = 1\n";
    let full = plan(&batch.replace("EXTENT", "full"), JobKind::Compare);
    let mut store = MemoryStore::default();
    let (outcome, events) = recorded(&full, &mut store, |_| false);
    outcome.expect("compares");
    assert!(
        events.iter().any(|e| matches!(e, Event::Warning(w)
            if w.kind == WarningKind::IgnoredWells
                && w.message.contains("fracture.wells")
                && w.message.contains("\"a\", packed whole"))),
        "{events:?}"
    );
    let err = Plan::load(
        &batch.replace("EXTENT", "window"),
        "t.toml",
        &Request::new(JobKind::Compare),
    )
    .expect_err("a window is not compared whole");
    assert!(err.is_input());
    assert!(
        err.to_string().contains("fracture.extent = \"window\""),
        "{err}"
    );
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

#[test]
fn a_relaxation_pack_refused_by_the_write_check_names_the_keys_to_change() {
    // Placed at 5 % porosity with one sweep: the overlaps stay.
    let text = format!(
        "{SQUARE}[packer]\nmethod = \"relaxation\"\nrelaxation_porosity = 0.05\nrelaxation_iterations = 1\n"
    );
    let plan = plan(&text, JobKind::Pack);
    let mut store = MemoryStore::default();
    let (outcome, _) = recorded(&plan, &mut store, |_| false);
    let Err(err @ JobError::Output(_)) = outcome else {
        panic!("{outcome:?}");
    };
    let message = format!("{:?}", err);
    for key in [
        "packer.relaxation_iterations",
        "packer.relaxation_porosity",
        "overlapping pairs",
    ] {
        assert!(message.contains(key), "{message}");
    }
    assert!(store.files.is_empty(), "nothing is written");
}
