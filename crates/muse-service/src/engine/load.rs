//! The start: what the planner needs from the store, and nothing more.
//!
//! Every announced zone (a handful) and every flight that still holds a reservation (ending
//! at or after the clock's now) are read, their checksums checked, and applied with
//! [`Engine::apply`], as live changes are. Flights that ended stay in the store, where reads
//! find them; so the start's time and memory grow with the traffic still ahead, not with the
//! days served. Nothing is planned again: each flight is put back as it stands, with the
//! outcome of every zone that changed it. Then the service leads its store or stands by
//! ([`Engine::start`]).

use std::sync::Arc;

use super::apply::Change;
use tokio::sync::oneshot;

use super::{Engine, Restored};
use crate::store::{Store, StoreError, StoredZone};
use crate::zones::book::{AnnouncedZone, read_stored};

impl Engine<'_> {
    /// Loads the store into the schedule, the index and the zones; returns what it found.
    pub(super) fn load(&mut self, store: &mut dyn Store) -> Result<Restored, StoreError> {
        let state = self.state;
        let world = &state.world;
        let now = self.live.now();
        let label = store.label();
        let mut restored = Restored::default();
        // One state of the store, whatever the leader commits meanwhile (for a standby): the
        // standby then follows from its last event.
        store.begin_snapshot()?;
        let (last_seq, last_event) = store.last_keys()?;
        for z in store.zones()? {
            restored.zones += 1;
            restored.withdrawn += usize::from(z.withdrawn.is_some());
            let change = self.stored_zone(&label, z)?;
            self.apply(change);
        }
        state.phase.set_to_load(store.count_holding(now)?);
        let phase = &state.phase;
        let held = store.holding(&world.airspace, now, &mut |n| phase.set_loaded(n))?;
        restored.held = held.len();
        let seqs = held.iter().map(|e| e.seq).collect();
        restored.checked = store.check_recent(&world.airspace, now, &seqs)?;
        store.end_snapshot()?;
        self.apply(Change::Flights(held.into_iter().map(Arc::new).collect()));
        self.next_seq = last_seq + 1;
        self.next_event = last_event + 1;
        restored.flights = last_seq;
        restored.events = last_event;
        state.events.restore(last_event);
        self.send(&mut Vec::new())
            .unwrap_or_else(|_| unreachable!("loading sends nothing to a writer"));
        Ok(restored)
    }
}

impl Engine<'_> {
    /// Loads the store, then takes the lead or stands by (following what the leader committed
    /// meanwhile), and says the service is ready on `ready`: whether it leads, `None` if the
    /// start failed (`ready` says why).
    pub(super) fn start(
        &mut self,
        store: &mut dyn Store,
        import: Option<crate::store::ImportReport>,
        ready: oneshot::Sender<Result<Restored, StoreError>>,
    ) -> Option<bool> {
        let state = self.state;
        let started = self.load(store).and_then(|mut restored| {
            restored.import = import;
            let leads = store.try_lead(&state.address, state.clock.now())?;
            if !leads {
                state
                    .role
                    .stand_by(store.leader()?.map(|leader| leader.address));
                self.follow(store, true)?;
            }
            Ok((leads, restored))
        });
        match started {
            Ok((leads, restored)) => {
                // The gauges (`/healthz`, `/metrics`) count what was loaded before anyone is
                // told the service is ready.
                state.metrics.set_store_bytes(store.bytes());
                self.update_gauges();
                state.phase.set_ready();
                let _ = ready.send(Ok(restored));
                Some(leads)
            }
            Err(e) => {
                let _ = ready.send(Err(e));
                None
            }
        }
    }

    /// The change a stored zone makes: its closures bind planning unless it was withdrawn.
    /// `label` names the store in errors.
    pub(super) fn stored_zone(&self, label: &str, z: StoredZone) -> Result<Change, StoreError> {
        let damaged = |what: String| StoreError::Damaged {
            path: label.to_owned(),
            what: format!("zones row {:?}: {what}", z.id),
        };
        let zones = read_stored(&z.feature, z.announced).map_err(&damaged)?;
        let closures = match z.withdrawn {
            Some(_) => None,
            None => Some(
                self.state
                    .world
                    .announced_closures(&zones, z.announced)
                    .map_err(|e| damaged(e.to_string()))?,
            ),
        };
        Ok(Change::Zone {
            zone: AnnouncedZone {
                id: z.id,
                zones,
                announced: z.announced,
                withdrawn: z.withdrawn,
                affected: z.affected,
            },
            closures,
        })
    }
}
