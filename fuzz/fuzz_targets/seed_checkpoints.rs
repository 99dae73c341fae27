//! Write real checkpoints of the checkpoint target's search into
//! `corpus/checkpoint/`: the search over `tests/data/replay/optimise.toml` stopped after
//! generation 1, 2 and 3 (a cancelled search saves its checkpoint).

use std::fs;

use gapack::Cancel;
use gapack::jobs::{self, Event, JobKind, MemoryStore, Plan, Request};

const CONFIG: &str = include_str!("../../tests/data/replay/optimise.toml");

fn main() {
    fs::create_dir_all("corpus/checkpoint").expect("corpus folder");
    for after in 1..=3 {
        let request = Request {
            checkpoint_every: 1,
            ..Request::new(JobKind::Optimise)
        };
        let plan = Plan::load(CONFIG, "optimise.toml", &request).expect("valid config");
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
        let bytes = store
            .files
            .get(jobs::CHECKPOINT_JSON)
            .expect("a stopped search keeps its checkpoint");
        let path = format!("corpus/checkpoint/seed_{after}.json");
        fs::write(&path, bytes).expect("write seed");
        println!("{path}: {} bytes", bytes.len());
    }
}
