//! The service's flights: what was asked, what was answered, and what became of it — and the
//! in-memory index that reads are served from.

use std::collections::HashMap;
use std::sync::Arc;

use muse_formats::plans::{ChangeNote, PlanLine, PlanRecord, plan_line};
use muse_model::plan::{Fate, FateKind};
use muse_model::{Airspace, Instant, Millis, Plan, RejectReason, Request, Stay, UtcOffset};
use serde::Serialize;

use crate::store::FlightRecord;

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
    /// The zone announcements that changed it, in order (SPEC §11).
    pub changes: Vec<ChangeNote>,
    /// What the last of them made of it; `None` if none changed it.
    pub fate: Option<Fate>,
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

    /// The spelling in answers (SPEC §7 and §11).
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

/// The SPEC §7 object of a flight as the service answers it: the plan line, plus who owns
/// the flight and, once cancelled, when.
#[derive(Clone, Debug, Serialize)]
pub struct FlightView {
    /// The SPEC §7 fields.
    #[serde(flatten)]
    pub line: PlanLine,
    /// The operator the flight belongs to.
    pub operator: String,
    /// When the flight was cancelled (RFC 3339), for cancelled flights.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cancelled_at: Option<String>,
}

impl FlightEntry {
    /// The flight's status.
    pub fn status(&self) -> Status {
        match (&self.result, self.cancelled_at, &self.fate) {
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
        match &self.fate {
            None => self.result.as_ref().ok(),
            Some(fate) => fate.plan(),
        }
    }

    /// The flight after a zone announcement at `announced` made `fate` of it (`airborne`:
    /// it had taken off then).
    #[must_use]
    pub fn changed(&self, zone: &str, announced: Instant, airborne: bool, fate: Fate) -> Self {
        let mut changed = self.clone();
        changed.changes.push(ChangeNote {
            zone: zone.to_owned(),
            announced,
            airborne,
            outcome: fate.kind(),
        });
        changed.fate = Some(fate);
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
        let current = match &self.fate {
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
            fate: self.fate.clone(),
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

    /// The store record of this answer (without the cancellation, a record of its own).
    pub fn to_record(&self, airspace: &Airspace) -> FlightRecord {
        let node = |n: muse_model::NodeId| airspace.node(n).id.clone();
        FlightRecord {
            seq: self.seq,
            id: self.request.id.clone(),
            operator: self.operator.clone(),
            origin: node(self.request.origin),
            destination: node(self.request.destination),
            departure: self.request.departure.0,
            answered: self.answered.0,
            path: self
                .result
                .as_ref()
                .ok()
                .map(|p| stays_to_record(airspace, p)),
            reason: self.result.as_ref().err().map(|r| r.as_str().to_owned()),
            free_flow: self.free_flow.map(|m| m.0),
            expanded: self.expanded,
        }
    }

    /// The flight a store record describes.
    pub fn from_record(airspace: &Airspace, r: &FlightRecord) -> Result<FlightEntry, String> {
        let node = |id: &str| {
            airspace
                .node_id(id)
                .ok_or_else(|| format!("flight `{}`: unknown node `{id}`", r.id))
        };
        let result = match (&r.path, &r.reason) {
            (Some(path), None) => Ok(stays_from_record(airspace, &r.id, path)?),
            (None, Some(reason)) => Err(RejectReason::parse(reason)
                .ok_or_else(|| format!("flight `{}`: unknown reason `{reason}`", r.id))?),
            _ => return Err(format!("flight `{}`: neither a plan nor a reason", r.id)),
        };
        Ok(FlightEntry {
            seq: r.seq,
            operator: r.operator.clone(),
            request: Request {
                id: r.id.clone(),
                origin: node(&r.origin)?,
                destination: node(&r.destination)?,
                departure: Instant(r.departure),
                submitted: Instant(r.departure),
            },
            result,
            free_flow: r.free_flow.map(Millis),
            expanded: r.expanded,
            answered: Instant(r.answered),
            cancelled_at: None,
            changes: Vec::new(),
            fate: None,
        })
    }
}

/// A plan's stays as stored: `(node id, arrive, depart)`, ms since the epoch.
pub fn stays_to_record(airspace: &Airspace, plan: &Plan) -> Vec<(String, i64, i64)> {
    plan.path
        .iter()
        .map(|s| (airspace.node(s.node).id.clone(), s.arrive.0, s.depart.0))
        .collect()
}

/// The plan of stored stays (see [`stays_to_record`]); `flight` names the flight in errors.
pub fn stays_from_record(
    airspace: &Airspace,
    flight: &str,
    stays: &[(String, i64, i64)],
) -> Result<Plan, String> {
    let mut path = Vec::with_capacity(stays.len());
    for (n, a, d) in stays {
        let node = airspace
            .node_id(n)
            .ok_or_else(|| format!("flight `{flight}`: unknown node `{n}`"))?;
        path.push(Stay {
            node,
            arrive: Instant(*a),
            depart: Instant(*d),
        });
    }
    Ok(Plan { path })
}

/// The flights the service holds in memory, by id and in answer order: every flight that
/// has not ended more than the retention time ago (see [`FlightIndex::evict_ended_before`]).
/// Written only by the planner task, after the store has made its changes durable; read by
/// every handler.
#[derive(Debug, Default)]
pub struct FlightIndex {
    by_id: HashMap<String, Arc<FlightEntry>>,
    /// In sequence (answer) order, for listing.
    order: Vec<Arc<FlightEntry>>,
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
    /// The flight with client id `id`.
    pub fn get(&self, id: &str) -> Option<&Arc<FlightEntry>> {
        self.by_id.get(id)
    }

    /// The flight with sequence number `seq`.
    pub fn get_seq(&self, seq: u64) -> Option<&Arc<FlightEntry>> {
        let i = self.order.partition_point(|e| e.seq < seq);
        self.order.get(i).filter(|e| e.seq == seq)
    }

    /// Number of flights known.
    pub fn len(&self) -> usize {
        self.by_id.len()
    }

    /// Whether no flight is known.
    pub fn is_empty(&self) -> bool {
        self.by_id.is_empty()
    }

    /// Adds a new flight (its sequence number above every one held) or replaces a held one
    /// (same id and sequence number).
    pub fn put(&mut self, entry: Arc<FlightEntry>) {
        match self.order.last() {
            Some(last) if last.seq >= entry.seq => {
                let i = self.order.partition_point(|e| e.seq < entry.seq);
                debug_assert!(self.order.get(i).is_some_and(|e| e.seq == entry.seq));
                if let Some(slot) = self.order.get_mut(i).filter(|e| e.seq == entry.seq) {
                    *slot = Arc::clone(&entry);
                }
            }
            _ => self.order.push(Arc::clone(&entry)),
        }
        self.by_id.insert(entry.request.id.clone(), entry);
    }

    /// Drops from memory every flight whose span ended before `t` (the store keeps them);
    /// returns how many.
    pub fn evict_ended_before(&mut self, t: Instant) -> usize {
        let before = self.order.len();
        let by_id = &mut self.by_id;
        self.order.retain(|e| {
            let keep = e.span().1 >= t;
            if !keep {
                by_id.remove(&e.request.id);
            }
            keep
        });
        before - self.order.len()
    }

    /// The flights a listing asks for, in answer order, and whether more follow the page.
    pub fn list(&self, q: &ListQuery) -> (Vec<Arc<FlightEntry>>, bool) {
        let start = q
            .after
            .map_or(0, |after| self.order.partition_point(|e| e.seq <= after));
        let limit = q.limit.unwrap_or(usize::MAX);
        let mut out = Vec::new();
        for e in &self.order[start..] {
            if q.operator.as_ref().is_some_and(|op| *op != e.operator)
                || q.status.is_some_and(|s| s != e.status())
            {
                continue;
            }
            let (a, b) = e.span();
            if q.from.is_some_and(|f| b < f) || q.to.is_some_and(|t| a >= t) {
                continue;
            }
            if out.len() == limit {
                return (out, true);
            }
            out.push(Arc::clone(e));
        }
        (out, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::NodeId;

    fn entry(seq: u64, departure: i64, planned: bool) -> Arc<FlightEntry> {
        let result = if planned {
            Ok(Plan {
                path: vec![
                    Stay {
                        node: NodeId(0),
                        arrive: Instant(departure),
                        depart: Instant(departure),
                    },
                    Stay {
                        node: NodeId(1),
                        arrive: Instant(departure + 100),
                        depart: Instant(departure + 100),
                    },
                ],
            })
        } else {
            Err(RejectReason::NoFeasiblePlan)
        };
        Arc::new(FlightEntry {
            seq,
            operator: "op".into(),
            request: Request {
                id: format!("f{seq}"),
                origin: NodeId(0),
                destination: NodeId(1),
                departure: Instant(departure),
                submitted: Instant(departure),
            },
            result,
            free_flow: Some(Millis(100)),
            expanded: 1,
            answered: Instant(0),
            cancelled_at: None,
            changes: Vec::new(),
            fate: None,
        })
    }

    #[test]
    fn pages_follow_answer_order_and_eviction_drops_ended_flights() {
        let mut index = FlightIndex::default();
        for seq in 1..=6 {
            index.put(entry(seq, 1_000 * seq as i64, seq % 2 == 0));
        }
        // Replacing keeps the place.
        let mut cancelled = (*entry(2, 2_000, true)).clone();
        cancelled.cancelled_at = Some(Instant(1));
        index.put(Arc::new(cancelled));
        let page = |index: &FlightIndex, after| {
            index.list(&ListQuery {
                after,
                limit: Some(2),
                ..ListQuery::default()
            })
        };
        let (first, more) = page(&index, None);
        assert!(more);
        assert_eq!(first.iter().map(|e| e.seq).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(first[1].status(), Status::Cancelled);
        let (second, _) = page(&index, Some(2));
        assert_eq!(second.iter().map(|e| e.seq).collect::<Vec<_>>(), [3, 4]);
        // Flights 1–3 end by 3,100 (rejections end at their departure).
        assert_eq!(index.evict_ended_before(Instant(3_101)), 3);
        assert!(index.get("f3").is_none() && index.get("f4").is_some());
        assert_eq!(index.len(), 3);
        let (rest, more) = page(&index, None);
        assert!(more);
        assert_eq!(rest.iter().map(|e| e.seq).collect::<Vec<_>>(), [4, 5]);
    }
}
