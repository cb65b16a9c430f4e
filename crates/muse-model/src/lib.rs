//! Core types of MUSE, shared by every other crate.
//!
//! Everything here is plain data with exact arithmetic where the reference demands it:
//!
//! - [`ids`]: dense node and edge indices;
//! - [`time`]: integer-millisecond instants and durations, RFC 3339 at the edges;
//! - [`coords`]: WGS84 and SVY21 (EPSG:3414) coordinates and geodesic lengths;
//! - [`frame`]: metres per degree at a latitude, and the local metric frame (metres east and
//!   north of an origin) built on them;
//! - [`units`]: cruise speed and the exact edge traversal time `w(e)`; lengths and heights
//!   exact to the micrometre;
//! - [`airspace`]: the airspace graph with a compact adjacency layout;
//! - [`request`]: delivery requests;
//! - [`zone`]: no-fly zones (area and/or explicit elements, with time windows and a vertical
//!   band) and the polygons of their areas;
//! - [`params`]: the flight model parameters (speed, battery, separations, ground delay);
//! - [`plan`]: planned flights and rejections;
//! - `testing` (with the `testing` feature, for other crates' tests only): one-line
//!   builders of nodes, edges, airspaces, requests, stays and plans.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod airspace;
pub mod coords;
pub mod frame;
pub mod ids;
pub mod layers;
pub mod params;
pub mod plan;
pub mod request;
#[cfg(any(test, feature = "testing"))]
pub mod testing;
pub mod time;
pub mod units;
pub mod zone;

pub use airspace::{Adjacent, Airspace, AirspaceError, Edge, EdgeKind, Node, NodeKind};
pub use coords::{LonLat, SVY21_PROJ, Svy21, WGS84_PROJ};
pub use frame::{LocalFrame, MetresPer};
pub use ids::{EdgeId, NodeId};
pub use layers::{HeadingRule, Layers, LayersError};
pub use params::{BatterySwap, EdgeRule, FlightParams, Separation};
pub use plan::{Plan, RejectReason, Stay};
pub use request::Request;
pub use time::{Instant, Millis, UtcOffset};
pub use units::{Metres, Speed};
pub use zone::{
    DailyWindow, Period, VerticalLimit, VerticalLimits, VerticalReference, Weekday, Zone, ZoneArea,
    circle_polygon, zone_area_polygons,
};
