//! The library's top-level modules depend on each other one way only: no
//! module reaches, through `crate::` paths in its non-test code, a module
//! that reaches it back (names re-exported by `lib.rs` count as their module's).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// Every `.rs` file under `path` (or the file itself).
fn sources(path: &Path, out: &mut Vec<String>) {
    if path.is_dir() {
        for entry in fs::read_dir(path).expect("read src") {
            sources(&entry.expect("entry").path(), out);
        }
    } else if path.extension().is_some_and(|e| e == "rs") {
        let text = fs::read_to_string(path).expect("read source");
        // Test modules may reach anywhere.
        out.push(text.split("#[cfg(test)]").next().unwrap_or("").to_owned());
    }
}

/// Identifiers following `crate::` in `text`.
fn crate_paths(text: &str) -> Vec<String> {
    text.match_indices("crate::")
        .map(|(i, _)| {
            text[i + 7..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

#[test]
fn no_module_depends_on_a_module_that_depends_on_it() {
    let src = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("src");
    let lib = fs::read_to_string(src.join("lib.rs")).expect("lib.rs");
    let mut modules = BTreeMap::new();
    for entry in fs::read_dir(&src).expect("read src") {
        let path = entry.expect("entry").path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if name == "lib" || name == "main" || !lib.contains(&format!("mod {name};")) {
            continue; // the binary's own modules are front ends
        }
        let mut texts = Vec::new();
        sources(&path, &mut texts);
        modules.insert(name, texts);
    }
    // `pub use module::{A, B}` at the root: A and B belong to `module`.
    let mut owner = BTreeMap::new();
    for part in lib.split("pub use ").skip(1) {
        let (module, rest) = part.split_once("::").unwrap_or(("", ""));
        let body = rest.split(';').next().unwrap_or("");
        for name in body.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
            if !name.is_empty() {
                owner.insert(name.to_owned(), module.to_owned());
            }
        }
    }
    let edges: BTreeMap<&String, BTreeSet<String>> = modules
        .iter()
        .map(|(name, texts)| {
            let targets = texts
                .iter()
                .flat_map(|t| crate_paths(t))
                .map(|t| owner.get(&t).cloned().unwrap_or(t))
                .filter(|t| t != name && modules.contains_key(t))
                .collect();
            (name, targets)
        })
        .collect();
    assert!(edges.len() > 10, "the modules were found: {edges:?}");
    // A cycle exists iff some module reaches itself.
    for start in edges.keys() {
        let mut seen = BTreeSet::new();
        let mut todo: Vec<&String> = edges[start].iter().collect();
        while let Some(m) = todo.pop() {
            assert_ne!(m, *start, "{start} reaches itself: {edges:?}");
            if seen.insert(m.clone()) {
                todo.extend(edges.get(m).into_iter().flatten());
            }
        }
    }
}
