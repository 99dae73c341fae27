//! Every command the README and the guide pages show runs as written: the
//! `sh` blocks' lines and the `cargo run --release -- …` quoted in their
//! text, page after page (`PAGES`, the README first), in order, in one
//! clean folder holding a copy of `configs/` (a page may use what an
//! earlier one wrote), each `cargo run --release -- ARGS` run as `gapack
//! ARGS` and expected to succeed, a command shown on two pages run once.
//! The lines that are not gapack runs, the one run of minutes (the
//! stability sweep) and the benchmarks are named here with where they are
//! run instead, or why they are not, so a new kind of line fails this test
//! until it is given a place; quoted commands with a placeholder in
//! capitals (`configs/apN.toml`) are forms, not commands.

use crate::common;

use std::fs;
use std::path::Path;

use common::{gapack, scratch};

/// The pages whose commands this test runs, from the repository root, in
/// order: the README, then the guide's pages (docs/SUMMARY.md).
const PAGES: &[&str] = &[
    "README.md",
    "docs/getting-started.md",
    "docs/concepts.md",
    "docs/faq.md",
    "docs/usage.md",
    "docs/shapes.md",
    "docs/optimise.md",
    "docs/layering.md",
    "docs/fractures.md",
    "docs/compare.md",
    "docs/sweep.md",
    "docs/strips.md",
    "docs/how-it-works.md",
    "docs/reliability.md",
    "docs/results.md",
    "docs/performance.md",
    "benchmarks/README.md",
    "CONTRIBUTING.md",
];

/// Lines of the pages' `sh` blocks (and quoted commands) that this test
/// does not run, by their start, and why.
const ELSEWHERE: &[(&str, &str)] = &[
    (
        "cargo run --release -- stability ",
        "the whole sweep takes minutes: tests/integration/stability.rs runs `gapack stability` on a small scene within a time cap",
    ),
    ("cargo test", "the test command itself"),
    (
        "cargo build --release --features gapack-cli/mpi",
        "the MPI build: CI builds the tests with the feature",
    ),
    (
        "cargo install --path cli",
        "installs the binary the tests build and run as `gapack`",
    ),
    (
        "cargo build --release -p gapack-cli --features count-alloc",
        "the benchmark build with the counting allocator (docs/performance.md): measured, not asserted",
    ),
    (
        "cargo build --release",
        "a release build: the tests build and run the same binary",
    ),
    ("cargo fmt", "formatting: .ci/run checks it"),
    ("cargo clippy", "the lints: .ci/run runs them"),
    ("CI=true bash .ci/run", "CI itself, on a clean clone"),
    (
        "cargo bench",
        "a benchmark: its figures are measured, not asserted, and take minutes; `cargo test` builds the benches",
    ),
    (
        "cargo rustc --release",
        "a benchmark build linked in a random layout (docs/performance.md): measured, not asserted",
    ),
    (
        "RAYON_NUM_THREADS=",
        "`gapack bench` at full size (minutes): tests/integration/cli.rs runs `gapack bench` on small scenes",
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
        "the Python package from the checkout: .ci/run builds the same sources as a wheel, installs it in a fresh virtualenv and runs python/tests against it (test_readme.py runs the README's Python blocks)",
    ),
    (
        "pip install maturin",
        "the wheel's builder: .ci/run installs it, builds the wheel and installs it in a fresh virtualenv",
    ),
    (
        "maturin build",
        "the wheel: .ci/run builds it so and runs python/tests against it in a fresh virtualenv",
    ),
    (
        "pip install dist/",
        "the wheel: .ci/run installs it so, in a fresh virtualenv",
    ),
    (
        "cargo run --release -- completions ",
        "the completion scripts: tests/integration/cli_conventions.rs loads bash's in bash and checks the others",
    ),
    (
        "cargo run --release -- man ",
        "the manual: tests/integration/cli_conventions.rs renders it with man -l and writes the pages with --dir",
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

/// The lines of a page's `sh` blocks (comments and blank lines left out)
/// and the `cargo run --release -- …` quoted in its text, in order.
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
    let dir = scratch("readme");
    copy_dir(&root.join("configs"), &dir.join("configs"));
    let mut done: Vec<String> = Vec::new();
    for page in PAGES {
        let text = fs::read_to_string(root.join(page)).unwrap_or_else(|e| panic!("{page}: {e}"));
        let mut ran = 0;
        for line in shell_lines(&text) {
            if ELSEWHERE.iter().any(|(start, _)| line.starts_with(start)) {
                continue;
            }
            if let Some(rest) = line.strip_prefix("cargo run --release -- ") {
                // Without the trailing comment.
                let command = rest.split(" #").next().unwrap_or(rest).trim().to_owned();
                ran += 1;
                if done.contains(&command) {
                    continue;
                }
                let args: Vec<&str> = command.split_whitespace().collect();
                let out = gapack(&dir, &args);
                assert!(
                    out.status.success(),
                    "{page}: command failed: {line}\n{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                );
                done.push(command);
                continue;
            }
            panic!("{page}: a command this test neither runs nor knows a place for: {line}");
        }
        if *page == "README.md" {
            assert!(ran >= 8, "only {ran} gapack commands found in the README");
        }
    }
}

/// A docs page that shows a `cargo run --release -- …` command is one of
/// `PAGES`, so that its commands are run too.
#[test]
fn every_page_showing_gapack_runs_is_listed() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    for entry in fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let page = format!("docs/{}", path.file_name().unwrap().to_string_lossy());
        if PAGES.contains(&page.as_str()) {
            continue;
        }
        let text = fs::read_to_string(&path).unwrap();
        if let Some(line) = shell_lines(&text)
            .into_iter()
            .find(|l| l.starts_with("cargo run --release -- "))
        {
            panic!("{page} shows `{line}` but is not in PAGES");
        }
    }
}
