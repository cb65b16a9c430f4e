//! `GET /v1/events`: the caller's flights' changes as server-sent events (see
//! [`crate::events`]).
//!
//! An operator receives its own flights' events, the authority every flight's. Each event
//! has its id (`id:`), its kind (`event:` `planned`, `cancelled`, `replanned`, `diverted` or
//! `contingency`) and `data:` JSON `{"flight", "operator", "status", "zone" (when a zone
//! caused it), "plan"}`. Without `Last-Event-ID` the stream starts with the events that
//! follow the connection; with `Last-Event-ID: N` it first replays every stored event with an
//! id above `N` (`0`: all of them, read from the store page by page), then continues live,
//! with no gap and no repeat. Events of flights archived since (`--archive-after-days`) are
//! in the archive's files, not replayed: a first comment says so. A comment is sent every [`KEEP_ALIVE`] so that idle connections
//! stay open.

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

/// Events read from the store at a time when a listener catches up.
const PAGE: usize = 512;

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
    /// Whether events after the cursor may still be in the store only (the history is read
    /// until it is exhausted).
    behind: bool,
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
            .event(e.kind.as_str())
            .data(e.data(&w.airspace, w.offset))
    }

    /// Reads the next page of events after the cursor from the store (after a lag, or at the
    /// start). A failed read ends the catching up with a comment saying why.
    async fn refill(&mut self) {
        let app = Arc::clone(&self.app);
        let operator = (self.caller.role != crate::auth::Role::Authority)
            .then(|| self.caller.operator.clone());
        let after = self.cursor;
        let read = tokio::task::spawn_blocking(move || {
            app.state.reader.events_after(
                &app.state.world.airspace,
                after,
                operator.as_deref(),
                PAGE,
            )
        })
        .await;
        match read {
            Ok(Ok(events)) => {
                self.behind = events.len() == PAGE;
                self.backlog = events.into_iter().map(Arc::new).collect();
            }
            Ok(Err(e)) => {
                self.behind = false;
                self.note = Some(format!("reading the stored events failed: {e}"));
            }
            Err(_) => {
                self.behind = false;
                self.note = Some("reading the stored events failed".into());
            }
        }
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
            if self.behind {
                self.refill().await;
                if let Some(note) = self.note.take() {
                    return Some((Ok(SseEvent::default().comment(note)), self));
                }
                continue;
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
                    self.behind = true;
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
    // Events of archived flights are in the archive's files only: said, never skipped
    // without a word.
    let note = match last {
        Some(after) => {
            let archived =
                super::read_store(&app, |app| app.state.reader.archived_events_through()).await?;
            (archived > after).then(|| {
                format!(
                    "events after {after} up to {archived} of flights archived since are not \
                     replayed: they are in the archive's events-DAY.csv.gz files"
                )
            })
        }
        None => None,
    };
    // Subscribe before reading the history: together they miss nothing.
    let rx = app.state.events.subscribe();
    let listener = Listener {
        stop: app.stopping.subscribe(),
        cursor: last.unwrap_or_else(|| app.state.events.last_id()),
        behind: last.is_some(),
        app: Arc::clone(&app),
        caller,
        rx,
        backlog: VecDeque::new(),
        note,
    };
    let stream = futures_util::stream::unfold(listener, Listener::next);
    Ok(Sse::new(stream)
        .keep_alive(KeepAlive::new().interval(KEEP_ALIVE).text("keep-alive"))
        .into_response())
}
