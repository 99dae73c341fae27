//! What every engine of the job store must do, checked on each: every
//! `check_*` function takes a fresh store and runs against SQLite (a
//! temporary file) and PostgreSQL (a fresh database on the cluster
//! `GAPACK_TEST_POSTGRES` names; those tests skip, saying so, without it).
//! The PostgreSQL-only tests at the end check what only a shared store
//! meets: concurrent claimers and openers, notifications, a database that
//! goes away and comes back.

use std::sync::{Arc, Barrier, PoisonError, RwLock, RwLockReadGuard};
use std::thread;
use std::time::{Duration, Instant};

use serde_json::json;

use super::postgres::{PgStore, test_database};
use super::sqlite::SqliteStore;
use super::{
    Beat, Caller, CancelOutcome, Ending, FIRST_USER, JobStore, MAX_ATTEMPTS, NewJob, Notice,
    QueueLimits, Role, State, StoreError,
};

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
fn check_events_are_numbered_per_job(store: &dyn JobStore) {
    let a = admin(store);
    store.insert(&job("j1", &a), ROOMY).unwrap();
    store.insert(&job("j2", &a), ROOMY).unwrap();
    let claimed = store.claim("w", LONG).unwrap().unwrap();
    assert_eq!(claimed.job.id, "j1");
    assert_eq!(claimed.job.seed, Some(SEED));
    assert!(claimed.job.force);
    assert_eq!(claimed.job.checkpoint_every, 7);
    assert_eq!(claimed.job.owner, FIRST_USER);
    for g in 0..5 {
        let seq = store
            .event(
                "j1",
                claimed.lease,
                &json!({"event": "progress", "g": g}),
                true,
            )
            .unwrap();
        // 1 queued, 2 running, then ours.
        assert_eq!(seq, Some(3 + g));
    }
    let all = store.events_after("j1", 0, 100).unwrap();
    let numbers: Vec<i64> = all.iter().map(|(n, _)| *n).collect();
    assert_eq!(numbers, (1..=7).collect::<Vec<_>>());
    assert!(all[0].1.contains("queued"), "{}", all[0].1);
    assert!(all[1].1.contains("running"), "{}", all[1].1);
    let after: Vec<i64> = store
        .events_after("j1", 4, 100)
        .unwrap()
        .iter()
        .map(|(n, _)| *n)
        .collect();
    assert_eq!(after, vec![5, 6, 7]);
    assert_eq!(store.events_after("j1", 4, 2).unwrap().len(), 2);
    assert!(store.events_after("j1", 7, 100).unwrap().is_empty());
    // The other job counts from 1 on its own.
    let other: Vec<i64> = store
        .events_after("j2", 0, 100)
        .unwrap()
        .iter()
        .map(|(n, _)| *n)
        .collect();
    assert_eq!(other, vec![1]);
    let row = store.get(&a, "j1").unwrap().unwrap();
    assert_eq!(
        row.progress.as_deref(),
        Some(r#"{"event":"progress","g":4}"#)
    );
    // A non-progress event leaves the progress as it was.
    store
        .event("j1", claimed.lease, &json!({"event": "note"}), false)
        .unwrap();
    let row = store.get(&a, "j1").unwrap().unwrap();
    assert_eq!(
        row.progress.as_deref(),
        Some(r#"{"event":"progress","g":4}"#)
    );
}

/// A queued job is cancelled at once, a running one by flag, a finished
/// one not at all.
fn check_cancel(store: &dyn JobStore) {
    let a = admin(store);
    assert_eq!(store.cancel(&a, "nope").unwrap(), None);
    store.insert(&job("run", &a), ROOMY).unwrap();
    store.insert(&job("wait", &a), ROOMY).unwrap();
    let claimed = store.claim("w", LONG).unwrap().unwrap();
    assert_eq!(claimed.job.id, "run");
    assert_eq!(
        store.cancel(&a, "wait").unwrap(),
        Some(CancelOutcome::Dequeued)
    );
    let waited = store.get(&a, "wait").unwrap().unwrap();
    assert_eq!(waited.state, State::Cancelled);
    assert!(waited.finished_ms.is_some());
    let last = store.events_after("wait", 0, 100).unwrap();
    assert!(last.last().unwrap().1.contains("cancelled"));
    assert!(!store.cancel_requested("run").unwrap());
    assert_eq!(
        store.cancel(&a, "run").unwrap(),
        Some(CancelOutcome::Stopping)
    );
    assert!(store.cancel_requested("run").unwrap());
    assert_eq!(store.get(&a, "run").unwrap().unwrap().state, State::Running);
    assert_eq!(
        store.heartbeat("w", "run", claimed.lease, LONG).unwrap(),
        Beat::Held {
            cancel_requested: true
        }
    );
    let ending = Ending::Final {
        state: State::Cancelled,
        summary: Some("{}".to_owned()),
        error: None,
    };
    assert!(store.finish("w", "run", claimed.lease, &ending).unwrap());
    assert_eq!(
        store.cancel(&a, "run").unwrap(),
        Some(CancelOutcome::Finished(State::Cancelled))
    );
    assert_eq!(
        store.cancel(&a, "wait").unwrap(),
        Some(CancelOutcome::Finished(State::Cancelled))
    );
    assert!(!store.cancel_requested("nope").unwrap());
}

/// Only a finished job is deleted, with its events, and only by its
/// owner (or an admin).
fn check_delete(store: &dyn JobStore) {
    let a = admin(store);
    let b = user(store, "bea");
    store.insert(&job("mine", &b), ROOMY).unwrap();
    assert_eq!(store.delete(&b, "mine").unwrap(), Some(Err(State::Queued)));
    let claimed = store.claim("w", LONG).unwrap().unwrap();
    assert_eq!(store.delete(&b, "mine").unwrap(), Some(Err(State::Running)));
    let ending = Ending::Final {
        state: State::Succeeded,
        summary: Some(r#"{"ok":true}"#.to_owned()),
        error: None,
    };
    assert!(store.finish("w", "mine", claimed.lease, &ending).unwrap());
    let done = store.get(&b, "mine").unwrap().unwrap();
    assert_eq!(done.summary.as_deref(), Some(r#"{"ok":true}"#));
    assert_eq!(done.worker, None);
    let c = user(store, "cy");
    assert_eq!(store.delete(&c, "mine").unwrap(), None);
    assert!(store.get(&b, "mine").unwrap().is_some());
    assert_eq!(store.delete(&b, "mine").unwrap(), Some(Ok(())));
    assert_eq!(store.get(&a, "mine").unwrap(), None);
    assert!(store.events_after("mine", 0, 100).unwrap().is_empty());
    assert_eq!(store.delete(&b, "mine").unwrap(), None);
    // An admin deletes anyone's.
    store.insert(&job("theirs", &c), ROOMY).unwrap();
    store.cancel(&c, "theirs").unwrap();
    assert_eq!(store.delete(&a, "theirs").unwrap(), Some(Ok(())));
}

/// Lists are newest first, paged by `before`, filtered by state.
fn check_paging(store: &dyn JobStore) {
    let a = admin(store);
    let ids = ["p0", "p1", "p2", "p3", "p4"];
    for id in ids {
        store.insert(&job(id, &a), ROOMY).unwrap();
    }
    store.cancel(&a, "p1").unwrap();
    let page = store.list(&a, None, None, 2).unwrap();
    let got: Vec<&str> = page.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(got, vec!["p4", "p3"]);
    let next = store.list(&a, None, Some(page[1].seq), 2).unwrap();
    let got: Vec<&str> = next.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(got, vec!["p2", "p1"]);
    let last = store.list(&a, None, Some(next[1].seq), 2).unwrap();
    let got: Vec<&str> = last.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(got, vec!["p0"]);
    let queued = store.list(&a, Some(State::Queued), None, 10).unwrap();
    let got: Vec<&str> = queued.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(got, vec!["p4", "p3", "p2", "p0"]);
    let cancelled = store.list(&a, Some(State::Cancelled), None, 10).unwrap();
    assert_eq!(cancelled.len(), 1);
    assert_eq!(cancelled[0].id, "p1");
    assert!(page.windows(2).all(|w| w[0].seq > w[1].seq));
}

/// A user sees and acts on their own jobs; another user's are missing;
/// an admin sees all.
fn check_scoping(store: &dyn JobStore) {
    let admin = admin(store);
    let a = user(store, "ann");
    let b = user(store, "bob");
    store.insert(&job("a1", &a), ROOMY).unwrap();
    store.insert(&job("b1", &b), ROOMY).unwrap();
    assert_eq!(store.get(&b, "a1").unwrap(), None);
    assert_eq!(store.cancel(&b, "a1").unwrap(), None);
    assert_eq!(store.delete(&b, "a1").unwrap(), None);
    assert_eq!(store.get(&a, "a1").unwrap().unwrap().owner, "ann");
    let bobs: Vec<String> = store
        .list(&b, None, None, 10)
        .unwrap()
        .into_iter()
        .map(|r| r.id)
        .collect();
    assert_eq!(bobs, vec!["b1"]);
    let all: Vec<String> = store
        .list(&admin, None, None, 10)
        .unwrap()
        .into_iter()
        .map(|r| r.id)
        .collect();
    assert_eq!(all, vec!["b1", "a1"]);
    assert_eq!(store.get(&admin, "a1").unwrap().unwrap().owner, "ann");
    assert_eq!(
        store.cancel(&admin, "b1").unwrap(),
        Some(CancelOutcome::Dequeued)
    );
    assert_eq!(store.get(&a, "a1").unwrap().unwrap().state, State::Queued);
}

/// The queue takes so many jobs in all, and so many of one user's (their
/// own share when set).
fn check_queue_limits(store: &dyn JobStore) {
    let a = user(store, "ann");
    let limits = QueueLimits {
        total: 5,
        per_user: 2,
    };
    store.insert(&job("a1", &a), limits).unwrap();
    store.insert(&job("a2", &a), limits).unwrap();
    assert!(matches!(
        store.insert(&job("a3", &a), limits),
        Err(StoreError::UserQueueFull(2))
    ));
    // A job no longer waiting frees its place.
    store.claim("w", LONG).unwrap().unwrap();
    store.insert(&job("a3", &a), limits).unwrap();
    // A user with a share of their own.
    let big = Caller::from(
        store
            .add_user("big", Role::User, &hash_of("big"), Some(10), None)
            .unwrap(),
    );
    assert_eq!(big.max_queued, Some(10));
    store.insert(&job("g1", &big), limits).unwrap();
    store.insert(&job("g2", &big), limits).unwrap();
    store.insert(&job("g3", &big), limits).unwrap();
    // 5 waiting: the queue is full, for everyone.
    assert!(matches!(
        store.insert(&job("g4", &big), limits),
        Err(StoreError::QueueFull(5))
    ));
    let none = Caller::from(
        store
            .add_user("none", Role::User, &hash_of("none"), Some(0), None)
            .unwrap(),
    );
    assert!(matches!(
        store.insert(&job("n1", &none), ROOMY),
        Err(StoreError::UserQueueFull(0))
    ));
    assert_eq!(store.get(&big, "g4").unwrap(), None);
}

/// A claim takes the oldest job of the user with the fewest jobs running.
fn check_fair_claims(store: &dyn JobStore) {
    let a = user(store, "ann");
    let b = user(store, "bob");
    for id in ["a1", "a2", "a3"] {
        store.insert(&job(id, &a), ROOMY).unwrap();
    }
    store.insert(&job("b1", &b), ROOMY).unwrap();
    store.insert(&job("b2", &b), ROOMY).unwrap();
    let order: Vec<String> = (0..5)
        .map(|_| store.claim("w", LONG).unwrap().unwrap().job.id)
        .collect();
    assert_eq!(order, vec!["a1", "b1", "a2", "b2", "a3"]);
    assert!(store.claim("w", LONG).unwrap().is_none());
}

/// Leases: held by heartbeats, never shared, reaped when they run out;
/// a reaped lease writes nothing more; attempts run out.
fn check_leases(store: &dyn JobStore) {
    let a = admin(store);
    store.insert(&job("l1", &a), ROOMY).unwrap();
    store.insert(&job("l2", &a), ROOMY).unwrap();
    let first = store
        .claim("w1", Duration::from_millis(50))
        .unwrap()
        .unwrap();
    assert_eq!(first.job.id, "l1");
    assert_eq!(first.job.state, State::Running);
    assert_eq!(first.job.attempts, 1);
    assert!(!first.job.resume);
    assert_eq!(first.job.worker.as_deref(), Some("w1"));
    assert_eq!(
        store
            .heartbeat("w1", "l1", first.lease, Duration::from_millis(50))
            .unwrap(),
        Beat::Held {
            cancel_requested: false
        }
    );
    let second = store.claim("w2", LONG).unwrap().unwrap();
    assert_eq!(second.job.id, "l2");
    assert_ne!(second.lease, first.lease);
    assert!(store.claim("w3", LONG).unwrap().is_none());
    thread::sleep(Duration::from_millis(150));
    let reaped = store.reap().unwrap();
    assert_eq!(reaped.len(), 1, "{reaped:?}");
    assert_eq!(reaped[0].id, "l1");
    assert_eq!(reaped[0].state, State::Queued);
    assert_eq!(reaped[0].worker.as_deref(), Some("w1"));
    assert!(store.reap().unwrap().is_empty(), "reaped once");
    let row = store.get(&a, "l1").unwrap().unwrap();
    assert_eq!(row.state, State::Queued);
    assert!(row.resume);
    assert_eq!(row.worker, None);
    let events = store.events_after("l1", 0, 100).unwrap();
    assert!(events.last().unwrap().1.contains("its worker was lost"));
    // The old lease writes nothing more.
    let before = store.events_after("l1", 0, 100).unwrap().len();
    assert_eq!(
        store
            .event("l1", first.lease, &json!({"event": "late"}), true)
            .unwrap(),
        None
    );
    let ending = Ending::Final {
        state: State::Succeeded,
        summary: None,
        error: None,
    };
    assert!(!store.finish("w1", "l1", first.lease, &ending).unwrap());
    assert_eq!(
        store.heartbeat("w1", "l1", first.lease, LONG).unwrap(),
        Beat::Lost
    );
    assert_eq!(store.events_after("l1", 0, 100).unwrap().len(), before);
    assert_eq!(store.get(&a, "l1").unwrap().unwrap().progress, None);
    // The next attempt resumes.
    let again = store
        .claim("w3", Duration::from_millis(50))
        .unwrap()
        .unwrap();
    assert_eq!(again.job.id, "l1");
    assert_eq!(again.job.attempts, 2);
    assert!(again.job.resume);
    let running = store.events_after("l1", 0, 100).unwrap();
    let running: serde_json::Value = serde_json::from_str(&running.last().unwrap().1).unwrap();
    assert_eq!(running["attempt"], 2);
    assert_eq!(running["resume"], true);
    // Lost again, and again: it fails.
    thread::sleep(Duration::from_millis(150));
    assert_eq!(store.reap().unwrap()[0].state, State::Queued);
    let third = store
        .claim("w3", Duration::from_millis(50))
        .unwrap()
        .unwrap();
    assert_eq!(third.job.attempts, MAX_ATTEMPTS);
    thread::sleep(Duration::from_millis(150));
    let reaped = store.reap().unwrap();
    assert_eq!(reaped.len(), 1);
    assert_eq!(reaped[0].state, State::Failed);
    let failed = store.get(&a, "l1").unwrap().unwrap();
    assert_eq!(failed.state, State::Failed);
    assert_eq!(
        failed.error.as_deref(),
        Some("its worker was lost 3 times; not tried again")
    );
    assert!(failed.finished_ms.is_some());
    // A job its user asked to cancel is cancelled when its worker is lost.
    store.insert(&job("l3", &a), ROOMY).unwrap();
    let doomed = store
        .claim("w4", Duration::from_millis(50))
        .unwrap()
        .unwrap();
    assert_eq!(doomed.job.id, "l3");
    assert_eq!(
        store.cancel(&a, "l3").unwrap(),
        Some(CancelOutcome::Stopping)
    );
    thread::sleep(Duration::from_millis(150));
    let reaped = store.reap().unwrap();
    assert_eq!(reaped.len(), 1);
    assert_eq!(reaped[0].state, State::Cancelled);
    assert_eq!(
        store.get(&a, "l3").unwrap().unwrap().state,
        State::Cancelled
    );
    // The long lease was never reaped.
    assert_eq!(store.get(&a, "l2").unwrap().unwrap().state, State::Running);
    // A stopping worker puts its job back, to resume.
    assert!(
        store
            .finish("w2", "l2", second.lease, &Ending::Requeue)
            .unwrap()
    );
    let back = store.get(&a, "l2").unwrap().unwrap();
    assert_eq!(back.state, State::Queued);
    assert!(back.resume);
}

/// Workers are counted: claims, ends, lost leases.
fn check_worker_counters(store: &dyn JobStore) {
    let a = admin(store);
    for id in ["c1", "c2", "c3"] {
        store.insert(&job(id, &a), ROOMY).unwrap();
    }
    let one = store.claim("alpha", LONG).unwrap().unwrap();
    let two = store.claim("alpha", LONG).unwrap().unwrap();
    let lost = store
        .claim("beta", Duration::from_millis(50))
        .unwrap()
        .unwrap();
    let ending = Ending::Final {
        state: State::Failed,
        summary: None,
        error: Some("bad".to_owned()),
    };
    assert!(
        store
            .finish("alpha", &one.job.id, one.lease, &ending)
            .unwrap()
    );
    let failed = store.events_after(&one.job.id, 0, 100).unwrap();
    assert!(failed.last().unwrap().1.contains(r#""error":"bad""#));
    assert!(
        store
            .finish("alpha", &two.job.id, two.lease, &Ending::Requeue)
            .unwrap()
    );
    thread::sleep(Duration::from_millis(150));
    assert_eq!(store.reap().unwrap().len(), 1);
    assert_eq!(
        store
            .heartbeat("beta", &lost.job.id, lost.lease, LONG)
            .unwrap(),
        Beat::Lost
    );
    let workers = store.workers().unwrap();
    let names: Vec<&str> = workers.iter().map(|w| w.name.as_str()).collect();
    assert_eq!(names, vec!["alpha", "beta"]);
    assert_eq!(
        (
            workers[0].claimed,
            workers[0].finished,
            workers[0].leases_lost
        ),
        (2, 2, 0)
    );
    // Lost once: counted by the reaper, not again by its own heartbeat.
    assert_eq!(
        (
            workers[1].claimed,
            workers[1].finished,
            workers[1].leases_lost
        ),
        (1, 0, 1)
    );
    assert!(workers[0].seen_ms > 1_600_000_000_000);
    // Alive, idle or new: seen now, counters kept.
    thread::sleep(Duration::from_millis(20));
    store
        .alive(&["alpha".to_owned(), "gamma".to_owned()])
        .unwrap();
    let seen = store.workers().unwrap();
    let names: Vec<&str> = seen.iter().map(|w| w.name.as_str()).collect();
    assert_eq!(names, vec!["alpha", "beta", "gamma"]);
    assert!(seen[0].seen_ms > workers[0].seen_ms);
    assert_eq!((seen[0].claimed, seen[0].finished), (2, 2));
    assert_eq!(seen[1].seen_ms, workers[1].seen_ms);
    assert_eq!(
        (seen[2].claimed, seen[2].finished, seen[2].leases_lost),
        (0, 0, 0)
    );
    let counts = store.counts().unwrap();
    assert_eq!(
        counts,
        vec![
            (State::Queued, 2),
            (State::Running, 0),
            (State::Succeeded, 0),
            (State::Failed, 1),
            (State::Cancelled, 0)
        ]
    );
    let b = user(store, "bo");
    store.insert(&job("b1", &b), ROOMY).unwrap();
    let by_user: Vec<(String, State, i64)> = store
        .counts_by_user()
        .unwrap()
        .into_iter()
        .map(|c| (c.user, c.state, c.jobs))
        .collect();
    assert_eq!(
        by_user,
        vec![
            ("admin".to_owned(), State::Failed, 1),
            ("admin".to_owned(), State::Queued, 2),
            ("bo".to_owned(), State::Queued, 1)
        ]
    );
}

/// Users: added once per name, found by their token's hash, shut out at
/// once when revoked.
fn check_users(store: &dyn JobStore) {
    assert!(!store.has_tokens().unwrap());
    let first = store.users().unwrap();
    assert_eq!(first.len(), 1);
    assert_eq!(first[0].name, FIRST_USER);
    assert_eq!(first[0].role, Role::Admin);
    let dee = store
        .add_user("dee", Role::Admin, &hash_of("tok-dee"), Some(4), Some(5000))
        .unwrap();
    assert_eq!(dee.tokens, 1);
    assert!(store.has_tokens().unwrap());
    assert!(matches!(
        store.add_user("dee", Role::User, &hash_of("other"), None, None),
        Err(StoreError::UserExists(name)) if name == "dee"
    ));
    let found = store.user_by_token(&hash_of("tok-dee")).unwrap().unwrap();
    assert_eq!(found.name, "dee");
    assert!(found.admin);
    assert_eq!(found.max_queued, Some(4));
    assert_eq!(found.max_particles, Some(5000));
    assert_eq!(store.user_by_token(&hash_of("tok-nobody")).unwrap(), None);
    assert_eq!(store.user_named("dee").unwrap(), Some(found.clone()));
    assert_eq!(store.user_named("nobody").unwrap(), None);
    let listed = store.users().unwrap();
    assert_eq!(listed.len(), 2);
    assert_eq!(listed[1], dee);
    assert!(store.revoke_user("dee").unwrap());
    assert_eq!(store.user_by_token(&hash_of("tok-dee")).unwrap(), None);
    // Revoking the last live token does not open the server to everyone.
    assert!(store.has_tokens().unwrap());
    assert_eq!(store.users().unwrap()[1].tokens, 0);
    assert!(!store.revoke_user("nobody").unwrap());
    // Still there, without a way in.
    assert!(store.user_named("dee").unwrap().is_some());
}

/// The tokens table holds the hash, never the clear token: `dump` gives
/// every value of every row of it as text (bytes in hex).
fn check_tokens_hold_hashes_only(store: &dyn JobStore, dump: &dyn Fn() -> String) {
    let clear = "gpk_Zm9vYmFyYmF6cXV4Y2xlYXJ0b2tlbg";
    store
        .add_user("eve", Role::User, &hash_of(clear), None, None)
        .unwrap();
    let table = dump().to_lowercase();
    assert!(table.contains(&hex(&hash_of(clear))), "{table}");
    assert!(!table.contains(&clear.to_lowercase()), "{table}");
    assert!(!table.contains(&hex(clear.as_bytes())), "{table}");
}

// ---- the engines ----

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
                    super::$check(&store);
                }
            )*
        }
        mod on_postgres {
            $(
                #[test]
                fn $check() {
                    if let Some((_url, store, _up)) = super::postgres() {
                        super::$check(&store);
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

/// Eight workers claiming at once from 200 jobs: each job is claimed
/// exactly once, and every event number is used once.
#[test]
fn postgres_concurrent_claims_take_each_job_once() {
    let Some((url, store, _up)) = postgres() else {
        return;
    };
    let a = admin(&store);
    for i in 0..200 {
        store.insert(&job(&format!("k{i:03}"), &a), ROOMY).unwrap();
    }
    let store = Arc::new(store);
    let start = Arc::new(Barrier::new(8));
    let started = Instant::now();
    let takers: Vec<_> = (0..8)
        .map(|w| {
            let store = Arc::clone(&store);
            let start = Arc::clone(&start);
            thread::spawn(move || {
                let name = format!("w{w}");
                let mut took = Vec::new();
                start.wait();
                // At most every job: the queue runs dry first.
                for _ in 0..=200 {
                    let Some(c) = store.claim(&name, LONG).unwrap() else {
                        break;
                    };
                    store
                        .event(&c.job.id, c.lease, &json!({"event": "progress"}), true)
                        .unwrap()
                        .unwrap();
                    took.push(c.job.id);
                }
                took
            })
        })
        .collect();
    let mut all: Vec<String> = takers.into_iter().flat_map(|t| t.join().unwrap()).collect();
    let took = started.elapsed();
    all.sort();
    let before = all.len();
    all.dedup();
    assert_eq!(before, 200, "claims in all");
    assert_eq!(all.len(), 200, "each job once");
    let claimed: i64 = store.workers().unwrap().iter().map(|w| w.claimed).sum();
    assert_eq!(claimed, 200);
    let doubles = pg_text(
        &url,
        "SELECT count(*) FROM (SELECT job FROM events GROUP BY job \
         HAVING count(*) <> 3 OR max(seq) <> 3) x",
    );
    assert_eq!(doubles, vec![vec!["0".to_owned()]]);
    println!("200 claims and 200 events by 8 threads: {took:?}");
}

/// Four processes opening a fresh database together: each opens it, and
/// each schema step is applied once.
#[test]
fn postgres_concurrent_opens_migrate_once() {
    let Some((url, _up)) = database() else {
        return;
    };
    let start = Arc::new(Barrier::new(4));
    let openers: Vec<_> = (0..4)
        .map(|_| {
            let url = url.clone();
            let start = Arc::clone(&start);
            thread::spawn(move || {
                start.wait();
                PgStore::open(&url).map(|s| s.engine())
            })
        })
        .collect();
    for opener in openers {
        assert_eq!(opener.join().unwrap().unwrap(), "postgres");
    }
    let versions = pg_text(&url, "SELECT version FROM schema_version ORDER BY version");
    assert_eq!(versions, vec![vec!["1".to_owned()], vec!["2".to_owned()]]);
    let users = pg_text(&url, "SELECT count(*) FROM users");
    assert_eq!(users, vec![vec!["1".to_owned()]]);
}

/// A database that cannot be reached is an error at once, whose message
/// does not show the URL's password (no cluster needed).
#[test]
fn postgres_unreachable_is_an_error_without_the_password() {
    let started = Instant::now();
    let refused = PgStore::open("postgres://gapack:s3cret-pw@127.0.0.1:1/gapack");
    let Err(StoreError::Postgres(message)) = refused else {
        panic!("not a PostgreSQL error");
    };
    assert!(!message.contains("s3cret-pw"), "{message}");
    assert!(
        started.elapsed() < Duration::from_secs(20),
        "{:?}",
        started.elapsed()
    );
    let bad = PgStore::open("postgres://gapack:s3cret-pw@127.0.0.1:1/gapack?sslmode=nonsense");
    let Err(StoreError::Url(message)) = bad else {
        panic!("not a URL error");
    };
    assert!(!message.contains("s3cret-pw"), "{message}");
}

/// A server that takes the connection and never answers: the open fails
/// after the pool's connect timeout, rather than hang (no cluster needed).
#[test]
fn postgres_silent_server_is_an_error_not_a_hang() {
    let silent = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = silent.local_addr().unwrap().port();
    let holder = thread::spawn(move || silent.accept().map(|(socket, _)| socket));
    let started = Instant::now();
    let opened = PgStore::open(&format!("postgres://gapack@127.0.0.1:{port}/gapack"));
    let took = started.elapsed();
    let Err(StoreError::Postgres(message)) = opened else {
        panic!("not a PostgreSQL error");
    };
    assert!(took < Duration::from_secs(15), "{took:?}");
    drop(holder.join().unwrap());
    println!("a silent server: the open failed after {took:?}: {message}");
}

/// A store whose schema is newer than this build is refused.
#[test]
fn postgres_refuses_a_newer_schema() {
    let Some((url, store, _up)) = postgres() else {
        return;
    };
    drop(store);
    pg_text(&url, "INSERT INTO schema_version VALUES (99, 0)");
    assert!(matches!(
        PgStore::open(&url),
        Err(StoreError::TooNew {
            found: 99,
            known: 2
        })
    ));
}

/// The store serves plain threads and the blocking threads of another
/// runtime, and may be dropped in async code.
#[test]
fn postgres_serves_any_thread() {
    let Some((_url, store, _up)) = postgres() else {
        return;
    };
    let store = Arc::new(store);
    let from_thread = {
        let store = Arc::clone(&store);
        thread::spawn(move || store.counts().map(|c| c.len()))
            .join()
            .unwrap()
    };
    assert_eq!(from_thread.unwrap(), 5);
    let server = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let from_blocking = server.block_on({
        let store = Arc::clone(&store);
        async move {
            let mut answers = Vec::new();
            for _ in 0..4 {
                let store = Arc::clone(&store);
                answers.push(tokio::task::spawn_blocking(move || {
                    store.users().map(|u| u.len())
                }));
            }
            let mut lens = Vec::new();
            for a in answers {
                lens.push(a.await.unwrap().unwrap());
            }
            lens
        }
    });
    assert_eq!(from_blocking, vec![1, 1, 1, 1]);
    // The last owner drops it inside a task.
    server.block_on(async move { drop(store) });
}

/// A change made through one store reaches another's subscriber.
#[test]
fn postgres_notifies_events() {
    let Some((url, store, _up)) = postgres() else {
        return;
    };
    let other = PgStore::open(&url).unwrap();
    let news = other.subscribe().unwrap();
    let a = admin(&store);
    // Until the listener is in place: a queued job's notice arrives.
    let mut listening = false;
    for i in 0..50 {
        store.insert(&job(&format!("n{i}"), &a), ROOMY).unwrap();
        if let Ok(Notice::Event(_) | Notice::Queued) = news.recv_timeout(Duration::from_millis(100))
        {
            listening = true;
            break;
        }
    }
    assert!(listening, "no notice within 5 s");
    let claimed = store.claim("w", LONG).unwrap().unwrap();
    thread::sleep(Duration::from_millis(200));
    while news.try_recv().is_ok() {}
    let mut delays = Vec::new();
    for k in 0..20 {
        let sent = Instant::now();
        store
            .event(
                &claimed.job.id,
                claimed.lease,
                &json!({"event": "progress", "k": k}),
                true,
            )
            .unwrap()
            .unwrap();
        let committed = sent.elapsed();
        let deadline = Instant::now() + Duration::from_secs(5);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match news.recv_timeout(left) {
                Ok(Notice::Event(id)) if id == claimed.job.id => break,
                Ok(_) => {}
                Err(e) => panic!("no notice of event {k}: {e}"),
            }
        }
        delays.push((committed, sent.elapsed()));
    }
    delays.sort();
    let median = delays[delays.len() / 2];
    println!(
        "notice of an event: median {:?} after the call began ({:?} for the call itself), worst {:?}",
        median.1,
        median.0,
        delays.iter().map(|d| d.1).max().unwrap_or_default()
    );
    assert_eq!(
        store.cancel(&a, &claimed.job.id).unwrap(),
        Some(CancelOutcome::Stopping)
    );
    let deadline = Instant::now() + Duration::from_secs(5);
    let mut cancelled = false;
    while let Ok(n) = news.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
        if n == Notice::Cancel(claimed.job.id.clone()) {
            cancelled = true;
            break;
        }
    }
    assert!(cancelled, "no cancel notice");
    // Dropping the store ends its listeners: the receiver is told.
    drop(other);
    let end = news.recv_timeout(Duration::from_secs(5));
    assert_eq!(end, Err(std::sync::mpsc::RecvTimeoutError::Disconnected));
}

/// The database stops for a while: calls fail (quickly, not hanging),
/// then work again once it is back, and a subscriber is told to resync.
/// Needs `GAPACK_TEST_PGCTL=PGBIN_DIR|DATA_DIR` of the cluster
/// `GAPACK_TEST_POSTGRES` names (skipped without it).
#[test]
fn postgres_survives_a_restart() {
    let Ok(pgctl) = std::env::var("GAPACK_TEST_PGCTL") else {
        println!("skipped: set GAPACK_TEST_PGCTL=PGBIN_DIR|DATA_DIR to stop and start the cluster");
        return;
    };
    let Some((url, shared)) = database() else {
        return;
    };
    // Alone on the cluster while it is down.
    drop(shared);
    let _alone = CLUSTER.write().unwrap_or_else(PoisonError::into_inner);
    let store = PgStore::open(&url).unwrap();
    let (bin, data) = pgctl
        .split_once('|')
        .expect("GAPACK_TEST_PGCTL=PGBIN_DIR|DATA_DIR");
    let a = admin(&store);
    store.insert(&job("s1", &a), ROOMY).unwrap();
    let news = store.subscribe().unwrap();
    thread::sleep(Duration::from_millis(300));
    // The server's own command line, to start it as it was.
    let opts = std::fs::read_to_string(format!("{data}/postmaster.opts")).unwrap();
    let args = opts
        .trim()
        .split_once(' ')
        .map_or("", |(_, rest)| rest)
        .replace(&format!("\"-D\" \"{data}\""), "");
    pg_ctl(bin, data, &["stop", "-m", "fast", "-w"]);
    // Started again however the test ends, for the tests after it.
    let mut down = Stopped {
        bin,
        data,
        args,
        up: false,
    };
    let stopped = Instant::now();
    let mut failures = Vec::new();
    while stopped.elapsed() < Duration::from_secs(3) {
        let call = Instant::now();
        let Err(error) = store.get(&a, "s1") else {
            panic!("an answer with the database down");
        };
        failures.push((call.elapsed(), error.to_string()));
        thread::sleep(Duration::from_millis(200));
    }
    down.start();
    let started = Instant::now();
    let mut back = None;
    for _ in 0..100 {
        if store.get(&a, "s1").is_ok() {
            back = Some(started.elapsed());
            break;
        }
        thread::sleep(Duration::from_millis(100));
    }
    let back = back.expect("calls work again within 10 s");
    let slowest = failures.iter().map(|f| f.0).max().unwrap_or_default();
    let message = store.get(&a, "s1").map(|r| r.map(|r| r.id));
    assert_eq!(message.unwrap().as_deref(), Some("s1"));
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut resync = false;
    while let Ok(n) = news.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
        if n == Notice::Resync {
            resync = true;
            break;
        }
    }
    assert!(resync, "no resync notice after the restart");
    let resynced = started.elapsed();
    store.insert(&job("s2", &a), ROOMY).unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    let mut heard = false;
    while let Ok(n) = news.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
        if n == Notice::Queued {
            heard = true;
            break;
        }
    }
    assert!(heard, "notices flow again");
    println!(
        "database down 3 s: {} calls failed, the slowest in {slowest:?}; calls work {back:?} \
         after the start, the subscriber resynced {resynced:?} after it",
        failures.len()
    );
    println!("the calls said: {:?}", failures.first().map(|f| &f.1));
}

/// A cluster stopped by a test: started again, as it was, by [`Stopped::start`]
/// or when dropped.
struct Stopped<'a> {
    bin: &'a str,
    data: &'a str,
    /// The server's arguments, from its `postmaster.opts`.
    args: String,
    up: bool,
}

impl Stopped<'_> {
    fn start(&mut self) {
        if !self.up {
            self.up = true;
            let log = format!("{}/gapack-restart.log", self.data);
            pg_ctl(
                self.bin,
                self.data,
                &["start", "-w", "-l", &log, "-o", &self.args],
            );
        }
    }
}

impl Drop for Stopped<'_> {
    fn drop(&mut self) {
        self.start();
    }
}

/// Run `pg_ctl` of `bin` on `data` as the data directory's owner (it
/// refuses root).
fn pg_ctl(bin: &str, data: &str, args: &[&str]) {
    use std::os::unix::fs::MetadataExt;
    let owner = std::fs::metadata(data).unwrap();
    let me = std::fs::metadata("/proc/self").unwrap();
    let pg_ctl = format!("{bin}/pg_ctl");
    let mut command = if owner.uid() == me.uid() {
        std::process::Command::new(&pg_ctl)
    } else {
        let mut c = std::process::Command::new("setpriv");
        c.arg(format!("--reuid={}", owner.uid()))
            .arg(format!("--regid={}", owner.gid()))
            .arg("--clear-groups")
            .arg(&pg_ctl);
        c
    };
    let status = command
        .arg("-D")
        .arg(data)
        .args(args)
        .current_dir("/tmp")
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "pg_ctl {args:?}: {status}");
}
