//! The HTTP API: one module per route group, each with its `router()`,
//! merged here into the service's router with its layers (the token in
//! front of the API and `/metrics`, the body limit, the time limit on an
//! answer, panics caught into a `500`, a log line per request) and the
//! JSON fallbacks.
//!
//! - [`jobs`]: submit, validate, list, get, cancel, delete ([`submission`]
//!   reads and plans what a submission asks);
//! - [`events`]: a job's events as Server-Sent Events;
//! - [`files`]: a finished job's files, as its manifest lists them;
//! - [`page`]: the web page, its assets and the data it draws;
//! - [`service`]: health and metrics;
//! - [`openapi`]: the OpenAPI document of the API;
//! - [`error`]: the one error type; [`auth`]: the bearer token.

mod auth;
mod error;
mod events;
mod files;
mod jobs;
mod openapi;
mod page;
mod service;
mod submission;
#[cfg(test)]
pub mod testing;

use std::any::Any;
use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::StatusCode;
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::trace::{MakeSpan, OnResponse, TraceLayer};
use tracing::Span;

use super::Shared;
use error::ApiError;

/// Largest request body (bytes): 1 MiB.
pub const MAX_BODY: usize = 1 << 20;

/// The state every handler reads.
type AppState = State<Arc<Shared>>;

/// The service's routes, with their layers.
pub fn router(shared: Arc<Shared>) -> Router {
    let api = Router::new()
        .merge(jobs::router())
        .merge(events::router())
        .merge(files::router())
        .merge(page::data())
        .merge(openapi::router());
    let routes = Router::new()
        .nest("/api/v1", api)
        .merge(service::metrics())
        .layer(middleware::from_fn_with_state(
            Arc::clone(&shared),
            auth::require_token,
        ))
        .merge(service::health())
        // The page and its assets hold no data: a server with a token
        // serves them to anyone, and the page asks for the token.
        .merge(page::web())
        .fallback(error::not_found)
        .method_not_allowed_fallback(error::method_not_allowed);
    layered(routes, shared.request_timeout).with_state(shared)
}

/// `routes` with the layers every request passes, innermost first: the
/// body limit (as read, then as declared), the time limit on an answer, panics
/// caught, the log line.
fn layered(routes: Router<Arc<Shared>>, timeout: Duration) -> Router<Arc<Shared>> {
    routes
        .layer(DefaultBodyLimit::max(MAX_BODY))
        .layer(middleware::from_fn(declared_size))
        .layer(middleware::from_fn_with_state(timeout, time_limit))
        .layer(CatchPanicLayer::custom(panicked))
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(RequestSpan)
                .on_request(())
                .on_response(LogLine),
        )
}

/// Run a blocking store or file call off the async threads.
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    tokio::task::spawn_blocking(f)
        .await
        .map_err(ApiError::internal)?
}

/// A body declared (`Content-Length`) over [`MAX_BODY`] is refused before
/// any of it is read, so a client announcing gigabytes is answered at once
/// rather than held open while it sends them.
async fn declared_size(request: Request, next: Next) -> Response {
    let declared = request
        .headers()
        .get(axum::http::header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if declared.is_some_and(|n| n > MAX_BODY as u64) {
        return ApiError::new(
            axum::http::StatusCode::PAYLOAD_TOO_LARGE,
            format!("the request body is over the limit of {MAX_BODY} bytes (1 MiB)"),
        )
        .into_response();
    }
    next.run(request).await
}

/// A request not answered within `limit` (its body read included: a
/// client that stops sending it is not waited for) is answered `408`, and
/// its connection closed. What comes after the answer's head (an event
/// stream, a file) is not timed.
async fn time_limit(State(limit): State<Duration>, request: Request, next: Next) -> Response {
    match tokio::time::timeout(limit, next.run(request)).await {
        Ok(response) => response,
        Err(_) => {
            let mut response = ApiError::new(
                StatusCode::REQUEST_TIMEOUT,
                format!(
                    "the request was not answered within {} s (was its body sent whole?)",
                    limit.as_secs_f64()
                ),
            )
            .into_response();
            response.headers_mut().insert(
                axum::http::header::CONNECTION,
                axum::http::HeaderValue::from_static("close"),
            );
            response
        }
    }
}

/// The answer to a handler's panic: a `500` with the JSON error body,
/// whose message carries a fresh id, logged with the panic's message
/// under the same id so the two can be matched.
fn panicked(panic: Box<dyn Any + Send + 'static>) -> Response {
    let what = panic
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| panic.downcast_ref::<&str>().copied())
        .unwrap_or("(no message)");
    let id = format!("{:016x}", rand::random::<u64>());
    tracing::error!(id, panic = what, "a handler panicked");
    ApiError::new(
        StatusCode::INTERNAL_SERVER_ERROR,
        format!(
            "internal error {id}: the server failed on this request; its log says why under this id"
        ),
    )
    .into_response()
}

/// Each request's span: its method and path, on every line logged while
/// it is handled (the answer's line, an error, a panic).
#[derive(Clone, Copy)]
struct RequestSpan;

impl<B> MakeSpan<B> for RequestSpan {
    fn make_span(&mut self, request: &axum::http::Request<B>) -> Span {
        tracing::info_span!(
            "request",
            method = %request.method(),
            path = %request.uri().path(),
            user = tracing::field::Empty
        )
    }
}

/// One log line per request, once its answer's head is sent: the status
/// and the time taken (ms), under the request's span.
#[derive(Clone, Copy)]
struct LogLine;

impl<B> OnResponse<B> for LogLine {
    fn on_response(self, response: &axum::http::Response<B>, latency: Duration, _: &Span) {
        tracing::info!(
            status = response.status().as_u16(),
            ms = latency.as_secs_f64() * 1e3,
            "answered"
        );
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;
    use std::sync::{Arc, Mutex, OnceLock, PoisonError};
    use std::time::{Duration, Instant};

    use axum::Router;
    use axum::body::Body;
    use axum::http::{Method, Request, StatusCode};
    use axum::routing::get;
    use http_body_util::BodyExt;
    use tower::ServiceExt;

    use super::testing::{SQUARE, TestServer, sse_events};

    /// Log lines written while the tests run.
    #[derive(Clone, Default)]
    struct Captured(Arc<Mutex<Vec<u8>>>);

    /// The tests' log, kept in memory: set once as the process's global
    /// subscriber (a per-thread one misses events whose call sites other
    /// tests' threads reached first).
    fn captured_log() -> &'static Captured {
        static LOG: OnceLock<Captured> = OnceLock::new();
        LOG.get_or_init(|| {
            let log = Captured::default();
            let sink = log.clone();
            let subscriber = tracing_subscriber::fmt()
                .with_writer(move || sink.clone())
                .with_ansi(false)
                .with_max_level(tracing::Level::INFO)
                .finish();
            tracing::subscriber::set_global_default(subscriber)
                .expect("the only global subscriber");
            log
        })
    }

    impl Write for Captured {
        fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
            self.0
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .extend_from_slice(bytes);
            Ok(bytes.len())
        }

        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Captured {
        fn text(&self) -> String {
            String::from_utf8_lossy(&self.0.lock().unwrap_or_else(PoisonError::into_inner))
                .into_owned()
        }
    }

    /// The service's layers over `routes`, with a `timeout` on answers,
    /// answering `path`: its status, its headers and its JSON body.
    async fn layered_reply(
        routes: Router<Arc<crate::Shared>>,
        timeout: Duration,
        path: &str,
    ) -> (StatusCode, axum::http::HeaderMap, serde_json::Value) {
        let server = TestServer::new();
        let router = super::layered(routes, timeout).with_state(Arc::clone(&server.shared));
        let request = Request::get(path).body(Body::empty()).expect("request");
        let response = router
            .oneshot(request)
            .await
            .expect("the router never fails");
        let (parts, body) = response.into_parts();
        let bytes = body.collect().await.expect("a body").to_bytes();
        let json = serde_json::from_slice(&bytes).expect("a JSON body");
        (parts.status, parts.headers, json)
    }

    #[tokio::test]
    async fn a_panic_is_answered_500_with_an_id_the_log_gives_with_its_message() {
        let log = captured_log();
        async fn boom() -> &'static str {
            panic!("the disk caught fire")
        }
        let routes = Router::new().route("/boom", get(boom));
        let (status, headers, body) = layered_reply(routes, Duration::from_secs(60), "/boom").await;
        assert_eq!(status, StatusCode::INTERNAL_SERVER_ERROR);
        assert_eq!(
            headers.get("content-type").and_then(|v| v.to_str().ok()),
            Some("application/json")
        );
        let error = body["error"].as_str().expect("an error message");
        let id = error
            .strip_prefix("internal error ")
            .and_then(|rest| rest.split(':').next())
            .expect("an id after \"internal error \"");
        assert!(
            id.len() == 16 && id.chars().all(|c| c.is_ascii_hexdigit()),
            "{error}"
        );
        // The message stays in the log, not in the answer.
        assert!(!error.contains("caught fire"), "{error}");
        let log = log.text();
        let panicked = log
            .lines()
            .find(|l| l.contains("a handler panicked"))
            .unwrap_or_else(|| panic!("no panic line in {log}"));
        assert!(panicked.contains(&format!("id=\"{id}\"")), "{panicked}");
        assert!(panicked.contains("the disk caught fire"), "{panicked}");
        assert!(panicked.contains("path=/boom"), "{panicked}");
        // And the request's own line says 500.
        let answered = log
            .lines()
            .find(|l| l.contains("answered") && l.contains("path=/boom"))
            .unwrap_or_else(|| panic!("no request line in {log}"));
        for part in ["method=GET", "path=/boom", "status=500", "ms="] {
            assert!(answered.contains(part), "{part}: {answered}");
        }
    }

    #[tokio::test]
    async fn an_answer_late_past_the_time_limit_is_a_408_that_closes() {
        let routes = Router::new().route(
            "/stuck",
            get(|| async {
                tokio::time::sleep(Duration::from_secs(3600)).await;
                "late"
            }),
        );
        let start = Instant::now();
        let (status, headers, body) =
            layered_reply(routes, Duration::from_millis(200), "/stuck").await;
        let took = start.elapsed();
        assert_eq!(status, StatusCode::REQUEST_TIMEOUT);
        assert!(took < Duration::from_secs(5), "{took:?}");
        assert_eq!(
            headers.get("connection").and_then(|v| v.to_str().ok()),
            Some("close")
        );
        assert_eq!(
            body["error"],
            "the request was not answered within 0.2 s (was its body sent whole?)"
        );
    }

    #[tokio::test]
    async fn a_body_declared_over_the_limit_is_refused_before_it_is_read() {
        let server = TestServer::new();
        for path in ["/api/v1/jobs?kind=pack", "/api/v1/validate"] {
            let r = server
                .call(
                    Method::POST,
                    path,
                    &[
                        ("content-type", "application/toml"),
                        ("content-length", "100000000000"),
                    ],
                )
                .await;
            assert_eq!(
                r.status,
                StatusCode::PAYLOAD_TOO_LARGE,
                "{path}: {}",
                r.text()
            );
            assert_eq!(
                r.error(),
                "the request body is over the limit of 1048576 bytes (1 MiB)"
            );
        }
    }

    #[tokio::test]
    async fn a_job_from_submission_to_its_files_then_deleted() {
        let server = TestServer::new();
        let r = server
            .post("/api/v1/jobs?kind=pack&seed=1", "application/toml", SQUARE)
            .await;
        assert_eq!(r.status, StatusCode::CREATED, "{}", r.text());
        let accepted = r.json();
        let id = accepted["id"].as_str().expect("id").to_owned();
        let base = format!("/api/v1/jobs/{id}");
        assert_eq!(r.header("location"), Some(base.as_str()));
        assert_eq!(
            (&accepted["kind"], &accepted["state"], &accepted["seed"]),
            (&"pack".into(), &"queued".into(), &1.into())
        );
        assert_eq!(accepted["urls"]["events"], format!("{base}/events"));

        let job = server.get(&base).await;
        assert_eq!(job.status, StatusCode::OK);
        assert_eq!(job.json()["state"], "queued");
        assert_eq!(job.json()["config"], SQUARE);
        let early = server.get(&format!("{base}/files")).await;
        assert_eq!(early.status, StatusCode::CONFLICT);
        assert!(early.error().contains("is queued"), "{}", early.error());

        server.run_queued().await;
        let job = server.get(&base).await.json();
        assert_eq!(job["state"], "succeeded", "{job}");
        let particles = job["summary"]["particles"].as_u64().expect("particles");
        assert!(particles > 100, "{particles}");

        // Events: the whole story in order, ending at the final state.
        let r = server.get(&format!("{base}/events")).await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(r.header("content-type"), Some("text/event-stream"));
        let events = sse_events(r.text());
        assert!(events.len() >= 3, "{events:?}");
        assert!(events.windows(2).all(|w| w[0].0 < w[1].0), "{events:?}");
        assert_eq!(events[0].2["state"], "queued");
        let (last_id, last_name, last) = events.last().expect("events");
        assert_eq!(
            (last_name.as_str(), &last["state"]),
            ("state", &"succeeded".into())
        );
        for (_, name, data) in &events {
            assert_eq!(data["event"], name.as_str());
        }
        // Resumed after the one before last: only the last.
        let previous = events[events.len() - 2].0.to_string();
        let resumed = server
            .call(
                Method::GET,
                &format!("{base}/events"),
                &[("last-event-id", &previous)],
            )
            .await;
        let resumed = sse_events(resumed.text());
        assert_eq!(resumed.len(), 1);
        assert_eq!(resumed[0].0, *last_id);

        // Files: as the manifest lists them, sized as on disk.
        let dir = server.data().join("jobs").join(&id);
        let list = server.get(&format!("{base}/files")).await.json();
        assert_eq!(list["interrupted"], false);
        let files = list["files"].as_array().expect("files");
        let names: Vec<&str> = files.iter().filter_map(|f| f["name"].as_str()).collect();
        assert!(
            names.contains(&"packing.csv") && names.contains(&"manifest.json"),
            "{names:?}"
        );
        assert_eq!(
            list["manifest"]["files"].as_array().map(Vec::len),
            Some(files.len())
        );
        for f in files {
            let name = f["name"].as_str().expect("name");
            let size = std::fs::metadata(dir.join(name)).expect("on disk").len();
            assert_eq!(f["bytes"], size, "{name}");
            assert_eq!(f["url"], format!("{base}/files/{name}"));
        }
        let csv = server.get(&format!("{base}/files/packing.csv")).await;
        assert_eq!(csv.status, StatusCode::OK);
        assert_eq!(csv.header("content-type"), Some("text/csv; charset=utf-8"));
        assert_eq!(
            csv.body,
            std::fs::read(dir.join("packing.csv")).expect("csv")
        );

        // The page's data: one column entry per disk, the square's bounds.
        let packing = server.get(&format!("{base}/packing")).await.json();
        for column in ["x", "y", "r"] {
            assert_eq!(
                packing[column].as_array().map(Vec::len),
                Some(particles as usize)
            );
        }
        assert_eq!(
            packing["bounds"],
            serde_json::json!([[0.0, 0.0], [20.0, 20.0]])
        );

        // A finished job's cancel changes nothing; a delete removes it all.
        let r = server
            .call(Method::POST, &format!("{base}/cancel"), &[])
            .await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(r.json()["state"], "succeeded");
        let r = server.call(Method::DELETE, &base, &[]).await;
        assert_eq!(r.status, StatusCode::NO_CONTENT);
        assert!(r.body.is_empty());
        assert!(!dir.exists());
        let r = server.get(&base).await;
        assert_eq!(r.status, StatusCode::NOT_FOUND);
        assert_eq!(r.error(), format!("no job {id:?}"));
        let r = server.call(Method::DELETE, &base, &[]).await;
        assert_eq!(r.status, StatusCode::NOT_FOUND);
    }

    #[tokio::test]
    async fn a_queued_job_is_cancelled_at_once_then_deleted() {
        let server = TestServer::new();
        let id = server.submit("?kind=pack", SQUARE).await;
        let base = format!("/api/v1/jobs/{id}");
        let r = server.call(Method::DELETE, &base, &[]).await;
        assert_eq!(r.status, StatusCode::CONFLICT);
        assert_eq!(
            r.error(),
            format!("job {id} is queued: cancel it, then delete it once it has stopped")
        );
        let r = server
            .call(Method::POST, &format!("{base}/cancel"), &[])
            .await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(r.json()["state"], "cancelled");
        let events = sse_events(server.get(&format!("{base}/events")).await.text());
        let states: Vec<&str> = events
            .iter()
            .filter_map(|e| e.2["state"].as_str())
            .collect();
        assert_eq!(states, ["queued", "cancelled"]);
        // Cancelled before it ran: nothing to serve, nothing left to run.
        let r = server.get(&format!("{base}/files")).await;
        assert_eq!(r.status, StatusCode::CONFLICT);
        assert_eq!(
            r.error(),
            format!("job {id} finished without writing files")
        );
        server.run_queued().await;
        assert_eq!(server.get(&base).await.json()["state"], "cancelled");
        assert_eq!(
            server.call(Method::DELETE, &base, &[]).await.status,
            StatusCode::NO_CONTENT
        );
        assert_eq!(server.get(&base).await.status, StatusCode::NOT_FOUND);
    }

    #[tokio::test]
    async fn unknown_routes_and_methods_answer_json() {
        let server = TestServer::new();
        for path in ["/api/v1/nothing", "/nothing", "/api/v1", "/api/v1/jobs/"] {
            let r = server.get(path).await;
            assert_eq!(r.status, StatusCode::NOT_FOUND, "{path}");
            assert_eq!(r.error(), "no such endpoint; see /api/v1/openapi.json");
        }
        for (method, path) in [
            (Method::PUT, "/api/v1/jobs"),
            (Method::GET, "/api/v1/validate"),
            (Method::POST, "/healthz"),
            (Method::PUT, "/metrics"),
            (Method::POST, "/"),
        ] {
            let r = server.call(method.clone(), path, &[]).await;
            assert_eq!(r.status, StatusCode::METHOD_NOT_ALLOWED, "{method} {path}");
            assert_eq!(
                r.error(),
                "method not allowed on this endpoint; see /api/v1/openapi.json"
            );
            assert_eq!(r.header("content-type"), Some("application/json"));
        }
    }
}
