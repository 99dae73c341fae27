//! What a submission asks (`POST /jobs`, `POST /validate`): a
//! [`Submission`] extracted from a TOML body with query parameters or from
//! a JSON body, planned as a worker will plan it and checked against the
//! server's rules and ceilings; and the [`Estimates`] a validation reports.

use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, QueryRejection};
use axum::extract::{FromRequest, FromRequestParts, Query, Request};
use axum::http::{HeaderMap, StatusCode, header};
use gapack::jobs::{JobKind, Plan, Request as JobRequest};
use serde::{Deserialize, Serialize};
use utoipa::openapi::schema::{Object, ObjectBuilder, SchemaType, Type};
use utoipa::{IntoParams, ToSchema};

use super::MAX_BODY;
use super::error::ApiError;
use crate::Shared;
use crate::store::Caller;
use crate::worker::ORIGIN;

/// Query parameters of a submission (with a TOML body; a JSON body's own
/// fields take precedence, but these are checked whichever body comes).
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct SubmitQuery {
    /// `pack`, `optimise`, `layer`, `compare`, `stability` or `sweep`
    /// [default: sweep with a [sweep] table, else optimise with an
    /// [optimise] one, else layer with a [layering] one, else pack].
    #[param(schema_with = kind_schema)]
    kind: Option<String>,
    /// Overrides the config's seed.
    #[param(nullable = false)]
    seed: Option<u64>,
    /// Run over the config's and the server's limits (only if the server
    /// was started with `--force`; else 403).
    #[param(nullable = false)]
    force: Option<bool>,
}

/// A submission as JSON: a property not listed here is refused (400).
#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SubmitBody {
    /// The job kind (see the query parameter `kind`).
    #[schema(schema_with = kind_or_null_schema)]
    kind: Option<String>,
    /// The config, TOML text.
    config: String,
    /// Overrides the config's seed.
    #[serde(default, deserialize_with = "whole_number")]
    seed: Option<u64>,
    /// Run over the limits (see the query parameter `force`).
    force: Option<bool>,
}

/// A JSON whole number from 0 to 2⁶⁴ − 1, or null: JSON (and the schema's
/// `integer`) make no difference between `7` and `7.0`, so neither does this.
fn whole_number<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
    /// The largest float below 2⁶⁴ is the last one a u64 holds.
    const ABOVE_U64: f64 = 18_446_744_073_709_551_616.0;
    let Some(n) = Option::<serde_json::Number>::deserialize(d)? else {
        return Ok(None);
    };
    if let Some(n) = n.as_u64() {
        return Ok(Some(n));
    }
    match n.as_f64() {
        Some(f) if f.fract() == 0.0 && (0.0..ABOVE_U64).contains(&f) => Ok(Some(f as u64)),
        _ => Err(serde::de::Error::custom(format!(
            "seed {n}: expected a whole number from 0 to 18446744073709551615"
        ))),
    }
}

/// The schema of a job kind: one of the kinds' names.
pub fn kind_schema() -> Object {
    ObjectBuilder::new()
        .schema_type(Type::String)
        .enum_values(Some(JobKind::ALL.map(JobKind::name)))
        .build()
}

/// The schema of a JSON submission's kind: a kind's name, or null (the
/// config's natural kind, as when absent).
pub fn kind_or_null_schema() -> Object {
    let names = JobKind::ALL.map(|k| serde_json::Value::from(k.name()));
    ObjectBuilder::new()
        .schema_type(SchemaType::from_iter([Type::String, Type::Null]))
        .enum_values(Some(names.into_iter().chain([serde_json::Value::Null])))
        .description(Some(
            "The job kind (see the query parameter `kind`); null or absent: the config's own",
        ))
        .build()
}

/// A submission, whichever way it came.
pub struct Submission {
    /// The kind asked for (`None`: the config's natural kind).
    kind: Option<JobKind>,
    /// The config, TOML text.
    pub config: String,
    /// The seed asked for (`None`: the config's).
    pub seed: Option<u64>,
    /// Whether to run over the limits.
    pub force: bool,
}

impl<S: Send + Sync> FromRequest<S> for Submission {
    type Rejection = ApiError;

    /// A TOML body with query parameters, or a JSON body. The body's
    /// fault (too large) is told first, then the query's, then the media
    /// type's, then the content's.
    async fn from_request(request: Request, state: &S) -> Result<Self, ApiError> {
        let (mut parts, body) = request.into_parts();
        let query = Query::<SubmitQuery>::from_request_parts(&mut parts, state).await;
        let headers = parts.headers.clone();
        let body = Bytes::from_request(Request::from_parts(parts, body), state).await;
        Submission::read(&headers, query, body)
    }
}

impl Submission {
    fn read(
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
        let Query(query) = query.map_err(bad_query)?;
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
        // The query's kind is checked even when a JSON body names its own.
        let query_kind = query.kind.as_deref().map(job_kind).transpose()?;
        match media.as_deref() {
            Some("application/toml") => Ok(Submission {
                kind: query_kind,
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
                        .as_deref()
                        .map(job_kind)
                        .transpose()?
                        .or(query_kind),
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

    /// Plan the submission as a worker will, and check it against the
    /// server's rules.
    pub fn plan(&self, shared: &Shared, who: &Caller) -> Result<Plan, ApiError> {
        if self.force && !shared.limits.force {
            return Err(ApiError::new(
                StatusCode::FORBIDDEN,
                "force is refused: this server was not started with --force",
            ));
        }
        let request = JobRequest {
            seed: self.seed,
            force: self.force,
            ..JobRequest::asking(self.kind)
        };
        let plan = Plan::load(&self.config, ORIGIN, &request)?;
        if plan.config.output.dir.is_some() {
            return Err(ApiError::config(
                "output.dir",
                "the server chooses where a job's files go; remove dir from [output]".to_owned(),
                gapack::config::key_location(&self.config, ORIGIN, "output.dir"),
            ));
        }
        if !self.force {
            ceilings(shared, who, &plan)?;
        }
        Ok(plan)
    }
}

/// A refused query string.
pub fn bad_query(e: QueryRejection) -> ApiError {
    ApiError::bad_request(format!("bad query: {}", e.body_text()))
}

/// The job kind `name` names.
fn job_kind(name: &str) -> Result<JobKind, ApiError> {
    JobKind::named(name).ok_or_else(|| {
        ApiError::bad_request(format!(
            "unknown job kind {name:?}; valid: {}",
            JobKind::names()
        ))
    })
}

/// The server's ceilings, which no config can raise: held against the
/// largest scene and the most memory of every run the job makes
/// ([`Plan::largest`]: every well, window, study point, and the
/// optimise or layering search), whatever the config's `[limits]` allow.
fn ceilings(shared: &Shared, who: &Caller, plan: &Plan) -> Result<(), ApiError> {
    let limits = &shared.limits;
    // A user's own ceiling, never above the server's.
    let max_particles = who
        .max_particles
        .and_then(|n| u64::try_from(n).ok())
        .map_or(limits.max_particles, |n| n.min(limits.max_particles));
    let largest = plan.largest();
    let mb = |bytes: f64| bytes / (1024.0 * 1024.0);
    if largest.max_disks > max_particles as f64 {
        let whose = if max_particles < limits.max_particles {
            format!("user {}'s", who.name)
        } else {
            "this server's".to_owned()
        };
        return Err(ApiError::config(
            "limits.max_particles",
            format!(
                "{} could hold {:.0} disks, over {whose} ceiling of {max_particles}",
                largest.max_disks_in, largest.max_disks
            ),
            None,
        ));
    }
    if largest.peak_bytes > limits.max_memory_bytes {
        return Err(ApiError::config(
            "limits.max_memory_mb",
            format!(
                "{} would need about {:.0} MB, over this server's ceiling of {:.0} MB",
                largest.peak_bytes_in,
                mb(largest.peak_bytes),
                mb(limits.max_memory_bytes)
            ),
            None,
        ));
    }
    Ok(())
}

/// A job's estimates: its first scene's, and the largest over its runs.
#[derive(Debug, Serialize, ToSchema)]
pub struct Estimates {
    /// Disks a packing of the first scene is expected to hold.
    disks: f64,
    /// The most disks the first scene could hold.
    max_disks: f64,
    /// Peak memory of a packing of the first scene (bytes, an upper bound).
    peak_bytes: f64,
    /// The most disks the scene of any run could hold (every well, window
    /// and study point): what `--max-particles` is held against.
    largest_max_disks: f64,
    /// Which scene that is (`the scene`, `well "a"`, `point width=600: the scene`).
    largest_max_disks_in: String,
    /// The most memory any run is estimated to need (bytes, an upper
    /// bound; a packing's or a search's): what `--max-memory-mb` is held against.
    largest_peak_bytes: f64,
    /// What needs it (`the scene`, `the layering search on the scene`, …).
    largest_peak_bytes_in: String,
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
    /// The estimates of `plan`'s first scene, and the largest over its runs.
    pub fn of(plan: &Plan) -> Self {
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
                .and_then(|o| search(o.stop.population, o.stop.generations)),
            JobKind::Layer => plan
                .config
                .layering
                .as_ref()
                .and_then(|l| search(l.stop.population, l.stop.generations)),
            _ => None,
        };
        let disks = scene.estimated_disks();
        let largest = plan.largest();
        Estimates {
            disks,
            max_disks: scene.max_disks(),
            peak_bytes: gapack::estimated_peak_bytes(scene),
            largest_max_disks: largest.max_disks,
            largest_max_disks_in: largest.max_disks_in,
            largest_peak_bytes: largest.peak_bytes,
            largest_peak_bytes_in: largest.peak_bytes_in,
            packings,
            seconds: packings.map(|n| disks * n as f64 / GUIDE_DISKS_PER_SECOND),
        }
    }
}

#[cfg(test)]
mod tests {
    use axum::http::StatusCode;

    use crate::api::testing::{Reply, SQUARE, TestServer};

    #[tokio::test]
    async fn config_faults_are_located_as_the_cli_locates_them() {
        let server = TestServer::new();
        let toml = "application/toml";
        let r = server
            .post(
                "/api/v1/jobs?kind=pack",
                toml,
                SQUARE.replace("width = 20", "width = 20 mm"),
            )
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        let v = r.json();
        assert!(r.error().starts_with("config.toml:4:9: "), "{}", r.error());
        assert_eq!(
            (&v["line"], &v["column"], &v["key"]),
            (&4.into(), &9.into(), &"domain.width".into())
        );
        assert!(
            v["message"]
                .as_str()
                .expect("message")
                .contains("TOML syntax error")
        );
        let r = server
            .post(
                "/api/v1/jobs",
                toml,
                SQUARE.replace("width = 20", "width = -1"),
            )
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        assert_eq!(r.json()["key"], "domain.width");
        let r = server
            .post("/api/v1/jobs?kind=optimise", toml, SQUARE)
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        assert!(
            r.error().contains("missing table [optimise]"),
            "{}",
            r.error()
        );
        // The server chooses where files go.
        let r = server
            .post(
                "/api/v1/jobs?kind=pack",
                toml,
                format!("{SQUARE}[output]\ndir = \"/tmp/elsewhere\"\n"),
            )
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        let v = r.json();
        assert_eq!(
            r.error(),
            "config.toml:9:1: output.dir: the server chooses where a job's files go; remove dir from [output]"
        );
        assert_eq!(
            (&v["line"], &v["column"], &v["key"]),
            (&9.into(), &1.into(), &"output.dir".into())
        );
        assert_eq!(
            v["message"],
            "the server chooses where a job's files go; remove dir from [output]"
        );
        assert_eq!(
            server.get("/api/v1/jobs").await.json()["jobs"],
            serde_json::json!([])
        );
    }

    /// A 10 m square of 1 mm disks with the `[limits]` lines given.
    fn big_square(limits: &str) -> String {
        format!(
            "[domain]\nshape = \"rectangle\"\nwidth = 10000\nheight = 10000\n[grading]\nconstant = 1.0\n[limits]\n{limits}"
        )
    }

    /// Submit [`big_square`] with `limits` as a pack job.
    async fn submit_big(server: &TestServer, limits: &str) -> Reply {
        server
            .post(
                "/api/v1/jobs?kind=pack",
                "application/toml",
                big_square(limits),
            )
            .await
    }

    #[tokio::test]
    async fn a_config_over_its_own_limits_is_told_how_to_go_over_them_here() {
        let server = TestServer::new();
        let r = submit_big(&server, "max_particles = 1000\n").await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        let v = r.json();
        let hint = ", or submit with \"force\": true to go ahead";
        assert_eq!(v["key"], "limits.max_particles");
        for text in [
            r.error(),
            v["message"].as_str().expect("message").to_owned(),
        ] {
            assert!(text.ends_with(hint), "{text}");
            assert!(!text.contains("--force"), "{text}");
        }
    }

    #[tokio::test]
    async fn the_servers_ceilings_hold_unless_it_allows_force() {
        let server = TestServer::new();
        let r = submit_big(
            &server,
            "max_particles = 1000000000\nmax_memory_mb = 100000\n",
        )
        .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        let v = r.json();
        assert_eq!(v["key"], "limits.max_particles");
        assert!(
            r.error()
                .starts_with("config.toml: limits.max_particles: the scene could hold "),
            "{}",
            r.error()
        );
        assert!(
            r.error().ends_with("over this server's ceiling of 2000000"),
            "{}",
            r.error()
        );
        assert_eq!(v.get("line"), None);
        let r = server
            .post(
                "/api/v1/jobs?kind=pack&force=true",
                "application/toml",
                SQUARE,
            )
            .await;
        assert_eq!(r.status, StatusCode::FORBIDDEN);
        assert_eq!(
            r.error(),
            "force is refused: this server was not started with --force"
        );
        // A lower memory ceiling, then a server that allows force.
        let server = TestServer::with(|o| o.max_memory_mb = 0, None);
        let r = server
            .post("/api/v1/validate", "application/toml", SQUARE)
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY);
        assert_eq!(r.json()["key"], "limits.max_memory_mb");
        let server = TestServer::with(
            |o| {
                o.force = true;
                o.max_memory_mb = 0;
            },
            None,
        );
        let r = server
            .post("/api/v1/validate?force=true", "application/toml", SQUARE)
            .await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
    }

    /// A 10 mm square of 0.5 mm disks swept over widths up to 600 mm.
    const WIDE_STUDY: &str = "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 300\n[grading]\nconstant = 0.5\n[sweep]\n\"domain.width\" = [10, 100, 600]\n";

    #[tokio::test]
    async fn every_point_of_a_study_is_held_to_the_ceilings() {
        let server = TestServer::with(|o| o.max_particles = 100_000, None);
        // The first point alone is well under the ceiling.
        let first = WIDE_STUDY.split("[sweep]").next().expect("the scene");
        let r = server
            .post("/api/v1/validate?kind=pack", "application/toml", first)
            .await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        let r = server
            .post("/api/v1/jobs", "application/toml", WIDE_STUDY)
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", r.text());
        let v = r.json();
        assert_eq!(v["key"], "limits.max_particles");
        let message = v["message"].as_str().expect("message");
        // 600 × 300 mm over the area of a 0.5 mm disk, as the scene alone is refused.
        let alone = server
            .post(
                "/api/v1/validate?kind=pack",
                "application/toml",
                first.replace("width = 10", "width = 600"),
            )
            .await;
        assert_eq!(alone.status, StatusCode::UNPROCESSABLE_ENTITY);
        let disks = alone.json()["message"]
            .as_str()
            .expect("message")
            .trim_start_matches("the scene could hold ")
            .split(' ')
            .next()
            .expect("a number")
            .to_owned();
        assert!(disks.parse::<f64>().expect("disks") > 900_000.0, "{disks}");
        assert_eq!(
            message,
            format!(
                "point width=600: the scene could hold {disks} disks, over this server's ceiling of 100000"
            )
        );
        assert_eq!(
            server.get("/api/v1/jobs").await.json()["jobs"],
            serde_json::json!([])
        );
        // The estimates name the largest run.
        let server = TestServer::new();
        let r = server
            .post("/api/v1/validate", "application/toml", WIDE_STUDY)
            .await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        let e = &r.json()["estimates"];
        assert_eq!(e["largest_max_disks_in"], "point width=600: the scene");
        assert_eq!(
            e["largest_max_disks"]
                .as_f64()
                .expect("disks")
                .round()
                .to_string(),
            disks
        );
        assert!(e["largest_max_disks"].as_f64() > e["max_disks"].as_f64());
    }

    /// [`SQUARE`] laid out by a layering search of `population` genomes,
    /// with the `[limits]` lines given.
    fn layering(population: u64, limits: &str) -> String {
        format!(
            "{SQUARE}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\nprofile = \"linear\"\npopulation = {population}\n[limits]\n{limits}"
        )
    }

    #[tokio::test]
    async fn a_layering_search_is_held_to_the_memory_ceiling() {
        let server = TestServer::with(|o| o.max_memory_mb = 64, None);
        let r = server
            .post("/api/v1/validate", "application/toml", layering(100, ""))
            .await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        // Within the config's own limit (4096 MB), over the server's.
        let r = server
            .post("/api/v1/jobs", "application/toml", layering(20_000, ""))
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", r.text());
        let v = r.json();
        assert_eq!(v["key"], "limits.max_memory_mb");
        let message = v["message"].as_str().expect("message");
        assert!(
            message.starts_with("the layering search on the scene would need about "),
            "{message}"
        );
        let mb: f64 = message
            .trim_start_matches("the layering search on the scene would need about ")
            .split(' ')
            .next()
            .and_then(|n| n.parse().ok())
            .expect("MB");
        assert!(mb > 64.0 && mb < 4096.0, "{message}");
        assert!(
            message.ends_with("over this server's ceiling of 64 MB"),
            "{message}"
        );
    }

    #[tokio::test]
    async fn a_configs_limits_do_not_lift_the_servers_ceilings() {
        let server = TestServer::new();
        // About 3.8 GB: over the config's default limit, which it raises.
        let big = layering(200_000, "max_memory_mb = 100000\n");
        let r = server
            .post("/api/v1/validate", "application/toml", big.clone())
            .await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", r.text());
        let v = r.json();
        assert_eq!(v["key"], "limits.max_memory_mb");
        assert!(
            r.error().ends_with("over this server's ceiling of 1024 MB"),
            "{}",
            r.error()
        );
        // Swept, the search is held to the ceiling at its largest point.
        let study = format!(
            "{}[sweep]\n\"layering.population\" = [10, 200000]\n",
            layering(10, "max_memory_mb = 100000\n")
        );
        let r = server.post("/api/v1/jobs", "application/toml", study).await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", r.text());
        assert!(
            r.error().starts_with(
                "config.toml: limits.max_memory_mb: point population=200000: the layering search on the scene would need about "
            ),
            "{}",
            r.error()
        );
    }

    #[tokio::test]
    async fn validate_plans_and_estimates_without_queueing() {
        let server = TestServer::new();
        let config = format!(
            "{SQUARE}[optimise]\ntarget_porosity = 0.95\npopulation = 8\ngenerations = 4\nstagnation = 100\n"
        );
        let r = server
            .post("/api/v1/validate", "application/toml", config)
            .await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        let v = r.json();
        assert_eq!((&v["kind"], &v["seed"]), (&"optimise".into(), &3.into()));
        assert!(!v["plan"].as_array().expect("plan").is_empty());
        assert!(!v["identity"].as_str().expect("identity").is_empty());
        let e = &v["estimates"];
        // 8 initial members, then under 3 × 8 packings per generation for 4.
        assert_eq!(e["packings"], 8 + 3 * 8 * 4);
        let disks = e["disks"].as_f64().expect("disks");
        assert!(disks > 10.0 && disks <= e["max_disks"].as_f64().expect("max"));
        assert!((e["seconds"].as_f64().expect("seconds") - disks * 104.0 / 1e6).abs() < 1e-9);
        let r = server
            .post("/api/v1/validate?kind=pack", "application/toml", SQUARE)
            .await;
        assert_eq!(r.json()["estimates"]["packings"], 1);
        assert_eq!(
            server.get("/api/v1/jobs").await.json()["jobs"],
            serde_json::json!([])
        );
    }
}
