//! `GET /v1/events`: the caller's flights' changes as server-sent events (see
//! [`crate::events`]).
//!
//! An operator receives its own flights' events, the authority every flight's. Each event
//! has its id (`id:`), its kind (`event:` `planned`, `cancelled`, `replanned`, `diverted` or
//! `contingency`) and `data:` JSON `{"flight", "operator", "status", "zone" (when a zone
//! caused it), "plan"}`. Without `Last-Event-ID` the stream starts with the events that
//! follow the connection; with `Last-Event-ID: N` it first replays every held event with an
//! id above `N` (`0`: all held), then continues live, with no gap and no repeat. A comment
//! is sent every [`KEEP_ALIVE`] so that idle connections stay open.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::State as AxumState;
use axum::http::HeaderMap;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use tokio::sync::{broadcast, watch};

use crate::auth::Caller;
use crate::events::Event;

use super::{ApiError, App, Authed};

/// How often a keep-alive comment is sent on an idle stream.
pub const KEEP_ALIVE: Duration = Duration::from_secs(15);

/// One client's stream.
struct Listener {
    app: Arc<App>,
    caller: Caller,
    rx: broadcast::Receiver<Arc<Event>>,
    /// Events read from the history, to send before the channel's.
    backlog: VecDeque<Arc<Event>>,
    /// The highest id sent or passed over.
    cursor: u64,
    stop: watch::Receiver<bool>,
    /// A comment to send first.
    note: Option<String>,
}

impl Listener {
    fn visible(&self, e: &Event) -> bool {
        self.caller.may_read(&e.entry.operator)
    }

    fn sse(&self, e: &Event) -> SseEvent {
        let w = &self.app.state.world;
        SseEvent::default()
            .id(e.id.to_string())
            .event(e.kind)
            .data(e.data(&w.airspace, w.offset))
    }

    /// Reads the events after the cursor from the history (after a lag, or at the start).
    fn refill(&mut self) {
        let caller = &self.caller;
        self.backlog = self
            .app
            .state
            .events
            .after(self.cursor, |e| caller.may_read(&e.entry.operator))
            .into();
    }

    /// The next event of the stream; `None` when the service stops.
    async fn next(mut self) -> Option<(Result<SseEvent, Infallible>, Self)> {
        if let Some(note) = self.note.take() {
            return Some((Ok(SseEvent::default().comment(note)), self));
        }
        loop {
            if let Some(e) = self.backlog.pop_front() {
                if e.id <= self.cursor {
                    continue;
                }
                self.cursor = e.id;
                let event = self.sse(&e);
                return Some((Ok(event), self));
            }
            let received = tokio::select! {
                r = self.rx.recv() => r,
                _ = self.stop.wait_for(|stopping| *stopping) => return None,
            };
            match received {
                Ok(e) if e.id > self.cursor => {
                    self.cursor = e.id;
                    if self.visible(&e) {
                        let event = self.sse(&e);
                        return Some((Ok(event), self));
                    }
                }
                Ok(_) => {}
                // Fallen behind the channel: what it dropped is in the history.
                Err(broadcast::error::RecvError::Lagged(_)) => {
                    self.app.state.metrics.count_event_lag();
                    self.refill();
                }
                Err(broadcast::error::RecvError::Closed) => return None,
            }
        }
    }
}

pub(super) async fn stream(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    headers: HeaderMap,
) -> Result<Response, ApiError> {
    let last = headers
        .get("last-event-id")
        .map(|v| {
            v.to_str()
                .ok()
                .and_then(|s| s.trim().parse::<u64>().ok())
                .ok_or_else(|| {
                    ApiError::invalid(
                        "Last-Event-ID",
                        "must be the id of an event (a non-negative integer)",
                    )
                })
        })
        .transpose()?;
    // Subscribe before reading the history: together they miss nothing.
    let rx = app.state.events.subscribe();
    let events = &app.state.events;
    let (cursor, note) = match last {
        Some(id) => {
            let first = events.first_held().unwrap_or(events.last_id() + 1);
            let note = (id + 1 < first && id < events.last_id()).then(|| {
                format!(
                    "events {} to {} are no longer held (older than the retention time)",
                    id + 1,
                    first - 1
                )
            });
            (id, note)
        }
        None => (events.last_id(), None),
    };
    let mut listener = Listener {
        stop: app.stopping.subscribe(),
        app: Arc::clone(&app),
        caller,
        rx,
        backlog: VecDeque::new(),
        cursor,
        note,
    };
    if last.is_some() {
        listener.refill();
    }
    let stream = futures_util::stream::unfold(listener, Listener::next);
    Ok(Sse::new(stream)
        .keep_alive(KeepAlive::new().interval(KEEP_ALIVE).text("keep-alive"))
        .into_response())
}
