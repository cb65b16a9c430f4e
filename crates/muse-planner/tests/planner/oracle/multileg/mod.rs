//! Multi-leg trips (docs/reference.md#multi-leg-trips: battery swaps at stations) by brute force
//! (tests only).
//!
//! Like the single-leg oracle in the parent module, this one shares nothing with the planner:
//! separation and zones are checked pairwise against the other flights' plans and the raw zone
//! windows ([`dmax`], [`traversal_ok`]), on the same time grid ([`Grid`]).
//!
//! # The rules, as read here
//!
//! A trip is a sequence of legs. Each leg takes off at a station and lands (an instantaneous
//! last stay) at a *different* station, so it traverses at least one edge, and lasts at most
//! `T_max` from take-off to landing. Leg 1 takes off at the request's origin in
//! `[departure, departure + G_max]`; leg `i + 1` takes off where leg `i` landed, at any instant
//! `>= landing_i + S` (no upper bound: waiting on the ground is unlimited). At most `K` legs
//! when `K` is set. The trip ends with its first landing at the destination (landing there
//! and flying on is never better: it lands later). The node, edge and zone rules apply to every
//! stay (landing and take-off stays included) and every traversal of every leg; between legs
//! the drone is on the ground, outside the airspace, and nothing applies. Optimality: earliest
//! final landing, then latest first take-off, then fewest legs.
//!
//! # Why the grid stays exact with swaps
//!
//! Fix everything discrete: the route of every leg (so the number of legs and the swap
//! stations) and the side of every separation and zone disjunction. What is left is the same
//! kind of system as for one leg (see the parent module): difference constraints with
//! whole-unit constants (`w`, `tau`, `h`, hover `>= 0`, and per leg `landing_i - takeoff_i <=
//! T_max`) plus single-time bounds taken from the other flights, the zone windows and the
//! take-off window. A swap adds exactly one constraint, `takeoff_{i+1} - landing_i >= S`:
//! another difference constraint, with `S` a whole number of units. Nothing bounds the ground
//! time from above, and no rule at all links the landing stay and the next take-off stay
//! otherwise. Such a system's solution set is closed under componentwise minimum and maximum,
//! so the least solution (every time = one lower bound + whole units) has the earliest final
//! landing `L`, and with `landing <= L` added the greatest solution (every time = one upper
//! bound, or `L`, + whole units; it exists since every time is `<= L`) has the latest first
//! take-off with that landing. Hence for every route with a given number of legs that achieves
//! the optimal (landing, first take-off), there is such a plan on the grid `{k u + o}` of the
//! parent module, and the fewest legs among them is found on the grid too.
//!
//! # A finite horizon despite unlimited ground waiting
//!
//! Let `E` be the last *event*: the largest of the start's last instant (`departure + G_max`
//! for a request, `at` when resuming), `d1 + tau` over the other flights' stays, `f1` and (under
//! headway) `s1 + h` over their traversals, and the end of every zone window. A stay `[a, d]`
//! with `a >= E` satisfies the node rule (`a >= d1 + tau`) and the zone rule (`a >= end`) against
//! everything; a traversal entered at `s >= E` satisfies the edge rules (`s >= f1`,
//! `s - s1 >= h`) and the zone rule (`s >= end`). So a leg that takes off at `E` or later is
//! never blocked. Let `C_m(Y)` be the least free-flow chain time from station `Y` to the
//! destination with at most `m` legs: `sum of the legs' shortest empty-graph times + S ×
//! (legs − 1)`, every leg joining two distinct stations within `T_max`; and `F` the largest
//! finite `C_m(Y)` over all stations and `m` (a least chain never lands twice at one station
//! — cutting the loop leaves a valid, no longer chain — so `m` up to the number of stations
//! minus one covers every `m`).
//!
//! **Claim:** if any trip exists, one lands by `H = E + T_max + S + F`; then the optimum lands
//! by `H` and all its instants are `<= H`, so searching the grid up to `H` is exact.
//! *Proof.* Take any trip `P` and its first leg `j` that takes off at or after `E` (for a
//! resumed trip, count from the first leg after the one in the air). If there is none, every
//! leg took off before `E` (or is the leg in the air, which took off by `at <= E`) and `P`
//! lands by `E + T_max`. If it is leg 1 of a request, then `E >= departure + G_max >=
//! takeoff_1`, so `takeoff_1 = E` and `P` is never blocked: flying instead a least chain from
//! the origin (it exists: `P` itself is one, each leg's shortest time being at most its
//! duration) from `takeoff_1` lands by `E + F`. Otherwise keep `P`'s legs before `j`: leg
//! `j − 1` took off before `E` (or is the leg that was in the air) and landed at some station
//! `Y` by `E + T_max`. `P`'s legs from `j` on are a chain from `Y` with the legs left, so a
//! least such chain exists; take off at `max(landing_{j−1} + S, E) <= E + T_max + S` and fly it
//! unobstructed: landing by `E + T_max + S + F`. (If `Y` is the destination, `P` could simply
//! have ended there.) ∎
//!
//! Besides, a drone on the ground with `n` legs flown at a station `Y` where `C_{K−n}(Y)` is
//! infinite can never reach the destination (each leg lasts at least its shortest time); such
//! swaps are not kept. So whenever the search holds a drone on the ground, some trip exists
//! and the search stops at the optimum, by `H`.
//!
//! # The search
//!
//! A sweep over grid instants, like the parent module's, with Pareto sets instead of one value:
//!
//! - **Airborne labels** at `(node, arrival instant)`: the current leg's take-off, the first
//!   take-off, the legs begun, and the current leg's take-off station (it may not land there).
//!   A label *covers* another at the same place and time when it has the same leg station, a
//!   leg take-off and a first take-off no earlier, and no more legs: every continuation of the
//!   other is open to it (the battery binds later, fewer legs leave more of `K`) and ends no
//!   worse (same landing, first take-off no earlier, legs no more). Covered labels are dropped.
//! - **Stays**: an arrival `a` at `v` whose stay is allowed opens a stay that may end at any
//!   grid instant in `[a, dmax(a)]` (the parent module's exact whole-stay test); from it the
//!   drone may leave along every edge whose traversal is allowed. A stay is dropped when
//!   another, open at least as long, covers it.
//! - **Landings**: an arrival at a station other than its leg's take-off station whose
//!   instantaneous stay is allowed may land. At the destination that ends the trip: the first
//!   instant with such a landing is the earliest landing, and among its labels the latest
//!   first take-off, then the fewest legs, wins. Elsewhere (if swaps are on, fewer than `K`
//!   legs were flown and a free-flow chain of the legs left exists) it becomes a **ground
//!   label** at the station: ready at `landing + S`, first take-off, legs, kept Pareto-minimal.
//!   A ready ground label takes off at every grid instant from then on (a take-off stay, the
//!   next leg, with this station as its take-off station).

use muse_model::{
    Airspace, EdgeRule, FlightParams, Instant, Millis, NodeId, Plan, RejectReason, Request,
};

use super::{Goal, Grid, RawClosures, Traffic, free_flow};

mod search;

use search::{Search, Start};

/// The key figures of an optimal trip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Trip {
    /// The final landing (at the destination).
    pub landing: Instant,
    /// The first leg's take-off.
    pub first_takeoff: Instant,
    /// The number of legs.
    pub legs: u32,
}

/// What the oracle finds for a request, battery swaps allowed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Answer {
    /// The optimal trip's landing, first take-off and legs, or the rejection reason.
    pub result: Result<Trip, RejectReason>,
    /// Free-flow time (module docs of [`free_flow_time`]), if the destination is reachable.
    pub free_flow: Option<Millis>,
    /// An optimal plan (for self-checks), when there is one.
    pub plan: Option<Plan>,
}

/// The swap time `S` and the leg limit `K` of `params`: `(0, 1)` without swaps (single legs).
fn swap_of(params: &FlightParams) -> (i64, u32) {
    params
        .battery_swap
        .map_or((0, 1), |s| (s.time.0, s.leg_limit()))
}

/// Free-flow chains of legs towards one destination.
struct Chains {
    /// `cost[m][y]`: the least `sum of legs' shortest times + S × (legs − 1)` over chains of
    /// at most `m` legs from station `y` to the destination, each leg joining two distinct
    /// stations with a shortest time within `T_max` (`None`: no such chain; never for the
    /// destination itself). Row 0 is all `None`; the last row serves every larger `m`.
    cost: Vec<Vec<Option<i64>>>,
}

impl Chains {
    fn new(airspace: &Airspace, params: &FlightParams, destination: NodeId) -> Self {
        let (swap, legs) = swap_of(params);
        let n = airspace.node_count();
        let stations: Vec<NodeId> = airspace.stations().collect();
        let leg: Vec<Vec<Option<i64>>> = (0..n)
            .map(|y| {
                (0..n)
                    .map(|z| {
                        let (y, z) = (NodeId(y as u32), NodeId(z as u32));
                        let both = airspace.is_station(y) && airspace.is_station(z) && y != z;
                        both.then(|| free_flow(airspace, params, y, z))
                            .flatten()
                            .map(|t| t.0)
                            .filter(|&t| t <= params.max_flight.0)
                    })
                    .collect()
            })
            .collect();
        // A least chain never lands twice at one station: at most `stations − 1` legs.
        let cap = (legs as usize).min(stations.len().saturating_sub(1)).max(1);
        let mut cost = vec![vec![None; n]];
        for m in 1..=cap {
            let prev = &cost[m - 1];
            let row = (0..n)
                .map(|y| {
                    let yid = NodeId(y as u32);
                    if !airspace.is_station(yid) || yid == destination {
                        return None;
                    }
                    let direct = leg[y][destination.index()];
                    let via = stations
                        .iter()
                        .filter(|&&z| z != yid && z != destination)
                        .filter_map(|&z| Some(leg[y][z.index()]? + swap + prev[z.index()]?))
                        .min();
                    direct.into_iter().chain(via).min()
                })
                .collect();
            cost.push(row);
        }
        Chains { cost }
    }

    /// The least chain time from `y` with at most `m` legs.
    fn within(&self, y: NodeId, m: u32) -> Option<i64> {
        let m = (m as usize).min(self.cost.len() - 1);
        self.cost[m][y.index()]
    }

    /// `F`: the largest finite chain time from any station with any number of legs.
    fn worst(&self) -> i64 {
        self.cost
            .iter()
            .flatten()
            .flatten()
            .copied()
            .max()
            .unwrap_or(0)
    }
}

/// The free-flow time of docs/reference.md#multi-leg-trips from `origin` to `destination`: the
/// least chain time with at most `K` legs (single legs without swaps) when a chain exists (the
/// direct shortest time whenever that is within `T_max`); otherwise the plain shortest time,
/// battery ignored; `None` if unreachable.
pub fn free_flow_time(
    airspace: &Airspace,
    params: &FlightParams,
    origin: NodeId,
    destination: NodeId,
) -> Option<Millis> {
    let (_, legs) = swap_of(params);
    Chains::new(airspace, params, destination)
        .within(origin, legs)
        .map(Millis)
        .or_else(|| free_flow(airspace, params, origin, destination))
}

/// `E`: the last instant at which anything can block (module docs): nothing restricts a stay
/// that begins, or a traversal entered, at `E` or later.
fn last_event(params: &FlightParams, traffic: &Traffic, closures: &RawClosures, start: i64) -> i64 {
    let tau = params.node_separation.0;
    let h = match params.edge_rule {
        EdgeRule::Headway(h) => h.0,
        EdgeRule::Exclusive => 0,
    };
    let stays = traffic.stays.iter().flatten().map(|&(_, d)| d + tau);
    let traversals = traffic
        .traversals
        .iter()
        .flatten()
        .map(|&(s, f, _)| f.max(s + h));
    let windows = closures
        .nodes
        .iter()
        .chain(&closures.edges)
        .flatten()
        .map(|&(_, end)| end);
    stays.chain(traversals).chain(windows).fold(start, i64::max)
}

/// Plans `request` optimally with battery swaps (`params.battery_swap`; without them, single
/// legs exactly as [`super::solve`]) against `others` and `closures`, or says why it cannot.
///
/// Requires parameters (`S` included), departure, traversal times and closure windows in
/// whole multiples of `unit` ms.
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
    let (swap, legs) = swap_of(params);
    assert!(
        whole(params.node_separation.0)
            && whole(params.max_flight.0)
            && whole(params.max_ground_delay.0)
            && whole(swap)
            && swap >= 0
            && legs >= 1
    );
    if let EdgeRule::Headway(h) = params.edge_rule {
        assert!(whole(h.0));
    }
    assert!(whole(request.departure.0));
    let windows = closures.nodes.iter().chain(&closures.edges).flatten();
    assert!(windows.clone().all(|&(from, to)| whole(from) && whole(to)));

    let plain = free_flow(airspace, params, request.origin, request.destination);
    let chains = Chains::new(airspace, params, request.destination);
    let chain = chains.within(request.origin, legs);
    let free = chain.map(Millis).or(plain);
    let reject = |reason| Answer {
        result: Err(reason),
        free_flow: free,
        plan: None,
    };
    if plain.is_none() {
        return reject(RejectReason::Unreachable);
    }
    if chain.is_none() {
        return reject(RejectReason::OutOfRange);
    }
    let traffic = Traffic::new(airspace, params, others);
    let offsets = traffic.offsets(unit);
    let latest = request.departure.0 + params.max_ground_delay.0;
    let start = Start::Request {
        origin: request.origin,
        earliest: request.departure.0,
        latest,
    };
    let search = Search::new(
        airspace,
        params,
        closures,
        traffic,
        Grid {
            base: request.departure.0,
            unit,
            offsets,
        },
        start,
        latest,
        Goal::Node(request.destination),
        Some(chains),
    );
    match search.run() {
        Some((trip, plan)) => Answer {
            result: Ok(trip),
            free_flow: free,
            plan: Some(plan),
        },
        None => reject(RejectReason::NoFeasiblePlan),
    }
}

/// Where a resumed trip ([`resume`]) is.
#[derive(Clone, Copy, Debug)]
pub enum Resume {
    /// In the air: arriving at `node` at `at` (any millisecond), on a leg that took off at
    /// `leg_takeoff` from `leg_station` (the leg may not land there; `None`: no such
    /// restriction, e.g. a diversion may return to its origin).
    Air {
        /// Where.
        node: NodeId,
        /// Arrival there.
        at: Instant,
        /// The current leg's take-off.
        leg_takeoff: Instant,
        /// The current leg's take-off station, if landing there is forbidden.
        leg_station: Option<NodeId>,
    },
    /// On the ground at `station`, free to take off at `at` (any millisecond) or later: the
    /// next leg takes off there (and may not land there).
    Ground {
        /// Where.
        station: NodeId,
        /// The earliest take-off.
        at: Instant,
    },
}

/// Resumes a trip (docs/reference.md#zones-announced-during-the-day replanning with swaps): from
/// `from`, with the first take-off fixed at `first_takeoff` and `legs` legs begun so far (`>= 1`;
/// on the ground, the next take-off begins leg `legs + 1`, so it needs `legs < K`), to `goal`:
///
/// - [`Goal::Node`]: the destination, with further legs if swaps are on (at most `K` in all):
///   the earliest landing, ties to the fewest legs;
/// - [`Goal::AnyStation`]: a single landing at any station (no swaps): the earliest landing,
///   ties to the lowest node index.
///
/// The plan returned starts with the stay at `node` from `at` (in the air) or with the
/// take-off stay at `station` (on the ground); `None` if no trip exists. `legs` in the answer
/// counts every leg, those before included.
///
/// The grid argument holds with `at`'s offset added: `at` is a lower bound; the first and
/// current take-offs are fixed and only give upper bounds that decide feasibility.
#[allow(clippy::too_many_arguments)]
pub fn resume(
    airspace: &Airspace,
    params: &FlightParams,
    closures: &RawClosures,
    others: &[&Plan],
    from: Resume,
    first_takeoff: Instant,
    legs: u32,
    goal: Goal,
    unit: i64,
) -> Option<(Trip, Plan)> {
    assert!(legs >= 1);
    let (swap, _) = swap_of(params);
    let weights_whole = (0..airspace.edge_count())
        .all(|i| super::weight(airspace, params, muse_model::EdgeId(i as u32)) % unit == 0);
    assert!(weights_whole && swap % unit == 0);
    let traffic = Traffic::new(airspace, params, others);
    let (at, start) = match from {
        Resume::Air {
            node,
            at,
            leg_takeoff,
            leg_station,
        } => (
            at.0,
            Start::Air {
                node,
                at: at.0,
                leg_takeoff: leg_takeoff.0,
                leg_station,
                first_takeoff: first_takeoff.0,
                legs,
            },
        ),
        Resume::Ground { station, at } => (
            at.0,
            Start::Ground {
                station,
                at: at.0,
                first_takeoff: first_takeoff.0,
                legs,
            },
        ),
    };
    let mut offsets = traffic.offsets(unit);
    offsets.push(at.rem_euclid(unit));
    offsets.sort_unstable();
    offsets.dedup();
    let chains = match goal {
        Goal::Node(d) => Some(Chains::new(airspace, params, d)),
        Goal::AnyStation => None,
    };
    let search = Search::new(
        airspace,
        params,
        closures,
        traffic,
        Grid {
            base: at - at.rem_euclid(unit),
            unit,
            offsets,
        },
        start,
        at,
        goal,
        chains,
    );
    search.run()
}
