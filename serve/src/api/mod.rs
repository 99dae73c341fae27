//! The HTTP API: one module per route group, each with its `router()`,
//! merged here into the service's router with its layers (the token in
//! front of the API and `/metrics`, the body limit, a log line per
//! request) and the JSON fallbacks.
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

use std::sync::Arc;
use std::time::Instant;

use axum::Router;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::middleware::{self, Next};
use axum::response::Response;

use super::Shared;
use error::ApiError;

/// Largest request body (bytes): 1 MiB.
pub const MAX_BODY: usize = 1 << 20;

/// The state every handler reads.
type AppState = State<Arc<Shared>>;

/// The service's routes.
pub fn router(shared: Arc<Shared>) -> Router {
    let api = Router::new()
        .merge(jobs::router())
        .merge(events::router())
        .merge(files::router())
        .merge(page::data())
        .merge(openapi::router());
    Router::new()
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
        .method_not_allowed_fallback(error::method_not_allowed)
        .layer(DefaultBodyLimit::max(MAX_BODY))
        .layer(middleware::from_fn(log))
        .with_state(shared)
}

/// Run a blocking store or file call off the async threads.
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    tokio::task::spawn_blocking(f)
        .await
        .map_err(ApiError::internal)?
}

/// One log line per request: method, path, status, time.
async fn log(request: Request, next: Next) -> Response {
    let method = request.method().clone();
    let path = request.uri().path().to_owned();
    let start = Instant::now();
    let response = next.run(request).await;
    tracing::info!(
        %method,
        path = %path,
        status = response.status().as_u16(),
        ms = start.elapsed().as_secs_f64() * 1e3,
        "request"
    );
    response
}
