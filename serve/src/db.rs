//! The job store: one SQLite file (WAL mode) with a row per job and the
//! events each job sent, in order. Every state change is one transaction
//! that also appends the `state` event saying so: a job is claimed by one
//! worker only, and a crash leaves each job in exactly one state.
//!
//! Calls block: the HTTP handlers make them on `spawn_blocking` threads, the
//! workers on their own threads. One connection behind a mutex serves them
//! all (SQLite writes one transaction at a time anyway).

use std::path::Path;
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::{SystemTime, UNIX_EPOCH};

use rusqlite::{Connection, OptionalExtension, Row, params};
use serde::Serialize;
use serde_json::json;

/// Why the store could not answer.
#[derive(Debug, thiserror::Error)]
pub enum DbError {
    /// SQLite failed.
    #[error("job store: {0}")]
    Sql(#[from] rusqlite::Error),
    /// The queue holds as many jobs as the server takes.
    #[error("the queue is full ({0} jobs waiting); try again later")]
    QueueFull(usize),
}

/// A job's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum State {
    /// Waiting for a worker.
    Queued,
    /// A worker runs it.
    Running,
    /// Finished; its files are served.
    Succeeded,
    /// Could not run or finish; `error` says why.
    Failed,
    /// Cancelled: what it had finished is kept (an optimise its best packing).
    Cancelled,
}

impl State {
    /// Every state, in the order a job goes through them.
    pub const ALL: [State; 5] = [
        State::Queued,
        State::Running,
        State::Succeeded,
        State::Failed,
        State::Cancelled,
    ];

    /// Its name in the API and the store.
    pub fn name(self) -> &'static str {
        match self {
            State::Queued => "queued",
            State::Running => "running",
            State::Succeeded => "succeeded",
            State::Failed => "failed",
            State::Cancelled => "cancelled",
        }
    }

    /// The state named `name`.
    pub fn parse(name: &str) -> Option<State> {
        State::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Whether the job will not change any more.
    pub fn is_final(self) -> bool {
        matches!(self, State::Succeeded | State::Failed | State::Cancelled)
    }
}

/// One job as stored.
#[derive(Debug, Clone)]
pub struct JobRow {
    /// Its order of submission (the paging cursor).
    pub seq: i64,
    /// Its random id.
    pub id: String,
    /// The job kind's name.
    pub kind: String,
    /// The config's text.
    pub config: String,
    /// The seed asked for, if any.
    pub seed: Option<u64>,
    /// Its state.
    pub state: State,
    /// Submitted, started and finished (ms since the Unix epoch).
    pub created_ms: i64,
    /// When the last attempt started.
    pub started_ms: Option<i64>,
    /// When it reached its final state.
    pub finished_ms: Option<i64>,
    /// Attempts started (more than one after a restart).
    pub attempts: i64,
    /// Whether the next attempt goes on from the checkpoint.
    pub resume: bool,
    /// Whether a cancel was asked for while it ran.
    pub cancel_requested: bool,
    /// The last progress event, JSON.
    pub progress: Option<String>,
    /// The summary of a finished job, JSON.
    pub summary: Option<String>,
    /// Why it failed.
    pub error: Option<String>,
}

const COLUMNS: &str = "seq, id, kind, config, seed, state, created_ms, started_ms, finished_ms, \
     attempts, resume, cancel_requested, progress, summary, error";

fn row(r: &Row<'_>) -> rusqlite::Result<JobRow> {
    let state: String = r.get(5)?;
    Ok(JobRow {
        seq: r.get(0)?,
        id: r.get(1)?,
        kind: r.get(2)?,
        config: r.get(3)?,
        // Seeds are stored as the i64 of the same bits.
        seed: r.get::<_, Option<i64>>(4)?.map(|s| s as u64),
        state: State::parse(&state).unwrap_or(State::Failed),
        created_ms: r.get(6)?,
        started_ms: r.get(7)?,
        finished_ms: r.get(8)?,
        attempts: r.get(9)?,
        resume: r.get(10)?,
        cancel_requested: r.get(11)?,
        progress: r.get(12)?,
        summary: r.get(13)?,
        error: r.get(14)?,
    })
}

/// Milliseconds since the Unix epoch.
pub fn now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// What a cancel request did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CancelOutcome {
    /// The job was waiting: it is cancelled now.
    Dequeued,
    /// The job runs: its worker was asked to stop.
    Stopping,
    /// The job had already finished: nothing changed.
    Finished(State),
}

/// How a worker's attempt ended.
pub enum Ending {
    /// A final state, with the summary and the error.
    Final {
        /// Succeeded, failed or cancelled.
        state: State,
        /// The summary (JSON), if the job made one.
        summary: Option<String>,
        /// Why it failed.
        error: Option<String>,
    },
    /// Back to the queue (the server stopped it): the next attempt resumes.
    Requeue,
}

/// The SQLite job store.
pub struct Db {
    conn: Mutex<Connection>,
}

impl Db {
    /// Open (or create) the store at `path`.
    ///
    /// # Errors
    /// [`DbError::Sql`] if the file cannot be opened or set up.
    pub fn open(path: &Path) -> Result<Db, DbError> {
        let conn = Connection::open(path)?;
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "NORMAL")?;
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS jobs (
                seq INTEGER PRIMARY KEY AUTOINCREMENT,
                id TEXT NOT NULL UNIQUE,
                kind TEXT NOT NULL,
                config TEXT NOT NULL,
                seed INTEGER,
                state TEXT NOT NULL,
                created_ms INTEGER NOT NULL,
                started_ms INTEGER,
                finished_ms INTEGER,
                attempts INTEGER NOT NULL DEFAULT 0,
                resume INTEGER NOT NULL DEFAULT 0,
                cancel_requested INTEGER NOT NULL DEFAULT 0,
                progress TEXT,
                summary TEXT,
                error TEXT
            );
            CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs (state, seq);
            CREATE TABLE IF NOT EXISTS events (
                job TEXT NOT NULL,
                seq INTEGER NOT NULL,
                data TEXT NOT NULL,
                PRIMARY KEY (job, seq)
            ) WITHOUT ROWID;",
        )?;
        Ok(Db {
            conn: Mutex::new(conn),
        })
    }

    fn conn(&self) -> MutexGuard<'_, Connection> {
        // A panic while holding the lock leaves no transaction open (an
        // uncommitted one rolls back when dropped): the connection is sound.
        self.conn.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// After a restart: every job left running goes back to the queue, to
    /// resume from its checkpoint. Returns how many.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn recover(&self) -> Result<usize, DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        let ids: Vec<String> = {
            let mut stmt =
                tx.prepare("SELECT id FROM jobs WHERE state = 'running' ORDER BY seq")?;
            stmt.query_map([], |r| r.get(0))?
                .collect::<Result<_, _>>()?
        };
        for id in &ids {
            tx.execute(
                "UPDATE jobs SET state = 'queued', resume = 1 WHERE id = ?1",
                [id],
            )?;
            append(
                &tx,
                id,
                &json!({"event": "state", "state": "queued", "reason": "the server restarted"}),
            )?;
        }
        tx.commit()?;
        Ok(ids.len())
    }

    /// Add a job to the queue, unless `max_queue` jobs already wait.
    ///
    /// # Errors
    /// [`DbError::QueueFull`], [`DbError::Sql`].
    pub fn insert(
        &self,
        id: &str,
        kind: &str,
        config: &str,
        seed: Option<u64>,
        max_queue: usize,
    ) -> Result<(), DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        let queued: i64 = tx.query_row(
            "SELECT count(*) FROM jobs WHERE state = 'queued'",
            [],
            |r| r.get(0),
        )?;
        if usize::try_from(queued).unwrap_or(usize::MAX) >= max_queue {
            return Err(DbError::QueueFull(max_queue));
        }
        tx.execute(
            "INSERT INTO jobs (id, kind, config, seed, state, created_ms) VALUES (?1, ?2, ?3, ?4, 'queued', ?5)",
            params![id, kind, config, seed.map(|s| s as i64), now_ms()],
        )?;
        append(&tx, id, &json!({"event": "state", "state": "queued"}))?;
        tx.commit()?;
        Ok(())
    }

    /// Take the oldest queued job and mark it running, in one transaction.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn claim(&self) -> Result<Option<JobRow>, DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        let job = tx
            .query_row(
                &format!("SELECT {COLUMNS} FROM jobs WHERE state = 'queued' ORDER BY seq LIMIT 1"),
                [],
                row,
            )
            .optional()?;
        let Some(mut job) = job else {
            return Ok(None);
        };
        let now = now_ms();
        tx.execute(
            "UPDATE jobs SET state = 'running', started_ms = ?2, attempts = attempts + 1 WHERE id = ?1",
            params![job.id, now],
        )?;
        job.state = State::Running;
        job.started_ms = Some(now);
        job.attempts += 1;
        append(
            &tx,
            &job.id,
            &json!({"event": "state", "state": "running", "attempt": job.attempts, "resume": job.resume}),
        )?;
        tx.commit()?;
        Ok(Some(job))
    }

    /// Append one of a running job's events (and keep it as its progress
    /// when `progress`). Returns the event's number.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn event(
        &self,
        id: &str,
        data: &serde_json::Value,
        progress: bool,
    ) -> Result<i64, DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        let seq = append(&tx, id, data)?;
        if progress {
            tx.execute(
                "UPDATE jobs SET progress = ?2 WHERE id = ?1",
                params![id, data.to_string()],
            )?;
        }
        tx.commit()?;
        Ok(seq)
    }

    /// End a worker's attempt.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn finish(&self, id: &str, ending: &Ending) -> Result<(), DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        match ending {
            Ending::Final {
                state,
                summary,
                error,
            } => {
                tx.execute(
                    "UPDATE jobs SET state = ?2, finished_ms = ?3, summary = ?4, error = ?5 WHERE id = ?1",
                    params![id, state.name(), now_ms(), summary, error],
                )?;
                let mut event = json!({"event": "state", "state": state.name()});
                if let Some(error) = error {
                    event["error"] = json!(error);
                }
                append(&tx, id, &event)?;
            }
            Ending::Requeue => {
                tx.execute(
                    "UPDATE jobs SET state = 'queued', resume = 1 WHERE id = ?1",
                    [id],
                )?;
                append(
                    &tx,
                    id,
                    &json!({"event": "state", "state": "queued", "reason": "the server stopped"}),
                )?;
            }
        }
        tx.commit()?;
        Ok(())
    }

    /// Cancel a job: a queued one at once, a running one by flag (its
    /// worker ends it), a finished one not at all.
    ///
    /// # Errors
    /// [`DbError::Sql`]; `Ok(None)` for an unknown id.
    pub fn cancel(&self, id: &str) -> Result<Option<CancelOutcome>, DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        let state: Option<String> = tx
            .query_row("SELECT state FROM jobs WHERE id = ?1", [id], |r| r.get(0))
            .optional()?;
        let Some(state) = state.as_deref().and_then(State::parse) else {
            return Ok(None);
        };
        let outcome = match state {
            State::Queued => {
                tx.execute(
                    "UPDATE jobs SET state = 'cancelled', finished_ms = ?2 WHERE id = ?1",
                    params![id, now_ms()],
                )?;
                append(&tx, id, &json!({"event": "state", "state": "cancelled"}))?;
                CancelOutcome::Dequeued
            }
            State::Running => {
                tx.execute("UPDATE jobs SET cancel_requested = 1 WHERE id = ?1", [id])?;
                CancelOutcome::Stopping
            }
            done => CancelOutcome::Finished(done),
        };
        tx.commit()?;
        Ok(Some(outcome))
    }

    /// Whether a cancel was asked for `id`.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn cancel_requested(&self, id: &str) -> Result<bool, DbError> {
        let conn = self.conn();
        let asked: Option<bool> = conn
            .query_row(
                "SELECT cancel_requested FROM jobs WHERE id = ?1",
                [id],
                |r| r.get(0),
            )
            .optional()?;
        Ok(asked.unwrap_or(false))
    }

    /// One job.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn get(&self, id: &str) -> Result<Option<JobRow>, DbError> {
        let conn = self.conn();
        Ok(conn
            .query_row(
                &format!("SELECT {COLUMNS} FROM jobs WHERE id = ?1"),
                [id],
                row,
            )
            .optional()?)
    }

    /// Up to `limit` jobs, newest first, submitted before `before` (a
    /// `seq`), in `state` if given.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn list(
        &self,
        state: Option<State>,
        before: Option<i64>,
        limit: usize,
    ) -> Result<Vec<JobRow>, DbError> {
        let conn = self.conn();
        let mut stmt = conn.prepare(&format!(
            "SELECT {COLUMNS} FROM jobs WHERE (?1 IS NULL OR state = ?1) AND seq < ?2 \
             ORDER BY seq DESC LIMIT ?3"
        ))?;
        let rows = stmt
            .query_map(
                params![
                    state.map(State::name),
                    before.unwrap_or(i64::MAX),
                    i64::try_from(limit).unwrap_or(i64::MAX)
                ],
                row,
            )?
            .collect::<Result<_, _>>()?;
        Ok(rows)
    }

    /// Remove a finished job and its events. `Ok(Some(state))` with the
    /// state of a job that is not finished (nothing removed), `Ok(None)`
    /// for an unknown id.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn delete(&self, id: &str) -> Result<Option<Result<(), State>>, DbError> {
        let mut conn = self.conn();
        let tx = conn.transaction()?;
        let state: Option<String> = tx
            .query_row("SELECT state FROM jobs WHERE id = ?1", [id], |r| r.get(0))
            .optional()?;
        let Some(state) = state.as_deref().and_then(State::parse) else {
            return Ok(None);
        };
        if !state.is_final() {
            return Ok(Some(Err(state)));
        }
        tx.execute("DELETE FROM events WHERE job = ?1", [id])?;
        tx.execute("DELETE FROM jobs WHERE id = ?1", [id])?;
        tx.commit()?;
        Ok(Some(Ok(())))
    }

    /// Up to `limit` events of `id` numbered after `after`, in order.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn events_after(
        &self,
        id: &str,
        after: i64,
        limit: usize,
    ) -> Result<Vec<(i64, String)>, DbError> {
        let conn = self.conn();
        let mut stmt = conn.prepare_cached(
            "SELECT seq, data FROM events WHERE job = ?1 AND seq > ?2 ORDER BY seq LIMIT ?3",
        )?;
        let rows = stmt
            .query_map(
                params![id, after, i64::try_from(limit).unwrap_or(i64::MAX)],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )?
            .collect::<Result<_, _>>()?;
        Ok(rows)
    }

    /// How many jobs are in each state.
    ///
    /// # Errors
    /// [`DbError::Sql`].
    pub fn counts(&self) -> Result<Vec<(State, i64)>, DbError> {
        let conn = self.conn();
        let mut stmt = conn.prepare_cached("SELECT state, count(*) FROM jobs GROUP BY state")?;
        let found: Vec<(String, i64)> = stmt
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))?
            .collect::<Result<_, _>>()?;
        Ok(State::ALL
            .into_iter()
            .map(|s| {
                let n = found
                    .iter()
                    .find(|(name, _)| name == s.name())
                    .map_or(0, |(_, n)| *n);
                (s, n)
            })
            .collect())
    }
}

/// Append an event to `id`'s list in `tx`; its number is one more than the last.
fn append(
    tx: &rusqlite::Transaction<'_>,
    id: &str,
    data: &serde_json::Value,
) -> rusqlite::Result<i64> {
    let seq: i64 = tx.query_row(
        "SELECT COALESCE(MAX(seq), 0) + 1 FROM events WHERE job = ?1",
        [id],
        |r| r.get(0),
    )?;
    tx.execute(
        "INSERT INTO events (job, seq, data) VALUES (?1, ?2, ?3)",
        params![id, seq, data.to_string()],
    )?;
    Ok(seq)
}
