//! What only a shared store meets, on PostgreSQL: concurrent claimers
//! and openers, unreachable and silent servers, notifications, a database
//! that goes away and comes back.

use std::sync::{Arc, Barrier, PoisonError};
use std::thread;
use std::time::{Duration, Instant};

use serde_json::json;

use super::{CLUSTER, LONG, ROOMY, admin, database, job, pg_text, postgres};
use crate::store::postgres::PgStore;
use crate::store::{CancelOutcome, JobStore, Notice, StoreError};

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
