//! `gapack._gapack`: the native half of the Python package `gapack`.
//!
//! Every run goes through the library's jobs layer ([`gapack::jobs::run`]),
//! as the command line's and the service's do: a [`Plan`] from the config's
//! text, the job on a thread of its own, its events to a Python callable,
//! `KeyboardInterrupt` to the job's [`gapack::Cancel`] token, the
//! [`gapack::jobs::Outcome`] to a `Packing` whose numpy arrays are made
//! once from the packed disks. The Python half (`gapack/__init__.py`) reads
//! configs (a path, TOML text or a dict), draws progress bars, turns the
//! events into warnings and defines the exceptions this module raises.
//!
//! No Rust panic crosses into Python: the job's thread is joined and a panic
//! there becomes a `GapackError`; pyo3 turns any other into a
//! `PanicException`.

mod convert;
mod errors;
mod packing;
mod runner;

use std::path::PathBuf;

use gapack::config::{self, ParseOptions};
use gapack::jobs::{self, DirStore, Job, JobKind, MemoryStore, Plan, Request, Summary};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use errors::{gapack_error, input_error, job_error};
use packing::Packing;
use runner::{Finished, run_plan};

/// The job named `name`, among `allowed`.
fn job_kind(name: &str, allowed: &[JobKind]) -> PyResult<JobKind> {
    allowed
        .iter()
        .copied()
        .find(|k| k.name() == name || (name == "optimize" && *k == JobKind::Optimise))
        .ok_or_else(|| {
            let names: Vec<&str> = allowed.iter().map(|k| k.name()).collect();
            PyValueError::new_err(format!("unknown job {name:?}; valid: {}", names.join(", ")))
        })
}

/// The request for the job named `job` among every job, or for the
/// config's own job ([`Request::natural`]) when `None`.
fn request_for(job: Option<&str>) -> PyResult<Request> {
    let kind = job.map(|name| job_kind(name, &JobKind::ALL)).transpose()?;
    Ok(Request::asking(kind))
}

/// Plan the job `request` asks for on the config `text` (named `origin`).
fn plan(py: Python<'_>, text: &str, origin: &str, request: &Request) -> PyResult<Plan> {
    Plan::load(text, origin, request).map_err(|e| job_error(py, e))
}

/// Run a `pack`, `optimise` or `layer` job on the config `text` (named
/// `origin`; read from `path` if it came from a file) and return its
/// packing, and whether a `KeyboardInterrupt` stopped it (the Python half
/// then raises `Interrupted` with the packing, or returns it).
///
/// The job runs with no output formats: its files are rendered when
/// `Packing.write` asks, from the same report.
#[pyfunction]
#[pyo3(signature = (kind, text, origin, path=None, seed=None, force=false, on_event=None))]
#[allow(clippy::too_many_arguments)]
fn run(
    py: Python<'_>,
    kind: &str,
    text: &str,
    origin: &str,
    path: Option<PathBuf>,
    seed: Option<u64>,
    force: bool,
    on_event: Option<Bound<'_, PyAny>>,
) -> PyResult<(Packing, bool)> {
    let kind = job_kind(kind, &[JobKind::Pack, JobKind::Optimise, JobKind::Layer])?;
    let request = Request {
        seed,
        force,
        // A search run from Python keeps no checkpoint: its files are
        // written later, where the user asks.
        checkpoint_every: 0,
        ..Request::new(kind)
    };
    let plan = plan(py, text, origin, &request)?;
    if matches!(plan.job, Job::Wells { .. }) {
        return Err(input_error(
            py,
            &format!(
                "{origin}: a [fracture] config packs each fracture into files of its own (a folder per well of a batch, wells.csv): run it with gapack.run(config, out=DIR), which writes them as the command line does"
            ),
        ));
    }
    let mut quiet = plan.clone();
    quiet.config.output.formats.clear();
    let Finished {
        result,
        store,
        warnings,
        interrupt,
    } = run_plan(py, &quiet, MemoryStore::default(), on_event.as_ref())?;
    let outcome = match result {
        Ok(outcome) => outcome,
        Err(e) => return Err(interrupt.unwrap_or_else(|| job_error(py, e))),
    };
    let packing = Packing::new(py, plan, outcome, (text.to_owned(), path), &store, warnings)?;
    Ok((packing, interrupt.is_some()))
}

/// Run any job on the config `text` straight into the folder `out` (the
/// config's `[output] dir`, else `out/<config name>`, when `None`), as the
/// command line does; return what it wrote, and whether a
/// `KeyboardInterrupt` stopped it.
#[pyfunction]
#[pyo3(signature = (text, origin, path=None, job=None, out=None, seed=None, force=false, resume=false, on_event=None))]
#[allow(clippy::too_many_arguments)]
fn run_to(
    py: Python<'_>,
    text: &str,
    origin: &str,
    path: Option<PathBuf>,
    job: Option<&str>,
    out: Option<PathBuf>,
    seed: Option<u64>,
    force: bool,
    resume: bool,
    on_event: Option<Bound<'_, PyAny>>,
) -> PyResult<(Py<PyAny>, bool)> {
    let request = Request {
        seed,
        force,
        resume,
        ..request_for(job)?
    };
    let plan = plan(py, text, origin, &request)?;
    let dir = jobs::output_dir(out.as_deref(), &plan.config, path.as_deref());
    let Finished {
        result, interrupt, ..
    } = run_plan(py, &plan, DirStore::new(&dir), on_event.as_ref())?;
    let outcome = match result {
        Ok(outcome) => outcome,
        Err(e) => return Err(interrupt.unwrap_or_else(|| job_error(py, e))),
    };
    // The job's summary (its files, lines and figures), as `json.loads`
    // reads its JSON, with where it went and its notes.
    let summary = Summary::of(&outcome, &outcome.location)
        .to_json()
        .map_err(|e| gapack_error(py, &format!("cannot read the summary: {e}")))?;
    let told = py
        .import("json")?
        .getattr("loads")?
        .call1((summary,))?
        .cast_into::<PyDict>()?;
    told.set_item("job", outcome.kind.name())?;
    told.set_item("location", &outcome.location)?;
    told.set_item("dir", dir.display().to_string())?;
    told.set_item("notes", &outcome.notes)?;
    Ok((told.into_any().unbind(), interrupt.is_some()))
}

/// Check the config `text` without running it: the plan the run would
/// execute, as `gapack validate` prints it, as a dict.
#[pyfunction]
#[pyo3(signature = (text, origin, path=None, job=None, seed=None, force=false))]
fn validate(
    py: Python<'_>,
    text: &str,
    origin: &str,
    path: Option<PathBuf>,
    job: Option<&str>,
    seed: Option<u64>,
    force: bool,
) -> PyResult<Py<PyAny>> {
    let request = Request {
        seed,
        force,
        ..request_for(job)?
    };
    let plan = plan(py, text, origin, &request)?;
    let out = jobs::output_dir(None, &plan.config, path.as_deref());
    let told = PyDict::new(py);
    told.set_item("valid", true)?;
    told.set_item("job", plan.kind.name())?;
    told.set_item("config", origin)?;
    told.set_item("seed", plan.seed())?;
    told.set_item("out", out.display().to_string())?;
    let warnings: Vec<&str> = plan.warnings.iter().map(|w| w.message.as_str()).collect();
    told.set_item("warnings", warnings)?;
    told.set_item("plan", plan.describe(&out.display().to_string()))?;
    Ok(told.into_any().unbind())
}

/// The independent check of disks `x`, `y`, `r` (mm) against the config
/// `text`'s domain and grading (`gapack::check`), as a dict; with `shapes`
/// (angle, a, b, alpha, beta), of those superellipses
/// (`gapack::check_particles_sized`).
#[pyfunction]
#[pyo3(signature = (x, y, r, text, origin, material=None, shapes=None))]
#[allow(clippy::too_many_arguments)]
fn verify(
    py: Python<'_>,
    x: numpy::PyReadonlyArray1<'_, f64>,
    y: numpy::PyReadonlyArray1<'_, f64>,
    r: numpy::PyReadonlyArray1<'_, f64>,
    text: &str,
    origin: &str,
    material: Option<numpy::PyReadonlyArray1<'_, i64>>,
    shapes: Option<[numpy::PyReadonlyArray1<'_, f64>; 5]>,
) -> PyResult<Py<PyAny>> {
    let options = ParseOptions { force: true };
    let parsed = config::parse_with(text, origin, options)
        .map_err(|e| job_error(py, jobs::JobError::from(e)))?;
    convert::verify(py, &parsed, origin, [x, y, r], material, shapes)
}

/// The module: the functions above, the packing class.
#[pymodule]
fn _gapack(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(run_to, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add_function(wrap_pyfunction!(verify, m)?)?;
    m.add_class::<Packing>()?;
    m.add("FORMATS", convert::format_names())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
