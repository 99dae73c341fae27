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
use gapack::{Grain, Outline};
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
/// disks as columns; for particles that are not disks, their outlines too.
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
    /// Particles that are not disks (`packing.csv` with an `angle` column):
    /// each one's outline, as columns in the same order; absent for disks
    /// (`r` is then each particle's area-equivalent radius).
    #[serde(skip_serializing_if = "Option::is_none")]
    shapes: Option<ShapesView>,
}

/// The outlines of a packing's particles that are not disks, as columns of
/// one value per particle (in `packing.csv`'s order), as `packing.csv`
/// gives them: a superellipse |x'/a|^alpha + |y'/b|^beta <= 1 or a convex
/// polygon rounded by a disk of radius `rounding`, in the particle's own
/// axes (x', y') about its centre, turned by `angle`. A family's columns are
/// absent when no particle is of it, and null for a particle of the other.
#[derive(Debug, Serialize, ToSchema)]
#[schema(as = PackingShapes)]
pub struct ShapesView {
    /// Radians, counter-clockwise from the x axis to the particle's own x' axis.
    angle: Vec<f64>,
    /// Superellipses: semi-axis along x' (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    a: Option<Vec<Option<f64>>>,
    /// Superellipses: semi-axis along y' (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    b: Option<Vec<Option<f64>>>,
    /// Superellipses: exponent of x' (>= 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    alpha: Option<Vec<Option<f64>>>,
    /// Superellipses: exponent of y' (>= 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    beta: Option<Vec<Option<f64>>>,
    /// Rounded polygons: the index of the config's template.
    #[serde(skip_serializing_if = "Option::is_none")]
    template: Option<Vec<Option<u16>>>,
    /// Rounded polygons: the corner radius (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    rounding: Option<Vec<Option<f64>>>,
    /// Rounded polygons: the vertices (mm) in the particle's own axes,
    /// counter-clockwise about its centroid (the particle's centre).
    #[serde(skip_serializing_if = "Option::is_none")]
    vertices: Option<Vec<Option<Vec<[f64; 2]>>>>,
}

impl ShapesView {
    /// The columns of `grains`; `None` for none (a packing of disks).
    fn of(grains: &[Grain]) -> Option<Self> {
        /// A family's column: empty, or `None` when no particle is of it.
        fn column<T>(present: bool, n: usize) -> Option<Vec<Option<T>>> {
            present.then(|| Vec::with_capacity(n))
        }
        /// The next particle's cell of a column that is present.
        fn push<T>(column: &mut Option<Vec<Option<T>>>, cell: Option<T>) {
            if let Some(c) = column {
                c.push(cell);
            }
        }
        if grains.is_empty() {
            return None;
        }
        let n = grains.len();
        let se = grains
            .iter()
            .any(|g| matches!(g.outline, Outline::Superellipse { .. }));
        let poly = grains
            .iter()
            .any(|g| matches!(g.outline, Outline::Polygon { .. }));
        let mut view = ShapesView {
            angle: Vec::with_capacity(n),
            a: column(se, n),
            b: column(se, n),
            alpha: column(se, n),
            beta: column(se, n),
            template: column(poly, n),
            rounding: column(poly, n),
            vertices: column(poly, n),
        };
        for g in grains {
            view.angle.push(g.angle);
            let (superellipse, polygon) = match &g.outline {
                Outline::Superellipse { a, b, alpha, beta } => {
                    (Some([*a, *b, *alpha, *beta]), None)
                }
                Outline::Polygon {
                    template,
                    vertices,
                    rounding,
                } => (None, Some((*template, *rounding, vertices))),
            };
            push(&mut view.a, superellipse.map(|s| s[0]));
            push(&mut view.b, superellipse.map(|s| s[1]));
            push(&mut view.alpha, superellipse.map(|s| s[2]));
            push(&mut view.beta, superellipse.map(|s| s[3]));
            push(&mut view.template, polygon.map(|p| p.0));
            push(&mut view.rounding, polygon.map(|p| p.1));
            push(
                &mut view.vertices,
                polygon.map(|p| p.2.iter().map(|v| [v.x, v.y]).collect()),
            );
        }
        Some(view)
    }
}

/// Segments per circle in a drawn outline.
const OUTLINE_SEGMENTS: usize = 256;

/// The packing of a finished job that wrote `packing.csv`, as columns.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/packing", params(super::jobs::IdParam),
    responses(
        (status = 200, description = "The packing as columns", body = PackingView),
        (status = 400, description = "An id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job, or it wrote no packing.csv", body = ErrorBody),
        (status = 409, description = "Not finished", body = ErrorBody),
    ))]
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
        // Planned only for its domain: the job ran, so the ceilings and
        // [limits] it was forced past are not asked again.
        let request = JobRequest {
            seed: row.seed,
            force: true,
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
            shapes: ShapesView::of(&table.grains),
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
#[utoipa::path(get, path = "/api/v1/examples",
    responses((status = 200, description = "The examples, the default scene first", body = Vec<Example>)))]
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

    use crate::api::testing::{SQUARE, TestServer};
    use crate::web::EXAMPLES;

    #[tokio::test]
    async fn the_packing_of_a_job_forced_past_a_limit_is_shown() {
        let server = TestServer::with(|o| o.force = true, None);
        // Refused before the run (the square could hold about 510), packed
        // whole (about 170).
        let config = format!("{SQUARE}[limits]\nmax_particles = 300\n");
        let id = server.submit("?kind=pack&force=true", &config).await;
        server.run_queued().await;
        let r = server.get(&format!("/api/v1/jobs/{id}/packing")).await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        assert!(r.json()["x"].as_array().is_some_and(|x| x.len() > 10));
    }

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

    #[test]
    fn a_packing_of_both_families_gives_each_particle_its_own_columns() {
        use gapack::{Grain, Outline, Point};

        use super::ShapesView;

        assert!(ShapesView::of(&[]).is_none(), "disks: no shapes");
        let ellipse = Outline::superellipse(1.5, 1.0, 2.0, 3.0).expect("a superellipse");
        let triangle = Outline::polygon(
            2,
            &[
                Point::new(-1.0, -1.0),
                Point::new(2.0, -1.0),
                Point::new(-1.0, 2.0),
            ],
            0.25,
        )
        .expect("a polygon");
        let both = [Grain::new(ellipse.clone(), 0.5), Grain::new(triangle, -1.0)];
        let view = serde_json::to_value(ShapesView::of(&both)).expect("JSON");
        assert_eq!(
            view,
            serde_json::json!({
                "angle": [0.5, -1.0],
                "a": [1.5, null],
                "b": [1.0, null],
                "alpha": [2.0, null],
                "beta": [3.0, null],
                "template": [null, 2],
                "rounding": [null, 0.25],
                "vertices": [null, [[-1.0, -1.0], [2.0, -1.0], [-1.0, 2.0]]],
            })
        );
        // One family: the other's columns are left out.
        let view = serde_json::to_value(ShapesView::of(&[Grain::new(ellipse, 0.0)])).expect("JSON");
        let keys: Vec<&str> = view
            .as_object()
            .expect("an object")
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(keys, ["a", "alpha", "angle", "b", "beta"]);
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
