//! The search behind [`super::solve`] and [`super::resume`]: labels on the time grid, in the
//! air and on the ground between legs.

use std::cmp::Reverse;
use std::collections::HashMap;

use muse_model::{Airspace, EdgeId, FlightParams, Instant, NodeId, Plan, Stay};

use super::super::{Goal, Grid, RawClosures, Traffic, dmax, rule_of, traversal_ok, weight};
use super::{Chains, Trip, last_event, swap_of};

/// Where a search starts.
#[derive(Clone, Copy, Debug)]
pub(super) enum Start {
    /// A request: leg 1 takes off at `origin` in `[earliest, latest]`.
    Request {
        origin: NodeId,
        earliest: i64,
        latest: i64,
    },
    /// In the air (see [`Resume::Air`]).
    Air {
        node: NodeId,
        at: i64,
        leg_takeoff: i64,
        leg_station: Option<NodeId>,
        first_takeoff: i64,
        legs: u32,
    },
    /// On the ground (see [`Resume::Ground`]).
    Ground {
        station: NodeId,
        at: i64,
        first_takeoff: i64,
        legs: u32,
    },
}

/// How a label came about.
#[derive(Clone, Copy, Debug)]
enum How {
    /// The start: leg 1's take-off, or the resumed airborne arrival.
    Start,
    /// Flew from the stay of label `from`, leaving at grid index `left`.
    Flew { from: usize, left: usize },
    /// Took off after a swap, having landed as label `landed` (`None`: a resumed ground start).
    Swapped { landed: Option<usize> },
}

/// An airborne arrival (or take-off) at `node`, grid index `arrived`.
#[derive(Clone, Copy, Debug)]
struct Label {
    node: NodeId,
    arrived: usize,
    /// The current leg's take-off instant.
    leg_takeoff: i64,
    /// The first leg's take-off instant.
    first_takeoff: i64,
    /// Legs begun, the current one included.
    legs: u32,
    /// The current leg's take-off station, where it may not land (`None`: anywhere).
    leg_station: Option<NodeId>,
    how: How,
}

impl Label {
    /// Whether every continuation of `other` (at the same node and instant) is open to this
    /// label and ends no worse.
    fn covers(&self, other: &Label) -> bool {
        self.leg_station == other.leg_station
            && self.leg_takeoff >= other.leg_takeoff
            && self.first_takeoff >= other.first_takeoff
            && self.legs <= other.legs
    }
}

/// A drone on the ground at a station, free to take off from `ready` on.
#[derive(Clone, Copy, Debug)]
struct Ground {
    ready: i64,
    first_takeoff: i64,
    /// Legs flown.
    legs: u32,
    /// The landing label (`None`: a resumed ground start).
    landed: Option<usize>,
}

impl Ground {
    fn covers(&self, other: &Ground) -> bool {
        self.ready <= other.ready
            && self.first_takeoff >= other.first_takeoff
            && self.legs <= other.legs
    }
}

/// Adds `new` to the labels at one place and instant unless one there covers it, dropping
/// those it covers.
fn add_label(labels: &mut Vec<Label>, here: &mut Vec<usize>, new: Label) {
    if here.iter().any(|&x| labels[x].covers(&new)) {
        return;
    }
    here.retain(|&x| !new.covers(&labels[x]));
    here.push(labels.len());
    labels.push(new);
}

/// Opens the stay of label `id`, which may last until grid index `until`, unless a stay open
/// at least as long covers it; drops the stays it covers that close no later.
fn add_stay(labels: &[Label], stays: &mut Vec<(usize, usize)>, id: usize, until: usize) {
    let new = &labels[id];
    if stays
        .iter()
        .any(|&(x, u)| u >= until && labels[x].covers(new))
    {
        return;
    }
    stays.retain(|&(x, u)| !(u <= until && new.covers(&labels[x])));
    stays.push((id, until));
}

/// Adds a ground label unless one at the station covers it, dropping those it covers.
fn add_ground(here: &mut Vec<Ground>, new: Ground) {
    if here.iter().any(|g| g.covers(&new)) {
        return;
    }
    here.retain(|g| !new.covers(g));
    here.push(new);
}

/// How landings at the goal at one instant rank (least first): for a destination, the latest
/// first take-off, then the fewest legs; for any station, the lowest node index first.
type Rank = (usize, Reverse<i64>, u32);

/// One search: everything fixed for a start and a goal.
pub(super) struct Search<'a> {
    airspace: &'a Airspace,
    params: &'a FlightParams,
    closures: &'a RawClosures,
    grid: Grid,
    traffic: Traffic,
    weights: Vec<i64>,
    start: Start,
    goal: Goal,
    /// Towards a destination: its free-flow chains (prune swaps that cannot reach it).
    chains: Option<Chains>,
    /// `S`, ms.
    swap: i64,
    /// `K` (1 without swaps).
    max_legs: u32,
    /// Whether intermediate landings are allowed (swaps on and a destination to reach).
    swaps: bool,
    /// `H`: no optimal trip has an instant after it (module docs).
    horizon: i64,
}

impl<'a> Search<'a> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        airspace: &'a Airspace,
        params: &'a FlightParams,
        closures: &'a RawClosures,
        traffic: Traffic,
        grid: Grid,
        start: Start,
        start_last: i64,
        goal: Goal,
        chains: Option<Chains>,
    ) -> Self {
        let weights: Vec<i64> = (0..airspace.edge_count())
            .map(|i| weight(airspace, params, EdgeId(i as u32)))
            .collect();
        assert!(weights.iter().all(|&w| w > 0 && w % grid.unit == 0));
        let (swap, max_legs) = swap_of(params);
        let e = last_event(params, &traffic, closures, start_last);
        let f = chains.as_ref().map_or(0, Chains::worst);
        let horizon = e + params.max_flight.0 + swap + f;
        Search {
            airspace,
            params,
            closures,
            grid,
            traffic,
            weights,
            start,
            goal,
            swaps: params.battery_swap.is_some() && matches!(goal, Goal::Node(_)),
            chains,
            swap,
            max_legs,
            horizon,
        }
    }

    /// Whether a drone of label `l` landing at station `v` (not the goal) may swap and go on.
    fn may_swap(&self, l: &Label, v: NodeId) -> bool {
        self.swaps
            && l.legs < self.max_legs
            && self
                .chains
                .as_ref()
                .is_some_and(|c| c.within(v, self.max_legs - l.legs).is_some())
    }

    /// The grid index of the last instant `<= t`, clamped to the grid.
    fn until(&self, t: i64, points: usize) -> usize {
        if t >= self.grid.time(points - 1) {
            points - 1
        } else {
            self.grid.floor(t)
        }
    }

    /// The optimal trip and a plan achieving it, if any.
    #[allow(clippy::too_many_lines)]
    pub(super) fn run(&self) -> Option<(Trip, Plan)> {
        let grid = &self.grid;
        let per_unit = grid.offsets.len();
        let unit = grid.unit;
        let t_max = self.params.max_flight.0;
        let tau = self.params.node_separation.0;
        let points = ((self.horizon - grid.base).max(0) / unit) as usize * per_unit + per_unit;
        let nodes = self.airspace.node_count();
        let mut labels: Vec<Label> = Vec::new();
        // Labels arriving at (grid index, node), Pareto-minimal.
        let mut arrivals: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
        // Open stays per node: (label, last grid index it may leave at).
        let mut stays: Vec<Vec<(usize, usize)>> = vec![Vec::new(); nodes];
        // Drones on the ground per station.
        let mut ground: Vec<Vec<Ground>> = vec![Vec::new(); nodes];
        // Leg 1's take-offs: grid indices [first, last] at the origin (none when resuming).
        let (first_leg, last_leg) = match self.start {
            Start::Request {
                earliest, latest, ..
            } => {
                let f = grid.floor(earliest);
                (f + usize::from(grid.time(f) < earliest), grid.floor(latest))
            }
            _ => (1, 0),
        };
        // The last grid index with an arrival scheduled.
        let mut pending = 0;
        match self.start {
            Start::Request { .. } => {}
            Start::Air {
                node,
                at,
                leg_takeoff,
                leg_station,
                first_takeoff,
                legs,
            } => {
                let i = grid.floor(at);
                assert_eq!(grid.time(i), at, "`at` is on the grid");
                let label = Label {
                    node,
                    arrived: i,
                    leg_takeoff,
                    first_takeoff,
                    legs,
                    leg_station,
                    how: How::Start,
                };
                add_label(
                    &mut labels,
                    arrivals.entry((i, node.index())).or_default(),
                    label,
                );
                pending = i;
            }
            Start::Ground {
                station,
                at,
                first_takeoff,
                legs,
            } => ground[station.index()].push(Ground {
                ready: at,
                first_takeoff,
                legs,
                landed: None,
            }),
        }

        for i in 0..points {
            let now = grid.time(i);
            if let Start::Request { origin, .. } = self.start
                && (first_leg..=last_leg).contains(&i)
            {
                let label = Label {
                    node: origin,
                    arrived: i,
                    leg_takeoff: now,
                    first_takeoff: now,
                    legs: 1,
                    leg_station: Some(origin),
                    how: How::Start,
                };
                add_label(
                    &mut labels,
                    arrivals.entry((i, origin.index())).or_default(),
                    label,
                );
            }
            // Arrivals at `now` are final: every edge takes at least a unit.
            // The best landing at the goal now: (rank, label).
            let mut best: Option<(Rank, usize)> = None;
            for v in 0..nodes {
                let node = NodeId(v as u32);
                for id in arrivals.remove(&(i, v)).unwrap_or_default() {
                    let l = labels[id];
                    debug_assert!(now - l.leg_takeoff <= t_max);
                    let Some(last) = dmax(node, now, tau, &self.traffic, self.closures) else {
                        continue;
                    };
                    if self.airspace.is_station(node) && l.leg_station != Some(node) {
                        // It may land here: the instantaneous stay [now, now] is allowed.
                        let goal = match self.goal {
                            Goal::Node(d) => d == node,
                            Goal::AnyStation => true,
                        };
                        if goal {
                            let index = match self.goal {
                                Goal::Node(_) => 0,
                                Goal::AnyStation => v,
                            };
                            let key = (index, Reverse(l.first_takeoff), l.legs);
                            if best.is_none_or(|(k, _)| key < k) {
                                best = Some((key, id));
                            }
                            continue;
                        }
                        if self.may_swap(&l, node) {
                            let g = Ground {
                                ready: now + self.swap,
                                first_takeoff: l.first_takeoff,
                                legs: l.legs,
                                landed: Some(id),
                            };
                            add_ground(&mut ground[v], g);
                        }
                    }
                    add_stay(&labels, &mut stays[v], id, self.until(last, points));
                }
            }
            if let Some((_, id)) = best {
                return Some(self.finish(&labels, id));
            }
            // Take-offs after a swap (landings just made included when `S = 0`).
            for v in 0..nodes {
                let node = NodeId(v as u32);
                for g in ground[v].clone() {
                    if g.ready > now || g.legs >= self.max_legs {
                        continue;
                    }
                    let Some(last) = dmax(node, now, tau, &self.traffic, self.closures) else {
                        continue;
                    };
                    labels.push(Label {
                        node,
                        arrived: i,
                        leg_takeoff: now,
                        first_takeoff: g.first_takeoff,
                        legs: g.legs + 1,
                        leg_station: Some(node),
                        how: How::Swapped { landed: g.landed },
                    });
                    add_stay(
                        &labels,
                        &mut stays[v],
                        labels.len() - 1,
                        self.until(last, points),
                    );
                }
            }
            // Departures at `now`.
            let mut alive = i < last_leg || ground.iter().any(|g| !g.is_empty());
            for (v, open) in stays.iter_mut().enumerate() {
                open.retain(|&(id, until)| until >= i && now - labels[id].leg_takeoff <= t_max);
                if open.is_empty() {
                    continue;
                }
                alive = true;
                let node = NodeId(v as u32);
                for adj in self.airspace.neighbours(node) {
                    let weight = self.weights[adj.edge.index()];
                    let to = i + (weight / unit) as usize * per_unit;
                    if to >= points {
                        continue;
                    }
                    let forward = self.airspace.edge(adj.edge).from == node;
                    let rule = rule_of(self.airspace, self.params, adj.edge);
                    if !traversal_ok(
                        adj.edge,
                        forward,
                        now,
                        weight,
                        rule,
                        &self.traffic,
                        self.closures,
                    ) {
                        continue;
                    }
                    for &(id, _) in open.iter() {
                        let l = labels[id];
                        if grid.time(to) - l.leg_takeoff > t_max {
                            continue;
                        }
                        let next = Label {
                            node: adj.node,
                            arrived: to,
                            how: How::Flew { from: id, left: i },
                            ..l
                        };
                        let here = arrivals.entry((to, adj.node.index())).or_default();
                        add_label(&mut labels, here, next);
                        pending = pending.max(to);
                    }
                }
            }
            if !alive && pending <= i {
                break;
            }
        }
        None
    }

    /// The trip ending with the landing of label `id`, and its plan.
    fn finish(&self, labels: &[Label], id: usize) -> (Trip, Plan) {
        let grid = &self.grid;
        let end = labels[id];
        let at = |i: usize| Instant(grid.time(i));
        let mut path = vec![Stay {
            node: end.node,
            arrive: at(end.arrived),
            depart: at(end.arrived),
        }];
        let mut cur = id;
        loop {
            match labels[cur].how {
                How::Start | How::Swapped { landed: None } => break,
                How::Flew { from, left } => {
                    let f = labels[from];
                    path.push(Stay {
                        node: f.node,
                        arrive: at(f.arrived),
                        depart: at(left),
                    });
                    cur = from;
                }
                How::Swapped {
                    landed: Some(landed),
                } => {
                    // The previous leg's landing stay.
                    let l = labels[landed];
                    path.push(Stay {
                        node: l.node,
                        arrive: at(l.arrived),
                        depart: at(l.arrived),
                    });
                    cur = landed;
                }
            }
        }
        path.reverse();
        let trip = Trip {
            landing: at(end.arrived),
            first_takeoff: Instant(end.first_takeoff),
            legs: end.legs,
        };
        (trip, Plan { path })
    }
}
