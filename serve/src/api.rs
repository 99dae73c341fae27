//! The HTTP API under `/api/v1`: small typed handlers, one error type
//! ([`ApiError`], always a JSON body), auth and request logs as
//! middleware, and the OpenAPI document generated from the handlers'
//! annotations.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::Json;
use axum::Router;
use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, QueryRejection};
use axum::extract::{DefaultBodyLimit, Path, Query, Request, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use futures_util::Stream;
use gapack::jobs::{JobError, JobKind, Plan, Request as JobRequest};
use rand::RngCore;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::{IntoParams, OpenApi, ToSchema};

use super::Shared;
use super::db::{CancelOutcome, DbError, JobRow, State as JobState};
use super::web;
use super::worker::{ORIGIN, job_dir};

/// Largest request body (bytes): 1 MiB.
pub const MAX_BODY: usize = 1 << 20;

type AppState = State<Arc<Shared>>;

/// The service's routes.
pub fn router(shared: Arc<Shared>) -> Router {
    let api = Router::new()
        .route("/jobs", post(submit).get(list))
        .route("/validate", post(validate))
        .route("/jobs/{id}", get(status).delete(delete))
        .route("/jobs/{id}/events", get(events))
        .route("/jobs/{id}/cancel", post(cancel))
        .route("/jobs/{id}/files", get(files))
        .route("/jobs/{id}/files/{*name}", get(file))
        .route("/jobs/{id}/packing", get(packing))
        .route("/examples", get(examples))
        .route("/openapi.json", get(openapi));
    Router::new()
        .nest("/api/v1", api)
        .route("/metrics", get(metrics))
        .layer(middleware::from_fn_with_state(Arc::clone(&shared), auth))
        .route("/healthz", get(healthz))
        // The page and its assets hold no data: a server with a token
        // serves them to anyone, and the page asks for the token.
        .route("/", get(web::index))
        .route("/app.js", get(web::script))
        .route("/app.css", get(web::style))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(DefaultBodyLimit::max(MAX_BODY))
        .layer(middleware::from_fn(log))
        .with_state(shared)
}

// ---------------------------------------------------------------- errors

/// A refusal: its status and a JSON body saying why.
#[derive(Debug)]
pub struct ApiError {
    status: StatusCode,
    body: Box<ErrorBody>,
    retry_after: Option<u64>,
}

/// The body of every refusal. A config fault also gives where it lies.
#[derive(Debug, Serialize, ToSchema)]
pub struct ErrorBody {
    /// The whole message (for a config: `config.toml:LINE:COLUMN: KEY: what is wrong`, as the CLI says it).
    error: String,
    /// Config faults: line, from 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    line: Option<usize>,
    /// Config faults: column, from 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    column: Option<usize>,
    /// Config faults: the key path at fault (`domain.width`).
    #[serde(skip_serializing_if = "Option::is_none")]
    key: Option<String>,
    /// Config faults: what is wrong, without the place.
    #[serde(skip_serializing_if = "Option::is_none")]
    message: Option<String>,
}

impl ApiError {
    fn new(status: StatusCode, error: impl Into<String>) -> Self {
        ApiError {
            status,
            body: Box::new(ErrorBody {
                error: error.into(),
                line: None,
                column: None,
                key: None,
                message: None,
            }),
            retry_after: None,
        }
    }

    fn bad_request(error: impl Into<String>) -> Self {
        ApiError::new(StatusCode::BAD_REQUEST, error)
    }

    fn unknown_job(id: &str) -> Self {
        ApiError::new(StatusCode::NOT_FOUND, format!("no job {id:?}"))
    }

    fn internal(e: impl std::fmt::Display) -> Self {
        tracing::error!(error = %e, "internal error");
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error: {e}"),
        )
    }

    /// A fault in the submitted config, at `key` (no place known).
    fn config(key: &str, message: String) -> Self {
        let mut e = ApiError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("{ORIGIN}: {key}: {message}"),
        );
        e.body.key = Some(key.to_owned());
        e.body.message = Some(message);
        e
    }
}

impl From<JobError> for ApiError {
    fn from(e: JobError) -> Self {
        let status = if e.is_input() {
            StatusCode::UNPROCESSABLE_ENTITY
        } else {
            StatusCode::INTERNAL_SERVER_ERROR
        };
        let mut api = ApiError::new(status, e.to_string());
        if let JobError::Config(config) = &e {
            let at = config.location();
            let full = config.to_string();
            let mut message = full
                .strip_prefix(&format!("{at}: "))
                .unwrap_or(&full)
                .to_owned();
            if let Some(key) = config.key()
                && let Some(rest) = message.strip_prefix(&format!("{key}: "))
            {
                message = rest.to_owned();
            }
            api.body.line = Some(at.line);
            api.body.column = Some(at.column);
            api.body.key = config.key().map(str::to_owned);
            api.body.message = Some(message);
        }
        api
    }
}

impl From<DbError> for ApiError {
    fn from(e: DbError) -> Self {
        match e {
            DbError::QueueFull(_) => {
                let mut api = ApiError::new(StatusCode::SERVICE_UNAVAILABLE, e.to_string());
                api.retry_after = Some(5);
                api
            }
            DbError::Sql(_) => ApiError::internal(e),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let mut response = (self.status, Json(self.body)).into_response();
        if let Some(seconds) = self.retry_after {
            response
                .headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(seconds));
        }
        response
    }
}

async fn not_found() -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        "no such endpoint; see /api/v1/openapi.json",
    )
}

async fn method_not_allowed() -> ApiError {
    ApiError::new(
        StatusCode::METHOD_NOT_ALLOWED,
        "method not allowed on this endpoint; see /api/v1/openapi.json",
    )
}

/// Run a blocking store call off the async threads.
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    tokio::task::spawn_blocking(f)
        .await
        .map_err(ApiError::internal)?
}

// ---------------------------------------------------------------- middleware

/// Every request but `/healthz` carries `Authorization: Bearer TOKEN` when
/// the server has a token; compared in constant time.
async fn auth(State(shared): AppState, request: Request, next: Next) -> Response {
    let Some(token) = &shared.token else {
        return next.run(request).await;
    };
    let given = request
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "));
    match given {
        Some(given) if same(given.trim().as_bytes(), token.as_bytes()) => next.run(request).await,
        Some(_) => ApiError::new(StatusCode::UNAUTHORIZED, "wrong bearer token").into_response(),
        None => {
            let mut response = ApiError::new(
                StatusCode::UNAUTHORIZED,
                "this server needs a token: Authorization: Bearer TOKEN",
            )
            .into_response();
            response
                .headers_mut()
                .insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
            response
        }
    }
}

/// Equal byte strings, in a time that depends on their lengths only.
fn same(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
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

// ---------------------------------------------------------------- submission

/// Query parameters of a submission (with a TOML body).
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct SubmitQuery {
    /// `pack`, `optimise`, `layer`, `compare`, `stability` or `sweep`
    /// [default: sweep with a [sweep] table, else optimise with an
    /// [optimise] one, else layer with a [layering] one, else pack].
    kind: Option<String>,
    /// Overrides the config's seed.
    seed: Option<u64>,
    /// Run over the config's and the server's limits (only if the server
    /// was started with `--force`).
    force: Option<bool>,
}

/// A submission as JSON.
#[derive(Debug, Deserialize, ToSchema)]
pub struct SubmitBody {
    /// The job kind (see the query parameter).
    kind: Option<String>,
    /// The config, TOML text.
    config: String,
    /// Overrides the config's seed.
    seed: Option<u64>,
    /// See the query parameter.
    force: Option<bool>,
}

/// A submission, whichever way it came.
struct Submission {
    kind: Option<JobKind>,
    config: String,
    seed: Option<u64>,
    force: bool,
}

fn job_kind(name: &str) -> Result<JobKind, ApiError> {
    JobKind::named(name).ok_or_else(|| {
        ApiError::bad_request(format!(
            "unknown job kind {name:?}; valid: {}",
            JobKind::names()
        ))
    })
}

/// The submission a request makes: a TOML body with query parameters, or
/// a JSON body.
fn submission(
    headers: &HeaderMap,
    query: Result<Query<SubmitQuery>, QueryRejection>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Submission, ApiError> {
    let body = body.map_err(|e| {
        let message = if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
            format!("the request body is over the limit of {MAX_BODY} bytes (1 MiB)")
        } else {
            e.body_text()
        };
        ApiError::new(e.status(), message)
    })?;
    let Query(query) =
        query.map_err(|e| ApiError::bad_request(format!("bad query: {}", e.body_text())))?;
    let media = headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .map(|v| {
            v.split(';')
                .next()
                .unwrap_or("")
                .trim()
                .to_ascii_lowercase()
        });
    let text = |bytes: Bytes| {
        String::from_utf8(bytes.to_vec())
            .map_err(|_| ApiError::bad_request("the config is not UTF-8 text"))
    };
    match media.as_deref() {
        Some("application/toml") => Ok(Submission {
            kind: query.kind.as_deref().map(job_kind).transpose()?,
            config: text(body)?,
            seed: query.seed,
            force: query.force.unwrap_or(false),
        }),
        Some("application/json") => {
            let json: SubmitBody = serde_json::from_slice(&body)
                .map_err(|e| ApiError::bad_request(format!("bad JSON body: {e}")))?;
            Ok(Submission {
                kind: json
                    .kind
                    .or(query.kind)
                    .as_deref()
                    .map(job_kind)
                    .transpose()?,
                config: json.config,
                seed: json.seed.or(query.seed),
                force: json.force.or(query.force).unwrap_or(false),
            })
        }
        other => Err(ApiError::new(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            format!(
                "Content-Type {}: send the config as application/toml (kind and seed as query parameters) or application/json ({{\"kind\", \"config\", \"seed\"}})",
                other.map_or_else(|| "missing".to_owned(), |m| format!("{m:?}"))
            ),
        )),
    }
}

/// Plan a submission as a worker will, and check it against the server's rules.
fn plan(shared: &Shared, s: &Submission) -> Result<(Plan, JobRequest), ApiError> {
    if s.force && !shared.limits.force {
        return Err(ApiError::new(
            StatusCode::FORBIDDEN,
            "force is refused: this server was not started with --force",
        ));
    }
    let kind = match s.kind {
        Some(kind) => kind,
        None => {
            let options = gapack::config::ParseOptions { force: s.force };
            let config = gapack::config::parse_with(&s.config, ORIGIN, options)
                .map_err(|e| ApiError::from(JobError::from(e)))?;
            JobKind::natural(&config)
        }
    };
    let request = JobRequest {
        seed: s.seed,
        force: s.force,
        ..JobRequest::new(kind)
    };
    let plan = Plan::load(&s.config, ORIGIN, &request)?;
    if plan.config.output.dir.is_some() {
        let mut e = ApiError::config(
            "output.dir",
            "the server chooses where a job's files go; remove dir from [output]".to_owned(),
        );
        if let Some(at) = gapack::config::key_location(&s.config, ORIGIN, "output.dir") {
            e.body.error = format!(
                "{at}: {}",
                e.body.error.trim_start_matches(&format!("{ORIGIN}: "))
            );
            e.body.line = Some(at.line);
            e.body.column = Some(at.column);
        }
        return Err(e);
    }
    if !s.force {
        ceilings(shared, &plan)?;
    }
    Ok((plan, request))
}

/// The server's ceilings, which no config can raise.
fn ceilings(shared: &Shared, plan: &Plan) -> Result<(), ApiError> {
    let limits = &shared.limits;
    let mut scenes = vec![&plan.config.scene];
    if let Some(run) = &plan.config.fracture {
        scenes.extend(run.wells.iter().map(|w| &w.scene));
    }
    let mb = |bytes: f64| bytes / (1024.0 * 1024.0);
    for scene in scenes {
        let disks = scene.max_disks();
        if disks > limits.max_particles as f64 {
            return Err(ApiError::config(
                "limits.max_particles",
                format!(
                    "the scene could hold {disks:.0} disks, over this server's ceiling of {}",
                    limits.max_particles
                ),
            ));
        }
        let mut bytes = gapack::estimated_peak_bytes(scene);
        if let (JobKind::Optimise, Some(o)) = (plan.kind, &plan.config.optimise) {
            bytes = bytes.max(o.peak_bytes(scene));
        }
        if bytes > limits.max_memory_bytes {
            return Err(ApiError::config(
                "limits.max_memory_mb",
                format!(
                    "the run would need about {:.0} MB, over this server's ceiling of {:.0} MB",
                    mb(bytes),
                    mb(limits.max_memory_bytes)
                ),
            ));
        }
    }
    Ok(())
}

/// A new job's id: 128 random bits, as hex.
fn new_id() -> String {
    let mut bytes = [0u8; 16];
    rand::rngs::OsRng.fill_bytes(&mut bytes);
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Whether `id` could be a job's id (so that nothing else reaches the store or a path).
fn checked_id(id: &str) -> Result<(), ApiError> {
    if id.len() == 32
        && id
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
    {
        Ok(())
    } else {
        Err(ApiError::unknown_job(id))
    }
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

fn links(id: &str) -> Links {
    let base = format!("/api/v1/jobs/{id}");
    Links {
        events: format!("{base}/events"),
        files: format!("{base}/files"),
        cancel: format!("{base}/cancel"),
        this: base,
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
    request_body(content = SubmitBody, description = "TOML text (application/toml) or this JSON", content_type = "application/json"),
    responses(
        (status = 201, description = "Queued", body = Accepted),
        (status = 400, description = "Bad query, JSON or job kind", body = ErrorBody),
        (status = 413, description = "Body over 1 MiB", body = ErrorBody),
        (status = 415, description = "Neither TOML nor JSON", body = ErrorBody),
        (status = 422, description = "Bad config, or over the server's ceilings", body = ErrorBody),
        (status = 503, description = "Queue full or server stopping (Retry-After)", body = ErrorBody),
    ))]
async fn submit(
    State(shared): AppState,
    headers: HeaderMap,
    query: Result<Query<SubmitQuery>, QueryRejection>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let s = submission(&headers, query, body)?;
    if shared.stopping.load(std::sync::atomic::Ordering::SeqCst) {
        let mut e = ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the server is stopping");
        e.retry_after = Some(10);
        return Err(e);
    }
    let id = new_id();
    let accepted = blocking({
        let shared = Arc::clone(&shared);
        let id = id.clone();
        move || {
            let (plan, request) = plan(&shared, &s)?;
            shared.db.insert(
                &id,
                request.kind.name(),
                &s.config,
                s.seed,
                shared.limits.max_queue,
            )?;
            Ok(Accepted {
                kind: request.kind.name().to_owned(),
                state: JobState::Queued,
                seed: plan.seed(),
                urls: links(&id),
                id: id.clone(),
            })
        }
    })
    .await?;
    shared.wake_worker();
    tracing::info!(job = %id, kind = %accepted.kind, state = "queued", "job state");
    let location = accepted.urls.this.clone();
    let mut response = (StatusCode::CREATED, Json(accepted)).into_response();
    if let Ok(value) = HeaderValue::from_str(&location) {
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

/// A scene's estimates.
#[derive(Debug, Serialize, ToSchema)]
pub struct Estimates {
    /// Disks a packing is expected to hold.
    disks: f64,
    /// The most disks it could hold.
    max_disks: f64,
    /// Peak memory of a packing (bytes, an upper bound).
    peak_bytes: f64,
    /// Packings the job makes at most: 1 for a pack; for a search the
    /// initial population and, per generation, under three per member
    /// (offspring and immigrants); absent for batches and sweeps.
    packings: Option<u64>,
    /// A guide to the run time (s), not a bound: `disks × packings` at
    /// 10⁶ disks a second, the packer's speed on one core.
    seconds: Option<f64>,
}

/// The packer's speed the time guide assumes (disks per second, one core).
const GUIDE_DISKS_PER_SECOND: f64 = 1e6;

impl Estimates {
    fn of(plan: &Plan) -> Self {
        let scene = &plan.config.scene;
        let search = |population: usize, generations: usize| {
            let per_generation = 3 * population.max(2) as u64;
            Some(
                (population as u64)
                    .saturating_add(per_generation.saturating_mul(generations as u64)),
            )
        };
        let packings = match plan.kind {
            JobKind::Pack if plan.config.fracture.is_none() => Some(1),
            JobKind::Optimise => plan
                .config
                .optimise
                .as_ref()
                .and_then(|o| search(o.population, o.generations)),
            JobKind::Layer => plan
                .config
                .layering
                .as_ref()
                .and_then(|l| search(l.population, l.generations)),
            _ => None,
        };
        let disks = scene.estimated_disks();
        Estimates {
            disks,
            max_disks: scene.max_disks(),
            peak_bytes: gapack::estimated_peak_bytes(scene),
            packings,
            seconds: packings.map(|n| disks * n as f64 / GUIDE_DISKS_PER_SECOND),
        }
    }
}

/// Check a config and return the plan and estimates, without running it.
#[utoipa::path(post, path = "/api/v1/validate", params(SubmitQuery),
    request_body(content = SubmitBody, description = "as for POST /jobs", content_type = "application/json"),
    responses(
        (status = 200, description = "Valid", body = Validated),
        (status = 422, description = "Bad config", body = ErrorBody),
    ))]
async fn validate(
    State(shared): AppState,
    headers: HeaderMap,
    query: Result<Query<SubmitQuery>, QueryRejection>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Validated>, ApiError> {
    let s = submission(&headers, query, body)?;
    let validated = blocking(move || {
        let (plan, request) = plan(&shared, &s)?;
        Ok(Validated {
            kind: request.kind.name().to_owned(),
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

// ---------------------------------------------------------------- status

/// A job.
#[derive(Debug, Serialize, ToSchema)]
pub struct JobView {
    /// Its id.
    id: String,
    /// Its kind.
    kind: String,
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
    #[schema(value_type = Option<Object>)]
    summary: Option<Value>,
    /// Why it failed.
    error: Option<String>,
    /// Where its resources are.
    urls: Links,
}

fn view(row: JobRow) -> JobView {
    let json = |s: Option<String>| s.and_then(|s| serde_json::from_str(&s).ok());
    JobView {
        urls: links(&row.id),
        id: row.id,
        kind: row.kind,
        seed: row.seed,
        config: row.config,
        state: row.state,
        attempts: row.attempts,
        cancel_requested: row.cancel_requested,
        created_ms: row.created_ms,
        started_ms: row.started_ms,
        finished_ms: row.finished_ms,
        progress: json(row.progress),
        summary: json(row.summary),
        error: row.error,
    }
}

/// A job's state, progress, timings, and its summary or error.
#[utoipa::path(get, path = "/api/v1/jobs/{id}", params(("id" = String, Path, description = "Job id")),
    responses((status = 200, body = JobView), (status = 404, body = ErrorBody)))]
async fn status(
    State(shared): AppState,
    Path(id): Path<String>,
) -> Result<Json<JobView>, ApiError> {
    checked_id(&id)?;
    let row = blocking(move || {
        shared
            .db
            .get(&id)?
            .ok_or_else(|| ApiError::unknown_job(&id))
    })
    .await?;
    Ok(Json(view(row)))
}

/// Paging and filter of the job list.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ListQuery {
    /// Only jobs in this state.
    state: Option<String>,
    /// Jobs per page, 1 to 500 [default 50].
    limit: Option<usize>,
    /// The `next` cursor of the previous page.
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
    responses((status = 200, body = JobPage), (status = 400, body = ErrorBody)))]
async fn list(
    State(shared): AppState,
    query: Result<Query<ListQuery>, QueryRejection>,
) -> Result<Json<JobPage>, ApiError> {
    let Query(q) =
        query.map_err(|e| ApiError::bad_request(format!("bad query: {}", e.body_text())))?;
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
    let rows = blocking(move || Ok(shared.db.list(state, q.before, limit)?)).await?;
    let next = (rows.len() == limit).then(|| {
        let last = rows.last().map_or(0, |r| r.seq);
        let mut url = format!("/api/v1/jobs?limit={limit}&before={last}");
        if let Some(state) = state {
            url += &format!("&state={}", state.name());
        }
        url
    });
    Ok(Json(JobPage {
        jobs: rows.into_iter().map(view).collect(),
        next,
    }))
}

/// Cancel a job (idempotent): a queued one at once; a running one stops
/// at its next check and keeps what it finished (an optimise its best packing).
#[utoipa::path(post, path = "/api/v1/jobs/{id}/cancel", params(("id" = String, Path, description = "Job id")),
    responses((status = 202, description = "Stopping", body = JobView), (status = 200, description = "Cancelled or already finished", body = JobView), (status = 404, body = ErrorBody)))]
async fn cancel(State(shared): AppState, Path(id): Path<String>) -> Result<Response, ApiError> {
    checked_id(&id)?;
    let (outcome, row) = blocking({
        let shared = Arc::clone(&shared);
        let id = id.clone();
        move || {
            let outcome = shared
                .db
                .cancel(&id)?
                .ok_or_else(|| ApiError::unknown_job(&id))?;
            if outcome == CancelOutcome::Stopping {
                shared.cancel_running(&id);
            }
            let row = shared
                .db
                .get(&id)?
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
    Ok((status, Json(view(row))).into_response())
}

/// Delete a finished job and its files.
#[utoipa::path(delete, path = "/api/v1/jobs/{id}", params(("id" = String, Path, description = "Job id")),
    responses((status = 204, description = "Deleted"), (status = 404, body = ErrorBody), (status = 409, description = "Not finished", body = ErrorBody)))]
async fn delete(State(shared): AppState, Path(id): Path<String>) -> Result<StatusCode, ApiError> {
    checked_id(&id)?;
    let dir = job_dir(&shared, &id);
    blocking(move || match shared.db.delete(&id)? {
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

// ---------------------------------------------------------------- events

/// Events read from the store at a time.
const EVENT_BATCH: usize = 256;

/// How long a stream waits for news before it looks at the store again.
const EVENT_POLL: Duration = Duration::from_secs(5);

/// The state of one event stream.
struct Follow {
    shared: Arc<Shared>,
    id: String,
    last: i64,
    pending: VecDeque<(i64, String)>,
    news: tokio::sync::broadcast::Receiver<String>,
    shutdown: tokio::sync::watch::Receiver<bool>,
    done: bool,
}

impl Follow {
    /// The next event, or `None` once the job reached a final state (or
    /// was deleted, or the server stops).
    async fn next(&mut self) -> Option<SseEvent> {
        loop {
            if let Some((seq, data)) = self.pending.pop_front() {
                self.last = seq;
                let value: Value = serde_json::from_str(&data).unwrap_or(Value::Null);
                let name = value["event"].as_str().unwrap_or("message").to_owned();
                if name == "state"
                    && value["state"]
                        .as_str()
                        .and_then(JobState::parse)
                        .is_some_and(JobState::is_final)
                {
                    self.done = true;
                }
                return Some(
                    SseEvent::default()
                        .id(seq.to_string())
                        .event(name)
                        .data(data),
                );
            }
            if self.done || *self.shutdown.borrow() {
                return None;
            }
            let (shared, id, last) = (Arc::clone(&self.shared), self.id.clone(), self.last);
            let read = tokio::task::spawn_blocking(move || {
                let exists = shared.db.get(&id).map(|r| r.is_some());
                let events = shared.db.events_after(&id, last, EVENT_BATCH);
                (exists, events)
            })
            .await;
            match read {
                Ok((Ok(true), Ok(events))) if !events.is_empty() => {
                    self.pending.extend(events);
                    continue;
                }
                Ok((Ok(true), Ok(_))) => {}
                _ => return None,
            }
            // Nothing new: wait for news of this job, a stop, or the poll period.
            let deadline = tokio::time::Instant::now() + EVENT_POLL;
            loop {
                tokio::select! {
                    news = self.news.recv() => match news {
                        Ok(job) if job != self.id => continue,
                        Ok(_) | Err(tokio::sync::broadcast::error::RecvError::Lagged(_)) => break,
                        Err(tokio::sync::broadcast::error::RecvError::Closed) => return None,
                    },
                    _ = self.shutdown.changed() => break,
                    () = tokio::time::sleep_until(deadline) => break,
                }
            }
        }
    }
}

/// The job's events as Server-Sent Events, from the first (or after
/// `Last-Event-ID`) to its final state. Each event's `event:` is its kind
/// (`state`, `started`, `stage`, `progress`, `generation`, `warning`,
/// `written`, …), its `id:` its number, its `data:` its JSON.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/events", params(("id" = String, Path, description = "Job id"), ("Last-Event-ID" = Option<i64>, Header, description = "Resume after this event")),
    responses((status = 200, description = "A text/event-stream of the job's events"), (status = 404, body = ErrorBody)))]
async fn events(
    State(shared): AppState,
    Path(id): Path<String>,
    headers: HeaderMap,
) -> Result<Sse<impl Stream<Item = Result<SseEvent, Infallible>>>, ApiError> {
    checked_id(&id)?;
    let last = match headers.get("last-event-id") {
        None => 0,
        Some(v) => v
            .to_str()
            .ok()
            .and_then(|s| s.trim().parse::<i64>().ok())
            .ok_or_else(|| ApiError::bad_request("Last-Event-ID must be an event number"))?,
    };
    // Subscribe before the first read: no event falls between the two.
    let news = shared.events.subscribe();
    let shutdown = shared.shutdown.subscribe();
    let exists = blocking({
        let shared = Arc::clone(&shared);
        let id = id.clone();
        move || Ok(shared.db.get(&id)?.is_some())
    })
    .await?;
    if !exists {
        return Err(ApiError::unknown_job(&id));
    }
    let follow = Follow {
        shared,
        id,
        last,
        pending: VecDeque::new(),
        news,
        shutdown,
        done: false,
    };
    let stream = futures_util::stream::unfold(follow, |mut f| async move {
        f.next().await.map(|event| (Ok(event), f))
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::default()))
}

// ---------------------------------------------------------------- files

/// One file of a run.
#[derive(Debug, Serialize, ToSchema)]
pub struct FileEntry {
    /// Its name in the run's folder (`packing.csv`, `well_a/packing.csv`).
    name: String,
    /// Its size (bytes).
    bytes: u64,
    /// Where to fetch it.
    url: String,
}

/// A finished run's files, from its manifest.
#[derive(Debug, Serialize, ToSchema)]
pub struct FileList {
    /// Whether the run was cut short (cancelled: what it finished).
    interrupted: bool,
    /// The files, as `manifest.json` lists them.
    files: Vec<FileEntry>,
    /// The manifest itself.
    #[schema(value_type = Object)]
    manifest: Value,
}

/// The manifest of a finished job, or why there is none to serve.
fn manifest(shared: &Shared, id: &str) -> Result<Value, ApiError> {
    let row = shared
        .db
        .get(id)?
        .ok_or_else(|| ApiError::unknown_job(id))?;
    if !row.state.is_final() {
        return Err(ApiError::new(
            StatusCode::CONFLICT,
            format!(
                "job {id} is {}: its files are served once it has finished",
                row.state.name()
            ),
        ));
    }
    let path = job_dir(shared, id).join(gapack::jobs::MANIFEST_JSON);
    let bytes = match std::fs::read(&path) {
        Ok(bytes) => bytes,
        Err(e)
            if matches!(
                e.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory
            ) =>
        {
            return Err(ApiError::new(
                StatusCode::NOT_FOUND,
                format!("job {id} wrote no files"),
            ));
        }
        Err(e) => return Err(ApiError::internal(e)),
    };
    serde_json::from_slice(&bytes).map_err(ApiError::internal)
}

fn listed(manifest: &Value) -> Vec<String> {
    manifest["files"]
        .as_array()
        .map(|files| {
            files
                .iter()
                .filter_map(|f| f.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

/// A finished job's files, as its `manifest.json` lists them.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/files", params(("id" = String, Path, description = "Job id")),
    responses((status = 200, body = FileList), (status = 404, body = ErrorBody), (status = 409, description = "Not finished", body = ErrorBody)))]
async fn files(
    State(shared): AppState,
    Path(id): Path<String>,
) -> Result<Json<FileList>, ApiError> {
    checked_id(&id)?;
    let list = blocking(move || {
        let manifest = manifest(&shared, &id)?;
        let dir = job_dir(&shared, &id);
        let files = listed(&manifest)
            .into_iter()
            .map(|name| FileEntry {
                bytes: std::fs::metadata(dir.join(&name)).map_or(0, |m| m.len()),
                url: format!("/api/v1/jobs/{id}/files/{name}"),
                name,
            })
            .collect();
        Ok(FileList {
            interrupted: manifest["interrupted"].as_bool().unwrap_or(false),
            files,
            manifest,
        })
    })
    .await?;
    Ok(Json(list))
}

/// The content type of a file by its extension.
fn content_type(name: &str) -> &'static str {
    match name.rsplit('.').next().unwrap_or("") {
        "csv" => "text/csv; charset=utf-8",
        "json" => "application/json",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "vtk" | "data" | "txt" | "dat" | "py" | "p4p" | "geo" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

/// One file of a finished job: only the names its manifest lists.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/files/{name}", params(("id" = String, Path, description = "Job id"), ("name" = String, Path, description = "File name as the manifest lists it")),
    responses((status = 200, description = "The file, with its content type"), (status = 404, body = ErrorBody), (status = 409, body = ErrorBody)))]
async fn file(
    State(shared): AppState,
    Path((id, name)): Path<(String, String)>,
) -> Result<Response, ApiError> {
    checked_id(&id)?;
    let bytes = blocking({
        let name = name.clone();
        move || {
            let manifest = manifest(&shared, &id)?;
            let names = listed(&manifest);
            let known = name == gapack::jobs::MANIFEST_JSON || names.contains(&name);
            let safe = !name.is_empty()
                && !name.starts_with('/')
                && !name.contains('\\')
                && name
                    .split('/')
                    .all(|p| !p.is_empty() && p != "." && p != "..");
            if !known || !safe {
                return Err(ApiError::new(
                    StatusCode::NOT_FOUND,
                    format!(
                        "job {id} has no file {name:?}; GET /api/v1/jobs/{id}/files lists them"
                    ),
                ));
            }
            std::fs::read(job_dir(&shared, &id).join(&name)).map_err(ApiError::internal)
        }
    })
    .await?;
    Ok(([(header::CONTENT_TYPE, content_type(&name))], bytes).into_response())
}

// ---------------------------------------------------------------- page data

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
async fn packing(
    State(shared): AppState,
    Path(id): Path<String>,
) -> Result<Json<PackingView>, ApiError> {
    checked_id(&id)?;
    let view = blocking(move || {
        let manifest = manifest(&shared, &id)?;
        if !listed(&manifest).iter().any(|f| f == "packing.csv") {
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

// ---------------------------------------------------------------- service

/// Whether the server is up.
async fn healthz(State(shared): AppState) -> Response {
    if shared.stopping.load(std::sync::atomic::Ordering::SeqCst) {
        (
            StatusCode::SERVICE_UNAVAILABLE,
            Json(serde_json::json!({"status": "stopping"})),
        )
            .into_response()
    } else {
        Json(serde_json::json!({"status": "ok"})).into_response()
    }
}

/// Prometheus text: jobs by state, queue length, job durations, GA
/// evaluations, packed disks.
async fn metrics(State(shared): AppState) -> Result<Response, ApiError> {
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
    )
        .into_response())
}

/// The API's OpenAPI document.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "gapack service",
        description = "Dense 2D disk packings and their genetic-algorithm optimisation, as jobs."
    ),
    paths(
        submit, validate, list, status, events, cancel, delete, files, file, packing, examples
    ),
    components(schemas(
        ErrorBody,
        Accepted,
        Links,
        Validated,
        Estimates,
        JobView,
        JobPage,
        FileList,
        FileEntry,
        JobState,
        SubmitBody,
        PackingView,
        Example
    ))
)]
struct ApiDoc;

/// This API's OpenAPI document.
async fn openapi() -> Response {
    match ApiDoc::openapi().to_json() {
        Ok(json) => ([(header::CONTENT_TYPE, "application/json")], json).into_response(),
        Err(e) => ApiError::internal(e).into_response(),
    }
}
