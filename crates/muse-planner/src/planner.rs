//! The planner: prepared once for an airspace and parameters, then asked many times.

use muse_model::{Airspace, FlightParams, Millis, Plan, RejectReason, Request};

use crate::heuristic::{Heuristics, UNREACHABLE};
use crate::schedule::{FlightId, Schedule};
use crate::sipp::{Problem, Scratch, search};

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

    /// Plans one request against `schedule` (which it does not change).
    pub fn plan(&self, schedule: &Schedule, request: &Request, scratch: &mut Scratch) -> Outcome {
        let h = self.heuristics.to(self.airspace, request.destination);
        let problem = Problem {
            airspace: self.airspace,
            params: &self.params,
            h,
        };
        let result = search(problem, schedule, request, scratch);
        let free_flow =
            (h[request.origin.index()] != UNREACHABLE).then_some(Millis(h[request.origin.index()]));
        Outcome {
            result,
            free_flow,
            expanded: scratch.expanded,
        }
    }
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

/// Plans `requests` in the given order (callers sort them by `(departure, id)` first), adding
/// each accepted plan to `schedule` before the next (first come, first served). The flight
/// id of request `i` is `i`. Each request's departure becomes the schedule's horizon
/// ([`Schedule::set_horizon`]), so in departure order the searches only look at current
/// traffic. Calls `progress` after each request.
pub fn plan_day(
    planner: &Planner<'_>,
    schedule: &mut Schedule,
    requests: &[Request],
    scratch: &mut Scratch,
    mut progress: impl FnMut(usize),
) -> Vec<Outcome> {
    let mut out = Vec::with_capacity(requests.len());
    for (i, request) in requests.iter().enumerate() {
        schedule.set_horizon(request.departure.0);
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
