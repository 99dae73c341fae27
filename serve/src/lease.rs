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

/// The keeper's loop, until this process's workers (named `workers`)
/// have all ended.
pub fn keep(shared: &Arc<Shared>, workers: &[String]) {
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
            // Idle workers too: a worker not seen for a lease is gone.
            if !workers.is_empty()
                && let Err(e) = shared.store.alive(workers)
            {
                tracing::warn!(error = %e, "cannot tell the store the workers are alive");
            }
        }
        std::thread::sleep(beat.saturating_sub(started.elapsed()));
    }
}

/// One heartbeat for every job running here.
fn renew(shared: &Shared, give_up: Duration) {
    let held: Vec<(String, i64, String)> = {
        let mut running = shared.lock_running();
        // A lease not renewed for too long is given up before trying again
        // (a call to an unreachable store may itself take seconds).
        for (id, entry) in running.iter_mut() {
            if entry.renewed.elapsed() >= give_up && !entry.lost.load(Ordering::SeqCst) {
                tracing::error!(job = %id, worker = %entry.worker, "lease not renewed in time: this attempt stops (another worker will resume the job)");
                entry.lose();
            }
        }
        running
            .iter()
            .filter(|(_, r)| !r.lost.load(Ordering::SeqCst))
            .map(|(id, r)| (id.clone(), r.lease, r.worker.clone()))
            .collect()
    };
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

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::sync::atomic::Ordering;
    use std::time::{Duration, Instant};

    use axum::http::Method;

    use crate::api::testing::{SQUARE, TestServer, on_both_stores};
    use crate::store::State;
    use crate::worker;

    /// A search long enough to be cancelled while it runs.
    const LONG: &str = "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 60\nheight = 60\n[grading]\nuniform = [1.0, 2.0]\n[optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 400\nstagnation = 1000\n";

    fn state_of(server: &TestServer, id: &str) -> State {
        let admin = &server.shared.admin;
        server
            .store(|s| s.get(admin, id))
            .expect("get")
            .expect("the job")
            .state
    }

    on_both_stores!(
        reaped,
        a_job_whose_worker_went_silent_is_reaped_and_run_again_to_its_end,
        |o| o.lease = std::time::Duration::from_millis(100)
    );
    on_both_stores!(
        cancelled,
        a_cancel_reaches_the_running_job_through_its_heartbeat,
        |o| o.lease = std::time::Duration::from_millis(400)
    );

    async fn a_job_whose_worker_went_silent_is_reaped_and_run_again_to_its_end(server: TestServer) {
        let id = server.submit("?kind=pack", SQUARE).await;
        // A worker claims it and is never heard of again.
        let claimed = server
            .store(|s| s.claim("gone:1:0", Duration::from_millis(100)))
            .expect("claim");
        assert_eq!(claimed.map(|c| c.job.id), Some(id.clone()));
        assert!(
            server.store(|s| s.reap()).expect("reap").is_empty(),
            "reaped before its lease ran out"
        );
        std::thread::sleep(Duration::from_millis(150));
        let reaped = server.store(|s| s.reap()).expect("reap");
        assert_eq!(reaped.len(), 1);
        assert_eq!(
            (reaped[0].state, reaped[0].worker.as_deref()),
            (State::Queued, Some("gone:1:0"))
        );
        assert_eq!(state_of(&server, &id), State::Queued);
        server.run_queued().await;
        let job = server.get(&format!("/api/v1/jobs/{id}")).await.json();
        assert_eq!(job["state"], "succeeded");
        assert_eq!(job["attempts"], 2);
        let events = server
            .store(|s| s.events_after(&id, 0, 100))
            .expect("events");
        let states: Vec<String> = events
            .iter()
            .filter_map(|(_, data)| {
                let v: serde_json::Value = serde_json::from_str(data).ok()?;
                (v["event"] == "state").then(|| {
                    format!(
                        "{}{}",
                        v["state"].as_str().unwrap_or(""),
                        v["reason"]
                            .as_str()
                            .map(|r| format!(" ({r})"))
                            .unwrap_or_default()
                    )
                })
            })
            .collect();
        assert_eq!(
            states,
            [
                "queued",
                "running",
                "queued (its worker was lost)",
                "running",
                "succeeded"
            ]
        );
        // Event numbers run on from the lost attempt's, without a gap.
        let numbers: Vec<i64> = events.iter().map(|(n, _)| *n).collect();
        assert_eq!(numbers, (1..=numbers.len() as i64).collect::<Vec<_>>());
        let workers = server.store(|s| s.workers()).expect("workers");
        let gone = workers
            .iter()
            .find(|w| w.name == "gone:1:0")
            .expect("the lost worker");
        assert_eq!((gone.claimed, gone.finished, gone.leases_lost), (1, 0, 1));
    }

    async fn a_cancel_reaches_the_running_job_through_its_heartbeat(server: TestServer) {
        let id = server.submit("?kind=optimise", LONG).await;
        let shared = Arc::clone(&server.shared);
        let keeper = std::thread::spawn({
            let shared = Arc::clone(&shared);
            move || super::keep(&shared, &[])
        });
        let run = tokio::task::spawn_blocking({
            let shared = Arc::clone(&shared);
            move || {
                let name = worker::worker_name(&shared, 0);
                let job = shared
                    .store
                    .claim(&name, shared.lease)
                    .expect("claim")
                    .expect("a job");
                worker::run_one(&shared, &name, job);
            }
        });
        let start = Instant::now();
        while server
            .store(|s| s.events_after(&id, 0, 1000))
            .expect("events")
            .len()
            < 5
        {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "the search never started"
            );
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        // The flag alone, as a front on another machine sets it: only the
        // heartbeat carries it to the worker.
        let asked = Instant::now();
        let admin = shared.admin.clone();
        assert_eq!(
            server.store(|s| s.cancel(&admin, &id)).expect("cancel"),
            Some(crate::store::CancelOutcome::Stopping)
        );
        run.await.expect("the run ended");
        let took = asked.elapsed();
        shared.crew_done.store(true, Ordering::SeqCst);
        keeper.join().expect("the keeper ended");
        assert_eq!(state_of(&server, &id), State::Cancelled);
        // A heartbeat is due every 100 ms; the search checks its token often.
        assert!(took < Duration::from_secs(10), "{took:?}");
        let r = server
            .call(Method::GET, &format!("/api/v1/jobs/{id}"), &[])
            .await;
        assert!(
            r.json()["summary"].is_object(),
            "the best packing is kept: {}",
            r.text()
        );
    }
}
