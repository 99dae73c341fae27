//! The checks every engine passes, each on a fresh store.

use std::thread;
use std::time::Duration;

use serde_json::json;

use super::{LONG, ROOMY, SEED, admin, hash_of, hex, job, user};
use crate::store::{
    Beat, Caller, CancelOutcome, Ending, FIRST_USER, JobStore, MAX_ATTEMPTS, QueueLimits, Role,
    State, StoreError,
};

pub(super) fn check_events_are_numbered_per_job(store: &dyn JobStore) {
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
pub(super) fn check_cancel(store: &dyn JobStore) {
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
pub(super) fn check_delete(store: &dyn JobStore) {
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
pub(super) fn check_paging(store: &dyn JobStore) {
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
pub(super) fn check_scoping(store: &dyn JobStore) {
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
pub(super) fn check_queue_limits(store: &dyn JobStore) {
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
pub(super) fn check_fair_claims(store: &dyn JobStore) {
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
pub(super) fn check_leases(store: &dyn JobStore) {
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
pub(super) fn check_worker_counters(store: &dyn JobStore) {
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
pub(super) fn check_users(store: &dyn JobStore) {
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
pub(super) fn check_tokens_hold_hashes_only(store: &dyn JobStore, dump: &dyn Fn() -> String) {
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
