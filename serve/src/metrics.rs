//! The counters behind `GET /metrics` (Prometheus text format): what the
//! store cannot count (durations, evaluations, disks, this process's
//! reaps) kept in memory since the process started; the jobs by state and
//! by user, the queue and every worker's counters (whatever process runs
//! it) come from the store.

use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};

use super::store::{State, UserCount, WorkerRow, now_ms};

/// Upper bounds (s) of the job-duration histogram's buckets.
const BUCKETS: [f64; 10] = [0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 1.0, 10.0, 60.0, 600.0];

/// Counters since the server started.
#[derive(Default)]
pub struct Metrics {
    /// Jobs finished, per final state (succeeded, failed, cancelled).
    finished: [AtomicU64; 3],
    /// Jobs whose run took at most each bucket's bound.
    buckets: [AtomicU64; BUCKETS.len()],
    /// Sum of run times (µs).
    micros: AtomicU64,
    /// Runs timed.
    runs: AtomicU64,
    /// GA evaluations of finished searches.
    evaluations: AtomicU64,
    /// Disks in the packings of finished jobs.
    disks: AtomicU64,
    /// Expired leases this process reaped (their jobs re-queued or ended).
    reaped: AtomicU64,
    /// Attempts this process's workers gave up, their lease lost.
    leases_lost: AtomicU64,
}

/// What the store says, for the metrics.
pub struct Stored<'a> {
    /// Jobs by state.
    pub counts: &'a [(State, i64)],
    /// Jobs by user and state.
    pub users: &'a [UserCount],
    /// Every worker's counters.
    pub workers: &'a [WorkerRow],
}

impl Metrics {
    /// A job reached `state` after a run of `seconds`, with `disks` packed
    /// and `evaluations` made.
    pub fn finished(&self, state: State, seconds: f64, disks: u64, evaluations: u64) {
        let slot = match state {
            State::Succeeded => 0,
            State::Failed => 1,
            _ => 2,
        };
        self.finished[slot].fetch_add(1, Ordering::Relaxed);
        for (bound, count) in BUCKETS.iter().zip(&self.buckets) {
            if seconds <= *bound {
                count.fetch_add(1, Ordering::Relaxed);
            }
        }
        self.micros
            .fetch_add((seconds * 1e6) as u64, Ordering::Relaxed);
        self.runs.fetch_add(1, Ordering::Relaxed);
        self.evaluations.fetch_add(evaluations, Ordering::Relaxed);
        self.disks.fetch_add(disks, Ordering::Relaxed);
    }

    /// This process reaped an expired lease.
    pub fn reaped(&self) {
        self.reaped.fetch_add(1, Ordering::Relaxed);
    }

    /// One of this process's workers lost a lease.
    pub fn lease_lost(&self) {
        self.leases_lost.fetch_add(1, Ordering::Relaxed);
    }

    /// The Prometheus text: these counters and the store's.
    pub fn render(&self, stored: &Stored<'_>) -> String {
        let counts = stored.counts;
        let mut out = String::new();
        let get = |a: &AtomicU64| a.load(Ordering::Relaxed);
        let _ = writeln!(out, "# HELP gapack_jobs Jobs in the store by state.");
        let _ = writeln!(out, "# TYPE gapack_jobs gauge");
        for (state, n) in counts {
            let _ = writeln!(out, "gapack_jobs{{state=\"{}\"}} {n}", state.name());
        }
        let queued = counts
            .iter()
            .find(|(s, _)| *s == State::Queued)
            .map_or(0, |(_, n)| *n);
        let _ = writeln!(out, "# HELP gapack_queue_length Jobs waiting for a worker.");
        let _ = writeln!(out, "# TYPE gapack_queue_length gauge");
        let _ = writeln!(out, "gapack_queue_length {queued}");
        let _ = writeln!(
            out,
            "# HELP gapack_jobs_finished_total Jobs finished since the server started, by final state."
        );
        let _ = writeln!(out, "# TYPE gapack_jobs_finished_total counter");
        for (state, slot) in [("succeeded", 0), ("failed", 1), ("cancelled", 2)] {
            let _ = writeln!(
                out,
                "gapack_jobs_finished_total{{state=\"{state}\"}} {}",
                get(&self.finished[slot])
            );
        }
        let _ = writeln!(
            out,
            "# HELP gapack_job_duration_seconds Run time of finished jobs."
        );
        let _ = writeln!(out, "# TYPE gapack_job_duration_seconds histogram");
        for (bound, count) in BUCKETS.iter().zip(&self.buckets) {
            let _ = writeln!(
                out,
                "gapack_job_duration_seconds_bucket{{le=\"{bound}\"}} {}",
                get(count)
            );
        }
        let runs = get(&self.runs);
        let _ = writeln!(
            out,
            "gapack_job_duration_seconds_bucket{{le=\"+Inf\"}} {runs}"
        );
        let _ = writeln!(
            out,
            "gapack_job_duration_seconds_sum {}",
            get(&self.micros) as f64 / 1e6
        );
        let _ = writeln!(out, "gapack_job_duration_seconds_count {runs}");
        let _ = writeln!(
            out,
            "# HELP gapack_ga_evaluations_total Genomes evaluated by finished searches."
        );
        let _ = writeln!(out, "# TYPE gapack_ga_evaluations_total counter");
        let _ = writeln!(
            out,
            "gapack_ga_evaluations_total {}",
            get(&self.evaluations)
        );
        let _ = writeln!(
            out,
            "# HELP gapack_packed_disks_total Disks in the packings of finished jobs."
        );
        let _ = writeln!(out, "# TYPE gapack_packed_disks_total counter");
        let _ = writeln!(out, "gapack_packed_disks_total {}", get(&self.disks));
        let _ = writeln!(
            out,
            "# HELP gapack_leases_reaped_total Expired leases this process reaped (their jobs re-queued, failed or cancelled)."
        );
        let _ = writeln!(out, "# TYPE gapack_leases_reaped_total counter");
        let _ = writeln!(out, "gapack_leases_reaped_total {}", get(&self.reaped));
        let _ = writeln!(
            out,
            "# HELP gapack_attempts_abandoned_total Attempts this process's workers gave up, their lease lost."
        );
        let _ = writeln!(out, "# TYPE gapack_attempts_abandoned_total counter");
        let _ = writeln!(
            out,
            "gapack_attempts_abandoned_total {}",
            get(&self.leases_lost)
        );
        render_stored(&mut out, stored);
        out
    }
}

/// The store's per-user and per-worker figures.
fn render_stored(out: &mut String, stored: &Stored<'_>) {
    let _ = writeln!(
        out,
        "# HELP gapack_user_jobs Jobs in the store by owner and state."
    );
    let _ = writeln!(out, "# TYPE gapack_user_jobs gauge");
    for c in stored.users {
        let _ = writeln!(
            out,
            "gapack_user_jobs{{user=\"{}\",state=\"{}\"}} {}",
            label(&c.user),
            c.state.name(),
            c.jobs
        );
    }
    let now = now_ms();
    // A name not seen for a day (a worker under a name never used again,
    // such as host:pid) leaves the figures.
    let workers: Vec<&WorkerRow> = stored
        .workers
        .iter()
        .filter(|w| now - w.seen_ms <= FORGOTTEN_MS)
        .collect();
    let series: [Series; 3] = [
        (
            "gapack_worker_claimed_total",
            "counter",
            "Jobs each worker claimed.",
            |w| w.claimed,
        ),
        (
            "gapack_worker_finished_total",
            "counter",
            "Attempts each worker ended (a final state, or back to the queue at a stop).",
            |w| w.finished,
        ),
        (
            "gapack_worker_leases_lost_total",
            "counter",
            "Leases each worker lost (reaped after it went silent).",
            |w| w.leases_lost,
        ),
    ];
    for (name, kind, help, value) in series {
        let _ = writeln!(out, "# HELP {name} {help}");
        let _ = writeln!(out, "# TYPE {name} {kind}");
        for w in &workers {
            let _ = writeln!(out, "{name}{{worker=\"{}\"}} {}", label(&w.name), value(w));
        }
    }
    let _ = writeln!(
        out,
        "# HELP gapack_worker_seen_seconds Seconds since each worker last said it is alive (every half lease, idle or busy)."
    );
    let _ = writeln!(out, "# TYPE gapack_worker_seen_seconds gauge");
    for w in &workers {
        let _ = writeln!(
            out,
            "gapack_worker_seen_seconds{{worker=\"{}\"}} {}",
            label(&w.name),
            (now - w.seen_ms).max(0) as f64 / 1e3
        );
    }
}

/// How long a worker unseen stays in the metrics: a day.
const FORGOTTEN_MS: i64 = 86_400_000;

/// A per-worker series: its name, its type, its help, its value.
type Series = (
    &'static str,
    &'static str,
    &'static str,
    fn(&WorkerRow) -> i64,
);

/// `text` as a Prometheus label value (backslash, quote and newline escaped).
fn label(text: &str) -> String {
    text.replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n")
}
