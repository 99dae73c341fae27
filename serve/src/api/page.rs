//! The web page and what it draws: the page and its assets (`/`,
//! `/app.js`, `/app.css`, open to anyone: they hold no data), a finished
//! job's packing as columns (`GET /jobs/{id}/packing`) and the shipped
//! example configs (`GET /examples`).

use std::sync::Arc;

use axum::extract::State;
use axum::http::StatusCode;
use axum::routing::get;
use axum::{Json, Router};
use gapack::jobs::{JobKind, Plan, Request as JobRequest};
use serde::Serialize;
use utoipa::ToSchema;

use super::error::{ApiError, ErrorBody};
use super::files::manifest;
use super::jobs::JobId;
use super::{AppState, blocking};
use crate::Shared;
use crate::web;
use crate::worker::{ORIGIN, job_dir};

/// The API routes of the page's data (under `/api/v1`, guarded).
pub fn data() -> Router<Arc<Shared>> {
    Router::new()
        .route("/jobs/{id}/packing", get(packing))
        .route("/examples", get(examples))
}

/// The page and its assets (open).
pub fn web() -> Router<Arc<Shared>> {
    Router::new()
        .route("/", get(web::index))
        .route("/app.js", get(web::script))
        .route("/app.css", get(web::style))
}

/// A finished job's packing, for drawing: the domain's outline and the
/// disks as columns.
#[derive(Debug, Serialize, ToSchema)]
pub struct PackingView {
    /// The domain's boundary, a closed polyline (mm; circles as 256 segments).
    outline: Vec<[f64; 2]>,
    /// Lower-left and upper-right corners of the domain's bounding box (mm).
    bounds: [[f64; 2]; 2],
    /// Centres and radii (mm), in `packing.csv`'s order (`id` is the index).
    x: Vec<f64>,
    y: Vec<f64>,
    r: Vec<f64>,
    /// Per disk, an index into `materials`; empty without materials.
    material: Vec<u16>,
    /// Material names.
    materials: Vec<String>,
}

/// Segments per circle in a drawn outline.
const OUTLINE_SEGMENTS: usize = 256;

/// The packing of a finished job that wrote `packing.csv`, as columns.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/packing", params(("id" = String, Path, description = "Job id")),
    responses((status = 200, body = PackingView), (status = 404, body = ErrorBody), (status = 409, description = "Not finished", body = ErrorBody)))]
async fn packing(State(shared): AppState, JobId(id): JobId) -> Result<Json<PackingView>, ApiError> {
    let view = blocking(move || {
        let manifest = manifest(&shared, &id)?;
        if !manifest.files.iter().any(|f| f == "packing.csv") {
            return Err(ApiError::new(
                StatusCode::NOT_FOUND,
                format!("job {id} wrote no packing.csv"),
            ));
        }
        let row = shared
            .db
            .get(&id)?
            .ok_or_else(|| ApiError::unknown_job(&id))?;
        let text = std::fs::read_to_string(job_dir(&shared, &id).join("packing.csv"))
            .map_err(ApiError::internal)?;
        let table =
            gapack::output::read_packing_csv(&text, "packing.csv").map_err(ApiError::internal)?;
        let request = JobRequest {
            seed: row.seed,
            ..JobRequest::new(JobKind::Pack)
        };
        let plan = Plan::load(&row.config, ORIGIN, &request)?;
        let domain = &plan.config.scene.domain;
        let (lo, hi) = domain.bounds();
        Ok(PackingView {
            outline: domain
                .outline(OUTLINE_SEGMENTS)
                .iter()
                .map(|p| [p.x, p.y])
                .collect(),
            bounds: [[lo.x, lo.y], [hi.x, hi.y]],
            x: table.disks.iter().map(|d| d.c.x).collect(),
            y: table.disks.iter().map(|d| d.c.y).collect(),
            r: table.disks.iter().map(|d| d.r).collect(),
            material: table.materials,
            materials: table.material_names,
        })
    })
    .await?;
    Ok(Json(view))
}

/// A shipped example config.
#[derive(Debug, Serialize, ToSchema)]
pub struct Example {
    /// Its name (the file stem under `configs/`).
    name: &'static str,
    /// Its text.
    config: &'static str,
}

/// The shipped example configs, the default scene first.
#[utoipa::path(get, path = "/api/v1/examples", responses((status = 200, body = Vec<Example>)))]
async fn examples() -> Json<Vec<Example>> {
    Json(
        web::EXAMPLES
            .iter()
            .map(|&(name, config)| Example { name, config })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use axum::http::StatusCode;

    use crate::api::testing::TestServer;
    use crate::web::EXAMPLES;

    #[tokio::test]
    async fn the_page_and_its_assets_are_served_revalidated() {
        let server = TestServer::new();
        for (path, kind, text) in [
            (
                "/",
                "text/html; charset=utf-8",
                include_str!("../web/index.html"),
            ),
            (
                "/app.js",
                "text/javascript; charset=utf-8",
                include_str!("../web/app.js"),
            ),
            (
                "/app.css",
                "text/css; charset=utf-8",
                include_str!("../web/app.css"),
            ),
        ] {
            let r = server.get(path).await;
            assert_eq!(r.status, StatusCode::OK, "{path}");
            assert_eq!(r.header("content-type"), Some(kind), "{path}");
            assert_eq!(r.header("cache-control"), Some("no-cache"), "{path}");
            assert_eq!(r.text(), text, "{path}");
        }
    }

    #[tokio::test]
    async fn the_examples_are_the_shipped_configs_default_first() {
        let server = TestServer::new();
        let r = server.get("/api/v1/examples").await;
        assert_eq!(r.status, StatusCode::OK);
        let examples = r.json();
        let examples = examples.as_array().expect("a list");
        assert_eq!(examples.len(), EXAMPLES.len());
        assert_eq!(examples[0]["name"], "default");
        for (got, (name, config)) in examples.iter().zip(EXAMPLES) {
            assert_eq!(
                (&got["name"], &got["config"]),
                (&(*name).into(), &(*config).into())
            );
        }
    }
}
