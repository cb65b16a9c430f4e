//! Plan output: JSON Lines, one object per request in planning order (SPEC §7).
//!
//! ```json
//! {"request": "r000042", "status": "planned", "reason": null, "origin": "S012", ...,
//!  "path": [{"node": "S012", "arrive": "...", "depart": "..."}, ...]}
//! ```
//!
//! Besides the SPEC's fields each line carries `expanded`, the number of search labels the
//! planner expanded for the request (search effort). Rejected requests have `status:
//! "rejected"`, their `reason`, `free_flow_s` where defined, null times and no `path`.
//!
//! A flight that zone announcements changed (SPEC §11) has the status of its last change and
//! keeps its id; its times, `path` and delays are those of its *final* plan, and the line adds:
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
//! A multi-leg plan (SPEC §12: battery swaps at stations) keeps these fields for the trip as a
//! whole (`takeoff` the first take-off, `landing` the last landing, `airborne_s` between them,
//! ground time included, `distance_m` the edges flown, `path` every stay with the station
//! repeated at each swap) and adds `legs`, one `{"takeoff", "landing", "path"}` per leg; so do
//! `original` and `committed` (as `committed_legs`). See [`LegLine`].

use std::fmt::Write as _;
use std::path::Path;

use muse_model::plan::{Fate, FateKind, ZONE_ANNOUNCED};
use muse_model::{Airspace, Instant, Millis, Plan, RejectReason, Stay, UtcOffset};
use serde::{Deserialize, Serialize};

use crate::error::{InputError, Location};

mod legs;

pub use legs::LegLine;
use legs::{PlanFields, leg_lines};

/// One line of a plans file, in model types.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanRecord {
    /// Request id.
    pub request: String,
    /// Origin station id.
    pub origin: String,
    /// Destination station id.
    pub destination: String,
    /// Requested departure.
    pub requested_departure: Instant,
    /// The first answer: the plan accepted, or why there is none.
    pub result: Result<Plan, RejectReason>,
    /// Free-flow airborne time, where the destination is reachable.
    pub free_flow: Option<Millis>,
    /// Search labels expanded.
    pub expanded: u64,
    /// The zone announcements that changed the flight since, in order (SPEC §11).
    pub changes: Vec<ChangeNote>,
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

/// What one zone announcement did to a flight.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChangeNote {
    /// The zone announced.
    pub zone: String,
    /// When it was announced.
    pub announced: Instant,
    /// Whether the flight had taken off then.
    pub airborne: bool,
    /// What the announcement made of the flight.
    pub outcome: FateKind,
}

/// A [`ChangeNote`] as written.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
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
pub struct StayLine {
    /// Node id.
    pub node: String,
    /// Arrival, RFC 3339.
    pub arrive: String,
    /// Departure, RFC 3339.
    pub depart: String,
}

/// The SPEC §7 object as written: one line of a plans file, or the body of the service's
/// answer about a flight.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanLine {
    /// Request id.
    pub request: String,
    /// `planned` or `rejected` (the service also says `cancelled`).
    pub status: String,
    /// Rejection (or cancellation) reason; `null` when planned.
    pub reason: Option<String>,
    /// Origin station id.
    pub origin: String,
    /// Destination station id.
    pub destination: String,
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
    /// The legs of `path`, when it has two or more (SPEC §12).
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
}

/// Total length of the edges a plan flies, metres (rounded to the millimetre): the time on
/// the ground between two legs adds nothing.
pub fn plan_distance_m(airspace: &Airspace, plan: &Plan) -> f64 {
    let total: f64 = plan
        .hops()
        .filter_map(|(x, y)| airspace.edge_between(x.node, y.node))
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

/// `stays` as written, times in `offset`.
fn stay_lines(airspace: &Airspace, offset: UtcOffset, stays: &[Stay]) -> Vec<StayLine> {
    stays
        .iter()
        .map(|s| StayLine {
            node: airspace.node(s.node).id.clone(),
            arrive: s.arrive.to_rfc3339(offset),
            depart: s.depart.to_rfc3339(offset),
        })
        .collect()
}

/// The SPEC §7 object for `record`, times in `offset`.
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
        origin: record.origin.clone(),
        destination: record.destination.clone(),
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
            .map(|s| airspace.node(s.node).id.clone()),
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
    }
}

/// Reads a plans JSON Lines file's text. Node ids are resolved against `airspace`; every
/// error names the file, line and field.
pub fn read_plans(
    text: &str,
    file: &str,
    airspace: &Airspace,
) -> Result<Vec<PlanRecord>, InputError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        if raw.trim().is_empty() {
            continue;
        }
        let at = LineReader {
            file,
            line_no: i + 1,
            airspace,
        };
        let line: PlanLine = serde_json::from_str(raw)
            .map_err(|e| at.err(None, format!("not a plan record: {e}")))?;
        out.push(at.record(&line)?);
    }
    Ok(out)
}

/// Reads one line of a plans file, naming it in errors.
struct LineReader<'a> {
    file: &'a str,
    line_no: usize,
    airspace: &'a Airspace,
}

impl LineReader<'_> {
    fn err(&self, field: Option<&str>, msg: String) -> InputError {
        InputError::new(self.file, Location::Line(self.line_no), field, msg)
    }

    fn time(&self, field: &str, text: &str) -> Result<Instant, InputError> {
        Instant::parse_rfc3339(text).map_err(|e| self.err(Some(field), e.to_string()))
    }

    /// The plan whose stays are `field` of a `status` line.
    fn stays(
        &self,
        field: &str,
        status: &str,
        stays: Option<&Vec<StayLine>>,
    ) -> Result<Plan, InputError> {
        let stays = stays
            .ok_or_else(|| self.err(Some(field), format!("missing for a `{status}` request")))?;
        if stays.is_empty() {
            return Err(self.err(Some(field), "empty".into()));
        }
        let mut path = Vec::with_capacity(stays.len());
        for (k, s) in stays.iter().enumerate() {
            let node = self.airspace.node_id(&s.node).ok_or_else(|| {
                self.err(
                    Some(&format!("{field}[{k}].node")),
                    format!("unknown node id `{}`", s.node),
                )
            })?;
            path.push(Stay {
                node,
                arrive: self.time(&format!("{field}[{k}].arrive"), &s.arrive)?,
                depart: self.time(&format!("{field}[{k}].depart"), &s.depart)?,
            });
        }
        Ok(Plan { path })
    }

    fn record(&self, line: &PlanLine) -> Result<PlanRecord, InputError> {
        let free_flow = line
            .free_flow_s
            .map(|s| {
                Millis::from_secs_f64(s).map_err(|e| self.err(Some("free_flow_s"), e.to_string()))
            })
            .transpose()?;
        let mut record = PlanRecord::first(
            line.request.clone(),
            line.origin.clone(),
            line.destination.clone(),
            self.time("requested_departure", &line.requested_departure)?,
            Err(RejectReason::NoFeasiblePlan),
            free_flow,
            line.expanded,
        );
        let status = line.status.as_str();
        match status {
            "planned" => record.result = Ok(self.plan(status, &final_plan(line))?),
            "rejected" => {
                let reason = line.reason.as_deref().unwrap_or("");
                record.result = Err(RejectReason::parse(reason).ok_or_else(|| {
                    self.err(
                        Some("reason"),
                        format!("`{reason}` is not a rejection reason"),
                    )
                })?);
            }
            _ => self.changed(line, &mut record)?,
        }
        Ok(record)
    }

    /// The first plan, changes and fate of a flight zone announcements changed.
    fn changed(&self, line: &PlanLine, record: &mut PlanRecord) -> Result<(), InputError> {
        let status = line.status.as_str();
        let kind = FateKind::parse(status).ok_or_else(|| {
            self.err(
                Some("status"),
                format!(
                    "`{status}` is not `planned`, `rejected`, `replanned`, `diverted`, \
                     `cancelled` or `contingency`"
                ),
            )
        })?;
        let original = line.original.as_ref();
        record.result = Ok(self.plan(
            status,
            &PlanFields {
                path: "original.path",
                stays: original.map(|o| &o.path),
                legs: "original.legs",
                leg_lines: original.and_then(|o| o.legs.as_ref()),
                lands: true,
            },
        )?);
        let changes = line
            .changes
            .as_ref()
            .filter(|c| !c.is_empty())
            .ok_or_else(|| {
                self.err(Some("changes"), format!("missing for a `{status}` request"))
            })?;
        for (k, c) in changes.iter().enumerate() {
            let outcome = FateKind::parse(&c.outcome).ok_or_else(|| {
                self.err(
                    Some(&format!("changes[{k}].outcome")),
                    format!("`{}` is not an outcome", c.outcome),
                )
            })?;
            record.changes.push(ChangeNote {
                zone: c.zone.clone(),
                announced: self.time(&format!("changes[{k}].announced"), &c.announced)?,
                airborne: c.airborne,
                outcome,
            });
        }
        if record.changes.last().map(|c| c.outcome) != Some(kind) {
            return Err(self.err(
                Some("status"),
                format!("`{status}` is not the outcome of the last change"),
            ));
        }
        let path = || self.plan(status, &final_plan(line));
        let committed = PlanFields {
            path: "committed",
            stays: line.committed.as_ref(),
            legs: "committed_legs",
            leg_lines: line.committed_legs.as_ref(),
            lands: false,
        };
        record.fate = Some(match kind {
            FateKind::Replanned => Fate::Replanned(path()?),
            FateKind::Diverted => Fate::Diverted(path()?),
            FateKind::Cancelled => Fate::Cancelled,
            FateKind::Contingency => Fate::Contingency(self.plan(status, &committed)?),
        });
        Ok(())
    }
}

/// Where a line's final plan is: `path` and `legs`.
fn final_plan(line: &PlanLine) -> PlanFields<'_> {
    PlanFields {
        path: "path",
        stays: line.path.as_ref(),
        legs: "legs",
        leg_lines: line.legs.as_ref(),
        lands: true,
    }
}

/// Reads a plans JSON Lines file.
pub fn read_plans_file(path: &Path, airspace: &Airspace) -> Result<Vec<PlanRecord>, InputError> {
    read_plans(
        &crate::read_to_string(path)?,
        &path.display().to_string(),
        airspace,
    )
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
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.81, 1.3]]}, "properties": {"from": "A", "to": "B", "length_m": 1000}}]}"#,
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
            changes: vec![ChangeNote {
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
        let no_original = out.replace(r#""original":"#, r#""first":"#);
        let e = read_plans(&no_original, "p.jsonl", &air())
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

    #[test]
    fn bad_lines_are_named() {
        let e = read_plans("{}\n", "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("p.jsonl: line 1: not a plan record"), "{e}");
        let line = r#"{"request":"r1","status":"planned","reason":null,"origin":"A","destination":"B","requested_departure":"1970-01-01T08:00:00.000+08:00","takeoff":null,"landing":null,"airborne_s":null,"free_flow_s":null,"air_delay_s":null,"ground_delay_s":null,"distance_m":null,"path":[{"node":"Q","arrive":"1970-01-01T08:00:00.000+08:00","depart":"1970-01-01T08:00:00.000+08:00"}]}"#;
        let e = read_plans(&format!("\n{line}\n"), "p.jsonl", &air())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "p.jsonl: line 2: field `path[0].node`: unknown node id `Q`"
        );
    }
}
