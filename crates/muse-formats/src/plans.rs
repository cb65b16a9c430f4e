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

use std::fmt::Write as _;
use std::path::Path;

use muse_model::{Airspace, Instant, Millis, Plan, RejectReason, Stay, UtcOffset};
use serde::{Deserialize, Serialize};

use crate::error::{InputError, Location};

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
    /// The plan, or why there is none.
    pub result: Result<Plan, RejectReason>,
    /// Free-flow airborne time, where the destination is reachable.
    pub free_flow: Option<Millis>,
    /// Search labels expanded.
    pub expanded: u64,
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
    /// The stays, when planned.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub path: Option<Vec<StayLine>>,
}

/// Total length of a plan's path, metres (rounded to the millimetre).
pub fn plan_distance_m(airspace: &Airspace, plan: &Plan) -> f64 {
    let total: f64 = plan
        .path
        .windows(2)
        .filter_map(|w| airspace.edge_between(w[0].node, w[1].node))
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
///     free_flow: Some(Millis(1_500_000)), expanded: 0,
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

/// The SPEC §7 object for `record`, times in `offset`.
pub fn plan_line(airspace: &Airspace, offset: UtcOffset, record: &PlanRecord) -> PlanLine {
    let secs = |m: Millis| m.as_secs_f64();
    let (status, reason, plan) = match &record.result {
        Ok(plan) => ("planned", None, Some(plan)),
        Err(r) => ("rejected", Some(r.as_str().to_owned()), None),
    };
    PlanLine {
        request: record.request.clone(),
        status: status.to_owned(),
        reason,
        origin: record.origin.clone(),
        destination: record.destination.clone(),
        requested_departure: record.requested_departure.to_rfc3339(offset),
        takeoff: plan.map(|p| p.takeoff().to_rfc3339(offset)),
        landing: plan.map(|p| p.landing().to_rfc3339(offset)),
        airborne_s: plan.map(|p| secs(p.airborne())),
        free_flow_s: record.free_flow.map(secs),
        air_delay_s: plan.and_then(|p| Some(secs(p.airborne() - record.free_flow?))),
        ground_delay_s: plan.map(|p| secs(p.takeoff() - record.requested_departure)),
        distance_m: plan.map(|p| plan_distance_m(airspace, p)),
        expanded: record.expanded,
        path: plan.map(|p| {
            p.path
                .iter()
                .map(|s| StayLine {
                    node: airspace.node(s.node).id.clone(),
                    arrive: s.arrive.to_rfc3339(offset),
                    depart: s.depart.to_rfc3339(offset),
                })
                .collect()
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
        let line_no = i + 1;
        if raw.trim().is_empty() {
            continue;
        }
        let err = |field: Option<&str>, msg: String| {
            InputError::new(file, Location::Line(line_no), field, msg)
        };
        let line: PlanLine =
            serde_json::from_str(raw).map_err(|e| err(None, format!("not a plan record: {e}")))?;
        let time = |field: &str, text: &str| {
            Instant::parse_rfc3339(text).map_err(|e| err(Some(field), e.to_string()))
        };
        let requested_departure = time("requested_departure", &line.requested_departure)?;
        let free_flow = line
            .free_flow_s
            .map(|s| Millis::from_secs_f64(s).map_err(|e| err(Some("free_flow_s"), e.to_string())))
            .transpose()?;
        let result = match line.status.as_str() {
            "planned" => {
                let stays = line
                    .path
                    .as_ref()
                    .ok_or_else(|| err(Some("path"), "missing for a planned request".into()))?;
                if stays.is_empty() {
                    return Err(err(Some("path"), "empty".into()));
                }
                let mut path = Vec::with_capacity(stays.len());
                for (k, s) in stays.iter().enumerate() {
                    let node = airspace.node_id(&s.node).ok_or_else(|| {
                        err(
                            Some(&format!("path[{k}].node")),
                            format!("unknown node id `{}`", s.node),
                        )
                    })?;
                    let arrive = time(&format!("path[{k}].arrive"), &s.arrive)?;
                    let depart = time(&format!("path[{k}].depart"), &s.depart)?;
                    path.push(Stay {
                        node,
                        arrive,
                        depart,
                    });
                }
                Ok(Plan { path })
            }
            "rejected" => {
                let reason = line.reason.as_deref().unwrap_or("");
                Err(RejectReason::parse(reason).ok_or_else(|| {
                    err(
                        Some("reason"),
                        format!("`{reason}` is not a rejection reason"),
                    )
                })?)
            }
            other => {
                return Err(err(
                    Some("status"),
                    format!("`{other}` is not `planned` or `rejected`"),
                ));
            }
        };
        out.push(PlanRecord {
            request: line.request,
            origin: line.origin,
            destination: line.destination,
            requested_departure,
            result,
            free_flow,
            expanded: line.expanded,
        });
    }
    Ok(out)
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

    fn air() -> Airspace {
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
