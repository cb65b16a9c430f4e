//! Planning a whole day on the Singapore default with the CBD zone
//! (docs/reference.md#built-in-scenarios demand: uniform departures 08:00–20:00, uniform distinct
//! station pairs, seed 1).
//!
//! Run with `cargo bench -p muse-planner --bench plan_day`. Each sample plans the whole day
//! first come, first served from an empty schedule, on one thread: a new [`Planner`] (its
//! heuristic tables are computed as the day needs them), a new [`Schedule`] and [`plan_day`].
//! The demand (from `muse-sim`), its planning order and the zone closures are prepared
//! outside the timed section. Search effort (labels expanded per request) is printed once per
//! size.

use std::sync::Once;

use divan::Bencher;
use muse_airspace::closures::{Closures, resolve};
use muse_model::request::sort_for_planning;
use muse_model::{Airspace, BatterySwap, FlightParams, Instant, Millis, Request, Zone};
use muse_planner::{Outcome, Planner, Schedule, Scratch, plan_day};
use muse_scenario::Scenario;
use muse_sim::day::closure_range;
use muse_sim::demand::{BookingLead, DemandSpec, OdRule, generate};

fn main() {
    divan::main();
}

/// A day to plan: the requests in planning order and the closures of the scenario's zones.
struct Day {
    requests: Vec<Request>,
    closures: Closures,
}

impl Day {
    /// `count` requests departing 08:00–20:00 local time on `s`, with pairs chosen by `od`.
    fn new(s: &Scenario, params: &FlightParams, count: usize, od: OdRule) -> Self {
        let eight = Instant::at_local(s.date, Millis::from_mins(8 * 60), s.offset);
        let twenty = Instant::at_local(s.date, Millis::from_mins(20 * 60), s.offset);
        let spec = DemandSpec {
            count,
            start: eight,
            end: twenty,
            seed: 1,
            od,
            booking_lead: BookingLead::NONE,
        };
        let mut requests = generate(&s.airspace, &spec).expect("demand");
        sort_for_planning(&mut requests);
        Day {
            closures: closures(&s.airspace, &s.zones, &requests, params),
            requests,
        }
    }

    /// Plans the day from scratch: what each sample times.
    fn plan(&self, airspace: &Airspace, params: FlightParams) -> Vec<Outcome> {
        let planner = Planner::new(airspace, params);
        let mut schedule = Schedule::new(airspace, &params, &self.closures);
        let mut scratch = Scratch::new();
        plan_day(
            &planner,
            &mut schedule,
            &self.requests,
            &mut scratch,
            |_| {},
        )
    }
}

/// The zones' closures over every instant the requests can reach.
fn closures(
    airspace: &Airspace,
    zones: &[Zone],
    requests: &[Request],
    params: &FlightParams,
) -> Closures {
    let (from, to) = closure_range(requests, params);
    resolve(airspace, zones, from, to).expect("the scenario's zones resolve")
}

/// Prints the search effort of one planned day.
fn report(label: &str, outcomes: &[Outcome]) {
    let n = outcomes.len();
    let expanded: u64 = outcomes.iter().map(|o| o.expanded).sum();
    let planned = outcomes.iter().filter(|o| o.result.is_ok()).count();
    eprintln!(
        "\n{label}, {n} requests: {planned} planned, {:.2} labels expanded per request",
        expanded as f64 / n as f64
    );
}

static PRINT: [Once; 3] = [Once::new(), Once::new(), Once::new()];

#[divan::bench(args = [1_000, 5_000, 10_000], sample_count = 30)]
fn singapore_77_cbd(bencher: Bencher, count: usize) {
    let s = muse_scenario::singapore_77();
    let params = FlightParams::default();
    let day = Day::new(&s, &params, count, OdRule::Uniform);
    let slot = match count {
        1_000 => 0,
        5_000 => 1,
        _ => 2,
    };
    PRINT[slot].call_once(|| report("singapore-77", &day.plan(&s.airspace, params)));
    bencher
        .counter(divan::counter::ItemsCount::new(count))
        .bench_local(|| day.plan(&s.airspace, params));
}

/// Every multi-storey car park a station (`singapore-all`, about 1,100 stations), with the
/// CBD zone; demand restricted to pairs within battery range so that the search works.
#[divan::bench(args = [10_000, 100_000], sample_count = 3)]
fn singapore_all_in_range(bencher: Bencher, count: usize) {
    let s = muse_scenario::singapore_all().expect("singapore-all builds");
    let params = FlightParams::default();
    let od = OdRule::InRange {
        speed: params.speed,
        max_flight: params.max_flight,
    };
    let day = Day::new(s, &params, count, od);
    report("singapore-all (in range)", &day.plan(&s.airspace, params));
    bencher.bench_local(|| day.plan(&s.airspace, params));
}

static PRINT_SWAPS: [Once; 2] = [Once::new(), Once::new()];

/// The same 5,000-request day with battery swaps of 5 minutes (docs/reference.md#multi-leg-trips):
/// with no deadline (`0`: waits between legs are unbounded) and with a one-hour delivery deadline
/// (`60`).
#[divan::bench(args = [0, 60], sample_count = 5)]
fn singapore_77_cbd_swaps(bencher: Bencher, deadline_min: i64) {
    let s = muse_scenario::singapore_77();
    let params = FlightParams {
        battery_swap: Some(BatterySwap::new(Millis::from_mins(5))),
        max_trip: (deadline_min > 0).then(|| Millis::from_mins(deadline_min)),
        ..FlightParams::default()
    };
    let day = Day::new(&s, &params, 5_000, OdRule::Uniform);
    PRINT_SWAPS[usize::from(deadline_min > 0)].call_once(|| {
        let label = if deadline_min > 0 {
            format!("singapore-77, swaps 5 min, deadline {deadline_min} min")
        } else {
            "singapore-77, swaps 5 min, no deadline".to_owned()
        };
        report(&label, &day.plan(&s.airspace, params));
    });
    bencher
        .counter(divan::counter::ItemsCount::new(5_000usize))
        .bench_local(|| day.plan(&s.airspace, params));
}
