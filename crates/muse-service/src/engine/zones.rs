//! Zone announcements and withdrawals on the live schedule (SPEC §11).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

use muse_airspace::closures::ClosureError;
use muse_model::Instant;
use muse_model::plan::Fate;

use super::{Engine, Staged, store_failed};
use crate::flights::{FlightEntry, stays_to_record};
use crate::store::{OutcomeRecord, Record, Store, ZoneRecord};
use crate::zones::{AnnouncedZone, NewZone};

/// The answer to [`Command::Announce`](super::Command::Announce).
#[derive(Debug)]
pub enum AnnounceReply {
    /// Announced now, durably, with what it did.
    Done(Announcement),
    /// The id is that of a zone known from the start or announced before.
    Taken,
    /// The zone does not fit the airspace (e.g. it names an unknown node).
    Invalid {
        /// The field at fault, when one is.
        field: Option<&'static str>,
        /// What is wrong.
        message: String,
    },
    /// The service could not answer.
    Failed(String),
}

/// A zone announced, and the flights it changed.
#[derive(Clone, Debug)]
pub struct Announcement {
    /// The zone's id.
    pub zone: String,
    /// The announcement instant (the clock's now when the planner took it).
    pub announced: Instant,
    /// The flights it changed, in the order they were replanned, as they now stand (their
    /// last change is this announcement's).
    pub affected: Vec<Arc<FlightEntry>>,
}

/// The answer to [`Command::Withdraw`](super::Command::Withdraw).
#[derive(Debug)]
pub enum WithdrawReply {
    /// Withdrawn now, durably.
    Done(AnnouncedZone),
    /// Withdrawn before: the zone as it stands.
    Already(AnnouncedZone),
    /// A zone known from the start: it cannot be withdrawn.
    Base,
    /// No zone has this id.
    Unknown,
    /// The service could not answer.
    Failed(String),
}

impl Engine<'_, '_> {
    /// Announces `zone` now: replans what it hits, stores the zone and every outcome as one
    /// record committed alone, and stages the changed flights and their events. Returns the
    /// answer and the zone to record as announced once published.
    pub(super) fn announce(
        &mut self,
        store: &mut Store,
        staged: &mut Staged,
        zone: NewZone,
    ) -> (AnnounceReply, Option<AnnouncedZone>) {
        let taken = self
            .state
            .zones
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .taken(&zone);
        if taken {
            return (AnnounceReply::Taken, None);
        }
        let n = self.live.now();
        let closures = match self.state.world.announced_closures(&zone.zones, n) {
            Ok(c) => c,
            Err(e) => {
                let field = match &e {
                    ClosureError::UnknownNode { .. } => Some("nodes"),
                    ClosureError::UnknownEdge { .. } | ClosureError::AmbiguousEdge { .. } => {
                        Some("edges")
                    }
                    _ => None,
                };
                let message = format!("the zone does not fit this airspace: {e}");
                return (AnnounceReply::Invalid { field, message }, None);
            }
        };
        let live = &mut self.live;
        let affected = match catch_unwind(AssertUnwindSafe(|| live.announce(&zone.id, closures))) {
            Ok(Ok(affected)) => affected,
            Ok(Err(_)) => return (AnnounceReply::Taken, None),
            // The schedule may be half replanned: stop, so that a restart recovers exactly
            // what is stored (nothing of this announcement).
            Err(_) => halt(&format!(
                "internal error while replanning for zone `{}`",
                zone.id
            )),
        };
        let mut outcomes = Vec::with_capacity(affected.len());
        let mut changed = Vec::with_capacity(affected.len());
        for a in affected {
            // Staged is empty (the group before was committed): the index knows every flight
            // the schedule holds.
            let known = self
                .state
                .index
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .get_seq(a.flight)
                .cloned();
            let Some(known) = known else {
                halt(&format!(
                    "the schedule holds flight #{} the index does not know",
                    a.flight
                ))
            };
            let airspace = &self.state.world.airspace;
            outcomes.push(OutcomeRecord {
                seq: a.flight,
                airborne: a.airborne,
                outcome: a.fate.kind().as_str().to_owned(),
                path: match &a.fate {
                    Fate::Replanned(p) | Fate::Diverted(p) | Fate::Contingency(p) => {
                        Some(stays_to_record(airspace, p))
                    }
                    Fate::Cancelled => None,
                },
            });
            let kind = a.fate.kind().as_str();
            let entry = Arc::new(known.changed(&zone.id, n, a.airborne, a.fate));
            self.emit(kind, n, Some(&zone.id), &entry);
            staged.insert(entry.request.id.clone(), Arc::clone(&entry));
            changed.push(entry);
        }
        let record = Record::Zone(ZoneRecord {
            id: zone.id.clone(),
            feature: zone.feature,
            announced: n.0,
            outcomes,
        });
        if let Err(e) = store.commit_alone(&record) {
            store_failed(&e, &mut Vec::new());
        }
        let mut zones = zone.zones;
        for z in &mut zones {
            z.announced = Some(n);
        }
        let known = AnnouncedZone {
            id: zone.id.clone(),
            zones,
            announced: n,
            withdrawn: None,
            affected: changed.len(),
        };
        self.state.metrics.count_zone(true);
        let answer = Announcement {
            zone: zone.id,
            announced: n,
            affected: changed,
        };
        (AnnounceReply::Done(answer), Some(known))
    }

    /// Withdraws the announced zone `id` now (nothing is replanned) and appends its record.
    /// Returns the answer and the withdrawal to record once durable.
    pub(super) fn withdraw(
        &mut self,
        store: &mut Store,
        id: &str,
    ) -> (WithdrawReply, Option<(String, Instant)>) {
        let zone = {
            let book = self
                .state
                .zones
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if book.is_base(id) {
                return (WithdrawReply::Base, None);
            }
            match book.get(id) {
                None => return (WithdrawReply::Unknown, None),
                Some(z) if z.withdrawn.is_some() => {
                    return (WithdrawReply::Already(z.clone()), None);
                }
                Some(z) => z.clone(),
            }
        };
        if self.live.withdraw(id).is_err() {
            return (
                WithdrawReply::Failed(format!(
                    "internal error: the schedule does not hold zone `{id}`"
                )),
                None,
            );
        }
        let at = self.live.now();
        store.append(&Record::Withdraw {
            id: id.to_owned(),
            at: at.0,
        });
        self.state.metrics.count_zone(false);
        let mut zone = zone;
        zone.withdrawn = Some(at);
        (WithdrawReply::Done(zone), Some((id.to_owned(), at)))
    }
}

/// Stops the service after an internal error that leaves the schedule unlike the store.
fn halt(message: &str) -> ! {
    eprintln!("muse serve: {message}; the service stops (a restart recovers what is stored)");
    std::process::exit(70);
}
