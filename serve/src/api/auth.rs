//! Who is asking: every guarded route (the API and `/metrics`) needs
//! `Authorization: Bearer TOKEN`, the router puts [`require_token`] in
//! front of exactly those routes. A token is the `--token-file` one (it
//! signs in as the store's first user, `admin`) or a user's (`gapack user
//! add`), found by its SHA-256 (the store keeps no token in clear). A
//! loopback server with neither lets every request in as `admin`. The
//! caller goes on to the handlers as a request extension; each job they
//! read or change must be theirs (an admin's: any).

use axum::extract::{Request, State};
use axum::http::{HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::AppState;
use super::error::ApiError;
use crate::store::Caller;
use crate::users::token_hash;

/// Passes a request on, with its [`Caller`], if the server needs no token
/// or the request carries a live one; else 401, with `WWW-Authenticate:
/// Bearer` when no token was given at all. Refusals are logged.
pub async fn require_token(State(shared): AppState, mut request: Request, next: Next) -> Response {
    let given = request
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(|t| t.trim().to_owned());
    let caller = {
        let shared = std::sync::Arc::clone(&shared);
        tokio::task::spawn_blocking(move || -> Result<Option<Caller>, ApiError> {
            // A server with no token at all lets everyone in, as ever.
            if shared.token.is_none() && !shared.store.has_tokens()? {
                return Ok(Some(shared.admin.clone()));
            }
            match given {
                Some(given) => {
                    if let Some(token) = &shared.token
                        && same(given.as_bytes(), token.as_bytes())
                    {
                        return Ok(Some(shared.admin.clone()));
                    }
                    match shared.store.user_by_token(&token_hash(&given))? {
                        Some(caller) => Ok(Some(caller)),
                        None => Err(ApiError::new(
                            StatusCode::UNAUTHORIZED,
                            "wrong bearer token",
                        )),
                    }
                }
                None => Ok(None),
            }
        })
        .await
        .map_err(ApiError::internal)
        .and_then(|found| found)
    };
    match caller {
        Ok(Some(caller)) => {
            tracing::Span::current().record("user", caller.name.as_str());
            request.extensions_mut().insert(caller);
            next.run(request).await
        }
        Ok(None) => {
            tracing::warn!("refused: no bearer token");
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
        Err(e) => {
            let response = e.into_response();
            if response.status() == StatusCode::UNAUTHORIZED {
                tracing::warn!("refused: a bearer token no user holds");
            }
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

#[cfg(test)]
mod tests {
    use axum::http::{Method, StatusCode};

    use super::same;
    use crate::api::testing::{TOKEN, TestServer};

    #[tokio::test]
    async fn a_token_guards_the_api_and_metrics_but_not_health_nor_the_page() {
        let server = TestServer::with(|_| {}, Some(TOKEN));
        let right = format!("Bearer {TOKEN}");
        let spaced = format!("Bearer  {TOKEN} ");
        let lower = format!("bearer {TOKEN}");
        let missing = "this server needs a token: Authorization: Bearer TOKEN";
        for (authorization, status, error) in [
            (None, StatusCode::UNAUTHORIZED, Some(missing)),
            (
                Some(lower.as_str()),
                StatusCode::UNAUTHORIZED,
                Some(missing),
            ),
            (Some(TOKEN), StatusCode::UNAUTHORIZED, Some(missing)),
            (
                Some("Bearer wrong"),
                StatusCode::UNAUTHORIZED,
                Some("wrong bearer token"),
            ),
            (
                Some("Bearer s3cret-token-0123456780"),
                StatusCode::UNAUTHORIZED,
                Some("wrong bearer token"),
            ),
            (Some(right.as_str()), StatusCode::OK, None),
            (Some(spaced.as_str()), StatusCode::OK, None),
        ] {
            let headers: Vec<(&str, &str)> = authorization
                .iter()
                .map(|a| ("authorization", *a))
                .collect();
            let r = server.call(Method::GET, "/api/v1/jobs", &headers).await;
            assert_eq!(r.status, status, "{authorization:?}");
            match error {
                Some(error) => {
                    assert_eq!(r.error(), error, "{authorization:?}");
                    let challenge = (error == missing).then_some("Bearer");
                    assert_eq!(r.header("www-authenticate"), challenge);
                }
                None => assert!(r.json()["jobs"].is_array()),
            }
        }
        for path in [
            "/metrics",
            "/api/v1/examples",
            "/api/v1/openapi.json",
            "/api/v1/jobs/0123456789abcdef0123456789abcdef",
        ] {
            assert_eq!(
                server.get(path).await.status,
                StatusCode::UNAUTHORIZED,
                "{path}"
            );
        }
        for path in ["/healthz", "/", "/app.js", "/app.css"] {
            assert_eq!(server.get(path).await.status, StatusCode::OK, "{path}");
        }
        // A submission without the token is refused before it is read.
        let r = server
            .post("/api/v1/jobs", "application/toml", "not even TOML")
            .await;
        assert_eq!(r.status, StatusCode::UNAUTHORIZED);
    }

    #[tokio::test]
    async fn without_a_token_nothing_is_checked() {
        let server = TestServer::new();
        let r = server
            .call(
                Method::GET,
                "/api/v1/jobs",
                &[("authorization", "Bearer anything")],
            )
            .await;
        assert_eq!(r.status, StatusCode::OK);
        assert_eq!(server.get("/metrics").await.status, StatusCode::OK);
    }

    #[test]
    fn same_compares_whole_strings() {
        assert!(same(b"abc", b"abc"));
        assert!(same(b"", b""));
        assert!(!same(b"abc", b"abd"));
        assert!(!same(b"abc", b"ab"));
        assert!(!same(b"ab", b"abc"));
    }
}

/// Users and their jobs: each sees and acts on their own only.
#[cfg(test)]
mod owners {
    use axum::http::{Method, StatusCode};

    use crate::api::testing::{NO_JOB, SQUARE, TestServer, on_both_stores};

    on_both_stores!(
        another_user_s_job_is_no_job,
        another_user_s_job_is_answered_as_no_job_at_all,
        |_| {}
    );
    on_both_stores!(
        revoked,
        a_revoked_token_is_refused_at_the_next_request,
        |_| {}
    );
    on_both_stores!(shares, a_user_s_share_of_the_queue_and_ceiling_hold, |o| {
        o.max_queue_per_user = 2
    });

    async fn another_user_s_job_is_answered_as_no_job_at_all(server: TestServer) {
        let ana = server.add_user("ana", false);
        let bruno = server.add_user("bruno", false);
        let boss = server.add_user("boss", true);
        let anas = server.submit_as(&ana, SQUARE).await;
        server.run_queued().await;
        // Once users hold tokens, a request without one is refused.
        assert_eq!(
            server.get("/api/v1/jobs").await.status,
            StatusCode::UNAUTHORIZED
        );
        for (method, path) in [
            (Method::GET, "/api/v1/jobs/{}"),
            (Method::GET, "/api/v1/jobs/{}/events"),
            (Method::GET, "/api/v1/jobs/{}/files"),
            (Method::GET, "/api/v1/jobs/{}/files/packing.csv"),
            (Method::GET, "/api/v1/jobs/{}/packing"),
            (Method::POST, "/api/v1/jobs/{}/cancel"),
            (Method::DELETE, "/api/v1/jobs/{}"),
        ] {
            let theirs = server
                .call_as(&bruno, method.clone(), &path.replace("{}", &anas))
                .await;
            let nobodys = server
                .call_as(&bruno, method.clone(), &path.replace("{}", NO_JOB))
                .await;
            assert_eq!(theirs.status, StatusCode::NOT_FOUND, "{method} {path}");
            assert_eq!(
                theirs.error().replace(&anas, NO_JOB),
                nobodys.error(),
                "{method} {path}: the same answer as no job"
            );
            // The owner and an admin are served (the delete last).
            if method != Method::DELETE {
                for token in [&ana, &boss] {
                    let r = server
                        .call_as(token, method.clone(), &path.replace("{}", &anas))
                        .await;
                    assert!(r.status.is_success(), "{method} {path}: {}", r.status);
                }
            }
        }
        let listed = |r: crate::api::testing::Reply| -> Vec<String> {
            r.json()["jobs"]
                .as_array()
                .expect("jobs")
                .iter()
                .map(|j| j["id"].as_str().expect("id").to_owned())
                .collect()
        };
        assert!(listed(server.call_as(&bruno, Method::GET, "/api/v1/jobs").await).is_empty());
        assert_eq!(
            listed(server.call_as(&ana, Method::GET, "/api/v1/jobs").await),
            std::slice::from_ref(&anas)
        );
        assert_eq!(
            listed(server.call_as(&boss, Method::GET, "/api/v1/jobs").await),
            std::slice::from_ref(&anas)
        );
        let job = server
            .call_as(&boss, Method::GET, &format!("/api/v1/jobs/{anas}"))
            .await;
        assert_eq!(job.json()["owner"], "ana");
        // Who is signed in; the metrics are an admin's.
        let me = server
            .call_as(&bruno, Method::GET, "/api/v1/me")
            .await
            .json();
        assert_eq!(
            (me["name"].as_str(), me["role"].as_str()),
            (Some("bruno"), Some("user"))
        );
        assert_eq!(
            server.call_as(&bruno, Method::GET, "/metrics").await.status,
            StatusCode::FORBIDDEN
        );
        let metrics = server.call_as(&boss, Method::GET, "/metrics").await;
        assert!(
            metrics
                .text()
                .contains("gapack_user_jobs{user=\"ana\",state=\"succeeded\"} 1"),
            "{}",
            metrics.text()
        );
        let r = server
            .call_as(&bruno, Method::DELETE, &format!("/api/v1/jobs/{anas}"))
            .await;
        assert_eq!(r.status, StatusCode::NOT_FOUND);
        let r = server
            .call_as(&ana, Method::DELETE, &format!("/api/v1/jobs/{anas}"))
            .await;
        assert_eq!(r.status, StatusCode::NO_CONTENT);
    }

    async fn a_revoked_token_is_refused_at_the_next_request(server: TestServer) {
        let ana = server.add_user("ana", false);
        assert_eq!(
            server
                .call_as(&ana, Method::GET, "/api/v1/jobs")
                .await
                .status,
            StatusCode::OK
        );
        assert!(server.store(|s| s.revoke_user("ana")).expect("revoke"));
        let r = server.call_as(&ana, Method::GET, "/api/v1/jobs").await;
        assert_eq!(r.status, StatusCode::UNAUTHORIZED);
        assert_eq!(r.error(), "wrong bearer token");
    }

    async fn a_user_s_share_of_the_queue_and_ceiling_hold(server: TestServer) {
        let ana = server.add_user("ana", false);
        let bruno = server.add_user("bruno", false);
        server.submit_as(&ana, SQUARE).await;
        server.submit_as(&ana, SQUARE).await;
        let request = axum::http::Request::post("/api/v1/jobs?kind=pack")
            .header("content-type", "application/toml")
            .header("authorization", format!("Bearer {ana}"))
            .body(axum::body::Body::from(SQUARE))
            .expect("request");
        let r = server.send(request).await;
        assert_eq!(r.status, StatusCode::TOO_MANY_REQUESTS, "{}", r.text());
        assert!(r.error().contains("2 jobs waiting"), "{}", r.error());
        // Another user's share is their own.
        server.submit_as(&bruno, SQUARE).await;
        // A user's own particle ceiling, under the server's.
        let token = "gpk_small_user_token_0123456789";
        let hash = crate::users::token_hash(token);
        server
            .store(|s| s.add_user("small", crate::store::Role::User, &hash, None, Some(100)))
            .expect("user");
        let request = axum::http::Request::post("/api/v1/validate?kind=pack")
            .header("content-type", "application/toml")
            .header("authorization", format!("Bearer {token}"))
            .body(axum::body::Body::from(SQUARE))
            .expect("request");
        let r = server.send(request).await;
        assert_eq!(r.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", r.text());
        assert!(
            r.error().contains("over user small's ceiling of 100"),
            "{}",
            r.error()
        );
    }
}
