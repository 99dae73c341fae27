//! The API's OpenAPI document (`GET /openapi.json`), generated from the
//! handlers' `#[utoipa::path]` annotations and the response types.

use std::sync::Arc;

use axum::Router;
use axum::http::header;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use utoipa::OpenApi;

use super::error::{ApiError, ErrorBody};
use super::files::{FileEntry, FileList};
use super::jobs::{Accepted, JobPage, JobView, Links, Validated};
use super::page::{Example, PackingView};
use super::submission::{Estimates, SubmitBody};
use crate::Shared;
use crate::db::State as JobState;
// The handlers' path descriptions, named without their module: utoipa
// would take a module prefix (`jobs::submit`) for the operation's tag.
use super::events::__path_events;
use super::files::{__path_file, __path_files};
use super::jobs::{
    __path_cancel, __path_delete, __path_list, __path_status, __path_submit, __path_validate,
};
use super::page::{__path_examples, __path_packing};

/// The document's route.
pub fn router() -> Router<Arc<Shared>> {
    Router::new().route("/openapi.json", get(openapi))
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
