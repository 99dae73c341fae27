//! A finished job's files: the list (`GET /jobs/{id}/files`) and each file
//! (`GET /jobs/{id}/files/{name}`), served only by the names its
//! `manifest.json` lists, so that no other file of the data folder can be
//! reached.

use std::sync::Arc;

use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::IntoResponse;
use axum::routing::get;
use axum::{Json, Router};
use gapack::jobs::Manifest;
use percent_encoding::{AsciiSet, NON_ALPHANUMERIC, utf8_percent_encode};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use super::error::{ApiError, ErrorBody};
use super::jobs::JobId;
use super::{AppState, blocking};
use crate::Shared;
use crate::worker::job_dir;

/// The routes of a job's files.
pub fn router() -> Router<Arc<Shared>> {
    Router::new()
        .route("/jobs/{id}/files", get(files))
        .route("/jobs/{id}/files/{*name}", get(file))
}

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
    /// The manifest itself (`manifest.json`).
    #[schema(value_type = Object)]
    manifest: Manifest,
}

/// The manifest of a finished job, or why there is none to serve.
pub fn manifest(shared: &Shared, id: &str) -> Result<Manifest, ApiError> {
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
    Manifest::from_bytes(&bytes).map_err(ApiError::internal)
}

/// What a URL path segment keeps as it is: RFC 3986's unreserved characters.
const SEGMENT: &AsciiSet = &NON_ALPHANUMERIC
    .remove(b'-')
    .remove(b'.')
    .remove(b'_')
    .remove(b'~');

/// The URL of a job's file `name` (a path under the job's folder, `/`
/// between its parts), each part percent-encoded: a well named `a b#1`
/// gives `a%20b%231/packing.csv`.
fn file_url(id: &str, name: &str) -> String {
    let parts: Vec<String> = name
        .split('/')
        .map(|part| utf8_percent_encode(part, SEGMENT).to_string())
        .collect();
    format!("/api/v1/jobs/{id}/files/{}", parts.join("/"))
}

/// A finished job's files, as its `manifest.json` lists them.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/files", params(super::jobs::IdParam),
    responses(
        (status = 200, description = "The files, as the manifest lists them", body = FileList),
        (status = 400, description = "An id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job, or it wrote no files (cancelled before it ran)", body = ErrorBody),
        (status = 409, description = "Not finished", body = ErrorBody),
    ))]
async fn files(State(shared): AppState, JobId(id): JobId) -> Result<Json<FileList>, ApiError> {
    let list = blocking(move || {
        let manifest = manifest(&shared, &id)?;
        let dir = job_dir(&shared, &id);
        let files = manifest
            .files
            .iter()
            .cloned()
            .map(|name| FileEntry {
                bytes: std::fs::metadata(dir.join(&name)).map_or(0, |m| m.len()),
                url: file_url(&id, &name),
                name,
            })
            .collect();
        Ok(FileList {
            interrupted: manifest.interrupted,
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

/// Whether `name` is a plain relative path inside a job's folder: the
/// jobs' own rule ([`gapack::jobs::check_file_name`]).
fn inside(name: &str) -> bool {
    gapack::jobs::check_file_name(name).is_ok()
}

/// The `{name}` of a file's route (its `{id}` is read as a [`JobId`]).
#[derive(Deserialize)]
struct NameParam {
    name: String,
}

/// One file of a finished job: only the names its manifest lists.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/files/{name}",
    params(super::jobs::IdParam,
        ("name" = String, Path, description = "File name as the manifest lists it (`packing.csv`, `well_a/packing.csv`)"),
        ("Range" = Option<String>, Header, nullable = false, description = "A byte range (`bytes=0-1023`): 206 with that part"),
        ("If-None-Match" = Option<String>, Header, nullable = false, description = "The ETag of a copy held: 304 if the file is unchanged")),
    responses(
        (status = 200, description = "The file, with its content type (text/csv, application/json, image/svg+xml, image/png, text/plain, …)", content_type = "*/*", body = serde_json::Value,
            headers(("ETag" = String, description = "The file's version"))),
        (status = 206, description = "The byte range asked for", content_type = "*/*", body = serde_json::Value,
            headers(("Content-Range" = String, description = "The range sent and the file's size"))),
        (status = 304, description = "Not modified since the ETag given"),
        (status = 400, description = "An id or a name that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job, or no such file in its manifest", body = ErrorBody),
        (status = 409, description = "Not finished", body = ErrorBody),
        (status = 416, description = "A range outside the file",
            headers(("Content-Range" = String, description = "`bytes */SIZE`"))),
    ))]
async fn file(
    State(shared): AppState,
    JobId(id): JobId,
    Path(NameParam { name }): Path<NameParam>,
) -> Result<impl IntoResponse, ApiError> {
    let bytes = blocking({
        let name = name.clone();
        move || {
            let manifest = manifest(&shared, &id)?;
            let known = name == gapack::jobs::MANIFEST_JSON || manifest.files.contains(&name);
            if !known || !inside(&name) {
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
    Ok(([(header::CONTENT_TYPE, content_type(&name))], bytes))
}

#[cfg(test)]
mod tests {
    use axum::http::StatusCode;

    use super::{content_type, file_url, inside};
    use crate::api::testing::{NO_JOB, SQUARE, TestServer};

    #[test]
    fn file_urls_encode_each_part_of_the_name() {
        assert_eq!(
            file_url("j", "a b#1/packing.csv"),
            "/api/v1/jobs/j/files/a%20b%231/packing.csv"
        );
        assert_eq!(
            file_url("j", "c%2?/x.csv"),
            "/api/v1/jobs/j/files/c%252%3F/x.csv"
        );
        assert_eq!(file_url("j", "wells.csv"), "/api/v1/jobs/j/files/wells.csv");
    }

    #[tokio::test]
    async fn every_file_url_listed_is_served_whatever_the_well_names() {
        let server = TestServer::new();
        let wells = "seed = 1\n[fracture]\n[[fracture.wells]]\nname = \"a b#1\"\nwidth_mm = 6\nheight_m = 0.02\n[[fracture.wells]]\nname = \"c%2?\"\nwidth_mm = 5\nheight_m = 0.02\n[grading]\nuniform = [1.0, 1.5]\n";
        let id = server.submit("?kind=pack", wells).await;
        server.run_queued().await;
        let list = server.get(&format!("/api/v1/jobs/{id}/files")).await;
        assert_eq!(list.status, StatusCode::OK, "{}", list.text());
        let files = list.json()["files"].as_array().cloned().unwrap_or_default();
        assert!(files.len() > 4, "{files:?}");
        for f in &files {
            let url = f["url"].as_str().expect("a url");
            let r = server.get(url).await;
            assert_eq!(r.status, StatusCode::OK, "{url}: {}", r.text());
        }
    }

    #[tokio::test]
    async fn only_the_names_the_manifest_lists_are_served() {
        let server = TestServer::new();
        let id = server.submit("?kind=pack", SQUARE).await;
        server.run_queued().await;
        let dir = server.data().join("jobs").join(&id);
        std::fs::write(dir.join("secret.txt"), "no").expect("write");
        std::fs::write(server.data().join("secret.txt"), "no").expect("write");
        for name in [
            "secret.txt",
            "../secret.txt",
            "..%2Fsecret.txt",
            "%2E%2E/%2E%2E/gapack.db",
            "./packing.csv",
            "/etc/passwd",
            "..",
            "a\\b",
            "packing.csv/",
        ] {
            let r = server.get(&format!("/api/v1/jobs/{id}/files/{name}")).await;
            assert_eq!(r.status, StatusCode::NOT_FOUND, "{name}: {}", r.text());
            assert!(r.error().contains("has no file"), "{name}: {}", r.error());
        }
        let manifest = server
            .get(&format!("/api/v1/jobs/{id}/files/manifest.json"))
            .await;
        assert_eq!(manifest.status, StatusCode::OK);
        assert_eq!(manifest.header("content-type"), Some("application/json"));
        assert_eq!(manifest.json()["job"], "pack");
        let svg = server
            .get(&format!("/api/v1/jobs/{id}/files/packing.svg"))
            .await;
        assert_eq!(svg.header("content-type"), Some("image/svg+xml"));
        // Invalid UTF-8 in a name is the path extractor's own 400.
        let r = server.get(&format!("/api/v1/jobs/{id}/files/%FF")).await;
        assert_eq!(r.status, StatusCode::BAD_REQUEST);
    }

    #[tokio::test]
    async fn files_wait_for_the_end_of_the_job() {
        let server = TestServer::new();
        let id = server.submit("?kind=pack", SQUARE).await;
        for path in ["files", "files/packing.csv", "packing"] {
            let r = server.get(&format!("/api/v1/jobs/{id}/{path}")).await;
            assert_eq!(r.status, StatusCode::CONFLICT, "{path}");
            assert_eq!(
                r.error(),
                format!("job {id} is queued: its files are served once it has finished")
            );
        }
        let r = server.get(&format!("/api/v1/jobs/{NO_JOB}/files")).await;
        assert_eq!(r.status, StatusCode::NOT_FOUND);
        assert_eq!(r.error(), format!("no job {NO_JOB:?}"));
    }

    #[test]
    fn names_stay_inside_the_job_folder() {
        for name in ["packing.csv", "well_a/packing.csv", "a.b/c"] {
            assert!(inside(name), "{name}");
        }
        for name in [
            "",
            "/etc/passwd",
            "..",
            "a/../b",
            "./a",
            "a//b",
            "a/",
            "a\\b",
        ] {
            assert!(!inside(name), "{name}");
        }
    }

    #[test]
    fn content_types_follow_the_extension() {
        assert_eq!(content_type("packing.csv"), "text/csv; charset=utf-8");
        assert_eq!(content_type("well_a/summary.json"), "application/json");
        assert_eq!(content_type("packing.png"), "image/png");
        assert_eq!(content_type("packing.vtk"), "text/plain; charset=utf-8");
        assert_eq!(content_type("checkpoint.bin"), "application/octet-stream");
        assert_eq!(content_type("noextension"), "application/octet-stream");
    }
}
