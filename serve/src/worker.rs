//! Workers: threads that claim queued jobs from the store under a lease
//! and run them with the jobs layer, exactly as the CLI does: the same
//! plan (with what the job was submitted with: its seed, `force`, its
//! checkpoint period), a [`DirStore`] on `DATA/jobs/<id>/`, a cancel token
//! per job, and an observer that appends each event to the store (while
//! the lease holds) and wakes the event streams. A job that ran before
//! (its worker stopped or was lost) resumes from its checkpoint.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use gapack::jobs::{
    self, Cancel, DirStore, Event, JobError, JobKind, Observer, Outcome, Plan, Store, Summary,
};

use super::Shared;
use super::lease::Running;
use super::store::{Claimed, Ending, JobRow, State};

/// The origin every submitted config is named by in messages and files
/// (`summary.json`, `manifest.json`): a run of `gapack <job> config.toml`
/// names its config the same way.
pub const ORIGIN: &str = "config.toml";

/// How long an idle worker sleeps before it looks at the queue again, if
/// nothing wakes it sooner.
const IDLE: Duration = Duration::from_millis(500);

/// How long a worker waits to write to a store that did not answer before
/// it tries again (until the store answers or the lease is given up).
const RETRY: Duration = Duration::from_millis(250);

/// The folder of job `id`'s files.
pub fn job_dir(shared: &Shared, id: &str) -> PathBuf {
    shared.data.join("jobs").join(id)
}

/// The name of this process's worker `index` in the store.
pub fn worker_name(shared: &Shared, index: usize) -> String {
    format!("{}:{index}", shared.name)
}

/// One worker's loop: claim, run, record; until the process stops.
pub fn work(shared: &Arc<Shared>, index: usize) {
    let name = worker_name(shared, index);
    while !shared.stopping.load(Ordering::SeqCst) {
        let job = match shared.store.claim(&name, shared.lease) {
            Ok(job) => job,
            Err(e) => {
                tracing::error!(worker = %name, error = %e, "cannot claim a job");
                None
            }
        };
        match job {
            Some(job) => run_one(shared, &name, job),
            None => shared.wait_for_work(IDLE),
        }
    }
}

/// Run one job `worker` claimed and record how it ended (unless its lease
/// was lost meanwhile: then another worker has the job, and nothing is
/// recorded).
pub fn run_one(shared: &Arc<Shared>, worker: &str, claimed: Claimed) {
    let Claimed { job, lease } = claimed;
    let id = job.id.clone();
    tracing::info!(job = %id, kind = %job.kind, owner = %job.owner, worker, attempt = job.attempts, resume = job.resume, state = "running", "job state");
    shared.notify(&id);
    let running = Running::new(worker, lease);
    let token = running.cancel.clone();
    let lost = Arc::clone(&running.lost);
    shared.register(&id, running);
    // A cancel or a stop that came between the claim and the registration.
    if shared.store.cancel_requested(&id).unwrap_or(false) || shared.stopping.load(Ordering::SeqCst)
    {
        token.cancel();
    }
    let started = Instant::now();
    let run_token = match shared.limits.max_seconds {
        Some(cap) => token.with_deadline(cap),
        None => token.clone(),
    };
    let result = catch_unwind(AssertUnwindSafe(|| {
        execute(shared, &job, lease, &lost, &run_token)
    }));
    if lost.load(Ordering::SeqCst) {
        shared.unregister(&id);
        shared.metrics.lease_lost();
        tracing::warn!(job = %id, worker, "the attempt ended without its lease: nothing recorded");
        return;
    }
    let user_cancel = shared.store.cancel_requested(&id).unwrap_or(false);
    let stopping = shared.stopping.load(Ordering::SeqCst);
    let ending = match result {
        Ok(Ok(outcome)) if !outcome.interrupted => Ending::Final {
            state: State::Succeeded,
            summary: Some(summary(&outcome)),
            error: None,
        },
        Ok(result) => {
            // Interrupted or cancelled: by whom?
            let kept = result.as_ref().ok().map(summary);
            if user_cancel {
                Ending::Final {
                    state: State::Cancelled,
                    summary: kept,
                    error: None,
                }
            } else if stopping && token.is_raised() {
                Ending::Requeue
            } else {
                match result {
                    Err(e) if !matches!(e, JobError::Cancelled) => Ending::Final {
                        state: State::Failed,
                        summary: None,
                        error: Some(format!("{:#}", anyhow::Error::from(e))),
                    },
                    _ => Ending::Final {
                        state: State::Failed,
                        summary: kept,
                        error: Some(format!(
                            "stopped at the server's run-time ceiling of {} s; what was finished is written",
                            shared.limits.max_seconds.map_or(0, |d| d.as_secs())
                        )),
                    },
                }
            }
        }
        Err(_) => Ending::Final {
            state: State::Failed,
            summary: None,
            error: Some("internal error: the job panicked".to_owned()),
        },
    };
    let seconds = started.elapsed().as_secs_f64();
    let state = match &ending {
        Ending::Final { state, .. } => *state,
        Ending::Requeue => State::Queued,
    };
    // Still registered: the keeper renews the lease while the end is
    // written (tried again while the store cannot be reached, until the
    // keeper gives the lease up).
    let recorded = loop {
        match shared.store.finish(worker, &id, lease, &ending) {
            Err(e) if !lost.load(Ordering::SeqCst) => {
                tracing::warn!(job = %id, worker, error = %e, "cannot record the job's end; trying again");
                std::thread::sleep(RETRY);
            }
            done => break done,
        }
    };
    shared.unregister(&id);
    match recorded {
        Ok(true) => {}
        Ok(false) => {
            shared.metrics.lease_lost();
            tracing::warn!(job = %id, worker, "the lease was lost before the job's end was recorded: another worker has it");
            return;
        }
        Err(e) => {
            // The lease runs out and the job goes back to the queue.
            tracing::error!(job = %id, worker, error = %e, "cannot record the job's end");
            return;
        }
    }
    if let Ending::Final { error, summary, .. } = &ending {
        let summary = summary.as_deref().and_then(|s| Summary::from_json(s).ok());
        let figure = |f: fn(&Summary) -> Option<u64>| summary.as_ref().and_then(f).unwrap_or(0);
        shared.metrics.finished(
            state,
            seconds,
            figure(|s| s.particles.map(|n| n as u64)),
            figure(|s| s.evaluations),
        );
        tracing::info!(job = %id, state = state.name(), seconds, error = error.as_deref().unwrap_or(""), "job state");
    } else {
        tracing::info!(job = %id, state = "queued", reason = "its worker stopped", "job state");
    }
    shared.notify(&id);
}

/// Plan and run the job as the CLI would.
fn execute(
    shared: &Shared,
    job: &JobRow,
    lease: i64,
    lost: &AtomicBool,
    cancel: &Cancel,
) -> Result<Outcome, JobError> {
    let kind = JobKind::named(&job.kind)
        .ok_or_else(|| JobError::Input(format!("unknown job kind {:?}", job.kind)))?;
    let mut store = DirStore::new(job_dir(shared, &job.id));
    // A restarted job goes on from what it left: a search from its
    // checkpoint, a study from the rows of its sweep.csv.
    let left = match kind {
        JobKind::Optimise => Some(jobs::CHECKPOINT_JSON),
        JobKind::Sweep => Some(gapack::output::SWEEP_CSV),
        _ => None,
    };
    let resume = job.resume && left.is_some_and(|f| matches!(store.read(f), Ok(Some(_))));
    let request = jobs::Request {
        seed: job.seed,
        force: job.force,
        resume,
        checkpoint_every: usize::try_from(job.checkpoint_every).unwrap_or(usize::MAX),
        ..jobs::Request::new(kind)
    };
    let plan = Plan::load(&job.config, ORIGIN, &request)?;
    let mut observer = Recorder {
        shared,
        id: &job.id,
        lease,
        lost,
        cancel,
    };
    jobs::run(&plan, &mut observer, cancel, &mut store)
}

/// A finished job's summary ([`Summary`]) as stored: its lines name the
/// job's folder as `jobs/<id>`, never by the server's own path.
fn summary(outcome: &Outcome) -> String {
    let shown = format!(
        "jobs/{}",
        outcome.location.rsplit('/').next().unwrap_or_default()
    );
    Summary::of(outcome, &shown)
        .to_json()
        .unwrap_or_else(|e| format!("{{\"error\": \"summary not written: {e}\"}}"))
}

/// The observer of a job run by the service: each event appended to the
/// store (the stream's source) under the attempt's lease, then the streams
/// woken. A lease found gone stops the run.
struct Recorder<'a> {
    shared: &'a Shared,
    id: &'a str,
    lease: i64,
    lost: &'a AtomicBool,
    cancel: &'a Cancel,
}

impl Observer for Recorder<'_> {
    fn event(&mut self, event: &Event) {
        let Ok(data) = serde_json::to_value(event) else {
            return;
        };
        let progress = matches!(
            event,
            Event::Stage { .. } | Event::Progress { .. } | Event::Generation { .. }
        );
        if self.lost.load(Ordering::SeqCst) {
            return;
        }
        match self
            .shared
            .store
            .event(self.id, self.lease, &data, progress)
        {
            Ok(Some(_)) => self.shared.notify(self.id),
            Ok(None) => {
                tracing::warn!(job = %self.id, "lease lost: another worker takes the job; this attempt stops");
                self.lost.store(true, Ordering::SeqCst);
                self.cancel.cancel();
            }
            Err(e) => {
                // Tried again until the store answers or the keeper gives
                // the lease up: no event is dropped while the store is away.
                tracing::warn!(job = %self.id, error = %e, "cannot record an event; trying again");
                while !self.lost.load(Ordering::SeqCst) {
                    std::thread::sleep(RETRY);
                    match self
                        .shared
                        .store
                        .event(self.id, self.lease, &data, progress)
                    {
                        Ok(Some(_)) => return self.shared.notify(self.id),
                        Ok(None) => {
                            self.lost.store(true, Ordering::SeqCst);
                            self.cancel.cancel();
                        }
                        Err(_) => {}
                    }
                }
            }
        }
    }
}
