//! Every optimised schedule is valid (the independent verifier finds nothing), never worse
//! than first come, first served, and the same on every run of the same seed and budget.

use muse_optimize::{Objective, Options, optimize};
use muse_planner::{Outcome, Planner, Schedule, Scratch, plan_day};
use muse_verify::{Flight, verify};

use crate::instances::{Instance, instance};

/// First come, first served by the planner itself, and its objective.
fn fcfs(inst: &Instance, planner: &Planner<'_>) -> (Vec<Outcome>, Objective) {
    let mut schedule = Schedule::new(&inst.airspace, &inst.params, &inst.closures());
    let outcomes = plan_day(
        planner,
        &mut schedule,
        &inst.requests,
        &mut Scratch::new(),
        |_| {},
    );
    (outcomes.clone(), objective(inst, &outcomes))
}

/// The objective of `outcomes`, recomputed here from the plans.
fn objective(inst: &Instance, outcomes: &[Outcome]) -> Objective {
    let mut o = Objective::default();
    for (r, out) in inst.requests.iter().zip(outcomes) {
        if let Ok(plan) = &out.result {
            o = o.with(Objective::delay_of(
                r,
                plan,
                out.free_flow.expect("planned"),
            ));
        }
    }
    o
}

/// Checks one instance; returns whether the optimiser did better than FCFS.
fn check(seed: u64, count: usize, swaps: bool, iterations: u64) -> bool {
    let inst = instance(seed, count, swaps);
    let planner = Planner::new(&inst.airspace, inst.params);
    let options = Options {
        iterations,
        seed,
        ..Options::default()
    };
    let out = optimize(&planner, &inst.closures(), &inst.requests, &options, |_| {});
    let (_, fcfs) = fcfs(&inst, &planner);
    let context = format!("seed {seed}, {count} requests, swaps {swaps}");
    assert_eq!(out.report.fcfs, fcfs, "{context}: the report's FCFS");
    assert_eq!(
        out.report.result,
        objective(&inst, &out.outcomes),
        "{context}"
    );
    assert!(out.report.result >= fcfs, "{context}: worse than FCFS");
    assert!(out.report.result.planned <= out.report.alone, "{context}");
    let flights: Vec<Flight<'_>> = inst
        .requests
        .iter()
        .zip(&out.outcomes)
        .filter_map(|(r, o)| o.result.as_ref().ok().map(|p| Flight::new(&r.id, r, p)))
        .collect();
    let violations = verify(&inst.airspace, &inst.closures(), &inst.params, &flights);
    assert!(violations.is_empty(), "{context}: {violations:#?}");
    let again = optimize(&planner, &inst.closures(), &inst.requests, &options, |_| {});
    assert_eq!(
        again.outcomes, out.outcomes,
        "{context}: a second run differs"
    );
    out.report.result > fcfs
}

/// Checks the instances of `seeds` (`4 + seed % spread` requests each, `steps` steps) and
/// that the optimiser improved on FCFS at least once.
fn check_all(seeds: std::ops::Range<u64>, spread: u64, swaps: bool, steps: u64) {
    println!(
        "seeds {seeds:?}, 4 to {} requests, {steps} steps, swaps {swaps}",
        3 + spread
    );
    let total = seeds.end - seeds.start;
    let better = seeds
        .filter(|&s| check(s, 4 + (s % spread) as usize, swaps, steps))
        .count();
    println!("better than FCFS on {better} of {total} instances");
    assert!(better > 0, "the optimiser never improved on FCFS");
}

#[test]
fn single_leg_schedules_are_valid_never_worse_and_repeat() {
    check_all(0..300, 21, false, 300);
}

/// Batteries of 3 minutes with swaps: many trips need two or three legs.
#[test]
fn multi_leg_schedules_are_valid_never_worse_and_repeat() {
    check_all(1_000..1_150, 13, true, 200);
}

#[test]
fn a_batch_on_top_of_booked_flights_leaves_them_and_is_valid() {
    use muse_optimize::optimize_on;
    use muse_planner::FlightId;
    let seeds = 2_000..2_100_u64;
    println!("seeds {seeds:?}: 6 flights booked first come, first served, then a batch of 8");
    for seed in seeds {
        let inst = instance(seed, 14, false);
        let planner = Planner::new(&inst.airspace, inst.params);
        let (booked, batch) = inst.requests.split_at(6);
        let mut base = Schedule::new(&inst.airspace, &inst.params, &inst.closures());
        let first = plan_day(&planner, &mut base, booked, &mut Scratch::new(), |_| {});
        let ids: Vec<FlightId> = (100..108).map(FlightId).collect();
        let options = Options {
            iterations: 200,
            seed,
            ..Options::default()
        };
        let out = optimize_on(&planner, &base, batch, &ids, &options, |_| {});
        assert!(out.report.result >= out.report.fcfs, "seed {seed}");
        let flights: Vec<Flight<'_>> = booked
            .iter()
            .zip(&first)
            .chain(batch.iter().zip(&out.outcomes))
            .filter_map(|(r, o)| o.result.as_ref().ok().map(|p| Flight::new(&r.id, r, p)))
            .collect();
        let violations = verify(&inst.airspace, &inst.closures(), &inst.params, &flights);
        assert!(violations.is_empty(), "seed {seed}: {violations:#?}");
    }
}
