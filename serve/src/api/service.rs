//! The service's own state: whether it is up (`GET /healthz`, open to
//! anyone) and its metrics in Prometheus text (`GET /metrics`, guarded).

use std::sync::Arc;

use axum::extract::State;
use axum::http::{StatusCode, header};
use axum::response::IntoResponse;
use axum::routing::get;
use axum::{Json, Router};
use serde_json::json;

use super::error::ApiError;
use super::{AppState, blocking};
use crate::Shared;

/// `/healthz` (open).
pub fn health() -> Router<Arc<Shared>> {
    Router::new().route("/healthz", get(healthz))
}

/// `/metrics` (guarded).
pub fn metrics() -> Router<Arc<Shared>> {
    Router::new().route("/metrics", get(prometheus))
}

/// Whether the server is up: 200 `ok`, or 503 `stopping` once a stop
/// signal came.
async fn healthz(State(shared): AppState) -> impl IntoResponse {
    if shared.stopping.load(std::sync::atomic::Ordering::SeqCst) {
        (
            StatusCode::SERVICE_UNAVAILABLE,
            Json(json!({"status": "stopping"})),
        )
    } else {
        (StatusCode::OK, Json(json!({"status": "ok"})))
    }
}

/// Prometheus text: jobs by state, queue length, job durations, GA
/// evaluations, packed disks.
async fn prometheus(State(shared): AppState) -> Result<impl IntoResponse, ApiError> {
    let text = blocking(move || {
        let counts = shared.db.counts()?;
        Ok(shared.metrics.render(&counts))
    })
    .await?;
    Ok((
        [(
            header::CONTENT_TYPE,
            "text/plain; version=0.0.4; charset=utf-8",
        )],
        text,
    ))
}
