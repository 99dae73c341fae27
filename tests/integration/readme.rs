//! Every command the README shows runs as written: the `sh` blocks' lines
//! and the `cargo run --release -- …` quoted in its text, in order, in a
//! clean folder holding a copy of `configs/`, each `cargo run --release --
//! ARGS` run as `gapack ARGS` and expected to succeed. The lines that are
//! not gapack runs, and the one run of minutes (the stability sweep), are
//! named here with where they are run instead, so a
//! new kind of line fails this test until it is given a place; quoted
//! commands with a placeholder in capitals (`configs/apN.toml`) are forms,
//! not commands.

use crate::common;

use std::fs;
use std::path::Path;

use common::{gapack, scratch};

/// Lines of the README's `sh` blocks that this test does not run, by their
/// start, and why.
const ELSEWHERE: &[(&str, &str)] = &[
    (
        "cargo run --release -- stability ",
        "the whole sweep takes minutes: tests/integration/stability.rs runs `gapack stability` on a small scene within a time cap",
    ),
    ("cargo test", "the test command itself"),
    (
        "cargo build --release --features mpi",
        "the MPI build: CI builds the tests with the feature",
    ),
    (
        "mpirun ",
        "tests/integration/mpi.rs runs jobs under mpirun against plain runs",
    ),
    (
        "apt-get install",
        "installs the browser the browser tests need",
    ),
    (
        "gapack serve",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
    (
        "curl ",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
    (
        "ID=$(curl",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
    (
        "--data-binary",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
    (
        "'http://",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
    (
        "kill %1",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
    (
        "pip install ./python",
        "the Python package: .ci/run installs it so, then runs python/tests (test_readme.py runs the README's Python blocks)",
    ),
    (
        "python3 examples/python/",
        "the Python examples: python/tests/test_examples.py runs them",
    ),
    (
        "wait",
        "the service block: tests/integration/serve.rs runs it as a script",
    ),
];

/// The lines of the README's `sh` blocks (comments and blank lines left
/// out) and the `cargo run --release -- …` quoted in its text, in order.
fn shell_lines(readme: &str) -> Vec<String> {
    const QUOTED: &str = "`cargo run --release -- ";
    let mut lines = Vec::new();
    let mut in_block = false;
    let mut in_sh = false;
    for line in readme.lines() {
        if let Some(fence) = line.strip_prefix("```") {
            in_block = !in_block;
            in_sh = in_block && (fence == "sh" || fence == "bash");
            continue;
        }
        let line = line.trim();
        if in_sh && !line.is_empty() && !line.starts_with('#') {
            lines.push(line.to_owned());
        } else if !in_block {
            let mut rest = line;
            while let Some(at) = rest.find(QUOTED) {
                let command = &rest[at + 1..];
                let end = command.find('`').unwrap_or(command.len());
                if !command[..end].chars().any(|c| c.is_ascii_uppercase()) {
                    lines.push(command[..end].to_owned());
                }
                rest = &command[end..];
            }
        }
    }
    lines
}

/// Copy `from` into `to`, files only (the configs are flat).
fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
        }
    }
}

#[test]
fn every_readme_command_runs_as_written() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let readme = fs::read_to_string(root.join("README.md")).unwrap();
    let dir = scratch("readme");
    copy_dir(&root.join("configs"), &dir.join("configs"));
    let mut ran = 0;
    for line in shell_lines(&readme) {
        if ELSEWHERE.iter().any(|(start, _)| line.starts_with(start)) {
            continue;
        }
        if let Some(rest) = line.strip_prefix("cargo run --release -- ") {
            // Without the trailing comment.
            let command = rest.split(" #").next().unwrap_or(rest);
            let args: Vec<&str> = command.split_whitespace().collect();
            let out = gapack(&dir, &args);
            assert!(
                out.status.success(),
                "README command failed: {line}\n{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
            ran += 1;
            continue;
        }
        panic!("a README command this test neither runs nor knows a place for: {line}");
    }
    assert!(ran >= 8, "only {ran} gapack commands found in the README");
}
