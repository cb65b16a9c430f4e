//! The planner: prepared once for an airspace and parameters, then asked many times.

use std::sync::{Arc, OnceLock};

use muse_airspace::closures::Closures;
use muse_airspace::conflicts::Relation;
use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId, Plan, RejectReason, Request};

use crate::heuristic::Heuristics;
use crate::schedule::{FlightId, Schedule};
use crate::sipp::{Goal, Problem, Remaining, Scratch, Start, Swaps, search};
use crate::time::Unbounded;

/// A prepared planner. Shareable between threads (`&Planner` is `Sync`); each thread brings
/// its own [`Scratch`] and each simulated day its own [`Schedule`].
#[derive(Debug)]
pub struct Planner<'a> {
    airspace: &'a Airspace,
    params: FlightParams,
    heuristics: Heuristics,
    /// Metric separation's conflict relation, worked out at the first schedule that needs it.
    relation: OnceLock<Option<Arc<Relation>>>,
}

/// What the planner says about one request ([`Planner::plan`]) or the rest of a trip
/// ([`Planner::resume`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The plan (earliest landing, then latest take-off) or why there is none.
    pub result: Result<Plan, RejectReason>,
    /// Shortest airborne time on the empty graph, if the destination is reachable (`None`
    /// for the rest of a trip, which has no such reference).
    pub free_flow: Option<Millis>,
    /// Search effort: labels expanded.
    pub expanded: u64,
}

impl<'a> Planner<'a> {
    /// Prepares a planner; heuristic tables are computed lazily, once per destination.
    pub fn new(airspace: &'a Airspace, params: FlightParams) -> Self {
        Planner {
            airspace,
            params,
            heuristics: Heuristics::new(airspace, &params),
            relation: OnceLock::new(),
        }
    }

    /// An empty schedule for this planner's airspace and parameters, with the zone closures
    /// as permanent blocks: [`Schedule::new`], but with metric separation on the conflict
    /// relation is worked out once per planner, not once per schedule.
    pub fn schedule(&self, closures: &Closures) -> Schedule {
        let relation = self.relation.get_or_init(|| {
            self.params
                .separation
                .is_on()
                .then(|| Arc::new(Relation::new(self.airspace, &self.params)))
        });
        Schedule::with_relation(self.airspace, &self.params, closures, relation.clone())
    }

    /// The airspace planned on.
    pub fn airspace(&self) -> &'a Airspace {
        self.airspace
    }

    /// The parameters planned with.
    pub fn params(&self) -> &FlightParams {
        &self.params
    }

    /// Free-flow time from `request.origin` to `request.destination`, if reachable.
    pub fn free_flow(&self, request: &Request) -> Option<Millis> {
        let h = self.heuristics.to(self.airspace, request.destination)[request.origin.index()];
        (h != Millis::INF).then_some(h)
    }

    /// How many ways a request has: the corridors that some flight of it could use within
    /// its battery on the empty airspace, those `(u, v)` with `free_flow(origin, u) + w +
    /// free_flow(v, destination)` no more than `T_max` (with battery swaps, the whole trip's
    /// span) in either direction. `0` when the destination cannot be reached.
    ///
    /// ```
    /// use muse_model::{Airspace, FlightParams, Instant, NodeId, Request};
    /// use muse_planner::Planner;
    /// // A - B - C - D, 1 km each: 2 minutes per corridor.
    /// let air = Airspace::line(&[1_000.0, 1_000.0, 1_000.0]);
    /// let planner = Planner::new(&air, FlightParams::default());
    /// let r = |o, d| Request { id: "r".into(), origin: NodeId(o), destination: NodeId(d),
    ///                          departure: Instant(0), submitted: Instant(0) };
    /// // A → B may go on to C and come back (4 + 2 ≤ 20 minutes) and to D (8 minutes).
    /// assert_eq!(planner.alternatives(&r(0, 1)), 3);
    /// ```
    pub fn alternatives(&self, request: &Request) -> usize {
        let limit = self.params.trip_span() - self.params.max_ground_delay;
        let from = self.heuristics.from(self.airspace, request.origin);
        let to = self.heuristics.to(self.airspace, request.destination);
        let times = self.heuristics.traversal_times();
        self.airspace
            .edges()
            .iter()
            .zip(times)
            .enumerate()
            .filter(|&(i, (e, &w))| {
                let via = |a: NodeId, b: NodeId| {
                    let (x, y) = (from[a.index()], to[b.index()]);
                    x != Millis::INF && y != Millis::INF && x + w + y <= limit
                };
                let one_way = matches!(
                    self.airspace.edge_kind(muse_model::EdgeId(i as u32)),
                    muse_model::EdgeKind::Corridor { one_way: true, .. }
                );
                via(e.from, e.to) || (!one_way && via(e.to, e.from))
            })
            .count()
    }

    /// Plans one request against `schedule` (which it does not change): take-off in
    /// `[departure, departure + G_max]`. With battery swaps (docs/reference.md#multi-leg-trips) the
    /// plan may have several legs ([`Plan::legs`]).
    ///
    /// ```
    /// use muse_airspace::closures::Closures;
    /// use muse_model::{Airspace, BatterySwap, FlightParams, Instant, Millis, NodeId, Request};
    /// use muse_planner::{Planner, Schedule, Scratch};
    /// // A — B — C, 6 km each: 12 minutes per corridor; the battery lasts 20.
    /// let airspace = Airspace::line(&[6_000.0, 6_000.0]);
    /// let r = Request { id: "r".into(), origin: NodeId(0), destination: NodeId(2),
    ///                   departure: Instant(0), submitted: Instant(0) };
    /// let single = Planner::new(&airspace, FlightParams::default());
    /// let schedule = Schedule::new(&airspace, single.params(), &Closures::none(&airspace));
    /// assert!(single.plan(&schedule, &r, &mut Scratch::new()).result.is_err(), "out of range");
    ///
    /// let params = FlightParams {
    ///     battery_swap: Some(BatterySwap::new(Millis::from_mins(5))),
    ///     ..FlightParams::default()
    /// };
    /// let swaps = Planner::new(&airspace, params);
    /// let out = swaps.plan(&schedule, &r, &mut Scratch::new());
    /// let plan = out.result.unwrap();
    /// // Lands at B at 12 min, swaps for 5, lands at C at 29 min.
    /// assert_eq!(plan.leg_count(), 2);
    /// assert_eq!(plan.landing(), Instant(29 * 60_000));
    /// assert_eq!(out.free_flow, Some(Millis::from_mins(29)), "the free-flow trip includes the swap");
    /// ```
    pub fn plan(&self, schedule: &Schedule, request: &Request, scratch: &mut Scratch) -> Outcome {
        let earliest = request.departure;
        self.plan_within(
            schedule,
            request,
            earliest,
            earliest + self.params.max_ground_delay,
            scratch,
        )
    }

    /// Plans one request with take-off anywhere in `[earliest, latest]` instead of the
    /// request's own window: docs/reference.md#zones-announced-during-the-day's replanning of a
    /// flight that has not taken off when a zone is announced at `n` uses `[max(departure, n),
    /// max(departure + G_max, n)]`.
    ///
    /// ```
    /// use muse_airspace::closures::Closures;
    /// use muse_model::{Airspace, FlightParams, Instant, NodeId, Request};
    /// use muse_planner::{Planner, Schedule, Scratch};
    /// let airspace = Airspace::line(&[1_000.0]);
    /// let planner = Planner::new(&airspace, FlightParams::default());
    /// let schedule = Schedule::new(&airspace, planner.params(), &Closures::none(&airspace));
    /// let r = Request { id: "r".into(), origin: NodeId(0), destination: NodeId(1),
    ///                   departure: Instant(0), submitted: Instant(0) };
    /// let out = planner.plan_within(&schedule, &r, Instant(60_000), Instant(60_000), &mut Scratch::new());
    /// assert_eq!(out.result.unwrap().takeoff(), Instant(60_000));
    /// ```
    pub fn plan_within(
        &self,
        schedule: &Schedule,
        request: &Request,
        earliest: Instant,
        latest: Instant,
        scratch: &mut Scratch,
    ) -> Outcome {
        let reject = |reason, free_flow, scratch: &mut Scratch| {
            scratch.expanded = 0;
            Outcome {
                result: Err(reason),
                free_flow,
                expanded: 0,
            }
        };
        let h = self.heuristics.to(self.airspace, request.destination);
        let direct = h[request.origin.index()];
        if direct == Millis::INF {
            return reject(RejectReason::Unreachable, None, scratch);
        }
        let (remaining, free_flow) =
            match self.heuristics.swaps_to(self.airspace, request.destination) {
                None if direct > self.params.max_flight => {
                    return reject(RejectReason::OutOfRange, Some(direct), scratch);
                }
                None => (Remaining::Single(h), direct),
                Some(table) => match table.free_flow(request.origin) {
                    None => {
                        return reject(RejectReason::OutOfRange, Some(direct), scratch);
                    }
                    Some(trip) => (Remaining::Swaps(table), trip),
                },
            };
        let start = Start::Ground {
            origin: request.origin,
            earliest,
            latest,
        };
        let mut problem = self.problem(remaining, request.origin, 1);
        if let Some(m) = self.params.max_trip {
            problem.deadline = request.departure + m;
        }
        let result = search(
            problem,
            schedule,
            start,
            Goal::Node(request.destination),
            scratch,
        )
        .ok_or(RejectReason::NoFeasiblePlan);
        Outcome {
            result,
            free_flow: Some(free_flow),
            expanded: scratch.expanded,
        }
    }

    /// Plans the rest of a trip that has begun (docs/reference.md#zones-announced-during-the-day
    /// with #multi-leg-trips): from the air at `from.node` (the current leg took off at
    /// `from.airborne_since`) or from the ground at station `from.node` between legs (free to take
    /// off from `from.at`). With `Landing::At(d)` and battery swaps on, the rest may land and swap
    /// on the way: the earliest landing at `d`, then the fewest legs. With `Landing::AnyStation`, a
    /// single landing at whichever station is earliest (ties to the lowest node index); from the
    /// ground that is no flight at all. The plan returned starts with the stay at `from.node` (in
    /// the air) or with the next take-off (on the ground). A delivery deadline
    /// ([`FlightParams::max_trip`]) binds the landing at `d`, not a diversion. When no plan exists
    /// the result is [`RejectReason::NoFeasiblePlan`]; the outcome's `free_flow` is `None`.
    ///
    /// ```
    /// use muse_airspace::closures::Closures;
    /// use muse_model::{Airspace, Edge, FlightParams, Instant, LonLat, Node, NodeId, NodeKind};
    /// use muse_planner::{Landing, Planner, Resume, Schedule, Scratch};
    /// let node = |id: &str, kind, lon| Node {
    ///     id: id.into(), kind, name: String::new(), pos: LonLat::new(lon, 1.3),
    /// };
    /// let airspace = Airspace::new(
    ///     vec![node("A", NodeKind::Station, 103.80), node("W", NodeKind::Waypoint, 103.81),
    ///          node("B", NodeKind::Station, 103.82)],
    ///     vec![Edge { id: "A-W".into(), from: NodeId(0), to: NodeId(1), length_m: 1_000.0 },
    ///          Edge { id: "W-B".into(), from: NodeId(1), to: NodeId(2), length_m: 2_000.0 }],
    /// ).unwrap();
    /// let planner = Planner::new(&airspace, FlightParams::default());
    /// let schedule = Schedule::new(&airspace, planner.params(), &Closures::none(&airspace));
    /// // At waypoint W 2 minutes after take-off from A: back to A is the nearest landing.
    /// let from = Resume { leg_origin: NodeId(0), departure: Instant(0), node: NodeId(1),
    ///                     at: Instant(120_000), airborne_since: Some(Instant(0)),
    ///                     first_takeoff: Instant(0), legs: 1 };
    /// let rest = planner.resume(&schedule, &from, Landing::AnyStation, &mut Scratch::new());
    /// let rest = rest.result.unwrap();
    /// assert_eq!((rest.path.last().unwrap().node, rest.landing()), (NodeId(0), Instant(240_000)));
    /// ```
    ///
    /// With battery swaps, from the ground between legs:
    ///
    /// ```
    /// use muse_airspace::closures::Closures;
    /// use muse_model::{Airspace, BatterySwap, FlightParams, Instant, Millis, NodeId};
    /// use muse_planner::{Landing, Planner, Resume, Schedule, Scratch};
    /// // A — B — C, 6 km each: 12 minutes per corridor, more than one battery for two.
    /// let airspace = Airspace::line(&[6_000.0, 6_000.0]);
    /// let params = FlightParams {
    ///     battery_swap: Some(BatterySwap::new(Millis::from_mins(5))),
    ///     ..FlightParams::default()
    /// };
    /// let planner = Planner::new(&airspace, params);
    /// let schedule = Schedule::new(&airspace, planner.params(), &Closures::none(&airspace));
    /// // On the ground at B after the first leg, which landed at 12 min; ready at 17 min.
    /// let from = Resume { leg_origin: NodeId(1), departure: Instant(0), node: NodeId(1),
    ///                     at: Instant(1_020_000), airborne_since: None,
    ///                     first_takeoff: Instant(0), legs: 1 };
    /// let rest = planner.resume(&schedule, &from, Landing::At(NodeId(2)), &mut Scratch::new());
    /// let rest = rest.result.unwrap();
    /// assert_eq!((rest.takeoff(), rest.landing()), (Instant(1_020_000), Instant(1_740_000)));
    /// ```
    pub fn resume(
        &self,
        schedule: &Schedule,
        from: &Resume,
        to: Landing,
        scratch: &mut Scratch,
    ) -> Outcome {
        scratch.expanded = 0;
        let (remaining, goal, swaps) = match to {
            Landing::At(d) => match self.heuristics.swaps_to(self.airspace, d) {
                Some(table) => (Remaining::Swaps(table), Goal::Node(d), true),
                None => (
                    Remaining::Single(self.heuristics.to(self.airspace, d)),
                    Goal::Node(d),
                    false,
                ),
            },
            Landing::AnyStation => (
                Remaining::Single(self.heuristics.to_any_station(self.airspace)),
                Goal::AnyStation,
                false,
            ),
        };
        let start = match from.airborne_since {
            Some(takeoff) => Start::Airborne {
                node: from.node,
                at: from.at,
                takeoff,
                first: from.first_takeoff,
                legs: from.legs,
            },
            None if swaps => Start::Landed {
                node: from.node,
                at: from.at,
                first: from.first_takeoff,
                legs: from.legs,
            },
            None => {
                return Outcome {
                    result: Err(RejectReason::NoFeasiblePlan),
                    free_flow: None,
                    expanded: 0,
                };
            }
        };
        // The leg the search starts with (in the air: the current one; on the ground: the
        // next) may not land where it took off.
        let leg = from.legs + u32::from(from.airborne_since.is_none());
        let mut problem = self.problem(remaining, from.leg_origin, leg);
        if !swaps {
            problem.swaps = None;
        }
        if let (Goal::Node(_), Some(m)) = (goal, self.params.max_trip) {
            problem.deadline = from.departure + m;
        }
        let plan = search(problem, schedule, start, goal, scratch);
        Outcome {
            result: plan.ok_or(RejectReason::NoFeasiblePlan),
            free_flow: None,
            expanded: scratch.expanded,
        }
    }

    fn problem<'h>(
        &'h self,
        remaining: Remaining<'h>,
        no_return: NodeId,
        no_return_legs: u32,
    ) -> Problem<'h> {
        Problem {
            airspace: self.airspace,
            params: &self.params,
            remaining,
            swaps: self.params.battery_swap.map(|s| Swaps {
                time: s.time,
                max_legs: s.leg_limit(),
                no_return,
                no_return_legs,
            }),
            deadline: Instant::INF,
        }
    }
}

/// Where a trip that has begun resumes ([`Planner::resume`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resume {
    /// Where the current leg took off (in the air), or `node` (on the ground): a leg may not
    /// land where it took off.
    pub leg_origin: NodeId,
    /// The trip's requested departure (a delivery deadline counts from it).
    pub departure: Instant,
    /// Where the drone is: the node it reaches in the air, or the station it is on the ground
    /// at.
    pub node: NodeId,
    /// When it reaches `node` (in the air), or from when it may take off (on the ground).
    pub at: Instant,
    /// In the air: when the current leg took off; `None` on the ground between legs.
    pub airborne_since: Option<Instant>,
    /// When the trip first took off.
    pub first_takeoff: Instant,
    /// Legs begun so far (the current one included when in the air).
    pub legs: u32,
}

/// Where a trip that has begun must land ([`Planner::resume`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Landing {
    /// At this station (its destination).
    At(NodeId),
    /// At whichever station it can land earliest (a diversion).
    AnyStation,
}

/// Plans `request` against `schedule` and, if a plan exists, adds it as `flight`: the one
/// step of first-come-first-served planning that the batch day ([`plan_day`]) and the online
/// service ([`Live`](crate::Live)) share.
pub fn plan_and_book(
    planner: &Planner<'_>,
    schedule: &mut Schedule,
    flight: FlightId,
    request: &Request,
    scratch: &mut Scratch,
) -> Outcome {
    let outcome = planner.plan(schedule, request, scratch);
    if let Ok(plan) = &outcome.result {
        schedule.insert(planner.airspace(), flight, plan);
    }
    outcome
}

/// Plans `requests` in the given order (callers sort them into planning order
/// `(submitted, id)` first, docs/reference.md#requests), adding each accepted plan to `schedule`
/// before the next (first come, first served). The flight id of request `i` is `i`. Each request's
/// submission instant becomes the schedule's horizon ([`Schedule::set_horizon`]): a request is
/// planned at or after it is submitted and never asks about instants before its departure, which is
/// no earlier, so in submission order the searches only look at current traffic. Calls `progress`
/// after each request.
pub fn plan_day(
    planner: &Planner<'_>,
    schedule: &mut Schedule,
    requests: &[Request],
    scratch: &mut Scratch,
    mut progress: impl FnMut(usize),
) -> Vec<Outcome> {
    let mut out = Vec::with_capacity(requests.len());
    for (i, request) in requests.iter().enumerate() {
        schedule.set_horizon(request.submitted);
        out.push(plan_and_book(
            planner,
            schedule,
            FlightId::from(i),
            request,
            scratch,
        ));
        progress(i + 1);
    }
    out
}
