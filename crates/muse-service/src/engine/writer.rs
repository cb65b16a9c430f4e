//! The store's writer: a thread of its own beside the planner task, so that deciding a group
//! and making the previous one durable overlap (the sync of a commit is the slowest step).
//!
//! The planner task sends each group as a [`Batch`]: the rows to write, what becomes visible
//! once they are durable, and the answers. The writer takes whatever batches have queued up,
//! writes them in one transaction, commits, and only then, batch by batch in order, publishes
//! them (reads, zones, events) and sends their answers; then it records how far it got in
//! [`Published`], which the planner task reads to know which of its staged flights the
//! index and the store now hold, and waits on before a zone change.
//!
//! If a commit fails, nothing of those batches is durable: their answers, and those of every
//! batch sent after them, say so, [`Published`] is marked failed (the planner task stops),
//! and the writer returns the error.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::{Arc, Condvar, Mutex};
use std::time::Instant as WallInstant;

use muse_model::Instant;

use super::{Pending, ZoneChange};
use crate::events::Event;
use crate::flights::FlightEntry;
use crate::state::State;
use crate::store::{Store, StoreError, StoredZone};

/// Most batches written in one transaction.
const MAX_BATCHES: usize = 64;

/// How often the store's size on disk is measured for `/metrics` while writes go on.
const SIZE_EVERY: std::time::Duration = std::time::Duration::from_millis(100);

/// One row to write.
pub(super) enum Write {
    /// A flight as it now stands: a new one (`true`) or a change of a stored one.
    Flight(Arc<FlightEntry>, bool),
    /// An event.
    Event(Arc<Event>),
    /// A zone announced.
    Zone(StoredZone),
    /// A zone withdrawn at an instant.
    Withdrawal(String, Instant),
}

/// A group decided by the planner task, to make durable, then visible, then answered.
#[derive(Default)]
pub(super) struct Batch {
    /// Its number (from 1, in the order sent).
    pub number: u64,
    pub writes: Vec<Write>,
    /// Flights it changed, as they now stand.
    pub entries: Vec<Arc<FlightEntry>>,
    pub zone_changes: Vec<ZoneChange>,
    pub events: Vec<Arc<Event>>,
    pub answers: Vec<Pending>,
}

/// How far the writer got: every batch numbered up to `done()` is durable and visible.
#[derive(Debug, Default)]
pub(super) struct Published {
    done: Mutex<u64>,
    moved: Condvar,
    failed: AtomicBool,
}

impl Published {
    /// The number of the last batch published (0: none).
    pub fn done(&self) -> u64 {
        *self
            .done
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Whether a commit failed (the writer has stopped).
    pub fn failed(&self) -> bool {
        self.failed.load(Ordering::Acquire)
    }

    /// Waits until batch `n` is published; `false` if the writer failed first.
    pub fn wait_for(&self, n: u64) -> bool {
        let mut done = self
            .done
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        while *done < n {
            if self.failed() {
                return false;
            }
            done = self
                .moved
                .wait(done)
                .unwrap_or_else(std::sync::PoisonError::into_inner);
        }
        true
    }

    fn set(&self, n: u64) {
        *self
            .done
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = n;
        self.moved.notify_all();
    }

    fn fail(&self) {
        self.failed.store(true, Ordering::Release);
        let _guard = self
            .done
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        self.moved.notify_all();
    }
}

/// Writes, commits, publishes and answers the batches received until the planner task lets
/// go of the channel; returns the store (to close) or the failure.
pub(super) fn run(
    state: &State,
    mut store: Box<dyn Store>,
    batches: &Receiver<Batch>,
    published: &Published,
) -> Result<Box<dyn Store>, StoreError> {
    let airspace = &state.world.airspace;
    let mut taken = Vec::with_capacity(MAX_BATCHES);
    let mut sized = WallInstant::now();
    while let Ok(first) = batches.recv() {
        taken.push(first);
        while taken.len() < MAX_BATCHES {
            match batches.try_recv() {
                Ok(b) => taken.push(b),
                Err(_) => break,
            }
        }
        let started = WallInstant::now();
        let written = taken
            .iter()
            .flat_map(|b| &b.writes)
            .try_for_each(|w| match w {
                Write::Flight(entry, new) => store.put_flight(airspace, entry, *new),
                Write::Event(event) => store.put_event(event),
                Write::Zone(zone) => store.put_zone(zone),
                Write::Withdrawal(id, at) => store.put_zone_withdrawn(id, *at),
            })
            .and_then(|()| store.commit());
        match written {
            Ok(rows) => {
                if rows > 0 {
                    state.metrics.store_latency.observe(started.elapsed());
                    let answers: usize = taken.iter().map(|b| b.answers.len()).sum();
                    state.metrics.group_size.observe_value(answers as f64);
                }
                let last = taken.last().map_or(0, |b| b.number);
                for batch in taken.drain(..) {
                    publish(state, batch);
                }
                published.set(last);
                if sized.elapsed() >= SIZE_EVERY {
                    state.metrics.set_store_bytes(store.bytes());
                    sized = WallInstant::now();
                }
                store.tidy();
            }
            Err(e) => {
                // Nothing of these batches is durable, nor will anything sent after them be.
                published.fail();
                let message = format!("the store failed ({e}); the service stops");
                for batch in taken.drain(..) {
                    fail(batch, &message);
                }
                while let Ok(batch) = batches.recv() {
                    fail(batch, &message);
                }
                return Err(e);
            }
        }
    }
    Ok(store)
}

fn fail(batch: Batch, message: &str) {
    for a in batch.answers {
        a.fail(message);
    }
}

impl Batch {
    /// Answers a batch the writer will never take: the store failed.
    pub(super) fn fail_all(batch: Batch) {
        fail(
            batch,
            "the store failed; the service stops (a restart recovers what is durable)",
        );
    }
}

/// Makes what a durable batch changed visible — the flights to reads, the zones to
/// `GET /v1/zones`, the events to their listeners — then sends its answers.
pub(super) fn publish(state: &State, batch: Batch) {
    if !batch.entries.is_empty() {
        let now = state.clock.now();
        let mut index = state
            .index
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        for entry in batch.entries {
            index.put(entry, now);
        }
    }
    if !batch.zone_changes.is_empty() {
        let mut book = state
            .zones
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        for change in batch.zone_changes {
            match change {
                ZoneChange::Announced(zone) => book.announce(zone),
                ZoneChange::Withdrawn(id, at) => {
                    book.withdraw(&id, at);
                }
            }
        }
    }
    if !batch.events.is_empty() {
        state.events.publish(batch.events);
    }
    for a in batch.answers {
        a.send();
    }
}
