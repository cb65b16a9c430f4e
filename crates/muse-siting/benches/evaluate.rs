//! What one siting evaluation costs on the Singapore default (77 stations, 1,038 candidates,
//! 2,257 HDB car parks as customers, the CBD zone, the paper's flight parameters, single legs),
//! and where the time goes.
//!
//! Run with `cargo bench -p muse-siting --bench evaluate`. Each evaluation rebuilds the
//! airspace from 78 pads, resolves the zones on it, maps every customer to its pad, prepares a
//! planner (its heuristic tables are computed as the days need them) and plans each seeded day
//! of 5,000 trips from an empty schedule. `evaluate` is timed with 1 and with 5 days: the
//! difference is the planning of 4 days, the rest the fixed cost of a rebuilt airspace. The
//! parts are timed alone beside it. Search effort (labels expanded per request) is printed.

use std::sync::{LazyLock, Once};

use divan::Bencher;
use muse_airspace::announced::KnownZones;
use muse_model::{FlightParams, Instant, Millis};
use muse_planner::Planner;
use muse_sim::customers::trips::TripSpec;
use muse_sim::demand::BookingLead;
use muse_siting::{Siting, SitingInput};

fn main() {
    divan::main();
}

/// The Singapore default with `days` seeded days of 5,000 trips (seeds 1 onwards).
fn singapore(days: u64) -> Siting {
    let s = muse_scenario::by_name(muse_scenario::SINGAPORE_77).expect("scenario");
    let at = |h: i64| Instant::at_local(s.date, Millis::from_mins(h * 60), s.offset);
    let input = SitingInput {
        existing: muse_scenario::station_nodes().expect("stations"),
        candidates: muse_scenario::candidates::candidate_pads().expect("candidates"),
        customers: muse_scenario::candidates::residential_customers().expect("customers"),
        last_mile_m: 1_000.0,
        days: (1..=days)
            .map(|seed| TripSpec {
                count: 5_000,
                start: at(8),
                end: at(20),
                seed,
                booking_lead: BookingLead::NONE,
            })
            .collect(),
        params: FlightParams::default(),
        zones: s.zones.clone(),
        build: muse_scenario::singapore_build_options(),
    };
    Siting::prepare(input).expect("the Singapore siting problem")
}

static ONE_DAY: LazyLock<Siting> = LazyLock::new(|| singapore(1));
static FIVE_DAYS: LazyLock<Siting> = LazyLock::new(|| singapore(5));

/// The candidate added in every timed evaluation (the first in file order).
const ADDED: [usize; 1] = [0];

#[divan::bench]
fn evaluate_1_day(bencher: Bencher) {
    let siting = &*ONE_DAY;
    bencher.bench(|| siting.evaluate(&ADDED).expect("evaluation"));
}

#[divan::bench]
fn evaluate_5_days(bencher: Bencher) {
    static EFFORT: Once = Once::new();
    let siting = &*FIVE_DAYS;
    EFFORT.call_once(|| {
        let e = siting.evaluate(&ADDED).expect("evaluation");
        let served: u32 = e.served.iter().sum();
        println!(
            "5 days: {} served, {} delivered, {:.2} labels expanded per served request",
            served,
            e.delivered.iter().sum::<u32>(),
            e.expanded as f64 / f64::from(served)
        );
    });
    bencher.bench(|| siting.evaluate(&ADDED).expect("evaluation"));
}

#[divan::bench]
fn rebuild_airspace(bencher: Bencher) {
    let siting = &*ONE_DAY;
    bencher.bench(|| siting.airspace(&ADDED).expect("airspace"));
}

#[divan::bench]
fn resolve_zones(bencher: Bencher) {
    let siting = &*ONE_DAY;
    let airspace = siting.airspace(&ADDED).expect("airspace");
    let (from, to) = siting.window();
    bencher
        .bench(|| KnownZones::resolve(&airspace, &siting.input().zones, from, to).expect("zones"));
}

#[divan::bench]
fn serving_pads(bencher: Bencher) {
    let siting = &*ONE_DAY;
    bencher.bench(|| siting.serving(&ADDED));
}

#[divan::bench]
fn prepare_planner(bencher: Bencher) {
    let siting = &*ONE_DAY;
    let airspace = siting.airspace(&ADDED).expect("airspace");
    bencher.bench(|| {
        let planner = Planner::new(&airspace, siting.input().params);
        divan::black_box(&planner);
    });
}

/// A day planned with a planner whose heuristic tables are already computed (a day planned
/// before on the same airspace): what `evaluate_1_day` costs beyond this and the parts above
/// is the tables.
#[divan::bench]
fn plan_1_day_warm_tables(bencher: Bencher) {
    let siting = &*ONE_DAY;
    let airspace = siting.airspace(&ADDED).expect("airspace");
    let (from, to) = siting.window();
    let zones = KnownZones::resolve(&airspace, &siting.input().zones, from, to).expect("zones");
    let planner = Planner::new(&airspace, siting.input().params);
    let serving = siting.serving(&ADDED);
    let requests: Vec<_> = siting
        .trips(0)
        .iter()
        .filter_map(|t| muse_sim::customers::trips::request_for(t, &serving).ok())
        .collect();
    let _warm = muse_sim::day::plan_sorted(&planner, &zones.base, &requests, |_| {});
    bencher.bench(|| muse_sim::day::plan_sorted(&planner, &zones.base, &requests, |_| {}));
}
