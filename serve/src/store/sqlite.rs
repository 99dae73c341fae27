//! The embedded store: one SQLite file (WAL mode), for one `gapack serve`
//! process (its leases guard the process's own workers; no other process
//! shares the file). One connection behind a mutex serves every call
//! (SQLite writes one transaction at a time anyway); each change is an
//! immediate transaction.

use std::path::Path;
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Duration;

use rusqlite::{Connection, OptionalExtension, Row, TransactionBehavior, params};
use serde_json::json;

use super::migrations::{LATEST, MIGRATIONS};
use super::{
    Beat, Caller, CancelOutcome, Claimed, Ending, JobRow, JobStore, MAX_ATTEMPTS, NewJob,
    QueueLimits, Reaped, Role, State, StoreError, User, UserCount, WorkerRow, millis, now_ms,
    state_event,
};

/// The columns of a [`JobRow`], in the order [`row`] reads them (`j` the
/// jobs, `u` the owner).
const COLUMNS: &str = "j.seq, j.id, u.name, j.kind, j.config, j.seed, j.force_limits, \
     j.checkpoint_every, j.state, j.created_ms, j.started_ms, j.finished_ms, j.attempts, \
     j.resume, j.cancel_requested, j.worker, j.progress, j.summary, j.error";

/// The jobs with their owners, for [`COLUMNS`].
const FROM: &str = "jobs j JOIN users u ON u.id = j.owner";

/// A job the caller `?2` (admin: `?3`) may see, by id `?1`.
const VISIBLE: &str = "j.id = ?1 AND (?3 OR j.owner = ?2)";

fn row(r: &Row<'_>) -> rusqlite::Result<JobRow> {
    let state: String = r.get(8)?;
    Ok(JobRow {
        seq: r.get(0)?,
        id: r.get(1)?,
        owner: r.get(2)?,
        kind: r.get(3)?,
        config: r.get(4)?,
        // Seeds are stored as the i64 of the same bits.
        seed: r.get::<_, Option<i64>>(5)?.map(|s| s as u64),
        force: r.get(6)?,
        checkpoint_every: r.get(7)?,
        state: State::parse(&state).unwrap_or(State::Failed),
        created_ms: r.get(9)?,
        started_ms: r.get(10)?,
        finished_ms: r.get(11)?,
        attempts: r.get(12)?,
        resume: r.get(13)?,
        cancel_requested: r.get(14)?,
        worker: r.get(15)?,
        progress: r.get(16)?,
        summary: r.get(17)?,
        error: r.get(18)?,
    })
}

fn user(r: &Row<'_>) -> rusqlite::Result<User> {
    let role: String = r.get(2)?;
    Ok(User {
        id: r.get(0)?,
        name: r.get(1)?,
        role: Role::parse(&role),
        max_queued: r.get(3)?,
        max_particles: r.get(4)?,
        tokens: r.get(5)?,
    })
}

/// The columns of a [`User`], for [`user`].
const USER_COLUMNS: &str = "u.id, u.name, u.role, u.max_queued, u.max_particles, \
     (SELECT count(*) FROM tokens t WHERE t.user_id = u.id AND t.revoked_ms IS NULL)";

/// The SQLite job store.
pub struct SqliteStore {
    conn: Mutex<Connection>,
}

impl SqliteStore {
    /// Open (or create) the store at `path`, its schema brought up to date.
    ///
    /// # Errors
    /// [`StoreError::Sqlite`] if the file cannot be opened or set up;
    /// [`StoreError::TooNew`] for a store a newer gapack made.
    pub fn open(path: &Path) -> Result<SqliteStore, StoreError> {
        let mut conn = Connection::open(path)?;
        conn.busy_timeout(Duration::from_secs(5))?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "NORMAL")?;
        migrate(&mut conn)?;
        Ok(SqliteStore {
            conn: Mutex::new(conn),
        })
    }

    fn conn(&self) -> MutexGuard<'_, Connection> {
        // A panic while holding the lock leaves no transaction open (an
        // uncommitted one rolls back when dropped): the connection is sound.
        self.conn.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Run `f` in an immediate transaction, committed if it returns `Ok`.
    fn write<T>(
        &self,
        f: impl FnOnce(&rusqlite::Transaction<'_>) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        let mut conn = self.conn();
        let tx = conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
        let value = f(&tx)?;
        tx.commit()?;
        Ok(value)
    }
}

/// Apply the steps past the store's version, each in its own transaction.
fn migrate(conn: &mut Connection) -> Result<(), StoreError> {
    let tx = conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
    tx.execute_batch(
        "CREATE TABLE IF NOT EXISTS schema_version (version INTEGER PRIMARY KEY, applied_ms INTEGER NOT NULL)",
    )?;
    let mut version: i64 = tx.query_row(
        "SELECT COALESCE(MAX(version), 0) FROM schema_version",
        [],
        |r| r.get(0),
    )?;
    // A store from before versions were recorded: its jobs table is version 1.
    let old: bool = tx.query_row(
        "SELECT count(*) > 0 FROM sqlite_master WHERE type = 'table' AND name = 'jobs'",
        [],
        |r| r.get(0),
    )?;
    if version == 0 && old {
        tx.execute(
            "INSERT INTO schema_version (version, applied_ms) VALUES (1, ?1)",
            [now_ms()],
        )?;
        version = 1;
    }
    tx.commit()?;
    if version > LATEST {
        return Err(StoreError::TooNew {
            found: version,
            known: LATEST,
        });
    }
    for step in MIGRATIONS.iter().filter(|m| m.version > version) {
        let tx = conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
        tx.execute_batch(step.sqlite)?;
        tx.execute(
            "INSERT INTO schema_version (version, applied_ms) VALUES (?1, ?2)",
            params![step.version, now_ms()],
        )?;
        tx.commit()?;
    }
    Ok(())
}

/// Append an event to `id`'s list in `tx`, numbered one past its last.
fn append(
    tx: &rusqlite::Transaction<'_>,
    id: &str,
    data: &serde_json::Value,
) -> rusqlite::Result<i64> {
    let seq: i64 = tx.query_row(
        "UPDATE jobs SET last_event = last_event + 1 WHERE id = ?1 RETURNING last_event",
        [id],
        |r| r.get(0),
    )?;
    tx.execute(
        "INSERT INTO events (job, seq, data) VALUES (?1, ?2, ?3)",
        params![id, seq, data.to_string()],
    )?;
    Ok(seq)
}

/// The state of job `id` if `who` may see it.
fn visible_state(
    tx: &rusqlite::Transaction<'_>,
    who: &Caller,
    id: &str,
) -> rusqlite::Result<Option<State>> {
    let state: Option<String> = tx
        .query_row(
            &format!("SELECT j.state FROM jobs j WHERE {VISIBLE}"),
            params![id, who.id, who.admin],
            |r| r.get(0),
        )
        .optional()?;
    Ok(state.as_deref().and_then(State::parse))
}

/// Whether `lease` is the current lease of running job `id`.
fn holds(tx: &rusqlite::Transaction<'_>, id: &str, lease: i64) -> rusqlite::Result<bool> {
    tx.query_row(
        "SELECT count(*) > 0 FROM jobs WHERE id = ?1 AND state = 'running' AND lease = ?2",
        params![id, lease],
        |r| r.get(0),
    )
}

/// Put running job `id` back in the queue, saying `reason`; its new
/// state. A job its user asked to cancel is cancelled instead, and one
/// that had its [`MAX_ATTEMPTS`] fails.
fn requeue(tx: &rusqlite::Transaction<'_>, id: &str, reason: &str) -> rusqlite::Result<State> {
    let (attempts, cancel): (i64, bool) = tx.query_row(
        "SELECT attempts, cancel_requested FROM jobs WHERE id = ?1",
        [id],
        |r| Ok((r.get(0)?, r.get(1)?)),
    )?;
    if cancel {
        // Its user wanted it stopped: it is, without its worker's summary.
        tx.execute(
            "UPDATE jobs SET state = 'cancelled', finished_ms = ?2, worker = NULL, lease = NULL, \
             lease_until_ms = NULL WHERE id = ?1",
            params![id, now_ms()],
        )?;
        append(
            tx,
            id,
            &json!({"event": "state", "state": "cancelled", "reason": reason}),
        )?;
        Ok(State::Cancelled)
    } else if attempts >= MAX_ATTEMPTS {
        let error = format!("{reason} {attempts} times; not tried again");
        tx.execute(
            "UPDATE jobs SET state = 'failed', finished_ms = ?2, error = ?3, worker = NULL, \
             lease = NULL, lease_until_ms = NULL WHERE id = ?1",
            params![id, now_ms(), error],
        )?;
        append(
            tx,
            id,
            &json!({"event": "state", "state": "failed", "error": error}),
        )?;
        Ok(State::Failed)
    } else {
        tx.execute(
            "UPDATE jobs SET state = 'queued', resume = 1, worker = NULL, lease = NULL, \
             lease_until_ms = NULL WHERE id = ?1",
            [id],
        )?;
        append(
            tx,
            id,
            &json!({"event": "state", "state": "queued", "reason": reason}),
        )?;
        Ok(State::Queued)
    }
}

fn limit_i64(limit: usize) -> i64 {
    i64::try_from(limit).unwrap_or(i64::MAX)
}

impl JobStore for SqliteStore {
    fn engine(&self) -> &'static str {
        "sqlite"
    }

    fn recover(&self) -> Result<usize, StoreError> {
        self.write(|tx| {
            let ids: Vec<String> = {
                let mut stmt =
                    tx.prepare("SELECT id FROM jobs WHERE state = 'running' ORDER BY seq")?;
                stmt.query_map([], |r| r.get(0))?
                    .collect::<Result<_, _>>()?
            };
            for id in &ids {
                tx.execute(
                    "UPDATE jobs SET state = 'queued', resume = 1, worker = NULL, lease = NULL, \
                     lease_until_ms = NULL WHERE id = ?1",
                    [id],
                )?;
                append(
                    tx,
                    id,
                    &json!({"event": "state", "state": "queued", "reason": "the server restarted"}),
                )?;
            }
            Ok(ids.len())
        })
    }

    fn insert(&self, job: &NewJob<'_>, limits: QueueLimits) -> Result<(), StoreError> {
        self.write(|tx| {
            let (queued, mine): (i64, i64) = tx.query_row(
                "SELECT count(*), COALESCE(SUM(owner = ?1), 0) FROM jobs WHERE state = 'queued'",
                [job.owner.id],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )?;
            if usize::try_from(queued).unwrap_or(usize::MAX) >= limits.total {
                return Err(StoreError::QueueFull(limits.total));
            }
            let share = job
                .owner
                .max_queued
                .map_or(limits.per_user, |n| usize::try_from(n).unwrap_or(0));
            if usize::try_from(mine).unwrap_or(usize::MAX) >= share {
                return Err(StoreError::UserQueueFull(share));
            }
            tx.execute(
                "INSERT INTO jobs (id, owner, kind, config, seed, force_limits, checkpoint_every, \
                 state, created_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, 'queued', ?8)",
                params![
                    job.id,
                    job.owner.id,
                    job.kind,
                    job.config,
                    job.seed.map(|s| s as i64),
                    job.force,
                    job.checkpoint_every,
                    now_ms()
                ],
            )?;
            append(tx, job.id, &state_event(State::Queued))?;
            Ok(())
        })
    }

    fn claim(&self, worker: &str, ttl: Duration) -> Result<Option<Claimed>, StoreError> {
        self.write(|tx| {
            let id: Option<String> = tx
                .query_row(
                    "SELECT j.id FROM jobs j WHERE j.state = 'queued' ORDER BY \
                     (SELECT count(*) FROM jobs r WHERE r.owner = j.owner AND r.state = 'running'), \
                     j.seq LIMIT 1",
                    [],
                    |r| r.get(0),
                )
                .optional()?;
            let Some(id) = id else {
                return Ok(None);
            };
            let now = now_ms();
            let lease: i64 = tx.query_row(
                "UPDATE lease_numbers SET last = last + 1 RETURNING last",
                [],
                |r| r.get(0),
            )?;
            tx.execute(
                "UPDATE jobs SET state = 'running', started_ms = ?2, attempts = attempts + 1, \
                 worker = ?3, lease = ?4, lease_until_ms = ?5 WHERE id = ?1",
                params![id, now, worker, lease, now.saturating_add(millis(ttl))],
            )?;
            tx.execute(
                "INSERT INTO workers (name, seen_ms, claimed) VALUES (?1, ?2, 1) \
                 ON CONFLICT (name) DO UPDATE SET seen_ms = ?2, claimed = claimed + 1",
                params![worker, now],
            )?;
            let job = tx.query_row(
                &format!("SELECT {COLUMNS} FROM {FROM} WHERE j.id = ?1"),
                [&id],
                row,
            )?;
            append(
                tx,
                &id,
                &json!({"event": "state", "state": "running", "attempt": job.attempts, "resume": job.resume}),
            )?;
            Ok(Some(Claimed { job, lease }))
        })
    }

    fn heartbeat(
        &self,
        worker: &str,
        id: &str,
        lease: i64,
        ttl: Duration,
    ) -> Result<Beat, StoreError> {
        self.write(|tx| {
            let now = now_ms();
            let asked: Option<bool> = tx
                .query_row(
                    "UPDATE jobs SET lease_until_ms = ?3 WHERE id = ?1 AND state = 'running' \
                     AND lease = ?2 RETURNING cancel_requested",
                    params![id, lease, now.saturating_add(millis(ttl))],
                    |r| r.get(0),
                )
                .optional()?;
            match asked {
                Some(cancel_requested) => {
                    tx.execute(
                        "UPDATE workers SET seen_ms = ?2 WHERE name = ?1",
                        params![worker, now],
                    )?;
                    Ok(Beat::Held { cancel_requested })
                }
                // Counted once, by the reaper that took the lease.
                None => Ok(Beat::Lost),
            }
        })
    }

    fn event(
        &self,
        id: &str,
        lease: i64,
        data: &serde_json::Value,
        progress: bool,
    ) -> Result<Option<i64>, StoreError> {
        self.write(|tx| {
            if !holds(tx, id, lease)? {
                return Ok(None);
            }
            let seq = append(tx, id, data)?;
            if progress {
                tx.execute(
                    "UPDATE jobs SET progress = ?2 WHERE id = ?1",
                    params![id, data.to_string()],
                )?;
            }
            Ok(Some(seq))
        })
    }

    fn finish(
        &self,
        worker: &str,
        id: &str,
        lease: i64,
        ending: &Ending,
    ) -> Result<bool, StoreError> {
        self.write(|tx| {
            if !holds(tx, id, lease)? {
                return Ok(false);
            }
            match ending {
                Ending::Final {
                    state,
                    summary,
                    error,
                } => {
                    tx.execute(
                        "UPDATE jobs SET state = ?2, finished_ms = ?3, summary = ?4, error = ?5, \
                         worker = NULL, lease = NULL, lease_until_ms = NULL WHERE id = ?1",
                        params![id, state.name(), now_ms(), summary, error],
                    )?;
                    let mut event = state_event(*state);
                    if let Some(error) = error {
                        event["error"] = json!(error);
                    }
                    append(tx, id, &event)?;
                }
                Ending::Requeue => {
                    tx.execute(
                        "UPDATE jobs SET state = 'queued', resume = 1, worker = NULL, lease = NULL, \
                         lease_until_ms = NULL WHERE id = ?1",
                        [id],
                    )?;
                    append(
                        tx,
                        id,
                        &json!({"event": "state", "state": "queued", "reason": "its worker stopped"}),
                    )?;
                }
            }
            tx.execute(
                "UPDATE workers SET finished = finished + 1, seen_ms = ?2 WHERE name = ?1",
                params![worker, now_ms()],
            )?;
            Ok(true)
        })
    }

    fn reap(&self) -> Result<Vec<Reaped>, StoreError> {
        self.write(|tx| {
            let expired: Vec<(String, Option<String>)> = {
                let mut stmt = tx.prepare(
                    "SELECT id, worker FROM jobs WHERE state = 'running' AND lease_until_ms < ?1 \
                     ORDER BY seq",
                )?;
                stmt.query_map([now_ms()], |r| Ok((r.get(0)?, r.get(1)?)))?
                    .collect::<Result<_, _>>()?
            };
            let mut reaped = Vec::with_capacity(expired.len());
            for (id, worker) in expired {
                let state = requeue(tx, &id, "its worker was lost")?;
                if let Some(w) = &worker {
                    tx.execute(
                        "UPDATE workers SET leases_lost = leases_lost + 1 WHERE name = ?1",
                        [w],
                    )?;
                }
                reaped.push(Reaped { id, state, worker });
            }
            Ok(reaped)
        })
    }

    fn cancel(&self, who: &Caller, id: &str) -> Result<Option<CancelOutcome>, StoreError> {
        self.write(|tx| {
            let Some(state) = visible_state(tx, who, id)? else {
                return Ok(None);
            };
            Ok(Some(match state {
                State::Queued => {
                    tx.execute(
                        "UPDATE jobs SET state = 'cancelled', finished_ms = ?2 WHERE id = ?1",
                        params![id, now_ms()],
                    )?;
                    append(tx, id, &state_event(State::Cancelled))?;
                    CancelOutcome::Dequeued
                }
                State::Running => {
                    tx.execute("UPDATE jobs SET cancel_requested = 1 WHERE id = ?1", [id])?;
                    CancelOutcome::Stopping
                }
                done => CancelOutcome::Finished(done),
            }))
        })
    }

    fn cancel_requested(&self, id: &str) -> Result<bool, StoreError> {
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

    fn get(&self, who: &Caller, id: &str) -> Result<Option<JobRow>, StoreError> {
        let conn = self.conn();
        Ok(conn
            .query_row(
                &format!("SELECT {COLUMNS} FROM {FROM} WHERE {VISIBLE}"),
                params![id, who.id, who.admin],
                row,
            )
            .optional()?)
    }

    fn list(
        &self,
        who: &Caller,
        state: Option<State>,
        before: Option<i64>,
        limit: usize,
    ) -> Result<Vec<JobRow>, StoreError> {
        let conn = self.conn();
        let mut stmt = conn.prepare_cached(&format!(
            "SELECT {COLUMNS} FROM {FROM} WHERE (?1 IS NULL OR j.state = ?1) AND j.seq < ?2 \
             AND (?5 OR j.owner = ?4) ORDER BY j.seq DESC LIMIT ?3"
        ))?;
        let rows = stmt
            .query_map(
                params![
                    state.map(State::name),
                    before.unwrap_or(i64::MAX),
                    limit_i64(limit),
                    who.id,
                    who.admin
                ],
                row,
            )?
            .collect::<Result<_, _>>()?;
        Ok(rows)
    }

    fn delete(&self, who: &Caller, id: &str) -> Result<Option<Result<(), State>>, StoreError> {
        self.write(|tx| {
            let Some(state) = visible_state(tx, who, id)? else {
                return Ok(None);
            };
            if !state.is_final() {
                return Ok(Some(Err(state)));
            }
            tx.execute("DELETE FROM events WHERE job = ?1", [id])?;
            tx.execute("DELETE FROM jobs WHERE id = ?1", [id])?;
            Ok(Some(Ok(())))
        })
    }

    fn events_after(
        &self,
        id: &str,
        after: i64,
        limit: usize,
    ) -> Result<Vec<(i64, String)>, StoreError> {
        let conn = self.conn();
        let mut stmt = conn.prepare_cached(
            "SELECT seq, data FROM events WHERE job = ?1 AND seq > ?2 ORDER BY seq LIMIT ?3",
        )?;
        let rows = stmt
            .query_map(params![id, after, limit_i64(limit)], |r| {
                Ok((r.get(0)?, r.get(1)?))
            })?
            .collect::<Result<_, _>>()?;
        Ok(rows)
    }

    fn counts(&self) -> Result<Vec<(State, i64)>, StoreError> {
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

    fn counts_by_user(&self) -> Result<Vec<UserCount>, StoreError> {
        let conn = self.conn();
        let mut stmt = conn.prepare_cached(
            "SELECT u.name, j.state, count(*) FROM jobs j JOIN users u ON u.id = j.owner \
             GROUP BY u.name, j.state ORDER BY u.name, j.state",
        )?;
        let found: Vec<(String, String, i64)> = stmt
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?
            .collect::<Result<_, _>>()?;
        Ok(found
            .into_iter()
            .filter_map(|(user, state, jobs)| {
                State::parse(&state).map(|state| UserCount { user, state, jobs })
            })
            .collect())
    }

    fn workers(&self) -> Result<Vec<WorkerRow>, StoreError> {
        let conn = self.conn();
        let mut stmt = conn.prepare_cached(
            "SELECT name, seen_ms, claimed, finished, leases_lost FROM workers ORDER BY name",
        )?;
        let rows = stmt
            .query_map([], |r| {
                Ok(WorkerRow {
                    name: r.get(0)?,
                    seen_ms: r.get(1)?,
                    claimed: r.get(2)?,
                    finished: r.get(3)?,
                    leases_lost: r.get(4)?,
                })
            })?
            .collect::<Result<_, _>>()?;
        Ok(rows)
    }

    fn alive(&self, names: &[String]) -> Result<(), StoreError> {
        self.write(|tx| {
            let now = now_ms();
            for name in names {
                tx.execute(
                    "INSERT INTO workers (name, seen_ms) VALUES (?1, ?2) \
                     ON CONFLICT (name) DO UPDATE SET seen_ms = ?2",
                    params![name, now],
                )?;
            }
            Ok(())
        })
    }

    fn add_user(
        &self,
        name: &str,
        role: Role,
        token_hash: &[u8; 32],
        max_queued: Option<i64>,
        max_particles: Option<i64>,
    ) -> Result<User, StoreError> {
        self.write(|tx| {
            let taken: bool = tx.query_row(
                "SELECT count(*) > 0 FROM users WHERE name = ?1",
                [name],
                |r| r.get(0),
            )?;
            if taken {
                return Err(StoreError::UserExists(name.to_owned()));
            }
            let now = now_ms();
            let id: i64 = tx.query_row(
                "INSERT INTO users (name, role, created_ms, max_queued, max_particles) \
                 VALUES (?1, ?2, ?3, ?4, ?5) RETURNING id",
                params![name, role.name(), now, max_queued, max_particles],
                |r| r.get(0),
            )?;
            tx.execute(
                "INSERT INTO tokens (hash, user_id, created_ms) VALUES (?1, ?2, ?3)",
                params![&token_hash[..], id, now],
            )?;
            Ok(User {
                id,
                name: name.to_owned(),
                role,
                max_queued,
                max_particles,
                tokens: 1,
            })
        })
    }

    fn revoke_user(&self, name: &str) -> Result<bool, StoreError> {
        self.write(|tx| {
            let id: Option<i64> = tx
                .query_row("SELECT id FROM users WHERE name = ?1", [name], |r| r.get(0))
                .optional()?;
            let Some(id) = id else {
                return Ok(false);
            };
            tx.execute(
                "UPDATE tokens SET revoked_ms = ?2 WHERE user_id = ?1 AND revoked_ms IS NULL",
                params![id, now_ms()],
            )?;
            Ok(true)
        })
    }

    fn users(&self) -> Result<Vec<User>, StoreError> {
        let conn = self.conn();
        let mut stmt =
            conn.prepare_cached(&format!("SELECT {USER_COLUMNS} FROM users u ORDER BY u.id"))?;
        let rows = stmt.query_map([], user)?.collect::<Result<_, _>>()?;
        Ok(rows)
    }

    fn user_by_token(&self, token_hash: &[u8; 32]) -> Result<Option<Caller>, StoreError> {
        let conn = self.conn();
        let found = conn
            .query_row(
                &format!(
                    "SELECT {USER_COLUMNS} FROM tokens t JOIN users u ON u.id = t.user_id \
                     WHERE t.hash = ?1 AND t.revoked_ms IS NULL"
                ),
                [&token_hash[..]],
                user,
            )
            .optional()?;
        Ok(found.map(Caller::from))
    }

    fn user_named(&self, name: &str) -> Result<Option<Caller>, StoreError> {
        let conn = self.conn();
        let found = conn
            .query_row(
                &format!("SELECT {USER_COLUMNS} FROM users u WHERE u.name = ?1"),
                [name],
                user,
            )
            .optional()?;
        Ok(found.map(Caller::from))
    }

    fn has_tokens(&self) -> Result<bool, StoreError> {
        let conn = self.conn();
        Ok(conn.query_row("SELECT EXISTS (SELECT 1 FROM tokens)", [], |r| r.get(0))?)
    }

    fn subscribe(&self) -> Option<std::sync::mpsc::Receiver<super::Notice>> {
        None
    }
}
