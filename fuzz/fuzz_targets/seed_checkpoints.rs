//! Write real checkpoints of the checkpoint target's search into
//! `corpus/checkpoint/`: the search over `tests/data/replay/optimise.toml`
//! stopped after generation 1, 2 and 3.

use std::fs;

#[path = "../../tests/integration/common/stopped_search.rs"]
mod stopped_search;

fn main() {
    fs::create_dir_all("corpus/checkpoint").expect("corpus folder");
    for after in 1..=3 {
        let bytes = stopped_search::checkpoint_after(after);
        let path = format!("corpus/checkpoint/seed_{after}.json");
        fs::write(&path, &bytes).expect("write seed");
        println!("{path}: {} bytes", bytes.len());
    }
}
