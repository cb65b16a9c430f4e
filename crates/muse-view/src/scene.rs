//! The scene: everything the page draws, as compact JSON. Times are integer milliseconds
//! from [`Scene::t0`] (the start of the local hour the day begins in), coordinates WGS84
//! degrees rounded to 1e-5 (about a metre).
//!
//! A layered airspace (docs/reference.md#layered-airspace) is drawn from above: its flat nodes and
//! corridors, each flight's stays at flat nodes (a climb or descent shown as a hover at the node),
//! and a zone closing a node or corridor at any layer as closing it. [`Scene::layers`] then gives
//! the layers' altitudes and which way each corridor is flown at each, each flight's
//! [`SceneFlight::z`] its layer over time, and each zone's [`SceneZone::layers`] the layers it
//! closes: the page colours drones by layer, shows one layer alone, and draws the selected flight's
//! altitude over time.

use geo::Simplify;
use geo_types::{LineString, Polygon};
use muse_airspace::closures::{closed_elements, zone_windows};
use muse_formats::plans::{OperatorCancellation, PlanRecord};
use muse_model::plan::{CANCELLED_BY_OPERATOR, Fate, ZONE_ANNOUNCED};
use muse_model::{Airspace, EdgeKind, Instant, NodeId, NodeKind, Plan, Stay, UtcOffset, Zone};
use serde::Serialize;

use crate::ViewError;

/// Tolerance of the land outline's simplification, degrees (about 20 m: far below what the
/// page can show at the island's scale, and it keeps the outline to a few hundred kB).
const LAND_TOLERANCE_DEG: f64 = 0.000_2;

/// One hour, ms.
const HOUR_MS: i64 = 3_600_000;

/// What a scene is made from.
#[derive(Clone, Debug)]
pub struct SceneInput<'a> {
    /// The airspace.
    pub airspace: &'a Airspace,
    /// The local UTC offset clocks are shown in.
    pub offset: UtcOffset,
    /// The stretch of time to show at least (the scene widens it to every flight, then to
    /// whole local hours).
    pub range: (Instant, Instant),
    /// A one-line title.
    pub title: String,
    /// Data attribution shown under the map (empty: none).
    pub attribution: String,
    /// Land polygons (WGS84 degrees), drawn filled under everything; simplified.
    pub land: &'a [Polygon<f64>],
    /// No-fly zones, known from the start or announced during the day.
    pub zones: &'a [Zone],
    /// The flights: each record's final plan is drawn (a contingency's committed part);
    /// rejected requests and those cancelled by a zone are listed with their reason.
    pub flights: &'a [PlanRecord],
    /// The flights their operators cancelled (a service listing): listed with that reason.
    pub cancelled: &'a [OperatorCancellation],
    /// The day's summary (`summary.json`), shown beside the map.
    pub summary: Option<serde_json::Value>,
}

impl<'a> SceneInput<'a> {
    /// A scene of `airspace` alone over `range`: no land, zones, flights or summary.
    pub fn new(airspace: &'a Airspace, offset: UtcOffset, range: (Instant, Instant)) -> Self {
        SceneInput {
            airspace,
            offset,
            range,
            title: String::new(),
            attribution: String::new(),
            land: &[],
            zones: &[],
            flights: &[],
            cancelled: &[],
            summary: None,
        }
    }
}

/// Everything the page draws (see the module docs for units).
#[derive(Clone, Debug, Serialize)]
pub struct Scene {
    /// A one-line title.
    pub title: String,
    /// Data attribution.
    pub attribution: String,
    /// The local UTC offset, seconds east.
    pub offset_s: i32,
    /// Epoch milliseconds every other time counts from.
    pub t0: i64,
    /// The length of the day shown, ms.
    pub span: i64,
    /// Nodes, in airspace order (their index is their number everywhere else).
    pub nodes: Vec<SceneNode>,
    /// Corridors, in airspace order, as `[from, to]` node indices.
    pub edges: Vec<[u32; 2]>,
    /// The layers of a layered airspace (docs/reference.md#layered-airspace); absent when flat.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layers: Option<SceneLayers>,
    /// Land polygons: rings (outer first) of `[lon, lat]`.
    pub land: Vec<Vec<Vec<[f64; 2]>>>,
    /// No-fly zones.
    pub zones: Vec<SceneZone>,
    /// Flights with something to draw, in the records' order.
    pub flights: Vec<SceneFlight>,
    /// The requests with nothing to draw (rejected, or cancelled before take-off), in the
    /// records' order, then the operators' cancellations: found by the page's search, which
    /// shows why.
    pub unflown: Vec<SceneUnflown>,
    /// Why each of `unflown` did not fly (they point into this list).
    pub reasons: Vec<SceneReason>,
    /// The day's summary, if any.
    pub summary: Option<serde_json::Value>,
    /// Whether the page is fed live by `muse serve` (flights come from its API).
    pub live: bool,
}

/// A node of the airspace.
#[derive(Clone, Debug, Serialize)]
pub struct SceneNode {
    /// Its id, e.g. `S001`.
    pub id: String,
    /// Longitude, degrees.
    pub lon: f64,
    /// Latitude, degrees.
    pub lat: f64,
    /// Whether drones take off and land there.
    pub station: bool,
}

/// The layers of a layered airspace.
#[derive(Clone, Debug, Serialize)]
pub struct SceneLayers {
    /// Each layer's altitude, metres, from layer 1 up.
    pub altitudes_m: Vec<f64>,
    /// The heading rule: `none` or `sectors`.
    pub heading_rule: &'static str,
    /// Per layer (from 1 up), per corridor of [`Scene::edges`], which way it is flown there:
    /// 0 not at all, 1 from its first node to its second only, 2 the other way only, 3 both.
    pub ways: Vec<Vec<u8>>,
}

/// A no-fly zone.
#[derive(Clone, Debug, Serialize)]
pub struct SceneZone {
    /// Its id.
    pub id: String,
    /// Its name.
    pub name: String,
    /// Its area as polygons of rings of `[lon, lat]` (empty for a zone given as node and
    /// corridor ids).
    pub area: Vec<Vec<Vec<[f64; 2]>>>,
    /// When it is active, `[start, end)` in ms from `t0`, within the day shown.
    pub windows: Vec<[i64; 2]>,
    /// When it was announced (ms from `t0`); absent for a zone known from the start.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub announced: Option<i64>,
    /// The nodes it closes (indices).
    pub nodes: Vec<u32>,
    /// The corridors it closes (indices).
    pub edges: Vec<u32>,
    /// In a layered airspace, the layers it closes nodes or corridors at (from 1 up; at each,
    /// the nodes of `nodes` and those corridors of `edges` flown there); empty when flat.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<u32>,
}

/// One flight.
#[derive(Clone, Debug, Serialize)]
pub struct SceneFlight {
    /// The request id.
    pub id: String,
    /// Origin node index.
    pub o: u32,
    /// Destination node index.
    pub d: u32,
    /// Requested departure, ms from `t0`.
    pub dep: i64,
    /// Free-flow time, ms (absent if the destination is unreachable).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ff: Option<i64>,
    /// Status as in `plans.jsonl`: `planned`, `replanned`, `diverted` or `contingency`.
    pub status: &'static str,
    /// The stays, flat: node index, arrival and departure (ms from `t0`) for each. A station
    /// met twice in a row is a battery swap: the drone is on the ground between the two.
    pub s: Vec<i64>,
    /// In a layered airspace, its layer over time, flat: `[t, layer, t, layer, ...]` (ms from
    /// `t0`, 1 up), from take-off to landing; between two points the layer changes evenly (a
    /// climb or descent) or stays; empty when flat.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub z: Vec<i64>,
}

/// A request with nothing to draw, compact: `[id, origin, destination, requested departure,
/// reason]` (node indices, ms from `t0`, an index into [`Scene::reasons`]).
#[derive(Clone, Debug, Serialize)]
pub struct SceneUnflown(
    /// The request id.
    pub String,
    /// Origin node index (`null`: an unserved request whose sender has no pad in reach).
    pub Option<u32>,
    /// Destination node index (`null`: an unserved request whose receiver has none).
    pub Option<u32>,
    /// Requested departure, ms from `t0`.
    pub i64,
    /// Its reason: an index into [`Scene::reasons`].
    pub usize,
);

/// Why a request did not fly.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct SceneReason {
    /// `rejected` or `cancelled`.
    pub status: &'static str,
    /// As in `plans.jsonl`: `out_of_range`, `unreachable`, `no_feasible_plan`,
    /// `departure_in_past`, `zone_announced` or `cancelled_by_operator`.
    pub reason: &'static str,
    /// The zone whose announcement cancelled it (`zone_announced`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zone: Option<String>,
    /// When it was cancelled (ms from `t0`): the zone's announcement, or the operator's
    /// cancellation when the file gives it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<i64>,
}

/// Builds the scene of `input`.
///
/// Errors: a zone whose schedule or area cannot be resolved over the day, or a flight
/// whose origin or destination is not a node of the airspace.
pub fn scene(input: &SceneInput<'_>) -> Result<Scene, ViewError> {
    let a = input.airspace;
    let drawn: Vec<(&PlanRecord, &Plan, &'static str)> = input
        .flights
        .iter()
        .filter_map(|r| {
            let plan = match &r.fate {
                Some(Fate::Contingency(c)) => Some(c),
                _ => r.final_plan(),
            }?;
            (!plan.path.is_empty()).then_some((r, plan, r.status()))
        })
        .collect();
    let first = drawn
        .iter()
        .map(|(r, p, _)| p.takeoff().min(r.requested_departure))
        .fold(input.range.0, Instant::min);
    let last = drawn
        .iter()
        .map(|(_, p, _)| p.landing())
        .fold(input.range.1, Instant::max);
    let off = i64::from(input.offset.0) * 1_000;
    let t0 = (first.0 + off).div_euclid(HOUR_MS) * HOUR_MS - off;
    let end = (last.0 + off + HOUR_MS - 1).div_euclid(HOUR_MS) * HOUR_MS - off;

    // A layered airspace (docs/reference.md#layered-airspace) is drawn from above: its flat nodes
    // and corridors.
    let nodes = a
        .flat()
        .nodes()
        .iter()
        .map(|n| SceneNode {
            id: n.id.clone(),
            lon: round5(n.pos.lon),
            lat: round5(n.pos.lat),
            station: n.kind == NodeKind::Station,
        })
        .collect();
    let edges = a
        .flat()
        .edges()
        .iter()
        .map(|e| [e.from.0, e.to.0])
        .collect();
    let layers = a.layers().map(|l| SceneLayers {
        altitudes_m: (1..=l.count).map(|k| l.altitude(k).m()).collect(),
        heading_rule: l.heading_rule.name(),
        ways: ways(a, l.count),
    });
    let land = input
        .land
        .iter()
        .map(|p| polygon_rings(&p.simplify(LAND_TOLERANCE_DEG)))
        .filter(|rings: &Vec<Vec<[f64; 2]>>| rings.first().is_some_and(|r| r.len() >= 4))
        .collect();

    let zones = input
        .zones
        .iter()
        .map(|z| scene_zone(a, z, t0, end))
        .collect::<Result<_, _>>()?;
    let flights = drawn
        .into_iter()
        .map(|(r, plan, status)| scene_flight(a, r, plan, status, t0))
        .collect::<Result<_, _>>()?;
    let (unflown, reasons) = unflown(input, t0)?;

    Ok(Scene {
        title: input.title.clone(),
        attribution: input.attribution.clone(),
        offset_s: input.offset.0,
        t0,
        span: end - t0,
        nodes,
        edges,
        layers,
        land,
        zones,
        flights,
        unflown,
        reasons,
        summary: input.summary.clone(),
        live: false,
    })
}

/// Zone `z` over `[t0, end)`.
fn scene_zone(a: &Airspace, z: &Zone, t0: i64, end: i64) -> Result<SceneZone, ViewError> {
    let err = |e: &dyn std::fmt::Display| ViewError::Zone {
        zone: z.id.clone(),
        message: e.to_string(),
    };
    let windows = zone_windows(z, Instant(t0), Instant(end)).map_err(|e| err(&e))?;
    let (closed_nodes, closed_edges) = closed_elements(a, z).map_err(|e| err(&e))?;
    // Drawn from above: a node or corridor closed at any layer; vertical links are not drawn.
    let mut nodes: Vec<u32> = closed_nodes.iter().map(|&n| a.flat_node(n).0).collect();
    let mut edges: Vec<u32> = closed_edges
        .iter()
        .filter_map(|&e| a.flat_edge(e))
        .map(|e| e.0)
        .collect();
    let mut layers: Vec<u32> = Vec::new();
    if a.layers().is_some() {
        layers.extend(closed_nodes.iter().map(|&n| a.node_layer(n)));
        layers.extend(closed_edges.iter().filter_map(|&e| match a.edge_kind(e) {
            EdgeKind::Corridor { layer, .. } => Some(layer),
            EdgeKind::Vertical { .. } => None,
        }));
    }
    for list in [&mut nodes, &mut edges, &mut layers] {
        list.sort_unstable();
        list.dedup();
    }
    Ok(SceneZone {
        id: z.id.clone(),
        name: z.name.clone(),
        area: z.polygons().iter().map(polygon_rings).collect(),
        windows: windows
            .iter()
            .map(|w| [w.start.0 - t0, w.end.0 - t0])
            .collect(),
        announced: z.announced.map(|t| t.0 - t0),
        nodes,
        edges,
        layers,
    })
}

/// The flight of record `r`, drawn along `plan`.
fn scene_flight(
    a: &Airspace,
    r: &PlanRecord,
    plan: &Plan,
    status: &'static str,
    t0: i64,
) -> Result<SceneFlight, ViewError> {
    let node = |id: &str| {
        a.node_id(id).map(|n| n.0).ok_or_else(|| ViewError::Flight {
            flight: r.request.clone(),
            message: format!("station `{id}` is not in the airspace"),
        })
    };
    Ok(SceneFlight {
        id: r.request.clone(),
        o: node(&r.origin)?,
        d: node(&r.destination)?,
        dep: r.requested_departure.0 - t0,
        ff: r.free_flow.map(|m| m.0),
        status,
        s: flat_stays(a, plan)
            .iter()
            .flat_map(|s| [i64::from(s.node.0), s.arrive.0 - t0, s.depart.0 - t0])
            .collect(),
        z: layer_profile(a, plan, t0),
    })
}

/// Per layer of `a` (`count` of them), per flat corridor, which way it is flown there (see
/// [`SceneLayers::ways`]).
fn ways(a: &Airspace, count: u32) -> Vec<Vec<u8>> {
    let flat = a.flat();
    let mut ways = vec![vec![0_u8; flat.edge_count()]; count as usize];
    for (i, e) in a.edges().iter().enumerate() {
        let id = muse_model::EdgeId(u32::try_from(i).expect("an edge index"));
        let (EdgeKind::Corridor { layer, one_way }, Some(f)) = (a.edge_kind(id), a.flat_edge(id))
        else {
            continue;
        };
        let way = if !one_way {
            3
        } else if a.flat_node(e.from) == flat.edge(f).from {
            1
        } else {
            2
        };
        ways[layer as usize - 1][f.index()] |= way;
    }
    ways
}

/// The layer of `plan` over time in a layered airspace, as [`SceneFlight::z`] gives it: each
/// stay's arrival and departure at its layer, less the points that say nothing (a repeat, or
/// the middle of three at one layer). Empty when `a` is flat.
fn layer_profile(a: &Airspace, plan: &Plan, t0: i64) -> Vec<i64> {
    if a.layers().is_none() {
        return Vec::new();
    }
    let mut points: Vec<[i64; 2]> = Vec::with_capacity(2 * plan.path.len());
    for s in &plan.path {
        let layer = i64::from(a.node_layer(s.node));
        for t in [s.arrive.0 - t0, s.depart.0 - t0] {
            let p = [t, layer];
            match points.as_slice() {
                [.., last] if *last == p => {}
                [.., before, last] if before[1] == layer && last[1] == layer => {
                    *points.last_mut().expect("two points") = p;
                }
                _ => points.push(p),
            }
        }
    }
    points.into_iter().flatten().collect()
}

/// The stays of `plan` seen from above: at flat nodes, a climb or descent between layers
/// (consecutive stays at copies of one node) merged into one stay from the first arrival to
/// the last departure. A battery swap, the same node twice in a row, stays two stays. A flat
/// airspace's plan is returned as it is.
fn flat_stays(a: &Airspace, plan: &Plan) -> Vec<Stay> {
    let mut out: Vec<(Stay, NodeId)> = Vec::with_capacity(plan.path.len());
    for s in &plan.path {
        let flat = a.flat_node(s.node);
        match out.last_mut() {
            Some((last, layered)) if last.node == flat && *layered != s.node => {
                last.depart = s.depart;
                *layered = s.node;
            }
            _ => out.push((Stay { node: flat, ..*s }, s.node)),
        }
    }
    out.into_iter().map(|(s, _)| s).collect()
}

/// The requests of `input` with nothing to draw, and their reasons (each listed once).
fn unflown(
    input: &SceneInput<'_>,
    t0: i64,
) -> Result<(Vec<SceneUnflown>, Vec<SceneReason>), ViewError> {
    let mut reasons: Vec<SceneReason> = Vec::new();
    let mut out = Vec::new();
    let mut push = |id: &str, od: (&str, &str), dep: Instant, why: SceneReason| {
        // An empty id: an unserved request's customer with no pad in reach.
        let node = |n: &str| {
            if n.is_empty() {
                return Ok(None);
            }
            input
                .airspace
                .node_id(n)
                .map(|n| Some(n.0))
                .ok_or_else(|| ViewError::Flight {
                    flight: id.to_owned(),
                    message: format!("station `{n}` is not in the airspace"),
                })
        };
        let k = reasons.iter().position(|r| *r == why).unwrap_or_else(|| {
            reasons.push(why);
            reasons.len() - 1
        });
        out.push(SceneUnflown(
            id.to_owned(),
            node(od.0)?,
            node(od.1)?,
            dep.0 - t0,
            k,
        ));
        Ok::<_, ViewError>(())
    };
    for r in input.flights {
        let why = match (&r.fate, &r.result) {
            (None, Err(reason)) => SceneReason {
                status: "rejected",
                reason: reason.as_str(),
                zone: None,
                at: None,
            },
            (Some(Fate::Cancelled), _) => {
                let last = r.changes.last();
                SceneReason {
                    status: "cancelled",
                    reason: ZONE_ANNOUNCED,
                    zone: last.map(|c| c.zone.clone()),
                    at: last.map(|c| c.announced.0 - t0),
                }
            }
            _ => continue,
        };
        push(
            &r.request,
            (&r.origin, &r.destination),
            r.requested_departure,
            why,
        )?;
    }
    for c in input.cancelled {
        let why = SceneReason {
            status: "cancelled",
            reason: CANCELLED_BY_OPERATOR,
            zone: None,
            at: c.cancelled_at.map(|t| t.0 - t0),
        };
        push(
            &c.request,
            (&c.origin, &c.destination),
            c.requested_departure,
            why,
        )?;
    }
    Ok((out, reasons))
}

/// `v` rounded to 1e-5.
fn round5(v: f64) -> f64 {
    (v * 1e5).round() / 1e5
}

/// The rings of `p`, outer first, rounded.
fn polygon_rings(p: &Polygon<f64>) -> Vec<Vec<[f64; 2]>> {
    let ring = |l: &LineString<f64>| l.0.iter().map(|c| [round5(c.x), round5(c.y)]).collect();
    std::iter::once(p.exterior())
        .chain(p.interiors())
        .map(ring)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::Millis;
    use muse_model::testing::plan;

    fn record(id: &str, stays: &[(u32, i64, i64)]) -> PlanRecord {
        PlanRecord::first(
            id.into(),
            "A".into(),
            "B".into(),
            Instant(stays[0].1),
            Ok(plan(stays)),
            Some(Millis(60_000)),
            1,
        )
    }

    #[test]
    fn times_count_from_the_local_hour_and_stays_are_flat() {
        let a = Airspace::line(&[1_000.0]);
        // 08:30 local in Singapore (+08:00) is 00:30 UTC.
        let half_past = 30 * 60_000;
        let flights = [record(
            "r1",
            &[
                (0, half_past, half_past),
                (1, half_past + 120_000, half_past + 120_000),
            ],
        )];
        let mut input = SceneInput::new(
            &a,
            UtcOffset::SINGAPORE,
            (Instant(half_past), Instant(half_past)),
        );
        input.flights = &flights;
        let s = scene(&input).unwrap();
        assert_eq!(s.t0, 0, "floored to the local hour");
        assert_eq!(s.span, HOUR_MS, "ceiled to the next hour");
        assert_eq!(
            s.flights[0].s,
            vec![
                0,
                half_past,
                half_past,
                1,
                half_past + 120_000,
                half_past + 120_000
            ]
        );
        assert_eq!(
            (s.flights[0].o, s.flights[0].d, s.flights[0].ff),
            (0, 1, Some(60_000))
        );
        assert_eq!(s.nodes.len(), 2);
        assert_eq!(s.edges, vec![[0, 1]]);
    }

    #[test]
    fn rejected_requests_are_not_drawn_and_unknown_stations_are_errors() {
        let a = Airspace::line(&[1_000.0]);
        let mut rejected = record("r2", &[(0, 0, 0)]);
        rejected.result = Err(muse_model::RejectReason::NoFeasiblePlan);
        let flights = [rejected];
        let mut input = SceneInput::new(&a, UtcOffset(0), (Instant(0), Instant(1)));
        input.flights = &flights;
        let s = scene(&input).unwrap();
        assert!(s.flights.is_empty());
        assert_eq!(s.unflown.len(), 1, "listed with its reason");
        assert_eq!(s.reasons[s.unflown[0].4].reason, "no_feasible_plan");
        let mut bad = record("r3", &[(0, 0, 0), (1, 5, 5)]);
        bad.origin = "nowhere".into();
        let flights = [bad];
        input.flights = &flights;
        let e = scene(&input).unwrap_err().to_string();
        assert!(e.contains("r3") && e.contains("nowhere"), "{e}");
    }

    #[test]
    fn unflown_requests_carry_their_reason_once_per_kind() {
        let a = Airspace::line(&[1_000.0]);
        let mut r1 = record("r1", &[(0, 0, 0)]);
        r1.result = Err(muse_model::RejectReason::OutOfRange);
        let mut r2 = r1.clone();
        r2.request = "r2".into();
        let mut z = record("z1", &[(0, 60_000, 60_000), (1, 180_000, 180_000)]);
        z.changes.push(muse_model::plan::Change {
            zone: "EVT".into(),
            announced: Instant(30_000),
            airborne: false,
            outcome: muse_model::plan::FateKind::Cancelled,
        });
        z.fate = Some(Fate::Cancelled);
        let flown = record("f1", &[(0, 0, 0), (1, 120_000, 120_000)]);
        let flights = [r1, flown, z, r2];
        let cancelled = [OperatorCancellation {
            request: "op1".into(),
            origin: "A".into(),
            destination: "B".into(),
            requested_departure: Instant(90_000),
            free_flow: None,
            original: None,
            changes: Vec::new(),
            cancelled_at: Some(Instant(45_000)),
        }];
        let mut input = SceneInput::new(&a, UtcOffset(0), (Instant(0), Instant(1)));
        input.flights = &flights;
        input.cancelled = &cancelled;
        let s = scene(&input).unwrap();
        assert_eq!(s.flights.len(), 1);
        let ids: Vec<(&str, usize)> = s.unflown.iter().map(|u| (u.0.as_str(), u.4)).collect();
        assert_eq!(ids, [("r1", 0), ("z1", 1), ("r2", 0), ("op1", 2)]);
        let reasons: Vec<(&str, &str, Option<&str>, Option<i64>)> = s
            .reasons
            .iter()
            .map(|r| (r.status, r.reason, r.zone.as_deref(), r.at))
            .collect();
        assert_eq!(
            reasons,
            [
                ("rejected", "out_of_range", None, None),
                ("cancelled", "zone_announced", Some("EVT"), Some(30_000)),
                ("cancelled", "cancelled_by_operator", None, Some(45_000)),
            ]
        );
        let json = serde_json::to_string(&s.unflown[3]).unwrap();
        assert_eq!(json, r#"["op1",0,1,90000,2]"#, "compact");
    }

    #[test]
    fn a_layered_day_is_drawn_from_above() {
        let layers = muse_model::Layers {
            count: 3,
            ..muse_model::Layers::default()
        };
        let a = Airspace::line(&[1_000.0, 1_000.0])
            .layered(&layers)
            .unwrap();
        // A (0) up to A@2 (3) and A@3 (6), along to B@3 (7) and C@3 (8), down to C@2 (5) and
        // C (2); then a swap at C (the same node twice) and back to B at layer 1.
        let flights = [record(
            "r1",
            &[
                (0, 0, 0),
                (3, 1_829, 1_829),
                (6, 3_658, 3_658),
                (7, 123_658, 123_658),
                (8, 243_658, 243_658),
                (5, 245_487, 245_487),
                (2, 247_316, 247_316),
                (2, 547_316, 547_316),
                (1, 667_316, 667_316),
            ],
        )];
        let mut input = SceneInput::new(&a, UtcOffset(0), (Instant(0), Instant(0)));
        input.flights = &flights;
        let s = scene(&input).unwrap();
        let ids: Vec<&str> = s.nodes.iter().map(|n| n.id.as_str()).collect();
        assert_eq!(ids, ["A", "B", "C"]);
        assert_eq!(s.edges, [[0, 1], [1, 2]]);
        assert_eq!(
            s.flights[0].s,
            [
                0, 0, 3_658, // A, climbing to layer 3
                1, 123_658, 123_658, // B
                2, 243_658, 247_316, // C, descending
                2, 547_316, 547_316, // C again after the swap
                1, 667_316, 667_316
            ]
        );
        assert_eq!(
            s.flights[0].z,
            [
                0, 1, 1_829, 2, 3_658, 3, 243_658, 3, 245_487, 2, 247_316, 1, 667_316, 1
            ],
            "up at A, level to C, down at C, level through the swap and back to B"
        );
        let l = s.layers.as_ref().expect("layered");
        assert_eq!(l.altitudes_m, [60.0, 69.144, 78.288]);
        assert_eq!(
            (l.heading_rule, l.ways.as_slice()),
            ("none", &vec![vec![3, 3]; 3][..])
        );
    }

    #[test]
    fn a_layered_scene_tells_each_corridors_ways_and_each_zones_layers() {
        // A — B — C run east off the equator: quadrantal, eastward (an initial bearing just
        // under 90°) is layer 1's (0°–90°), westward (just over 270°) layer 4's (270°–360°).
        let layers = muse_model::Layers {
            count: 4,
            heading_rule: muse_model::HeadingRule::Sectors,
            ..muse_model::Layers::default()
        };
        let a = Airspace::line(&[1_000.0, 1_000.0])
            .layered(&layers)
            .unwrap();
        // A zone on B from the ground to 70 m: layers 1 (60 m) and 2 (69.144 m).
        let zone = Zone {
            id: "LOW".into(),
            name: "low".into(),
            restriction: "PROHIBITED".into(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: Vec::new(),
            periods: Vec::new(),
            announced: None,
            withdrawn: None,
            vertical: muse_model::VerticalLimits::agl(
                None,
                Some(muse_model::Metres::from_mm(70_000)),
            ),
        };
        let zones = [zone];
        let mut input = SceneInput::new(&a, UtcOffset(0), (Instant(0), Instant(1)));
        input.zones = &zones;
        let s = scene(&input).unwrap();
        let ways = &s.layers.as_ref().unwrap().ways;
        assert_eq!(ways, &[vec![1, 1], vec![0, 0], vec![0, 0], vec![2, 2]]);
        assert_eq!(
            (s.zones[0].nodes.as_slice(), s.zones[0].layers.as_slice()),
            (&[1][..], &[1, 2][..])
        );
        let flat_scene = scene(&SceneInput {
            airspace: a.flat(),
            ..input
        })
        .unwrap();
        assert!(flat_scene.layers.is_none() && flat_scene.zones[0].layers.is_empty());
        let json = serde_json::to_string(&flat_scene).unwrap();
        assert!(
            !json.contains("\"layers\"") && !json.contains("\"z\""),
            "{json}"
        );
    }
}
