//! Fuzz `optimise --resume` with edited checkpoints: the input is the
//! `checkpoint.json` a search over `tests/data/replay/optimise.toml` resumes from.
//!
//! Structure-aware: the mutator parses the input as JSON and changes one
//! value of it (a number to 0, −1, a huge or a fractional value, a string,
//! an array cut, grown or emptied, a field removed), so that most inputs stay
//! checkpoints a resume reads far into; inputs that are not JSON get
//! libFuzzer's own byte mutations. Seeds are real checkpoints
//! (`cargo run --bin seed_checkpoints`).
//!
//! The contract: no input panics, hangs or allocates without bound; a
//! resume either refuses the checkpoint or runs the search to its end.
#![no_main]

use std::time::Duration;

use gapack::Cancel;
use gapack::jobs::{self, JobKind, MemoryStore, Plan, Request, Silent, Store};
use libfuzzer_sys::{fuzz_mutator, fuzz_target, fuzzer_mutate};
use serde_json::Value;

/// The edits, shared with the replay test of the main crate.
#[path = "../../tests/integration/common/json_edit.rs"]
mod json_edit;

/// The search the checkpoints belong to.
const CONFIG: &str = include_str!("../../tests/data/replay/optimise.toml");

fuzz_target!(|data: &[u8]| {
    let request = Request {
        resume: true,
        ..Request::new(JobKind::Optimise)
    };
    let plan = Plan::load(CONFIG, "optimise.toml", &request).expect("the fixture config is valid");
    let mut store = MemoryStore::default();
    store
        .write(&[(jobs::CHECKPOINT_JSON.to_owned(), data.to_vec())])
        .expect("memory store");
    // The search is 4 generations of 8 genomes: far under this deadline. A
    // resume that honours the token returns soon after it even if edited
    // counters asked for more; one that does not, hangs (libFuzzer's -timeout).
    let cancel = Cancel::new().with_deadline(Duration::from_secs(3));
    if let Err(error) = jobs::run(&plan, &mut Silent, &cancel, &mut store) {
        let _ = error.to_string();
    }
});

fuzz_mutator!(|data: &mut [u8], size: usize, max_size: usize, seed: u32| {
    let Ok(mut value) = serde_json::from_slice::<Value>(&data[..size]) else {
        return fuzzer_mutate(data, size, max_size);
    };
    let place = seed as usize % json_edit::places(&value);
    json_edit::edit_at(&mut value, place, seed >> 16);
    match serde_json::to_vec(&value) {
        Ok(bytes) if bytes.len() <= max_size => {
            data[..bytes.len()].copy_from_slice(&bytes);
            bytes.len()
        }
        _ => fuzzer_mutate(data, size, max_size),
    }
});
