//! Applying a decided change to the service's state: the one way the live schedule changes,
//! used by every command once its rows are written, and at start to put back what the store
//! holds.

use std::sync::Arc;

use muse_airspace::closures::Closures;
use muse_model::Instant;
use muse_planner::FlightId;

use super::{Engine, ZoneChange};
use crate::flights::FlightEntry;
use crate::zones::book::AnnouncedZone;

/// A change decided (and stored) that the state must now reflect.
pub(super) enum Change {
    /// Flights as they now stand (new, cancelled, changed by a zone, or read from the store
    /// at start): each holds in the schedule what it now holds, and nothing else. Flights
    /// changed together (a zone's outcomes) release their old holdings before any reserves
    /// its new one.
    Flights(Vec<Arc<FlightEntry>>),
    /// A zone announced during the day; its closures bind planning unless it was withdrawn
    /// (`closures` is `None` then).
    Zone {
        /// The zone.
        zone: AnnouncedZone,
        /// Its resolved closures, while it is in force.
        closures: Option<Closures>,
    },
    /// An announced zone withdrawn.
    Withdrawal {
        /// The zone's id.
        id: String,
        /// When.
        at: Instant,
    },
}

impl Engine<'_> {
    /// Applies `change` to the live schedule at once (the group's later decisions see it) and
    /// stages it for reads, which see it once the group is durable (the writer publishes it).
    pub(super) fn apply(&mut self, change: Change) {
        match change {
            Change::Flights(flights) => {
                let holdings: Vec<_> = flights
                    .iter()
                    .map(|e| (FlightId(e.seq), &e.request, e.holding()))
                    .collect();
                self.live.hold_all(&holdings);
                // Staged under the number the group being decided will be sent under, until
                // the writer has published it (while loading, the group is published at once).
                if let Some(pipe) = &self.pipe {
                    for e in &flights {
                        self.staged
                            .insert(e.request.id.clone(), (pipe.sent + 1, Arc::clone(e)));
                    }
                }
                self.group.entries.extend(flights);
            }
            Change::Zone { zone, closures } => {
                if let Some(closures) = closures {
                    // An id the book refused is never decided, and a stored one is unique.
                    let _ = self.live.add_announced(&zone.id, closures);
                }
                self.group.zone_changes.push(ZoneChange::Announced(zone));
            }
            Change::Withdrawal { id, at } => {
                let _ = self.live.withdraw(&id);
                self.group.zone_changes.push(ZoneChange::Withdrawn(id, at));
            }
        }
    }
}
