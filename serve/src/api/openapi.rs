//! The API's OpenAPI document (`GET /openapi.json`), generated from the
//! handlers' `#[utoipa::path]` annotations and the response types.

use std::sync::Arc;

use axum::Router;
use axum::http::header;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use utoipa::openapi::security::{HttpAuthScheme, HttpBuilder, SecurityScheme};
use utoipa::openapi::{Content, HeaderBuilder, ObjectBuilder, Ref, RefOr, ResponseBuilder, Type};
use utoipa::{Modify, OpenApi};

use super::error::{ApiError, ErrorBody};
use super::files::{FileEntry, FileList};
use super::jobs::{Accepted, JobPage, JobView, Links, Me, SummaryView, Validated};
use super::page::{Example, PackingView};
use super::submission::{Estimates, SubmitBody};
use crate::Shared;
use crate::store::{Role, State as JobState};
// The handlers' path descriptions, named without their module: utoipa
// would take a module prefix (`jobs::submit`) for the operation's tag.
use super::events::__path_events;
use super::files::{__path_file, __path_files};
use super::jobs::{
    __path_cancel, __path_delete, __path_list, __path_me, __path_status, __path_submit,
    __path_validate,
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
        submit, validate, list, status, events, cancel, delete, files, file, packing, examples, me
    ),
    components(schemas(
        ErrorBody,
        Accepted,
        Links,
        Validated,
        Estimates,
        JobView,
        SummaryView,
        JobPage,
        FileList,
        FileEntry,
        JobState,
        SubmitBody,
        PackingView,
        Example,
        Me,
        Role
    )),
    modifiers(&Guarded),
    security(("bearer" = []))
)]
struct ApiDoc;

/// What every operation shares, added to each: the bearer token's scheme
/// and its 401 (the guard in front of every route of the API), the 408 of
/// the request deadline and the 413 of a body declared over the limit
/// (layers in front of every route), and the 500 of a failed store, file
/// or task, or of a panic caught; and a file's bytes left without a schema.
struct Guarded;

impl Modify for Guarded {
    fn modify(&self, doc: &mut utoipa::openapi::OpenApi) {
        let scheme = HttpBuilder::new()
            .scheme(HttpAuthScheme::Bearer)
            .description(Some(
                "The token of a server started with --token-file (needed on any address but \
                 loopback); a server without one takes any request.",
            ))
            .build();
        doc.components
            .get_or_insert_with(Default::default)
            .add_security_scheme("bearer", SecurityScheme::Http(scheme));
        let error = || Content::new(Some(Ref::from_schema_name("ErrorBody")));
        let unauthorized = ResponseBuilder::new()
            .description("No token, or the wrong one (the server has a token)")
            .content("application/json", error())
            .header(
                "WWW-Authenticate",
                HeaderBuilder::new()
                    .schema(Some(ObjectBuilder::new().schema_type(Type::String)))
                    .description(Some("`Bearer`, when no token was given"))
                    .build(),
            )
            .build();
        let internal = ResponseBuilder::new()
            .description("The store, a file or a task failed (logged with its cause)")
            .content("application/json", error())
            .build();
        let timeout = ResponseBuilder::new()
            .description(
                "Not answered within the server's --request-timeout (a body too slow to \
                 arrive, or work too long); the connection is closed",
            )
            .content("application/json", error())
            .build();
        let too_large = ResponseBuilder::new()
            .description("A body declared (Content-Length) over 1 MiB, refused before it is read")
            .content("application/json", error())
            .build();
        for item in doc.paths.paths.values_mut() {
            for operation in [
                &mut item.get,
                &mut item.post,
                &mut item.delete,
                &mut item.put,
                &mut item.patch,
            ]
            .into_iter()
            .flatten()
            {
                let responses = &mut operation.responses.responses;
                responses
                    .entry("401".to_owned())
                    .or_insert_with(|| unauthorized.clone().into());
                responses
                    .entry("408".to_owned())
                    .or_insert_with(|| timeout.clone().into());
                responses
                    .entry("413".to_owned())
                    .or_insert_with(|| too_large.clone().into());
                responses
                    .entry("500".to_owned())
                    .or_insert_with(|| internal.clone().into());
                // A file (`*/*`) is any bytes, a range of a JSON file no
                // JSON: its media type carries no schema to check it by.
                for response in responses.values_mut() {
                    if let RefOr::T(response) = response
                        && let Some(RefOr::T(raw)) = response.content.get_mut("*/*")
                    {
                        raw.schema = None;
                    }
                }
            }
        }
    }
}

/// This API's OpenAPI document.
async fn openapi() -> Response {
    match document() {
        Ok(json) => ([(header::CONTENT_TYPE, "application/json")], json).into_response(),
        Err(e) => ApiError::internal(e).into_response(),
    }
}

/// The document's text, pretty-printed (the committed copy is this text).
fn document() -> Result<String, serde_json::Error> {
    ApiDoc::openapi().to_pretty_json()
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use axum::http::{Method, StatusCode};
    use serde_json::Value;

    use crate::api::testing::{NO_JOB, TestServer};

    /// Every operation the API's routers serve under `/api/v1` but the
    /// document's own route.
    const SERVED: [(&str, &str); 12] = [
        ("get", "/api/v1/examples"),
        ("get", "/api/v1/jobs"),
        ("post", "/api/v1/jobs"),
        ("delete", "/api/v1/jobs/{id}"),
        ("get", "/api/v1/jobs/{id}"),
        ("post", "/api/v1/jobs/{id}/cancel"),
        ("get", "/api/v1/jobs/{id}/events"),
        ("get", "/api/v1/jobs/{id}/files"),
        ("get", "/api/v1/jobs/{id}/files/{name}"),
        ("get", "/api/v1/jobs/{id}/packing"),
        ("get", "/api/v1/me"),
        ("post", "/api/v1/validate"),
    ];

    const FALLBACKS: [&str; 2] = [
        "no such endpoint; see /api/v1/openapi.json",
        "method not allowed on this endpoint; see /api/v1/openapi.json",
    ];

    fn documented(doc: &Value) -> BTreeSet<(String, String)> {
        doc["paths"]
            .as_object()
            .expect("paths")
            .iter()
            .flat_map(|(path, item)| {
                item.as_object()
                    .expect("a path item")
                    .keys()
                    .map(move |method| (method.clone(), path.clone()))
            })
            .collect()
    }

    fn refs<'a>(value: &'a Value, out: &mut Vec<&'a str>) {
        match value {
            Value::Object(map) => {
                for (key, v) in map {
                    match (key.as_str(), v) {
                        ("$ref", Value::String(r)) => out.push(r),
                        _ => refs(v, out),
                    }
                }
            }
            Value::Array(items) => items.iter().for_each(|v| refs(v, out)),
            _ => {}
        }
    }

    /// The committed copy of the document, for review of every change.
    const COMMITTED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/openapi.json");

    #[tokio::test]
    async fn the_served_document_is_the_committed_copy() {
        let server = TestServer::new();
        let reply = server.get("/api/v1/openapi.json").await;
        let served = reply.text();
        if std::env::var_os("GAPACK_BLESS").is_some() {
            std::fs::write(COMMITTED, format!("{served}\n")).expect("write serve/openapi.json");
        }
        let committed = std::fs::read_to_string(COMMITTED).unwrap_or_default();
        assert!(
            served.trim_end() == committed.trim_end(),
            "the served OpenAPI document differs from serve/openapi.json: review the change \
             (git diff after refreshing), then refresh the copy with \
             GAPACK_BLESS=1 cargo test -p gapack-serve the_served_document_is_the_committed_copy"
        );
    }

    #[tokio::test]
    async fn every_operation_declares_its_refusals_with_the_error_body() {
        let server = TestServer::new();
        let doc = server.get("/api/v1/openapi.json").await.json();
        let error = serde_json::json!({"$ref": "#/components/schemas/ErrorBody"});
        for (path, item) in doc["paths"].as_object().expect("paths") {
            for (method, op) in item.as_object().expect("an item") {
                let responses = op["responses"].as_object().expect("responses");
                for (status, response) in responses {
                    assert!(
                        response["description"].is_string(),
                        "{method} {path} {status}"
                    );
                    // Every refusal carries an ErrorBody.
                    if status.starts_with('4') {
                        assert_eq!(
                            response["content"]["application/json"]["schema"], error,
                            "{method} {path} {status}"
                        );
                    }
                }
                for status in ["401", "408", "413", "500"] {
                    assert!(responses.contains_key(status), "{method} {path} {status}");
                }
                if path.contains("{id}") {
                    assert!(responses.contains_key("404"), "{method} {path}");
                }
            }
        }
        assert_eq!(doc["security"], serde_json::json!([{"bearer": []}]));
        assert_eq!(
            doc["components"]["securitySchemes"]["bearer"]["scheme"],
            "bearer"
        );
        // The JSON submission refuses what it does not know, and says so.
        let body = &doc["components"]["schemas"]["SubmitBody"];
        assert_eq!(body["additionalProperties"], false, "{body}");
        assert_eq!(body["required"], serde_json::json!(["config"]));
        let kinds: Vec<&str> = gapack::jobs::JobKind::ALL
            .iter()
            .map(|k| k.name())
            .collect();
        let mut kinds = serde_json::json!(kinds);
        kinds
            .as_array_mut()
            .expect("kinds")
            .push(serde_json::Value::Null);
        assert_eq!(body["properties"]["kind"]["enum"], kinds);
    }

    #[tokio::test]
    async fn a_jobs_summary_is_described_field_by_field() {
        let server = TestServer::new();
        let doc = server.get("/api/v1/openapi.json").await.json();
        let summary = &doc["components"]["schemas"]["Summary"]["properties"];
        for field in ["files", "lines", "interrupted", "particles", "porosity"] {
            assert!(summary.get(field).is_some(), "{field}: {summary}");
        }
        let view = doc["components"]["schemas"]["JobView"]["properties"]["summary"].to_string();
        assert!(view.contains("#/components/schemas/Summary"), "{view}");
        // Particles that are not disks: their shape measures, described too.
        let shape = summary["particle_shape"].to_string();
        assert!(shape.contains("#/components/schemas/ShapeStats"), "{shape}");
        let stats = &doc["components"]["schemas"]["ShapeStats"]["properties"];
        for field in [
            "aspect",
            "sphericity",
            "roundness",
            "fabric",
            "mean_least_width",
        ] {
            assert!(stats.get(field).is_some(), "{field}: {stats}");
        }
    }

    #[tokio::test]
    async fn the_document_lists_every_route_the_router_serves() {
        let server = TestServer::new();
        let r = server.get("/api/v1/openapi.json").await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(r.header("content-type"), Some("application/json"));
        let doc = r.json();
        assert_eq!(doc["openapi"], "3.1.0");
        assert_eq!(doc["info"]["title"], "gapack service");
        let expected: BTreeSet<(String, String)> = SERVED
            .iter()
            .map(|(m, p)| ((*m).to_owned(), (*p).to_owned()))
            .collect();
        assert_eq!(documented(&doc), expected);
        // Each is served (not a fallback), and its other methods are not.
        for (method, path) in &expected {
            let uri = path
                .replace("{id}", NO_JOB)
                .replace("{name}", "packing.csv");
            let method: Method = method.to_uppercase().parse().expect("a method");
            let r = server.call(method.clone(), &uri, &[]).await;
            assert_ne!(r.status, StatusCode::METHOD_NOT_ALLOWED, "{method} {uri}");
            let error = serde_json::from_slice::<Value>(&r.body)
                .ok()
                .and_then(|v| v["error"].as_str().map(str::to_owned));
            assert!(
                !error.as_deref().is_some_and(|e| FALLBACKS.contains(&e)),
                "{method} {uri}: {error:?}"
            );
            for other in [
                Method::GET,
                Method::POST,
                Method::PUT,
                Method::DELETE,
                Method::PATCH,
            ] {
                let name = other.as_str().to_lowercase();
                if !expected.contains(&(name, path.clone())) {
                    let r = server.call(other.clone(), &uri, &[]).await;
                    assert_eq!(r.status, StatusCode::METHOD_NOT_ALLOWED, "{other} {uri}");
                }
            }
        }
        // Each operation is named once; each schema it refers to exists.
        let ids: BTreeSet<&str> = doc["paths"]
            .as_object()
            .expect("paths")
            .values()
            .flat_map(|item| item.as_object().expect("item").values())
            .map(|op| op["operationId"].as_str().expect("operationId"))
            .collect();
        assert_eq!(ids.len(), SERVED.len());
        let mut found = Vec::new();
        refs(&doc, &mut found);
        assert!(!found.is_empty());
        for r in found {
            let name = r
                .strip_prefix("#/components/schemas/")
                .expect("a schema ref");
            assert!(doc["components"]["schemas"][name].is_object(), "{r}");
        }
    }
}
