//! The service's flights: what was asked, what was answered, and what became of it — and the
//! in-memory index of the flights the live schedule holds (every other flight is read from the
//! store).

use std::collections::HashMap;
use std::sync::Arc;

use muse_formats::plans::{PlanLine, PlanRecord, plan_line};
use muse_model::plan::Change;
use muse_model::plan::{Fate, FateKind};
use muse_model::{Airspace, Instant, Millis, Plan, RejectReason, Request, UtcOffset};
use muse_planner::Holding;
use serde::Serialize;

// The client id rule is shared with the requests file (`muse_model::request::valid_id`):
// 1 to `MAX_ID_LEN` characters of letters, digits and `._~:-` (an id names the flight in a
// URL path, and `#` is left for the store).
pub use muse_model::request::{ID_RULE, valid_id};

/// The reason given for a flight cancelled by its operator.
pub const CANCELLED_BY_OPERATOR: &str = "cancelled_by_operator";

/// One flight as the service knows it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FlightEntry {
    /// Sequence number (the flight's id in the schedule; also the listing order).
    pub seq: u64,
    /// The operator it belongs to.
    pub operator: String,
    /// The request (its `id` is the client's id).
    pub request: Request,
    /// The answer: a plan or a rejection.
    pub result: Result<Plan, RejectReason>,
    /// Free-flow time, where defined.
    pub free_flow: Option<Millis>,
    /// Search labels expanded.
    pub expanded: u64,
    /// When it was answered (service clock).
    pub answered: Instant,
    /// When its operator cancelled it, if it did.
    pub cancelled_at: Option<Instant>,
    /// The zone announcements that changed it, in order
    /// (docs/reference.md#zones-announced-during-the-day).
    pub changes: Vec<Change>,
    /// What each of them made of it, in the same order (the last is its current fate).
    pub fates: Vec<Fate>,
}

/// A flight's status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Planned and still booked as first planned.
    Planned,
    /// Rejected (no plan).
    Rejected,
    /// Planned, then cancelled by its operator or by a zone announcement.
    Cancelled,
    /// Replanned after a zone announcement (a new plan to its destination).
    Replanned,
    /// Airborne at a zone announcement and landing at another station.
    Diverted,
    /// Airborne at a zone announcement with no station to land at.
    Contingency,
}

impl Status {
    /// Every status, in the order documented.
    pub const ALL: [Status; 6] = [
        Status::Planned,
        Status::Rejected,
        Status::Cancelled,
        Status::Replanned,
        Status::Diverted,
        Status::Contingency,
    ];

    /// The spelling in answers (docs/reference.md#plans and #zones-announced-during-the-day).
    pub const fn as_str(self) -> &'static str {
        match self {
            Status::Planned => "planned",
            Status::Rejected => "rejected",
            Status::Cancelled => "cancelled",
            Status::Replanned => "replanned",
            Status::Diverted => "diverted",
            Status::Contingency => "contingency",
        }
    }

    /// Parses the spelling.
    pub fn parse(text: &str) -> Option<Status> {
        Status::ALL.into_iter().find(|s| s.as_str() == text)
    }
}

/// The docs/reference.md#plans object of a flight as the service answers it: the plan line, plus
/// who owns the flight and, once cancelled, when.
#[derive(Clone, Debug, Serialize)]
pub struct FlightView {
    /// The docs/reference.md#plans fields.
    #[serde(flatten)]
    pub line: PlanLine,
    /// The operator the flight belongs to.
    pub operator: String,
    /// When the flight was cancelled (RFC 3339), for cancelled flights.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cancelled_at: Option<String>,
}

impl FlightEntry {
    /// What the last zone announcement that changed it made of it; `None` if none did.
    pub fn fate(&self) -> Option<&Fate> {
        self.fates.last()
    }

    /// The flight's status.
    pub fn status(&self) -> Status {
        match (&self.result, self.cancelled_at, self.fate()) {
            (Err(_), _, _) => Status::Rejected,
            (Ok(_), Some(_), _) => Status::Cancelled,
            (Ok(_), None, None) => Status::Planned,
            (Ok(_), None, Some(fate)) => match fate.kind() {
                FateKind::Replanned => Status::Replanned,
                FateKind::Diverted => Status::Diverted,
                FateKind::Cancelled => Status::Cancelled,
                FateKind::Contingency => Status::Contingency,
            },
        }
    }

    /// The plan the flight holds and will land by, if any: its first plan, or the one a zone
    /// announcement replanned or diverted it to; none once cancelled (by its operator or a
    /// zone) or left in contingency.
    pub fn booked_plan(&self) -> Option<&Plan> {
        if self.cancelled_at.is_some() {
            return None;
        }
        match self.fate() {
            None => self.result.as_ref().ok(),
            Some(fate) => fate.plan(),
        }
    }

    /// What the flight holds in the live schedule: its booked plan, the committed part of a
    /// contingency, or nothing.
    pub fn holding(&self) -> Holding<'_> {
        if self.cancelled_at.is_some() {
            return Holding::Nothing;
        }
        match self.fate() {
            None => self
                .result
                .as_ref()
                .map_or(Holding::Nothing, Holding::Booked),
            Some(fate) => Holding::of_fate(fate),
        }
    }

    /// The last instant at which the flight holds a reservation (the landing of its booked
    /// plan or of a contingency's committed part); `None` if it holds nothing.
    pub fn holds_until(&self) -> Option<Instant> {
        match self.holding() {
            Holding::Booked(p) | Holding::Committed(p) => Some(p.landing()),
            Holding::Nothing => None,
        }
    }

    /// The flight as it stood just after its first `changes` zone changes, before any
    /// cancellation by its operator (which is always its last change) unless `cancelled`.
    #[must_use]
    pub fn as_of(&self, changes: usize, cancelled: bool) -> Self {
        let mut then = self.clone();
        then.changes.truncate(changes);
        then.fates.truncate(changes);
        if !cancelled {
            then.cancelled_at = None;
        }
        then
    }

    /// The flight after a zone announcement at `announced` made `fate` of it (`airborne`:
    /// it had taken off then).
    #[must_use]
    pub fn changed(&self, zone: &str, announced: Instant, airborne: bool, fate: Fate) -> Self {
        let mut changed = self.clone();
        changed
            .changes
            .push(Change::new(zone, announced, airborne, &fate));
        changed.fates.push(fate);
        changed
    }

    /// Whether `request` asks for the same flight (same stations and departure).
    pub fn same_request(&self, request: &Request) -> bool {
        self.request.origin == request.origin
            && self.request.destination == request.destination
            && self.request.departure == request.departure
    }

    /// The instants the flight spans: take-off to landing of its current plan (first,
    /// replanned or diverted; a contingency's committed part; a cancelled flight's last
    /// plan), else the requested departure.
    pub fn span(&self) -> (Instant, Instant) {
        let current = match self.fate() {
            Some(Fate::Replanned(p) | Fate::Diverted(p) | Fate::Contingency(p)) => Some(p),
            Some(Fate::Cancelled) | None => self.result.as_ref().ok(),
        };
        match current {
            Some(plan) => (plan.takeoff(), plan.landing()),
            None => (self.request.departure, self.request.departure),
        }
    }

    /// The answer as the API shows it (times in `offset`).
    pub fn view(&self, airspace: &Airspace, offset: UtcOffset) -> FlightView {
        let record = PlanRecord {
            request: self.request.id.clone(),
            origin: airspace.node(self.request.origin).id.clone(),
            destination: airspace.node(self.request.destination).id.clone(),
            requested_departure: self.request.departure,
            result: self.result.clone(),
            free_flow: self.free_flow,
            expanded: self.expanded,
            changes: self.changes.clone(),
            fate: self.fate().cloned(),
        };
        let mut line = plan_line(airspace, offset, &record);
        if self.cancelled_at.is_some() {
            // A cancelled flight holds no reservation: it shows no plan, so that a list of
            // flights never shows two drones in one slot (what zones changed stays listed).
            line.status = "cancelled".into();
            line.reason = Some(CANCELLED_BY_OPERATOR.into());
            line.takeoff = None;
            line.landing = None;
            line.airborne_s = None;
            line.air_delay_s = None;
            line.ground_delay_s = None;
            line.distance_m = None;
            line.path = None;
            line.legs = None;
            line.extra_delay_s = None;
            line.diverted_to = None;
        }
        FlightView {
            line,
            operator: self.operator.clone(),
            cancelled_at: self.cancelled_at.map(|t| t.to_rfc3339(offset)),
        }
    }
}

/// The flights the live schedule holds (a booked plan or a contingency's committed part that
/// has not ended), by id and by sequence number: what cancellations, zone announcements and
/// most reads need at once. Every other flight is read from the store, so memory is bounded by
/// the traffic of the booking horizon, not by the days served. Written only by the planner
/// task, after the store has made its changes durable; read by every handler.
#[derive(Debug, Default)]
pub struct FlightIndex {
    by_seq: HashMap<u64, Arc<FlightEntry>>,
    by_id: HashMap<String, u64>,
}

/// What a listing asks for.
#[derive(Clone, Debug, Default)]
pub struct ListQuery {
    /// Only this operator's flights (`None`: every operator's).
    pub operator: Option<String>,
    /// Only flights with this status.
    pub status: Option<Status>,
    /// Only flights whose span ends at or after this instant.
    pub from: Option<Instant>,
    /// Only flights whose span starts before this instant.
    pub to: Option<Instant>,
    /// Only flights answered after this sequence number (a page cursor).
    pub after: Option<u64>,
    /// At most this many.
    pub limit: Option<usize>,
}

impl FlightIndex {
    /// The flight with client id `id`, if the schedule holds it.
    pub fn get(&self, id: &str) -> Option<&Arc<FlightEntry>> {
        self.by_id.get(id).and_then(|seq| self.by_seq.get(seq))
    }

    /// The flight with sequence number `seq`, if the schedule holds it.
    pub fn get_seq(&self, seq: u64) -> Option<&Arc<FlightEntry>> {
        self.by_seq.get(&seq)
    }

    /// Number of flights held.
    pub fn len(&self) -> usize {
        self.by_seq.len()
    }

    /// Records a flight as it now stands: kept if it holds a reservation that ends at or after
    /// `now`, dropped otherwise (cancelled, rejected, landed).
    pub fn put(&mut self, entry: Arc<FlightEntry>, now: Instant) {
        if entry.holds_until().is_some_and(|t| t >= now) {
            self.by_id.insert(entry.request.id.clone(), entry.seq);
            self.by_seq.insert(entry.seq, entry);
        } else if let Some(old) = self.by_seq.remove(&entry.seq) {
            self.by_id.remove(&old.request.id);
        }
    }

    /// Drops every flight whose reservations ended before `t`; returns how many.
    pub fn evict_ended_before(&mut self, t: Instant) -> usize {
        let before = self.by_seq.len();
        let by_id = &mut self.by_id;
        self.by_seq.retain(|_, e| {
            let keep = e.holds_until().is_some_and(|end| end >= t);
            if !keep {
                by_id.remove(&e.request.id);
            }
            keep
        });
        before - self.by_seq.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::testing::{plan, request};

    fn entry(seq: u64, departure: i64, planned: bool) -> Arc<FlightEntry> {
        let result = if planned {
            Ok(plan(&[
                (0, departure, departure),
                (1, departure + 100, departure + 100),
            ]))
        } else {
            Err(RejectReason::NoFeasiblePlan)
        };
        Arc::new(FlightEntry {
            seq,
            operator: "op".into(),
            request: request(&format!("f{seq}"), 0, 1, departure),
            result,
            free_flow: Some(Millis(100)),
            expanded: 1,
            answered: Instant(0),
            cancelled_at: None,
            changes: Vec::new(),
            fates: Vec::new(),
        })
    }

    #[test]
    fn the_index_holds_what_the_schedule_holds() {
        let mut index = FlightIndex::default();
        for seq in 1..=6 {
            index.put(entry(seq, 1_000 * seq as i64, seq % 2 == 0), Instant(0));
        }
        // Rejected flights hold nothing: only 2, 4 and 6 are kept.
        assert_eq!(index.len(), 3);
        assert!(index.get("f1").is_none() && index.get("f2").is_some());
        // A cancellation drops it.
        let mut cancelled = (*entry(2, 2_000, true)).clone();
        cancelled.cancelled_at = Some(Instant(1));
        assert_eq!(cancelled.holding(), Holding::Nothing);
        index.put(Arc::new(cancelled), Instant(0));
        assert!(index.get("f2").is_none() && index.get_seq(2).is_none());
        // Flight 4 lands at 4,100.
        assert_eq!(index.evict_ended_before(Instant(4_101)), 1);
        assert_eq!(index.get_seq(6).map(|e| e.seq), Some(6));
        assert_eq!(index.len(), 1);
    }

    #[test]
    fn a_flight_as_of_an_earlier_change() {
        let mut e = (*entry(1, 1_000, true)).clone();
        let first = e.result.clone().unwrap();
        e = e.changed("Z", Instant(500), false, Fate::Replanned(first.clone()));
        e = e.changed("Y", Instant(600), false, Fate::Cancelled);
        assert_eq!(e.status(), Status::Cancelled);
        let then = e.as_of(1, false);
        assert_eq!(then.status(), Status::Replanned);
        assert_eq!(then.holding(), Holding::Booked(&first));
        assert_eq!(e.as_of(0, false).status(), Status::Planned);
    }
}
