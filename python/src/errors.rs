//! The library's errors as the Python exceptions of `gapack._errors`:
//! `ConfigError` (with `origin`, `line`, `column`, `key`) for a bad
//! config, `InputError` for a request the config does not fit, and
//! `GapackError`, their base, for a run that failed.

use std::error::Error;

use gapack::jobs::JobError;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// An instance of the exception class `name` of `gapack._errors`, made
/// with `args`, as an error to raise; if the class cannot be had (the
/// package is broken), a `RuntimeError` saying so.
fn raise<'py, A>(py: Python<'py>, name: &str, args: A) -> PyErr
where
    A: pyo3::call::PyCallArgs<'py>,
{
    let made = py
        .import("gapack._errors")
        .and_then(|m| m.getattr(name))
        .and_then(|class| class.call1(args));
    match made {
        Ok(instance) => PyErr::from_value(instance),
        Err(e) => PyRuntimeError::new_err(format!("gapack._errors.{name} is missing: {e}")),
    }
}

/// `GapackError(message)`.
pub(crate) fn gapack_error(py: Python<'_>, message: &str) -> PyErr {
    raise(py, "GapackError", (message,))
}

/// `InputError(message)`.
pub(crate) fn input_error(py: Python<'_>, message: &str) -> PyErr {
    raise(py, "InputError", (message,))
}

/// The message of `e` and of each error under it, joined by `: `
/// (`cannot pack the scene: the domain is narrower than …`).
fn chain(e: &dyn Error) -> String {
    let mut message = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let more = s.to_string();
        // A transparent wrapper repeats its source's message.
        if !message.ends_with(&more) {
            message.push_str(": ");
            message.push_str(&more);
        }
        source = s.source();
    }
    message
}

/// What Python adds to a `[limits]` refusal that `force=True` skips (the
/// library's message ends with the config keys that raise the limit).
const FORCE: &str = ", or pass force=True to go ahead";

/// A job's error as the exception a Python user catches.
pub(crate) fn job_error(py: Python<'_>, e: JobError) -> PyErr {
    match e {
        JobError::Config(c) => {
            let at = c.location();
            let force = if c.forceable() { FORCE } else { "" };
            raise(
                py,
                "ConfigError",
                (
                    format!("{c}{force}"),
                    at.origin.clone(),
                    at.line,
                    at.column,
                    c.key().map(str::to_owned),
                ),
            )
        }
        JobError::Input(message) => input_error(py, &message),
        other => gapack_error(py, &chain(&other)),
    }
}
