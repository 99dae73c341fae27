//! What every engine of the job store must do, checked on each: every
//! `check_*` function takes a fresh store and runs against SQLite (a
//! temporary file) and PostgreSQL (a fresh database on the cluster
//! `GAPACK_TEST_POSTGRES` names; those tests skip, saying so, without it).
//! The PostgreSQL-only tests (`shared_store`) check what only a shared store
//! meets: concurrent claimers and openers, notifications, a database that
//! goes away and comes back.

mod checks;
mod shared_store;

use checks::check_tokens_hold_hashes_only;

use std::sync::{PoisonError, RwLock, RwLockReadGuard};
use std::time::Duration;

use super::postgres::{PgStore, test_database};
use super::sqlite::SqliteStore;
use super::{Beat, Caller, FIRST_USER, JobStore, NewJob, QueueLimits, Role, State};

/// Limits no test reaches.
const ROOMY: QueueLimits = QueueLimits {
    total: 10_000,
    per_user: 10_000,
};

/// A lease long enough not to run out during a test.
const LONG: Duration = Duration::from_secs(600);

/// A seed that needs all 64 bits.
const SEED: u64 = u64::MAX - 6;

fn job<'a>(id: &'a str, owner: &'a Caller) -> NewJob<'a> {
    NewJob {
        id,
        owner,
        kind: "optimise",
        config: "[scene]\nparticles = 10\n",
        seed: Some(SEED),
        force: true,
        checkpoint_every: 7,
    }
}

/// A stand-in for a token's SHA-256: 32 bytes that depend on every byte
/// of `token` (the store only ever sees this hash).
fn hash_of(token: &str) -> [u8; 32] {
    let mut out = [0u8; 32];
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for (i, slot) in out.iter_mut().enumerate() {
        for b in token.bytes().chain([i as u8]) {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        *slot = (h >> 24) as u8;
    }
    out
}

fn admin(store: &dyn JobStore) -> Caller {
    store
        .user_named(FIRST_USER)
        .unwrap()
        .expect("the first user")
}

fn user(store: &dyn JobStore, name: &str) -> Caller {
    let added = store
        .add_user(name, Role::User, &hash_of(name), None, None)
        .unwrap();
    Caller::from(added)
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Event numbers run 1, 2, 3… per job, and a reader resumes after any.
fn sqlite() -> (tempfile::TempDir, SqliteStore) {
    let dir = tempfile::tempdir().unwrap();
    let store = SqliteStore::open(&dir.path().join("gapack.db")).unwrap();
    (dir, store)
}

/// The cluster: the test that stops it holds it alone, the others share
/// it (each holds it for as long as it runs).
pub static CLUSTER: RwLock<()> = RwLock::new(());

/// A share of the cluster, for a test that needs it up.
pub fn cluster() -> RwLockReadGuard<'static, ()> {
    CLUSTER.read().unwrap_or_else(PoisonError::into_inner)
}

/// A fresh database (its URL) while the cluster is shared; `None` (the
/// test skips) without a cluster.
fn database() -> Option<(String, RwLockReadGuard<'static, ()>)> {
    let up = cluster();
    Some((test_database()?, up))
}

/// A store on a fresh database, with its URL and the share of the
/// cluster; `None` (the test skips) without a cluster.
fn postgres() -> Option<(String, PgStore, RwLockReadGuard<'static, ()>)> {
    let (url, up) = database()?;
    let store = PgStore::open(&url).unwrap();
    Some((url, store, up))
}

/// Run `sql` on the database at `url`; every row's columns as text.
fn pg_text(url: &str, sql: &str) -> Vec<Vec<String>> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    runtime.block_on(async {
        let (client, connection) = tokio_postgres::connect(url, tokio_postgres::NoTls)
            .await
            .unwrap();
        tokio::spawn(connection);
        client
            .simple_query(sql)
            .await
            .unwrap()
            .into_iter()
            .filter_map(|m| match m {
                tokio_postgres::SimpleQueryMessage::Row(r) => Some(
                    (0..r.len())
                        .map(|i| r.get(i).unwrap_or("").to_owned())
                        .collect(),
                ),
                _ => None,
            })
            .collect()
    })
}

/// Each check, as a test on each engine.
macro_rules! on_both_engines {
    ($($check:ident),* $(,)?) => {
        mod on_sqlite {
            $(
                #[test]
                fn $check() {
                    let (_dir, store) = super::sqlite();
                    super::checks::$check(&store);
                }
            )*
        }
        mod on_postgres {
            $(
                #[test]
                fn $check() {
                    if let Some((_url, store, _up)) = super::postgres() {
                        super::checks::$check(&store);
                    }
                }
            )*
        }
    };
}

on_both_engines!(
    check_events_are_numbered_per_job,
    check_cancel,
    check_delete,
    check_paging,
    check_scoping,
    check_queue_limits,
    check_fair_claims,
    check_leases,
    check_worker_counters,
    check_users,
);

#[test]
fn sqlite_tokens_hold_hashes_only() {
    let (dir, store) = sqlite();
    let path = dir.path().join("gapack.db");
    check_tokens_hold_hashes_only(&store, &|| {
        let conn = rusqlite::Connection::open(&path).unwrap();
        let mut stmt = conn
            .prepare("SELECT hex(hash), user_id, created_ms, revoked_ms FROM tokens")
            .unwrap();
        let rows: Vec<String> = stmt
            .query_map([], |r| {
                Ok(format!(
                    "{}|{}|{}|{:?}",
                    r.get::<_, String>(0)?,
                    r.get::<_, i64>(1)?,
                    r.get::<_, i64>(2)?,
                    r.get::<_, Option<i64>>(3)?
                ))
            })
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        rows.join("\n")
    });
}

#[test]
fn postgres_tokens_hold_hashes_only() {
    let Some((url, store, _up)) = postgres() else {
        return;
    };
    check_tokens_hold_hashes_only(&store, &|| {
        pg_text(&url, "SELECT t::text FROM tokens t")
            .into_iter()
            .map(|r| r.join("|"))
            .collect::<Vec<_>>()
            .join("\n")
    });
}

/// SQLite serves one process: at its start, every job left running goes
/// back to the queue, to resume.
#[test]
fn sqlite_recover_requeues_running_jobs() {
    let (_dir, store) = sqlite();
    let a = admin(&store);
    store.insert(&job("r1", &a), ROOMY).unwrap();
    store.insert(&job("r2", &a), ROOMY).unwrap();
    let claimed = store.claim("w", LONG).unwrap().unwrap();
    assert_eq!(store.recover().unwrap(), 1);
    let row = store.get(&a, "r1").unwrap().unwrap();
    assert_eq!(row.state, State::Queued);
    assert!(row.resume);
    assert_eq!(store.get(&a, "r2").unwrap().unwrap().state, State::Queued);
    assert_eq!(
        store.heartbeat("w", "r1", claimed.lease, LONG).unwrap(),
        Beat::Lost
    );
}

/// PostgreSQL is shared: a starting front leaves running jobs to their
/// leases.
#[test]
fn postgres_recover_leaves_running_jobs() {
    let Some((_url, store, _up)) = postgres() else {
        return;
    };
    let a = admin(&store);
    store.insert(&job("r1", &a), ROOMY).unwrap();
    let claimed = store.claim("w", LONG).unwrap().unwrap();
    assert_eq!(store.recover().unwrap(), 0);
    assert_eq!(
        store.heartbeat("w", "r1", claimed.lease, LONG).unwrap(),
        Beat::Held {
            cancel_requested: false
        }
    );
}
