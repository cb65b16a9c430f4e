//! Planning a day: requests in first-come-first-served order against one schedule, and the
//! zones announced during it (docs/reference.md#requests, #zones-announced-during-the-day).

use std::time::Duration;

use muse_airspace::announced::KnownZones;
use muse_airspace::closures::{ClosureError, Closures};
use muse_model::request::sort_for_planning;
use muse_model::{Airspace, FlightParams, Instant, Millis, Request, Zone};
use muse_planner::ZoneError;
use muse_planner::{Outcome, Planner, Scratch, plan_day};
use muse_verify::Flight;

use crate::replay::{Replay, replay};

/// Errors of a planning run.
#[derive(Debug, thiserror::Error)]
pub enum DayError {
    /// A zone could not be resolved against the airspace.
    #[error(transparent)]
    Zones(#[from] ClosureError),
    /// Two announced zones share an id.
    #[error(transparent)]
    Announced(#[from] ZoneError),
    /// A zone was withdrawn (docs/reference.md#zones-announced-during-the-day, as a service lists
    /// it): a day is replayed with its announcements, never its withdrawals, so it cannot be
    /// planned with such a zone.
    #[error(
        "zone `{0}` has a `withdrawn` instant: planning replays zone announcements, not \
         withdrawals; leave the zone out, or give it without `withdrawn` (only `muse verify` \
         and `muse view` read withdrawn zones)"
    )]
    Withdrawn(String),
    /// Batch planning (docs/reference.md#batch-planning) was asked for a day with zones announced
    /// during it.
    #[error(
        "zone `{0}` is announced during the day: the optimiser plans a batch known in advance \
         against zones known from the start (docs/reference.md#batch-planning); leave out `--optimize` or the \
         zone's `announced` instant"
    )]
    OptimizeAnnounced(String),
}

/// How a day's requests are planned.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Planning {
    /// One at a time in planning order, each against those before it (docs/reference.md#requests
    /// and #planning).
    #[default]
    FirstComeFirstServed,
    /// As one batch, better than first come, first served (docs/reference.md#batch-planning).
    Optimized(muse_optimize::Options),
}

/// The result of planning a day: its requests, what planning made of them (a [`Replay`]),
/// the zones planned against, and the optimiser's report.
#[derive(Debug)]
pub struct DayRun {
    /// The requests in planning order `(submitted, id)`.
    pub requests: Vec<Request>,
    /// What planning made of each request, in the same order: its first answer, what zone
    /// announcements did to its flight since, and the planning loop's time.
    pub replay: Replay,
    /// The zones planned against: known from the start, and announced.
    pub zones: KnownZones,
    /// What the optimiser did, when the day was planned as a batch
    /// (docs/reference.md#batch-planning).
    pub optimizer: Option<muse_optimize::Report>,
}

impl DayRun {
    /// A day no zone announcement changed: `outcomes` of `requests`, planned against `zones`
    /// in `planner_wall`.
    pub fn unchanged(
        requests: Vec<Request>,
        outcomes: Vec<Outcome>,
        planner_wall: Duration,
        zones: KnownZones,
    ) -> Self {
        DayRun::replayed(requests, Replay::unchanged(outcomes, planner_wall), zones)
    }

    /// A day replayed with its announcements ([`replay`]).
    pub fn replayed(requests: Vec<Request>, replay: Replay, zones: KnownZones) -> Self {
        DayRun {
            requests,
            replay,
            zones,
            optimizer: None,
        }
    }

    /// The flights that fly, each as it finally stands after the day's zone announcements
    /// ([`Flight::last`]), for the verifier and the summary's separation report.
    #[must_use]
    pub fn flights(&self) -> Vec<Flight<'_>> {
        self.requests
            .iter()
            .zip(&self.replay.outcomes)
            .enumerate()
            .filter_map(|(i, (r, o))| {
                Flight::last(&r.id, r, o.result.as_ref().ok(), self.replay.fate(i))
            })
            .collect()
    }
}

/// The range of instants whose zone closures can matter to `requests`: from a day before the
/// first submission (a request booked ahead is planned from then on; without bookings ahead
/// this is the first departure) to a day after the last possible landing.
pub fn closure_range(requests: &[Request], params: &FlightParams) -> (Instant, Instant) {
    let first = requests
        .iter()
        .map(|r| r.submitted.min(r.departure))
        .min()
        .unwrap_or_default();
    let last = requests
        .iter()
        .map(|r| r.departure)
        .max()
        .unwrap_or_default();
    closure_window(first, last, params)
}

/// The range of instants whose zone closures can matter to requests submitted from `first`
/// on and departing up to `last`: from a day before `first` to a day after the last possible
/// landing ([`closure_range`] of such requests).
pub fn closure_window(first: Instant, last: Instant, params: &FlightParams) -> (Instant, Instant) {
    let day = Millis::from_secs(86_400);
    (first - day, last + params.trip_span() + day)
}

/// Plans `requests` (in any order: they are sorted into planning order `(submitted, id)` first,
/// docs/reference.md#requests) on `airspace` with `zones`, each accepted plan reserved before the
/// next request. When some zone carries an announcement instant, the day is [replayed](replay):
/// each announcement is made at its instant between the requests and replans the flights it hits
/// (docs/reference.md#zones-announced-during-the-day). `progress` is called with the number of
/// requests done. A zone with a [withdrawal](Zone::withdrawn) is refused ([`DayError::Withdrawn`]).
pub fn plan_requests(
    airspace: &Airspace,
    zones: &[Zone],
    params: FlightParams,
    requests: Vec<Request>,
    progress: impl FnMut(usize),
) -> Result<DayRun, DayError> {
    plan_requests_by(
        airspace,
        zones,
        params,
        requests,
        Planning::FirstComeFirstServed,
        progress,
    )
}

/// [`plan_requests`], or with [`Planning::Optimized`] as one batch
/// (docs/reference.md#batch-planning): `progress` is then called with the optimiser's steps done.
/// Zones announced during the day cannot be optimised ([`DayError::OptimizeAnnounced`]).
pub fn plan_requests_by(
    airspace: &Airspace,
    zones: &[Zone],
    params: FlightParams,
    mut requests: Vec<Request>,
    planning: Planning,
    progress: impl FnMut(usize),
) -> Result<DayRun, DayError> {
    if let Some(z) = zones.iter().find(|z| z.withdrawn.is_some()) {
        return Err(DayError::Withdrawn(z.id.clone()));
    }
    if let (Planning::Optimized(_), Some(z)) =
        (planning, zones.iter().find(|z| z.announced.is_some()))
    {
        return Err(DayError::OptimizeAnnounced(z.id.clone()));
    }
    sort_for_planning(&mut requests);
    let (from, to) = closure_range(&requests, &params);
    let announced_from = zones
        .iter()
        .filter_map(|z| z.announced)
        .min()
        .map_or(from, |n| n.min(from));
    let known = KnownZones::resolve(airspace, zones, announced_from, to)?;
    let planner = Planner::new(airspace, params);
    if known.announced.is_empty() {
        let Planning::Optimized(options) = planning else {
            let (outcomes, planner_wall) = plan_sorted(&planner, &known.base, &requests, progress);
            return Ok(DayRun::unchanged(requests, outcomes, planner_wall, known));
        };
        let mut progress = progress;
        let out = muse_optimize::optimize(&planner, &known.base, &requests, &options, |n| {
            progress(usize::try_from(n).unwrap_or(usize::MAX));
        });
        let mut run = DayRun::unchanged(requests, out.outcomes, out.report.elapsed, known);
        run.optimizer = Some(out.report);
        return Ok(run);
    }
    let run = replay(planner, &known, &requests, progress)?;
    Ok(DayRun::replayed(requests, run, known))
}

/// Plans requests already in planning order with a prepared planner and resolved closures,
/// from an empty schedule; returns the outcomes and the wall time of the planning loop.
pub fn plan_sorted(
    planner: &Planner<'_>,
    closures: &Closures,
    requests: &[Request],
    progress: impl FnMut(usize),
) -> (Vec<Outcome>, Duration) {
    let mut schedule = planner.schedule(closures);
    let mut scratch = Scratch::new();
    let started = std::time::Instant::now();
    let outcomes = plan_day(planner, &mut schedule, requests, &mut scratch, progress);
    (outcomes, started.elapsed())
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::{Plan, RejectReason};

    /// Two stations one kilometre apart: two minutes of flight at 30 km/h.
    fn pair() -> Airspace {
        Airspace::line(&[1_000.0])
    }

    fn request(id: &str, from: u32, departure_min: i64, submitted_min: i64) -> Request {
        Request {
            submitted: Instant(submitted_min * 60_000),
            ..muse_model::testing::request(id, from, 1 - from, departure_min * 60_000)
        }
    }

    /// The take-off of each request by id, or its rejection.
    fn outcome(run: &DayRun) -> Vec<(String, Result<Instant, RejectReason>)> {
        let mut v: Vec<_> = run
            .requests
            .iter()
            .zip(&run.replay.outcomes)
            .map(|(r, o)| {
                (
                    r.id.clone(),
                    o.result.as_ref().map(Plan::takeoff).map_err(|e| *e),
                )
            })
            .collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        v
    }

    #[test]
    fn optimizing_a_day_with_an_announced_zone_is_refused_and_fcfs_is_not() {
        use crate::replay::example::{airspace, params, requests, zone};
        let options = muse_optimize::Options::default();
        let e = plan_requests_by(
            &airspace(),
            &[zone()],
            params(),
            requests(),
            Planning::Optimized(options),
            |_| {},
        )
        .unwrap_err();
        assert!(
            matches!(&e, DayError::OptimizeAnnounced(z) if z == "Z"),
            "{e}"
        );
        assert!(e.to_string().contains("--optimize"), "{e}");
        let fcfs = plan_requests(&airspace(), &[zone()], params(), requests(), |_| {}).unwrap();
        assert!(fcfs.optimizer.is_none());
        let optimized = plan_requests_by(
            &airspace(),
            &[],
            params(),
            requests(),
            Planning::Optimized(options),
            |_| {},
        )
        .unwrap();
        let report = optimized.optimizer.as_ref().unwrap();
        assert!(report.result >= report.fcfs);
        assert_eq!(optimized.replay.outcomes.len(), optimized.requests.len());
    }

    #[test]
    fn submission_order_decides_who_gets_a_contested_slot() {
        // `early` flies A→B departing at minute 600, `late` B→A at minute 601: the corridor
        // (exclusive, two minutes) cannot carry both, and without ground delay neither can wait
        // on the ground. Whoever is planned first gets it.
        let air = pair();
        let params = FlightParams::default();
        let plan = |requests| plan_requests(&air, &[], params, requests, |_| {}).unwrap();

        // Submitted at departure (the paper): first come by departure, `early` wins.
        let run = plan(vec![
            request("late", 1, 601, 601),
            request("early", 0, 600, 600),
        ]);
        assert_eq!(
            run.requests
                .iter()
                .map(|r| r.id.as_str())
                .collect::<Vec<_>>(),
            ["early", "late"]
        );
        assert_eq!(
            outcome(&run),
            [
                ("early".into(), Ok(Instant(600 * 60_000))),
                ("late".into(), Err(RejectReason::NoFeasiblePlan)),
            ]
        );

        // `late` booked an hour ahead: it is planned first and takes the corridor, although it
        // departs a minute after `early`.
        let run = plan(vec![
            request("early", 0, 600, 600),
            request("late", 1, 601, 541),
        ]);
        assert_eq!(
            run.requests
                .iter()
                .map(|r| r.id.as_str())
                .collect::<Vec<_>>(),
            ["late", "early"]
        );
        assert_eq!(
            outcome(&run),
            [
                ("early".into(), Err(RejectReason::NoFeasiblePlan)),
                ("late".into(), Ok(Instant(601 * 60_000))),
            ]
        );

        // Booked ahead but after `early` was submitted: departure order again.
        let run = plan(vec![
            request("early", 0, 600, 590),
            request("late", 1, 601, 595),
        ]);
        assert_eq!(
            outcome(&run)[0],
            ("early".into(), Ok(Instant(600 * 60_000)))
        );
        assert_eq!(
            outcome(&run)[1],
            ("late".into(), Err(RejectReason::NoFeasiblePlan))
        );
    }

    #[test]
    fn closure_range_starts_a_day_before_the_first_submission() {
        let params = FlightParams::default();
        let day = Millis::from_secs(86_400);
        let reqs = [request("a", 0, 600, 600), request("b", 1, 700, 300)];
        let (from, to) = closure_range(&reqs, &params);
        assert_eq!(from, Instant(300 * 60_000) - day);
        assert_eq!(to, Instant(700 * 60_000) + params.max_flight + day);
        let at_departure = [request("a", 0, 600, 600), request("b", 1, 700, 700)];
        assert_eq!(
            closure_range(&at_departure, &params).0,
            Instant(600 * 60_000) - day
        );
    }

    #[test]
    fn a_withdrawn_zone_is_refused() {
        let zone = Zone {
            id: "W".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: vec![],
            periods: vec![],
            announced: Some(Instant(0)),
            withdrawn: Some(Instant(60_000)),
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
        };
        let err = plan_requests(&pair(), &[zone], FlightParams::default(), vec![], |_| {})
            .expect_err("withdrawals are not replayed");
        assert!(
            matches!(&err, DayError::Withdrawn(id) if id == "W"),
            "{err}"
        );
    }
}
