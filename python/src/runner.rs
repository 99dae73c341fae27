//! A plan run on a thread of its own while the caller's thread, the GIL
//! released between polls, hands its events to Python and watches for
//! `KeyboardInterrupt`.

use std::sync::Mutex;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use gapack::jobs::{self, Cancel, Event, JobError, Outcome, Plan, Store};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;

use crate::errors::gapack_error;

/// How often the waiting thread looks for a `KeyboardInterrupt` when no
/// event comes: a Ctrl-C is seen within this, and the job (which polls its
/// token every few milliseconds) stops soon after.
const POLL: Duration = Duration::from_millis(20);

/// What a run left: the job's result, the store its files went to, the
/// warnings it gave, and the `KeyboardInterrupt` that cancelled it, if one did.
pub(crate) struct Finished<S> {
    pub result: Result<Outcome, JobError>,
    pub store: S,
    pub warnings: Vec<String>,
    pub interrupt: Option<PyErr>,
}

/// Run `plan` into `store` on a worker thread; each event goes to
/// `on_event` (a dict, as `json.loads` reads the event's JSON) on this
/// thread, with the GIL. A `KeyboardInterrupt` (or any error a signal
/// handler raises) raises the job's cancel token and is kept for the
/// caller; an error raised by `on_event` cancels the job too and is
/// returned once the job has stopped.
///
/// # Errors
/// The error `on_event` raised; a `GapackError` if the job's thread panicked.
pub(crate) fn run_plan<S: Store + Send>(
    py: Python<'_>,
    plan: &Plan,
    mut store: S,
    on_event: Option<&Bound<'_, PyAny>>,
) -> PyResult<Finished<S>> {
    let cancel = Cancel::new();
    let (tx, rx) = mpsc::channel::<Event>();
    // Waited on with the GIL released, hence from a closure that must be Send.
    let rx = Mutex::new(rx);
    let loads = py.import("json")?.getattr("loads")?;
    let mut warnings = Vec::new();
    let mut interrupt: Option<PyErr> = None;
    let mut failed: Option<PyErr> = None;
    let joined = std::thread::scope(|scope| {
        let (token, files) = (&cancel, &mut store);
        let worker = scope.spawn(move || {
            let mut observer = |event: &Event| {
                // The receiver outlives the job: a failed send cannot happen.
                let _ = tx.send(event.clone());
            };
            jobs::run(plan, &mut observer, token, files)
        });
        loop {
            let got = py.detach(|| match rx.lock() {
                Ok(rx) => rx.recv_timeout(POLL),
                Err(_) => Err(RecvTimeoutError::Disconnected),
            });
            match got {
                Ok(event) => {
                    if let Event::Warning(w) = &event {
                        warnings.push(w.message.clone());
                    }
                    if let (Some(callback), None) = (on_event, &failed) {
                        let told = serde_json::to_string(&event)
                            .map_err(|e| gapack_error(py, &format!("cannot read an event: {e}")))
                            .and_then(|json| loads.call1((json,)))
                            .and_then(|dict| callback.call1((dict,)));
                        match told {
                            Ok(_) => {}
                            // A signal's handler ran inside the callback (the
                            // interpreter runs them between bytecodes): Ctrl-C
                            // all the same.
                            Err(e) if e.is_instance_of::<PyKeyboardInterrupt>(py) => {
                                cancel.cancel();
                                interrupt.get_or_insert(e);
                            }
                            Err(e) => {
                                cancel.cancel();
                                failed = Some(e);
                            }
                        }
                    }
                }
                Err(RecvTimeoutError::Timeout) => {}
                // The job is over: its thread dropped the sender.
                Err(RecvTimeoutError::Disconnected) => break,
            }
            if interrupt.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.cancel();
                interrupt = Some(e);
            }
        }
        py.detach(move || worker.join())
    });
    if let Some(e) = failed {
        return Err(e);
    }
    let result = joined.map_err(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".to_owned());
        gapack_error(py, &format!("the job failed unexpectedly: {what}"))
    })?;
    Ok(Finished {
        result,
        store,
        warnings,
        interrupt,
    })
}
