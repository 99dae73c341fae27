//! The service's own state: whether it is up (`GET /healthz`, open to
//! anyone) and its metrics in Prometheus text (`GET /metrics`, guarded).

use std::sync::Arc;

use axum::Extension;
use axum::extract::State;
use axum::http::{StatusCode, header};
use axum::response::IntoResponse;
use axum::routing::get;
use axum::{Json, Router};
use serde_json::json;

use super::error::ApiError;
use super::{AppState, blocking};
use crate::Shared;
use crate::store::Caller;

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

/// Prometheus text: jobs by state and by user, queue length, job
/// durations, GA evaluations, packed disks, leases, every worker's
/// counters. For admins only: it names every user.
async fn prometheus(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
) -> Result<impl IntoResponse, ApiError> {
    if !who.admin {
        return Err(ApiError::new(
            StatusCode::FORBIDDEN,
            "the metrics are for admins: they count every user's jobs",
        ));
    }
    let text = blocking(move || {
        let counts = shared.store.counts()?;
        let users = shared.store.counts_by_user()?;
        let workers = shared.store.workers()?;
        Ok(shared.metrics.render(&crate::metrics::Stored {
            counts: &counts,
            users: &users,
            workers: &workers,
        }))
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

#[cfg(test)]
mod tests {
    use std::sync::atomic::Ordering;

    use axum::http::{Method, StatusCode};
    use serde_json::json;

    use crate::api::testing::{SQUARE, TestServer};

    #[tokio::test]
    async fn metrics_count_the_jobs_in_prometheus_text() {
        let server = TestServer::new();
        let done = server.submit("?kind=pack", SQUARE).await;
        server.run_queued().await;
        let cancelled = server.submit("?kind=pack", SQUARE).await;
        server
            .call(
                Method::POST,
                &format!("/api/v1/jobs/{cancelled}/cancel"),
                &[],
            )
            .await;
        server.submit("?kind=pack", SQUARE).await;
        let r = server.get("/metrics").await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(
            r.header("content-type"),
            Some("text/plain; version=0.0.4; charset=utf-8")
        );
        let text = r.text();
        let particles =
            server.get(&format!("/api/v1/jobs/{done}")).await.json()["summary"]["particles"]
                .as_u64()
                .expect("particles");
        for line in [
            "# TYPE gapack_jobs gauge".to_owned(),
            "gapack_jobs{state=\"queued\"} 1".to_owned(),
            "gapack_jobs{state=\"succeeded\"} 1".to_owned(),
            "gapack_jobs{state=\"cancelled\"} 1".to_owned(),
            "gapack_queue_length 1".to_owned(),
            "gapack_jobs_finished_total{state=\"succeeded\"} 1".to_owned(),
            "gapack_job_duration_seconds_count 1".to_owned(),
            format!("gapack_packed_disks_total {particles}"),
        ] {
            assert!(text.lines().any(|l| l == line), "{line} in\n{text}");
        }
    }

    #[tokio::test]
    async fn health_says_ok_until_the_server_stops() {
        let server = TestServer::new();
        let r = server.get("/healthz").await;
        assert_eq!(
            (r.status, r.json()),
            (StatusCode::OK, json!({"status": "ok"}))
        );
        server.shared.stopping.store(true, Ordering::SeqCst);
        let r = server.get("/healthz").await;
        assert_eq!(
            (r.status, r.json()),
            (
                StatusCode::SERVICE_UNAVAILABLE,
                json!({"status": "stopping"})
            )
        );
    }
}
