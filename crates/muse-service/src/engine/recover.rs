//! Replaying the store at start: the index, the schedule, the zones and the event history,
//! exactly as acknowledged, without planning anything.
//!
//! Records are applied in log order: a flight's first plan is [restored](Live::restore); an
//! operator's cancellation releases it; a zone announcement adds the zone's closures
//! ([`Live::add_announced`], re-resolved from the stored feature) and applies each stored
//! outcome ([`Live::apply_fate`]: the old plan released, the new plan or committed part
//! reserved, a cancelled flight holding nothing); a withdrawal lifts the zone. Events are
//! numbered as they were live: one per planned flight, cancellation and zone outcome.

use std::collections::HashMap;
use std::sync::Arc;

use muse_model::Instant;
use muse_model::plan::{Fate, FateKind};
use muse_planner::Live;

use super::Restored;
use crate::events::Event;
use crate::flights::{FlightEntry, stays_from_record};
use crate::state::State;
use crate::store::{OutcomeRecord, Record, ZoneRecord};
use crate::zones::{AnnouncedZone, ZoneBook, read_stored};

/// What recovery rebuilt, besides the shared state.
pub(super) struct Recovered {
    /// What was restored.
    pub restored: Restored,
    /// The highest sequence number seen.
    pub max_seq: u64,
}

/// The replay's working state.
struct Replay<'s> {
    state: &'s State,
    entries: HashMap<String, Arc<FlightEntry>>,
    by_seq: HashMap<u64, String>,
    order: Vec<String>,
    events: Vec<Arc<Event>>,
    zones: ZoneBook,
    restored: Restored,
    max_seq: u64,
}

/// Replays `records` into the index, `live`, the zones and the event history of `state`.
pub(super) fn recover(
    state: &State,
    live: &mut Live<'_>,
    records: &[Record],
) -> Result<Recovered, String> {
    let mut replay = Replay {
        state,
        entries: HashMap::new(),
        by_seq: HashMap::new(),
        order: Vec::new(),
        events: Vec::new(),
        zones: ZoneBook::new(&state.world.zones),
        restored: Restored::default(),
        max_seq: 0,
    };
    for record in records {
        replay
            .apply(live, record)
            .map_err(|e| format!("restoring from the store: {e}"))?;
    }
    Ok(replay.publish(live.now()))
}

impl Replay<'_> {
    fn apply(&mut self, live: &mut Live<'_>, record: &Record) -> Result<(), String> {
        let airspace = &self.state.world.airspace;
        match record {
            Record::Header { .. } | Record::Large { .. } => {}
            Record::Flight(f) => {
                let entry = Arc::new(FlightEntry::from_record(airspace, f)?);
                self.max_seq = self.max_seq.max(entry.seq);
                if let Ok(plan) = &entry.result {
                    live.restore(entry.seq, &entry.request, plan);
                    self.emit("planned", entry.answered, None, &entry);
                }
                if self.entries.insert(f.id.clone(), entry).is_some() {
                    return Err(format!("flight `{}` twice", f.id));
                }
                self.by_seq.insert(f.seq, f.id.clone());
                self.order.push(f.id.clone());
            }
            Record::Cancel { id, at } => {
                let entry = self
                    .entries
                    .get_mut(id)
                    .ok_or_else(|| format!("cancel of unknown `{id}`"))?;
                let e = Arc::make_mut(entry);
                e.cancelled_at = Some(Instant(*at));
                // Releases what it holds, as the cancellation did.
                live.apply_fate(e.seq, &e.request, &Fate::Cancelled);
                let entry = Arc::clone(entry);
                self.emit("cancelled", Instant(*at), None, &entry);
                self.restored.cancellations += 1;
            }
            Record::Zone(z) => self.zone(live, z)?,
            Record::Withdraw { id, at } => {
                live.withdraw(id)
                    .map_err(|e| format!("withdrawal of zone `{id}`: {e}"))?;
                self.zones.withdraw(id, Instant(*at));
                self.restored.withdrawn += 1;
            }
        }
        Ok(())
    }

    /// Puts an announcement back: the zone, then each stored outcome, without replanning.
    fn zone(&mut self, live: &mut Live<'_>, z: &ZoneRecord) -> Result<(), String> {
        let n = Instant(z.announced);
        let zones = read_stored(&z.feature, n)?;
        let closures = self
            .state
            .world
            .announced_closures(&zones, n)
            .map_err(|e| format!("zone `{}`: {e}", z.id))?;
        live.add_announced(&z.id, closures)
            .map_err(|e| format!("zone `{}`: {e}", z.id))?;
        for o in &z.outcomes {
            let id = self
                .by_seq
                .get(&o.seq)
                .ok_or_else(|| format!("zone `{}`: unknown flight #{}", z.id, o.seq))?;
            let entry = self.entries.get_mut(id).expect("by_seq names entries");
            let fate = fate(&self.state.world.airspace, id, o)?;
            live.apply_fate(o.seq, &entry.request, &fate);
            let kind = fate.kind().as_str();
            *entry = Arc::new(entry.changed(&z.id, n, o.airborne, fate));
            let entry = Arc::clone(entry);
            self.emit(kind, n, Some(&z.id), &entry);
        }
        self.zones.announce(AnnouncedZone {
            id: z.id.clone(),
            zones,
            announced: n,
            withdrawn: None,
            affected: z.outcomes.len(),
        });
        self.restored.zones += 1;
        Ok(())
    }

    fn emit(
        &mut self,
        kind: &'static str,
        at: Instant,
        zone: Option<&str>,
        entry: &Arc<FlightEntry>,
    ) {
        self.restored.events += 1;
        self.events.push(Arc::new(Event {
            id: self.restored.events,
            kind,
            at,
            zone: zone.map(str::to_owned),
            entry: Arc::clone(entry),
        }));
    }

    /// Publishes the rebuilt index, zones and events (those of the retention time).
    fn publish(mut self, now: Instant) -> Recovered {
        let state = self.state;
        let mut index = state
            .index
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        for id in &self.order {
            let entry = self.entries.remove(id).expect("every id was inserted");
            if entry.booked_plan().is_some_and(|p| p.landing() >= now) {
                self.restored.booked += 1;
            }
            self.restored.flights += 1;
            index.put(entry);
        }
        index.evict_ended_before(now - state.retain);
        drop(index);
        *state
            .zones
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = self.zones;
        let cutoff = now - state.retain;
        let held: Vec<Arc<Event>> = self.events.into_iter().filter(|e| e.at >= cutoff).collect();
        state.events.restore(held, self.restored.events);
        Recovered {
            restored: self.restored,
            max_seq: self.max_seq,
        }
    }
}

/// The fate an outcome record describes.
fn fate(airspace: &muse_model::Airspace, flight: &str, o: &OutcomeRecord) -> Result<Fate, String> {
    let kind = FateKind::parse(&o.outcome)
        .ok_or_else(|| format!("flight `{flight}`: unknown outcome `{}`", o.outcome))?;
    let plan = || match &o.path {
        Some(path) => stays_from_record(airspace, flight, path),
        None => Err(format!(
            "flight `{flight}`: a {} outcome without a path",
            o.outcome
        )),
    };
    Ok(match kind {
        FateKind::Replanned => Fate::Replanned(plan()?),
        FateKind::Diverted => Fate::Diverted(plan()?),
        FateKind::Contingency => Fate::Contingency(plan()?),
        FateKind::Cancelled => Fate::Cancelled,
    })
}
