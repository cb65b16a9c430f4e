//! The A* heuristic: exact free-flow time to the destination.
//!
//! For a destination `d`, `h(v)` is the shortest traversal time from `v` to `d` on the empty
//! graph, ignoring traffic and zones. It never overestimates the remaining flight (traffic
//! and zones only add waiting) and it is consistent (`h(u) ≤ w(u, v) + h(v)` by the triangle
//! inequality of shortest paths), unlike the paper's straight-line estimate divided by speed,
//! which is admissible but not tight. Tables are computed once per destination, on first use,
//! by one Dijkstra search backwards from the destination (a corridor may be one-way under a
//! heading rule), and then shared.
//!
//! A diversion (docs/reference.md#zones-announced-during-the-day) goes to whichever station it can
//! land at earliest; its heuristic is the free-flow time to the *nearest* station, one multi-source
//! search from all stations, equally exact and consistent.
//!
//! With battery swaps (docs/reference.md#multi-leg-trips) the remaining time also depends on how
//! long the current leg has flown: [`swaps`] holds those tables, built from the same free-flow
//! times.
//!
//! A node from which the destination cannot be reached has the time `Millis::INF`, the
//! planner's one infinity.

pub mod swaps;

use std::sync::OnceLock;

use muse_airspace::shortest::Dijkstra;
use muse_model::{Airspace, FlightParams, Millis, NodeId};

use crate::time::Unbounded;
use swaps::{Near, SwapTable};

/// Lazily computed free-flow time tables, one per destination; safe to share between threads.
#[derive(Debug)]
pub struct Heuristics {
    times: Vec<Millis>,
    tables: Vec<OnceLock<Box<[Millis]>>>,
    from_tables: Vec<OnceLock<Box<[Millis]>>>,
    any_station: OnceLock<Box<[Millis]>>,
    params: FlightParams,
    near: OnceLock<Near>,
    swap_tables: Vec<OnceLock<SwapTable>>,
}

impl Heuristics {
    /// Prepares (but does not yet compute) the tables for `airspace` and `params`.
    pub fn new(airspace: &Airspace, params: &FlightParams) -> Self {
        Heuristics {
            times: airspace.traversal_times(params.speed),
            tables: lazy(airspace),
            from_tables: lazy(airspace),
            any_station: OnceLock::new(),
            params: *params,
            near: OnceLock::new(),
            swap_tables: if params.battery_swap.is_some() {
                lazy(airspace)
            } else {
                Vec::new()
            },
        }
    }

    /// Traversal time of each edge, indexed by edge.
    pub fn traversal_times(&self) -> &[Millis] {
        &self.times
    }

    /// The multi-leg tables for `destination` (docs/reference.md#multi-leg-trips), or `None` when
    /// the parameters allow no battery swaps. Computed on the first call for this destination (the
    /// first call at all computes every station's free-flow table).
    pub fn swaps_to(&self, airspace: &Airspace, destination: NodeId) -> Option<&SwapTable> {
        let swap = self.params.battery_swap?;
        let t_max = self.params.max_flight;
        Some(self.swap_tables[destination.index()].get_or_init(|| {
            let near = self
                .near
                .get_or_init(|| Near::new(airspace, t_max, |x| self.to(airspace, x).to_vec()));
            SwapTable::new(
                airspace,
                near,
                destination,
                swap.time,
                t_max,
                swap.leg_limit(),
            )
        }))
    }

    /// Free-flow time from every node to `destination` (`Millis::INF` if none), indexed by
    /// node. Computed on the first call for this destination.
    pub fn to(&self, airspace: &Airspace, destination: NodeId) -> &[Millis] {
        self.tables[destination.index()].get_or_init(|| {
            let mut search = Dijkstra::new(airspace.node_count());
            // Backwards: corridors may be one-way (docs/reference.md#layered-airspace's heading
            // rule).
            search.run_towards_all(airspace, &self.times, &[destination]);
            times(&search)
        })
    }

    /// Free-flow time from `origin` to every node (`Millis::INF` if none), indexed by node.
    /// Computed on the first call for this origin.
    pub fn from(&self, airspace: &Airspace, origin: NodeId) -> &[Millis] {
        self.from_tables[origin.index()].get_or_init(|| {
            let mut search = Dijkstra::new(airspace.node_count());
            search.run(airspace, &self.times, origin);
            times(&search)
        })
    }

    /// Free-flow time from every node to the nearest station (`Millis::INF` if none),
    /// indexed by node. Computed on the first call.
    pub fn to_any_station(&self, airspace: &Airspace) -> &[Millis] {
        self.any_station.get_or_init(|| {
            let stations: Vec<NodeId> = airspace.stations().collect();
            let mut search = Dijkstra::new(airspace.node_count());
            search.run_towards_all(airspace, &self.times, &stations);
            times(&search)
        })
    }
}

/// The times a search found, `Millis::INF` where it found none (its raw times mark those
/// `i64::MAX`).
fn times(search: &Dijkstra) -> Box<[Millis]> {
    search
        .raw_times()
        .iter()
        .map(|&t| {
            if t == i64::MAX {
                Millis::INF
            } else {
                Millis(t)
            }
        })
        .collect()
}

/// One empty, lazily filled slot per node.
fn lazy<T>(airspace: &Airspace) -> Vec<OnceLock<T>> {
    (0..airspace.node_count())
        .map(|_| OnceLock::new())
        .collect()
}
