//! `gapack serve` sending a large job's files and its packing view, on the
//! real binary: ten clients at once cost the server a buffer each, not the
//! file (its peak resident set, `VmHWM` after a reset through
//! `/proc/PID/clear_refs`, against its idle `VmRSS`); the file arrives
//! whole with its `Content-Length`, a range of it as asked.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::common;

use common::scratch;
use common::server::{Server, agent};
use serde_json::Value;

const SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n[output]\nformats = [\"csv\"]\n";

/// Peak resident set ten downloads at once may add to the idle server
/// (bytes). Reading each file whole, as the server did, added ten times
/// the file (over 300 MB here); streamed, each download holds a read
/// buffer (64 KiB) or a batch of rows (256 KiB of text and its table).
const MAX_ADDED: u64 = 40 << 20;

/// Clients downloading at once.
const CLIENTS: usize = 10;

/// A job of the server, finished: its id.
fn finished_job(server: &Server) -> String {
    let r = agent()
        .post(server.url("/api/v1/jobs?kind=pack"))
        .header("Content-Type", "application/toml")
        .send(SQUARE)
        .expect("submitted");
    assert_eq!(r.status().as_u16(), 201);
    let accepted: Value = serde_json::from_reader(r.into_body().into_reader()).expect("JSON");
    let id = accepted["id"].as_str().expect("an id").to_owned();
    let start = Instant::now();
    loop {
        let job: Value = serde_json::from_reader(
            agent()
                .get(server.url(&format!("/api/v1/jobs/{id}")))
                .call()
                .expect("the job")
                .into_body()
                .into_reader(),
        )
        .expect("JSON");
        if job["state"] == "succeeded" {
            return id;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "job {id} still {}",
            job["state"]
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `packing.csv` of at least `bytes` bytes of disks, in place of the job's own.
fn write_large_packing(path: &Path, bytes: usize) {
    let mut text = String::with_capacity(bytes + 64);
    text.push_str("id,x,y,r\n");
    let mut i = 0u64;
    while text.len() < bytes {
        let f = i as f64;
        text.push_str(&format!(
            "{i},{},{},{}\n",
            (f * 0.754_877_666).fract() * 2000.0,
            (f * 0.569_840_291).fract() * 2000.0,
            1.0 + (f * 0.618_033_988_7).fract()
        ));
        i += 1;
    }
    std::fs::write(path, text).expect("written");
}

/// Line `key` of the server's `/proc/PID/status`, in bytes.
fn status_bytes(server: &Server, key: &str) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{}/status", server.pid())).expect("status");
    status
        .lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(':'))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .map(|kb| kb * 1024)
        .unwrap_or_else(|| panic!("no {key} in {status}"))
}

/// `CLIENTS` downloads of `path` at once, each read to its end: the bytes
/// each received, and what the server's peak resident set rose by over
/// its idle one meanwhile.
fn downloads_at_once(server: &Server, path: &str) -> (Vec<u64>, u64) {
    std::thread::sleep(Duration::from_millis(500));
    let idle = status_bytes(server, "VmRSS");
    std::fs::write(format!("/proc/{}/clear_refs", server.pid()), "5").expect("peak reset");
    let url = server.url(path);
    let sizes = std::thread::scope(|s| {
        let clients: Vec<_> = (0..CLIENTS)
            .map(|_| {
                s.spawn(|| {
                    let r = agent().get(&url).call().expect("a response");
                    assert_eq!(r.status().as_u16(), 200, "{url}");
                    let mut body = r.into_body().into_reader();
                    std::io::copy(&mut body, &mut std::io::sink()).expect("the body")
                })
            })
            .collect();
        clients
            .into_iter()
            .map(|c| c.join().expect("a client"))
            .collect()
    });
    let peak = status_bytes(server, "VmHWM");
    (sizes, peak.saturating_sub(idle))
}

#[test]
fn ten_downloads_of_a_large_file_at_once_cost_a_buffer_each() {
    let dir = scratch("serve-files-large");
    let data = dir.join("data");
    let server = Server::start(&data, &[]);
    let id = finished_job(&server);
    let csv = data.join("jobs").join(&id).join("packing.csv");
    write_large_packing(&csv, 32 << 20);
    let size = std::fs::metadata(&csv).expect("the file").len();
    let url = format!("/api/v1/jobs/{id}/files/packing.csv");
    // The length, then a range from the middle, as on disk.
    let head = agent().head(server.url(&url)).call().expect("HEAD");
    assert_eq!(
        head.headers()
            .get("content-length")
            .and_then(|v| v.to_str().ok()),
        Some(size.to_string().as_str())
    );
    let from = size / 2;
    let mut part = agent()
        .get(server.url(&url))
        .header("Range", format!("bytes={from}-{}", from + 99))
        .call()
        .expect("a range");
    assert_eq!(part.status().as_u16(), 206);
    let expected = std::fs::read(&csv).expect("the file");
    let from = usize::try_from(from).expect("in memory");
    assert!(part.body_mut().read_to_vec().expect("the range") == expected[from..from + 100]);
    drop(expected);

    let (sizes, added) = downloads_at_once(&server, &url);
    assert!(sizes.iter().all(|&n| n == size), "{sizes:?} of {size}");
    assert!(
        added < MAX_ADDED,
        "the server's peak rose by {} MB over {CLIENTS} downloads of a {} MB file",
        added >> 20,
        size >> 20
    );
}

#[test]
fn ten_views_of_a_large_packing_at_once_cost_a_batch_each() {
    let dir = scratch("serve-view-large");
    let data = dir.join("data");
    let server = Server::start(&data, &[]);
    let id = finished_job(&server);
    let csv = data.join("jobs").join(&id).join("packing.csv");
    write_large_packing(&csv, 8 << 20);
    let rows = std::fs::read_to_string(&csv)
        .expect("the file")
        .lines()
        .count()
        - 1;
    let url = format!("/api/v1/jobs/{id}/packing");
    let body = agent()
        .get(server.url(&url))
        .call()
        .expect("the view")
        .body_mut()
        .with_config()
        .limit(1 << 30)
        .read_to_vec()
        .expect("the body");
    let view: Value = serde_json::from_slice(&body).expect("JSON");
    for column in ["x", "y", "r"] {
        assert_eq!(
            view[column].as_array().map(Vec::len),
            Some(rows),
            "{column}"
        );
    }
    let size = body.len() as u64;
    drop((view, body));
    let (sizes, added) = downloads_at_once(&server, &url);
    assert!(sizes.iter().all(|&n| n == size), "{sizes:?} of {size}");
    assert!(
        added < MAX_ADDED,
        "the server's peak rose by {} MB over {CLIENTS} views of a {} MB packing",
        added >> 20,
        size >> 20
    );
}
