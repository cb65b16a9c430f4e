//! Cancelling a flight (`Schedule::remove`) gives the same planning results as never having
//! inserted it.

use crate::oracle;
use crate::scenario;

use crate::scenario::{Instance, Shape, ZoneSpec};
use muse_model::Plan;
use muse_planner::{FlightId, Outcome, Planner, Schedule, Scratch, plan_day};
use proptest::test_runner::TestCaseError;

fn results(outcomes: &[Outcome]) -> Vec<Result<Plan, muse_model::RejectReason>> {
    outcomes.iter().map(|o| o.result.clone()).collect()
}

/// Plans every request of the instance with flight `k` removed after planning the day, and
/// compares with a schedule that never had it, and with the oracle.
fn check(instance: &Instance, pick: usize) -> Result<(), String> {
    let b = instance.build();
    let planner = Planner::new(&b.airspace, b.params);
    let mut scratch = Scratch::new();
    let mut schedule = Schedule::new(&b.airspace, &b.params, &b.closures);
    let day = plan_day(&planner, &mut schedule, &b.requests, &mut scratch, |_| {});
    let accepted: Vec<(usize, Plan)> = day
        .iter()
        .enumerate()
        .filter_map(|(i, o)| o.result.clone().ok().map(|p| (i, p)))
        .collect();
    if accepted.is_empty() {
        return Ok(());
    }
    let (k, removed) = &accepted[pick % accepted.len()];
    if !schedule.remove(&b.airspace, FlightId(*k as u64), removed) {
        return Err(format!("remove of flight {k} returned false"));
    }
    if schedule.remove(&b.airspace, FlightId(*k as u64), removed) {
        return Err(format!("a second remove of flight {k} returned true"));
    }
    let mut fresh = Schedule::new(&b.airspace, &b.params, &b.closures);
    let rest: Vec<(usize, Plan)> = accepted.iter().filter(|(i, _)| i != k).cloned().collect();
    for (i, p) in &rest {
        fresh.insert(&b.airspace, FlightId(*i as u64), p);
    }
    let others: Vec<&Plan> = rest.iter().map(|(_, p)| p).collect();
    for request in &b.requests {
        let after_remove = planner.plan(&schedule, request, &mut scratch);
        let never = planner.plan(&fresh, request, &mut scratch);
        if after_remove.result != never.result {
            return Err(format!(
                "request {}: after remove {:?}, never inserted {:?}",
                request.id, after_remove.result, never.result
            ));
        }
        let want = oracle::solve(
            &b.airspace,
            &b.params,
            &b.raw,
            &others,
            request,
            instance.unit,
        );
        let got = after_remove
            .result
            .as_ref()
            .map(|p| (p.takeoff(), p.landing()))
            .map_err(|r| *r);
        if got != want.result {
            return Err(format!(
                "request {}: planner {got:?}, oracle {:?}",
                request.id, want.result
            ));
        }
    }
    // Re-inserting restores the day's schedule: replanning the removed request gives its plan.
    schedule.insert(&b.airspace, FlightId(*k as u64), removed);
    let mut again = Schedule::new(&b.airspace, &b.params, &b.closures);
    let replay = plan_day(&planner, &mut again, &b.requests, &mut scratch, |_| {});
    if results(&replay) != results(&day) {
        return Err("planning the day twice differs".into());
    }
    for request in &b.requests {
        if planner.plan(&schedule, request, &mut scratch).result
            != planner.plan(&again, request, &mut scratch).result
        {
            return Err(format!(
                "request {}: remove + insert differs from the original schedule",
                request.id
            ));
        }
    }
    Ok(())
}

#[test]
fn remove_equals_never_inserted() {
    let mut runner = scenario::runner(1_000, 0x5eed_0005);
    let strategy = (scenario::instances(Shape::CROWDED), 0..64usize);
    let result = runner.run(&strategy, |(instance, pick)| {
        check(&instance, pick).map_err(TestCaseError::fail)
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

#[test]
fn plan_insert_remove_replan() {
    // N0 - N1 - N2, 10 s each, tau 5 s, up to 30 s on the ground; N1 closed [40 s, 50 s).
    let instance = Instance {
        unit: 1000,
        waypoint: vec![false, true, false],
        tree: vec![None, Some((0, 10)), Some((1, 10))],
        extra: vec![],
        tau: 5,
        headway: None,
        g_max: 30,
        t_max: 60,
        requests: vec![(0, 1, 0), (1, 0, 3), (0, 1, 5)],
        zones: vec![ZoneSpec {
            nodes: vec![1],
            edges: vec![],
            start: 40,
            len: 10,
        }],
        swap: None,
        layers: None,
    };
    let b = instance.build();
    let planner = Planner::new(&b.airspace, b.params);
    let mut scratch = Scratch::new();
    let mut schedule = Schedule::new(&b.airspace, &b.params, &b.closures);
    let before: Vec<Outcome> = b
        .requests
        .iter()
        .map(|r| planner.plan(&schedule, r, &mut scratch))
        .collect();
    let first = before[0].result.clone().unwrap();
    schedule.insert(&b.airspace, FlightId(0), &first);
    let during: Vec<Outcome> = b
        .requests
        .iter()
        .map(|r| planner.plan(&schedule, r, &mut scratch))
        .collect();
    assert_ne!(
        results(&before),
        results(&during),
        "the flight is in the way"
    );
    assert!(schedule.remove(&b.airspace, FlightId(0), &first));
    let after: Vec<Outcome> = b
        .requests
        .iter()
        .map(|r| planner.plan(&schedule, r, &mut scratch))
        .collect();
    assert_eq!(results(&before), results(&after));
    assert!(
        !schedule.remove(&b.airspace, FlightId(0), &first),
        "already removed"
    );
    check(&instance, 0).unwrap();
    check(&instance, 1).unwrap();
}
