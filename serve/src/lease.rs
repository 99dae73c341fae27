//! Keeping leases: each process's keeper thread renews the lease of every
//! job its workers run (a heartbeat every second, or a quarter of the
//! lease if shorter), raises a job's cancel token when a user asked to
//! cancel it (from any front) or when its lease is lost, and reaps the
//! leases of lost workers, in any process, so that their jobs go back to
//! the queue. A worker that cannot renew a lease for most of its length
//! (the store unreachable, the machine cut off) stops the job itself, so
//! that it has stopped writing before another worker may take the job.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use gapack::jobs::Cancel;

use super::Shared;
use super::store::{Beat, Notice, State};

/// A job running in this process.
pub struct Running {
    /// Its cancel token (a user's cancel, a stop, a lost lease).
    pub cancel: Cancel,
    /// The lease it runs under.
    pub lease: i64,
    /// The worker running it.
    pub worker: String,
    /// Set when the lease is lost: the attempt records nothing more.
    pub lost: Arc<AtomicBool>,
    /// When the lease was last renewed (or claimed).
    pub renewed: Instant,
}

impl Running {
    /// A job just claimed by `worker` under `lease`.
    pub fn new(worker: &str, lease: i64) -> Running {
        Running {
            cancel: Cancel::new(),
            lease,
            worker: worker.to_owned(),
            lost: Arc::new(AtomicBool::new(false)),
            renewed: Instant::now(),
        }
    }

    /// Give the job up: nothing more is recorded, the run stops.
    fn lose(&self) {
        self.lost.store(true, Ordering::SeqCst);
        self.cancel.cancel();
    }
}

/// The time between two heartbeats of a lease of `ttl`.
pub fn beat(ttl: Duration) -> Duration {
    (ttl / 4)
        .min(Duration::from_secs(1))
        .max(Duration::from_millis(10))
}

/// The keeper's loop, until this process's workers have all ended.
pub fn keep(shared: &Arc<Shared>) {
    let beat = beat(shared.lease);
    // A lease not renewed for this long is given up here: the store lets
    // another worker take the job only once the whole lease has passed.
    let give_up = shared.lease.saturating_sub(beat);
    let mut last_reap = Instant::now()
        .checked_sub(shared.lease)
        .unwrap_or_else(Instant::now);
    while !shared.crew_done.load(Ordering::SeqCst) {
        let started = Instant::now();
        renew(shared, give_up);
        // Reaped twice per lease: a lost job waits at most 1.5 leases.
        if last_reap.elapsed() >= shared.lease / 2 {
            last_reap = Instant::now();
            reap(shared);
        }
        std::thread::sleep(beat.saturating_sub(started.elapsed()));
    }
}

/// One heartbeat for every job running here.
fn renew(shared: &Shared, give_up: Duration) {
    let held: Vec<(String, i64, String)> = shared
        .lock_running()
        .iter()
        .map(|(id, r)| (id.clone(), r.lease, r.worker.clone()))
        .collect();
    for (id, lease, worker) in held {
        let beat = shared.store.heartbeat(&worker, &id, lease, shared.lease);
        let mut running = shared.lock_running();
        let Some(entry) = running.get_mut(&id) else {
            continue;
        };
        match beat {
            Ok(Beat::Held { cancel_requested }) => {
                entry.renewed = Instant::now();
                if cancel_requested {
                    entry.cancel.cancel();
                }
            }
            Ok(Beat::Lost) => {
                tracing::warn!(job = %id, worker = %worker, "lease lost: another worker takes the job; this attempt stops and records nothing more");
                entry.lose();
            }
            Err(e) if entry.renewed.elapsed() >= give_up => {
                tracing::error!(job = %id, worker = %worker, error = %e, "lease not renewed in time: this attempt stops (another worker will resume the job)");
                entry.lose();
            }
            Err(e) => {
                tracing::warn!(job = %id, worker = %worker, error = %e, "cannot renew a lease; trying again");
            }
        }
    }
}

/// Put the jobs of lost workers back in the queue.
fn reap(shared: &Shared) {
    match shared.store.reap() {
        Ok(reaped) => {
            for job in &reaped {
                tracing::warn!(job = %job.id, worker = job.worker.as_deref().unwrap_or(""), state = job.state.name(), "lease expired: its worker was lost");
                shared.metrics.reaped();
                shared.notify(&job.id);
            }
            if reaped.iter().any(|j| j.state == State::Queued) {
                shared.wake_all();
            }
        }
        Err(e) => tracing::warn!(error = %e, "cannot reap expired leases"),
    }
}

/// Pass other processes' news on: events to the streams, queued jobs to
/// idle workers, cancels to running jobs. Ends when the store's listener
/// does.
pub fn listen(shared: &Shared, news: &Receiver<Notice>) {
    while let Ok(notice) = news.recv() {
        match notice {
            Notice::Event(id) => shared.notify(&id),
            Notice::Queued => shared.wake_worker(),
            Notice::Cancel(id) => shared.cancel_running(&id),
            Notice::Resync => {
                tracing::info!("the store's notifications are back");
                shared.wake_all();
            }
        }
    }
}
