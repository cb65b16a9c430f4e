//! An independent checker of planned flights against docs/reference.md#flight-model-and-separation
//! (flight model and separation), docs/reference.md#no-fly-zones (no-fly zones),
//! #zones-announced-during-the-day (zones announced during the day) and #multi-leg-trips (multi-leg
//! trips).
//!
//! The verifier is deliberately simple: every rule is written out as the reference states it, on
//! plain integer milliseconds, and it shares no interval or search code with the planner. It
//! reads zone closures as per-element windows ([`Closures`]) and nothing else from
//! `muse-airspace`: on a layered airspace (docs/reference.md#layered-airspace), windows per copy of
//! a node or corridor and per vertical link, as `muse-airspace` resolves them on that airspace (a
//! zone closing only the layers of its vertical band), so what a zone closes, at which layers, is
//! decided there once for the planner and the verifier.
//!
//! [`verify`] lists **every** violation, all pairs of flights included. Pairwise rules are
//! checked per element (node or edge): occupations are sorted by start and each one is
//! compared only with the following ones that could still conflict with it, so the work is
//! proportional to the number of occupations plus the number of pairs close in time, not to
//! the square of the number of flights.
//!
//! The rules, with `w(e) = params.speed.traversal_time(length_m)`:
//!
//! - [`Rule::Path`]: a plan is non-empty, starts at the request's origin and ends at its
//!   destination, joins consecutive nodes by an edge, has `arrive <= depart` at every stay,
//!   `arrive_{i+1} = depart_i + w(e)` and `depart = arrive` at the last stay (landing).
//! - [`Rule::Node`]: stays `[a1, d1]`, `[a2, d2]` of different flights at the same node satisfy
//!   `a2 >= d1 + tau` or `a1 >= d2 + tau`.
//! - [`Rule::Edge`]: traversals `[s, s + w(e)]` of the same edge by different flights satisfy,
//!   under [`EdgeRule::Exclusive`](muse_model::EdgeRule::Exclusive) (and in opposite directions
//!   under [`EdgeRule::Headway`](muse_model::EdgeRule::Headway)),
//!   `s2 >= f1` or `s1 >= f2`; in the same direction under `Headway(h)`, `|s2 - s1| >= h`.
//! - [`Rule::Battery`]: `landing - takeoff <= T_max`, for each leg.
//! - [`Rule::GroundDelay`]: `departure <= takeoff <= departure + G_max` (the first take-off).
//! - [`Rule::Swap`]: a plan of several legs (docs/reference.md#multi-leg-trips) needs battery swaps
//!   ([`FlightParams::battery_swap`]), has at most `K` legs, and its legs chain: leg `i + 1`
//!   takes off from the station where leg `i` landed, at least `S` after that landing.
//! - [`Rule::Zone`]: a stay `[a, d]` at a closed node, or a traversal `[s, f]` of a closed
//!   edge, shares no instant with a closure window `[start, end)`: `d < start` or `a >= end`.
//!   Origin and destination are no exception; on a layered airspace the rule is per copy
//!   (node or corridor at a layer, vertical link). With zones announced during the day
//!   ([`verify_known`]), a zone announced at `n` (and withdrawn at `m`, if it was) binds only
//!   the stays and traversals that begin in `[n, m)`: one that begins before `n` is exempt.
//!
//! A multi-leg plan lists the stays of all its legs; a leg ends where two consecutive stays
//! are at the same station (the landing, then the next take-off), or where the drone lands at
//! one station and takes off at another that no edge joins (a chain violation). Every leg
//! obeys [`Rule::Path`] on its own: it flies at least one edge, its consecutive stays are
//! traversals, and every leg but the last lands (`depart = arrive`) at a station other than
//! the one it took off from (so does the last, when bound for the destination). Between two
//! legs the drone is on the ground, outside the airspace: that time occupies no node and is
//! bound by no zone; the landing and take-off stays are ordinary stays.
//!
//! A replanned flight (docs/reference.md#zones-announced-during-the-day) is checked like any other;
//! a [diverted](Ending::Diverted) one must end at some station rather than its destination; a
//! flight left in [contingency](Ending::Committed) is its committed part, ending with its arrival
//! at the node where it is stranded. It cannot comply with the zones (that is what a contingency
//! is), so the zone rule does not apply to it; every other rule does (others must keep their
//! separation from it), except landing at a station.
//!
//! ```
//! use muse_airspace::closures::Closures;
//! use muse_model::{Airspace, Edge, FlightParams, Instant, LonLat, Node, NodeId, NodeKind, Plan, Request, Stay};
//! use muse_verify::{Flight, Rule, verify};
//!
//! let node = |id: &str, lon| Node {
//!     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3),
//! };
//! let airspace = Airspace::new(
//!     vec![node("A", 103.80), node("B", 103.81)],
//!     vec![Edge { id: "A-B".into(), from: NodeId(0), to: NodeId(1), length_m: 1_000.0 }],
//! ).unwrap();
//! let params = FlightParams::default(); // 30 km/h: 1 km takes 120 s
//! let request = |id: &str, t| Request { id: id.into(), origin: NodeId(0), destination: NodeId(1), departure: Instant(t), submitted: Instant(t) };
//! let plan = |t: i64| Plan { path: vec![
//!     Stay { node: NodeId(0), arrive: Instant(t), depart: Instant(t) },
//!     Stay { node: NodeId(1), arrive: Instant(t + 120_000), depart: Instant(t + 120_000) },
//! ] };
//! let (r1, r2) = (request("r1", 0), request("r2", 60_000));
//! let (p1, p2) = (plan(0), plan(60_000));
//! let flights = [
//!     Flight::new("r1", &r1, &p1),
//!     Flight::new("r2", &r2, &p2),
//! ];
//! let violations = verify(&airspace, &Closures::none(&airspace), &params, &flights);
//! // Both drones are on A-B between 60 s and 120 s.
//! assert_eq!(violations.len(), 1);
//! assert_eq!(violations[0].rule, Rule::Edge);
//! assert_eq!(violations[0].flights, ["r1", "r2"]);
//! ```
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

use std::fmt;

pub mod approach;
mod legs;
mod path;
pub mod recorded;
mod separation;
mod zones;

use path::check_flight;
use separation::{Occupation, collect, edge_rule, node_rule};
use zones::zone_rule;

use muse_airspace::announced::{Announced, KnownZones};
use muse_airspace::closures::Closures;
use muse_model::plan::Fate;
use muse_model::{
    Airspace, EdgeId, EdgeKind, FlightParams, Instant, Millis, NodeId, Plan, Request, UtcOffset,
};

/// One flight to check: its request and its plan.
#[derive(Clone, Copy, Debug)]
pub struct Flight<'a> {
    /// The name used in violations (usually the request id).
    pub id: &'a str,
    /// The request the plan answers (origin, destination, departure).
    pub request: &'a Request,
    /// The plan.
    pub plan: &'a Plan,
    /// How the plan must end.
    pub ending: Ending,
}

impl<'a> Flight<'a> {
    /// A flight that must land at its request's destination.
    pub fn new(id: &'a str, request: &'a Request, plan: &'a Plan) -> Self {
        Flight {
            id,
            request,
            plan,
            ending: Ending::Destination,
        }
    }

    /// The flight as it finally stands after zone announcements
    /// (docs/reference.md#zones-announced-during-the-day): its first plan if none changed it, else
    /// what the last one made of it: a replanned plan (to the destination), a diverted one (to some
    /// station), or a contingency's committed part. `None` if it does not fly: rejected (`first` is
    /// `None`) or cancelled.
    ///
    /// ```
    /// use muse_model::plan::Fate;
    /// use muse_model::{NodeId, Plan, Request, Instant};
    /// use muse_verify::{Ending, Flight};
    /// let r = Request { id: "r".into(), origin: NodeId(0), destination: NodeId(1),
    ///                   departure: Instant(0), submitted: Instant(0) };
    /// let (first, committed) = (Plan::default(), Plan::default());
    /// assert!(Flight::last("r", &r, Some(&first), Some(&Fate::Cancelled)).is_none());
    /// let stranded = Fate::Contingency(committed);
    /// let f = Flight::last("r", &r, Some(&first), Some(&stranded)).unwrap();
    /// assert_eq!(f.ending, Ending::Committed);
    /// ```
    pub fn last(
        id: &'a str,
        request: &'a Request,
        first: Option<&'a Plan>,
        fate: Option<&'a Fate>,
    ) -> Option<Self> {
        let (plan, ending) = match fate {
            None => (first?, Ending::Destination),
            Some(Fate::Replanned(p)) => (p, Ending::Destination),
            Some(Fate::Diverted(p)) => (p, Ending::Diverted),
            Some(Fate::Contingency(p)) => (p, Ending::Committed),
            Some(Fate::Cancelled) => return None,
        };
        Some(Flight::new(id, request, plan).ending(ending))
    }

    /// The same flight with another ending.
    #[must_use]
    pub fn ending(self, ending: Ending) -> Self {
        Flight { ending, ..self }
    }
}

/// How a plan must end (docs/reference.md#flight-model-and-separation,
/// #zones-announced-during-the-day).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Ending {
    /// Landing at the request's destination (planned and replanned flights).
    #[default]
    Destination,
    /// Landing at some station (a flight diverted after a zone announcement).
    Diverted,
    /// Not landing: the committed part of a flight left in contingency, ending with its
    /// arrival at the node where it is stranded; exempt from the zone rule.
    Committed,
}

/// The rule a [`Violation`] breaks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Rule {
    /// The plan itself is malformed (docs/reference.md#flight-model-and-separation: empty, wrong
    /// origin or destination, nodes not joined by an edge, `arrive > depart`, wrong traversal time,
    /// hovering before landing; docs/reference.md#multi-leg-trips: a leg that flies no edge, lands
    /// at a waypoint or where it took off).
    Path,
    /// Node separation `tau` between stays of two flights.
    Node,
    /// Edge separation (exclusive or headway) between traversals of two flights.
    Edge,
    /// Airborne time of a leg above `T_max`.
    Battery,
    /// Take-off before the requested departure or more than `G_max` after it.
    GroundDelay,
    /// A stay or traversal during a no-fly window (docs/reference.md#no-fly-zones).
    Zone,
    /// Legs that do not fit together (docs/reference.md#multi-leg-trips): several legs with battery
    /// swaps off, more than `K` legs, or a leg that does not take off from the station where the
    /// previous one landed, or takes off less than `S` after that landing.
    Swap,
    /// A flight landing at its destination later than its requested departure plus the
    /// delivery deadline ([`FlightParams::max_trip`], when set).
    Deadline,
    /// Two flights closer than the metric separation allows
    /// (docs/reference.md#metric-separation, [`FlightParams::separation`], when on).
    Separation,
}

impl Rule {
    /// A short name: `path`, `node`, `edge`, `battery`, `ground_delay`, `zone`, `swap`,
    /// `deadline` or `separation`.
    pub const fn name(self) -> &'static str {
        match self {
            Rule::Path => "path",
            Rule::Node => "node",
            Rule::Edge => "edge",
            Rule::Battery => "battery",
            Rule::GroundDelay => "ground_delay",
            Rule::Zone => "zone",
            Rule::Deadline => "deadline",
            Rule::Swap => "swap",
            Rule::Separation => "separation",
        }
    }
}

impl fmt::Display for Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One broken rule.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{rule} rule violated by {}{}: {detail}", .flights.join(", "), at(.element))]
pub struct Violation {
    /// Which rule.
    pub rule: Rule,
    /// The flights involved, by [`Flight::id`]: one, or two for separation rules.
    pub flights: Vec<String>,
    /// The node or edge id concerned; empty when the violation concerns a flight as a whole
    /// (battery, ground delay, empty plan).
    pub element: String,
    /// What is wrong, with the instants involved as RFC 3339 timestamps with milliseconds (in
    /// UTC, or in the offset given to [`verify_known_in`]) and durations in seconds.
    pub detail: String,
}

/// Checks `flights` against every rule of docs/reference.md#flight-model-and-separation and
/// #no-fly-zones and returns all violations: per-flight rules first (flight by flight), then node
/// separation (node by node), edge separation (edge by edge) and zones (flight by flight). An empty
/// result means the flights are valid together.
///
/// Node and edge indices outside the airspace are reported as [`Rule::Path`] violations and
/// otherwise ignored; stays and traversals of a malformed plan are still checked against the
/// other rules wherever they are well defined (a traversal is taken to start at the departure
/// from its first node and to last `w(e)`).
///
/// Violations give their instants in UTC ([`verify_known_in`] writes them in another offset).
pub fn verify(
    airspace: &Airspace,
    closures: &Closures,
    params: &FlightParams,
    flights: &[Flight<'_>],
) -> Vec<Violation> {
    check(airspace, closures, &[], params, flights, UtcOffset(0))
}

/// [`verify`] with zones announced during the day
/// (docs/reference.md#zones-announced-during-the-day): the zones known from the start bind every
/// stay and traversal; an announced zone binds those that begin while it is announced (see
/// [`Announced::binds`]).
///
/// ```
/// use muse_airspace::announced::KnownZones;
/// use muse_model::{Airspace, FlightParams, Instant, NodeId, Period, Plan, Request, Stay, Zone};
/// use muse_verify::{Flight, verify_known};
/// let airspace = Airspace::line(&[1_000.0]);
/// // A-B closed from 60 s, announced at 30 s.
/// let zone = Zone { id: "Z".into(), name: String::new(), restriction: String::new(), area: None,
///     node_ids: vec![], edge_ids: vec!["A-B".into()], announced: Some(Instant(30_000)), withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
///     periods: vec![Period { start: Some(Instant(60_000)), end: None, daily: vec![] }] };
/// let known = KnownZones::resolve(&airspace, &[zone], Instant(0), Instant(86_400_000)).unwrap();
/// let r = |t| Request { id: "r".into(), origin: NodeId(0), destination: NodeId(1),
///                       departure: Instant(t), submitted: Instant(t) };
/// let plan = |t: i64| Plan { path: vec![
///     Stay { node: NodeId(0), arrive: Instant(t), depart: Instant(t) },
///     Stay { node: NodeId(1), arrive: Instant(t + 120_000), depart: Instant(t + 120_000) },
/// ] };
/// let params = FlightParams::default();
/// // Entering A-B at 0 s, before the announcement: exempt. At 40 s: bound, and closed at 60 s.
/// let (r0, p0, r1, p1) = (r(0), plan(0), r(40_000), plan(40_000));
/// assert!(verify_known(&airspace, &known, &params, &[Flight::new("a", &r0, &p0)]).is_empty());
/// assert_eq!(verify_known(&airspace, &known, &params, &[Flight::new("b", &r1, &p1)]).len(), 1);
/// ```
pub fn verify_known(
    airspace: &Airspace,
    zones: &KnownZones,
    params: &FlightParams,
    flights: &[Flight<'_>],
) -> Vec<Violation> {
    verify_known_in(airspace, zones, params, flights, UtcOffset(0))
}

/// [`verify_known`] with the instants of the violations written in `offset` (the world's:
/// the offset every file of the run gives its times in) rather than in UTC.
///
/// ```
/// use muse_airspace::announced::KnownZones;
/// use muse_airspace::closures::Closures;
/// use muse_model::{Airspace, FlightParams, Instant, NodeId, Plan, Request, Stay, UtcOffset};
/// use muse_verify::{Flight, verify_known_in};
/// let airspace = Airspace::line(&[1_000.0]);
/// let r = Request { id: "r".into(), origin: NodeId(0), destination: NodeId(1),
///                   departure: Instant(0), submitted: Instant(0) };
/// // Lands at B a second early: 1 km takes 120 s at 30 km/h.
/// let p = Plan { path: vec![
///     Stay { node: NodeId(0), arrive: Instant(0), depart: Instant(0) },
///     Stay { node: NodeId(1), arrive: Instant(119_000), depart: Instant(119_000) },
/// ] };
/// let zones = KnownZones { base: Closures::none(&airspace), announced: vec![] };
/// let v = verify_known_in(&airspace, &zones, &FlightParams::default(),
///                         &[Flight::new("r", &r, &p)], UtcOffset::SINGAPORE);
/// assert!(v[0].detail.contains("departs `A` at 1970-01-01T08:00:00.000+08:00"), "{}", v[0]);
/// ```
pub fn verify_known_in(
    airspace: &Airspace,
    zones: &KnownZones,
    params: &FlightParams,
    flights: &[Flight<'_>],
    offset: UtcOffset,
) -> Vec<Violation> {
    check(
        airspace,
        &zones.base,
        &zones.announced,
        params,
        flights,
        offset,
    )
}

fn check(
    airspace: &Airspace,
    closures: &Closures,
    announced: &[Announced],
    params: &FlightParams,
    flights: &[Flight<'_>],
    offset: UtcOffset,
) -> Vec<Violation> {
    let mut out = Vec::new();
    let mut stays: Vec<Vec<Occupation>> = vec![Vec::new(); airspace.node_count()];
    let mut traversals: Vec<Vec<Occupation>> = vec![Vec::new(); airspace.edge_count()];
    for (index, flight) in flights.iter().enumerate() {
        check_flight(airspace, params, flight, &mut out, offset);
        collect(
            airspace,
            params,
            index,
            flight.plan,
            &mut stays,
            &mut traversals,
        );
    }
    for (n, list) in stays.iter_mut().enumerate() {
        node_rule(
            airspace,
            params,
            flights,
            NodeId(n as u32),
            list,
            &mut out,
            offset,
        );
    }
    for (e, list) in traversals.iter_mut().enumerate() {
        edge_rule(
            airspace,
            params,
            flights,
            EdgeId(e as u32),
            list,
            &mut out,
            offset,
        );
    }
    for flight in flights {
        zone_rule(
            airspace, closures, announced, params, flight, &mut out, offset,
        );
    }
    separation_rule(airspace, params, flights, &mut out, offset);
    out
}

/// Metric separation (docs/reference.md#metric-separation), when on: every pair of flights
/// closer than `D` horizontally while within `V` vertically, at its closest approach.
fn separation_rule(
    airspace: &Airspace,
    params: &FlightParams,
    flights: &[Flight<'_>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let separation = params.separation;
    if !separation.is_on() {
        return;
    }
    let (d, v) = (
        separation.horizontal.m(),
        separation.vertical_in(airspace).m(),
    );
    let positions = approach::Positions::new(airspace, &airspace.plane());
    for a in approach::closer_than(&positions, flights, d, v) {
        out.push(Violation {
            rule: Rule::Separation,
            flights: vec![
                flights[a.flights.0].id.to_owned(),
                flights[a.flights.1].id.to_owned(),
            ],
            element: node_name(airspace, a.near),
            detail: format!(
                "{:.3} m apart horizontally at {} (at least {d} m, or {v} m vertically)",
                a.distance_m,
                stamp(Instant(a.at_ms.round() as i64), offset),
            ),
        });
    }
}

/// Names the element in a message (nothing for a whole-flight violation).
fn at(element: &str) -> String {
    if element.is_empty() {
        String::new()
    } else {
        format!(" at `{element}`")
    }
}

/// Writes an instant as RFC 3339 in `offset`, with milliseconds (as every file MUSE writes).
fn stamp(t: Instant, offset: UtcOffset) -> String {
    t.to_rfc3339(offset)
}

/// Formats a duration as seconds with three decimals, exactly.
fn dur(d: Millis) -> String {
    let sign = if d.0 < 0 { "-" } else { "" };
    let ms = d.0.unsigned_abs();
    format!("{sign}{}.{:03}s", ms / 1000, ms % 1000)
}

/// `[a, b]`, both instants as [`stamp`] writes them.
fn span(a: Instant, b: Instant, offset: UtcOffset) -> String {
    format!("[{}, {}]", stamp(a, offset), stamp(b, offset))
}

fn node_name(airspace: &Airspace, n: NodeId) -> String {
    if n.index() >= airspace.node_count() {
        return n.to_string();
    }
    match airspace.layers() {
        // A layered airspace's copies are named as the files name them: flat id and layer.
        Some(_) => format!(
            "{} (layer {})",
            airspace.flat().node(airspace.flat_node(n)).id,
            airspace.node_layer(n)
        ),
        None => airspace.node(n).id.clone(),
    }
}

/// How violations name edge `e`: its id, or on a layered airspace the flat corridor and its
/// layer, or the vertical link's node and layers.
fn edge_name(airspace: &Airspace, e: EdgeId) -> String {
    let edge = airspace.edge(e);
    if airspace.layers().is_none() {
        return edge.id.clone();
    }
    match (airspace.edge_kind(e), airspace.flat_edge(e)) {
        (EdgeKind::Vertical { layer, .. }, _) => format!(
            "the vertical link at {} between layers {layer} and {}",
            airspace.flat().node(airspace.flat_node(edge.from)).id,
            layer + 1
        ),
        (EdgeKind::Corridor { layer, .. }, Some(flat)) => {
            format!("{} (layer {layer})", airspace.flat().edge(flat).id)
        }
        (EdgeKind::Corridor { .. }, None) => edge.id.clone(),
    }
}

fn traversal_time(airspace: &Airspace, params: &FlightParams, e: EdgeId) -> Millis {
    match (airspace.edge_kind(e), airspace.layers()) {
        // docs/reference.md#layered-airspace: `ceil(Δ_mm · 1000 / c_mm_per_s)` ms, here from Δ in
        // µm.
        (EdgeKind::Vertical { .. }, Some(layers)) => {
            let rate = i64::from(layers.climb_mm_per_s);
            Millis((layers.spacing.um() + rate - 1) / rate)
        }
        _ => params.speed.traversal_time(airspace.edge(e).length_m),
    }
}

/// The edge joining two nodes of a plan, if both exist and are joined.
fn edge_of(airspace: &Airspace, a: NodeId, b: NodeId) -> Option<EdgeId> {
    let n = airspace.node_count();
    if a.index() >= n || b.index() >= n || a == b {
        return None;
    }
    airspace.edge_between(a, b)
}

/// A violation of one flight's own rules.
fn single(rule: Rule, flight: &Flight<'_>, element: String, detail: String) -> Violation {
    Violation {
        rule,
        flights: vec![flight.id.to_string()],
        element,
        detail,
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use muse_airspace::closures::resolve;
    use muse_model::testing::joined;
    use muse_model::{EdgeRule, NodeKind, Period, Speed, Stay, Zone};

    use super::*;

    /// `A - B - C`, `B - D` and `B - E`, 100 m each: 10 s at 36 km/h.
    pub(crate) fn airspace() -> Airspace {
        airspace_with(&[])
    }

    /// [`airspace`] with `waypoints` waypoints instead of stations.
    pub(crate) fn airspace_with(waypoints: &[&str]) -> Airspace {
        let node = |id: &str, lon| {
            let kind = if waypoints.contains(&id) {
                NodeKind::Waypoint
            } else {
                NodeKind::Station
            };
            muse_model::testing::node(id, kind, lon, 1.3)
        };
        joined(
            vec![
                node("A", 103.80),
                node("B", 103.81),
                node("C", 103.82),
                node("D", 103.83),
                node("E", 103.84),
            ],
            &[
                ("A", "B", 100.0),
                ("B", "C", 100.0),
                ("B", "D", 100.0),
                ("B", "E", 100.0),
            ],
        )
    }

    pub(crate) fn params() -> FlightParams {
        FlightParams {
            speed: Speed::from_kmh(36.0).unwrap(),
            max_flight: Millis::from_secs(100),
            node_separation: Millis::from_secs(5),
            edge_rule: EdgeRule::Exclusive,
            max_ground_delay: Millis::from_secs(30),
            battery_swap: None,
            max_trip: None,
            separation: muse_model::Separation::OFF,
        }
    }

    pub(crate) const W: i64 = 10_000;

    /// A consistent plan through `nodes` (ids, hover in ms at each), taking off at `t`.
    pub(crate) fn plan(a: &Airspace, t: i64, nodes: &[(&str, i64)]) -> Plan {
        let mut path = Vec::new();
        let mut now = t;
        for (i, &(id, hover)) in nodes.iter().enumerate() {
            if i > 0 {
                now += W;
            }
            path.push(Stay {
                node: a.node_id(id).unwrap(),
                arrive: Instant(now),
                depart: Instant(now + hover),
            });
            now += hover;
        }
        Plan { path }
    }

    pub(crate) fn request(a: &Airspace, plan: &Plan, departure: i64) -> Request {
        Request {
            id: String::new(),
            origin: plan.path.first().map_or(NodeId(0), |s| s.node),
            destination: plan.path.last().map_or(a.node_id("C").unwrap(), |s| s.node),
            departure: Instant(departure),
            submitted: Instant(departure),
        }
    }

    /// Verifies plans named `f0`, `f1`, … each requested at its own take-off.
    fn check_with(params: &FlightParams, closures: &Closures, plans: &[Plan]) -> Vec<Violation> {
        let a = airspace();
        let requests: Vec<Request> = plans
            .iter()
            .map(|p| request(&a, p, p.takeoff().0))
            .collect();
        let ids: Vec<String> = (0..plans.len()).map(|i| format!("f{i}")).collect();
        let flights: Vec<Flight<'_>> = plans
            .iter()
            .zip(&requests)
            .zip(&ids)
            .map(|((plan, request), id)| Flight::new(id, request, plan))
            .collect();
        verify(&a, closures, params, &flights)
    }

    fn check(params: &FlightParams, plans: &[Plan]) -> Vec<Violation> {
        check_with(params, &Closures::none(&airspace()), plans)
    }

    pub(crate) fn rules(v: &[Violation]) -> Vec<Rule> {
        v.iter().map(|v| v.rule).collect()
    }

    #[test]
    fn a_valid_flight_passes() {
        let a = airspace();
        let p = plan(&a, 0, &[("A", 0), ("B", 3_000), ("C", 0)]);
        assert_eq!(check(&params(), &[p]), []);
    }

    #[test]
    fn path_rules() {
        let a = airspace();
        let pr = params();
        let good = plan(&a, 0, &[("A", 0), ("B", 0), ("C", 0)]);
        let one = |plan: &Plan, request: &Request| {
            verify(
                &a,
                &Closures::none(&a),
                &pr,
                &[Flight::new("x", request, plan)],
            )
        };
        let req = request(&a, &good, 0);
        assert_eq!(one(&good, &req), []);

        let empty = Plan::default();
        let v = one(&empty, &req);
        assert_eq!(rules(&v), [Rule::Path]);
        assert!(v[0].detail.contains("no stays"), "{}", v[0]);

        let other = Request {
            origin: a.node_id("D").unwrap(),
            ..req.clone()
        };
        let v = one(&good, &other);
        assert_eq!(rules(&v), [Rule::Path]);
        assert!(v[0].detail.contains("origin is `D`"), "{}", v[0]);
        let other = Request {
            destination: a.node_id("D").unwrap(),
            ..req.clone()
        };
        let v = one(&good, &other);
        assert_eq!(rules(&v), [Rule::Path]);
        assert!(v[0].detail.contains("destination is `D`"), "{}", v[0]);

        // A and C are not joined.
        let mut jump = good.clone();
        jump.path.remove(1);
        jump.path[1].arrive = Instant(W);
        jump.path[1].depart = Instant(W);
        let v = one(&jump, &req);
        assert_eq!(rules(&v), [Rule::Path]);
        assert_eq!(v[0].element, "A-C");

        // Arriving after departing.
        let mut back = good.clone();
        back.path[1].depart = Instant(W - 1);
        back.path[2].arrive = Instant(2 * W - 1);
        back.path[2].depart = Instant(2 * W - 1);
        let v = one(&back, &req);
        assert_eq!(rules(&v), [Rule::Path]);
        assert!(
            v[0].detail
                .contains("stay 1 arrives at 1970-01-01T00:00:10.000+00:00 after it departs at 1970-01-01T00:00:09.999+00:00"),
            "{}",
            v[0]
        );

        // Arriving one millisecond early or late.
        for delta in [-1, 1] {
            let mut off = good.clone();
            off.path[2].arrive = Instant(2 * W + delta);
            off.path[2].depart = Instant(2 * W + delta);
            let v = one(&off, &req);
            assert_eq!(rules(&v), [Rule::Path], "{delta}");
            assert_eq!(v[0].element, "B-C");
        }

        // Hovering at the destination before landing.
        let mut hover = good.clone();
        hover.path[2].depart = Instant(2 * W + 1);
        let v = one(&hover, &req);
        assert_eq!(rules(&v), [Rule::Path]);
        assert!(v[0].detail.contains("end at landing"), "{}", v[0]);

        // A node that is not in the airspace.
        let mut bad = good.clone();
        bad.path[1].node = NodeId(99);
        let v = one(&bad, &req);
        assert_eq!(rules(&v), [Rule::Path, Rule::Path, Rule::Path], "{v:?}");
        assert_eq!(v[0].element, "node#99");
    }

    #[test]
    fn node_rule_boundaries() {
        let a = airspace();
        let pr = params(); // tau = 5 s
        // f0 is at B during [10 s, 13 s]; f1 flies D - B - E.
        let first = plan(&a, 0, &[("A", 0), ("B", 3_000), ("C", 0)]);
        let at_b =
            |arrive: i64, hover: i64| plan(&a, arrive - W, &[("D", 0), ("B", hover), ("E", 0)]);
        // Exactly tau after f0 leaves: fine.
        assert_eq!(check(&pr, &[first.clone(), at_b(18_000, 0)]), []);
        let v = check(&pr, &[first.clone(), at_b(17_999, 0)]);
        assert_eq!(rules(&v), [Rule::Node]);
        assert_eq!(v[0].flights, ["f0", "f1"]);
        assert_eq!(v[0].element, "B");
        assert!(
            v[0].detail
                .contains("[1970-01-01T00:00:10.000+00:00, 1970-01-01T00:00:13.000+00:00] and [1970-01-01T00:00:17.999+00:00, 1970-01-01T00:00:17.999+00:00]"),
            "{}",
            v[0]
        );
        // Leaving exactly tau before f0 arrives: fine; a millisecond later is not.
        assert_eq!(check(&pr, &[first.clone(), at_b(1_000, 4_000)]), []);
        let v = check(&pr, &[first.clone(), at_b(1_000, 4_001)]);
        assert_eq!(rules(&v), [Rule::Node]);
        assert_eq!(v[0].flights, ["f1", "f0"], "listed in order of arrival");

        // tau = 0: touching stays are fine, a stay inside another's hover is not, and two
        // instantaneous stays at the same instant are fine.
        let zero = FlightParams {
            node_separation: Millis::ZERO,
            edge_rule: EdgeRule::Headway(Millis::ZERO),
            ..pr
        };
        assert_eq!(check(&zero, &[first.clone(), at_b(13_000, 0)]), []);
        assert_eq!(check(&zero, &[first.clone(), at_b(10_000, 0)]), []);
        assert_eq!(
            rules(&check(&zero, &[first.clone(), at_b(12_000, 0)])),
            [Rule::Node]
        );
        let through = plan(&a, 0, &[("A", 0), ("B", 0), ("C", 0)]);
        assert_eq!(check(&zero, &[through.clone(), at_b(10_000, 0)]), []);
    }

    #[test]
    fn every_pair_is_reported() {
        let a = airspace();
        let pr = params();
        let plans: Vec<Plan> = (0..4)
            .map(|i| plan(&a, i * 1_000, &[("B", 0), ("D", 0)]))
            .collect();
        let v = check(&pr, &plans);
        // Six node conflicts at B, six at D, six edge conflicts on B-D.
        let count = |rule| v.iter().filter(|v| v.rule == rule).count();
        assert_eq!(
            (count(Rule::Node), count(Rule::Edge), v.len()),
            (12, 6, 18),
            "{v:#?}"
        );
        let mut pairs: Vec<Vec<String>> = v
            .iter()
            .filter(|v| v.rule == Rule::Node && v.element == "B")
            .map(|v| v.flights.clone())
            .collect();
        pairs.sort();
        assert_eq!(
            pairs,
            [
                ["f0", "f1"],
                ["f0", "f2"],
                ["f0", "f3"],
                ["f1", "f2"],
                ["f1", "f3"],
                ["f2", "f3"]
            ]
        );
        // Far apart in time, nothing.
        let apart: Vec<Plan> = (0..4)
            .map(|i| plan(&a, i * 15_000, &[("B", 0), ("D", 0)]))
            .collect();
        assert_eq!(check(&pr, &apart), []);
    }

    #[test]
    fn exclusive_edges() {
        let a = airspace();
        let pr = FlightParams {
            node_separation: Millis::ZERO,
            ..params()
        };
        let ab = |t| plan(&a, t, &[("A", 0), ("B", 0)]);
        let ba = |t| plan(&a, t, &[("B", 0), ("A", 0)]);
        // End-to-start touching is fine, in either direction.
        assert_eq!(check(&pr, &[ab(0), ab(W)]), []);
        assert_eq!(check(&pr, &[ab(0), ba(W)]), []);
        assert_eq!(check(&pr, &[ba(W), ab(0)]), []);
        let v = check(&pr, &[ab(0), ab(W - 1)]);
        assert_eq!(rules(&v), [Rule::Edge]);
        assert_eq!(v[0].element, "A-B");
        assert!(v[0].detail.contains("A->B"), "{}", v[0]);
        let v = check(&pr, &[ba(W - 1), ab(0)]);
        assert_eq!(rules(&v), [Rule::Edge]);
        assert_eq!(v[0].flights, ["f1", "f0"]);
        assert!(
            v[0].detail.contains("A->B") && v[0].detail.contains("B->A"),
            "{}",
            v[0]
        );
        // Identical traversals (with tau = 0 the instantaneous stays at A and B are fine).
        assert_eq!(rules(&check(&pr, &[ab(0), ab(0)])), [Rule::Edge]);
    }

    #[test]
    fn headway_edges() {
        let a = airspace();
        let h = Millis::from_secs(2);
        let pr = FlightParams {
            node_separation: Millis::ZERO,
            edge_rule: EdgeRule::Headway(h),
            ..params()
        };
        let ab = |t| plan(&a, t, &[("A", 0), ("B", 0)]);
        let ba = |t| plan(&a, t, &[("B", 0), ("A", 0)]);
        // Same direction: exactly h apart is fine, even though both are on the edge.
        assert_eq!(check(&pr, &[ab(0), ab(2_000)]), []);
        let v = check(&pr, &[ab(0), ab(1_999)]);
        assert_eq!(rules(&v), [Rule::Edge]);
        assert!(v[0].detail.contains("headway 2.000s"), "{}", v[0]);
        // Opposite directions: exclusive.
        assert_eq!(check(&pr, &[ab(0), ba(W)]), []);
        assert_eq!(rules(&check(&pr, &[ab(0), ba(W - 1)])), [Rule::Edge]);
        assert_eq!(rules(&check(&pr, &[ab(0), ba(5_000)])), [Rule::Edge]);
        // A long queue in the same direction: only pairs closer than h.
        let queue: Vec<Plan> = (0..5).map(|i| ab(i * 1_000)).collect();
        assert_eq!(check(&pr, &queue).len(), 4);
        // h = 0: simultaneous entries in the same direction are allowed.
        let zero = FlightParams {
            edge_rule: EdgeRule::Headway(Millis::ZERO),
            ..pr
        };
        assert_eq!(check(&zero, &[ab(0), ab(0)]), []);
    }

    #[test]
    fn battery_and_ground_delay() {
        let a = airspace();
        let pr = FlightParams {
            max_flight: Millis::from_secs(25),
            ..params()
        };
        let p = |hover| plan(&a, 1_000, &[("A", 0), ("B", hover), ("C", 0)]);
        assert_eq!(check(&pr, &[p(5_000)]), []);
        let v = check(&pr, &[p(5_001)]);
        assert_eq!(rules(&v), [Rule::Battery]);
        assert!(v[0].detail.contains("airborne 25.001s"), "{}", v[0]);

        let flight = p(0);
        let one = |departure| {
            let request = request(&a, &flight, departure);
            verify(
                &a,
                &Closures::none(&a),
                &pr,
                &[Flight::new("x", &request, &flight)],
            )
        };
        assert_eq!(one(1_000), []);
        assert_eq!(one(-29_000), [], "G_max = 30 s");
        assert_eq!(rules(&one(-29_001)), [Rule::GroundDelay]);
        assert_eq!(
            rules(&one(1_001)),
            [Rule::GroundDelay],
            "before the requested departure"
        );
        let no_delay = FlightParams {
            max_ground_delay: Millis::ZERO,
            ..pr
        };
        let request = request(&a, &flight, 999);
        let v = verify(
            &a,
            &Closures::none(&a),
            &no_delay,
            &[Flight::new("x", &request, &flight)],
        );
        assert_eq!(rules(&v), [Rule::GroundDelay]);
    }

    pub(crate) fn closures(nodes: &[&str], edges: &[&str], start: i64, end: i64) -> Closures {
        let a = airspace();
        let zone = Zone {
            id: "Z".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: nodes.iter().map(|s| (*s).to_string()).collect(),
            edge_ids: edges.iter().map(|s| (*s).to_string()).collect(),
            announced: None,
            withdrawn: None,
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
            periods: vec![Period {
                start: Some(Instant(start)),
                end: Some(Instant(end)),
                daily: vec![],
            }],
        };
        resolve(&a, &[zone], Instant(0), Instant(86_400_000)).unwrap()
    }

    #[test]
    fn zone_boundaries() {
        let a = airspace();
        let pr = params();
        let z = closures(&["B"], &[], 20_000, 30_000);
        let at_b = |arrive, hover| plan(&a, arrive - W, &[("A", 0), ("B", hover), ("C", 0)]);
        // Arriving exactly when the window ends: fine.
        assert_eq!(check_with(&pr, &z, &[at_b(30_000, 0)]), []);
        assert_eq!(
            rules(&check_with(&pr, &z, &[at_b(29_999, 0)])),
            [Rule::Zone]
        );
        // Leaving exactly when the window starts is too late; a millisecond earlier is fine.
        let v = check_with(&pr, &z, &[at_b(15_000, 5_000)]);
        assert_eq!(rules(&v), [Rule::Zone]);
        assert_eq!(
            (v[0].element.as_str(), v[0].flights.as_slice()),
            ("B", ["f0".to_string()].as_slice())
        );
        assert!(
            v[0].detail
                .contains("stay [1970-01-01T00:00:15.000+00:00, 1970-01-01T00:00:20.000+00:00]"),
            "{}",
            v[0]
        );
        assert_eq!(check_with(&pr, &z, &[at_b(15_000, 4_999)]), []);
        // Hovering across the whole window.
        assert_eq!(
            rules(&check_with(&pr, &z, &[at_b(15_000, 20_000)])),
            [Rule::Zone]
        );

        // Edges: traversal [s, s + 10 s].
        let z = closures(&[], &["B-C"], 20_000, 30_000);
        let bc = |t| plan(&a, t, &[("B", 0), ("C", 0)]);
        assert_eq!(check_with(&pr, &z, &[bc(30_000)]), []);
        assert_eq!(check_with(&pr, &z, &[bc(9_999)]), []);
        assert_eq!(rules(&check_with(&pr, &z, &[bc(10_000)])), [Rule::Zone]);
        assert_eq!(rules(&check_with(&pr, &z, &[bc(29_999)])), [Rule::Zone]);

        // Origin and destination are no exception, even for an instantaneous stay.
        let z = closures(&["A", "C"], &[], 0, 5_000);
        let v = check_with(&pr, &z, &[plan(&a, 4_999, &[("A", 0), ("B", 0)])]);
        assert_eq!(rules(&v), [Rule::Zone]);
        assert_eq!(v[0].element, "A");
        let z = closures(&["C"], &[], 20_000, 20_001);
        assert_eq!(
            rules(&check_with(
                &pr,
                &z,
                &[plan(&a, 0, &[("A", 0), ("B", 0), ("C", 0)])]
            )),
            [Rule::Zone]
        );
    }

    #[test]
    fn display_names_rule_flights_element_and_times() {
        let a = airspace();
        let first = plan(&a, 0, &[("A", 0), ("B", 3_000), ("C", 0)]);
        let second = plan(&a, 7_000, &[("D", 0), ("B", 0), ("E", 0)]);
        let v = check(&params(), &[first, second]);
        assert_eq!(rules(&v), [Rule::Node]);
        assert_eq!(
            v[0].to_string(),
            "node rule violated by f0, f1 at `B`: stays [1970-01-01T00:00:10.000+00:00, 1970-01-01T00:00:13.000+00:00] and [1970-01-01T00:00:17.000+00:00, 1970-01-01T00:00:17.000+00:00] are less than tau = 5.000s apart"
        );
        assert_eq!(dur(Millis(-1_500)), "-1.500s");
        let a = airspace();
        let late = plan(&a, 0, &[("A", 0), ("B", 95_000), ("C", 0)]);
        let v = check(&params(), &[late]);
        assert_eq!(
            v[0].to_string(),
            "battery rule violated by f0: airborne 115.000s (take-off 1970-01-01T00:00:00.000+00:00, landing 1970-01-01T00:01:55.000+00:00), \
             more than T_max = 100.000s"
        );
    }

    #[test]
    fn a_withdrawn_zone_binds_only_what_begins_before_its_withdrawal() {
        // `B` closed from 0 to 100 s by a zone announced at 1 s and withdrawn at 50 s
        // (docs/reference.md#zones-announced-during-the-day).
        let a = airspace();
        let zone = Zone {
            id: "W".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: vec![],
            announced: Some(Instant(1_000)),
            withdrawn: Some(Instant(50_000)),
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
            periods: vec![Period {
                start: Some(Instant(0)),
                end: Some(Instant(100_000)),
                daily: vec![],
            }],
        };
        let known = KnownZones::resolve(&a, &[zone], Instant(0), Instant(86_400_000)).unwrap();
        assert_eq!(known.announced[0].withdrawn, Some(Instant(50_000)));
        let through_b = |arrive: i64| plan(&a, arrive - W, &[("A", 0), ("B", 0), ("C", 0)]);
        let check = |p: &Plan| {
            let r = request(&a, p, p.takeoff().0);
            verify_known_in(
                &a,
                &known,
                &params(),
                &[Flight::new("f", &r, p)],
                UtcOffset::SINGAPORE,
            )
        };
        // At `B` while the zone is in force: a violation, its instants in the offset given.
        let v = check(&through_b(49_999));
        assert_eq!(rules(&v), [Rule::Zone]);
        assert!(
            v[0].detail.contains(
                "stay [1970-01-01T08:00:49.999+08:00, 1970-01-01T08:00:49.999+08:00] shares an \
                 instant with the closure [1970-01-01T08:00:00.000+08:00, \
                 1970-01-01T08:01:40.000+08:00) of zone `W` announced at \
                 1970-01-01T08:00:01.000+08:00"
            ),
            "{}",
            v[0]
        );
        // From its withdrawal on, the window still open binds nothing.
        assert_eq!(check(&through_b(50_000)), []);
        assert_eq!(check(&through_b(90_000)), []);
    }
}
