//! The planner: prepared once for an airspace and parameters, then asked many times.

use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId, Plan, RejectReason, Request};

use crate::heuristic::{Heuristics, UNREACHABLE};
use crate::schedule::{FlightId, Schedule};
use crate::sipp::{Goal, Problem, Scratch, Start, search};

/// A prepared planner. Shareable between threads (`&Planner` is `Sync`); each thread brings
/// its own [`Scratch`] and each simulated day its own [`Schedule`].
#[derive(Debug)]
pub struct Planner<'a> {
    airspace: &'a Airspace,
    params: FlightParams,
    heuristics: Heuristics,
}

/// What the planner says about one request.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The plan (earliest landing, then latest take-off) or why there is none.
    pub result: Result<Plan, RejectReason>,
    /// Shortest airborne time on the empty graph, if the destination is reachable.
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
            heuristics: Heuristics::new(airspace, params.speed),
        }
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
        (h != UNREACHABLE).then_some(Millis(h))
    }

    /// Plans one request against `schedule` (which it does not change): take-off in
    /// `[departure, departure + G_max]`.
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
    /// request's own window: SPEC §11's replanning of a flight that has not taken off when a
    /// zone is announced at `n` uses `[max(departure, n), max(departure + G_max, n)]`.
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
        let h = self.heuristics.to(self.airspace, request.destination);
        let start = Start::Ground {
            origin: request.origin,
            earliest: earliest.0,
            latest: latest.0,
        };
        let result = search(
            self.problem(h),
            schedule,
            start,
            Goal::Node(request.destination),
            scratch,
        );
        let free_flow =
            (h[request.origin.index()] != UNREACHABLE).then_some(Millis(h[request.origin.index()]));
        Outcome {
            result,
            free_flow,
            expanded: scratch.expanded,
        }
    }

    /// Plans the rest of a flight that is in the air (SPEC §11): it arrives at `node` at
    /// instant `at`, having taken off at `takeoff`, and must land at `to` within the battery
    /// left (`T_max − (at − takeoff)`). The plan returned starts with the stay at `node` from
    /// `at`: the earliest landing (with `Landing::AnyStation`, at whichever station it is
    /// earliest, ties to the lowest node index). `None` if no such plan exists.
    ///
    /// ```
    /// use muse_airspace::closures::Closures;
    /// use muse_model::{Airspace, Edge, FlightParams, Instant, LonLat, Node, NodeId, NodeKind};
    /// use muse_planner::{Landing, Planner, Schedule, Scratch};
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
    /// let mut scratch = Scratch::new();
    /// // At waypoint W 2 minutes after take-off: back to A is nearest.
    /// let (rest, _) = planner.continue_from(&schedule, NodeId(1), Instant(120_000), Instant(0),
    ///                                       Landing::AnyStation, &mut scratch);
    /// let rest = rest.unwrap();
    /// assert_eq!((rest.path.last().unwrap().node, rest.landing()), (NodeId(0), Instant(240_000)));
    /// ```
    pub fn continue_from(
        &self,
        schedule: &Schedule,
        node: NodeId,
        at: Instant,
        takeoff: Instant,
        to: Landing,
        scratch: &mut Scratch,
    ) -> (Option<Plan>, u64) {
        let (h, goal) = match to {
            Landing::At(d) => (self.heuristics.to(self.airspace, d), Goal::Node(d)),
            Landing::AnyStation => (
                self.heuristics.to_any_station(self.airspace),
                Goal::AnyStation,
            ),
        };
        let start = Start::Airborne {
            node,
            at: at.0,
            takeoff: takeoff.0,
        };
        let result = search(self.problem(h), schedule, start, goal, scratch);
        (result.ok(), scratch.expanded)
    }

    fn problem<'h>(&'h self, h: &'h [i64]) -> Problem<'h> {
        Problem {
            airspace: self.airspace,
            params: &self.params,
            h,
        }
    }
}

/// Where an airborne flight must land ([`Planner::continue_from`]).
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
/// `(submitted, id)` first, SPEC §5), adding each accepted plan to `schedule` before the next
/// (first come, first served). The flight id of request `i` is `i`. Each request's submission
/// instant becomes the schedule's horizon ([`Schedule::set_horizon`]): a request is planned
/// at or after it is submitted and never asks about instants before its departure, which is
/// no earlier, so in submission order the searches only look at current traffic. Calls
/// `progress` after each request.
pub fn plan_day(
    planner: &Planner<'_>,
    schedule: &mut Schedule,
    requests: &[Request],
    scratch: &mut Scratch,
    mut progress: impl FnMut(usize),
) -> Vec<Outcome> {
    let mut out = Vec::with_capacity(requests.len());
    for (i, request) in requests.iter().enumerate() {
        schedule.set_horizon(request.submitted.0);
        out.push(plan_and_book(
            planner,
            schedule,
            i as FlightId,
            request,
            scratch,
        ));
        progress(i + 1);
    }
    out
}
