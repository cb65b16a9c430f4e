//! Plan output: JSON Lines, one object per request in planning order (docs/reference.md#plans).
//!
//! ```json
//! {"request": "r000042", "status": "planned", "reason": null, "origin": "S012", ...,
//!  "path": [{"node": "S012", "arrive": "...", "depart": "..."}, ...]}
//! ```
//!
//! Besides the reference's fields each line carries `expanded`, the number of search labels the
//! planner expanded for the request (search effort). Rejected requests have `status:
//! "rejected"`, their `reason`, `free_flow_s` where defined, null times and no `path`.
//!
//! A flight that zone announcements changed (docs/reference.md#zones-announced-during-the-day) has
//! the status of its last change and keeps its id; its times, `path` and delays are those of its
//! *final* plan, and the line adds:
//!
//! - `changes`: each announcement that hit it, in order: `{"zone", "announced", "airborne",
//!   "outcome"}` (`airborne`: whether it had taken off at the announcement);
//! - `original`: the plan first accepted: `{"takeoff", "landing", "path"}`;
//! - `replanned`: `extra_delay_s`, final landing minus original landing;
//! - `diverted`: `diverted_to`, the station it now lands at (`destination` stays the
//!   request's); `air_delay_s` is null (free flow is to the destination);
//! - `cancelled`: `reason: "zone_announced"`, null times, no `path`;
//! - `contingency`: no `path` (it lands nowhere); `committed` holds the part it is committed
//!   to, ending at the node it reached at or after the announcement; `takeoff` is its take-off,
//!   `landing` null.
//!
//! In a layered airspace (docs/reference.md#layered-airspace: `--layers` 2 or more) every stay adds
//! `layer` (1…L) and its `node` is the flat station or waypoint id (`{"node": "S012", "layer": 3,
//! ...}`); a flat airspace's stays have no `layer`, and reading refuses one.
//!
//! A multi-leg plan (docs/reference.md#multi-leg-trips: battery swaps at stations) keeps these
//! fields for the trip as a whole (`takeoff` the first take-off, `landing` the last landing,
//! `airborne_s` between them, ground time included, `distance_m` the edges flown, `path` every stay
//! with the station repeated at each swap) and adds `legs`, one `{"takeoff", "landing", "path"}`
//! per leg; so do `original` and `committed` (as `committed_legs`). See [`LegLine`].
//!
//! The service (`muse serve`, docs/reference.md#the-planning-service) answers with the same object
//! plus `operator`, the operator the flight belongs to, and lists a flight its operator cancelled
//! before take-off with `status: "cancelled"`, `reason: "cancelled_by_operator"`, `cancelled_at`
//! and no plan (no `path`, null times; `changes` and `original` stay when zone announcements had
//! changed it before). A service listing saved as JSON Lines is a plans file: [`read_plan_entries`]
//! reads every line of it, [`read_plans`] the lines that hold a request's answer. Any other field
//! is an error naming it, as is a value of the wrong kind, and so is a request id on a second line:
//! a plans file holds one line per request ([`read_listed_plans`] reads a listing fetched page
//! after page, which may repeat a flight).

use std::fmt::Write as _;

use muse_model::plan::{Change, Fate, ZONE_ANNOUNCED};
use muse_model::{Airspace, EdgeKind, Instant, Millis, Plan, RejectReason, Stay, UtcOffset};
use serde::{Deserialize, Serialize};

mod legs;
mod line;
mod read;

pub use legs::LegLine;
use legs::leg_lines;
pub use read::{
    read_listed_plans, read_plan_entries, read_plan_entries_file, read_plans, read_plans_file,
};

/// One line of a plans file, in model types.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanRecord {
    /// Request id.
    pub request: String,
    /// Origin station id; empty only for an unserved request (docs/reference.md#airspace-from-pads)
    /// whose sender has no pad in reach (written `null`).
    pub origin: String,
    /// Destination station id; empty only for an unserved request whose receiver has no pad
    /// in reach.
    pub destination: String,
    /// Requested departure.
    pub requested_departure: Instant,
    /// The first answer: the plan accepted, or why there is none.
    pub result: Result<Plan, RejectReason>,
    /// Free-flow airborne time, where the destination is reachable.
    pub free_flow: Option<Millis>,
    /// Search labels expanded.
    pub expanded: u64,
    /// The zone announcements that changed the flight since, in order
    /// (docs/reference.md#zones-announced-during-the-day).
    pub changes: Vec<Change>,
    /// What the last of them made of it; `None` if none changed it.
    pub fate: Option<Fate>,
}

impl PlanRecord {
    /// A request answered once and never changed.
    pub fn first(
        request: String,
        origin: String,
        destination: String,
        requested_departure: Instant,
        result: Result<Plan, RejectReason>,
        free_flow: Option<Millis>,
        expanded: u64,
    ) -> Self {
        PlanRecord {
            request,
            origin,
            destination,
            requested_departure,
            result,
            free_flow,
            expanded,
            changes: Vec::new(),
            fate: None,
        }
    }

    /// The final plan, if the flight lands somewhere: the first plan, or the one it was
    /// replanned or diverted to.
    pub fn final_plan(&self) -> Option<&Plan> {
        match &self.fate {
            None => self.result.as_ref().ok(),
            Some(f) => f.plan(),
        }
    }

    /// The status written: `planned`, `rejected`, or the last change's outcome.
    pub fn status(&self) -> &'static str {
        match (&self.fate, &self.result) {
            (Some(f), _) => f.kind().as_str(),
            (None, Ok(_)) => "planned",
            (None, Err(_)) => "rejected",
        }
    }
}

/// A [`Change`] as written.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChangeLine {
    /// Zone id.
    pub zone: String,
    /// Announcement instant, RFC 3339.
    pub announced: String,
    /// Whether the flight had taken off then.
    pub airborne: bool,
    /// `replanned`, `diverted`, `cancelled` or `contingency`.
    pub outcome: String,
}

/// The plan first accepted for a flight that announcements changed, as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OriginalLine {
    /// Take-off, RFC 3339.
    pub takeoff: String,
    /// Landing, RFC 3339.
    pub landing: String,
    /// The stays.
    pub path: Vec<StayLine>,
    /// Its legs, when it has two or more.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub legs: Option<Vec<LegLine>>,
}

/// One stay of a [`PlanLine`], as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StayLine {
    /// Node id: in a layered airspace (docs/reference.md#layered-airspace), the id of the flat
    /// station or waypoint.
    pub node: String,
    /// The layer (1…L) of the stay in a layered airspace; absent in a flat one.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub layer: Option<u32>,
    /// Arrival, RFC 3339.
    pub arrive: String,
    /// Departure, RFC 3339.
    pub depart: String,
}

/// The docs/reference.md#plans object as written: one line of a plans file, or the body of the
/// service's answer about a flight (which adds `operator` and, once its operator cancelled it,
/// `cancelled_at`). Reading refuses any other field.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanLine {
    /// Request id.
    pub request: String,
    /// `planned`, `rejected`, or what zone announcements made of it (`replanned`, `diverted`,
    /// `cancelled`, `contingency`); the service also says `cancelled` for a flight its
    /// operator cancelled.
    pub status: String,
    /// Rejection (or cancellation: `zone_announced`, `cancelled_by_operator`) reason; `null`
    /// when planned.
    pub reason: Option<String>,
    /// Origin station id; `null` only for an unserved request whose sender has no pad in
    /// reach (reason `unserved`, docs/reference.md#airspace-from-pads).
    pub origin: Option<String>,
    /// Destination station id; `null` only for an unserved request whose receiver has no pad
    /// in reach.
    pub destination: Option<String>,
    /// Requested departure, RFC 3339.
    pub requested_departure: String,
    /// Take-off, RFC 3339.
    pub takeoff: Option<String>,
    /// Landing, RFC 3339.
    pub landing: Option<String>,
    /// Landing minus take-off, s.
    pub airborne_s: Option<f64>,
    /// Free-flow airborne time, s.
    pub free_flow_s: Option<f64>,
    /// Airborne minus free flow, s.
    pub air_delay_s: Option<f64>,
    /// Take-off minus requested departure, s.
    pub ground_delay_s: Option<f64>,
    /// Length of the path, m.
    pub distance_m: Option<f64>,
    /// Search labels expanded.
    #[serde(default)]
    pub expanded: u64,
    /// Zone announcements that changed the flight, in order.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub changes: Option<Vec<ChangeLine>>,
    /// Replanned: final landing minus original landing, s.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub extra_delay_s: Option<f64>,
    /// Diverted: the station it lands at instead.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub diverted_to: Option<String>,
    /// The stays, when it lands somewhere.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub path: Option<Vec<StayLine>>,
    /// The legs of `path`, when it has two or more (docs/reference.md#multi-leg-trips).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub legs: Option<Vec<LegLine>>,
    /// Contingency: the stays it is committed to.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub committed: Option<Vec<StayLine>>,
    /// The legs of `committed`, when it has two or more; the last has no landing.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub committed_legs: Option<Vec<LegLine>>,
    /// Changed by announcements: the plan first accepted.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub original: Option<OriginalLine>,
    /// The operator the flight belongs to: given by the service (`muse serve`), never by
    /// [`plan_line`].
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub operator: Option<String>,
    /// When its operator cancelled the flight, RFC 3339: given by the service for a flight
    /// cancelled by its operator, never by [`plan_line`].
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub cancelled_at: Option<String>,
}

/// A flight its operator cancelled before take-off, as the service lists it
/// (docs/reference.md#the-planning-service): `status: "cancelled"`, `reason:
/// "cancelled_by_operator"`, no plan. It holds no reservation and flies nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct OperatorCancellation {
    /// Request id.
    pub request: String,
    /// Origin station id.
    pub origin: String,
    /// Destination station id.
    pub destination: String,
    /// Requested departure.
    pub requested_departure: Instant,
    /// Free-flow airborne time, where the destination is reachable.
    pub free_flow: Option<Millis>,
    /// The plan first accepted, when the line gives it (`original`: zone announcements had
    /// changed the flight before it was cancelled).
    pub original: Option<Plan>,
    /// The zone announcements that had changed it, in order
    /// (docs/reference.md#zones-announced-during-the-day).
    pub changes: Vec<Change>,
    /// When it was cancelled, if the line says (`cancelled_at`).
    pub cancelled_at: Option<Instant>,
}

/// What one line of a plans file holds.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanItem {
    /// A request's answer: planned, rejected, or changed by zone announcements
    /// (docs/reference.md#plans, #zones-announced-during-the-day).
    Record(PlanRecord),
    /// A flight its operator cancelled (a service listing): it flies nothing.
    CancelledByOperator(OperatorCancellation),
}

/// One line of a plans file, as [`read_plan_entries`] reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanEntry {
    /// Its line number in the file (1-based; blank lines count).
    pub line: usize,
    /// The operator the flight belongs to, when the line gives it (a service listing).
    pub operator: Option<String>,
    /// What the line holds.
    pub item: PlanItem,
}

impl PlanEntry {
    /// The request id.
    pub fn request(&self) -> &str {
        match &self.item {
            PlanItem::Record(r) => &r.request,
            PlanItem::CancelledByOperator(c) => &c.request,
        }
    }

    /// The origin and destination station ids.
    pub fn stations(&self) -> (&str, &str) {
        match &self.item {
            PlanItem::Record(r) => (&r.origin, &r.destination),
            PlanItem::CancelledByOperator(c) => (&c.origin, &c.destination),
        }
    }

    /// The requested departure.
    pub fn requested_departure(&self) -> Instant {
        match &self.item {
            PlanItem::Record(r) => r.requested_departure,
            PlanItem::CancelledByOperator(c) => c.requested_departure,
        }
    }

    /// The status the line gives: [`PlanRecord::status`], or `cancelled`.
    pub fn status(&self) -> &'static str {
        match &self.item {
            PlanItem::Record(r) => r.status(),
            PlanItem::CancelledByOperator(_) => "cancelled",
        }
    }

    /// The zone announcements that changed the flight, in order.
    pub fn changes(&self) -> &[Change] {
        match &self.item {
            PlanItem::Record(r) => &r.changes,
            PlanItem::CancelledByOperator(c) => &c.changes,
        }
    }

    /// The record of a request's answer; `None` for a flight its operator cancelled.
    pub fn record(&self) -> Option<&PlanRecord> {
        match &self.item {
            PlanItem::Record(r) => Some(r),
            PlanItem::CancelledByOperator(_) => None,
        }
    }
}

/// Total length of the corridors a plan flies, metres (rounded to the millimetre): the time
/// on the ground between two legs adds nothing, nor do the vertical links between layers
/// (docs/reference.md#layered-airspace).
pub fn plan_distance_m(airspace: &Airspace, plan: &Plan) -> f64 {
    let total: f64 = plan
        .hops()
        .filter_map(|(x, y)| airspace.edge_between(x.node, y.node))
        .filter(|&e| matches!(airspace.edge_kind(e), EdgeKind::Corridor { .. }))
        .map(|e| airspace.edge(e).length_m)
        .sum();
    (total * 1e3).round() / 1e3
}

/// Appends one JSON line (with its newline) for `record` to `out`.
///
/// ```
/// use muse_formats::plans::{write_plan_line, PlanRecord};
/// use muse_model::{Instant, Millis, RejectReason, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": []}"#, "a").unwrap();
/// let r = PlanRecord {
///     request: "r1".into(), origin: "A".into(), destination: "B".into(),
///     requested_departure: Instant(0), result: Err(RejectReason::OutOfRange),
///     free_flow: Some(Millis(1_500_000)), expanded: 0, changes: vec![], fate: None,
/// };
/// let mut out = String::new();
/// write_plan_line(&mut out, &air, UtcOffset::SINGAPORE, &r);
/// assert!(out.starts_with(r#"{"request":"r1","status":"rejected","reason":"out_of_range""#));
/// ```
pub fn write_plan_line(
    out: &mut String,
    airspace: &Airspace,
    offset: UtcOffset,
    record: &PlanRecord,
) {
    let line = plan_line(airspace, offset, record);
    // Serialising plain strings and numbers cannot fail.
    let _ = writeln!(out, "{}", serde_json::to_string(&line).unwrap_or_default());
}

/// `stays` as written, times in `offset`: in a layered airspace, each node as its flat id and
/// its layer.
fn stay_lines(airspace: &Airspace, offset: UtcOffset, stays: &[Stay]) -> Vec<StayLine> {
    let layered = airspace.layers().is_some();
    stays
        .iter()
        .map(|s| StayLine {
            node: airspace.flat().node(airspace.flat_node(s.node)).id.clone(),
            layer: layered.then(|| airspace.node_layer(s.node)),
            arrive: s.arrive.to_rfc3339(offset),
            depart: s.depart.to_rfc3339(offset),
        })
        .collect()
}

/// The docs/reference.md#plans object for `record`, times in `offset`.
pub fn plan_line(airspace: &Airspace, offset: UtcOffset, record: &PlanRecord) -> PlanLine {
    let secs = |m: Millis| m.as_secs_f64();
    let plan = record.final_plan();
    let reason = match (&record.fate, &record.result) {
        (Some(Fate::Cancelled), _) => Some(ZONE_ANNOUNCED.to_owned()),
        (None, Err(r)) => Some(r.as_str().to_owned()),
        _ => None,
    };
    let diverted = matches!(record.fate, Some(Fate::Diverted(_)));
    let committed = match &record.fate {
        Some(Fate::Contingency(c)) => Some(c),
        _ => None,
    };
    let original = record
        .result
        .as_ref()
        .ok()
        .filter(|_| record.fate.is_some());
    PlanLine {
        request: record.request.clone(),
        status: record.status().to_owned(),
        reason,
        origin: (!record.origin.is_empty()).then(|| record.origin.clone()),
        destination: (!record.destination.is_empty()).then(|| record.destination.clone()),
        requested_departure: record.requested_departure.to_rfc3339(offset),
        takeoff: plan.or(committed).map(|p| p.takeoff().to_rfc3339(offset)),
        landing: plan.map(|p| p.landing().to_rfc3339(offset)),
        airborne_s: plan.map(|p| secs(p.airborne())),
        free_flow_s: record.free_flow.map(secs),
        air_delay_s: plan
            .filter(|_| !diverted)
            .and_then(|p| Some(secs(p.airborne() - record.free_flow?))),
        ground_delay_s: plan.map(|p| secs(p.takeoff() - record.requested_departure)),
        distance_m: plan.map(|p| plan_distance_m(airspace, p)),
        expanded: record.expanded,
        changes: (!record.changes.is_empty()).then(|| {
            record
                .changes
                .iter()
                .map(|c| ChangeLine {
                    zone: c.zone.clone(),
                    announced: c.announced.to_rfc3339(offset),
                    airborne: c.airborne,
                    outcome: c.outcome.as_str().to_owned(),
                })
                .collect()
        }),
        extra_delay_s: match (&record.fate, original) {
            (Some(Fate::Replanned(p)), Some(o)) => Some(secs(p.landing() - o.landing())),
            _ => None,
        },
        diverted_to: plan
            .filter(|_| diverted)
            .and_then(|p| p.path.last())
            .map(|s| airspace.flat().node(airspace.flat_node(s.node)).id.clone()),
        path: plan.map(|p| stay_lines(airspace, offset, &p.path)),
        legs: plan.and_then(|p| leg_lines(airspace, offset, p, true)),
        committed: committed.map(|p| stay_lines(airspace, offset, &p.path)),
        committed_legs: committed.and_then(|p| leg_lines(airspace, offset, p, false)),
        original: original.map(|o| OriginalLine {
            takeoff: o.takeoff().to_rfc3339(offset),
            landing: o.landing().to_rfc3339(offset),
            path: stay_lines(airspace, offset, &o.path),
            legs: leg_lines(airspace, offset, o, true),
        }),
        operator: None,
        cancelled_at: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airspace_geojson::read_airspace;
    use muse_model::NodeId;

    pub(super) fn air() -> Airspace {
        read_airspace(
            r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8089, 1.3]}, "properties": {"id": "B", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.8089, 1.3]]}, "properties": {"from": "A", "to": "B", "length_m": 1000}}]}"#,
            "a",
        )
        .unwrap()
    }

    #[test]
    fn golden_line_and_round_trip() {
        let plan = Plan {
            path: vec![
                Stay {
                    node: NodeId(0),
                    arrive: Instant(1_000),
                    depart: Instant(6_250),
                },
                Stay {
                    node: NodeId(1),
                    arrive: Instant(126_250),
                    depart: Instant(126_250),
                },
            ],
        };
        let rec = PlanRecord {
            request: "r1".into(),
            origin: "A".into(),
            destination: "B".into(),
            requested_departure: Instant(0),
            result: Ok(plan),
            free_flow: Some(Millis(120_000)),
            expanded: 3,
            changes: vec![],
            fate: None,
        };
        let mut out = String::new();
        write_plan_line(&mut out, &air(), UtcOffset::SINGAPORE, &rec);
        assert_eq!(
            out,
            concat!(
                r#"{"request":"r1","status":"planned","reason":null,"origin":"A","destination":"B","#,
                r#""requested_departure":"1970-01-01T08:00:00.000+08:00","takeoff":"1970-01-01T08:00:01.000+08:00","#,
                r#""landing":"1970-01-01T08:02:06.250+08:00","airborne_s":125.25,"free_flow_s":120.0,"air_delay_s":5.25,"#,
                r#""ground_delay_s":1.0,"distance_m":1000.0,"expanded":3,"path":[{"node":"A","arrive":"1970-01-01T08:00:01.000+08:00","#,
                r#""depart":"1970-01-01T08:00:06.250+08:00"},{"node":"B","arrive":"1970-01-01T08:02:06.250+08:00","depart":"1970-01-01T08:02:06.250+08:00"}]}"#,
                "\n"
            )
        );
        assert_eq!(read_plans(&out, "p.jsonl", &air()).unwrap(), vec![rec]);
    }

    fn flight(takeoff: i64, to: u32) -> Plan {
        let stay = |n, t| Stay {
            node: NodeId(n),
            arrive: Instant(t),
            depart: Instant(t),
        };
        Plan {
            path: vec![stay(1 - to, takeoff), stay(to, takeoff + 120_000)],
        }
    }

    /// A record first planned A→B at take-off 0, then changed by zone `Z` announced at 0.
    fn changed(fate: Fate) -> PlanRecord {
        PlanRecord {
            changes: vec![Change {
                zone: "Z".into(),
                announced: Instant(0),
                airborne: matches!(fate, Fate::Diverted(_) | Fate::Contingency(_)),
                outcome: fate.kind(),
            }],
            fate: Some(fate),
            ..PlanRecord::first(
                "r1".into(),
                "A".into(),
                "B".into(),
                Instant(0),
                Ok(flight(0, 1)),
                Some(Millis(120_000)),
                3,
            )
        }
    }

    #[test]
    fn every_fate_round_trips() {
        let committed = Plan {
            path: flight(0, 1).path[..1].to_vec(),
        };
        let fates = [
            Fate::Replanned(flight(60_000, 1)),
            Fate::Diverted(flight(0, 0)),
            Fate::Cancelled,
            Fate::Contingency(committed),
        ];
        for fate in fates {
            let rec = changed(fate);
            let mut out = String::new();
            write_plan_line(&mut out, &air(), UtcOffset::SINGAPORE, &rec);
            assert!(
                out.contains(&format!(r#""status":"{}""#, rec.status())),
                "{out}"
            );
            assert!(out.contains(r#""original":{"takeoff":"1970-01-01T08:00:00.000+08:00""#));
            assert_eq!(read_plans(&out, "p.jsonl", &air()).unwrap(), vec![rec]);
        }
    }

    #[test]
    fn changed_lines_carry_their_outcome_fields() {
        let line = |rec: &PlanRecord| plan_line(&air(), UtcOffset::SINGAPORE, rec);
        let replanned = line(&changed(Fate::Replanned(flight(60_000, 1))));
        assert_eq!(replanned.extra_delay_s, Some(60.0));
        assert_eq!(replanned.air_delay_s, Some(0.0));
        let diverted = line(&changed(Fate::Diverted(flight(0, 0))));
        assert_eq!(diverted.diverted_to.as_deref(), Some("A"));
        assert_eq!(diverted.air_delay_s, None);
        let cancelled = line(&changed(Fate::Cancelled));
        assert_eq!(cancelled.reason.as_deref(), Some("zone_announced"));
        assert!(cancelled.path.is_none() && cancelled.takeoff.is_none());
        let stranded = line(&changed(Fate::Contingency(Plan {
            path: flight(0, 1).path[..1].to_vec(),
        })));
        assert!(stranded.path.is_none() && stranded.landing.is_none());
        assert_eq!(stranded.committed.map(|c| c.len()), Some(1));
    }

    #[test]
    fn changed_lines_must_be_whole() {
        let mut out = String::new();
        write_plan_line(
            &mut out,
            &air(),
            UtcOffset::SINGAPORE,
            &changed(Fate::Cancelled),
        );
        let mut no_original: serde_json::Value = serde_json::from_str(&out).unwrap();
        no_original.as_object_mut().unwrap().remove("original");
        let e = read_plans(&no_original.to_string(), "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "p.jsonl: line 1: field `original.path`: missing for a `cancelled` request"
        );
        let wrong_status = out.replace(r#""status":"cancelled""#, r#""status":"diverted""#);
        let e = read_plans(&wrong_status, "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "p.jsonl: line 1: field `status`: `diverted` is not the outcome of the last change"
        );
    }

    /// The airspace and the listing of `testdata/service` (see its README): a real `muse
    /// serve` session's `GET /v1/flights`, one flight a line.
    fn service_listing() -> (Airspace, &'static str) {
        let air = read_airspace(
            include_str!("../testdata/service/line.geojson"),
            "line.geojson",
        )
        .unwrap();
        (air, include_str!("../testdata/service/flights.jsonl"))
    }

    #[test]
    fn a_service_listing_is_read_line_by_line() {
        let (air, text) = service_listing();
        let entries = read_plan_entries(text, "flights.jsonl", &air).unwrap();
        let seen: Vec<(&str, &str, usize)> = entries
            .iter()
            .map(|e| (e.request(), e.status(), e.line))
            .collect();
        assert_eq!(
            seen,
            [
                ("a1", "diverted", 1),
                ("k1", "contingency", 2),
                ("a2", "cancelled", 3),
                ("b1", "cancelled", 4),
                ("e1", "replanned", 5),
                ("b2", "cancelled", 6),
                ("a3", "planned", 7),
                ("c1", "cancelled", 8),
                ("r1", "rejected", 9),
                ("r2", "rejected", 10),
            ]
        );
        assert!(
            entries
                .iter()
                .all(|e| e.operator.as_deref() == Some("open"))
        );
        let cancelled: Vec<&OperatorCancellation> = entries
            .iter()
            .filter_map(|e| match &e.item {
                PlanItem::CancelledByOperator(c) => Some(c),
                PlanItem::Record(_) => None,
            })
            .collect();
        assert_eq!(cancelled.len(), 2);
        // b1 was replanned by ZC, then cancelled by its operator: its change and first plan
        // are kept; c1 was cancelled before any zone.
        let (b1, c1) = (cancelled[0], cancelled[1]);
        assert_eq!((b1.request.as_str(), c1.request.as_str()), ("b1", "c1"));
        assert_eq!(b1.changes.len(), 1);
        assert_eq!(b1.changes[0].outcome, muse_model::plan::FateKind::Replanned);
        assert_eq!(b1.original.as_ref().map(|p| p.path.len()), Some(2));
        assert!(c1.changes.is_empty() && c1.original.is_none());
        assert!(b1.cancelled_at.is_some() && c1.cancelled_at.is_some());
        assert_eq!(b1.free_flow, Some(Millis(120_000)));
        // The records are the other eight lines, as read_plans gives them.
        let records = read_plans(text, "flights.jsonl", &air).unwrap();
        let from_entries: Vec<&PlanRecord> = entries.iter().filter_map(PlanEntry::record).collect();
        assert_eq!(records.iter().collect::<Vec<_>>(), from_entries);
        assert_eq!(records.len(), 8);
        let flying = records.iter().filter(|r| r.final_plan().is_some()).count();
        assert_eq!(flying, 3, "a1, e1 and a3 land; k1 is committed only");
        assert!(matches!(
            records[1].fate,
            Some(Fate::Contingency(ref p)) if p.path.len() == 2
        ));
        // A line of `muse plan` (no operator) reads the same as the service's.
        let planned = text
            .lines()
            .nth(6)
            .unwrap()
            .replace(r#","operator":"open""#, "");
        let plain = read_plan_entries(&planned, "p.jsonl", &air).unwrap();
        assert_eq!(plain[0].operator, None);
        assert_eq!(plain[0].item, entries[6].item);
    }

    #[test]
    fn malformed_service_lines_are_named() {
        let (air, text) = service_listing();
        let b1 = text.lines().nth(3).unwrap();
        let c1 = text.lines().nth(7).unwrap();
        let a3 = text.lines().nth(6).unwrap();
        let edit = |line: &str, f: &dyn Fn(&mut serde_json::Map<String, serde_json::Value>)| {
            let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
            f(v.as_object_mut().unwrap());
            read_plan_entries(&format!("\n{v}\n"), "p.jsonl", &air)
                .unwrap_err()
                .to_string()
        };
        let a3_path = serde_json::from_str::<serde_json::Value>(a3).unwrap()["path"].clone();
        assert_eq!(
            edit(c1, &|o| {
                o.insert("path".into(), a3_path.clone());
            }),
            "p.jsonl: line 2: field `path`: a flight cancelled by its operator flies nothing: it \
             has no `path` (status `cancelled`, reason `cancelled_by_operator`)"
        );
        assert_eq!(
            edit(b1, &|o| {
                o.remove("original");
            }),
            "p.jsonl: line 2: field `original.path`: missing for a flight that zone \
             announcements changed before its operator cancelled it"
        );
        assert!(
            edit(c1, &|o| {
                o.insert("cancelled_at".into(), "yesterday".into());
            })
            .starts_with(
                "p.jsonl: line 2: field `cancelled_at`: `yesterday` is not an RFC 3339 timestamp"
            )
        );
        assert_eq!(
            edit(a3, &|o| {
                o.insert("cancelled_at".into(), "2026-01-05T08:00:00Z".into());
            }),
            "p.jsonl: line 2: field `cancelled_at`: only a flight cancelled by its operator \
             (status `cancelled`, reason `cancelled_by_operator`) has one; this line's status is \
             `planned`"
        );
        assert_eq!(
            edit(c1, &|o| {
                o.insert("reason".into(), serde_json::Value::Null);
            }),
            "p.jsonl: line 2: field `reason`: null is not the reason of a `cancelled` flight: \
             `zone_announced` (a zone announcement cancelled it) or `cancelled_by_operator` (its \
             operator did)"
        );
        assert!(
            edit(c1, &|o| {
                o.insert("operator".into(), 7.into());
            })
            .starts_with("p.jsonl: line 2: field `operator`: not a plan record: invalid type"),
        );
        let e = edit(a3, &|o| {
            o.insert("pilot".into(), "Ann".into());
        });
        assert!(
            e.starts_with(
                "p.jsonl: line 2: field `pilot`: not a plan record: unknown field `pilot`"
            ),
            "{e}"
        );
        let e = edit(a3, &|o| {
            o["path"][1]
                .as_object_mut()
                .unwrap()
                .insert("hover".into(), true.into());
        });
        assert!(
            e.starts_with(
                "p.jsonl: line 2: field `path[1].hover`: not a plan record: unknown field `hover`"
            ),
            "{e}"
        );
        let e = edit(a3, &|o| {
            o.insert(
                "requested_departure".into(),
                "2026-06-30T23:59:60+08:00".into(),
            );
        });
        assert!(
            e.starts_with("p.jsonl: line 2: field `requested_departure`: `2026-06-30T23:59:60+08:00` is a leap second"),
            "{e}"
        );
    }

    #[test]
    fn bad_lines_are_named() {
        let e = read_plans("{}\n", "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("p.jsonl: line 1: not a plan record"), "{e}");
        for empty in ["", "\n \n"] {
            assert_eq!(
                read_plans(empty, "p.jsonl", &air())
                    .unwrap_err()
                    .to_string(),
                "p.jsonl: no plans: the file has no line (a plans file has one line per request)"
            );
        }
        let e = read_plans("\n{\"request\":\"r1\",\"sta", "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "p.jsonl: line 2: the line is cut short: it ends before its JSON object does (not \
             complete JSON; was the file truncated?)"
        );
        let e = read_plans("{\"request\";\"r1\"}", "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "p.jsonl: line 1: not JSON: expected `:` at column 11 of the line"
        );
        let line = r#"{"request":"r1","status":"planned","reason":null,"origin":"A","destination":"B","requested_departure":"1970-01-01T08:00:00.000+08:00","takeoff":null,"landing":null,"airborne_s":null,"free_flow_s":null,"air_delay_s":null,"ground_delay_s":null,"distance_m":null,"path":[{"node":"Q","arrive":"1970-01-01T08:00:00.000+08:00","depart":"1970-01-01T08:00:00.000+08:00"}]}"#;
        let e = read_plans(&format!("\n{line}\n"), "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "p.jsonl: line 2: field `path[0].node`: unknown node id `Q`"
        );
        for field in ["origin", "destination"] {
            let bad = line
                .replace("\"node\":\"Q\"", "\"node\":\"A\"")
                .replace(&format!("\"{field}\":\""), &format!("\"{field}\":\"Z"));
            let e = read_plans(&bad, "p.jsonl", &air()).unwrap_err().to_string();
            let id = if field == "origin" { "ZA" } else { "ZB" };
            assert_eq!(
                e,
                format!("p.jsonl: line 1: field `{field}`: unknown node id `{id}`")
            );
        }
    }

    /// `A — B` (1 km, eastward) at two layers, and A→B climbing to layer 2: up at `A` in
    /// 1.829 s, along in 120 s, down at `B`.
    fn layered() -> (Airspace, PlanRecord) {
        let layers = muse_model::Layers {
            count: 2,
            ..muse_model::Layers::default()
        };
        let air = Airspace::line(&[1_000.0]).layered(&layers).unwrap();
        let plan = muse_model::testing::plan(&[
            (0, 0, 0),
            (2, 1_829, 1_829),
            (3, 121_829, 124_000),
            (1, 125_829, 125_829),
        ]);
        let rec = PlanRecord::first(
            "r1".into(),
            "A".into(),
            "B".into(),
            Instant(0),
            Ok(plan),
            Some(Millis(120_000)),
            4,
        );
        (air, rec)
    }

    #[test]
    fn layered_stays_give_the_flat_node_and_the_layer() {
        let (air, rec) = layered();
        let mut out = String::new();
        write_plan_line(&mut out, &air, UtcOffset::SINGAPORE, &rec);
        let stay = |node: &str, layer: u32, arrive: &str, depart: &str| {
            format!(
                r#"{{"node":"{node}","layer":{layer},"arrive":"1970-01-01T08:0{arrive}+08:00","depart":"1970-01-01T08:0{depart}+08:00"}}"#
            )
        };
        let path = [
            stay("A", 1, "0:00.000", "0:00.000"),
            stay("A", 2, "0:01.829", "0:01.829"),
            stay("B", 2, "2:01.829", "2:04.000"),
            stay("B", 1, "2:05.829", "2:05.829"),
        ]
        .join(",");
        // The vertical links add to the time, not to the distance.
        assert!(
            out.ends_with(&format!(
                "{}{path}]}}\n",
                r#""distance_m":1000.0,"expanded":4,"path":["#
            )),
            "{out}"
        );
        assert_eq!(read_plans(&out, "p.jsonl", &air).unwrap(), vec![rec]);
    }

    #[test]
    fn layers_out_of_place_are_refused() {
        let (air, rec) = layered();
        let mut out = String::new();
        write_plan_line(&mut out, &air, UtcOffset::SINGAPORE, &rec);
        let err = |text: &str, air: &Airspace| {
            read_plans(&format!("\n{text}"), "p.jsonl", air)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            err(&out.replacen(r#""layer":2"#, r#""layer":3"#, 1), &air),
            "p.jsonl: line 2: field `path[1].layer`: layer 3 is out of range: give 1 to 2"
        );
        assert_eq!(
            err(&out.replacen(r#""layer":1,"#, r#""layer":0,"#, 1), &air),
            "p.jsonl: line 2: field `path[0].layer`: layer 0 is out of range: give 1 to 2"
        );
        assert_eq!(
            err(&out.replacen(r#""layer":2,"#, "", 1), &air),
            "p.jsonl: line 2: field `path[1].layer`: missing: the airspace has 2 layers, and \
             every stay gives its layer (1 to 2)"
        );
        assert_eq!(
            err(&out, air.flat()),
            "p.jsonl: line 2: field `path[0].layer`: layer 1, but the airspace is flat (one \
             layer): a stay gives its layer only in a layered airspace (`--layers` 2 or more)"
        );
        // The layered ids are not written, nor read.
        assert_eq!(
            err(
                &out.replacen(r#""node":"A","layer":2"#, r#""node":"A@2","layer":2"#, 1),
                &air
            ),
            "p.jsonl: line 2: field `path[1].node`: unknown node id `A@2`"
        );
        assert_eq!(
            err(
                &out.replacen(r#""origin":"A""#, r#""origin":"A@2""#, 1),
                &air
            ),
            "p.jsonl: line 2: field `origin`: unknown node id `A@2`"
        );
        let e = err(&out.replacen(r#""layer":2"#, r#""layer":-2"#, 1), &air);
        assert!(
            e.starts_with("p.jsonl: line 2: field `path[1].layer`: not a plan record"),
            "{e}"
        );
    }
}
