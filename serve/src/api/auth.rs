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
