//! A real checkpoint: the search of `tests/data/replay/optimise.toml`
//! stopped after a given generation (a cancelled search keeps its
//! checkpoint). Shared by the replay test and the checkpoint fuzz target's
//! seed writer.

use gapack::Cancel;
use gapack::jobs::{self, Event, JobKind, MemoryStore, Plan, Request};

/// The search the checkpoints belong to.
pub const CONFIG: &str = include_str!("../../data/replay/optimise.toml");

/// The origin the checkpoints are made and resumed under.
pub const ORIGIN: &str = "optimise.toml";

/// The `checkpoint.json` of the search stopped after generation `after`.
pub fn checkpoint_after(after: usize) -> Vec<u8> {
    checkpoint_of(CONFIG, ORIGIN, after)
}

/// The `checkpoint.json` of the search of `config` (named `origin`)
/// stopped after generation `after`.
pub fn checkpoint_of(config: &str, origin: &str, after: usize) -> Vec<u8> {
    let request = Request {
        checkpoint_every: 1,
        ..Request::new(JobKind::Optimise)
    };
    let plan = Plan::load(config, origin, &request).expect("valid fixture");
    let cancel = Cancel::new();
    let stop = cancel.clone();
    let mut observer = |event: &Event| {
        if let Event::Generation { index, .. } = event
            && *index >= after
        {
            stop.cancel();
        }
    };
    let mut store = MemoryStore::default();
    let _ = jobs::run(&plan, &mut observer, &cancel, &mut store);
    store
        .files
        .remove(jobs::CHECKPOINT_JSON)
        .expect("a stopped search keeps its checkpoint")
}
