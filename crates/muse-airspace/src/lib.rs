//! Building and analysing airspaces.
//!
//! - [`builder`]: stations (and waypoints) → Delaunay triangulation → the paper's
//!   "join collinear nodes" → optional maximum edge length → a connected [`Airspace`](muse_model::Airspace);
//! - [`plane`]: the local metric plane an airspace is built in (UTM, SVY21, stereographic);
//! - [`closures`]: zones + a date range → each node's and edge's closure windows (on a
//!   layered airspace, of the copies at the layers in each zone's vertical band);
//! - [`announced`]: those windows by when their zones became known
//!   (docs/reference.md#zones-announced-during-the-day);
//! - [`shortest`]: Dijkstra on integer traversal times (free-flow times, heuristics);
//! - [`stats`]: graph statistics for `muse airspace info`.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod announced;
pub mod builder;
pub mod closures;
pub mod conflicts;
pub mod corners;
pub mod plane;
pub mod shortest;
pub mod stats;
