//! The API's one error type: every refusal is an [`ApiError`], answered
//! with its status and a JSON [`ErrorBody`] (a config fault also says
//! where it lies), and `Retry-After` when trying later may help. The
//! router's fallbacks (no such route, no such method) answer the same way.

use axum::Json;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use gapack::config::Location;
use gapack::jobs::JobError;
use serde::Serialize;
use utoipa::ToSchema;

use crate::store::StoreError;
use crate::worker::ORIGIN;

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
    /// A refusal with `status`, saying `error`.
    pub fn new(status: StatusCode, error: impl Into<String>) -> Self {
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

    /// 400: the request itself is malformed.
    pub fn bad_request(error: impl Into<String>) -> Self {
        ApiError::new(StatusCode::BAD_REQUEST, error)
    }

    /// 404: no job has this id.
    pub fn unknown_job(id: &str) -> Self {
        ApiError::new(StatusCode::NOT_FOUND, format!("no job {id:?}"))
    }

    /// 500, logged: the store, a file or a task failed.
    pub fn internal(e: impl std::fmt::Display) -> Self {
        tracing::error!(error = %e, "internal error");
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error: {e}"),
        )
    }

    /// 422: a fault in the submitted config at `key`, placed at `at` when
    /// the config's text shows where the key is.
    pub fn config(key: &str, message: String, at: Option<Location>) -> Self {
        let place = at
            .as_ref()
            .map_or_else(|| ORIGIN.to_owned(), ToString::to_string);
        let mut e = ApiError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("{place}: {key}: {message}"),
        );
        e.body.line = at.as_ref().map(|at| at.line);
        e.body.column = at.as_ref().map(|at| at.column);
        e.body.key = Some(key.to_owned());
        e.body.message = Some(message);
        e
    }

    /// The same refusal, telling the client to try again in `seconds`.
    pub fn retry_after(mut self, seconds: u64) -> Self {
        self.retry_after = Some(seconds);
        self
    }
}

impl From<JobError> for ApiError {
    fn from(e: JobError) -> Self {
        let status = if e.is_input() {
            StatusCode::UNPROCESSABLE_ENTITY
        } else {
            StatusCode::INTERNAL_SERVER_ERROR
        };
        // A `[limits]` refusal says how to go over it in this medium.
        let hint = match &e {
            JobError::Config(config) if config.forceable() => FORCE,
            _ => "",
        };
        let mut api = ApiError::new(status, format!("{e}{hint}"));
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
            api.body.message = Some(format!("{message}{hint}"));
        }
        api
    }
}

/// What a `[limits]` refusal's message ends with over HTTP: the submission's
/// own way past it (a server started with `--force` allows it).
const FORCE: &str = ", or submit with \"force\": true to go ahead";

impl From<StoreError> for ApiError {
    fn from(e: StoreError) -> Self {
        match e {
            StoreError::QueueFull(_) => {
                ApiError::new(StatusCode::SERVICE_UNAVAILABLE, e.to_string()).retry_after(5)
            }
            // A share, not the server's load: retrying soon does not help.
            StoreError::UserQueueFull(_) => {
                ApiError::new(StatusCode::TOO_MANY_REQUESTS, e.to_string())
            }
            _ => ApiError::internal(e),
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

/// The router's fallback: no route has this path.
pub async fn not_found() -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        "no such endpoint; see /api/v1/openapi.json",
    )
}

/// The router's fallback: the path has no route for this method.
pub async fn method_not_allowed() -> ApiError {
    ApiError::new(
        StatusCode::METHOD_NOT_ALLOWED,
        "method not allowed on this endpoint; see /api/v1/openapi.json",
    )
}
