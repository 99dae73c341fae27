//! The shared store: a PostgreSQL database that any number of fronts
//! (`gapack serve`) and workers (`gapack worker`) use at once, from any
//! number of machines.
//!
//! Every timestamp comes from the database server (`gapack_now_ms()`), so
//! the machines' clocks do not matter to leases. Concurrent claims and
//! reaps skip each other's rows (`FOR UPDATE SKIP LOCKED`); an event's
//! number comes from its job's counter, bumped under the row's lock.
//! Each change also notifies (`pg_notify`, delivered at commit) the
//! other processes: `gapack_events` with a job's id when it has a new
//! event or state, `gapack_queue` when a job is queued, `gapack_cancel`
//! with a job's id when a cancel is asked for while it runs.
//!
//! The calls block. The store drives its connections on a small runtime
//! of its own, so that it serves plain threads and the `spawn_blocking`
//! threads of any other runtime alike; a call from async code (a task
//! being polled) is refused by tokio.

use std::future::Future;
use std::time::Duration;

use deadpool_postgres::{
    GenericClient, Manager, ManagerConfig, Pool, PoolError, RecyclingMethod, TimeoutType,
    Transaction,
};
use serde_json::json;
use tokio_postgres::types::ToSql;
use tokio_postgres::{NoTls, Row};

use super::migrations::{LATEST, MIGRATIONS};
use super::{
    Beat, Caller, CancelOutcome, Claimed, Ending, JobRow, JobStore, MAX_ATTEMPTS, NewJob, Notice,
    QueueLimits, Reaped, Role, State, StoreError, User, UserCount, WorkerRow, millis, state_event,
};

/// The advisory lock that makes processes opening the store together
/// apply each schema step once.
const MIGRATION_LOCK: i64 = 0x6761_7061_636b_0001;

/// The advisory lock that serialises submissions, so that concurrent
/// inserts cannot both see room for one more job.
const QUEUE_LOCK: i64 = 0x6761_7061_636b_0002;

/// Connections in the pool.
const POOL_SIZE: usize = 8;

/// How long a new connection may take.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

/// How long a call waits for a connection of the pool (all busy, or the
/// database unreachable) before it fails.
const WAIT_TIMEOUT: Duration = Duration::from_secs(10);

/// How long a whole call may take before it fails (a connection that
/// stopped answering without closing).
const CALL_TIMEOUT: Duration = Duration::from_secs(30);

/// How long the listener waits before connecting again after it lost
/// its connection.
const RELISTEN: Duration = Duration::from_secs(1);

/// The channels the listener follows.
const LISTEN: &str = "LISTEN gapack_events; LISTEN gapack_queue; LISTEN gapack_cancel";

/// The columns of a [`JobRow`], in the order [`job_row`] reads them (`j`
/// the jobs, `u` the owner).
const COLUMNS: &str = "j.seq, j.id, u.name, j.kind, j.config, j.seed, j.force_limits, \
     j.checkpoint_every, j.state, j.created_ms, j.started_ms, j.finished_ms, j.attempts, \
     j.resume, j.cancel_requested, j.worker, j.progress, j.summary, j.error";

/// The jobs with their owners, for [`COLUMNS`].
const FROM: &str = "jobs j JOIN users u ON u.id = j.owner";

/// A job the caller `$2` (admin: `$3`) may see, by id `$1`.
const VISIBLE: &str = "j.id = $1 AND ($3 OR j.owner = $2)";

/// The columns of a [`User`], for [`user_row`].
const USER_COLUMNS: &str = "u.id, u.name, u.role, u.max_queued, u.max_particles, \
     (SELECT count(*) FROM tokens t WHERE t.user_id = u.id AND t.revoked_ms IS NULL)";

/// Why the queue is left: the reaper's reason, in events and errors.
const LOST: &str = "its worker was lost";

/// `e` with its causes (the client's own message is only their kind:
/// "db error", "error connecting to server"). They name no connection
/// parameter, so no password.
fn message(e: &tokio_postgres::Error) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    // A chain is short; four links say all there is.
    for _ in 0..4 {
        let Some(c) = cause else { break };
        text.push_str(": ");
        text.push_str(&c.to_string());
        cause = c.source();
    }
    text
}

impl From<tokio_postgres::Error> for StoreError {
    fn from(e: tokio_postgres::Error) -> Self {
        StoreError::Postgres(message(&e))
    }
}

impl From<PoolError> for StoreError {
    fn from(e: PoolError) -> Self {
        StoreError::Postgres(match e {
            PoolError::Backend(e) => message(&e),
            PoolError::Timeout(TimeoutType::Wait) => format!(
                "no free connection to PostgreSQL within {} s",
                WAIT_TIMEOUT.as_secs()
            ),
            PoolError::Timeout(_) => format!(
                "PostgreSQL did not answer a connection within {} s (is it running, and reachable?)",
                CONNECT_TIMEOUT.as_secs()
            ),
            other => other.to_string(),
        })
    }
}

type PgResult<T> = Result<T, tokio_postgres::Error>;

fn job_row(r: &Row) -> PgResult<JobRow> {
    let state: String = r.try_get(8)?;
    Ok(JobRow {
        seq: r.try_get(0)?,
        id: r.try_get(1)?,
        owner: r.try_get(2)?,
        kind: r.try_get(3)?,
        config: r.try_get(4)?,
        // Seeds are stored as the i64 of the same bits.
        seed: r.try_get::<_, Option<i64>>(5)?.map(|s| s as u64),
        force: r.try_get(6)?,
        checkpoint_every: r.try_get(7)?,
        state: State::parse(&state).unwrap_or(State::Failed),
        created_ms: r.try_get(9)?,
        started_ms: r.try_get(10)?,
        finished_ms: r.try_get(11)?,
        attempts: r.try_get(12)?,
        resume: r.try_get(13)?,
        cancel_requested: r.try_get(14)?,
        worker: r.try_get(15)?,
        progress: r.try_get(16)?,
        summary: r.try_get(17)?,
        error: r.try_get(18)?,
    })
}

fn user_row(r: &Row) -> PgResult<User> {
    let role: String = r.try_get(2)?;
    Ok(User {
        id: r.try_get(0)?,
        name: r.try_get(1)?,
        role: Role::parse(&role),
        max_queued: r.try_get(3)?,
        max_particles: r.try_get(4)?,
        tokens: r.try_get(5)?,
    })
}

/// Parameters of a statement.
type Params<'a> = [&'a (dyn ToSql + Sync)];

/// The rows `sql` gives (a statement prepared once per connection).
async fn rows(c: &impl GenericClient, sql: &str, params: &Params<'_>) -> PgResult<Vec<Row>> {
    let statement = c.prepare_cached(sql).await?;
    c.query(&statement, params).await
}

/// The row `sql` gives, if any.
async fn opt(c: &impl GenericClient, sql: &str, params: &Params<'_>) -> PgResult<Option<Row>> {
    let statement = c.prepare_cached(sql).await?;
    c.query_opt(&statement, params).await
}

/// The one row `sql` gives.
async fn one(c: &impl GenericClient, sql: &str, params: &Params<'_>) -> PgResult<Row> {
    let statement = c.prepare_cached(sql).await?;
    c.query_one(&statement, params).await
}

/// Run `sql`; how many rows it changed.
async fn exec(c: &impl GenericClient, sql: &str, params: &Params<'_>) -> PgResult<u64> {
    let statement = c.prepare_cached(sql).await?;
    c.execute(&statement, params).await
}

/// Append an event to `id`'s list, numbered one past its last (the
/// counter is bumped under the job row's lock, so concurrent appends
/// never share a number), and tell the listeners at commit.
async fn append(tx: &Transaction<'_>, id: &str, data: &serde_json::Value) -> PgResult<i64> {
    let seq: i64 = one(
        tx,
        "UPDATE jobs SET last_event = last_event + 1 WHERE id = $1 RETURNING last_event",
        &[&id],
    )
    .await?
    .try_get(0)?;
    exec(
        tx,
        "INSERT INTO events (job, seq, data) VALUES ($1, $2, $3)",
        &[&id, &seq, &data.to_string()],
    )
    .await?;
    notify(tx, "gapack_events", id).await?;
    Ok(seq)
}

/// Notify `channel` with `payload` at commit.
async fn notify(tx: &Transaction<'_>, channel: &str, payload: &str) -> PgResult<()> {
    exec(tx, "SELECT pg_notify($1, $2)", &[&channel, &payload]).await?;
    Ok(())
}

/// Whether `lease` is the current lease of running job `id` (the row
/// locked until commit, so that the lease cannot be reaped meanwhile).
async fn holds(tx: &Transaction<'_>, id: &str, lease: i64) -> PgResult<bool> {
    Ok(opt(
        tx,
        "SELECT 1 FROM jobs WHERE id = $1 AND state = 'running' AND lease = $2 FOR UPDATE",
        &[&id, &lease],
    )
    .await?
    .is_some())
}

/// The state of job `id` if `who` may see it, its row locked until commit.
async fn visible_state(tx: &Transaction<'_>, who: &Caller, id: &str) -> PgResult<Option<State>> {
    let found = opt(
        tx,
        &format!("SELECT j.state FROM jobs j WHERE {VISIBLE} FOR UPDATE"),
        &[&id, &who.id, &who.admin],
    )
    .await?;
    found
        .map(|r| r.try_get::<_, String>(0).map(|s| State::parse(&s)))
        .transpose()
        .map(Option::flatten)
}

/// Put running job `id` (locked), whose worker was lost, back in the
/// queue; its new state. A job its user asked to cancel is cancelled
/// instead, and one that had its [`MAX_ATTEMPTS`] fails.
async fn requeue(tx: &Transaction<'_>, id: &str, attempts: i64, cancel: bool) -> PgResult<State> {
    if cancel {
        // Its user wanted it stopped: it is, without its worker's summary.
        exec(
            tx,
            "UPDATE jobs SET state = 'cancelled', finished_ms = gapack_now_ms(), worker = NULL, \
             lease = NULL, lease_until_ms = NULL WHERE id = $1",
            &[&id],
        )
        .await?;
        append(
            tx,
            id,
            &json!({"event": "state", "state": "cancelled", "reason": LOST}),
        )
        .await?;
        Ok(State::Cancelled)
    } else if attempts >= MAX_ATTEMPTS {
        let error = format!("{LOST} {attempts} times; not tried again");
        exec(
            tx,
            "UPDATE jobs SET state = 'failed', finished_ms = gapack_now_ms(), error = $2, \
             worker = NULL, lease = NULL, lease_until_ms = NULL WHERE id = $1",
            &[&id, &error],
        )
        .await?;
        append(
            tx,
            id,
            &json!({"event": "state", "state": "failed", "error": error}),
        )
        .await?;
        Ok(State::Failed)
    } else {
        exec(
            tx,
            "UPDATE jobs SET state = 'queued', resume = TRUE, worker = NULL, lease = NULL, \
             lease_until_ms = NULL WHERE id = $1",
            &[&id],
        )
        .await?;
        append(
            tx,
            id,
            &json!({"event": "state", "state": "queued", "reason": LOST}),
        )
        .await?;
        Ok(State::Queued)
    }
}

fn limit_i64(limit: usize) -> i64 {
    i64::try_from(limit).unwrap_or(i64::MAX)
}

/// The PostgreSQL job store.
pub struct PgStore {
    /// The connections the calls use.
    pool: Pool,
    /// Where the listeners connect (each its own connection, not pooled:
    /// a pooled one would drop its `LISTEN` when handed back).
    config: tokio_postgres::Config,
    /// The store's runtime: it drives the connections between calls.
    /// `None` only while the store is dropped.
    runtime: Option<tokio::runtime::Runtime>,
}

impl PgStore {
    /// Connect to the database at `url` (`postgres://USER[:PASSWORD]@HOST[:PORT]/DATABASE`),
    /// its schema brought up to date.
    ///
    /// # Errors
    /// [`StoreError::Url`] for a URL that does not parse;
    /// [`StoreError::Postgres`] if the database cannot be reached or set
    /// up; [`StoreError::TooNew`] for a store a newer gapack made.
    pub fn open(url: &str) -> Result<PgStore, StoreError> {
        let mut config: tokio_postgres::Config = url.parse().map_err(|e| {
            StoreError::Url(format!(
                "--store {}: {}",
                super::StoreUrl::Postgres(url.to_owned()).shown(),
                message(&e)
            ))
        })?;
        config
            .connect_timeout(CONNECT_TIMEOUT)
            // A peer gone without closing (a machine cut off) is found
            // in about 25 s, rather than the system's two hours.
            .keepalives(true)
            .keepalives_idle(Duration::from_secs(10))
            .keepalives_interval(Duration::from_secs(5))
            .keepalives_retries(3)
            .application_name("gapack");
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("gapack-postgres")
            .enable_all()
            .build()
            .map_err(|e| StoreError::Postgres(format!("cannot start its runtime: {e}")))?;
        let manager = Manager::from_config(
            config.clone(),
            NoTls,
            ManagerConfig {
                // A connection PostgreSQL closed is found closed before it
                // is handed out; one that fails in use fails that call (its
                // caller tries again), without a query per checkout.
                recycling_method: RecyclingMethod::Fast,
            },
        );
        let pool = Pool::builder(manager)
            .max_size(POOL_SIZE)
            .wait_timeout(Some(WAIT_TIMEOUT))
            .create_timeout(Some(CONNECT_TIMEOUT))
            .recycle_timeout(Some(CONNECT_TIMEOUT))
            .runtime(deadpool_postgres::Runtime::Tokio1)
            .build()
            .map_err(|e| StoreError::Postgres(format!("cannot make its pool: {e}")))?;
        let store = PgStore {
            pool,
            config,
            runtime: Some(runtime),
        };
        store.run(async {
            let mut client = store.pool.get().await?;
            migrate(&mut client).await
        })?;
        Ok(store)
    }

    /// Run `work` on the store's runtime, waiting for it, within
    /// [`CALL_TIMEOUT`].
    fn run<T>(&self, work: impl Future<Output = Result<T, StoreError>>) -> Result<T, StoreError> {
        let Some(runtime) = &self.runtime else {
            return Err(StoreError::Postgres("the store is closed".to_owned()));
        };
        runtime.block_on(async {
            tokio::time::timeout(CALL_TIMEOUT, work)
                .await
                .unwrap_or_else(|_| {
                    Err(StoreError::Postgres(format!(
                        "PostgreSQL did not answer within {} s",
                        CALL_TIMEOUT.as_secs()
                    )))
                })
        })
    }

    /// Run `f` in a transaction, committed if it returns `Ok` (rolled back
    /// otherwise).
    fn write<T>(
        &self,
        f: impl AsyncFnOnce(&Transaction<'_>) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        self.run(async {
            let mut client = self.pool.get().await?;
            let tx = client.transaction().await?;
            let value = f(&tx).await?;
            tx.commit().await?;
            Ok(value)
        })
    }

    /// Run `f` on a connection of the pool (one statement, or reads).
    fn read<T>(
        &self,
        f: impl AsyncFnOnce(&deadpool_postgres::Client) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        self.run(async {
            let client = self.pool.get().await?;
            f(&client).await
        })
    }
}

impl Drop for PgStore {
    fn drop(&mut self) {
        // Without waiting (this may run in async code): its connections
        // and listeners end with it.
        if let Some(runtime) = self.runtime.take() {
            runtime.shutdown_background();
        }
    }
}

/// Apply the steps past the store's version, each in its own transaction
/// under [`MIGRATION_LOCK`].
async fn migrate(client: &mut deadpool_postgres::Client) -> Result<(), StoreError> {
    for step in &MIGRATIONS {
        let tx = client.transaction().await?;
        tx.execute("SELECT pg_advisory_xact_lock($1)", &[&MIGRATION_LOCK])
            .await?;
        tx.batch_execute(
            "CREATE TABLE IF NOT EXISTS schema_version \
             (version BIGINT PRIMARY KEY, applied_ms BIGINT NOT NULL)",
        )
        .await?;
        let version: i64 = tx
            .query_one("SELECT COALESCE(MAX(version), 0) FROM schema_version", &[])
            .await?
            .try_get(0)?;
        if version > LATEST {
            return Err(StoreError::TooNew {
                found: version,
                known: LATEST,
            });
        }
        if version >= step.version {
            // Applied already (by this process earlier, or another one).
            tx.commit().await?;
            continue;
        }
        tx.batch_execute(step.postgres).await?;
        tx.execute(
            "INSERT INTO schema_version (version, applied_ms) \
             VALUES ($1, (extract(epoch from clock_timestamp()) * 1000)::BIGINT)",
            &[&step.version],
        )
        .await?;
        tx.commit().await?;
    }
    Ok(())
}

mod listen;
mod queries;

/// A fresh database for a test, on the cluster `GAPACK_TEST_POSTGRES`
/// names (a URL to a database there, as a user who may create
/// databases): its URL. `None`, having said how to run the test, when the
/// variable is unset, unless `GAPACK_POSTGRES_TESTS=required` (then the
/// test fails). The databases are left behind, for a throwaway cluster.
#[cfg(test)]
pub fn test_database() -> Option<String> {
    let Ok(url) = std::env::var("GAPACK_TEST_POSTGRES") else {
        assert!(
            std::env::var("GAPACK_POSTGRES_TESTS").as_deref() != Ok("required"),
            "GAPACK_POSTGRES_TESTS=required but GAPACK_TEST_POSTGRES is unset"
        );
        println!(
            "skipped: the PostgreSQL store tests run with \
             GAPACK_TEST_POSTGRES=postgres://USER@HOST:PORT/postgres (a user who may create databases)"
        );
        return None;
    };
    let name = format!("gapack_t_{:016x}", rand::random::<u64>());
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("a runtime for the test");
    runtime.block_on(async {
        let (client, connection) = tokio_postgres::connect(&url, NoTls)
            .await
            .unwrap_or_else(|e| panic!("cannot connect to GAPACK_TEST_POSTGRES: {e}"));
        let driver = tokio::spawn(connection);
        client
            .batch_execute(&format!("CREATE DATABASE {name}"))
            .await
            .unwrap_or_else(|e| panic!("cannot create database {name}: {e}"));
        drop(client);
        let _ = driver.await;
    });
    // The same URL with the new database as its path.
    let (scheme, rest) = url.split_once("://").expect("a URL with a scheme");
    let authority = rest.split(['/', '?']).next().unwrap_or(rest);
    let query = rest.find('?').map_or("", |at| &rest[at..]);
    Some(format!("{scheme}://{authority}/{name}{query}"))
}
