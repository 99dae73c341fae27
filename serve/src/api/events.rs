//! A job's events as Server-Sent Events (`GET /jobs/{id}/events`): from
//! the first (or after `Last-Event-ID`) to its final state, read from the
//! store and woken by the workers' news, ended by a server stop.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

use axum::Extension;
use axum::Router;
use axum::extract::State;
use axum::http::HeaderMap;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::routing::get;
use futures_util::Stream;
use serde_json::Value;
use utoipa::openapi::RefOr;
use utoipa::openapi::schema::{ObjectBuilder, Schema, Type};
use utoipa::{PartialSchema, ToSchema};

use super::error::{ApiError, ErrorBody};
use super::jobs::JobId;
use super::{AppState, blocking};
use crate::Shared;
use crate::store::{Caller, State as JobState};

/// The event stream's route.
pub fn router() -> Router<Arc<Shared>> {
    Router::new().route("/jobs/{id}/events", get(events))
}

/// One event of the stream, as the document describes it: its number
/// (`id:`), its kind (`event:`) and its JSON (`data:`).
pub struct StreamEvent;

impl PartialSchema for StreamEvent {
    fn schema() -> RefOr<Schema> {
        let text = |description: &str| {
            ObjectBuilder::new()
                .schema_type(Type::String)
                .description(Some(description))
        };
        ObjectBuilder::new()
            .schema_type(Type::Object)
            .property(
                "id",
                text("The event's number, from 1 (resume after it with Last-Event-ID)")
                    .pattern(Some("^[0-9]+$")),
            )
            .property(
                "event",
                text("Its kind: state, started, stage, progress, generation, warning, written, …"),
            )
            .property(
                "data",
                text("Its JSON: an object whose `event` is the kind")
                    .content_media_type("application/json"),
            )
            .required("id")
            .required("event")
            .required("data")
            .into()
    }
}

impl ToSchema for StreamEvent {}

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
            // The job first, then its events: a final state and its event
            // are written together, so a final job's events are all seen.
            let read = tokio::task::spawn_blocking(move || {
                let ended = shared
                    .store
                    .get(&shared.admin, &id)
                    .map(|r| r.map(|r| r.state.is_final()));
                let events = shared.store.events_after(&id, last, EVENT_BATCH);
                (ended, events)
            })
            .await;
            match read {
                Ok((Ok(Some(_)), Ok(events))) if !events.is_empty() => {
                    self.pending.extend(events);
                    continue;
                }
                // Running or queued: wait for more.
                Ok((Ok(Some(false)), Ok(_))) => {}
                // Ended with nothing after the resume point (a stream
                // resumed at or past its last event), deleted, or unreadable.
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

/// The number in a `Last-Event-ID` header (0, from the first, without
/// one): a whole number from 0 (events are numbered from 1).
fn last_event_id(headers: &HeaderMap) -> Result<i64, ApiError> {
    match headers.get("last-event-id") {
        None => Ok(0),
        Some(v) => v
            .to_str()
            .ok()
            .and_then(|s| s.trim().parse::<i64>().ok())
            .filter(|n| *n >= 0)
            .ok_or_else(|| ApiError::bad_request("Last-Event-ID must be an event number")),
    }
}

/// The job's events as Server-Sent Events, from the first (or after
/// `Last-Event-ID`) to its final state. Each event's `event:` is its kind
/// (`state`, `started`, `stage`, `progress`, `generation`, `warning`,
/// `written`, …), its `id:` its number, its `data:` its JSON.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/events",
    params(super::jobs::IdParam,
        ("Last-Event-ID" = Option<i64>, Header, nullable = false, minimum = 0,
            description = "Resume after this event number (0: from the first)")),
    responses(
        (status = 200, description = "The job's events, to its final state", content_type = "text/event-stream", body = StreamEvent),
        (status = 400, description = "A Last-Event-ID that is not an event number, or an id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
async fn events(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
    headers: HeaderMap,
) -> Result<Sse<impl Stream<Item = Result<SseEvent, Infallible>>>, ApiError> {
    let last = last_event_id(&headers)?;
    // Subscribe before the first read: no event falls between the two.
    let news = shared.events.subscribe();
    let shutdown = shared.shutdown.subscribe();
    let exists = blocking({
        let shared = Arc::clone(&shared);
        let id = id.clone();
        move || Ok(shared.store.get(&who, &id)?.is_some())
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

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use axum::http::{Method, StatusCode};

    use crate::api::testing::{NO_JOB, SQUARE, TestServer, sse_events};

    #[tokio::test]
    async fn a_stream_opened_before_the_run_follows_it_to_the_end() {
        let server = std::sync::Arc::new(TestServer::new());
        let id = server.submit("?kind=pack", SQUARE).await;
        let follower = tokio::spawn({
            let server = std::sync::Arc::clone(&server);
            let path = format!("/api/v1/jobs/{id}/events");
            async move { server.get(&path).await }
        });
        // The stream waits for news while the job is queued.
        tokio::time::sleep(Duration::from_millis(200)).await;
        assert!(!follower.is_finished());
        server.run_queued().await;
        let r = tokio::time::timeout(Duration::from_secs(60), follower)
            .await
            .expect("the stream ends with the job")
            .expect("the follower");
        assert_eq!(r.status, StatusCode::OK);
        let events = sse_events(r.text());
        let states: Vec<&str> = events
            .iter()
            .filter(|e| e.1 == "state")
            .filter_map(|e| e.2["state"].as_str())
            .collect();
        assert_eq!(states, ["queued", "running", "succeeded"], "{events:?}");
    }

    #[tokio::test]
    async fn a_stream_resumed_at_or_past_a_finished_job_s_last_event_ends() {
        let server = TestServer::new();
        let id = server.submit("?kind=pack", SQUARE).await;
        server.run_queued().await;
        let path = format!("/api/v1/jobs/{id}/events");
        let all = sse_events(server.get(&path).await.text());
        assert!(all.len() >= 3, "{all:?}");
        let last = all.last().map_or(0, |e| e.0);
        for from in [last, last + 5] {
            let from = from.to_string();
            let r = tokio::time::timeout(
                Duration::from_secs(3),
                server.call(Method::GET, &path, &[("last-event-id", &from)]),
            )
            .await
            .expect("the stream ends at once");
            assert_eq!(r.status, StatusCode::OK);
            assert!(sse_events(r.text()).is_empty(), "after {from}");
        }
        // One before the last: that last event alone.
        let one = (last - 1).to_string();
        let r = server
            .call(Method::GET, &path, &[("last-event-id", &one)])
            .await;
        assert_eq!(sse_events(r.text()).len(), 1);
    }

    #[tokio::test]
    async fn a_bad_resume_point_or_an_unknown_job_is_refused() {
        let server = TestServer::new();
        let id = server.submit("?kind=pack", SQUARE).await;
        for bad in ["abc", "1.5", "", "-1"] {
            let r = server
                .call(
                    Method::GET,
                    &format!("/api/v1/jobs/{id}/events"),
                    &[("last-event-id", bad)],
                )
                .await;
            assert_eq!(r.status, StatusCode::BAD_REQUEST, "{bad:?}");
            assert_eq!(r.error(), "Last-Event-ID must be an event number");
        }
        for unknown in [NO_JOB, "nope"] {
            let r = server.get(&format!("/api/v1/jobs/{unknown}/events")).await;
            assert_eq!(r.status, StatusCode::NOT_FOUND);
            assert_eq!(r.error(), format!("no job {unknown:?}"));
        }
    }
}
