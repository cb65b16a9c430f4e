//! A zone announcement or withdrawal decided against the live schedule
//! (docs/reference.md#zones-announced-during-the-day), without changing anything: which flights an
//! announcement replans, diverts, cancels or leaves in contingency (worked out on a copy of the
//! schedule), and the planner task's answers. The planner task (the engine) then stores the
//! decision with its group and applies it, as it does every command's.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

use muse_airspace::closures::{ClosureError, Closures};
use muse_model::Instant;
use muse_planner::Live;

use super::book::{AnnouncedZone, NewZone};
use crate::events::EventKind;
use crate::flights::FlightEntry;
use crate::state::State;
use crate::store::StoredZone;

/// The planner task's answer to an announcement (`Command::Announce`).
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

/// The planner task's answer to a withdrawal (`Command::Withdraw`).
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

/// An announcement decided: what the planner task stores and applies.
#[derive(Debug)]
pub struct Decided {
    /// The zone as the store keeps it.
    pub stored: StoredZone,
    /// The flights it changes, in the order they were replanned, as they now stand, each
    /// with the kind of its change's event.
    pub changed: Vec<(EventKind, Arc<FlightEntry>)>,
    /// The zone as the book lists it, announced at the clock's now.
    pub zone: AnnouncedZone,
    /// Its resolved closures.
    pub closures: Closures,
}

/// Decides the announcement of `zone` now (the clock of `live`): what it does to the flights
/// it hits, worked out on a copy of the schedule; or the answer when it cannot be announced.
pub fn announcement(
    state: &State,
    live: &mut Live<'_>,
    zone: NewZone,
) -> Result<Decided, AnnounceReply> {
    let taken = state
        .zones
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .taken(&zone);
    if taken {
        return Err(AnnounceReply::Taken);
    }
    let n = live.now();
    let closures = match state.world.announced_closures(&zone.zones, n) {
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
            return Err(AnnounceReply::Invalid { field, message });
        }
    };
    let decided = catch_unwind(AssertUnwindSafe(|| {
        live.decide_announcement(&zone.id, &closures)
    }));
    let affected = match decided {
        Ok(Ok(affected)) => affected,
        Ok(Err(_)) => return Err(AnnounceReply::Taken),
        // Deciding works on a copy: nothing changed.
        Err(_) => {
            return Err(AnnounceReply::Failed(format!(
                "internal error while replanning for zone `{}`; nothing was changed",
                zone.id
            )));
        }
    };
    let mut changed = Vec::with_capacity(affected.len());
    for a in affected {
        // The group before was committed: the index knows every flight the schedule holds.
        let known = state
            .index
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get_seq(a.flight.0)
            .cloned();
        let Some(known) = known else {
            return Err(AnnounceReply::Failed(format!(
                "internal error: the schedule holds flight #{} the index does not know; \
                 nothing was changed",
                a.flight
            )));
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
    let mut zones = zone.zones;
    for z in &mut zones {
        z.announced = Some(n);
    }
    let affected = changed.len();
    Ok(Decided {
        stored,
        changed,
        zone: AnnouncedZone {
            id: zone.id,
            zones,
            announced: n,
            withdrawn: None,
            affected,
        },
        closures,
    })
}

/// Decides the withdrawal of the announced zone `id` now (the clock of `live`; nothing is
/// replanned): the zone as it stands once withdrawn, or the answer when it cannot be.
pub fn withdrawal(
    state: &State,
    live: &Live<'_>,
    id: &str,
) -> Result<AnnouncedZone, WithdrawReply> {
    let zone = {
        let book = state
            .zones
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if book.is_base(id) {
            return Err(WithdrawReply::Base);
        }
        match book.get(id) {
            None => return Err(WithdrawReply::Unknown),
            Some(z) if z.withdrawn.is_some() => {
                return Err(WithdrawReply::Already(z.clone()));
            }
            Some(z) => z.clone(),
        }
    };
    let mut zone = zone;
    zone.withdrawn = Some(live.now());
    Ok(zone)
}
