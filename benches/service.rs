//! Load benchmark of `gapack serve` (not a test): `cargo bench --bench service`.
//!
//! Two loads, each on a fresh server (the real binary on a random loopback
//! port, two workers): 25 client threads submit 1,000 jobs (seeds 0..40 in
//! turn) and follow each over SSE to its end; first the default scene as
//! shipped (its pictures included), then the same scene writing
//! `packing.csv` and `summary.json` only. Every job is checked: it
//! succeeded, it is listed once, and its `packing.csv` is byte for byte the
//! one the jobs layer gives in process for the same seed. Prints jobs/s, p50
//! and p99 submit→succeeded latency under load, the service's overhead on one
//! job at a time (its latency less the same run in process, files written to
//! disk as the CLI writes them), and the server's peak RSS.
//!
//! `GAPACK_BENCH_JOBS`, `GAPACK_BENCH_CLIENTS` and `GAPACK_BENCH_WORKERS`
//! change the load.
//!
//! `GAPACK_BENCH_STORES=1` compares the job stores instead, on the CSV-only
//! scene: jobs/s and p50/p99 submit→succeeded with 1, 2 and 4 workers,
//! SQLite (one `gapack serve --workers N`) against PostgreSQL (one
//! `gapack serve --workers 0` and one `gapack worker --workers N`, on a
//! private cluster: it needs Debian's postgresql); then how long a job
//! whose worker is killed (`kill -9`, leases of 5 s) takes to run again on
//! the other worker, and to succeed.

#[path = "../tests/integration/common/server.rs"]
#[allow(dead_code)] // the tests use all of it, this bench only the start
mod server;

#[path = "../tests/integration/common/postgres.rs"]
#[allow(dead_code)] // the tests use all of it, this bench less
mod postgres;

use std::collections::BTreeSet;
use std::io::{BufRead, BufReader};

use std::sync::Mutex;
use std::time::{Duration, Instant};

use gapack::config::{DEFAULT_CONFIG, DEFAULT_ORIGIN};
use gapack::jobs::{self, Cancel, DirStore, JobKind, Plan, Request, Silent};
use postgres::{Cluster, Worker};
use server::Server;

const SEEDS: u64 = 40;

fn env_or(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn agent() -> ureq::Agent {
    ureq::Agent::config_builder()
        .http_status_as_error(false)
        .timeout_global(Some(Duration::from_secs(600)))
        .build()
        .into()
}

/// The packing.csv of the default scene with `seed`, run in process as the
/// CLI runs it (its files written to a folder under `scratch`), and how
/// long that took.
fn expected(config: &str, seed: u64, scratch: &std::path::Path) -> (Vec<u8>, Duration) {
    let request = Request {
        seed: Some(seed),
        ..Request::new(JobKind::Pack)
    };
    let plan = Plan::load(config, DEFAULT_ORIGIN, &request).expect("plan");
    let dir = scratch.join(format!("cli-{seed}"));
    let mut store = DirStore::new(dir.clone());
    let start = Instant::now();
    jobs::run(&plan, &mut Silent, &Cancel::new(), &mut store).expect("runs");
    let took = start.elapsed();
    let csv = std::fs::read(dir.join("packing.csv")).expect("packing.csv");
    (csv, took)
}

/// Submit the default scene with `seed`, follow it to its end; the id and
/// the latency from submit to `succeeded`.
fn run_one(base: &str, config: &str, seed: u64) -> (String, Duration) {
    let agent = agent();
    let start = Instant::now();
    let mut r = agent
        .post(format!("{base}/api/v1/jobs?kind=pack&seed={seed}"))
        .header("Content-Type", "application/toml")
        .send(config)
        .expect("submit");
    let body: serde_json::Value =
        serde_json::from_str(&r.body_mut().read_to_string().expect("body")).expect("json");
    assert_eq!(r.status().as_u16(), 201, "{body}");
    let id = body["id"].as_str().expect("id").to_owned();
    let events = agent
        .get(format!("{base}/api/v1/jobs/{id}/events"))
        .call()
        .expect("events");
    let mut last = String::new();
    for line in BufReader::new(events.into_body().into_reader()).lines() {
        let line = line.expect("line");
        if let Some(data) = line.strip_prefix("data:") {
            last = data.trim().to_owned();
        }
    }
    let latency = start.elapsed();
    let last: serde_json::Value = serde_json::from_str(&last).expect("last event");
    assert_eq!(last["state"], "succeeded", "{id}: {last}");
    (id, latency)
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// The server's peak resident memory (kB), from /proc.
fn peak_kb(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
}

fn main() {
    let total = env_or("GAPACK_BENCH_JOBS", 1000);
    let clients = env_or("GAPACK_BENCH_CLIENTS", 25);
    let workers = env_or("GAPACK_BENCH_WORKERS", 2);
    let csv_only = format!("{DEFAULT_CONFIG}\n[output]\nformats = [\"csv\"]\n");
    if std::env::var("GAPACK_BENCH_STORES").is_ok_and(|v| v == "1") {
        stores(&csv_only, total, clients);
        return;
    }
    load("the default scene", DEFAULT_CONFIG, total, clients, workers);
    load(
        "the default scene, packing.csv and summary.json only",
        &csv_only,
        total,
        clients,
        workers,
    );
}

/// One load: a fresh server, `total` jobs of `config` from `clients`
/// clients, every result verified, the figures printed.
fn load(label: &str, config: &str, total: usize, clients: usize, workers: usize) {
    let workers = workers.to_string();
    let data = std::env::temp_dir().join(format!("gapack-bench-service-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    let server = Server::start(&data, &["--max-queue", "100000", "--workers", &workers]);
    let base = server.base.clone();

    let scratch = data.with_extension("cli");
    let expected: Vec<(Vec<u8>, Duration)> =
        (0..SEEDS).map(|s| expected(config, s, &scratch)).collect();
    let _ = std::fs::remove_dir_all(&scratch);
    let mut alone: Vec<Duration> = expected.iter().map(|(_, d)| *d).collect();
    alone.sort();
    let packing = percentile(&alone, 0.5);

    // One job at a time: the service's own cost.
    let mut single: Vec<Duration> = (0..20)
        .map(|i| run_one(&base, config, i % SEEDS).1)
        .collect();
    single.sort();

    let results = Mutex::new(Vec::with_capacity(total));
    let start = Instant::now();
    std::thread::scope(|scope| {
        for c in 0..clients {
            let (base, results) = (&base, &results);
            scope.spawn(move || {
                let mut i = c;
                while i < total {
                    let seed = i as u64 % SEEDS;
                    let (id, latency) = run_one(base, config, seed);
                    results.lock().expect("results").push((id, seed, latency));
                    i += clients;
                }
            });
        }
    });
    let elapsed = start.elapsed();
    let results = results.into_inner().expect("results");

    // Verify every result: listed once, succeeded, the expected packing.
    let agent = agent();
    let ids: BTreeSet<&str> = results.iter().map(|(id, _, _)| id.as_str()).collect();
    assert_eq!(ids.len(), total, "duplicated ids");
    for (id, seed, _) in &results {
        let mut r = agent
            .get(format!("{base}/api/v1/jobs/{id}/files/packing.csv"))
            .call()
            .expect("file");
        assert_eq!(r.status().as_u16(), 200);
        let bytes = r
            .body_mut()
            .with_config()
            .limit(64 << 20)
            .read_to_vec()
            .expect("bytes");
        assert!(bytes == expected[*seed as usize].0, "{id}: packing differs");
    }
    let mut listed = BTreeSet::new();
    let mut url = format!("{base}/api/v1/jobs?limit=500&state=succeeded");
    for _ in 0..(total / 500 + 25) {
        let mut r = agent.get(&url).call().expect("list");
        let page: serde_json::Value =
            serde_json::from_str(&r.body_mut().read_to_string().expect("body")).expect("json");
        for job in page["jobs"].as_array().expect("jobs") {
            assert!(
                listed.insert(job["id"].as_str().expect("id").to_owned()),
                "listed twice"
            );
        }
        match page["next"].as_str() {
            Some(next) => url = format!("{base}{next}"),
            None => break,
        }
    }
    assert_eq!(listed.len(), total + single.len(), "jobs lost");

    let mut latencies: Vec<Duration> = results.iter().map(|(_, _, l)| *l).collect();
    latencies.sort();
    let peak = peak_kb(server.pid());
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!("service load: {total} jobs of {label} from {clients} clients, {workers} workers");
    println!("  none lost or duplicated; every packing.csv verified against the jobs layer");
    println!(
        "  throughput: {:.1} jobs/s ({:.2} s)",
        total as f64 / elapsed.as_secs_f64(),
        elapsed.as_secs_f64()
    );
    println!(
        "  submit→succeeded under load: p50 {:.1} ms, p99 {:.1} ms",
        ms(percentile(&latencies, 0.5)),
        ms(percentile(&latencies, 0.99))
    );
    println!(
        "  one job at a time: p50 {:.1} ms against {:.1} ms for the same run in process (files written as the CLI writes them): the service adds {:.1} ms",
        ms(percentile(&single, 0.5)),
        ms(packing),
        ms(percentile(&single, 0.5)) - ms(packing)
    );
    match peak {
        Some(kb) => println!("  server peak RSS: {:.1} MB", kb as f64 / 1024.0),
        None => println!("  server peak RSS: unknown (no /proc)"),
    }
    server.terminate();
    let _ = std::fs::remove_dir_all(&data);
}

/// Where a store comparison runs its jobs.
enum Engine<'a> {
    /// One `gapack serve --workers N` on its own SQLite file.
    Sqlite,
    /// One `gapack serve --workers 0` and one `gapack worker --workers N`
    /// on a fresh database of this cluster.
    Postgres(&'a Cluster),
}

/// Throughput and latencies of one load.
struct Figures {
    jobs_per_second: f64,
    p50: Duration,
    p99: Duration,
}

/// The store comparison (`GAPACK_BENCH_STORES=1`): `total` jobs of
/// `config` from `clients` clients on each engine with 1, 2 and 4 workers,
/// then the lease expiry delay.
fn stores(config: &str, total: usize, clients: usize) {
    let Some(cluster) = Cluster::start() else {
        return;
    };
    println!(
        "job stores: {total} jobs of the default scene (packing.csv and summary.json only) from {clients} clients each"
    );
    println!("| store | workers | jobs/s | p50 ms | p99 ms |");
    println!("|---|---|---|---|---|");
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    for workers in [1, 2, 4] {
        for (name, engine) in [
            ("SQLite", Engine::Sqlite),
            ("PostgreSQL", Engine::Postgres(&cluster)),
        ] {
            let f = store_load(&engine, config, total, clients, workers);
            println!(
                "| {name} | {workers} | {:.1} | {:.1} | {:.1} |",
                f.jobs_per_second,
                ms(f.p50),
                ms(f.p99)
            );
        }
    }
    lease_expiry(&cluster);
}

/// One load on `engine` with `workers` workers: every job followed to its
/// success and counted once.
fn store_load(
    engine: &Engine<'_>,
    config: &str,
    total: usize,
    clients: usize,
    workers: usize,
) -> Figures {
    let label = match engine {
        Engine::Sqlite => format!("sqlite-{workers}"),
        Engine::Postgres(_) => format!("postgres-{workers}"),
    };
    let data = std::env::temp_dir().join(format!(
        "gapack-bench-stores-{}-{label}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&data);
    std::fs::create_dir_all(&data).expect("data");
    let n = workers.to_string();
    let (server, worker) = match engine {
        Engine::Sqlite => (
            Server::start(&data, &["--max-queue", "100000", "--workers", &n]),
            None,
        ),
        Engine::Postgres(cluster) => {
            let url = cluster.create_database(&label.replace('-', "_"));
            let server = Server::start(
                &data,
                &["--store", &url, "--max-queue", "100000", "--workers", "0"],
            );
            (server, Some(Worker::start(&data, &url, "w", workers, 30)))
        }
    };
    let base = server.base.clone();
    let latencies = Mutex::new(Vec::with_capacity(total));
    let ids = Mutex::new(BTreeSet::new());
    let start = Instant::now();
    std::thread::scope(|scope| {
        for c in 0..clients {
            let (base, latencies, ids) = (&base, &latencies, &ids);
            scope.spawn(move || {
                let mut i = c;
                while i < total {
                    let (id, latency) = run_one(base, config, i as u64 % SEEDS);
                    latencies.lock().expect("latencies").push(latency);
                    assert!(ids.lock().expect("ids").insert(id), "an id twice");
                    i += clients;
                }
            });
        }
    });
    let elapsed = start.elapsed();
    let mut latencies = latencies.into_inner().expect("latencies");
    assert_eq!(latencies.len(), total, "jobs lost");
    latencies.sort();
    drop(worker);
    server.terminate();
    let _ = std::fs::remove_dir_all(&data);
    Figures {
        jobs_per_second: total as f64 / elapsed.as_secs_f64(),
        p50: percentile(&latencies, 0.5),
        p99: percentile(&latencies, 0.99),
    }
}

/// A search on one of two workers (leases of 5 s), that worker killed
/// (`kill -9`) past its first checkpoint: the time from the kill to the
/// search running again on the other worker, and to its success.
fn lease_expiry(cluster: &Cluster) {
    const LEASE: u64 = 5;
    let search = "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 60\nheight = 60\n[grading]\nuniform = [1.0, 2.0]\n\
         [optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 30\nstagnation = 100\n";
    let url = cluster.create_database("bench_lease");
    let data = std::env::temp_dir().join(format!("gapack-bench-lease-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    std::fs::create_dir_all(&data).expect("data");
    let lease = LEASE.to_string();
    let server = Server::start(
        &data,
        &[
            "--store",
            &url,
            "--workers",
            "0",
            "--lease-seconds",
            &lease,
            "--checkpoint-every",
            "2",
        ],
    );
    let mut workers = [
        Worker::start(&data, &url, "w1", 1, LEASE),
        Worker::start(&data, &url, "w2", 1, LEASE),
    ];
    let base = server.base.clone();
    let agent = agent();
    let mut r = agent
        .post(format!("{base}/api/v1/jobs?kind=optimise&seed=9"))
        .header("Content-Type", "application/toml")
        .send(search)
        .expect("submit");
    let body: serde_json::Value =
        serde_json::from_str(&r.body_mut().read_to_string().expect("body")).expect("json");
    let id = body["id"].as_str().expect("id").to_owned();
    // The stream, read on its own thread: each event with when it came.
    let (tx, rx) = std::sync::mpsc::channel();
    let follower = {
        let (base, id) = (base.clone(), id.clone());
        std::thread::spawn(move || {
            let events = agent
                .get(format!("{base}/api/v1/jobs/{id}/events"))
                .call()
                .expect("events");
            for line in BufReader::new(events.into_body().into_reader()).lines() {
                let line = line.expect("line");
                if let Some(data) = line.strip_prefix("data:") {
                    let v: serde_json::Value = serde_json::from_str(data.trim()).expect("json");
                    if tx.send((Instant::now(), v)).is_err() {
                        return;
                    }
                }
            }
        })
    };
    let next = || rx.recv_timeout(Duration::from_secs(120)).expect("an event");
    loop {
        let (_, e) = next();
        if e["event"] == "generation" && e["index"].as_u64() >= Some(4) {
            break;
        }
        assert!(
            e["event"] != "state" || e["state"] == "queued" || e["state"] == "running",
            "{e}"
        );
    }
    let holder = cluster.psql(
        "bench_lease",
        &format!("SELECT worker FROM jobs WHERE id = '{id}'"),
    );
    let victim = workers
        .iter_mut()
        .find(|w| holder.starts_with(&format!("{}:", w.name)))
        .expect("the worker holding the search");
    victim.kill();
    let killed = Instant::now();
    let rerun = loop {
        let (at, e) = next();
        if e["event"] == "state" && e["state"] == "running" {
            assert_eq!(e["attempt"], 2, "{e}");
            break at - killed;
        }
    };
    let done = loop {
        let (at, e) = next();
        if e["event"] == "state" && e["state"] != "running" {
            assert_eq!(e["state"], "succeeded", "{e}");
            break at - killed;
        }
    };
    follower.join().expect("the stream's reader");
    println!(
        "lease expiry (leases of {LEASE} s, kill -9 past the first checkpoint): running again on the other worker {:.2} s after the kill, succeeded {:.2} s after it",
        rerun.as_secs_f64(),
        done.as_secs_f64()
    );
    drop(workers);
    server.terminate();
    let _ = std::fs::remove_dir_all(&data);
}
