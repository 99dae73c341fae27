//! The service as a cluster: real `gapack serve` fronts and `gapack worker`
//! processes on loopback, sharing one PostgreSQL store (a private cluster,
//! `common::postgres`) and one `--data` folder. A worker killed with
//! `kill -9` mid-search, PostgreSQL stopped for 10 s under load, 1,000 jobs
//! from 25 clients over two fronts and two workers, and the users' scoping
//! and tokens over real processes. Skipped (one line on stderr) without
//! PostgreSQL, unless `GAPACK_POSTGRES_TESTS=required`.

use crate::common;

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::time::{Duration, Instant};

use common::postgres::{Cluster, Worker};
use common::server::{Server, agent};
use common::{cli_run, gapack, scratch, untimed};
use serde_json::Value;

/// A small pack (about 180 disks, a few milliseconds), writing its CSV only.
const TINY: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n[output]\nformats = [\"csv\"]\n";

/// A search long enough to be killed part-way (every generation run).
const LONG_SEARCH: &str = "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 60\nheight = 60\n[grading]\nuniform = [1.0, 2.0]\n\
     [optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 30\nstagnation = 100\n";

/// A shorter search, a few seconds: several of them keep two workers busy.
const SHORT_SEARCH: &str = "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 40\nheight = 40\n[grading]\nuniform = [1.0, 2.0]\n\
     [optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 12\nstagnation = 100\n";

/// A search that runs well past a 10 s outage of the store.
const OUTAGE_SEARCH: &str = "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 60\nheight = 60\n[grading]\nuniform = [1.0, 2.0]\n\
     [optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 90\nstagnation = 1000\n";

/// The states a job ends in.
const FINAL: [&str; 3] = ["succeeded", "failed", "cancelled"];

/// Start a front (`gapack serve`, no worker of its own) on store `url`.
fn front(data: &Path, url: &str, lease_seconds: u64, extra: &[&str]) -> Server {
    let lease = lease_seconds.to_string();
    let mut args = vec![
        "--store",
        url,
        "--workers",
        "0",
        "--lease-seconds",
        &lease,
        "--max-queue",
        "100000",
    ];
    args.extend_from_slice(extra);
    Server::start(data, &args)
}

/// An answer: its status and body.
struct Reply {
    status: u16,
    body: Vec<u8>,
}

impl Reply {
    fn json(&self) -> Value {
        serde_json::from_slice(&self.body).unwrap_or_else(|e| {
            panic!(
                "{e}: {} {}",
                self.status,
                String::from_utf8_lossy(&self.body)
            )
        })
    }

    fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }
}

/// `method url` with `token` (if any) and a TOML `body` (if any); an error
/// only when no answer came.
fn try_call(
    method: &str,
    url: &str,
    token: Option<&str>,
    body: Option<&str>,
) -> Result<Reply, ureq::Error> {
    let mut request = ureq::http::Request::builder().method(method).uri(url);
    if let Some(token) = token {
        request = request.header("Authorization", format!("Bearer {token}"));
    }
    if body.is_some() {
        request = request.header("Content-Type", "application/toml");
    }
    let request = request
        .body(body.unwrap_or("").to_owned())
        .expect("a request");
    let mut r = agent().run(request)?;
    Ok(Reply {
        status: r.status().as_u16(),
        body: r
            .body_mut()
            .with_config()
            .limit(64 << 20)
            .read_to_vec()
            .expect("body"),
    })
}

fn call(method: &str, url: &str, token: Option<&str>, body: Option<&str>) -> Reply {
    try_call(method, url, token, body).unwrap_or_else(|e| panic!("{method} {url}: {e}"))
}

/// Submit `config` as a `kind` job with `seed`: its id.
fn submit(server: &Server, token: Option<&str>, kind: &str, seed: u64, config: &str) -> String {
    let r = call(
        "POST",
        &server.url(&format!("/api/v1/jobs?kind={kind}&seed={seed}")),
        token,
        Some(config),
    );
    assert_eq!(r.status, 201, "{}", r.text());
    r.json()["id"].as_str().expect("id").to_owned()
}

/// Follow job `id`'s events from the first to the end of the stream (the
/// job's end), calling `each` on every event's data until it says stop.
fn follow_while(
    server: &Server,
    token: Option<&str>,
    id: &str,
    mut each: impl FnMut(&Value) -> bool,
) -> Vec<Value> {
    let mut request = agent().get(server.url(&format!("/api/v1/jobs/{id}/events")));
    if let Some(token) = token {
        request = request.header("Authorization", format!("Bearer {token}"));
    }
    let response = request.call().expect("events");
    assert_eq!(response.status().as_u16(), 200, "events of {id}");
    let mut seen = Vec::new();
    for line in BufReader::new(response.into_body().into_reader()).lines() {
        let line = line.expect("a line");
        if let Some(data) = line.strip_prefix("data:") {
            let v: Value = serde_json::from_str(data.trim()).expect("json");
            let go_on = each(&v);
            seen.push(v);
            if !go_on {
                break;
            }
        }
    }
    seen
}

/// Every event of a finished job.
fn events(server: &Server, token: Option<&str>, id: &str) -> Vec<Value> {
    follow_while(server, token, id, |_| true)
}

/// The `state` events among `events`, each as `state` or `state (reason)`.
fn states(events: &[Value]) -> Vec<String> {
    events
        .iter()
        .filter(|e| e["event"] == "state")
        .map(|e| {
            let state = e["state"].as_str().unwrap_or("?");
            match e["reason"].as_str() {
                Some(reason) => format!("{state} ({reason})"),
                None => state.to_owned(),
            }
        })
        .collect()
}

/// How many of `events` say the job ended.
fn endings(events: &[Value]) -> usize {
    events
        .iter()
        .filter(|e| e["event"] == "state" && FINAL.iter().any(|s| e["state"] == *s))
        .count()
}

/// Poll job `id` until it ends (at most `limit`): its view.
fn wait_end(server: &Server, token: Option<&str>, id: &str, limit: Duration) -> Value {
    let start = Instant::now();
    loop {
        if let Ok(r) = try_call(
            "GET",
            &server.url(&format!("/api/v1/jobs/{id}")),
            token,
            None,
        ) && r.status == 200
        {
            let job = r.json();
            if FINAL.iter().any(|s| job["state"] == *s) {
                return job;
            }
        }
        assert!(start.elapsed() < limit, "job {id} did not end in {limit:?}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Every job `token` may list (paged), by id.
fn list_all(server: &Server, token: &str) -> Vec<String> {
    let mut ids = Vec::new();
    let mut url = server.url("/api/v1/jobs?limit=500");
    for _ in 0..100 {
        let r = call("GET", &url, Some(token), None);
        assert_eq!(r.status, 200, "{}", r.text());
        let page = r.json();
        for job in page["jobs"].as_array().expect("jobs") {
            ids.push(job["id"].as_str().expect("id").to_owned());
        }
        match page["next"].as_str() {
            Some(next) => url = server.url(next),
            None => return ids,
        }
    }
    panic!("more than 100 pages");
}

/// `gapack user add NAME` (`--admin` if `admin`) on store `url`: the token
/// (the last line of its output).
fn add_user(dir: &Path, url: &str, name: &str, admin: bool) -> String {
    let mut args = vec!["user", "add", name, "--store", url];
    if admin {
        args.push("--admin");
    }
    let out = gapack(dir, &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let token = stdout
        .lines()
        .last()
        .expect("a token line")
        .trim()
        .to_owned();
    assert!(token.starts_with("gpk_") && token.len() == 68, "{stdout}");
    token
}

/// A file of a job, through the API.
fn file(server: &Server, token: Option<&str>, id: &str, name: &str) -> Vec<u8> {
    let r = call(
        "GET",
        &server.url(&format!("/api/v1/jobs/{id}/files/{name}")),
        token,
        None,
    );
    assert_eq!(r.status, 200, "{name}: {}", r.text());
    r.body
}

#[test]
fn a_worker_killed_mid_search_is_replaced_and_the_search_ends_as_if_never_stopped() {
    let Some(pg) = Cluster::start() else { return };
    let url = pg.create_database("kill9");
    let dir = scratch("cluster-kill9");
    let data = dir.join("data");
    let server = front(&data, &url, 2, &["--checkpoint-every", "2"]);
    let mut workers = [
        Worker::start(&data, &url, "w1", 1, 2),
        Worker::start(&data, &url, "w2", 1, 2),
    ];
    let id = submit(&server, None, "optimise", 9, LONG_SEARCH);
    // Past the first checkpoint (generation 2).
    let seen = follow_while(&server, None, &id, |e| {
        !(e["event"] == "generation" && e["index"].as_u64() >= Some(4)
            || e["event"] == "state" && FINAL.iter().any(|s| e["state"] == *s))
    });
    assert!(
        seen.iter()
            .any(|e| e["event"] == "generation" && e["index"].as_u64() >= Some(4)),
        "ended before generation 4: {seen:?}"
    );
    assert!(
        data.join("jobs")
            .join(&id)
            .join("checkpoint.json")
            .is_file()
    );
    let holder = pg.psql(
        "kill9",
        &format!("SELECT worker FROM jobs WHERE id = '{id}'"),
    );
    let victim = workers
        .iter()
        .position(|w| holder.starts_with(&format!("{}:", w.name)))
        .unwrap_or_else(|| panic!("held by {holder:?}, no worker of ours"));
    workers[victim].kill();
    let killed = Instant::now();

    let job = wait_end(&server, None, &id, Duration::from_secs(120));
    let took = killed.elapsed();
    assert_eq!(job["state"], "succeeded", "{job}");
    assert_eq!(job["attempts"], 2, "{job}");
    let events = events(&server, None, &id);
    assert_eq!(
        states(&events),
        [
            "queued",
            "running",
            "queued (its worker was lost)",
            "running",
            "succeeded"
        ]
    );
    assert_eq!(endings(&events), 1, "finished once");
    let rerun = events
        .iter()
        .filter(|e| e["event"] == "state" && e["state"] == "running")
        .nth(1)
        .expect("a second running event");
    assert_eq!(
        (&rerun["attempt"], &rerun["resume"]),
        (&2.into(), &true.into())
    );
    // The survivor finished it.
    let survivor = &workers[1 - victim].name;
    let finished = pg.psql(
        "kill9",
        &format!("SELECT name, claimed, finished FROM workers WHERE name LIKE '{survivor}:%'"),
    );
    assert_eq!(finished, format!("{survivor}:0|1|1"));
    // Resumed from its checkpoint to the packing the uninterrupted run makes.
    let cli = cli_run(&dir, "optimise", LONG_SEARCH, 9);
    assert!(
        file(&server, None, &id, "packing.csv")
            == fs::read(cli.join("packing.csv")).expect("cli packing"),
        "packing.csv differs from the uninterrupted run's"
    );
    assert_eq!(
        untimed(&file(&server, None, &id, "convergence.csv")),
        untimed(&fs::read(cli.join("convergence.csv")).expect("cli convergence")),
        "convergence.csv (but its seconds) differs from the uninterrupted run's"
    );
    eprintln!("kill -9 → the other worker finished the search {took:?} later");
    assert!(workers[1 - victim].alive());
    server.terminate();
}

#[test]
fn postgres_stopped_for_ten_seconds_loses_no_job_and_ends_each_once() {
    let Some(mut pg) = Cluster::start() else {
        return;
    };
    let url = pg.create_database("outage");
    let dir = scratch("cluster-outage");
    let data = dir.join("data");
    // Leases of 4 s, shorter than the outage: the workers cannot renew
    // them, stop their jobs themselves (before another worker may take
    // them), and the reapers put them back in the queue once the store is
    // back; the jobs resume from their checkpoints.
    let server = front(&data, &url, 4, &["--checkpoint-every", "2"]);
    let mut workers = [
        Worker::start(&data, &url, "w1", 1, 4),
        Worker::start(&data, &url, "w2", 1, 4),
    ];
    // Two long searches first (the workers take them at once), then
    // shorter ones and packs, queued.
    let mut ids: Vec<String> = (0..2)
        .map(|s| submit(&server, None, "optimise", s, OUTAGE_SEARCH))
        .collect();
    ids.extend((2..4).map(|s| submit(&server, None, "optimise", s, SHORT_SEARCH)));
    ids.extend((0..6).map(|s| submit(&server, None, "pack", s, TINY)));
    // Both long searches past their first checkpoint.
    let start = Instant::now();
    let running = loop {
        let running = pg.psql(
            "outage",
            "SELECT id FROM jobs WHERE state = 'running' AND progress LIKE '%\"generation\"%' \
             AND (progress::json->>'index')::int >= 3 ORDER BY id",
        );
        if running.lines().count() == 2 {
            break running;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "never two running"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    let running: Vec<String> = running.lines().map(str::to_owned).collect();
    let mut long = ids[..2].to_vec();
    long.sort();
    assert_eq!(running, long, "the long searches run");
    pg.stop();
    let stopped = Instant::now();
    let during = try_call("GET", &server.url("/api/v1/jobs"), None, None)
        .map(|r| r.status)
        .ok();
    assert!(
        matches!(during, Some(500 | 503)),
        "the front answers an error while the store is down: {during:?}"
    );
    std::thread::sleep(Duration::from_secs(10).saturating_sub(stopped.elapsed()));
    pg.start_again();
    let restarted = Instant::now();
    // The front answers again.
    let back = loop {
        if let Ok(r) = try_call("GET", &server.url("/api/v1/jobs"), None, None)
            && r.status == 200
        {
            break restarted.elapsed();
        }
        assert!(
            restarted.elapsed() < Duration::from_secs(30),
            "the front never answered again"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    for id in &ids {
        let job = wait_end(&server, None, id, Duration::from_secs(120));
        assert_eq!(job["state"], "succeeded", "{job}");
        let events = events(&server, None, id);
        assert_eq!(
            endings(&events),
            1,
            "{id} ended once: {:?}",
            states(&events)
        );
    }
    // The searches running through the outage stopped themselves once
    // their leases could not be renewed, went back to the queue once the
    // store was back, and resumed from their checkpoints.
    let logs = ["w1", "w2"]
        .map(|w| fs::read_to_string(data.with_extension(format!("{w}.log"))).unwrap_or_default())
        .join("");
    for id in &running {
        let events = events(&server, None, id);
        assert_eq!(
            states(&events),
            [
                "queued",
                "running",
                "queued (its worker was lost)",
                "running",
                "succeeded"
            ],
            "{id}"
        );
        let resumed = events
            .iter()
            .filter(|e| e["event"] == "state" && e["state"] == "running")
            .nth(1)
            .expect("a second running event");
        assert_eq!(resumed["resume"], true, "{id}");
        assert!(
            logs.lines()
                .any(|l| l.contains("lease not renewed in time") && l.contains(id.as_str())),
            "{id}: the attempt did not stop itself"
        );
    }
    let all = pg.psql("outage", "SELECT count(*), count(DISTINCT id) FROM jobs");
    assert_eq!(all, "10|10");
    let retried = pg.psql("outage", "SELECT count(*) FROM jobs WHERE attempts > 1");
    eprintln!(
        "PostgreSQL down 10 s: the front answered {during:?} during the outage, 200 again {back:?} after the restart; every job done {:?} after it; {retried} jobs ran more than once",
        restarted.elapsed()
    );
    for w in &mut workers {
        assert!(w.alive(), "worker {} died", w.name);
    }
    server.terminate();
}

#[test]
fn a_thousand_jobs_from_25_clients_over_two_fronts_and_two_workers_run_once_each() {
    let Some(pg) = Cluster::start() else { return };
    let url = pg.create_database("load");
    let dir = scratch("cluster-load");
    let data = dir.join("data");
    let users: Vec<(String, String)> = (0..5)
        .map(|u| {
            let name = format!("user{u}");
            let token = add_user(&dir, &url, &name, false);
            (name, token)
        })
        .collect();
    let admin = add_user(&dir, &url, "boss", true);
    let fronts = [
        front(&data, &url, 10, &["--max-queue-per-user", "1000"]),
        front(&data, &url, 10, &["--max-queue-per-user", "1000"]),
    ];
    let _workers = [
        Worker::start(&data, &url, "w1", 1, 10),
        Worker::start(&data, &url, "w2", 1, 10),
    ];
    const CLIENTS: usize = 25;
    const JOBS: usize = 1000;
    let start = Instant::now();
    let submitted: Vec<(usize, Vec<String>)> = std::thread::scope(|scope| {
        let threads: Vec<_> = (0..CLIENTS)
            .map(|c| {
                let (fronts, users) = (&fronts, &users);
                scope.spawn(move || {
                    let token = users[c % users.len()].1.as_str();
                    let ids: Vec<String> = (0..JOBS / CLIENTS)
                        .map(|i| submit(&fronts[i % 2], Some(token), "pack", i as u64, TINY))
                        .collect();
                    for (i, id) in ids.iter().enumerate() {
                        let events = events(&fronts[(i + 1) % 2], Some(token), id);
                        assert_eq!(states(&events), ["queued", "running", "succeeded"], "{id}");
                    }
                    (c % users.len(), ids)
                })
            })
            .collect();
        threads
            .into_iter()
            .map(|t| t.join().expect("a client"))
            .collect()
    });
    let took = start.elapsed();
    let mut mine: BTreeMap<usize, BTreeSet<String>> = BTreeMap::new();
    for (user, ids) in submitted {
        mine.entry(user).or_default().extend(ids);
    }
    let every: BTreeSet<&String> = mine.values().flatten().collect();
    assert_eq!(every.len(), JOBS, "ids unique");
    let listed = list_all(&fronts[0], &admin);
    assert_eq!(listed.len(), JOBS);
    assert_eq!(
        listed.iter().collect::<BTreeSet<_>>(),
        every,
        "the admin lists every job once"
    );
    for (u, (name, token)) in users.iter().enumerate() {
        let listed = list_all(&fronts[1], token);
        assert_eq!(listed.len(), JOBS / users.len(), "{name}");
        assert_eq!(
            listed.into_iter().collect::<BTreeSet<_>>(),
            mine[&u],
            "{name} lists exactly their jobs"
        );
    }
    let once = pg.psql(
        "load",
        "SELECT count(*) FROM jobs WHERE state = 'succeeded' AND attempts = 1",
    );
    assert_eq!(once, JOBS.to_string(), "every job ran once");
    eprintln!(
        "{JOBS} jobs from {CLIENTS} clients over 2 fronts and 2 workers: {took:?} ({:.1} jobs/s)",
        JOBS as f64 / took.as_secs_f64()
    );
}

#[test]
fn users_see_only_their_jobs_and_a_revoked_token_is_refused_by_every_front() {
    let Some(pg) = Cluster::start() else { return };
    let url = pg.create_database("users");
    let dir = scratch("cluster-users");
    let data = dir.join("data");
    let token_file = dir.join("token");
    let root = "s3cret-admin-token-0123456789";
    fs::write(&token_file, root).expect("token file");
    let token_file = token_file.display().to_string();
    let a = add_user(&dir, &url, "alice", false);
    let b = add_user(&dir, &url, "bob", false);
    let fronts = [
        front(&data, &url, 10, &["--token-file", &token_file]),
        front(&data, &url, 10, &["--token-file", &token_file]),
    ];
    let _worker = Worker::start(&data, &url, "w1", 1, 10);
    let id = submit(&fronts[0], Some(&a), "pack", 1, TINY);
    let job = wait_end(&fronts[0], Some(&a), &id, Duration::from_secs(60));
    assert_eq!(job["state"], "succeeded", "{job}");

    // Bob: alice's job is as unknown as an id nobody has.
    let unknown = "0123456789abcdef0123456789abcdef";
    assert!(!list_all(&fronts[1], &b).contains(&id));
    assert_eq!(list_all(&fronts[1], root), std::slice::from_ref(&id));
    for front in &fronts {
        for (method, path) in [
            ("GET", "/api/v1/jobs/ID"),
            ("GET", "/api/v1/jobs/ID/events"),
            ("GET", "/api/v1/jobs/ID/files"),
            ("GET", "/api/v1/jobs/ID/files/packing.csv"),
            ("GET", "/api/v1/jobs/ID/packing"),
            ("POST", "/api/v1/jobs/ID/cancel"),
            ("DELETE", "/api/v1/jobs/ID"),
        ] {
            let theirs = call(method, &front.url(&path.replace("ID", &id)), Some(&b), None);
            let nobodys = call(
                method,
                &front.url(&path.replace("ID", unknown)),
                Some(&b),
                None,
            );
            assert_eq!(theirs.status, 404, "{method} {path}: {}", theirs.text());
            assert_eq!(
                theirs.text().replace(&id, "ID"),
                nobodys.text().replace(unknown, "ID"),
                "{method} {path}: the same answer as no job"
            );
            assert_eq!(theirs.status, nobodys.status);
        }
    }
    // Nothing of alice's changed.
    let still = call(
        "GET",
        &fronts[0].url(&format!("/api/v1/jobs/{id}")),
        Some(&a),
        None,
    );
    assert_eq!(still.status, 200);
    assert_eq!(still.json()["state"], "succeeded");
    assert_eq!(
        file(&fronts[1], Some(&a), &id, "packing.csv"),
        fs::read(data.join("jobs").join(&id).join("packing.csv")).expect("on disk")
    );

    // Revoked: refused by both fronts at the very next request.
    for front in &fronts {
        let me = call("GET", &front.url("/api/v1/me"), Some(&a), None);
        assert_eq!((me.status, &me.json()["name"]), (200, &"alice".into()));
    }
    let out = gapack(&dir, &["user", "revoke", "alice", "--store", &url]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for front in &fronts {
        let me = call("GET", &front.url("/api/v1/me"), Some(&a), None);
        assert_eq!(me.status, 401, "{}", me.text());
        let job = call(
            "GET",
            &front.url(&format!("/api/v1/jobs/{id}")),
            Some(&a),
            None,
        );
        assert_eq!(job.status, 401, "{}", job.text());
        let me = call("GET", &front.url("/api/v1/me"), Some(&b), None);
        assert_eq!(me.status, 200, "bob is not revoked");
    }

    // The store keeps SHA-256 hashes only: 32 bytes, none holding a token.
    let rows = pg.psql(
        "users",
        "SELECT encode(hash, 'hex'), length(hash) FROM tokens",
    );
    assert_eq!(rows.lines().count(), 2, "{rows}");
    for token in [&a, &b] {
        let hex: String = token.bytes().map(|b| format!("{b:02x}")).collect();
        let secret = token.trim_start_matches("gpk_");
        for row in rows.lines() {
            assert!(row.ends_with("|32"), "{row}");
            assert!(!row.contains(secret) && !row.contains(&hex), "{row}");
        }
        let found = pg.psql(
            "users",
            &format!(
                "SELECT u.name FROM tokens t JOIN users u ON u.id = t.user_id \
                 WHERE t.hash = sha256(convert_to('{token}', 'UTF8'))"
            ),
        );
        assert_eq!(found, if token == &a { "alice" } else { "bob" });
    }
    let anywhere = pg.psql(
        "users",
        &format!(
            "SELECT (SELECT count(*) FROM tokens t WHERE t::text LIKE '%{0}%') + \
             (SELECT count(*) FROM users u WHERE u::text LIKE '%{0}%')",
            a.trim_start_matches("gpk_")
        ),
    );
    assert_eq!(anywhere, "0", "a token in clear");
}
