//! The job store: a row per job, the events each job sent (numbered, for
//! `Last-Event-ID`), the users and the hashes of their tokens, and the
//! workers that hold jobs under leases. Two engines keep it:
//!
//! - [`sqlite`]: one file beside the data (`sqlite://DIR/gapack.db`), the
//!   embedded default, for one `gapack serve` process;
//! - [`postgres`]: a PostgreSQL database (`postgres://…`), shared by any
//!   number of fronts (`gapack serve`) and workers (`gapack worker`) on
//!   any number of machines.
//!
//! Both keep one schema, brought up to date by [`migrations`] when a
//! process opens the store. Every state change is one transaction that
//! also appends the `state` event saying so.
//!
//! A worker holds each job it runs under a lease: a number the claim
//! draws, valid until a deadline the worker's heartbeat pushes on. Only
//! the holder of the current lease may append the job's events or end
//! it; a worker that lost its lease (it stalled, its machine was cut off)
//! writes nothing more. A lease past its deadline is reaped by any
//! process: the job goes back to the queue, to resume from its checkpoint
//! on the next worker, or fails after [`MAX_ATTEMPTS`] attempts.
//!
//! Calls block: handlers make them on `spawn_blocking` threads, workers on
//! their own threads (the jobs layer's observer is synchronous).

#[cfg(test)]
pub mod conformance;
pub mod migrations;
pub mod postgres;
pub mod sqlite;

use std::sync::Arc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use serde::Serialize;

/// Attempts a job gets: a job whose worker was lost this many times
/// fails rather than go back to the queue (a job that kills its workers
/// cannot take them all down in turn).
pub const MAX_ATTEMPTS: i64 = 3;

/// Why the store could not answer.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// SQLite failed.
    #[error("job store: {0}")]
    Sqlite(#[from] rusqlite::Error),
    /// PostgreSQL failed (or could not be reached).
    #[error("job store: {0}")]
    Postgres(String),
    /// The queue holds as many jobs as the server takes.
    #[error("the queue is full ({0} jobs waiting); try again later")]
    QueueFull(usize),
    /// The user has as many jobs waiting as a user may.
    #[error("you have {0} jobs waiting, as many as a user may; try again when some have run")]
    UserQueueFull(usize),
    /// A user of that name exists already.
    #[error("a user named {0:?} exists already")]
    UserExists(String),
    /// A store URL this build cannot open.
    #[error("{0}")]
    Url(String),
    /// The store's schema is newer than this build knows.
    #[error(
        "the job store is at schema version {found}, newer than this gapack knows ({known}): upgrade gapack"
    )]
    TooNew {
        /// The store's version.
        found: i64,
        /// The newest this build applies.
        known: i64,
    },
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
#[derive(Debug, Clone, PartialEq)]
pub struct JobRow {
    /// Its order of submission (the paging cursor).
    pub seq: i64,
    /// Its random id.
    pub id: String,
    /// The name of the user who submitted it.
    pub owner: String,
    /// The job kind's name.
    pub kind: String,
    /// The config's text.
    pub config: String,
    /// The seed asked for, if any.
    pub seed: Option<u64>,
    /// Whether it runs over the config's limits (asked for at submission).
    pub force: bool,
    /// optimise: the checkpoint period (generations) it was submitted with,
    /// so that every worker resumes the same run.
    pub checkpoint_every: i64,
    /// Its state.
    pub state: State,
    /// Submitted (ms since the Unix epoch).
    pub created_ms: i64,
    /// When the last attempt started.
    pub started_ms: Option<i64>,
    /// When it reached its final state.
    pub finished_ms: Option<i64>,
    /// Attempts started (more than one after a restart or a lost worker).
    pub attempts: i64,
    /// Whether the next attempt goes on from the checkpoint.
    pub resume: bool,
    /// Whether a cancel was asked for while it ran.
    pub cancel_requested: bool,
    /// The worker holding it (while running).
    pub worker: Option<String>,
    /// The last progress event, JSON.
    pub progress: Option<String>,
    /// The summary of a finished job, JSON.
    pub summary: Option<String>,
    /// Why it failed.
    pub error: Option<String>,
}

/// A job to queue.
#[derive(Debug, Clone)]
pub struct NewJob<'a> {
    /// Its random id.
    pub id: &'a str,
    /// Its submitter.
    pub owner: &'a Caller,
    /// The job kind's name.
    pub kind: &'a str,
    /// The config's text.
    pub config: &'a str,
    /// The seed asked for.
    pub seed: Option<u64>,
    /// Run over the config's limits.
    pub force: bool,
    /// optimise: checkpoint period (generations).
    pub checkpoint_every: i64,
}

/// How many jobs may wait: in all, and for one user.
#[derive(Debug, Clone, Copy)]
pub struct QueueLimits {
    /// Jobs waiting, all users together.
    pub total: usize,
    /// Jobs one user may have waiting.
    pub per_user: usize,
}

/// A user's role.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Sees and acts on their own jobs only.
    User,
    /// Sees and acts on every job.
    Admin,
}

impl Role {
    /// Its name in the store.
    pub fn name(self) -> &'static str {
        match self {
            Role::User => "user",
            Role::Admin => "admin",
        }
    }

    /// The role named `name` (anything unknown is the lesser role).
    pub fn parse(name: &str) -> Role {
        if name == "admin" {
            Role::Admin
        } else {
            Role::User
        }
    }
}

/// A user of the service.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct User {
    /// Their number in the store.
    pub id: i64,
    /// Their name (unique).
    pub name: String,
    /// What they may see.
    pub role: Role,
    /// Most jobs they may have waiting (`None`: the server's default).
    pub max_queued: Option<i64>,
    /// Most particles a scene of theirs may hold (`None`: the server's
    /// ceiling; never above it).
    pub max_particles: Option<i64>,
    /// Tokens not revoked.
    pub tokens: i64,
}

/// Who makes a request: the user its token names. Every read and change
/// of a job goes through a caller; a job not theirs (unless they are an
/// admin) is as missing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Caller {
    /// The user's number.
    pub id: i64,
    /// The user's name.
    pub name: String,
    /// Whether they see every job.
    pub admin: bool,
    /// Most jobs they may have waiting (`None`: the server's default).
    pub max_queued: Option<i64>,
    /// Most particles a scene of theirs may hold (`None`: the server's).
    pub max_particles: Option<i64>,
}

impl From<User> for Caller {
    fn from(u: User) -> Self {
        Caller {
            id: u.id,
            admin: u.role == Role::Admin,
            name: u.name,
            max_queued: u.max_queued,
            max_particles: u.max_particles,
        }
    }
}

/// The user every store starts with (number 1): the admin of the
/// `--token-file` token, and of a server with no token on loopback.
pub const FIRST_USER: &str = "admin";

/// A job claimed by a worker, under a lease.
#[derive(Debug, Clone)]
pub struct Claimed {
    /// The job, as it is now (running, its attempt counted).
    pub job: JobRow,
    /// The lease's number: shown with every write the attempt makes.
    pub lease: i64,
}

/// What a heartbeat found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Beat {
    /// The lease is renewed; whether a cancel was asked for.
    Held {
        /// A user asked to cancel the job.
        cancel_requested: bool,
    },
    /// The lease is gone (expired and reaped, or the job deleted): stop,
    /// write nothing more.
    Lost,
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
    /// Back to the queue (its worker is stopping): the next attempt resumes.
    Requeue,
}

/// A job a reaper put back in the queue (or failed) after its lease ran out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reaped {
    /// The job.
    pub id: String,
    /// Queued again, or failed after [`MAX_ATTEMPTS`].
    pub state: State,
    /// The worker that lost it.
    pub worker: Option<String>,
}

/// Jobs by owner and state, for the metrics.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UserCount {
    /// The owner's name.
    pub user: String,
    /// The state.
    pub state: State,
    /// How many of their jobs are in it.
    pub jobs: i64,
}

/// A worker as the store knows it, for the metrics.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WorkerRow {
    /// Its name (`host:pid:index`).
    pub name: String,
    /// When it last said it is alive, claimed or renewed a lease (ms
    /// since the Unix epoch).
    pub seen_ms: i64,
    /// Jobs it claimed.
    pub claimed: i64,
    /// Jobs it ended (any final state, or back to the queue at a stop).
    pub finished: i64,
    /// Leases it lost (reaped, or found gone at a heartbeat).
    pub leases_lost: i64,
}

/// Where the store lives, parsed from `--store`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StoreUrl {
    /// `sqlite://PATH` (a file).
    Sqlite(std::path::PathBuf),
    /// `postgres://…` or `postgresql://…`, as given.
    Postgres(String),
}

impl StoreUrl {
    /// Parse `--store`.
    ///
    /// # Errors
    /// [`StoreError::Url`] for any other scheme.
    pub fn parse(url: &str) -> Result<StoreUrl, StoreError> {
        if let Some(path) = url.strip_prefix("sqlite://") {
            if path.is_empty() {
                return Err(StoreError::Url(
                    "sqlite:// needs a file: sqlite://gapack-data/gapack.db".to_owned(),
                ));
            }
            return Ok(StoreUrl::Sqlite(path.into()));
        }
        if url.starts_with("postgres://") || url.starts_with("postgresql://") {
            return Ok(StoreUrl::Postgres(url.to_owned()));
        }
        Err(StoreError::Url(format!(
            "--store {:?}: give sqlite://FILE or postgres://USER@HOST:PORT/DATABASE",
            redact(url)
        )))
    }

    /// The URL as it may be shown: a password replaced by `***`.
    pub fn shown(&self) -> String {
        match self {
            StoreUrl::Sqlite(path) => format!("sqlite://{}", path.display()),
            StoreUrl::Postgres(url) => redact(url),
        }
    }
}

/// `url` without the password of its `user:password@` part.
fn redact(url: &str) -> String {
    let Some((scheme, rest)) = url.split_once("://") else {
        return url.to_owned();
    };
    let authority_end = rest.find('/').unwrap_or(rest.len());
    let (authority, path) = rest.split_at(authority_end);
    match authority.rsplit_once('@') {
        Some((user, host)) => match user.split_once(':') {
            Some((name, _)) => format!("{scheme}://{name}:***@{host}{path}"),
            None => url.to_owned(),
        },
        None => url.to_owned(),
    }
}

/// Open the store at `url`, bringing its schema up to date.
///
/// # Errors
/// [`StoreError`] when it cannot be reached, opened or migrated.
pub fn open(url: &StoreUrl) -> Result<Arc<dyn JobStore>, StoreError> {
    Ok(match url {
        StoreUrl::Sqlite(path) => Arc::new(sqlite::SqliteStore::open(path)?),
        StoreUrl::Postgres(url) => Arc::new(postgres::PgStore::open(url)?),
    })
}

/// What every store does. Per-job reads and changes take the [`Caller`]:
/// a job of another user is answered as missing (`None`), unless the
/// caller is an admin.
pub trait JobStore: Send + Sync {
    /// `sqlite` or `postgres`.
    fn engine(&self) -> &'static str;

    /// What a starting front does to jobs a crash left running. SQLite,
    /// which serves one process, re-queues them all at once (to resume);
    /// PostgreSQL leaves them to their leases. Returns how many.
    fn recover(&self) -> Result<usize, StoreError>;

    /// Queue `job`, unless the queue or its owner's share is full.
    fn insert(&self, job: &NewJob<'_>, limits: QueueLimits) -> Result<(), StoreError>;

    /// Take the next queued job for `worker` under a lease of `ttl`: the
    /// oldest job of the user with the fewest jobs running (so that one
    /// user's long queue does not starve the rest). Concurrent claims
    /// never take the same job.
    fn claim(&self, worker: &str, ttl: Duration) -> Result<Option<Claimed>, StoreError>;

    /// Renew the lease on job `id` for `ttl` more.
    fn heartbeat(
        &self,
        worker: &str,
        id: &str,
        lease: i64,
        ttl: Duration,
    ) -> Result<Beat, StoreError>;

    /// Append an event of the attempt holding `lease` (and keep it as the
    /// job's progress when `progress`). Its number, or `None` when the
    /// lease is gone (nothing written).
    fn event(
        &self,
        id: &str,
        lease: i64,
        data: &serde_json::Value,
        progress: bool,
    ) -> Result<Option<i64>, StoreError>;

    /// End the attempt holding `lease`. `false` when the lease is gone
    /// (another worker has the job now; nothing written).
    fn finish(
        &self,
        worker: &str,
        id: &str,
        lease: i64,
        ending: &Ending,
    ) -> Result<bool, StoreError>;

    /// Put back in the queue (or fail, after [`MAX_ATTEMPTS`]) every job
    /// whose lease ran out. Any process may call it; each expired lease is
    /// reaped once.
    fn reap(&self) -> Result<Vec<Reaped>, StoreError>;

    /// Cancel a job: a queued one at once, a running one by flag (its
    /// worker sees it at its next heartbeat), a finished one not at all.
    fn cancel(&self, who: &Caller, id: &str) -> Result<Option<CancelOutcome>, StoreError>;

    /// Whether a cancel was asked for `id`.
    fn cancel_requested(&self, id: &str) -> Result<bool, StoreError>;

    /// One job.
    fn get(&self, who: &Caller, id: &str) -> Result<Option<JobRow>, StoreError>;

    /// Up to `limit` jobs, newest first, submitted before `before` (a
    /// `seq`), in `state` if given.
    fn list(
        &self,
        who: &Caller,
        state: Option<State>,
        before: Option<i64>,
        limit: usize,
    ) -> Result<Vec<JobRow>, StoreError>;

    /// Remove a finished job and its events: `Some(Err(state))` for a job
    /// not finished (nothing removed), `None` for no such job.
    fn delete(&self, who: &Caller, id: &str) -> Result<Option<Result<(), State>>, StoreError>;

    /// Up to `limit` events of `id` numbered after `after`, in order. The
    /// caller has checked the job is the asker's.
    fn events_after(
        &self,
        id: &str,
        after: i64,
        limit: usize,
    ) -> Result<Vec<(i64, String)>, StoreError>;

    /// How many jobs are in each state.
    fn counts(&self) -> Result<Vec<(State, i64)>, StoreError>;

    /// Jobs by owner and state (the states a user has jobs in).
    fn counts_by_user(&self) -> Result<Vec<UserCount>, StoreError>;

    /// The workers that ever claimed a job or said they are alive, with
    /// their counters.
    fn workers(&self) -> Result<Vec<WorkerRow>, StoreError>;

    /// Workers `names` are alive (idle or busy): their `seen_ms` is now.
    fn alive(&self, names: &[String]) -> Result<(), StoreError>;

    /// Add a user with the token whose SHA-256 is `token_hash`.
    fn add_user(
        &self,
        name: &str,
        role: Role,
        token_hash: &[u8; 32],
        max_queued: Option<i64>,
        max_particles: Option<i64>,
    ) -> Result<User, StoreError>;

    /// Revoke every token of user `name` (they can no longer sign in;
    /// their jobs stay). `false`: no such user.
    fn revoke_user(&self, name: &str) -> Result<bool, StoreError>;

    /// Every user, by number.
    fn users(&self) -> Result<Vec<User>, StoreError>;

    /// The user whose live token hashes to `token_hash`.
    fn user_by_token(&self, token_hash: &[u8; 32]) -> Result<Option<Caller>, StoreError>;

    /// The user named `name`.
    fn user_named(&self, name: &str) -> Result<Option<Caller>, StoreError>;

    /// Whether a token was ever issued to a user (revoked or not): then a
    /// request without a live token is refused, even on loopback. (Revoking
    /// the last user's token must not open the server to everyone.)
    fn has_tokens(&self) -> Result<bool, StoreError>;

    /// News from other processes sharing the store, for this process's
    /// event streams and idle workers; `None` when nothing else shares it.
    fn subscribe(&self) -> Option<std::sync::mpsc::Receiver<Notice>>;
}

/// What another process sharing the store told this one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Notice {
    /// Job `id` has a new event or state.
    Event(String),
    /// A job was queued.
    Queued,
    /// A cancel was asked for job `id`.
    Cancel(String),
    /// The connection that brings news was lost and is back: anything may
    /// have happened meanwhile.
    Resync,
}

/// Milliseconds since the Unix epoch, by this machine's clock.
pub fn now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// `d` in whole milliseconds (saturated).
pub fn millis(d: Duration) -> i64 {
    i64::try_from(d.as_millis()).unwrap_or(i64::MAX)
}

/// The `state` event of a change to `state`.
pub fn state_event(state: State) -> serde_json::Value {
    serde_json::json!({"event": "state", "state": state.name()})
}

#[cfg(test)]
mod tests {
    use super::{StoreUrl, redact};

    #[test]
    fn store_urls_are_parsed_and_shown_without_passwords() {
        assert_eq!(
            StoreUrl::parse("sqlite://gapack-data/gapack.db").unwrap(),
            StoreUrl::Sqlite("gapack-data/gapack.db".into())
        );
        assert!(matches!(
            StoreUrl::parse("postgresql://u@h/db").unwrap(),
            StoreUrl::Postgres(_)
        ));
        assert!(StoreUrl::parse("sqlite://").is_err());
        let refused = StoreUrl::parse("mysql://u:secret@h/db")
            .unwrap_err()
            .to_string();
        assert!(!refused.contains("secret"), "{refused}");
        assert_eq!(
            redact("postgres://gapack:pw@10.0.0.1:5432/gapack"),
            "postgres://gapack:***@10.0.0.1:5432/gapack"
        );
        assert_eq!(redact("postgres://gapack@h/db"), "postgres://gapack@h/db");
    }
}
