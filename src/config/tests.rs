//! Tests of config parsing and validation: one per rule, checking the whole
//! one-line message (origin, line, column, key path, reason).
//!
//! The tests marked "builds" call the `Domain`/`Grading` constructors and the
//! scene checks; the others fail before any of them is called.

use super::*;

mod domain;
mod fracture;
mod grading;
mod layering;
mod limits;
mod optimise;
mod output;
mod packer;
mod schema;
mod shape;

/// The error `text` gives; fails the test if it parses.
fn err(text: &str) -> ConfigError {
    match parse(text, "t.toml") {
        Err(e) => e,
        Ok(scene) => panic!("accepted:\n{text}\nas {scene:?}"),
    }
}

/// Asserts the full message of the error `text` gives.
fn fails_with(text: &str, message: &str) {
    assert_eq!(err(text).to_string(), message, "for:\n{text}");
}

/// A rectangle scene with `domain` lines and `rest` appended after the grading.
fn rect(domain: &str, rest: &str) -> String {
    format!("[domain]\nshape = \"rectangle\"\n{domain}\n[grading]\nconstant = 1.2\n{rest}")
}
