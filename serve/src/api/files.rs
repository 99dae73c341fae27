//! A finished job's files: the list (`GET /jobs/{id}/files`) and each file
//! (`GET /jobs/{id}/files/{name}`), served only by the names its
//! `manifest.json` lists, so that no other file of the data folder can be
//! reached.

use std::sync::Arc;

use axum::Extension;
use axum::body::Body;
use axum::extract::{Path, Request, State};
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use gapack::jobs::Manifest;
use percent_encoding::{AsciiSet, NON_ALPHANUMERIC, utf8_percent_encode};
use serde::{Deserialize, Serialize};
use tower_http::services::ServeFile;
use utoipa::ToSchema;

use super::error::{ApiError, ErrorBody};
use super::jobs::JobId;
use super::{AppState, blocking};
use crate::Shared;
use crate::store::Caller;
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
pub fn manifest(shared: &Shared, who: &Caller, id: &str) -> Result<Manifest, ApiError> {
    let row = shared
        .store
        .get(who, id)?
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
            // The job is there; its state (cancelled or failed before it
            // wrote anything) has no files: a conflict, not a missing job.
            return Err(ApiError::new(
                StatusCode::CONFLICT,
                format!("job {id} finished without writing files"),
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
        (status = 404, description = "No such job", body = ErrorBody),
        (status = 409, description = "Not finished, or finished without writing files (cancelled or failed before it wrote any)", body = ErrorBody),
    ))]
async fn files(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
) -> Result<Json<FileList>, ApiError> {
    let list = blocking(move || {
        let manifest = manifest(&shared, &who, &id)?;
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
        // numpy's archive is a zip; VTK's XML with raw appended bytes is
        // not text a browser may show: bytes, as any unnamed type.
        "npz" => "application/zip",
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

/// The answer "no such file" for `name` of job `id`.
fn no_file(id: &str, name: &str) -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        format!("job {id} has no file {name:?}; GET /api/v1/jobs/{id}/files lists them"),
    )
}

/// One file of a finished job: only the names its manifest lists.
// Streamed from disk with `Content-Length`; one byte range (`Range`: 206,
// or 416 when outside the file; several ranges get the whole file); a
// strong `ETag` (size and modification time) and `Last-Modified` for
// conditional requests (`If-None-Match`, `If-Modified-Since`: 304;
// `If-Match`, `If-Unmodified-Since`: 412).
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
        (status = 409, description = "Not finished, or finished without writing files", body = ErrorBody),
        (status = 412, description = "If-Match or If-Unmodified-Since names another version", body = ErrorBody),
        (status = 416, description = "A range outside the file", body = ErrorBody,
            headers(("Content-Range" = String, description = "`bytes */SIZE`"))),
    ))]
async fn file(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
    Path(NameParam { name }): Path<NameParam>,
    request: Request,
) -> Result<Response, ApiError> {
    let path = blocking({
        let (id, name) = (id.clone(), name.clone());
        move || {
            let manifest = manifest(&shared, &who, &id)?;
            let known = name == gapack::jobs::MANIFEST_JSON || manifest.files.contains(&name);
            if !known || !inside(&name) {
                return Err(no_file(&id, &name));
            }
            Ok(job_dir(&shared, &id).join(&name))
        }
    })
    .await?;
    // Streamed from disk (a file of any size costs one read buffer). The
    // file served is `path` whatever the URI: of the request, only its
    // method and its headers (`Range`, `If-…`) count.
    let (parts, _) = request.into_parts();
    let served = ServeFile::new(&path)
        .ignore_multi_range_requests(true)
        .try_call(Request::from_parts(parts, Body::empty()))
        .await;
    let (mut parts, body) = match served {
        Ok(response) => response.into_parts(),
        // Removed since the manifest was read (the job was deleted).
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(no_file(&id, &name)),
        Err(e) => return Err(ApiError::internal(e)),
    };
    let refusal = match parts.status {
        StatusCode::OK | StatusCode::PARTIAL_CONTENT => {
            parts.headers.insert(
                header::CONTENT_TYPE,
                HeaderValue::from_static(content_type(&name)),
            );
            return Ok(Response::from_parts(parts, Body::new(body)));
        }
        StatusCode::NOT_MODIFIED => return Ok(Response::from_parts(parts, Body::empty())),
        StatusCode::NOT_FOUND => no_file(&id, &name),
        StatusCode::RANGE_NOT_SATISFIABLE => {
            let size = parts
                .headers
                .get(header::CONTENT_RANGE)
                .and_then(|v| v.to_str().ok())
                .and_then(|v| v.strip_prefix("bytes */"))
                .unwrap_or("?");
            ApiError::new(
                StatusCode::RANGE_NOT_SATISFIABLE,
                format!("the range asked for is not within {name:?} ({size} bytes)"),
            )
        }
        StatusCode::PRECONDITION_FAILED => ApiError::new(
            StatusCode::PRECONDITION_FAILED,
            format!("{name:?} is not the version If-Match or If-Unmodified-Since names"),
        ),
        status => ApiError::new(status, format!("{name:?} could not be served")),
    };
    // A refusal answers JSON like every other, keeping `Content-Range`.
    let mut response = refusal.into_response();
    if let Some(range) = parts.headers.remove(header::CONTENT_RANGE) {
        response.headers_mut().insert(header::CONTENT_RANGE, range);
    }
    Ok(response)
}

#[cfg(test)]
mod tests {
    use axum::http::{Method, StatusCode};

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
        assert_eq!(content_type("packing.npz"), "application/zip");
        assert_eq!(content_type("packing.vtp"), "application/octet-stream");
        assert_eq!(content_type("checkpoint.bin"), "application/octet-stream");
        assert_eq!(content_type("noextension"), "application/octet-stream");
    }

    /// A finished pack of [`SQUARE`] (with its pictures, packing.json, VTK
    /// and the DEM exports); its id and folder.
    async fn finished(server: &TestServer) -> (String, std::path::PathBuf) {
        let config = format!(
            "{SQUARE}[output]\nformats = [\"csv\", \"json\", \"svg\", \"png\", \"vtk\", \"lammps\", \"yade\", \"pfc\"]\n"
        );
        let id = server.submit("?kind=pack", &config).await;
        server.run_queued().await;
        let dir = server.data().join("jobs").join(&id);
        (id, dir)
    }

    #[tokio::test]
    async fn a_range_is_served_alone_with_its_place_in_the_file() {
        let server = TestServer::new();
        let (id, dir) = finished(&server).await;
        let url = format!("/api/v1/jobs/{id}/files/packing.csv");
        let whole = std::fs::read(dir.join("packing.csv")).expect("the csv");
        let n = whole.len();
        assert!(n > 1000, "{n}");
        for (range, from, to) in [
            ("bytes=10-49".to_owned(), 10, 49),
            ("bytes=0-0".to_owned(), 0, 0),
            (format!("bytes={}-", n - 7), n - 7, n - 1),
            ("bytes=-25".to_owned(), n - 25, n - 1),
            (format!("bytes=100-{}", n + 1000), 100, n - 1),
        ] {
            let r = server.call(Method::GET, &url, &[("range", &range)]).await;
            assert_eq!(r.status, StatusCode::PARTIAL_CONTENT, "{range}");
            assert_eq!(r.body, whole[from..=to], "{range}");
            assert_eq!(
                r.header("content-range"),
                Some(format!("bytes {from}-{to}/{n}").as_str()),
                "{range}"
            );
            assert_eq!(
                r.header("content-length"),
                Some((to - from + 1).to_string().as_str()),
                "{range}"
            );
            assert_eq!(r.header("content-type"), Some("text/csv; charset=utf-8"));
        }
        // Outside the file, or not a range: 416, saying the file's size.
        for range in [
            format!("bytes={n}-"),
            format!("bytes={}-{}", n + 5, n + 9),
            "bytes=9-3".to_owned(),
            "lines=1-2".to_owned(),
        ] {
            let r = server.call(Method::GET, &url, &[("range", &range)]).await;
            assert_eq!(r.status, StatusCode::RANGE_NOT_SATISFIABLE, "{range}");
            assert_eq!(
                r.header("content-range"),
                Some(format!("bytes */{n}").as_str()),
                "{range}"
            );
            assert_eq!(
                r.error(),
                format!("the range asked for is not within \"packing.csv\" ({n} bytes)")
            );
        }
        // Several ranges: the whole file.
        let r = server
            .call(Method::GET, &url, &[("range", "bytes=0-1,5-9")])
            .await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(r.body, whole);
        assert_eq!(r.header("accept-ranges"), Some("bytes"));
    }

    #[tokio::test]
    async fn a_file_known_to_the_client_is_not_sent_again() {
        let server = TestServer::new();
        let (id, _) = finished(&server).await;
        let url = format!("/api/v1/jobs/{id}/files/packing.svg");
        let first = server.get(&url).await;
        assert_eq!(first.status, StatusCode::OK);
        let etag = first.header("etag").expect("an ETag").to_owned();
        assert!(
            etag.starts_with('"') && etag.ends_with('"'),
            "strong: {etag}"
        );
        let modified = first.header("last-modified").expect("a date").to_owned();
        for (name, value) in [
            ("if-none-match", etag.clone()),
            ("if-none-match", format!("\"other\", W/{etag}")),
            ("if-none-match", "*".to_owned()),
            ("if-modified-since", modified.clone()),
        ] {
            let r = server.call(Method::GET, &url, &[(name, &value)]).await;
            assert_eq!(r.status, StatusCode::NOT_MODIFIED, "{name}: {value}");
            assert!(r.body.is_empty(), "{name}: {value}");
            assert_eq!(r.header("etag"), Some(etag.as_str()));
        }
        // Another version: the file.
        for (name, value) in [
            ("if-none-match", "\"not-this-one\"".to_owned()),
            (
                "if-modified-since",
                "Thu, 01 Jan 1970 00:00:01 GMT".to_owned(),
            ),
        ] {
            let r = server.call(Method::GET, &url, &[(name, &value)]).await;
            assert_eq!(r.status, StatusCode::OK, "{name}: {value}");
            assert_eq!(r.body, first.body, "{name}: {value}");
        }
        // A precondition on another version: 412, as JSON.
        let r = server
            .call(Method::GET, &url, &[("if-match", "\"not-this-one\"")])
            .await;
        assert_eq!(r.status, StatusCode::PRECONDITION_FAILED);
        assert!(r.error().contains("packing.svg"), "{}", r.error());
        let r = server.call(Method::GET, &url, &[("if-match", &etag)]).await;
        assert_eq!(r.status, StatusCode::OK);
        // A range of the version the client has.
        let r = server
            .call(
                Method::GET,
                &url,
                &[("if-match", &etag), ("range", "bytes=0-4")],
            )
            .await;
        assert_eq!(r.status, StatusCode::PARTIAL_CONTENT);
        assert_eq!(r.body, first.body[..5]);
    }

    #[tokio::test]
    async fn every_file_is_sent_whole_with_its_length_and_type() {
        let server = TestServer::new();
        let (id, dir) = finished(&server).await;
        let list = server.get(&format!("/api/v1/jobs/{id}/files")).await.json();
        let names: Vec<String> = list["files"]
            .as_array()
            .expect("files")
            .iter()
            .filter_map(|f| f["name"].as_str().map(str::to_owned))
            .collect();
        let mut seen = std::collections::BTreeSet::new();
        for name in &names {
            let kind = match name.rsplit('.').next() {
                Some("csv") => "text/csv; charset=utf-8",
                Some("json") => "application/json",
                Some("svg") => "image/svg+xml",
                Some("png") => "image/png",
                Some("vtk" | "txt" | "data" | "py" | "p4p" | "geo" | "dat") => {
                    "text/plain; charset=utf-8"
                }
                _ => "application/octet-stream",
            };
            let url = format!("/api/v1/jobs/{id}/files/{name}");
            let on_disk = std::fs::read(dir.join(name)).expect("on disk");
            let r = server.get(&url).await;
            assert_eq!(r.status, StatusCode::OK, "{name}");
            assert_eq!(r.header("content-type"), Some(kind), "{name}");
            assert_eq!(
                r.header("content-length"),
                Some(on_disk.len().to_string().as_str()),
                "{name}"
            );
            assert!(r.body == on_disk, "{name}");
            seen.insert(kind);
            // HEAD: the same headers, no body.
            let head = server.call(Method::HEAD, &url, &[]).await;
            assert_eq!(head.status, StatusCode::OK, "{name}");
            assert_eq!(head.header("content-length"), r.header("content-length"));
            assert_eq!(head.header("etag"), r.header("etag"));
            assert!(head.body.is_empty(), "{name}");
        }
        for kind in [
            "text/csv; charset=utf-8",
            "application/json",
            "image/svg+xml",
            "image/png",
            "text/plain; charset=utf-8",
        ] {
            assert!(seen.contains(kind), "{kind}: {names:?}");
        }
    }

    #[tokio::test]
    async fn a_listed_file_gone_from_disk_is_no_file() {
        let server = TestServer::new();
        let (id, dir) = finished(&server).await;
        std::fs::remove_file(dir.join("packing.svg")).expect("removed");
        let r = server
            .get(&format!("/api/v1/jobs/{id}/files/packing.svg"))
            .await;
        assert_eq!(r.status, StatusCode::NOT_FOUND);
        assert!(
            r.error().contains("has no file \"packing.svg\""),
            "{}",
            r.error()
        );
    }
}
