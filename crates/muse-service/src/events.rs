//! What happens to flights, as a stream of events (`GET /v1/events`, server-sent events).
//!
//! Every acknowledged change of a flight is an [`Event`]: `planned` (a request accepted),
//! `cancelled` (by its operator, or by a zone announcement: reason `zone_announced`),
//! `replanned`, `diverted`, `contingency` (SPEC §11). A rejected request is no event.
//!
//! # Ids
//!
//! Event ids count the events in the order of the store's log, from 1: a planned flight's
//! record gives one, a cancellation one, a zone announcement one per flight it changed, in
//! the order it replanned them. The planner task numbers them as it appends the records,
//! and a restart numbers them again while it replays the log, so an id names the same event
//! before and after a restart (and a client can resume with `Last-Event-ID`).
//!
//! # History and live events
//!
//! [`Events`] holds the events in memory (rebuilt from the log at start) and hands each new
//! one to every listener over a broadcast channel, *after* its record is durable. A listener
//! subscribes first and then reads the history: together they miss nothing, and the ids tell
//! it what it has already seen. A listener too slow for the channel falls back to the
//! history.
//!
//! Memory: the history keeps the events of the retention time (`--retain-hours`, like the
//! flight index); older ones are dropped as the clock moves and are not rebuilt at start. A
//! client resuming from before that is told so in a comment, then gets what is held.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, RwLock};

use muse_model::{Airspace, Instant, UtcOffset};
use serde::Serialize;
use tokio::sync::broadcast;

use crate::flights::{FlightEntry, FlightView};

/// Events a listener may fall behind by before it reads the history instead.
pub const LIVE_CAPACITY: usize = 4_096;

/// One change of one flight.
#[derive(Clone, Debug)]
pub struct Event {
    /// Its id (see the module docs).
    pub id: u64,
    /// `planned`, `cancelled`, `replanned`, `diverted` or `contingency`.
    pub kind: &'static str,
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
    /// it), "plan"}`, `plan` being the flight as `GET /v1/flights/{id}` shows it.
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

/// The events held and the channel new ones go out on (see the module docs).
#[derive(Debug)]
pub struct Events {
    history: RwLock<VecDeque<Arc<Event>>>,
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
            history: RwLock::new(VecDeque::new()),
            last: AtomicU64::new(0),
            live: broadcast::channel(buffer.max(1)).0,
        }
    }

    /// A listener for the events published from now on.
    pub fn subscribe(&self) -> broadcast::Receiver<Arc<Event>> {
        self.live.subscribe()
    }

    /// Adds events (ids increasing, above every one held) to the history, then sends them to
    /// the listeners.
    pub fn publish(&self, events: impl IntoIterator<Item = Arc<Event>>) {
        for event in events {
            debug_assert!(event.id > self.last_id());
            self.history
                .write()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push_back(Arc::clone(&event));
            self.last.store(event.id, Ordering::Release);
            // No listener is not an error.
            let _ = self.live.send(event);
        }
    }

    /// Sets the history rebuilt from the log at start; `last` is the id of the last event
    /// of the log (the history may hold fewer).
    pub fn restore(&self, events: Vec<Arc<Event>>, last: u64) {
        *self
            .history
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = events.into();
        self.last.store(last, Ordering::Release);
    }

    /// The id of the last event (0: none yet).
    pub fn last_id(&self) -> u64 {
        self.last.load(Ordering::Acquire)
    }

    /// The id of the oldest event held, if any.
    pub fn first_held(&self) -> Option<u64> {
        self.history
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .front()
            .map(|e| e.id)
    }

    /// The events held with an id above `id` that `visible` keeps, in id order.
    pub fn after(&self, id: u64, visible: impl Fn(&Event) -> bool) -> Vec<Arc<Event>> {
        let history = self
            .history
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let start = history.partition_point(|e| e.id <= id);
        history
            .range(start..)
            .filter(|e| visible(e))
            .cloned()
            .collect()
    }

    /// Drops the events that happened before `t`; returns how many.
    pub fn forget_before(&self, t: Instant) -> usize {
        let mut history = self
            .history
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let n = history.partition_point(|e| e.at < t);
        history.drain(..n);
        n
    }

    /// Number of events held.
    pub fn held(&self) -> usize {
        self.history
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::{NodeId, RejectReason, Request};

    fn event(id: u64, operator: &str, at: i64) -> Arc<Event> {
        Arc::new(Event {
            id,
            kind: "planned",
            at: Instant(at),
            zone: None,
            entry: Arc::new(FlightEntry {
                seq: id,
                operator: operator.into(),
                request: Request {
                    id: format!("f{id}"),
                    origin: NodeId(0),
                    destination: NodeId(1),
                    departure: Instant(at),
                    submitted: Instant(at),
                },
                result: Err(RejectReason::NoFeasiblePlan),
                free_flow: None,
                expanded: 0,
                answered: Instant(at),
                cancelled_at: None,
                changes: Vec::new(),
                fate: None,
            }),
        })
    }

    #[test]
    fn a_listener_subscribed_before_reading_the_history_misses_nothing() {
        let events = Events::default();
        events.publish([event(1, "a", 10), event(2, "b", 20)]);
        let mut rx = events.subscribe();
        events.publish([event(3, "a", 30)]);
        let held: Vec<u64> = events.after(1, |_| true).iter().map(|e| e.id).collect();
        assert_eq!(held, [2, 3]);
        // Event 3 is in both: the ids tell the listener it has it already.
        assert_eq!(rx.try_recv().unwrap().id, 3);
        let mine: Vec<u64> = events
            .after(0, |e| e.entry.operator == "a")
            .iter()
            .map(|e| e.id)
            .collect();
        assert_eq!(mine, [1, 3]);
        assert_eq!(events.forget_before(Instant(25)), 2);
        assert_eq!(
            (events.first_held(), events.last_id(), events.held()),
            (Some(3), 3, 1)
        );
    }
}
