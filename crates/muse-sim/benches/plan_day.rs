//! Planning a whole day on the Singapore default with the CBD zone (SPEC §8 demand: uniform
//! departures 08:00–20:00, uniform distinct station pairs, seed 1).
//!
//! Run with `cargo bench -p muse-sim --bench plan_day`. Each sample plans the whole day from
//! an empty schedule, on one thread; zone resolution and demand generation are outside the
//! timed section. Search effort (labels expanded per request) is printed once per size.

use std::sync::Once;

use divan::Bencher;
use muse_model::{BatterySwap, FlightParams, Instant, Millis};
use muse_sim::day::{DayRun, plan_requests};
use muse_sim::demand::{BookingLead, DemandSpec, OdRule, generate};

fn main() {
    divan::main();
}

fn day(count: usize) -> Vec<muse_model::Request> {
    let s = muse_scenario::singapore_77();
    let eight = Instant::at_local(s.date, Millis::from_mins(8 * 60), s.offset);
    let twenty = Instant::at_local(s.date, Millis::from_mins(20 * 60), s.offset);
    let spec = DemandSpec {
        count,
        start: eight,
        end: twenty,
        seed: 1,
        od: OdRule::Uniform,
        booking_lead: BookingLead::NONE,
    };
    generate(&s.airspace, &spec).expect("demand")
}

static PRINT: [Once; 3] = [Once::new(), Once::new(), Once::new()];

/// Prints the search effort of one planned day (once per benchmark size).
fn report(label: &str, run: &DayRun) {
    let n = run.outcomes.len();
    let expanded: u64 = run.outcomes.iter().map(|o| o.expanded).sum();
    let planned = run.outcomes.iter().filter(|o| o.result.is_ok()).count();
    eprintln!(
        "\n{label}, {n} requests: {planned} planned, {:.2} labels expanded per request",
        expanded as f64 / n as f64
    );
}

#[divan::bench(args = [1_000, 5_000, 10_000], sample_count = 30)]
fn singapore_77_cbd(bencher: Bencher, count: usize) {
    let s = muse_scenario::singapore_77();
    let params = FlightParams::default();
    let requests = day(count);
    let slot = match count {
        1_000 => 0,
        5_000 => 1,
        _ => 2,
    };
    PRINT[slot].call_once(|| {
        let run = plan_requests(&s.airspace, &s.zones, params, requests.clone(), |_| {}).unwrap();
        report("singapore-77", &run);
    });
    bencher
        .counter(divan::counter::ItemsCount::new(count))
        .with_inputs(|| requests.clone())
        .bench_local_values(|reqs| {
            plan_requests(&s.airspace, &s.zones, params, reqs, |_| {}).unwrap()
        });
}

/// Every multi-storey car park a station (`singapore-all`, about 1,100 stations), with the
/// CBD zone; demand restricted to pairs within battery range so that the search works.
#[divan::bench(args = [10_000, 100_000], sample_count = 3)]
fn singapore_all_in_range(bencher: Bencher, count: usize) {
    let s = muse_scenario::singapore_all().expect("singapore-all builds");
    let params = FlightParams::default();
    let eight = Instant::at_local(s.date, Millis::from_mins(8 * 60), s.offset);
    let twenty = Instant::at_local(s.date, Millis::from_mins(20 * 60), s.offset);
    let od = OdRule::InRange {
        speed: params.speed,
        max_flight: params.max_flight,
    };
    let spec = DemandSpec {
        count,
        start: eight,
        end: twenty,
        seed: 1,
        od,
        booking_lead: BookingLead::NONE,
    };
    let requests = generate(&s.airspace, &spec).expect("demand");
    let run = plan_requests(&s.airspace, &s.zones, params, requests.clone(), |_| {}).unwrap();
    report("singapore-all (in range)", &run);
    bencher
        .with_inputs(|| requests.clone())
        .bench_local_values(|reqs| {
            plan_requests(&s.airspace, &s.zones, params, reqs, |_| {}).unwrap()
        });
}

static PRINT_SWAPS: [Once; 2] = [Once::new(), Once::new()];

/// The same 5,000-request day with battery swaps of 5 minutes (SPEC §12): with no deadline
/// (`0`: waits between legs are unbounded) and with a one-hour delivery deadline (`60`).
#[divan::bench(args = [0, 60], sample_count = 5)]
fn singapore_77_cbd_swaps(bencher: Bencher, deadline_min: i64) {
    let s = muse_scenario::singapore_77();
    let params = FlightParams {
        battery_swap: Some(BatterySwap::new(Millis::from_mins(5))),
        max_trip: (deadline_min > 0).then(|| Millis::from_mins(deadline_min)),
        ..FlightParams::default()
    };
    let requests = day(5_000);
    PRINT_SWAPS[usize::from(deadline_min > 0)].call_once(|| {
        let run = plan_requests(&s.airspace, &s.zones, params, requests.clone(), |_| {}).unwrap();
        let label = if deadline_min > 0 {
            format!("singapore-77, swaps 5 min, deadline {deadline_min} min")
        } else {
            "singapore-77, swaps 5 min, no deadline".to_owned()
        };
        report(&label, &run);
    });
    bencher
        .counter(divan::counter::ItemsCount::new(5_000usize))
        .with_inputs(|| requests.clone())
        .bench_local_values(|reqs| {
            plan_requests(&s.airspace, &s.zones, params, reqs, |_| {}).unwrap()
        });
}
