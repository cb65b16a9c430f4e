//! Zone announcements and withdrawals on the live schedule (SPEC §11).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

use muse_airspace::closures::ClosureError;
use muse_model::Instant;

use super::Engine;
use super::apply::Change;
use super::writer::Write;
use crate::events::EventKind;
use crate::flights::FlightEntry;
use crate::store::StoredZone;
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

impl Engine<'_> {
    /// Announces `zone` now: decides what it does to the flights it hits (on a copy of the
    /// schedule), stores the zone, every changed flight and its event, then applies it all.
    pub(super) fn announce(&mut self, zone: NewZone) -> AnnounceReply {
        let taken = self
            .state
            .zones
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .taken(&zone);
        if taken {
            return AnnounceReply::Taken;
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
                return AnnounceReply::Invalid { field, message };
            }
        };
        let live = &mut self.live;
        let decided = catch_unwind(AssertUnwindSafe(|| {
            live.decide_announcement(&zone.id, &closures)
        }));
        let affected = match decided {
            Ok(Ok(affected)) => affected,
            Ok(Err(_)) => return AnnounceReply::Taken,
            // Deciding works on a copy: nothing changed.
            Err(_) => {
                return AnnounceReply::Failed(format!(
                    "internal error while replanning for zone `{}`; nothing was changed",
                    zone.id
                ));
            }
        };
        let mut changed = Vec::with_capacity(affected.len());
        for a in affected {
            // The group before was committed: the index knows every flight the schedule holds.
            let known = self
                .state
                .index
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .get_seq(a.flight.0)
                .cloned();
            let Some(known) = known else {
                return AnnounceReply::Failed(format!(
                    "internal error: the schedule holds flight #{} the index does not know; \
                     nothing was changed",
                    a.flight
                ));
            };
            let kind = EventKind::of_fate(a.fate.kind());
            changed.push((
                kind,
                Arc::new(known.changed(&zone.id, n, a.airborne, a.fate)),
            ));
        }
        let stored = StoredZone {
            id: zone.id.clone(),
            feature: zone.feature,
            announced: n,
            withdrawn: None,
            affected: changed.len(),
        };
        self.group.writes.push(Write::Zone(stored));
        for (kind, entry) in &changed {
            self.group
                .writes
                .push(Write::Flight(Arc::clone(entry), false));
            self.emit(*kind, n, Some(&zone.id), entry);
        }
        let mut zones = zone.zones;
        for z in &mut zones {
            z.announced = Some(n);
        }
        let affected: Vec<Arc<FlightEntry>> = changed.into_iter().map(|(_, e)| e).collect();
        self.apply(Change::Zone {
            zone: AnnouncedZone {
                id: zone.id.clone(),
                zones,
                announced: n,
                withdrawn: None,
                affected: affected.len(),
            },
            closures: Some(closures),
        });
        self.apply(Change::Flights(affected.clone()));
        self.state.metrics.count_zone(true);
        AnnounceReply::Done(Announcement {
            zone: zone.id,
            announced: n,
            affected,
        })
    }

    /// Withdraws the announced zone `id` now (nothing is replanned): stores it, applies it.
    pub(super) fn withdraw(&mut self, id: &str) -> WithdrawReply {
        let zone = {
            let book = self
                .state
                .zones
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if book.is_base(id) {
                return WithdrawReply::Base;
            }
            match book.get(id) {
                None => return WithdrawReply::Unknown,
                Some(z) if z.withdrawn.is_some() => {
                    return WithdrawReply::Already(z.clone());
                }
                Some(z) => z.clone(),
            }
        };
        let at = self.live.now();
        let mut zone = zone;
        zone.withdrawn = Some(at);
        self.group.writes.push(Write::Withdrawal(id.to_owned(), at));
        self.apply(Change::Withdrawal {
            id: id.to_owned(),
            at,
        });
        self.state.metrics.count_zone(false);
        WithdrawReply::Done(zone)
    }
}
