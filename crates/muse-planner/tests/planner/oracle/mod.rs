//! A brute-force, time-expanded reference planner for small instances (tests only).
//!
//! It shares nothing with the planner: separation is checked pairwise against the other
//! flights' plans, straight from docs/reference.md#flight-model-and-separation, and closures are
//! the raw zone windows of the instance (not `muse_airspace`'s merged windows).
//!
//! # Why a grid search is exact here
//!
//! The instances' data are whole multiples of a time unit `u` (whole seconds: `u = 1000` ms):
//! traversal times, `tau`, the headway, `G_max`, `T_max`, requested departures and zone
//! windows. The other flights' plans come from the planner and may use any millisecond. For a
//! fixed route and a fixed choice of which side of every separation and zone disjunction a
//! plan is on, the feasible plans form a system of difference constraints `x_i - x_j <= c`
//! (with `c` whole units: `w`, `tau`, `h`, `T_max`, hover `>= 0`) plus lower and upper bounds
//! on single times:
//!
//! - lower bounds: `a >= d1 + tau`, `a >= end` (zone), `s >= f1`, `s >= s1 + h`,
//!   `take-off >= departure`;
//! - upper bounds: `d <= a1 - tau`, `d <= start - 1 ms` (zone: `d < start`), `s <= s1 - w`,
//!   `s <= s1 - h`, `take-off <= departure + G_max`, and `landing <= L` once the earliest
//!   landing `L` is known.
//!
//! Such a system's least solution (earliest landing) takes every time from one lower bound
//! plus whole units, and its greatest solution (latest take-off once the landing is fixed)
//! from one upper bound plus whole units. So an optimal plan exists whose every time is a
//! whole unit plus an offset from `O = {0, u - 1} ∪ {t mod u : t a time of another flight}`.
//! The search therefore runs on the grid `{k u + o : o ∈ O}`; with no traffic off whole units
//! that is whole units and "one millisecond before" them (needed because a stay must *end
//! before* a closure starts: a drone may leave a node at `start - 1 ms`).
//!
//! # The search
//!
//! States are arrivals `(node, arrival time)` valued by the latest take-off that reaches them
//! (a later take-off is never worse: the only rule linking a plan's past to its future is the
//! battery). A stay `[a, d]` is checked whole, by the reference formulas: it is allowed exactly for
//! `d` in `[a, dmax(a)]`, where `dmax` is the tightest of `a1 - tau` over other stays with
//! `a < d1 + tau` and `start - 1 ms` over windows with `a < end` (both rules are monotone in
//! `d`). From a node the drone may leave at any grid instant covered by one of its stays there;
//! the traversal `[s, s + w]` is checked against every other traversal of the edge and every
//! window. The first time the destination can be arrived at (and the instantaneous landing
//! stay is allowed) is the earliest landing; its value the latest take-off.
//!
//! (A simpler per-instant test "the node is free at both ends of each hover step" is not
//! exact: with `tau = 0` a stay `[x - 1 s, x + 1 s]` conflicts with another flight's
//! instantaneous stay `[x, x]`, although both hover seconds only touch it at an end.)

pub mod metric;
pub mod multileg;

use muse_model::{
    Airspace, EdgeId, EdgeKind, EdgeRule, FlightParams, Instant, Millis, NodeId, Plan,
    RejectReason, Request, Stay,
};

/// Closure windows `[start, end)` in ms, per node and per edge index, as the zones give them.
#[derive(Clone, Debug, Default)]
pub struct RawClosures {
    /// Per node.
    pub nodes: Vec<Vec<(i64, i64)>>,
    /// Per edge.
    pub edges: Vec<Vec<(i64, i64)>>,
}

/// What the oracle finds for a request.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Answer {
    /// Earliest landing and the latest take-off achieving it, or the rejection reason.
    pub result: Result<(Instant, Instant), RejectReason>,
    /// Free-flow time, if the destination is reachable.
    pub free_flow: Option<Millis>,
    /// An optimal plan (for self-checks), when there is one.
    pub plan: Option<Plan>,
}

/// Shortest airborne time from `from` to `to` on the empty graph (Bellman-Ford).
pub fn free_flow(
    airspace: &Airspace,
    params: &FlightParams,
    from: NodeId,
    to: NodeId,
) -> Option<Millis> {
    let mut dist = vec![i64::MAX; airspace.node_count()];
    dist[from.index()] = 0;
    for _ in 0..airspace.node_count() {
        let mut changed = false;
        for i in 0..airspace.edge_count() {
            let w = weight(airspace, params, EdgeId(i as u32));
            for (x, y) in ends(airspace, EdgeId(i as u32)) {
                if dist[x.index()] != i64::MAX && dist[x.index()] + w < dist[y.index()] {
                    dist[y.index()] = dist[x.index()] + w;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    (dist[to.index()] != i64::MAX).then_some(Millis(dist[to.index()]))
}

/// Traversal time of edge `e`, ms, straight from the reference: a corridor's at cruise speed
/// (docs/reference.md#flight-model-and-separation), a vertical link's `ceil(Δ_mm · 1000 /
/// c_mm_per_s)` (#layered-airspace).
pub fn weight(airspace: &Airspace, params: &FlightParams, e: EdgeId) -> i64 {
    match (airspace.edge_kind(e), airspace.layers()) {
        (EdgeKind::Vertical { .. }, Some(l)) => {
            let (um, rate) = (l.spacing.um(), i64::from(l.climb_mm_per_s));
            (um + rate - 1) / rate
        }
        _ => params.speed.traversal_time(airspace.edge(e).length_m).0,
    }
}

/// The directions edge `e` may be flown in, as `(from, to)`: a one-way corridor only from
/// its `from` end (docs/reference.md#layered-airspace heading rule).
pub fn ends(airspace: &Airspace, e: EdgeId) -> Vec<(NodeId, NodeId)> {
    let edge = airspace.edge(e);
    match airspace.edge_kind(e) {
        EdgeKind::Corridor { one_way: true, .. } => vec![(edge.from, edge.to)],
        _ => vec![(edge.from, edge.to), (edge.to, edge.from)],
    }
}

/// The edge rule on `e`: vertical links are exclusive whatever the corridors'
/// (docs/reference.md#layered-airspace).
pub fn rule_of(airspace: &Airspace, params: &FlightParams, e: EdgeId) -> EdgeRule {
    match airspace.edge_kind(e) {
        EdgeKind::Vertical { .. } => EdgeRule::Exclusive,
        EdgeKind::Corridor { .. } => params.edge_rule,
    }
}

/// The other flights' stays per node `(a, d)` and traversals per edge `(s, f, forward)`.
///
/// Other flights may be multi-leg trips (docs/reference.md#multi-leg-trips): every stay of every
/// leg occupies its node (landing and take-off stays included), every traversal within a leg its
/// edge, and the time on the ground between legs nothing.
struct Traffic {
    stays: Vec<Vec<(i64, i64)>>,
    traversals: Vec<Vec<(i64, i64, bool)>>,
}

impl Traffic {
    fn new(airspace: &Airspace, params: &FlightParams, plans: &[&Plan]) -> Self {
        let mut stays = vec![Vec::new(); airspace.node_count()];
        let mut traversals = vec![Vec::new(); airspace.edge_count()];
        for plan in plans {
            for s in &plan.path {
                stays[s.node.index()].push((s.arrive.0, s.depart.0));
            }
            // Traversals within legs only: between a landing and the next take-off (two
            // stays at the same station) the drone is on the ground.
            for (from, to) in plan.hops() {
                let e = airspace
                    .edge_between(from.node, to.node)
                    .expect("plans follow edges");
                let w = weight(airspace, params, e);
                let forward = airspace.edge(e).from == from.node;
                traversals[e.index()].push((from.depart.0, from.depart.0 + w, forward));
            }
        }
        Traffic { stays, traversals }
    }

    fn offsets(&self, unit: i64) -> Vec<i64> {
        let mut o = vec![0, unit - 1];
        for list in &self.stays {
            for &(a, d) in list {
                o.push(a.rem_euclid(unit));
                o.push(d.rem_euclid(unit));
            }
        }
        for list in &self.traversals {
            for &(s, f, _) in list {
                o.push(s.rem_euclid(unit));
                o.push(f.rem_euclid(unit));
            }
        }
        o.sort_unstable();
        o.dedup();
        o
    }
}

/// The latest departure `d` such that a stay `[a, d]` at `v` is allowed (allowed exactly for
/// `d` in `[a, dmax]`), or `None` if even `[a, a]` is not.
fn dmax(v: NodeId, a: i64, tau: i64, traffic: &Traffic, closures: &RawClosures) -> Option<i64> {
    let mut bound = i64::MAX;
    for &(a1, d1) in &traffic.stays[v.index()] {
        // the rule: a >= d1 + tau || a1 >= d + tau.
        if a < d1 + tau {
            bound = bound.min(a1 - tau);
        }
    }
    for &(start, end) in &closures.nodes[v.index()] {
        // the rule: d < start || a >= end.
        if a < end {
            bound = bound.min(start - 1);
        }
    }
    (bound >= a).then_some(bound)
}

/// Whether the traversal of `edge` entering at `start` (in direction `forward`) is allowed.
fn traversal_ok(
    edge: EdgeId,
    forward: bool,
    start: i64,
    weight: i64,
    rule: EdgeRule,
    traffic: &Traffic,
    closures: &RawClosures,
) -> bool {
    let finish = start + weight;
    for &(s1, f1, forward1) in &traffic.traversals[edge.index()] {
        let ok = match rule {
            // the rule: same direction under headway: |s2 - s1| >= h.
            EdgeRule::Headway(h) if forward == forward1 => (start - s1).abs() >= h.0,
            // the rule: s2 >= f1 || s1 >= f2.
            _ => start >= f1 || s1 >= finish,
        };
        if !ok {
            return false;
        }
    }
    // the rule: f < start || s >= end.
    closures.edges[edge.index()]
        .iter()
        .all(|&(from, to)| finish < from || start >= to)
}

/// The time grid: whole units from the departure, each with the offsets `O`.
struct Grid {
    base: i64,
    unit: i64,
    offsets: Vec<i64>,
}

impl Grid {
    fn time(&self, i: usize) -> i64 {
        let per_unit = self.offsets.len();
        self.base + (i / per_unit) as i64 * self.unit + self.offsets[i % per_unit]
    }

    /// The last index whose time is `<= t` (`t >= base`).
    fn floor(&self, t: i64) -> usize {
        let rel = t - self.base;
        let units = rel.div_euclid(self.unit) as usize;
        let rest = rel.rem_euclid(self.unit);
        units * self.offsets.len() + self.offsets.partition_point(|&o| o <= rest) - 1
    }
}

const NONE: i64 = i64::MIN;

/// How a drone came to arrive somewhere: from a stay at `node` that began at grid index
/// `arrived` and left at grid index `left`; `None` for the take-off.
#[derive(Clone, Copy)]
struct Pred {
    node: u32,
    arrived: u32,
    left: u32,
}

/// Plans `request` optimally against `others` and `closures`, or says why it cannot.
///
/// Requires parameters, departure, traversal times and closure windows in whole multiples of
/// `unit` ms (1000: whole seconds).
pub fn solve(
    airspace: &Airspace,
    params: &FlightParams,
    closures: &RawClosures,
    others: &[&Plan],
    request: &Request,
    unit: i64,
) -> Answer {
    assert!(unit > 0);
    let whole = |ms: i64| ms % unit == 0;
    assert!(
        whole(params.node_separation.0)
            && whole(params.max_flight.0)
            && whole(params.max_ground_delay.0)
    );
    if let EdgeRule::Headway(h) = params.edge_rule {
        assert!(whole(h.0));
    }
    assert!(whole(request.departure.0));
    let weights: Vec<i64> = (0..airspace.edge_count())
        .map(|i| weight(airspace, params, EdgeId(i as u32)))
        .collect();
    assert!(weights.iter().all(|&w| w > 0 && whole(w)));
    let windows = closures.nodes.iter().chain(&closures.edges).flatten();
    assert!(windows.clone().all(|&(from, to)| whole(from) && whole(to)));

    let free = free_flow(airspace, params, request.origin, request.destination);
    let reject = |reason| Answer {
        result: Err(reason),
        free_flow: free,
        plan: None,
    };
    let Some(ff) = free else {
        return reject(RejectReason::Unreachable);
    };
    if ff > params.max_flight {
        return reject(RejectReason::OutOfRange);
    }
    let traffic = Traffic::new(airspace, params, others);
    let search = Search {
        airspace,
        params,
        closures,
        grid: Grid {
            base: request.departure.0,
            unit,
            offsets: traffic.offsets(unit),
        },
        traffic,
        weights,
        from: From::Ground {
            origin: request.origin,
            earliest: request.departure.0,
            latest: request.departure.0 + params.max_ground_delay.0,
        },
        goal: Goal::Node(request.destination),
    };
    match search.run() {
        Some(plan) => Answer {
            result: Ok((plan.takeoff(), plan.landing())),
            free_flow: free,
            plan: Some(plan),
        },
        None => reject(RejectReason::NoFeasiblePlan),
    }
}

/// Where a search starts: on the ground (take-off window) or in the air at a node.
#[derive(Clone, Copy, Debug)]
enum From {
    Ground {
        origin: NodeId,
        earliest: i64,
        latest: i64,
    },
    Air {
        node: NodeId,
        at: i64,
        takeoff: i64,
    },
}

/// Where a search may end: one station, or any station (the lowest index among the earliest).
#[derive(Clone, Copy, Debug)]
pub enum Goal {
    /// This node.
    Node(NodeId),
    /// Any station.
    AnyStation,
}

/// Plans the rest of a flight in the air (docs/reference.md#zones-announced-during-the-day): it
/// arrives at `node` at `at` (any millisecond), took off at `takeoff`, and must land at `goal`
/// within `T_max` of take-off: the plan with the earliest landing (any station: the lowest node
/// index among the earliest), starting with the stay at `node`, or `None`.
///
/// The grid argument holds with `at`'s offset added: it is a lower bound (the stay at `node`
/// begins then), and the battery is an upper bound, which only decides feasibility.
#[allow(clippy::too_many_arguments)]
pub fn solve_airborne(
    airspace: &Airspace,
    params: &FlightParams,
    closures: &RawClosures,
    others: &[&Plan],
    node: NodeId,
    at: Instant,
    takeoff: Instant,
    goal: Goal,
    unit: i64,
) -> Option<Plan> {
    let weights: Vec<i64> = (0..airspace.edge_count())
        .map(|i| weight(airspace, params, EdgeId(i as u32)))
        .collect();
    assert!(weights.iter().all(|&w| w > 0 && w % unit == 0));
    let traffic = Traffic::new(airspace, params, others);
    let mut offsets = traffic.offsets(unit);
    offsets.push(at.0.rem_euclid(unit));
    offsets.sort_unstable();
    offsets.dedup();
    let search = Search {
        airspace,
        params,
        closures,
        grid: Grid {
            base: at.0 - at.0.rem_euclid(unit),
            unit,
            offsets,
        },
        traffic,
        weights,
        from: From::Air {
            node,
            at: at.0,
            takeoff: takeoff.0,
        },
        goal,
    };
    search.run()
}

/// One search: everything fixed for a request.
struct Search<'a> {
    airspace: &'a Airspace,
    params: &'a FlightParams,
    closures: &'a RawClosures,
    grid: Grid,
    traffic: Traffic,
    weights: Vec<i64>,
    from: From,
    goal: Goal,
}

impl Search<'_> {
    /// The origin and the grid indices of the first and last take-off (none in the air).
    fn takeoffs(&self) -> (Option<NodeId>, usize, usize) {
        let grid = &self.grid;
        match self.from {
            From::Ground {
                origin,
                earliest,
                latest,
            } => (
                Some(origin),
                grid.floor(earliest) + usize::from(grid.time(grid.floor(earliest)) < earliest),
                grid.floor(latest),
            ),
            From::Air { .. } => (None, 1, 0),
        }
    }

    /// An optimal plan, if any.
    fn run(&self) -> Option<Plan> {
        let grid = &self.grid;
        let per_unit = grid.offsets.len();
        let unit = grid.unit;
        let t_max = self.params.max_flight.0;
        // Every instant of a plan lies in [base, latest take-off + T_max].
        let end = match self.from {
            From::Ground { latest, .. } => latest + t_max,
            From::Air { takeoff, .. } => takeoff + t_max,
        };
        let points = ((end - grid.base).max(0) / unit) as usize * per_unit + per_unit;
        let nodes = self.airspace.node_count();
        // Arrivals: latest take-off reaching (node, index), and how.
        let mut arrival = vec![NONE; nodes * points];
        let mut pred: Vec<Option<Pred>> = vec![None; nodes * points];
        // Stays in progress per node: (take-off, arrival index, last allowed departure index).
        let mut active: Vec<Vec<(i64, usize, usize)>> = vec![Vec::new(); nodes];
        // Take-offs: indices [first_takeoff, last_takeoff] at the origin.
        let (origin, first_takeoff, last_takeoff) = self.takeoffs();
        // The last index with an arrival scheduled.
        let mut pending = 0;
        if let From::Air { node, at, takeoff } = self.from {
            let i = grid.floor(at);
            assert_eq!(grid.time(i), at, "`at` is on the grid");
            arrival[node.index() * points + i] = takeoff;
            pending = i;
        }

        for i in 0..points {
            let now = grid.time(i);
            if let Some(origin) = origin
                && (first_takeoff..=last_takeoff).contains(&i)
            {
                let at = origin.index() * points + i;
                if arrival[at] < now {
                    arrival[at] = now;
                    pred[at] = None;
                }
            }
            // Arrivals at `now` are final: every edge takes at least a unit.
            for (v, stays) in active.iter_mut().enumerate() {
                let takeoff = arrival[v * points + i];
                if takeoff == NONE || now - takeoff > t_max {
                    continue;
                }
                let node = NodeId(v as u32);
                let tau = self.params.node_separation.0;
                let Some(last) = dmax(node, now, tau, &self.traffic, self.closures) else {
                    continue;
                };
                let done = match self.goal {
                    Goal::Node(d) => node == d,
                    Goal::AnyStation => self.airspace.is_station(node),
                };
                if done {
                    return Some(rebuild(grid, &pred, points, node, i));
                }
                let until = if last >= grid.time(points - 1) {
                    points - 1
                } else {
                    grid.floor(last)
                };
                stays.push((takeoff, i, until));
            }
            let mut alive = origin.is_some() && i < last_takeoff;
            for (v, stays) in active.iter_mut().enumerate() {
                stays.retain(|&(takeoff, _, until)| until >= i && now - takeoff <= t_max);
                let Some(&(takeoff, arrived, _)) = stays.iter().max_by_key(|x| x.0) else {
                    continue;
                };
                alive = true;
                let node = NodeId(v as u32);
                for adj in self.airspace.neighbours(node) {
                    let weight = self.weights[adj.edge.index()];
                    let to = i + (weight / unit) as usize * per_unit;
                    if to >= points || grid.time(to) - takeoff > t_max {
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
                    let at = adj.node.index() * points + to;
                    if arrival[at] < takeoff {
                        arrival[at] = takeoff;
                        pred[at] = Some(Pred {
                            node: v as u32,
                            arrived: arrived as u32,
                            left: i as u32,
                        });
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
}

/// The plan ending with an arrival at `node` at grid index `i`.
fn rebuild(grid: &Grid, pred: &[Option<Pred>], points: usize, node: NodeId, i: usize) -> Plan {
    let mut path = vec![Stay {
        node,
        arrive: Instant(grid.time(i)),
        depart: Instant(grid.time(i)),
    }];
    let mut at = (node.index(), i);
    while let Some(p) = pred[at.0 * points + at.1] {
        path.push(Stay {
            node: NodeId(p.node),
            arrive: Instant(grid.time(p.arrived as usize)),
            depart: Instant(grid.time(p.left as usize)),
        });
        at = (p.node as usize, p.arrived as usize);
    }
    path.reverse();
    Plan { path }
}
