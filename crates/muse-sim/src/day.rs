//! Planning a day: requests in first-come-first-served order against one schedule.

use std::time::Duration;

use muse_airspace::closures::{ClosureError, Closures, resolve};
use muse_model::request::sort_for_planning;
use muse_model::{Airspace, FlightParams, Instant, Millis, Request, Zone};
use muse_planner::{Outcome, Planner, Schedule, Scratch, plan_day};

/// Errors of a planning run.
#[derive(Debug, thiserror::Error)]
pub enum DayError {
    /// A zone could not be resolved against the airspace.
    #[error(transparent)]
    Zones(#[from] ClosureError),
}

/// The result of planning a day.
#[derive(Debug)]
pub struct DayRun {
    /// The requests in planning order `(departure, id)`.
    pub requests: Vec<Request>,
    /// One outcome per request, in the same order.
    pub outcomes: Vec<Outcome>,
    /// Wall time of the planning loop alone (no I/O, no zone resolution).
    pub planner_wall: Duration,
    /// The zone closures planned against.
    pub closures: Closures,
}

/// The range of instants whose zone closures can matter to `requests`: from a day before the
/// first departure to a day after the last possible landing.
pub fn closure_range(requests: &[Request], params: &FlightParams) -> (Instant, Instant) {
    let day = Millis::from_secs(86_400);
    let first = requests
        .iter()
        .map(|r| r.departure)
        .min()
        .unwrap_or_default();
    let last = requests
        .iter()
        .map(|r| r.departure)
        .max()
        .unwrap_or_default();
    (
        first - day,
        last + params.max_ground_delay + params.max_flight + day,
    )
}

/// Plans `requests` (in any order: they are sorted by `(departure, id)` first) on `airspace`
/// with `zones`, each accepted plan reserved before the next request. `progress` is called
/// with the number of requests done.
pub fn plan_requests(
    airspace: &Airspace,
    zones: &[Zone],
    params: FlightParams,
    mut requests: Vec<Request>,
    progress: impl FnMut(usize),
) -> Result<DayRun, DayError> {
    sort_for_planning(&mut requests);
    let (from, to) = closure_range(&requests, &params);
    let closures = resolve(airspace, zones, from, to)?;
    let planner = Planner::new(airspace, params);
    let (outcomes, planner_wall) = plan_sorted(&planner, &closures, &requests, progress);
    Ok(DayRun {
        requests,
        outcomes,
        planner_wall,
        closures,
    })
}

/// Plans requests already in planning order with a prepared planner and resolved closures,
/// from an empty schedule; returns the outcomes and the wall time of the planning loop.
pub fn plan_sorted(
    planner: &Planner<'_>,
    closures: &Closures,
    requests: &[Request],
    progress: impl FnMut(usize),
) -> (Vec<Outcome>, Duration) {
    let mut schedule = Schedule::new(planner.airspace(), planner.params(), closures);
    let mut scratch = Scratch::new();
    let started = std::time::Instant::now();
    let outcomes = plan_day(planner, &mut schedule, requests, &mut scratch, progress);
    (outcomes, started.elapsed())
}
