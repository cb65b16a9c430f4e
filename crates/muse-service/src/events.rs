//! What happens to flights, as a stream of events (`GET /v1/events`, server-sent events).
//!
//! Every acknowledged change of a flight is an [`Event`] of one [`EventKind`]: `planned` (a
//! request accepted), `cancelled` (by its operator, or by a zone announcement: reason
//! `zone_announced`), `replanned`, `diverted`, `contingency`
//! (docs/reference.md#zones-announced-during-the-day). A rejected request is no event.
//!
//! # Ids
//!
//! Event ids count the events from 1, in the order the planner task decided them: a planned
//! flight gives one, a cancellation one, a zone announcement one per flight it changed, in the
//! order it replanned them. Each event is a row of the store's `events` table, written in the
//! same transaction as the change it reports, so an id names the same event for the life of
//! the store (a client resumes with `Last-Event-ID`, across restarts too).
//!
//! # History and live events
//!
//! The history is the store: a listener resuming from an id reads the events after it from
//! there, page by page. New events go to every listener over a broadcast channel, *after*
//! their transaction is durable. A listener subscribes first and then reads the history:
//! together they miss nothing, and the ids tell it what it has already seen. A listener too
//! slow for the channel falls back to the history. Memory holds no history at all.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use muse_model::plan::FateKind;
use muse_model::{Airspace, Instant, UtcOffset};
use serde::Serialize;
use tokio::sync::broadcast;

use crate::flights::{FlightEntry, FlightView};

/// Events a listener may fall behind by before it reads the history instead.
pub const LIVE_CAPACITY: usize = 4_096;

/// What changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// A request accepted with a plan.
    Planned,
    /// Cancelled: by its operator, or by a zone announcement (the event names the zone).
    Cancelled,
    /// Replanned after a zone announcement.
    Replanned,
    /// Diverted to another station after a zone announcement.
    Diverted,
    /// Left in contingency by a zone announcement.
    Contingency,
}

impl EventKind {
    /// Every kind, in the order documented.
    pub const ALL: [EventKind; 5] = [
        EventKind::Planned,
        EventKind::Cancelled,
        EventKind::Replanned,
        EventKind::Diverted,
        EventKind::Contingency,
    ];

    /// The spelling in the stream (`event:`) and in the store.
    pub const fn as_str(self) -> &'static str {
        match self {
            EventKind::Planned => "planned",
            EventKind::Cancelled => "cancelled",
            EventKind::Replanned => "replanned",
            EventKind::Diverted => "diverted",
            EventKind::Contingency => "contingency",
        }
    }

    /// Parses the spelling.
    pub fn parse(text: &str) -> Option<EventKind> {
        EventKind::ALL.into_iter().find(|k| k.as_str() == text)
    }

    /// The event of a zone's outcome.
    pub const fn of_fate(kind: FateKind) -> EventKind {
        match kind {
            FateKind::Replanned => EventKind::Replanned,
            FateKind::Diverted => EventKind::Diverted,
            FateKind::Cancelled => EventKind::Cancelled,
            FateKind::Contingency => EventKind::Contingency,
        }
    }
}

/// One change of one flight.
#[derive(Clone, Debug)]
pub struct Event {
    /// Its id (see the module docs).
    pub id: u64,
    /// What changed.
    pub kind: EventKind,
    /// When it happened (service clock).
    pub at: Instant,
    /// The zone announcement that caused it, if one did.
    pub zone: Option<String>,
    /// The flight just after the change.
    pub entry: Arc<FlightEntry>,
}

#[derive(Serialize)]
struct EventData<'a> {
    flight: &'a str,
    operator: &'a str,
    status: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    zone: Option<&'a str>,
    plan: &'a FlightView,
}

impl Event {
    /// The event's `data:`: `{"flight", "operator", "status", "zone" (when a zone caused
    /// it), "plan"}`, `plan` being the flight as `GET /v1/flights/{id}` showed it then.
    pub fn data(&self, airspace: &Airspace, offset: UtcOffset) -> String {
        let view = self.entry.view(airspace, offset);
        let data = EventData {
            flight: &self.entry.request.id,
            operator: &self.entry.operator,
            status: &view.line.status,
            zone: self.zone.as_deref(),
            plan: &view,
        };
        // Plain strings and numbers: serialising cannot fail.
        serde_json::to_string(&data).unwrap_or_default()
    }
}

/// The channel new events go out on, and the id of the last one (see the module docs).
#[derive(Debug)]
pub struct Events {
    /// The id of the last event published (0: none yet).
    last: AtomicU64,
    live: broadcast::Sender<Arc<Event>>,
}

impl Default for Events {
    fn default() -> Self {
        Events::new(LIVE_CAPACITY)
    }
}

impl Events {
    /// No events yet; a listener may fall behind the live ones by `buffer` (at least 1).
    pub fn new(buffer: usize) -> Self {
        Events {
            last: AtomicU64::new(0),
            live: broadcast::channel(buffer.max(1)).0,
        }
    }

    /// A listener for the events published from now on.
    pub fn subscribe(&self) -> broadcast::Receiver<Arc<Event>> {
        self.live.subscribe()
    }

    /// Sends events (ids increasing, above every one published), durable in the store, to the
    /// listeners.
    pub fn publish(&self, events: impl IntoIterator<Item = Arc<Event>>) {
        for event in events {
            debug_assert!(event.id > self.last_id());
            self.last.store(event.id, Ordering::Release);
            // No listener is not an error.
            let _ = self.live.send(event);
        }
    }

    /// Sets the id of the last event the store holds (at start).
    pub fn restore(&self, last: u64) {
        self.last.store(last, Ordering::Release);
    }

    /// The id of the last event (0: none yet).
    pub fn last_id(&self) -> u64 {
        self.last.load(Ordering::Acquire)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_spelt_as_documented() {
        for k in EventKind::ALL {
            assert_eq!(EventKind::parse(k.as_str()), Some(k));
        }
        assert_eq!(EventKind::parse("landed"), None);
        assert_eq!(
            EventKind::of_fate(FateKind::Diverted).as_str(),
            FateKind::Diverted.as_str()
        );
    }
}
