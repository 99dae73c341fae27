//! The in-process test harness: the real router over a store (SQLite in a
//! temporary folder, or a fresh PostgreSQL database of the test cluster),
//! driven request by request with `tower::ServiceExt::oneshot`; queued
//! jobs run when a test says so, by the workers' own code on a blocking
//! thread. Store calls a test makes itself go through [`TestServer::store`]
//! (off the test's async thread, as the service makes them).

use std::path::PathBuf;
use std::sync::Arc;

use axum::Router;
use axum::body::{Body, Bytes};
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use http_body_util::BodyExt;
use serde_json::Value;
use tempfile::TempDir;
use tower::ServiceExt;

use crate::store::{JobStore, Role};
use crate::users::token_hash;
use crate::{Options, Shared, worker};

/// A small pack: a 20 mm square, about 180 disks, a few milliseconds.
pub const SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n";

/// The token of a guarded test server.
pub const TOKEN: &str = "s3cret-token-0123456789";

/// An id no job has, of the right shape.
pub const NO_JOB: &str = "0123456789abcdef0123456789abcdef";

/// The router over its own store, with no worker running.
pub struct TestServer {
    /// The state the handlers share (the store, the limits, the flags).
    pub shared: Arc<Shared>,
    router: Router,
    dir: TempDir,
}

impl TestServer {
    /// A server with the default options and no token.
    pub fn new() -> Self {
        Self::with(|_| {}, None)
    }

    /// A server with the options `options` sets and `token`: on SQLite,
    /// or on PostgreSQL when `GAPACK_TEST_STORE=postgres` (CI runs every
    /// API test a second time so).
    pub fn with(options: impl FnOnce(&mut Options), token: Option<&str>) -> Self {
        if std::env::var("GAPACK_TEST_STORE").as_deref() == Ok("postgres") {
            return Self::postgres(options, token)
                .expect("GAPACK_TEST_STORE=postgres needs GAPACK_TEST_POSTGRES");
        }
        Self::open(options, token, None)
    }

    /// A server as [`TestServer::with`] on a fresh PostgreSQL database of
    /// the test cluster; `None` (the test skips, saying how to run it)
    /// without one. The test holds a share of the cluster
    /// (`store::conformance::cluster()`) while it runs.
    pub fn postgres(options: impl FnOnce(&mut Options), token: Option<&str>) -> Option<Self> {
        let url = std::thread::scope(|s| {
            s.spawn(crate::store::postgres::test_database)
                .join()
                .expect("a database")
        })?;
        Some(Self::open(options, token, Some(url)))
    }

    fn open(
        options: impl FnOnce(&mut Options),
        token: Option<&str>,
        store: Option<String>,
    ) -> Self {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let mut args = Options {
            data: dir.path().join("data"),
            store,
            ..Options::default()
        };
        options(&mut args);
        let token = token.map(str::to_owned);
        // Off any async thread: a store's calls block.
        let (shared, _) = std::thread::scope(|s| {
            s.spawn(|| Shared::open(&args, token))
                .join()
                .expect("opened")
        })
        .expect("the store");
        let shared = Arc::new(shared);
        TestServer {
            router: super::router(Arc::clone(&shared)),
            shared,
            dir,
        }
    }

    /// `f` on the store, off the test's async thread.
    pub fn store<T: Send>(&self, f: impl FnOnce(&dyn JobStore) -> T + Send) -> T {
        let store = Arc::clone(&self.shared.store);
        std::thread::scope(|s| {
            s.spawn(move || f(store.as_ref()))
                .join()
                .expect("a store call")
        })
    }

    /// The data folder (`gapack.db`, `jobs/<id>/`).
    pub fn data(&self) -> PathBuf {
        self.dir.path().join("data")
    }

    /// The router's answer to `request`, its body read to the end.
    pub async fn send(&self, request: Request<Body>) -> Reply {
        let response = self
            .router
            .clone()
            .oneshot(request)
            .await
            .expect("the router never fails");
        let status = response.status();
        let headers = response.headers().clone();
        let body = response
            .into_body()
            .collect()
            .await
            .expect("a body")
            .to_bytes();
        Reply {
            status,
            headers,
            body,
        }
    }

    /// `method path`, without a body, with `headers`.
    pub async fn call(&self, method: Method, path: &str, headers: &[(&str, &str)]) -> Reply {
        let mut request = Request::builder().method(method).uri(path);
        for (name, value) in headers {
            request = request.header(*name, *value);
        }
        self.send(request.body(Body::empty()).expect("a request"))
            .await
    }

    /// `GET path`.
    pub async fn get(&self, path: &str) -> Reply {
        self.call(Method::GET, path, &[]).await
    }

    /// `POST path` with `body` of `content_type` (none if empty).
    pub async fn post(&self, path: &str, content_type: &str, body: impl Into<Body>) -> Reply {
        let mut request = Request::post(path);
        if !content_type.is_empty() {
            request = request.header(header::CONTENT_TYPE, content_type);
        }
        self.send(request.body(body.into()).expect("a request"))
            .await
    }

    /// Submit `config` as TOML with `query` (`?kind=pack`); its id.
    pub async fn submit(&self, query: &str, config: &str) -> String {
        let r = self
            .post(
                &format!("/api/v1/jobs{query}"),
                "application/toml",
                config.to_owned(),
            )
            .await;
        assert_eq!(r.status, StatusCode::CREATED, "{}", r.text());
        r.json()["id"].as_str().expect("an id").to_owned()
    }

    /// Add user `name` (an admin if `admin`) with a fresh token: the token.
    pub fn add_user(&self, name: &str, admin: bool) -> String {
        let token = format!("gpk_test_{name}_{:016x}", rand::random::<u64>());
        let role = if admin { Role::Admin } else { Role::User };
        let hash = token_hash(&token);
        self.store(|s| s.add_user(name, role, &hash, None, None))
            .expect("a new user");
        token
    }

    /// `method path` with `token` as the bearer token, without a body.
    pub async fn call_as(&self, token: &str, method: Method, path: &str) -> Reply {
        let bearer = format!("Bearer {token}");
        self.call(method, path, &[("authorization", &bearer)]).await
    }

    /// Submit `config` as TOML for `token`'s user; its id.
    pub async fn submit_as(&self, token: &str, config: &str) -> String {
        let request = Request::post("/api/v1/jobs?kind=pack")
            .header(header::CONTENT_TYPE, "application/toml")
            .header(header::AUTHORIZATION, format!("Bearer {token}"))
            .body(Body::from(config.to_owned()))
            .expect("a request");
        let r = self.send(request).await;
        assert_eq!(r.status, StatusCode::CREATED, "{}", r.text());
        r.json()["id"].as_str().expect("an id").to_owned()
    }

    /// Run every queued job to its end, oldest first, as a worker does.
    pub async fn run_queued(&self) {
        let shared = Arc::clone(&self.shared);
        tokio::task::spawn_blocking(move || {
            let name = worker::worker_name(&shared, 0);
            while let Some(job) = shared.store.claim(&name, shared.lease).expect("claim") {
                worker::run_one(&shared, &name, job);
            }
        })
        .await
        .expect("the jobs ran");
    }
}

/// An answer: status, headers, the whole body.
pub struct Reply {
    /// Its status.
    pub status: StatusCode,
    /// Its headers.
    pub headers: HeaderMap,
    /// Its body.
    pub body: Bytes,
}

impl Reply {
    /// The body as text.
    pub fn text(&self) -> &str {
        std::str::from_utf8(&self.body).expect("UTF-8")
    }

    /// The body as JSON.
    pub fn json(&self) -> Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&self.body)))
    }

    /// A refusal's `error`; the body must be an error body.
    pub fn error(&self) -> String {
        self.json()["error"]
            .as_str()
            .unwrap_or_else(|| panic!("no error in {}", self.text()))
            .to_owned()
    }

    /// Header `name`, as text.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.get(name).and_then(|v| v.to_str().ok())
    }
}

/// The events of an SSE body: (id, event, data as JSON), in order.
pub fn sse_events(body: &str) -> Vec<(i64, String, Value)> {
    body.split("\n\n")
        .filter(|block| !block.trim().is_empty())
        .map(|block| {
            let field = |name: &str| {
                block
                    .lines()
                    .find_map(|l| l.strip_prefix(name))
                    .unwrap_or_else(|| panic!("no {name} in {block:?}"))
                    .to_owned()
            };
            let id = field("id:").trim().parse().expect("a numeric id");
            let data = serde_json::from_str(field("data:").trim()).expect("JSON data");
            (id, field("event:").trim().to_owned(), data)
        })
        .collect()
}

/// Test `check` (an `async fn(TestServer)`) on both stores: two tests in a
/// module `name`, `sqlite` and `postgres` (the latter skipped, saying how
/// to run it, without the test cluster), each on a server with the options
/// `options` (a `fn(&mut Options)`) sets.
macro_rules! on_both_stores {
    ($name:ident, $check:ident, $options:expr) => {
        mod $name {
            use crate::api::testing::TestServer;

            #[tokio::test]
            async fn sqlite() {
                super::$check(TestServer::with($options, None)).await;
            }

            // The share of the cluster is held for the whole test (its
            // restart test waits for every share), on the test's one thread.
            #[allow(clippy::await_holding_lock)]
            #[tokio::test]
            async fn postgres() {
                let _up = crate::store::conformance::cluster();
                if let Some(server) = TestServer::postgres($options, None) {
                    super::$check(server).await;
                }
            }
        }
    };
}
pub(crate) use on_both_stores;
