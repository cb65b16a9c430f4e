//! The heuristic of multi-leg trips (docs/reference.md#multi-leg-trips): the exact remaining time
//! on the empty graph when the drone may land at stations and swap its battery.
//!
//! # The relaxed problem
//!
//! Drop the traffic and the zones, keep the battery and the swaps. A drone in the air at node
//! `v` that has flown `u` ms of its current leg can land at any station `X` whose free-flow
//! time `D(v, X)` fits the battery left, `D(v, X) ≤ T_max − u`. Landing at the destination
//! `d` ends the trip; landing elsewhere costs the swap `S` and leaves the drone on the ground
//! at `X` with a full battery, from where the best trip takes `G(X)`. So the optimal remaining
//! time is
//!
//! ```text
//! H(v, u) = min over stations X with D(v, X) ≤ T_max − u of D(v, X) + c(X),
//! c(d) = 0,   c(X) = S + G(X) otherwise,   G(X) = H(X, 0).
//! ```
//!
//! `G` is a shortest-path problem on the *station graph* (an edge `X–Y` when
//! `D(X, Y) ≤ T_max`), solved by one Dijkstra search from `d` per destination. `H` is the
//! exact cost of a relaxation of the real problem, so it never overestimates (admissible) and
//! every real step — flying an edge, hovering, landing, waiting on the ground, taking off —
//! costs at least the drop in `H` it causes (consistent): what the A* search needs.
//!
//! For a node `v`, as `u` grows the stations within reach shrink to those nearest `v`, so
//! `H(v, ·)` is a non-decreasing step function. It is stored as its steps: pairs
//! `(max_used, remaining)` with `max_used` decreasing and `remaining` strictly decreasing;
//! `H(v, u)` is the `remaining` of the last step whose `max_used ≥ u`, and no landing is
//! reachable when `u` exceeds the first step's `max_used`.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use muse_model::{Airspace, Millis, NodeId};

use crate::time::Unbounded;

/// Stations within one battery of each node: `(station, free-flow time)`, nearest first;
/// and, per station, the stations within one battery of it the other way (a corridor may be
/// one-way under a heading rule, docs/reference.md#layered-airspace).
#[derive(Debug)]
pub struct Near {
    offsets: Vec<u32>,
    entries: Vec<(NodeId, Millis)>,
    into_offsets: Vec<u32>,
    into_entries: Vec<(NodeId, Millis)>,
}

impl Near {
    /// From `to_station(X)[v]`, the free-flow time from `v` to station `X` (`Millis::INF` if
    /// none), keeping those within `t_max`.
    pub fn new(
        airspace: &Airspace,
        t_max: Millis,
        to_station: impl Fn(NodeId) -> Vec<Millis>,
    ) -> Self {
        let mut per_node: Vec<Vec<(NodeId, Millis)>> = vec![Vec::new(); airspace.node_count()];
        let mut into: Vec<Vec<(NodeId, Millis)>> = vec![Vec::new(); airspace.node_count()];
        for x in airspace.stations() {
            for (v, &t) in to_station(x).iter().enumerate() {
                if t != Millis::INF && t <= t_max {
                    let v = NodeId(v as u32);
                    per_node[v.index()].push((x, t));
                    if airspace.is_station(v) {
                        into[x.index()].push((v, t));
                    }
                }
            }
        }
        let (offsets, entries) = flatten(per_node);
        let (into_offsets, into_entries) = flatten(into);
        Near {
            offsets,
            entries,
            into_offsets,
            into_entries,
        }
    }

    /// The stations within one battery of `v`, nearest first.
    pub fn of(&self, v: NodeId) -> &[(NodeId, Millis)] {
        &self.entries[self.offsets[v.index()] as usize..self.offsets[v.index() + 1] as usize]
    }

    /// The stations from which station `x` is within one battery, with the time from each,
    /// nearest first.
    pub fn into(&self, x: NodeId) -> &[(NodeId, Millis)] {
        &self.into_entries
            [self.into_offsets[x.index()] as usize..self.into_offsets[x.index() + 1] as usize]
    }
}

/// Per-node lists, each sorted nearest first, as one offsets array and one flat array.
fn flatten(lists: Vec<Vec<(NodeId, Millis)>>) -> (Vec<u32>, Vec<(NodeId, Millis)>) {
    let mut offsets = Vec::with_capacity(lists.len() + 1);
    let mut entries = Vec::new();
    offsets.push(0);
    for mut list in lists {
        list.sort_unstable_by_key(|&(x, t)| (t, x));
        entries.extend(list);
        offsets.push(entries.len() as u32);
    }
    (offsets, entries)
}

/// The multi-leg tables for one destination.
#[derive(Debug)]
pub struct SwapTable {
    offsets: Vec<u32>,
    /// `(max_used, remaining)` steps per node (see the module docs).
    steps: Vec<(Millis, Millis)>,
    /// `G(X)`: the free-flow trip from the ground at each node (stations only; others
    /// `Millis::INF`), swaps included, with no bound on the legs.
    ground: Vec<Millis>,
    /// The free-flow trip from the ground with at most the planner's leg limit, per node.
    ground_within_limit: Vec<Millis>,
}

impl SwapTable {
    /// Builds the tables for destination `d`: swap time `swap`, battery `t_max`, at most
    /// `max_legs` legs for the free-flow trip ([`SwapTable::free_flow`]).
    pub fn new(
        airspace: &Airspace,
        near: &Near,
        d: NodeId,
        swap: Millis,
        t_max: Millis,
        max_legs: u32,
    ) -> Self {
        let n = airspace.node_count();
        let ground = station_dijkstra(airspace, near, d, swap);
        let cost = |x: NodeId| {
            if x == d {
                Millis::ZERO
            } else if ground[x.index()] == Millis::INF {
                Millis::INF
            } else {
                swap + ground[x.index()]
            }
        };
        let mut offsets = Vec::with_capacity(n + 1);
        let mut steps = Vec::new();
        offsets.push(0);
        for v in 0..n {
            let mut best = Millis::INF;
            for &(x, t) in near.of(NodeId(v as u32)) {
                let c = cost(x);
                if c != Millis::INF && t + c < best {
                    best = t + c;
                    steps.push((t_max - t, best));
                }
            }
            offsets.push(steps.len() as u32);
        }
        let ground_within_limit = if max_legs == u32::MAX {
            ground.clone()
        } else {
            limited_legs(airspace, near, d, swap, max_legs)
        };
        SwapTable {
            offsets,
            steps,
            ground,
            ground_within_limit,
        }
    }

    /// `H(v, used)`: the least time still to fly (swaps included) from node `v` after `used`
    /// of the current leg, or `Millis::INF` when no station is within the battery left.
    #[inline]
    pub fn remaining(&self, v: NodeId, used: Millis) -> Millis {
        let steps = self.steps_of(v);
        let mut best = Millis::INF;
        for &(max_used, remaining) in steps {
            if max_used < used {
                break;
            }
            best = remaining;
        }
        best
    }

    /// The most a leg may have flown on reaching `v` and still land somewhere useful
    /// (`Millis::NEG_INF` if nowhere).
    #[inline]
    pub fn max_used(&self, v: NodeId) -> Millis {
        self.steps_of(v).first().map_or(Millis::NEG_INF, |s| s.0)
    }

    /// `G(v)`: the free-flow trip from the ground at station `v`, swaps included
    /// (`Millis::INF` if none).
    #[inline]
    pub fn trip_from_ground(&self, v: NodeId) -> Millis {
        self.ground[v.index()]
    }

    /// The free-flow trip from the ground at station `v` with at most the leg limit, swaps
    /// included (docs/reference.md#multi-leg-trips: `free_flow_s`), or `None` when no chain of legs
    /// within range joins `v` to the destination (`out_of_range`).
    pub fn free_flow(&self, v: NodeId) -> Option<Millis> {
        let t = self.ground_within_limit[v.index()];
        (t != Millis::INF).then_some(t)
    }

    #[inline]
    fn steps_of(&self, v: NodeId) -> &[(Millis, Millis)] {
        &self.steps[self.offsets[v.index()] as usize..self.offsets[v.index() + 1] as usize]
    }
}

/// `G` for every node: Dijkstra on the station graph from the destination, where reaching
/// `X` from `Y` costs `D(X, Y)` plus the swap at `Y` unless `Y` is the destination.
fn station_dijkstra(airspace: &Airspace, near: &Near, d: NodeId, swap: Millis) -> Vec<Millis> {
    let n = airspace.node_count();
    // `c[x]`: the cost from being in the air *at* station `x`, about to land there.
    let mut c = vec![Millis::INF; n];
    let mut ground = vec![Millis::INF; n];
    let mut heap = BinaryHeap::new();
    c[d.index()] = Millis::ZERO;
    heap.push(Reverse((Millis::ZERO, d)));
    while let Some(Reverse((cy, y))) = heap.pop() {
        if cy > c[y.index()] {
            continue;
        }
        // The stations from which `y` is within one battery (`D` is not symmetric when a
        // heading rule makes corridors one-way).
        for &(x, t) in near.into(y) {
            if x == y || x == d {
                continue;
            }
            let g = t + cy;
            if g < ground[x.index()] {
                ground[x.index()] = g;
                let cx = swap + g;
                if cx < c[x.index()] {
                    c[x.index()] = cx;
                    heap.push(Reverse((cx, x)));
                }
            }
        }
    }
    ground[d.index()] = Millis::ZERO;
    ground
}

/// The free-flow trip from the ground with at most `max_legs` legs: Bellman–Ford on the
/// station graph, one round per leg.
fn limited_legs(
    airspace: &Airspace,
    near: &Near,
    d: NodeId,
    swap: Millis,
    max_legs: u32,
) -> Vec<Millis> {
    let n = airspace.node_count();
    let mut best = vec![Millis::INF; n];
    best[d.index()] = Millis::ZERO;
    for _ in 0..max_legs.min(n as u32) {
        let mut next = best.clone();
        for x in airspace.stations() {
            if x == d {
                continue;
            }
            for &(y, t) in near.of(x) {
                if y == x || best[y.index()] == Millis::INF {
                    continue;
                }
                let via = if y == d { Millis::ZERO } else { swap };
                next[x.index()] = next[x.index()].min(t + via + best[y.index()]);
            }
        }
        if next == best {
            break;
        }
        best = next;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::Airspace;

    /// Stations 0 — 1 — 2 — 3 in a line, each corridor 1 km: 120 s at 30 km/h.
    fn line() -> Airspace {
        Airspace::line(&[1_000.0, 1_000.0, 1_000.0])
    }

    fn tables(t_max: i64, swap: i64, max_legs: u32) -> SwapTable {
        let a = line();
        let to = |x: NodeId| {
            (0..a.node_count())
                .map(|v| Millis((v as i64 - i64::from(x.0)).abs() * 120_000))
                .collect::<Vec<_>>()
        };
        let near = Near::new(&a, Millis(t_max), to);
        SwapTable::new(&a, &near, NodeId(3), Millis(swap), Millis(t_max), max_legs)
    }

    #[test]
    fn remaining_time_counts_the_swaps_the_battery_forces() {
        // Each edge takes 120 s; the battery lasts 250 s: two edges per leg at most.
        let t = tables(250_000, 60_000, u32::MAX);
        assert_eq!(t.trip_from_ground(NodeId(3)), Millis(0));
        assert_eq!(t.trip_from_ground(NodeId(2)), Millis(120_000));
        assert_eq!(t.trip_from_ground(NodeId(1)), Millis(240_000));
        // From 0: three edges need one swap.
        assert_eq!(t.trip_from_ground(NodeId(0)), Millis(360_000 + 60_000));
        // In the air at 1 with 100 s flown: only station 1 or 2 is reachable (≤ 150 s).
        assert_eq!(
            t.remaining(NodeId(1), Millis(100_000)),
            Millis(120_000 + 60_000 + 120_000)
        );
        assert_eq!(t.remaining(NodeId(1), Millis(0)), Millis(240_000));
        assert_eq!(
            t.remaining(NodeId(1), Millis(200_000)),
            Millis(60_000 + 240_000)
        );
        assert_eq!(t.remaining(NodeId(1), Millis(250_001)), Millis::INF);
        assert_eq!(t.max_used(NodeId(1)), Millis(250_000));
        assert_eq!(t.free_flow(NodeId(0)), Some(Millis(420_000)));
    }

    #[test]
    fn a_leg_limit_bounds_the_free_flow_trip() {
        let t = tables(250_000, 60_000, 1);
        assert_eq!(t.free_flow(NodeId(0)), None, "three edges need two legs");
        assert_eq!(t.free_flow(NodeId(1)), Some(Millis(240_000)));
        let t = tables(130_000, 60_000, 2);
        assert_eq!(t.free_flow(NodeId(0)), None, "one edge per leg: three legs");
        let t = tables(130_000, 60_000, 3);
        assert_eq!(t.free_flow(NodeId(0)), Some(Millis(360_000 + 120_000)));
    }
}
