//! Small builders for tests: nodes, edges, airspaces, requests, stays and plans in one line
//! each.
//!
//! Compiled only for this crate's own tests and with the `testing` feature, which other
//! crates enable under `[dev-dependencies]` only: nothing here is part of a normal build.
//! Unlike the library, these builders panic on invalid input (with a message saying what
//! was wrong), as a test should. For a straight line of stations there is also
//! [`Airspace::line`], which is public.
//!
//! ```
//! use muse_model::testing::{airspace, edge, plan, request, station, waypoint};
//! use muse_model::{Instant, NodeId};
//!
//! // A — W — B, 1 km and 2 km, with a waypoint in the middle.
//! let a = airspace(
//!     vec![station("A", 103.80, 1.3), waypoint("W", 103.81, 1.3), station("B", 103.82, 1.3)],
//!     vec![edge(0, 1, 1_000.0), edge(1, 2, 2_000.0)],
//! );
//! assert_eq!(a.edge_id("1-2"), a.edge_between(NodeId(1), NodeId(2)));
//! assert_eq!(a.stations().count(), 2);
//!
//! let r = request("r1", 0, 2, 60_000);
//! assert_eq!((r.departure, r.submitted), (Instant(60_000), Instant(60_000)));
//! let p = plan(&[(0, 60_000, 60_000), (1, 130_000, 130_000), (2, 270_000, 270_000)]);
//! assert_eq!(p.landing(), Instant(270_000));
//! ```

use crate::{Airspace, Edge, Instant, LonLat, Node, NodeId, NodeKind, Plan, Request, Stay};

/// A node of the given kind at `(lon, lat)`, with an empty name.
pub fn node(id: &str, kind: NodeKind, lon: f64, lat: f64) -> Node {
    Node {
        id: id.into(),
        kind,
        name: String::new(),
        pos: LonLat::new(lon, lat),
    }
}

/// A station at `(lon, lat)`, with an empty name.
///
/// ```
/// use muse_model::{testing::station, NodeKind};
/// assert_eq!(station("S1", 103.8, 1.3).kind, NodeKind::Station);
/// ```
pub fn station(id: &str, lon: f64, lat: f64) -> Node {
    node(id, NodeKind::Station, lon, lat)
}

/// A waypoint at `(lon, lat)`, with an empty name.
///
/// ```
/// use muse_model::{testing::waypoint, NodeKind};
/// assert_eq!(waypoint("W1", 103.8, 1.3).kind, NodeKind::Waypoint);
/// ```
pub fn waypoint(id: &str, lon: f64, lat: f64) -> Node {
    node(id, NodeKind::Waypoint, lon, lat)
}

/// The edge between node indices `from` and `to`, `length_m` metres long, with id
/// `"{from}-{to}"`.
///
/// ```
/// use muse_model::testing::edge;
/// assert_eq!(edge(0, 3, 250.0).id, "0-3");
/// ```
pub fn edge(from: u32, to: u32, length_m: f64) -> Edge {
    named_edge(&format!("{from}-{to}"), from, to, length_m)
}

/// The edge between node indices `from` and `to`, `length_m` metres long, with the given id.
///
/// ```
/// use muse_model::testing::named_edge;
/// assert_eq!(named_edge("A-B", 0, 1, 250.0).id, "A-B");
/// ```
pub fn named_edge(id: &str, from: u32, to: u32, length_m: f64) -> Edge {
    Edge {
        id: id.into(),
        from: NodeId(from),
        to: NodeId(to),
        length_m,
    }
}

/// The airspace of these nodes and edges.
///
/// # Panics
///
/// If [`Airspace::new`] refuses them, with its error.
pub fn airspace(nodes: Vec<Node>, edges: Vec<Edge>) -> Airspace {
    Airspace::new(nodes, edges).unwrap_or_else(|e| panic!("test airspace is invalid: {e}"))
}

/// The airspace of these nodes and of edges given as `(from id, to id, length_m)`, each
/// named `"{from id}-{to id}"`.
///
/// ```
/// use muse_model::testing::{joined, station};
/// let a = joined(
///     vec![station("A", 103.80, 1.3), station("B", 103.81, 1.3)],
///     &[("A", "B", 1_000.0)],
/// );
/// assert_eq!(a.edge(a.edge_id("A-B").unwrap()).length_m, 1_000.0);
/// ```
///
/// # Panics
///
/// If an edge names an unknown node, or [`Airspace::new`] refuses the result.
pub fn joined(nodes: Vec<Node>, edges: &[(&str, &str, f64)]) -> Airspace {
    let index = |id: &str| {
        let i = nodes
            .iter()
            .position(|n| n.id == id)
            .unwrap_or_else(|| panic!("test edge names an unknown node {id:?}"));
        u32::try_from(i).expect("test airspace fits u32 indices")
    };
    let edges = edges
        .iter()
        .map(|&(a, b, length_m)| named_edge(&format!("{a}-{b}"), index(a), index(b), length_m))
        .collect();
    airspace(nodes, edges)
}

/// A request from node index `origin` to `destination`, departing at `departure_ms` and
/// submitted at the same instant (override `submitted` with struct update syntax).
///
/// ```
/// use muse_model::testing::request;
/// use muse_model::{Instant, Request};
/// let late = Request { submitted: Instant(0), ..request("r1", 0, 1, 5_000) };
/// assert_eq!((late.departure, late.submitted), (Instant(5_000), Instant(0)));
/// ```
pub fn request(id: &str, origin: u32, destination: u32, departure_ms: i64) -> Request {
    Request {
        id: id.into(),
        origin: NodeId(origin),
        destination: NodeId(destination),
        departure: Instant(departure_ms),
        submitted: Instant(departure_ms),
    }
}

/// A stay at node index `node` from `arrive_ms` to `depart_ms`.
pub fn stay(node: u32, arrive_ms: i64, depart_ms: i64) -> Stay {
    Stay {
        node: NodeId(node),
        arrive: Instant(arrive_ms),
        depart: Instant(depart_ms),
    }
}

/// A plan of stays given as `(node index, arrive_ms, depart_ms)`.
///
/// ```
/// use muse_model::testing::plan;
/// use muse_model::Instant;
/// let p = plan(&[(0, 0, 1_000), (1, 5_000, 5_000)]);
/// assert_eq!((p.takeoff(), p.landing()), (Instant(0), Instant(5_000)));
/// ```
pub fn plan(stays: &[(u32, i64, i64)]) -> Plan {
    Plan {
        path: stays.iter().map(|&(n, a, d)| stay(n, a, d)).collect(),
    }
}
