//! The jobs: submit (`POST /jobs`), check without running (`POST
//! /validate`), list (`GET /jobs`), read (`GET /jobs/{id}`), cancel
//! (`POST /jobs/{id}/cancel`) and delete (`DELETE /jobs/{id}`); and
//! [`JobId`], the checked id every `/jobs/{id}` route extracts.

use std::sync::Arc;

use axum::Extension;
use axum::extract::rejection::QueryRejection;
use axum::extract::{FromRequestParts, Path, Query, State};
use axum::http::request::Parts;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use gapack::jobs::Summary;
use gapack::{AskedFamily, AskedOrientation, Figures, ShapeStats};
use rand::RngCore;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::{IntoParams, ToSchema};

use super::error::{ApiError, ErrorBody};
use super::submission::{Estimates, Submission, SubmitBody, SubmitQuery, bad_query};
use super::{AppState, blocking};
use crate::Shared;
use crate::store::{Caller, CancelOutcome, JobRow, NewJob, Role, State as JobState};
use crate::worker::job_dir;

/// The routes of the jobs themselves.
pub fn router() -> Router<Arc<Shared>> {
    Router::new()
        .route("/jobs", post(submit).get(list))
        .route("/validate", post(validate))
        .route("/jobs/{id}", get(status).delete(delete))
        .route("/jobs/{id}/cancel", post(cancel))
        .route("/me", get(me))
}

/// Who the request's token signs in as.
#[derive(Debug, Serialize, ToSchema)]
pub struct Me {
    /// The user's name.
    name: String,
    /// `admin` sees every job; `user` their own.
    role: Role,
}

/// Who is signed in: the user the request's token names (`admin` on a
/// server with no token).
#[utoipa::path(get, path = "/api/v1/me",
    responses((status = 200, description = "The signed-in user", body = Me)))]
async fn me(Extension(who): Extension<Caller>) -> Json<Me> {
    Json(Me {
        role: if who.admin { Role::Admin } else { Role::User },
        name: who.name,
    })
}

/// The `{id}` of a `/jobs/{id}…` route, checked to be one this service
/// could have made (32 lowercase hex digits), so that nothing else reaches
/// the store or a path: any other is an unknown job (404).
pub struct JobId(pub String);

/// The path parameter a [`JobId`] is read from (others are ignored), as
/// the document describes it.
#[derive(Deserialize, IntoParams)]
#[into_params(parameter_in = Path)]
pub struct IdParam {
    /// The job's id, as `POST /api/v1/jobs` gave it: 32 lowercase hex
    /// digits (any other is no job: 404).
    #[param(pattern = "^[0-9a-f]{32}$")]
    id: String,
}

impl<S: Send + Sync> FromRequestParts<S> for JobId {
    type Rejection = Response;

    async fn from_request_parts(parts: &mut Parts, state: &S) -> Result<Self, Response> {
        let Path(IdParam { id }) = Path::from_request_parts(parts, state)
            .await
            .map_err(IntoResponse::into_response)?;
        let hex = |b: u8| b.is_ascii_digit() || (b'a'..=b'f').contains(&b);
        if id.len() == 32 && id.bytes().all(hex) {
            Ok(JobId(id))
        } else {
            Err(ApiError::unknown_job(&id).into_response())
        }
    }
}

/// A new job's id: 128 random bits, as hex.
fn new_id() -> String {
    let mut bytes = [0u8; 16];
    rand::rngs::OsRng.fill_bytes(&mut bytes);
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Where a job's resources are.
#[derive(Debug, Serialize, ToSchema)]
pub struct Links {
    /// The job (`GET`, `DELETE`).
    #[serde(rename = "self")]
    this: String,
    /// Its event stream (SSE).
    events: String,
    /// Its files.
    files: String,
    /// Cancel it (`POST`).
    cancel: String,
}

impl Links {
    /// Job `id`'s links.
    fn of(id: &str) -> Self {
        let base = format!("/api/v1/jobs/{id}");
        Links {
            events: format!("{base}/events"),
            files: format!("{base}/files"),
            cancel: format!("{base}/cancel"),
            this: base,
        }
    }
}

/// A job accepted.
#[derive(Debug, Serialize, ToSchema)]
pub struct Accepted {
    /// Its id.
    id: String,
    /// Its kind.
    kind: String,
    /// `queued`.
    state: JobState,
    /// Its seed.
    seed: u64,
    /// Where to follow it.
    urls: Links,
}

/// Submit a job.
///
/// The body is the TOML config (`Content-Type: application/toml`, kind and
/// seed as query parameters) or JSON (`{kind, config, seed}`).
#[utoipa::path(post, path = "/api/v1/jobs", params(SubmitQuery),
    request_body(description = "The config as TOML text (kind, seed and force as query parameters), or this JSON",
        content(
            (String = "application/toml"),
            (SubmitBody = "application/json"),
        )),
    responses(
        (status = 201, description = "Queued", body = Accepted,
            headers(("Location" = String, description = "The job's URL")),
            links(
                ("status" = (operation_id = "status", parameters(("id" = "$response.body#/id")), description = "Read the job")),
                ("events" = (operation_id = "events", parameters(("id" = "$response.body#/id")), description = "Follow its events")),
                ("files" = (operation_id = "files", parameters(("id" = "$response.body#/id")), description = "List its files once finished")),
                ("packing" = (operation_id = "packing", parameters(("id" = "$response.body#/id")), description = "Its packing once finished")),
                ("cancel" = (operation_id = "cancel", parameters(("id" = "$response.body#/id")), description = "Cancel it")),
                ("delete" = (operation_id = "delete", parameters(("id" = "$response.body#/id")), description = "Delete it once finished")),
            )),
        (status = 400, description = "Bad query, JSON, job kind, or a config that is not UTF-8", body = ErrorBody),
        (status = 403, description = "`force` asked of a server not started with --force", body = ErrorBody),
        (status = 413, description = "Body over 1 MiB", body = ErrorBody),
        (status = 415, description = "Neither TOML nor JSON", body = ErrorBody),
        (status = 422, description = "Bad config, or over the server's or the user's ceilings", body = ErrorBody),
        (status = 429, description = "The user has as many jobs waiting as a user may", body = ErrorBody),
        (status = 503, description = "Queue full or server stopping", body = ErrorBody,
            headers(("Retry-After" = u64, description = "Seconds to wait before trying again"))),
    ))]
async fn submit(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    s: Submission,
) -> Result<impl IntoResponse, ApiError> {
    if shared.stopping.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(
            ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the server is stopping")
                .retry_after(10),
        );
    }
    let id = new_id();
    let accepted = blocking({
        let shared = Arc::clone(&shared);
        let id = id.clone();
        move || {
            let plan = s.plan(&shared, &who)?;
            shared.store.insert(
                &NewJob {
                    id: &id,
                    owner: &who,
                    kind: plan.kind.name(),
                    config: &s.config,
                    seed: s.seed,
                    force: s.force,
                    checkpoint_every: i64::try_from(shared.limits.checkpoint_every)
                        .unwrap_or(i64::MAX),
                },
                shared.limits.queue,
            )?;
            Ok(Accepted {
                kind: plan.kind.name().to_owned(),
                state: JobState::Queued,
                seed: plan.seed(),
                urls: Links::of(&id),
                id: id.clone(),
            })
        }
    })
    .await?;
    shared.wake_worker();
    tracing::info!(job = %id, kind = %accepted.kind, state = "queued", "job state");
    let mut response = (StatusCode::CREATED, Json(&accepted)).into_response();
    if let Ok(value) = HeaderValue::from_str(&accepted.urls.this) {
        response.headers_mut().insert(header::LOCATION, value);
    }
    Ok(response)
}

/// What a job would do, without running it.
#[derive(Debug, Serialize, ToSchema)]
pub struct Validated {
    /// The job kind.
    kind: String,
    /// The seed it would run with.
    seed: u64,
    /// The run's identity (config text and seed).
    identity: String,
    /// The plan in words, as `gapack validate` prints it.
    plan: Vec<String>,
    /// Tables the job would ignore.
    warnings: Vec<String>,
    /// Estimates for the first scene.
    estimates: Estimates,
}

/// Check a config and return the plan and estimates, without running it.
#[utoipa::path(post, path = "/api/v1/validate", params(SubmitQuery),
    request_body(description = "As for POST /api/v1/jobs",
        content(
            (String = "application/toml"),
            (SubmitBody = "application/json"),
        )),
    responses(
        (status = 200, description = "Valid: the plan and estimates", body = Validated),
        (status = 400, description = "Bad query, JSON, job kind, or a config that is not UTF-8", body = ErrorBody),
        (status = 403, description = "`force` asked of a server not started with --force", body = ErrorBody),
        (status = 413, description = "Body over 1 MiB", body = ErrorBody),
        (status = 415, description = "Neither TOML nor JSON", body = ErrorBody),
        (status = 422, description = "Bad config, or over the server's ceilings", body = ErrorBody),
    ))]
async fn validate(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    s: Submission,
) -> Result<Json<Validated>, ApiError> {
    let validated = blocking(move || {
        let plan = s.plan(&shared, &who)?;
        Ok(Validated {
            kind: plan.kind.name().to_owned(),
            seed: plan.seed(),
            identity: plan.identity.clone(),
            plan: plan.describe("jobs/<id>"),
            warnings: plan.warnings.iter().map(|w| w.message.clone()).collect(),
            estimates: Estimates::of(&plan),
        })
    })
    .await?;
    Ok(Json(validated))
}

/// A job.
#[derive(Debug, Serialize, ToSchema)]
pub struct JobView {
    /// Its id.
    id: String,
    /// Its kind.
    kind: String,
    /// The user who submitted it.
    owner: String,
    /// The seed asked for (the config's own when absent).
    seed: Option<u64>,
    /// The config it runs, as submitted.
    config: String,
    /// Its state.
    state: JobState,
    /// Attempts started (more than one after a restart).
    attempts: i64,
    /// Whether a cancel was asked for while it ran.
    cancel_requested: bool,
    /// Submitted (ms since the Unix epoch).
    created_ms: i64,
    /// Last attempt started.
    started_ms: Option<i64>,
    /// Finished.
    finished_ms: Option<i64>,
    /// The last progress event (stage, generation with best and mean porosity).
    #[schema(value_type = Option<Object>)]
    progress: Option<Value>,
    /// When finished: the result in words, its files, particles, porosity.
    summary: Option<SummaryView>,
    /// Why it failed.
    error: Option<String>,
    /// Where its resources are.
    urls: Links,
}

/// A finished job's summary: the library's [`Summary`] (which the workers
/// store) as the API serves and documents it, field for field.
#[derive(Debug, Serialize, ToSchema)]
#[schema(as = Summary)]
pub struct SummaryView {
    /// `optimise`: the porosity of the best packing.
    #[serde(skip_serializing_if = "Option::is_none")]
    best_porosity: Option<f64>,
    /// `optimise`: packings made by the search.
    #[serde(skip_serializing_if = "Option::is_none")]
    evaluations: Option<u64>,
    /// Every file of the run, `manifest.json` included.
    files: Vec<String>,
    /// `optimise`: generations run.
    #[serde(skip_serializing_if = "Option::is_none")]
    generations: Option<usize>,
    /// Whether the job was cancelled and holds only what it finished.
    interrupted: bool,
    /// The result in words, the job's folder named `jobs/<id>`.
    lines: Vec<String>,
    /// Particles that are not disks (`pack`, `layer`, `optimise`): their
    /// shape measures, as `summary.json`'s `particle_shape`.
    #[serde(skip_serializing_if = "Option::is_none")]
    particle_shape: Option<ShapeView>,
    /// Disks of the packing (of every well, for a `[fracture]` run).
    #[serde(skip_serializing_if = "Option::is_none")]
    particles: Option<usize>,
    /// The packing's porosity (`pack`, `layer`, `optimise`).
    #[serde(skip_serializing_if = "Option::is_none")]
    porosity: Option<f64>,
    /// `optimise`: the porosity aimed at.
    #[serde(skip_serializing_if = "Option::is_none")]
    target_porosity: Option<f64>,
}

impl From<Summary> for SummaryView {
    fn from(s: Summary) -> Self {
        SummaryView {
            best_porosity: s.best_porosity,
            evaluations: s.evaluations,
            files: s.files,
            generations: s.generations,
            interrupted: s.interrupted,
            lines: s.lines,
            particle_shape: s.particle_shape.map(ShapeView::from),
            particles: s.particles,
            porosity: s.porosity,
            target_porosity: s.target_porosity,
        }
    }
}

/// The shape measures of a packing of particles that are not disks: the
/// library's [`ShapeStats`] as the API serves and documents it, field for
/// field.
#[derive(Debug, Serialize, ToSchema)]
#[schema(as = ShapeStats)]
pub struct ShapeView {
    /// What the config's `[shape]` asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    asked: Option<AskedView>,
    /// Aspect ratio: greatest over least width (≥ 1).
    aspect: FiguresView,
    /// Orientation of the particles' long axes: the fabric tensor.
    fabric: FabricView,
    /// Mean diameter of the disk of the same area (mm).
    mean_equivalent_diameter: f64,
    /// Mean least width (mm): the sieve size.
    mean_least_width: f64,
    /// Particles measured.
    particles: usize,
    /// Wadell's roundness: mean corner radius over the inscribed radius, in [0, 1].
    roundness: FiguresView,
    /// The size the grading gave: `sieve` (least width) or `equivalent`
    /// (area-equivalent diameter).
    #[serde(skip_serializing_if = "Option::is_none")]
    size_measure: Option<&'static str>,
    /// Riley's sphericity √(D_inscribed / D_enclosing), in (0, 1].
    sphericity: FiguresView,
}

/// One measure over a packing's particles.
#[derive(Debug, Serialize, ToSchema)]
#[schema(as = ShapeFigures)]
pub struct FiguresView {
    /// Greatest value.
    max: f64,
    /// Mean.
    mean: f64,
    /// Least value.
    min: f64,
    /// Sample standard deviation.
    sd: f64,
}

/// The fabric tensor F = mean of n⊗n over the particles' long axes.
#[derive(Debug, Serialize, ToSchema)]
#[schema(as = Fabric)]
pub struct FabricView {
    /// λ1 − λ2: 0 with no preferred direction, 1 all aligned.
    anisotropy: f64,
    /// Principal direction (degrees counter-clockwise from x, in [0, 180)).
    direction: f64,
    /// Eigenvalues, greatest first.
    eigenvalues: [f64; 2],
    /// [F_xx, F_xy, F_yy].
    tensor: [f64; 3],
}

/// What a config's `[shape]` asked.
#[derive(Debug, Serialize, ToSchema)]
#[schema(as = ShapeAsked)]
pub struct AskedView {
    /// Superellipses: least and greatest exponent α.
    #[serde(skip_serializing_if = "Option::is_none")]
    alpha: Option<[f64; 2]>,
    /// Superellipses: least and greatest aspect a/b.
    #[serde(skip_serializing_if = "Option::is_none")]
    aspect: Option<[f64; 2]>,
    /// Superellipses: least and greatest exponent β.
    #[serde(skip_serializing_if = "Option::is_none")]
    beta: Option<[f64; 2]>,
    /// `superellipse` or `polygons`.
    family: &'static str,
    /// `random` or `aligned`.
    orientation: &'static str,
    /// Aligned: the mean angle (degrees).
    #[serde(skip_serializing_if = "Option::is_none")]
    orientation_mean: Option<f64>,
    /// Aligned: the standard deviation of the angle (degrees).
    #[serde(skip_serializing_if = "Option::is_none")]
    orientation_spread: Option<f64>,
    /// Polygons: how many templates.
    #[serde(skip_serializing_if = "Option::is_none")]
    templates: Option<usize>,
}

impl From<ShapeStats> for ShapeView {
    fn from(s: ShapeStats) -> Self {
        let figures = |f: Figures| FiguresView {
            max: f.max,
            mean: f.mean,
            min: f.min,
            sd: f.sd,
        };
        ShapeView {
            asked: s.asked.map(|a| AskedView {
                alpha: a.alpha,
                aspect: a.aspect,
                beta: a.beta,
                family: match a.family {
                    AskedFamily::Superellipse => "superellipse",
                    AskedFamily::Polygons => "polygons",
                },
                orientation: match a.orientation {
                    AskedOrientation::Random => "random",
                    AskedOrientation::Aligned => "aligned",
                },
                orientation_mean: a.orientation_mean,
                orientation_spread: a.orientation_spread,
                templates: a.templates,
            }),
            aspect: figures(s.aspect),
            fabric: FabricView {
                anisotropy: s.fabric.anisotropy,
                direction: s.fabric.direction,
                eigenvalues: s.fabric.eigenvalues,
                tensor: s.fabric.tensor,
            },
            mean_equivalent_diameter: s.mean_equivalent_diameter,
            mean_least_width: s.mean_least_width,
            particles: s.particles,
            roundness: figures(s.roundness),
            size_measure: s.size_measure.map(|m| m.name()),
            sphericity: figures(s.sphericity),
        }
    }
}

impl From<JobRow> for JobView {
    fn from(row: JobRow) -> Self {
        let json = |s: Option<String>| s.and_then(|s| serde_json::from_str(&s).ok());
        JobView {
            urls: Links::of(&row.id),
            id: row.id,
            kind: row.kind,
            owner: row.owner,
            seed: row.seed,
            config: row.config,
            state: row.state,
            attempts: row.attempts,
            cancel_requested: row.cancel_requested,
            created_ms: row.created_ms,
            started_ms: row.started_ms,
            finished_ms: row.finished_ms,
            progress: json(row.progress),
            summary: row
                .summary
                .and_then(|s| Summary::from_json(&s).ok())
                .map(SummaryView::from),
            error: row.error,
        }
    }
}

/// A job's state, progress, timings, and its summary or error.
#[utoipa::path(get, path = "/api/v1/jobs/{id}", params(IdParam),
    responses(
        (status = 200, description = "The job", body = JobView),
        (status = 400, description = "An id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
async fn status(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
) -> Result<Json<JobView>, ApiError> {
    let row = blocking(move || {
        shared
            .store
            .get(&who, &id)?
            .ok_or_else(|| ApiError::unknown_job(&id))
    })
    .await?;
    Ok(Json(row.into()))
}

/// Paging and filter of the job list.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ListQuery {
    /// Only jobs in this state.
    #[param(value_type = Option<JobState>, nullable = false)]
    state: Option<String>,
    /// Jobs per page, 1 to 500 [default 50].
    #[param(nullable = false, minimum = 1, maximum = 500)]
    limit: Option<usize>,
    /// The `next` cursor of the previous page: jobs submitted before it.
    #[param(nullable = false)]
    before: Option<i64>,
}

/// A page of jobs, newest first.
#[derive(Debug, Serialize, ToSchema)]
pub struct JobPage {
    /// The jobs.
    jobs: Vec<JobView>,
    /// The next page's URL, if there may be one.
    next: Option<String>,
}

/// The jobs, newest first, paged, filtered by state.
#[utoipa::path(get, path = "/api/v1/jobs", params(ListQuery),
    responses(
        (status = 200, description = "A page of jobs", body = JobPage),
        (status = 400, description = "Bad query: an unknown state, a limit out of range", body = ErrorBody),
    ))]
async fn list(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    query: Result<Query<ListQuery>, QueryRejection>,
) -> Result<Json<JobPage>, ApiError> {
    let Query(q) = query.map_err(bad_query)?;
    let state = match q.state.as_deref() {
        None => None,
        Some(name) => Some(JobState::parse(name).ok_or_else(|| {
            ApiError::bad_request(format!(
                "unknown state {name:?}; valid: queued, running, succeeded, failed, cancelled"
            ))
        })?),
    };
    let limit = q.limit.unwrap_or(50);
    if !(1..=500).contains(&limit) {
        return Err(ApiError::bad_request(format!(
            "limit must be 1 to 500, got {limit}"
        )));
    }
    let rows = blocking(move || Ok(shared.store.list(&who, state, q.before, limit)?)).await?;
    let next = (rows.len() == limit).then(|| {
        let last = rows.last().map_or(0, |r| r.seq);
        let mut url = format!("/api/v1/jobs?limit={limit}&before={last}");
        if let Some(state) = state {
            url += &format!("&state={}", state.name());
        }
        url
    });
    Ok(Json(JobPage {
        jobs: rows.into_iter().map(JobView::from).collect(),
        next,
    }))
}

/// Cancel a job (idempotent): a queued one at once; a running one stops
/// at its next check and keeps what it finished (an optimise its best packing).
#[utoipa::path(post, path = "/api/v1/jobs/{id}/cancel", params(IdParam),
    responses(
        (status = 200, description = "Cancelled, or already finished", body = JobView),
        (status = 202, description = "Running: stopping at its next check", body = JobView),
        (status = 400, description = "An id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
async fn cancel(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
) -> Result<impl IntoResponse, ApiError> {
    let (outcome, row) = blocking({
        let shared = Arc::clone(&shared);
        let id = id.clone();
        move || {
            let outcome = shared
                .store
                .cancel(&who, &id)?
                .ok_or_else(|| ApiError::unknown_job(&id))?;
            if outcome == CancelOutcome::Stopping {
                shared.cancel_running(&id);
            }
            let row = shared
                .store
                .get(&who, &id)?
                .ok_or_else(|| ApiError::unknown_job(&id))?;
            Ok((outcome, row))
        }
    })
    .await?;
    let status = match outcome {
        CancelOutcome::Stopping => StatusCode::ACCEPTED,
        CancelOutcome::Dequeued => {
            tracing::info!(job = %id, state = "cancelled", "job state");
            shared.notify(&id);
            StatusCode::OK
        }
        CancelOutcome::Finished(_) => StatusCode::OK,
    };
    Ok((status, Json(JobView::from(row))))
}

/// Delete a finished job and its files.
#[utoipa::path(delete, path = "/api/v1/jobs/{id}", params(IdParam),
    responses(
        (status = 204, description = "Deleted"),
        (status = 400, description = "An id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job", body = ErrorBody),
        (status = 409, description = "Not finished: cancel it first", body = ErrorBody),
    ))]
async fn delete(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
) -> Result<StatusCode, ApiError> {
    let dir = job_dir(&shared, &id);
    blocking(move || match shared.store.delete(&who, &id)? {
        None => Err(ApiError::unknown_job(&id)),
        Some(Err(state)) => Err(ApiError::new(
            StatusCode::CONFLICT,
            format!(
                "job {id} is {}: cancel it, then delete it once it has stopped",
                state.name()
            ),
        )),
        Some(Ok(())) => {
            if let Err(e) = std::fs::remove_dir_all(&dir)
                && e.kind() != std::io::ErrorKind::NotFound
            {
                tracing::warn!(job = %id, error = %e, "cannot remove the job's files");
            }
            tracing::info!(job = %id, state = "deleted", "job state");
            Ok(())
        }
    })
    .await?;
    Ok(StatusCode::NO_CONTENT)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::Ordering;

    use axum::http::{Method, StatusCode};
    use serde_json::json;

    use crate::api::testing::{NO_JOB, SQUARE, TestServer};

    #[tokio::test]
    async fn malformed_submissions_are_refused_and_nothing_is_queued() {
        let server = TestServer::new();
        let toml = "application/toml";
        let json = "application/json";
        let huge = format!("{SQUARE}#{}\n", "x".repeat(1 << 20));
        let cases: Vec<(&str, &str, Vec<u8>, StatusCode, &str)> = vec![
            (
                "",
                "text/html",
                SQUARE.into(),
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                "Content-Type \"text/html\": send the config as application/toml",
            ),
            (
                "",
                "",
                SQUARE.into(),
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                "Content-Type missing: send",
            ),
            (
                "",
                json,
                b"{\"kind\": \"pack\"".to_vec(),
                StatusCode::BAD_REQUEST,
                "bad JSON body: ",
            ),
            (
                "",
                json,
                json!({"kind": "bake", "config": SQUARE}).to_string().into(),
                StatusCode::BAD_REQUEST,
                "unknown job kind \"bake\"; valid: ",
            ),
            (
                "?kind=bake",
                toml,
                SQUARE.into(),
                StatusCode::BAD_REQUEST,
                "unknown job kind \"bake\"; valid: ",
            ),
            // The query's kind is checked even when the JSON names one.
            (
                "?kind=bake",
                json,
                json!({"kind": "pack", "config": SQUARE}).to_string().into(),
                StatusCode::BAD_REQUEST,
                "unknown job kind \"bake\"; valid: ",
            ),
            // A property the body does not have is refused, as the
            // document's `additionalProperties: false` says.
            (
                "",
                json,
                json!({"config": SQUARE, "sede": 4}).to_string().into(),
                StatusCode::BAD_REQUEST,
                "bad JSON body: unknown field `sede`, expected one of ",
            ),
            (
                "",
                json,
                json!({"config": SQUARE, "seed": 4.5}).to_string().into(),
                StatusCode::BAD_REQUEST,
                "bad JSON body: seed 4.5: expected a whole number from 0 to ",
            ),
            (
                "",
                json,
                json!({"config": SQUARE, "seed": -1}).to_string().into(),
                StatusCode::BAD_REQUEST,
                "bad JSON body: seed -1: expected a whole number from 0 to ",
            ),
            (
                "?seed=abc",
                toml,
                SQUARE.into(),
                StatusCode::BAD_REQUEST,
                "bad query: ",
            ),
            (
                "",
                toml,
                vec![0xff, 0xfe, b'a'],
                StatusCode::BAD_REQUEST,
                "the config is not UTF-8 text",
            ),
            (
                "?kind=pack",
                toml,
                huge.into(),
                StatusCode::PAYLOAD_TOO_LARGE,
                "the request body is over the limit of 1048576 bytes (1 MiB)",
            ),
        ];
        for (query, content_type, body, status, start) in cases {
            let r = server
                .post(&format!("/api/v1/jobs{query}"), content_type, body)
                .await;
            assert_eq!(r.status, status, "{query} {content_type}: {}", r.text());
            assert!(r.error().starts_with(start), "{}", r.error());
            assert_eq!(r.header("content-type"), Some("application/json"));
        }
        assert_eq!(server.get("/api/v1/jobs").await.json()["jobs"], json!([]));
    }

    #[tokio::test]
    async fn a_json_submission_takes_its_kind_and_seed_from_the_body() {
        let server = TestServer::new();
        let body = json!({"kind": "pack", "config": SQUARE, "seed": 4}).to_string();
        let r = server
            .post("/api/v1/jobs?seed=9", "application/json", body)
            .await;
        assert_eq!(r.status, StatusCode::CREATED, "{}", r.text());
        assert_eq!(
            (&r.json()["kind"], &r.json()["seed"]),
            (&"pack".into(), &4.into())
        );
        // A whole number written as a float is that number, as in JSON
        // Schema; null is as absent.
        let body = json!({"kind": null, "config": SQUARE, "seed": 5.0, "force": null});
        let r = server
            .post("/api/v1/jobs", "application/json", body.to_string())
            .await;
        assert_eq!(r.status, StatusCode::CREATED, "{}", r.text());
        assert_eq!(
            (&r.json()["kind"], &r.json()["seed"]),
            (&"pack".into(), &5.into())
        );
        // Without a kind: the config's natural one; without a seed: its own.
        let r = server
            .post("/api/v1/jobs", "application/toml", SQUARE)
            .await;
        assert_eq!(
            (&r.json()["kind"], &r.json()["seed"]),
            (&"pack".into(), &3.into())
        );
    }

    #[tokio::test]
    async fn unknown_and_malformed_ids_are_unknown_jobs() {
        let server = TestServer::new();
        for id in [
            NO_JOB,
            "nope",
            "0123456789ABCDEF0123456789ABCDEF",
            "..",
            "0123456789abcdef0123456789abcdef0",
        ] {
            for (method, tail) in [
                (Method::GET, ""),
                (Method::DELETE, ""),
                (Method::POST, "/cancel"),
                (Method::GET, "/files"),
                (Method::GET, "/files/packing.csv"),
                (Method::GET, "/packing"),
            ] {
                let r = server
                    .call(method.clone(), &format!("/api/v1/jobs/{id}{tail}"), &[])
                    .await;
                assert_eq!(r.status, StatusCode::NOT_FOUND, "{method} {id}{tail}");
                assert_eq!(r.error(), format!("no job {id:?}"));
            }
        }
        // Not UTF-8 once decoded: the path extractor's 400.
        assert_eq!(
            server.get("/api/v1/jobs/%FF").await.status,
            StatusCode::BAD_REQUEST
        );
    }

    #[tokio::test]
    async fn the_list_pages_newest_first_and_filters_by_state() {
        let server = TestServer::new();
        let mut ids = Vec::new();
        for _ in 0..3 {
            ids.push(server.submit("?kind=pack", SQUARE).await);
        }
        let r = server
            .call(
                Method::POST,
                &format!("/api/v1/jobs/{}/cancel", ids[0]),
                &[],
            )
            .await;
        assert_eq!(r.json()["state"], "cancelled");
        let page = server.get("/api/v1/jobs?limit=2").await.json();
        let listed: Vec<&str> = page["jobs"]
            .as_array()
            .expect("jobs")
            .iter()
            .filter_map(|j| j["id"].as_str())
            .collect();
        assert_eq!(listed, [ids[2].as_str(), ids[1].as_str()]);
        let next = page["next"].as_str().expect("a next page");
        assert!(next.starts_with("/api/v1/jobs?limit=2&before="), "{next}");
        let page = server.get(next).await.json();
        assert_eq!(page["jobs"][0]["id"], ids[0].as_str());
        assert_eq!(page["jobs"].as_array().map(Vec::len), Some(1));
        assert_eq!(page["next"], json!(null));
        let queued = server.get("/api/v1/jobs?state=queued&limit=1").await.json();
        assert_eq!(queued["jobs"][0]["id"], ids[2].as_str());
        assert!(
            queued["next"]
                .as_str()
                .expect("next")
                .ends_with("&state=queued")
        );
        let cancelled = server.get("/api/v1/jobs?state=cancelled").await.json();
        assert_eq!(cancelled["jobs"].as_array().map(Vec::len), Some(1));
        for (query, error) in [
            (
                "state=sleeping",
                "unknown state \"sleeping\"; valid: queued, running, succeeded, failed, cancelled",
            ),
            ("limit=0", "limit must be 1 to 500, got 0"),
            ("limit=501", "limit must be 1 to 500, got 501"),
        ] {
            let r = server.get(&format!("/api/v1/jobs?{query}")).await;
            assert_eq!(r.status, StatusCode::BAD_REQUEST, "{query}");
            assert_eq!(r.error(), error);
        }
        let r = server.get("/api/v1/jobs?limit=abc").await;
        assert_eq!(r.status, StatusCode::BAD_REQUEST);
        assert!(r.error().starts_with("bad query: "), "{}", r.error());
    }

    #[tokio::test]
    async fn a_full_queue_and_a_stopping_server_say_when_to_retry() {
        let server = TestServer::with(|o| o.max_queue = 1, None);
        server.submit("?kind=pack", SQUARE).await;
        let r = server
            .post("/api/v1/jobs", "application/toml", SQUARE)
            .await;
        assert_eq!(r.status, StatusCode::SERVICE_UNAVAILABLE);
        assert_eq!(r.header("retry-after"), Some("5"));
        assert!(r.error().contains("queue is full"), "{}", r.error());
        server.shared.stopping.store(true, Ordering::SeqCst);
        let r = server
            .post("/api/v1/jobs", "application/toml", SQUARE)
            .await;
        assert_eq!(r.status, StatusCode::SERVICE_UNAVAILABLE);
        assert_eq!(r.header("retry-after"), Some("10"));
        assert_eq!(r.error(), "the server is stopping");
    }
}
