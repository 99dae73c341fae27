//! `gapack serve` at its edges, over raw sockets: clients that trickle
//! their headers, stall in their body, announce an oversized body, or
//! outnumber the connection bound; an event stream against the request
//! timeout; SIGTERM with a request half-sent.

use crate::common;

use std::io::{BufRead, BufReader, ErrorKind, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use common::scratch;
use common::server::{Server, agent};
use serde_json::Value;

const SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n";

/// A `GET /healthz` on a fresh connection: its status and how long the
/// answer took.
fn timed_health(server: &Server) -> (u16, Duration) {
    let start = Instant::now();
    let (status, _) = server.raw(
        format!(
            "GET /healthz HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
            server.addr()
        )
        .as_bytes(),
    );
    (status, start.elapsed())
}

/// Wait (at most `limit`) until the server closes `stream`: whether it did.
fn closed_within(stream: &mut TcpStream, limit: Duration) -> bool {
    let deadline = Instant::now() + limit;
    let mut buffer = [0_u8; 1024];
    // Each pass reads something or waits out part of the time left.
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return false;
        }
        stream.set_read_timeout(Some(left)).expect("timeout");
        match stream.read(&mut buffer) {
            Ok(0) => return true,
            Ok(_) => {}
            Err(e) if e.kind() == ErrorKind::ConnectionReset => return true,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                return false;
            }
            Err(e) => panic!("read: {e}"),
        }
    }
}

#[test]
fn fifty_trickling_clients_hold_up_no_request_and_are_closed() {
    let dir = scratch("serve-edges-trickle");
    let server = Server::start(
        &dir.join("data"),
        &["--workers", "0", "--header-timeout", "3"],
    );
    let opened = Instant::now();
    let mut tricklers: Vec<TcpStream> = (0..50)
        .map(|_| TcpStream::connect(server.addr()).expect("connect"))
        .collect();
    let writers: Vec<TcpStream> = tricklers
        .iter()
        .map(|s| s.try_clone().expect("clone"))
        .collect();
    // A byte on every socket every half second, for at most 8 s: headers
    // that would take minutes to finish.
    let trickle = std::thread::spawn(move || {
        let line = format!("GET /healthz HTTP/1.1\r\nX-Slow: {}", "a".repeat(400));
        let mut writers = writers;
        for byte in line.bytes().take(16) {
            for w in &mut writers {
                // Closed by the server: the point of the test, not a fault.
                let _ = w.write_all(&[byte]);
            }
            std::thread::sleep(Duration::from_millis(500));
        }
    });
    std::thread::sleep(Duration::from_secs(1));
    for _ in 0..3 {
        let (status, took) = timed_health(&server);
        assert_eq!(status, 200);
        assert!(took < Duration::from_secs(1), "answered after {took:?}");
    }
    // Each trickler is closed once its 3 s for headers are out.
    for (i, stream) in tricklers.iter_mut().enumerate() {
        let left = Duration::from_secs(8).saturating_sub(opened.elapsed());
        assert!(
            closed_within(stream, left),
            "trickler {i} still open after {:?}",
            opened.elapsed()
        );
    }
    assert!(opened.elapsed() >= Duration::from_millis(2500));
    trickle.join().expect("trickle");
    let (status, took) = timed_health(&server);
    assert_eq!(status, 200);
    assert!(took < Duration::from_secs(1), "answered after {took:?}");
}

#[test]
fn an_incomplete_body_is_answered_408_and_closed_in_time() {
    let dir = scratch("serve-edges-incomplete");
    let server = Server::start(
        &dir.join("data"),
        &["--workers", "0", "--request-timeout", "2"],
    );
    for path in ["/api/v1/jobs?kind=pack", "/api/v1/validate"] {
        let start = Instant::now();
        // 100 bytes announced, 9 sent, the connection kept open.
        let (status, body) = server.raw(
            format!(
                "POST {path} HTTP/1.1\r\nHost: {}\r\nContent-Type: application/toml\r\n\
                 Content-Length: 100\r\n\r\nseed = 1\n",
                server.addr()
            )
            .as_bytes(),
        );
        let took = start.elapsed();
        assert_eq!(status, 408, "{path}: {body}");
        let error: Value = serde_json::from_str(&body).expect("a JSON body");
        assert_eq!(
            error["error"],
            "the request was not answered within 2 s (was its body sent whole?)"
        );
        assert!(
            took >= Duration::from_millis(1900) && took < Duration::from_secs(5),
            "{path}: closed after {took:?}"
        );
    }
}

#[test]
fn a_body_declared_oversized_is_refused_at_once_though_some_is_sent() {
    let dir = scratch("serve-edges-oversize");
    let server = Server::start(&dir.join("data"), &["--workers", "0"]);
    let start = Instant::now();
    // Kept alive, 3 bytes of the body sent: the answer comes, then the close.
    let (status, body) = server.raw(
        format!(
            "POST /api/v1/jobs?kind=pack HTTP/1.1\r\nHost: {}\r\n\
             Content-Type: application/toml\r\nContent-Length: {}\r\n\r\nabc",
            server.addr(),
            (1 << 20) + 1
        )
        .as_bytes(),
    );
    let took = start.elapsed();
    assert_eq!(status, 413, "{body}");
    assert!(body.contains("1 MiB"), "{body}");
    assert!(took < Duration::from_secs(1), "answered after {took:?}");
}

#[test]
fn connections_beyond_the_bound_wait_for_a_free_slot() {
    let dir = scratch("serve-edges-bound");
    let server = Server::start(
        &dir.join("data"),
        &[
            "--workers",
            "0",
            "--max-connections",
            "2",
            "--header-timeout",
            "2",
        ],
    );
    // Both slots held by clients that never send a byte.
    let silent: Vec<TcpStream> = (0..2)
        .map(|_| TcpStream::connect(server.addr()).expect("connect"))
        .collect();
    std::thread::sleep(Duration::from_millis(200));
    let (status, took) = timed_health(&server);
    assert_eq!(status, 200);
    // Answered once the header timeout freed a slot: not before, not long after.
    assert!(
        took >= Duration::from_secs(1) && took < Duration::from_secs(6),
        "answered after {took:?}"
    );
    drop(silent);
    let (status, took) = timed_health(&server);
    assert_eq!(status, 200);
    assert!(took < Duration::from_secs(1), "answered after {took:?}");
}

#[test]
fn an_event_stream_outlives_the_request_timeout() {
    let dir = scratch("serve-edges-sse");
    let server = Server::start(
        &dir.join("data"),
        &["--workers", "0", "--request-timeout", "1"],
    );
    let mut r = agent()
        .post(server.url("/api/v1/jobs?kind=pack&seed=1"))
        .header("Content-Type", "application/toml")
        .send(SQUARE)
        .expect("submit");
    assert_eq!(r.status().as_u16(), 201);
    let job: Value =
        serde_json::from_str(&r.body_mut().read_to_string().expect("body")).expect("json");
    let id = job["id"].as_str().expect("id").to_owned();
    let events = agent()
        .get(server.url(&format!("/api/v1/jobs/{id}/events")))
        .call()
        .expect("events");
    assert_eq!(events.status().as_u16(), 200);
    let start = Instant::now();
    // The job is queued with no worker: the stream waits, past the timeout,
    // until the job is cancelled.
    let follow = std::thread::spawn(move || {
        let reader = BufReader::new(events.into_body().into_reader());
        reader
            .lines()
            .map(|line| line.expect("line"))
            .filter_map(|line| line.strip_prefix("data:").map(str::to_owned))
            .map(|data| serde_json::from_str::<Value>(&data).expect("json"))
            .filter_map(|event| event["state"].as_str().map(str::to_owned))
            .collect::<Vec<_>>()
    });
    std::thread::sleep(Duration::from_millis(2500));
    let r = agent()
        .post(server.url(&format!("/api/v1/jobs/{id}/cancel")))
        .send_empty()
        .expect("cancel");
    assert_eq!(r.status().as_u16(), 200);
    let states = follow.join().expect("follow");
    assert_eq!(states, ["queued", "cancelled"]);
    assert!(start.elapsed() >= Duration::from_millis(2500));
}

#[test]
fn sigterm_with_a_request_half_sent_still_exits() {
    let dir = scratch("serve-edges-sigterm");
    let server = Server::start(
        &dir.join("data"),
        &["--workers", "0", "--header-timeout", "2"],
    );
    let mut half = TcpStream::connect(server.addr()).expect("connect");
    half.write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n")
        .expect("write");
    std::thread::sleep(Duration::from_millis(200));
    let start = Instant::now();
    server.terminate();
    let took = start.elapsed();
    assert!(took < Duration::from_secs(6), "exit after {took:?}");
    drop(half);
}
