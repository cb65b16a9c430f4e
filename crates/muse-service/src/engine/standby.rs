//! The planner task of a standby (see `crate::role`): it follows what the leader commits into
//! its own schedule, index, zones and event stream, by the same [`Engine::apply`] as every
//! other change, and takes the lead when the leader stops.
//!
//! Following reads the store, never the leader: the zones (a handful, read whole, to see an
//! announcement or a withdrawal), then the events after the last one applied, in order. Every
//! change of a flight that matters to the schedule has an event (planned, cancelled,
//! replanned, diverted, contingency), which carries the flight as it stood then; applying them
//! in order replays the leader's decisions exactly, so the schedule is the leader's as of the
//! last event read. Rejected flights hold nothing and have no event: reads find them in the
//! store.
//!
//! The standby looks again as soon as the leader's commit is announced (at most one look per
//! [`GAP`]), or every [`POLL`] at the latest, and each time tries to take the lead (the zones,
//! the lease and the last keys are read every [`WHOLE_EVERY`]): it succeeds once the leader's
//! session has ended. It then reads the last of the old leader's commits (there can be no
//! more: the lead is taken in the store, see `store::pg::lease`) and plans on from there; the
//! schedule is warm, so the take-over reads only that tail.

use std::sync::Arc;
use std::time::Duration;

use tokio::sync::mpsc;
use tokio::sync::mpsc::error::TryRecvError;

use super::apply::Change;
use super::{Command, Engine};
use crate::store::{Store, StoreError};

/// How long a standby waits for the leader's next commit before it looks again, and tries to
/// take the lead, anyway.
pub(super) const POLL: Duration = Duration::from_millis(50);

/// The least time between two looks: under steady writes the leader commits hundreds of
/// times a second, and one look reads all the events since the last, so looks closer together
/// would only cost the store and the machine work.
const GAP: Duration = Duration::from_millis(10);

/// How often a standby also reads the zones, the lease and the last keys (a zone announced
/// that changed no flight has no event; the leader's address; how far behind it is).
const WHOLE_EVERY: Duration = Duration::from_millis(250);

/// Most events read from the store at once.
const STEP: usize = 4_096;

impl Engine<'_> {
    /// Stands by, following the leader, until this service takes the lead (`Ok(true)`) or
    /// stops (`Ok(false)`: every sender of commands is gone).
    pub(super) fn stand_by(
        &mut self,
        store: &mut dyn Store,
        commands: &mut mpsc::Receiver<Command>,
    ) -> Result<bool, StoreError> {
        let state = self.state;
        let mut whole_at = std::time::Instant::now();
        loop {
            let looked = std::time::Instant::now();
            // A command reaches a standby only in a race with a change of leader; the handlers
            // send writes to the leader.
            loop {
                match commands.try_recv() {
                    Ok(command) => command.refuse(
                        "this service is a standby, and the leader changed meanwhile; retry \
                         with the same id",
                    ),
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => return Ok(false),
                }
            }
            let whole = whole_at.elapsed() >= WHOLE_EVERY;
            self.follow(store, whole)?;
            if store.try_lead(&state.address, state.clock.now())? {
                // The old leader can commit no more: read what it committed last.
                // Every event is applied now, and the old leader commits no more: the next
                // numbers follow the last keys (archived ones included).
                if let Some((last_seq, last_event)) = self.follow(store, true)? {
                    self.next_seq = self.next_seq.max(last_seq + 1);
                    self.next_event = self.next_event.max(last_event + 1);
                }
                state.role.took_over();
                self.update_gauges();
                return Ok(true);
            }
            if whole {
                state
                    .role
                    .stand_by(store.leader()?.map(|leader| leader.address));
                whole_at = std::time::Instant::now();
            }
            store.wait_for_commits(POLL)?;
            if let Some(rest) = GAP.checked_sub(looked.elapsed()) {
                std::thread::sleep(rest);
            }
        }
    }

    /// Applies what the leader committed since the last look (see the module docs), and
    /// publishes it: to reads, to `GET /v1/zones`, to the event streams. `whole`: the zones
    /// and the last keys are read too (else only the events), and the keys are returned. They
    /// are read after the events: while the leader writes, more may have come since, so the
    /// next event to read stays the one after the last applied.
    pub(super) fn follow(
        &mut self,
        store: &mut dyn Store,
        whole: bool,
    ) -> Result<Option<(u64, u64)>, StoreError> {
        let state = self.state;
        self.tick();
        let zones = if whole { store.zones()? } else { Vec::new() };
        for stored in zones {
            let known = state
                .zones
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .get(&stored.id)
                .map(|z| z.withdrawn);
            match (known, stored.withdrawn) {
                (None, _) => {
                    let change = self.stored_zone(&store.label(), stored)?;
                    self.apply(change);
                }
                (Some(None), Some(at)) => self.apply(Change::Withdrawal { id: stored.id, at }),
                _ => {}
            }
        }
        loop {
            let events = state.reader.events_after(
                &state.world.airspace,
                self.next_event - 1,
                None,
                STEP,
            )?;
            let read = events.len();
            for event in events {
                self.next_event = event.id + 1;
                self.apply(Change::Flights(vec![Arc::clone(&event.entry)]));
                self.group.events.push(Arc::new(event));
            }
            if read < STEP {
                break;
            }
        }
        let keys = if whole {
            Some(store.last_keys()?)
        } else {
            None
        };
        self.send(&mut Vec::new())
            .unwrap_or_else(|_| unreachable!("a standby sends nothing to a writer"));
        state.role.followed(
            self.next_event - 1,
            keys.map_or(self.next_event - 1, |(_, event)| event),
            crate::state::system_ms(),
        );
        self.update_gauges();
        Ok(keys)
    }
}
