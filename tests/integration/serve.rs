//! `gapack serve` end to end: the real binary on a random loopback port,
//! driven by an HTTP client. Every job kind is submitted, followed over SSE
//! to its end and its files compared with the CLI's for the same config and
//! seed; cancel, delete, paging, every malformed request, the token; and
//! the faults: `kill -9` mid-optimise then a restart, a job whose output
//! write fails, SIGTERM with jobs queued and running.

use crate::common;

use std::fs;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use common::server::{Server, agent};
use common::{cli_run, gapack, scratch, untimed};
use serde_json::Value;

const SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n";

fn optimise_config() -> String {
    format!(
        "{SQUARE}[optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 4\nstagnation = 100\n"
    )
}

fn layer_config() -> String {
    format!(
        "{SQUARE}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\naxis = \"y\"\nbins = 10\nprofile = \"steps\"\nlayers = [[\"a\", 0.5], [\"b\", 0.5]]\npopulation = 8\ngenerations = 4\ntolerance = 0.0\n"
    )
}

/// A long search (a bigger square, every generation run): long enough to be
/// stopped part-way.
fn long_optimise_config() -> String {
    "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 60\nheight = 60\n[grading]\nuniform = [1.0, 2.0]\n\
     [optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 30\nstagnation = 100\n"
        .to_owned()
}

/// A response: status, content type, body.
struct Reply {
    status: u16,
    content_type: String,
    headers: ureq::http::HeaderMap,
    body: Vec<u8>,
}

impl Reply {
    fn json(&self) -> Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&self.body)))
    }

    fn error(&self) -> String {
        self.json()["error"]
            .as_str()
            .unwrap_or_else(|| panic!("no error in {}", String::from_utf8_lossy(&self.body)))
            .to_owned()
    }
}

fn reply(r: Result<ureq::http::Response<ureq::Body>, ureq::Error>) -> Reply {
    let mut r = r.expect("request");
    let content_type = r
        .headers()
        .get("content-type")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_owned();
    Reply {
        status: r.status().as_u16(),
        content_type,
        headers: r.headers().clone(),
        body: r
            .body_mut()
            .with_config()
            .limit(64 << 20)
            .read_to_vec()
            .expect("body"),
    }
}

fn get(server: &Server, path: &str) -> Reply {
    reply(agent().get(server.url(path)).call())
}

fn post_toml(server: &Server, path: &str, body: &str) -> Reply {
    reply(
        agent()
            .post(server.url(path))
            .header("Content-Type", "application/toml")
            .send(body),
    )
}

/// Submit and return the job's id.
fn submit(server: &Server, kind: &str, seed: u64, config: &str) -> String {
    let r = post_toml(
        server,
        &format!("/api/v1/jobs?kind={kind}&seed={seed}"),
        config,
    );
    assert_eq!(r.status, 201, "{}", String::from_utf8_lossy(&r.body));
    let json = r.json();
    assert_eq!(json["state"], "queued");
    json["id"].as_str().expect("id").to_owned()
}

/// Follow a job's events to the end: `(id, event, data)` of each.
fn follow(server: &Server, id: &str, last: Option<i64>) -> Vec<(i64, String, Value)> {
    let mut request = agent().get(server.url(&format!("/api/v1/jobs/{id}/events")));
    if let Some(last) = last {
        request = request.header("Last-Event-ID", last.to_string());
    }
    let response = request.call().expect("events");
    assert_eq!(response.status().as_u16(), 200);
    let reader = BufReader::new(response.into_body().into_reader());
    let mut events = Vec::new();
    let (mut seq, mut name, mut data) = (0, String::new(), String::new());
    for line in reader.lines() {
        let line = line.expect("line");
        if let Some(v) = line.strip_prefix("id:") {
            seq = v.trim().parse().expect("id");
        } else if let Some(v) = line.strip_prefix("event:") {
            name = v.trim().to_owned();
        } else if let Some(v) = line.strip_prefix("data:") {
            data = v.trim().to_owned();
        } else if line.is_empty() && !data.is_empty() {
            events.push((
                seq,
                name.clone(),
                serde_json::from_str(&data).expect("json"),
            ));
            data.clear();
        }
    }
    events
}

/// Wait (at most 120 s) until the job is in one of `states`.
fn wait_for(server: &Server, id: &str, states: &[&str]) -> Value {
    let start = Instant::now();
    loop {
        let job = get(server, &format!("/api/v1/jobs/{id}")).json();
        if states.iter().any(|s| job["state"] == *s) {
            return job;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "job {id} still {}",
            job["state"]
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The job's files by name, fetched through the API.
fn download(server: &Server, id: &str) -> Vec<(String, Vec<u8>)> {
    let list = get(server, &format!("/api/v1/jobs/{id}/files"));
    assert_eq!(list.status, 200, "{}", String::from_utf8_lossy(&list.body));
    let list = list.json();
    let mut files = Vec::new();
    for f in list["files"].as_array().expect("files") {
        let name = f["name"].as_str().expect("name").to_owned();
        let r = get(server, f["url"].as_str().expect("url"));
        assert_eq!(r.status, 200, "{name}");
        let expected = match name.rsplit('.').next() {
            Some("csv") => "text/csv",
            Some("json") => "application/json",
            Some("svg") => "image/svg+xml",
            Some("png") => "image/png",
            _ => "",
        };
        assert!(
            r.content_type.starts_with(expected),
            "{name}: {}",
            r.content_type
        );
        files.push((name, r.body));
    }
    files
}

fn manifest_files(manifest: &[u8]) -> Vec<String> {
    let v: Value = serde_json::from_slice(manifest).expect("manifest");
    v["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| f.as_str().expect("name").to_owned())
        .collect()
}

#[test]
fn every_job_kind_runs_as_the_cli_runs_it() {
    let dir = scratch("serve-kinds");
    let server = Server::start(&dir.join("data"), &[]);
    let stability = "seed = 1\n[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 1.0\n[packer]\nattempts = 200\n[compare]\nmethods = [\"rsa\"]\n"
        .to_owned();
    let cases = [
        ("pack", SQUARE.to_owned(), "packing.csv"),
        ("optimise", optimise_config(), "packing.csv"),
        ("layer", layer_config(), "packing.csv"),
        (
            "compare",
            format!("{SQUARE}[compare]\nmethods = [\"rsa\"]\nrepeats = 1\n"),
            "compare.csv",
        ),
        ("stability", stability, "stability.csv"),
        (
            "sweep",
            format!(
                "{SQUARE}[sweep]\n\"domain.width\" = [12.0, 16.0]\nseeds = 2\nkeep = \"summary\"\n"
            ),
            "sweep.csv",
        ),
    ];
    for (kind, config, table) in cases {
        let id = submit(&server, kind, 11, &config);
        let events = follow(&server, &id, None);
        let names: Vec<&str> = events.iter().map(|(_, n, _)| n.as_str()).collect();
        assert_eq!(names.first(), Some(&"state"), "{kind}: {names:?}");
        assert!(names.contains(&"started"), "{kind}: {names:?}");
        assert!(names.contains(&"written"), "{kind}: {names:?}");
        let (_, _, last) = events.last().expect("events");
        assert_eq!(last["state"], "succeeded", "{kind}: {events:?}");
        for pair in events.windows(2) {
            assert_eq!(pair[1].0, pair[0].0 + 1, "{kind}: numbered in order");
        }
        if kind == "optimise" {
            let generation = events
                .iter()
                .find(|(_, n, _)| n == "generation")
                .expect("generation events");
            assert!(generation.2["best"].is_number() && generation.2["mean"].is_number());
        }
        // Resumed after the third event: the rest, the same.
        let tail = follow(&server, &id, Some(events[2].0));
        assert_eq!(tail.len(), events.len() - 3, "{kind}");
        assert_eq!(tail[0].2, events[3].2);

        let job = get(&server, &format!("/api/v1/jobs/{id}")).json();
        assert_eq!(job["state"], "succeeded");
        assert_eq!(job["kind"], kind);
        assert!(job["summary"]["lines"].is_array(), "{job}");
        assert!(job["finished_ms"].as_i64() >= job["started_ms"].as_i64());

        let served = download(&server, &id);
        let cli = cli_run(&dir, kind, &config, 11);
        let cli_manifest = fs::read(cli.join("manifest.json")).expect("cli manifest");
        let served_manifest = &served
            .iter()
            .find(|(n, _)| n == "manifest.json")
            .expect("manifest served")
            .1;
        assert_eq!(
            manifest_files(served_manifest),
            manifest_files(&cli_manifest),
            "{kind}"
        );
        let mine = &served.iter().find(|(n, _)| n == table).expect(table).1;
        let theirs = fs::read(cli.join(table)).expect("cli table");
        if table == "packing.csv" {
            assert!(mine == &theirs, "{kind}: {table} differs from the CLI's");
        } else if kind == "compare" || kind == "sweep" {
            assert_eq!(untimed(mine), untimed(&theirs), "{kind}");
        } else {
            assert_eq!(untimed(mine).len(), untimed(&theirs).len(), "{kind}");
        }
    }
}

#[test]
fn cancel_delete_and_paging() {
    let dir = scratch("serve-cancel");
    let server = Server::start(&dir.join("data"), &["--workers", "1"]);
    let long = submit(&server, "optimise", 1, &long_optimise_config());
    let queued = submit(&server, "pack", 1, SQUARE);
    wait_for(&server, &long, &["running"]);
    // A queued job is cancelled at once, and again without change.
    for _ in 0..2 {
        let r = reply(
            agent()
                .post(server.url(&format!("/api/v1/jobs/{queued}/cancel")))
                .send_empty(),
        );
        assert_eq!(r.status, 200);
        assert_eq!(r.json()["state"], "cancelled");
    }
    // A running search keeps its best packing.
    let events = follow_until_generation(&server, &long, 1);
    assert!(!events.is_empty());
    let r = reply(
        agent()
            .post(server.url(&format!("/api/v1/jobs/{long}/cancel")))
            .send_empty(),
    );
    assert_eq!(r.status, 202, "{}", String::from_utf8_lossy(&r.body));
    let job = wait_for(&server, &long, &["cancelled"]);
    assert_eq!(job["summary"]["interrupted"], true, "{job}");
    let files = download(&server, &long);
    assert!(files.iter().any(|(n, _)| n == "packing.csv"));
    assert!(files.iter().any(|(n, _)| n == "checkpoint.json"));
    let again = reply(
        agent()
            .post(server.url(&format!("/api/v1/jobs/{long}/cancel")))
            .send_empty(),
    );
    assert_eq!(again.status, 200);
    assert_eq!(again.json()["state"], "cancelled");

    // Paging: newest first, by state.
    let mut ids = vec![long.clone(), queued.clone()];
    for seed in 0..3 {
        ids.push(submit(&server, "pack", seed, SQUARE));
    }
    for id in &ids[2..] {
        wait_for(&server, id, &["succeeded"]);
    }
    let mut seen = Vec::new();
    let mut url = "/api/v1/jobs?limit=2".to_owned();
    for _ in 0..10 {
        let page = get(&server, &url).json();
        let jobs = page["jobs"].as_array().expect("jobs");
        assert!(jobs.len() <= 2);
        seen.extend(
            jobs.iter()
                .map(|j| j["id"].as_str().expect("id").to_owned()),
        );
        match page["next"].as_str() {
            Some(next) => url = next.to_owned(),
            None => break,
        }
    }
    let mut newest_first = ids.clone();
    newest_first.reverse();
    assert_eq!(seen, newest_first);
    let cancelled = get(&server, "/api/v1/jobs?state=cancelled").json();
    let cancelled: Vec<&str> = cancelled["jobs"]
        .as_array()
        .expect("jobs")
        .iter()
        .map(|j| j["id"].as_str().expect("id"))
        .collect();
    assert_eq!(cancelled, vec![queued.as_str(), long.as_str()]);

    // Delete: the job and its files go.
    let job_dir = dir.join("data").join("jobs").join(&long);
    assert!(job_dir.exists());
    let r = reply(
        agent()
            .delete(server.url(&format!("/api/v1/jobs/{long}")))
            .call(),
    );
    assert_eq!(r.status, 204);
    assert!(!job_dir.exists());
    assert_eq!(get(&server, &format!("/api/v1/jobs/{long}")).status, 404);
    let r = reply(
        agent()
            .delete(server.url(&format!("/api/v1/jobs/{long}")))
            .call(),
    );
    assert_eq!(r.status, 404);
    server.terminate();
}

/// Follow a job's events until generation `index` of its search (or its end).
fn follow_until_generation(server: &Server, id: &str, index: u64) -> Vec<Value> {
    let response = agent()
        .get(server.url(&format!("/api/v1/jobs/{id}/events")))
        .call()
        .expect("events");
    let reader = BufReader::new(response.into_body().into_reader());
    let mut seen = Vec::new();
    for line in reader.lines() {
        let line = line.expect("line");
        if let Some(data) = line.strip_prefix("data:") {
            let v: Value = serde_json::from_str(data.trim()).expect("json");
            let done = (v["event"] == "generation" && v["index"].as_u64() >= Some(index))
                || (v["event"] == "state"
                    && !matches!(v["state"].as_str(), Some("queued" | "running")));
            seen.push(v);
            if done {
                break;
            }
        }
    }
    seen
}

#[test]
fn malformed_requests_are_refused_with_json_errors() {
    let dir = scratch("serve-malformed");
    let server = Server::start(&dir.join("data"), &["--workers", "0"]);
    // Bad TOML: located as the CLI locates it.
    let bad = SQUARE.replace("width = 20", "width = 20 mm");
    let r = post_toml(&server, "/api/v1/jobs?kind=pack", &bad);
    assert_eq!(r.status, 422);
    let v = r.json();
    fs::write(dir.join("config.toml"), &bad).expect("write");
    let cli = gapack(&dir, &["pack", "config.toml"]);
    let cli_error = String::from_utf8_lossy(&cli.stderr);
    assert_eq!(
        cli_error.trim(),
        format!("error: {}", v["error"].as_str().expect("error"))
    );
    assert_eq!(v["line"], 4);
    assert_eq!(v["column"], 9);
    assert_eq!(v["key"], "domain.width");
    assert!(
        v["message"]
            .as_str()
            .expect("message")
            .contains("TOML syntax error")
    );
    // A bad value.
    let r = post_toml(
        &server,
        "/api/v1/jobs",
        &SQUARE.replace("width = 20", "width = -1"),
    );
    assert_eq!(r.status, 422);
    assert_eq!(r.json()["key"], "domain.width");
    // Unknown kind.
    let r = post_toml(&server, "/api/v1/jobs?kind=bake", SQUARE);
    assert_eq!(r.status, 400);
    assert!(
        r.error().contains("unknown job kind \"bake\""),
        "{}",
        r.error()
    );
    // A job the config has no table for.
    let r = post_toml(&server, "/api/v1/jobs?kind=optimise", SQUARE);
    assert_eq!(r.status, 422);
    assert!(r.error().contains("missing table [optimise]"));
    // Wrong content type.
    let r = reply(
        agent()
            .post(server.url("/api/v1/jobs"))
            .header("Content-Type", "text/html")
            .send(SQUARE),
    );
    assert_eq!(r.status, 415);
    assert!(r.error().contains("application/toml"));
    // Bad JSON, and good JSON.
    let r = reply(
        agent()
            .post(server.url("/api/v1/jobs"))
            .header("Content-Type", "application/json")
            .send("{\"kind\": \"pack\""),
    );
    assert_eq!(r.status, 400);
    let body = serde_json::json!({"kind": "pack", "config": SQUARE, "seed": 4}).to_string();
    let r = reply(
        agent()
            .post(server.url("/api/v1/jobs"))
            .header("Content-Type", "application/json")
            .send(&body),
    );
    assert_eq!(r.status, 201);
    // Oversized body: refused on its declared length, before a byte of it
    // is read (the body is never sent; the reply still comes).
    let (status, body) = server.raw(
        format!(
            "POST /api/v1/jobs?kind=pack HTTP/1.1\r\nHost: {}\r\n\
             Content-Type: application/toml\r\nContent-Length: {}\r\n\
             Connection: close\r\n\r\n",
            server.addr(),
            (1 << 20) + 1
        )
        .as_bytes(),
    );
    assert_eq!(status, 413, "{body}");
    assert!(body.contains("1 MiB"), "{body}");
    // [output] dir.
    let r = post_toml(
        &server,
        "/api/v1/jobs?kind=pack",
        &format!("{SQUARE}[output]\ndir = \"/tmp/elsewhere\"\n"),
    );
    assert_eq!(r.status, 422);
    assert_eq!(r.json()["key"], "output.dir");
    assert_eq!(
        (r.json()["line"].as_u64(), r.json()["column"].as_u64()),
        (Some(9), Some(1))
    );
    assert!(
        r.error()
            .starts_with("config.toml:9:1: output.dir: the server chooses"),
        "{}",
        r.error()
    );
    // Over the server's ceiling, though the config raises its own limit.
    let big = "[domain]\nshape = \"rectangle\"\nwidth = 10000\nheight = 10000\n[grading]\nconstant = 1.0\n[limits]\nmax_particles = 1000000000\nmax_memory_mb = 100000\n";
    let r = post_toml(&server, "/api/v1/jobs?kind=pack", big);
    assert_eq!(r.status, 422);
    assert_eq!(r.json()["key"], "limits.max_particles", "{}", r.error());
    let r = post_toml(&server, "/api/v1/jobs?kind=pack&force=true", SQUARE);
    assert_eq!(r.status, 403);
    // Unknown ids, unknown routes, wrong methods.
    for path in [
        "/api/v1/jobs/0123456789abcdef0123456789abcdef",
        "/api/v1/jobs/../../etc/passwd",
        "/api/v1/jobs/nope/files",
        "/api/v1/nothing",
    ] {
        let r = get(&server, path);
        assert_eq!(r.status, 404, "{path}");
        assert!(!r.error().is_empty());
    }
    let r = reply(agent().put(server.url("/api/v1/jobs")).send(""));
    assert_eq!(r.status, 405);
    assert!(!r.error().is_empty());
    let r = get(&server, "/api/v1/jobs?state=sleeping");
    assert_eq!(r.status, 400);
    // Validate: the plan without a run.
    let r = post_toml(
        &server,
        "/api/v1/validate?kind=optimise",
        &optimise_config(),
    );
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    let v = r.json();
    assert_eq!(v["kind"], "optimise");
    assert!(v["estimates"]["disks"].as_f64() > Some(10.0));
    assert!(!v["plan"].as_array().expect("plan").is_empty());
    // Files of a job that has not run.
    let id = submit(&server, "pack", 1, SQUARE);
    let r = get(&server, &format!("/api/v1/jobs/{id}/files"));
    assert_eq!(r.status, 409);
    let r = get(&server, &format!("/api/v1/jobs/{id}/files/packing.csv"));
    assert_eq!(r.status, 409);
    let r = reply(
        agent()
            .delete(server.url(&format!("/api/v1/jobs/{id}")))
            .call(),
    );
    assert_eq!(r.status, 409);
    // The queue's limit.
    drop(server);
    let server = Server::start(&dir.join("data2"), &["--workers", "0", "--max-queue", "2"]);
    submit(&server, "pack", 1, SQUARE);
    submit(&server, "pack", 2, SQUARE);
    let r = post_toml(&server, "/api/v1/jobs?kind=pack", SQUARE);
    assert_eq!(r.status, 503);
    assert_eq!(
        r.headers.get("retry-after").and_then(|v| v.to_str().ok()),
        Some("5")
    );
    assert!(r.error().contains("queue is full"));
    // Health, metrics and the API's document.
    assert_eq!(get(&server, "/healthz").json()["status"], "ok");
    let metrics = String::from_utf8(get(&server, "/metrics").body).expect("text");
    assert!(
        metrics.contains("gapack_jobs{state=\"queued\"} 2"),
        "{metrics}"
    );
    assert!(metrics.contains("gapack_queue_length 2"));
    let doc = get(&server, "/api/v1/openapi.json").json();
    for path in [
        "/api/v1/jobs",
        "/api/v1/jobs/{id}/events",
        "/api/v1/jobs/{id}/files/{name}",
    ] {
        assert!(doc["paths"][path].is_object(), "{path} documented");
    }
}

#[test]
fn files_outside_the_manifest_are_never_served() {
    let dir = scratch("serve-files");
    let server = Server::start(&dir.join("data"), &[]);
    let id = submit(&server, "pack", 1, SQUARE);
    wait_for(&server, &id, &["succeeded"]);
    fs::write(dir.join("data/jobs").join(&id).join("secret.txt"), "no").expect("write");
    fs::write(dir.join("data/secret.txt"), "no").expect("write");
    for name in [
        "secret.txt",
        "../secret.txt",
        "..%2Fsecret.txt",
        "%2E%2E/%2E%2E/gapack.db",
        "/etc/passwd",
        "..",
    ] {
        let r = get(&server, &format!("/api/v1/jobs/{id}/files/{name}"));
        assert!(
            r.status == 404 || r.status == 400,
            "{name}: {} {}",
            r.status,
            String::from_utf8_lossy(&r.body)
        );
        assert!(!r.body.starts_with(b"no"), "{name}");
    }
    assert_eq!(
        get(&server, &format!("/api/v1/jobs/{id}/files/packing.csv")).status,
        200
    );
}

#[test]
fn a_token_guards_every_endpoint_but_health() {
    let dir = scratch("serve-token");
    fs::create_dir_all(&dir).expect("dir");
    let token = "s3cret-token-0123456789";
    fs::write(dir.join("token"), format!("{token}\n")).expect("token");
    let token_file = dir.join("token");
    let server = Server::start(
        &dir.join("data"),
        &["--token-file", token_file.to_str().expect("utf-8")],
    );
    let r = get(&server, "/api/v1/jobs");
    assert_eq!(r.status, 401);
    assert!(r.error().contains("Bearer"));
    let r = reply(
        agent()
            .get(server.url("/api/v1/jobs"))
            .header("Authorization", "Bearer wrong-token-0123456789")
            .call(),
    );
    assert_eq!(r.status, 401);
    assert_eq!(r.error(), "wrong bearer token");
    let r = reply(
        agent()
            .get(server.url("/api/v1/jobs"))
            .header("Authorization", format!("Bearer {token}"))
            .call(),
    );
    assert_eq!(r.status, 200);
    assert_eq!(get(&server, "/healthz").status, 200);
    assert_eq!(get(&server, "/metrics").status, 401);
    assert_eq!(get(&server, "/api/v1/examples").status, 401);
    // The page holds no data: served to anyone, it asks for the token.
    let page = get(&server, "/");
    assert_eq!(page.status, 200);
    assert!(page.content_type.starts_with("text/html"));
    drop(server);
    // Any address but loopback needs a token.
    let out = Command::new(env!("CARGO_BIN_EXE_gapack"))
        .args(["serve", "--listen", "0.0.0.0:0", "--data"])
        .arg(dir.join("data"))
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("needs --token-file"));
}

#[test]
fn the_page_and_the_data_it_draws() {
    let dir = scratch("serve-page");
    let server = Server::start(&dir.join("data"), &[]);
    for (path, kind) in [
        ("/", "text/html"),
        ("/app.js", "text/javascript"),
        ("/app.css", "text/css"),
    ] {
        let r = get(&server, path);
        assert_eq!(r.status, 200, "{path}");
        assert!(
            r.content_type.starts_with(kind),
            "{path}: {}",
            r.content_type
        );
    }
    // Every shipped example, the default scene first, as on disk.
    let examples = get(&server, "/api/v1/examples").json();
    let examples = examples.as_array().expect("a list");
    assert_eq!(examples[0]["name"], "default");
    assert_eq!(
        examples.len(),
        fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../configs"))
            .expect("configs")
            .count()
    );
    for e in examples {
        let name = e["name"].as_str().expect("name");
        let text = fs::read_to_string(format!(
            "{}/../configs/{name}.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .expect("config");
        assert_eq!(e["config"].as_str(), Some(text.as_str()), "{name}");
    }
    // Estimates: a search's packings are bounded by its population and generations.
    let v = post_toml(
        &server,
        "/api/v1/validate?kind=optimise",
        &optimise_config(),
    )
    .json();
    assert_eq!(v["estimates"]["packings"], 8 + 4 * 3 * 8);
    assert!(v["estimates"]["seconds"].as_f64().is_some_and(|s| s > 0.0));
    let v = post_toml(&server, "/api/v1/validate?kind=pack", SQUARE).json();
    assert_eq!(v["estimates"]["packings"], 1);
    // A finished job: its config, its words without the server's path, its packing as columns.
    let id = submit(&server, "layer", 2, &layer_config());
    let job = wait_for(&server, &id, &["succeeded"]);
    assert_eq!(job["config"].as_str(), Some(layer_config().as_str()));
    let data_dir = dir.join("data").display().to_string();
    for line in job["summary"]["lines"].as_array().expect("lines") {
        let line = line.as_str().expect("line");
        assert!(!line.contains(&data_dir), "{line}");
        assert!(line.starts_with(&format!("jobs/{id}")), "{line}");
    }
    let drawn = get(&server, &format!("/api/v1/jobs/{id}/packing")).json();
    let csv = String::from_utf8(get(&server, &format!("/api/v1/jobs/{id}/files/packing.csv")).body)
        .expect("UTF-8");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(drawn["x"].as_array().map(Vec::len), Some(rows.len()));
    assert_eq!(drawn["materials"], serde_json::json!(["a", "b"]));
    for (i, row) in rows.iter().enumerate() {
        for (k, column) in ["x", "y", "r"].iter().enumerate() {
            // Within an ulp or two: serde_json's own float parsing is not exact.
            let v: f64 = row[k + 1].parse().expect("number");
            let got = drawn[column][i].as_f64().expect("number");
            assert!(
                (got - v).abs() <= 4.0 * f64::EPSILON * v.abs(),
                "disk {i} {column}: {got} against {v}"
            );
        }
        let material = drawn["material"][i].as_u64().expect("material") as usize;
        assert_eq!(drawn["materials"][material].as_str(), Some(row[4]));
    }
    assert_eq!(
        drawn["bounds"],
        serde_json::json!([[0.0, 0.0], [20.0, 20.0]])
    );
    assert!(drawn["outline"].as_array().is_some_and(|o| o.len() >= 4));
    // Not finished, or no packing: refused.
    let queued = get(&server, "/api/v1/jobs?limit=1").json();
    assert!(queued["jobs"].is_array());
    let compare = submit(
        &server,
        "compare",
        1,
        &format!("{SQUARE}[compare]\nmethods = [\"rsa\"]\nrepeats = 1\n"),
    );
    wait_for(&server, &compare, &["succeeded"]);
    assert_eq!(
        get(&server, &format!("/api/v1/jobs/{compare}/packing")).status,
        409
    );
}

/// A 15 mm square of particles of `shape` (a `[shape]` table and what follows it).
fn shapes_config(shape: &str) -> String {
    format!(
        "seed = 1\n[domain]\nshape = \"rectangle\"\nwidth = 15\nheight = 15\n\
         [grading]\nuniform = [1.0, 2.0]\n{shape}"
    )
}

/// `packing.csv`'s rows as maps of column to cell.
fn csv_rows(csv: &[u8]) -> Vec<std::collections::HashMap<String, String>> {
    let mut reader = csv::Reader::from_reader(csv);
    let header: Vec<String> = reader
        .headers()
        .expect("a header")
        .iter()
        .map(str::to_owned)
        .collect();
    reader
        .records()
        .map(|r| {
            header
                .iter()
                .cloned()
                .zip(r.expect("a record").iter().map(str::to_owned))
                .collect()
        })
        .collect()
}

/// `got` is the CSV's number `cell`, within the few ulps serde_json's own
/// float parsing may differ by.
fn same_number(got: &Value, cell: &str, what: &str) {
    let want: f64 = cell.parse().unwrap_or_else(|_| panic!("{what}: {cell:?}"));
    let got = got
        .as_f64()
        .unwrap_or_else(|| panic!("{what}: not a number: {got}"));
    assert!(
        (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
        "{what}: {got} against {want}"
    );
}

#[test]
fn the_packing_view_of_particles_carries_their_outlines() {
    let dir = scratch("serve-shapes-view");
    let server = Server::start(&dir.join("data"), &[]);
    let ellipses = submit(
        &server,
        "pack",
        1,
        &shapes_config(
            "[shape]\nkind = \"superellipse\"\naspect = 1.5\nalpha = 2.5\nbeta = 3\norientation = \"random\"\n",
        ),
    );
    let polygons = submit(
        &server,
        "pack",
        1,
        &shapes_config(
            "[shape]\nkind = \"polygon\"\norientation = \"random\"\n\
             [[shape.templates]]\nvertices = [[0, 0], [2, 0], [1, 1.7]]\nrounding = 0.1\nshare = 0.5\n\
             [[shape.templates]]\nvertices = [[0, 0], [3, 0], [3, 1], [0, 1]]\nrounding = 0.05\nshare = 0.5\n",
        ),
    );
    for (id, family, other) in [
        (
            &ellipses,
            ["a", "b", "alpha", "beta"].as_slice(),
            ["template", "rounding", "vertices"].as_slice(),
        ),
        (
            &polygons,
            ["template", "rounding", "vertices"].as_slice(),
            ["a", "b", "alpha", "beta"].as_slice(),
        ),
    ] {
        let job = wait_for(&server, id, &["succeeded", "failed"]);
        assert_eq!(job["state"], "succeeded", "{job}");
        let drawn = get(&server, &format!("/api/v1/jobs/{id}/packing")).json();
        let rows = csv_rows(&get(&server, &format!("/api/v1/jobs/{id}/files/packing.csv")).body);
        assert!(rows.len() > 20, "{} particles", rows.len());
        let shapes = drawn["shapes"].as_object().expect("the shapes");
        // The family's columns, none of the other's.
        let mut keys: Vec<&str> = shapes.keys().map(String::as_str).collect();
        keys.sort_unstable();
        let mut expected: Vec<&str> = family.iter().copied().chain(["angle"]).collect();
        expected.sort_unstable();
        assert_eq!(keys, expected);
        for name in other {
            assert!(!shapes.contains_key(*name), "{name}");
        }
        for (i, row) in rows.iter().enumerate() {
            for column in ["x", "y", "r"] {
                same_number(
                    &drawn[column][i],
                    &row[column],
                    &format!("particle {i} {column}"),
                );
            }
            same_number(
                &shapes["angle"][i],
                &row["angle"],
                &format!("particle {i} angle"),
            );
            for &column in family {
                let what = format!("particle {i} {column}");
                let got = &shapes[column][i];
                match column {
                    "template" => assert_eq!(
                        got.as_u64().map(|t| t.to_string()).as_deref(),
                        Some(row[column].as_str()),
                        "{what}"
                    ),
                    "vertices" => {
                        let cell: Vec<&str> = row[column].split(';').collect();
                        let got = got.as_array().expect("vertices");
                        assert_eq!(got.len(), cell.len(), "{what}");
                        for (g, c) in got.iter().zip(cell) {
                            let (x, y) = c.split_once(' ').expect("x y");
                            same_number(&g[0], x, &what);
                            same_number(&g[1], y, &what);
                        }
                    }
                    _ => same_number(got, &row[column], &what),
                }
            }
        }
    }
    // Disks: the view as it always was, without `shapes`.
    let disks = submit(&server, "pack", 1, SQUARE);
    wait_for(&server, &disks, &["succeeded"]);
    let drawn = get(&server, &format!("/api/v1/jobs/{disks}/packing")).json();
    let keys: Vec<&str> = drawn
        .as_object()
        .expect("an object")
        .keys()
        .map(String::as_str)
        .collect();
    assert_eq!(
        keys,
        ["bounds", "material", "materials", "outline", "r", "x", "y"]
    );
    // The document describes them.
    let doc = get(&server, "/api/v1/openapi.json").json();
    let shapes = doc["components"]["schemas"]["PackingView"]["properties"]["shapes"].to_string();
    assert!(
        shapes.contains("#/components/schemas/PackingShapes"),
        "{shapes}"
    );
    let columns = &doc["components"]["schemas"]["PackingShapes"]["properties"];
    for field in [
        "angle", "a", "b", "alpha", "beta", "template", "rounding", "vertices",
    ] {
        assert!(columns.get(field).is_some(), "{field}: {columns}");
    }
}

#[test]
fn kill_9_mid_search_then_restart_resumes_to_the_same_packing() {
    let dir = scratch("serve-kill9");
    let data = dir.join("data");
    let config = long_optimise_config();
    let server = Server::start(&data, &["--checkpoint-every", "1"]);
    let id = submit(&server, "optimise", 9, &config);
    let seen = follow_until_generation(&server, &id, 4);
    assert!(
        seen.iter()
            .any(|e| e["event"] == "generation" && e["index"] == 4),
        "stopped before generation 4: {seen:?}"
    );
    server.kill();
    assert!(data.join("jobs").join(&id).join("checkpoint.json").exists());

    let server = Server::start(&data, &["--checkpoint-every", "1"]);
    let job = wait_for(&server, &id, &["succeeded", "failed", "cancelled"]);
    assert_eq!(job["state"], "succeeded", "{job}");
    assert_eq!(job["attempts"], 2);
    let events = follow(&server, &id, None);
    assert!(
        events
            .iter()
            .any(|(_, n, v)| n == "state" && v["reason"] == "the server restarted")
    );
    let served = download(&server, &id);
    let cli = cli_run(&dir, "optimise", &config, 9);
    for table in ["packing.csv", "convergence.csv"] {
        let mine = &served.iter().find(|(n, _)| n == table).expect(table).1;
        let theirs = fs::read(cli.join(table)).expect("cli");
        assert_eq!(untimed(mine), untimed(&theirs), "{table}");
    }
    server.terminate();
}

#[test]
fn a_failed_write_fails_its_job_and_the_next_jobs_run() {
    let dir = scratch("serve-write-fails");
    let data = dir.join("data");
    let server = Server::start(&data, &["--workers", "0"]);
    let doomed = submit(&server, "pack", 1, SQUARE);
    server.terminate();
    // Its folder cannot be made: a file stands in its place.
    fs::write(data.join("jobs").join(&doomed), "in the way").expect("write");
    let server = Server::start(&data, &["--workers", "1"]);
    let job = wait_for(&server, &doomed, &["failed", "succeeded"]);
    assert_eq!(job["state"], "failed");
    let error = job["error"].as_str().expect("error");
    assert!(error.contains("cannot write the outputs"), "{error}");
    assert!(error.contains(&doomed), "names the folder: {error}");
    let events = follow(&server, &doomed, None);
    assert_eq!(events.last().expect("events").2["error"], error);
    // Failed before it wrote anything: no files, said as a conflict.
    let r = get(&server, &format!("/api/v1/jobs/{doomed}/files"));
    assert_eq!(r.status, 409);
    assert!(
        r.error().contains("finished without writing files"),
        "{}",
        r.error()
    );
    let next = submit(&server, "pack", 2, SQUARE);
    assert_eq!(
        wait_for(&server, &next, &["succeeded", "failed"])["state"],
        "succeeded"
    );
    server.terminate();
}

#[test]
fn sigterm_loses_nothing_queued_or_running() {
    let dir = scratch("serve-sigterm");
    let data = dir.join("data");
    let config = long_optimise_config();
    let server = Server::start(&data, &["--workers", "1", "--checkpoint-every", "1"]);
    let running = submit(&server, "optimise", 9, &config);
    let queued: Vec<String> = (0..3).map(|s| submit(&server, "pack", s, SQUARE)).collect();
    follow_until_generation(&server, &running, 2);
    server.terminate();

    let server = Server::start(&data, &["--workers", "1", "--checkpoint-every", "1"]);
    let job = wait_for(&server, &running, &["succeeded", "failed", "cancelled"]);
    assert_eq!(job["state"], "succeeded", "{job}");
    for id in &queued {
        assert_eq!(
            wait_for(&server, id, &["succeeded", "failed"])["state"],
            "succeeded"
        );
    }
    let served = download(&server, &running);
    let cli = cli_run(&dir, "optimise", &config, 9);
    let mine = &served
        .iter()
        .find(|(n, _)| n == "packing.csv")
        .expect("packing")
        .1;
    assert!(mine == &fs::read(cli.join("packing.csv")).expect("cli"));
    let all = get(&server, "/api/v1/jobs?limit=500").json();
    assert_eq!(
        all["jobs"].as_array().expect("jobs").len(),
        4,
        "none lost, none doubled"
    );
    server.terminate();
}

/// The README's "Run as a service" block, run as a script (on a free port,
/// with `gapack` on the PATH) in a scratch folder holding the default config.
#[test]
fn the_readme_service_commands_run() {
    let readme = fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
        "/README.md"
    ))
    .expect("README");
    let section = readme
        .split("## Run as a service")
        .nth(1)
        .expect("a Run as a service section");
    let script = section
        .split("```sh\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("a sh block");
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let script = script.replace("127.0.0.1:8080", &format!("127.0.0.1:{port}"));
    let dir = scratch("serve-readme");
    fs::create_dir_all(dir.join("configs")).expect("dir");
    fs::copy(
        concat!(
            concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
            "/configs/default.toml"
        ),
        dir.join("configs/default.toml"),
    )
    .expect("config");
    let bin = Path::new(env!("CARGO_BIN_EXE_gapack"))
        .parent()
        .expect("bin dir")
        .to_owned();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new("bash")
        .args(["-e", "-c", &script])
        .current_dir(&dir)
        .env("PATH", path)
        .output()
        .expect("bash");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("listening on http://127.0.0.1:"),
        "{stdout}"
    );
    assert!(stdout.contains("\"status\":\"ok\""), "{stdout}");
    assert!(
        stdout.contains("event: state\ndata: {\"event\":\"state\",\"state\":\"succeeded\"}"),
        "{stdout}"
    );
    assert!(stdout.contains("\"name\":\"packing.csv\""), "{stdout}");
    let cli = cli_run(
        &dir,
        "pack",
        &fs::read_to_string(dir.join("configs/default.toml")).expect("read"),
        7,
    );
    assert!(
        fs::read(dir.join("packing.csv")).expect("fetched")
            == fs::read(cli.join("packing.csv")).expect("cli")
    );
}
