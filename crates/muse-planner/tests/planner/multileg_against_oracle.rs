//! Multi-leg trips (docs/reference.md#multi-leg-trips: battery swaps at stations): the planner
//! against the brute-force multi-leg oracle (`oracle/multileg.rs`) and the verifier, on random
//! small instances whose batteries are short against their paths, so that many trips need two or
//! three legs, plus hand-made cases checked by hand, and checks of the oracle itself; and the
//! resumption of a trip under way (`Planner::resume`,
//! docs/reference.md#zones-announced-during-the-day replanning with swaps) against the oracle's.
//!
//! Property runs are deterministic: a fixed `ChaCha` seed per test, no failure persistence
//! (see `scenario::runner` for soak runs). On a failure proptest shrinks the instance and the
//! panic message shows the seed and the minimal instance. A planner call that does not
//! answer within `scenario::multileg::HANG` cannot be shrunk: the watchdog prints the
//! instance and ends the test process (`scenario::multileg::watched`).

use crate::oracle;
use crate::scenario;

use crate::oracle::Goal;
use crate::oracle::multileg::{self, Resume, Trip};
use crate::scenario::multileg::{SwapSpec, check_rules, check_trip, multileg_instances, watched};
use crate::scenario::{Instance, Shape, Tally, ZoneSpec, runner};
use muse_model::{Instant, NodeId, Plan, RejectReason, Stay};
use muse_planner::{FlightId, Planner, Schedule, Scratch};
use proptest::prelude::{Strategy, prop_assert_eq};
use proptest::test_runner::TestCaseError;

/// Runs `cases` random instances of `shape` (half of them with swaps) through `run`; panics
/// with the seed and the minimal failing instance.
fn property_of(
    run: fn(&Instance) -> Result<Tally, String>,
    path: &str,
    shape: Shape,
    cases: u32,
    seed: u64,
) -> Tally {
    let label = format!("{path} {shape:?}");
    scenario::check_property(run, multileg_instances(shape), &label, cases, seed)
}

/// The batch path (`scenario::run`).
fn property(shape: Shape, cases: u32, seed: u64) -> Tally {
    property_of(scenario::run, "batch", shape, cases, seed)
}

/// The online path (`scenario::run_online`).
fn property_online(shape: Shape, cases: u32, seed: u64) -> Tally {
    property_of(scenario::run_online, "online", shape, cases, seed)
}

/// The generator reaches every kind of multi-leg answer.
fn assert_reaches_every_answer(t: &Tally, scale: usize) {
    let [one, two, three, _] = t.legs;
    let [out_of_range, _, no_feasible] = t.swap_rejected;
    assert!(
        one > 100 * scale && two > 100 * scale && three > 20 * scale,
        "single-leg trips with swaps on, two and three legs: {t:?}"
    );
    assert!(
        out_of_range > 20 * scale && no_feasible > 20 * scale && t.long_swaps > 10 * scale,
        "out of range, no feasible plan, longer swaps: {t:?}"
    );
}

#[test]
fn planner_matches_multileg_oracle() {
    let t = property(Shape::MULTILEG, 3_000, 0x5eed_0031);
    assert_reaches_every_answer(&t, 10);
    assert!(t.ground_delayed > 500 && t.air_delayed > 500, "{t:?}");
}

#[test]
fn planner_matches_multileg_oracle_crowded() {
    let t = property(Shape::MULTILEG_CROWDED, 2_000, 0x5eed_0032);
    assert_reaches_every_answer(&t, 10);
    assert!(t.swap_rejected[2] > 500, "{t:?}");
}

#[test]
fn online_matches_multileg_oracle() {
    let t = property_online(Shape::MULTILEG, 1_000, 0x5eed_0041);
    assert_reaches_every_answer(&t, 3);
    assert!(t.in_past > 100 && t.cancelled > 100, "{t:?}");
}

#[test]
fn online_matches_multileg_oracle_crowded() {
    let t = property_online(Shape::MULTILEG_CROWDED, 1_000, 0x5eed_0042);
    assert_reaches_every_answer(&t, 3);
    assert!(t.in_past > 100 && t.cancelled > 100, "{t:?}");
}

// ---------------------------------------------------------------------------------------
// The oracle checked by itself (no planner: the oracle's own plans make the schedule).

/// Plans the instance's requests in order with `solve`, accepting the oracle's own plans, and
/// returns every answer.
fn oracle_day(instance: &Instance, unit: i64) -> Vec<multileg::Answer> {
    let b = instance.build();
    let mut accepted: Vec<Plan> = Vec::new();
    let mut answers = Vec::new();
    for request in &b.requests {
        let others: Vec<&Plan> = accepted.iter().collect();
        let answer = multileg::solve(&b.airspace, &b.params, &b.raw, &others, request, unit);
        if let Some(plan) = &answer.plan {
            accepted.push(plan.clone());
        }
        answers.push(answer);
    }
    answers
}

/// Without swaps the multi-leg oracle is the single-leg one.
#[test]
fn multileg_oracle_without_swaps_is_the_single_leg_oracle() {
    let result = runner(400, 0x5eed_0033).run(&scenario::instances(Shape::MIXED), |instance| {
        let b = instance.build();
        let mut accepted: Vec<Plan> = Vec::new();
        for request in &b.requests {
            let others: Vec<&Plan> = accepted.iter().collect();
            let unit = instance.unit;
            let one = oracle::solve(&b.airspace, &b.params, &b.raw, &others, request, unit);
            let multi = multileg::solve(&b.airspace, &b.params, &b.raw, &others, request, unit);
            let figures = multi.result.map(|t| (t.first_takeoff, t.landing, t.legs));
            prop_assert_eq!(
                one.result.map(|(t, l)| (t, l, 1)),
                figures,
                "request {}",
                request.id
            );
            prop_assert_eq!(one.free_flow, multi.free_flow);
            if let Some(plan) = one.plan {
                accepted.push(plan);
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// The grid argument with swaps, checked: on data in units of 7 or 37 ms, searching the grid
/// of whole units plus offsets gives the same answers as searching every millisecond; and the
/// oracle's plans are sound trips.
#[test]
fn multileg_oracle_grid_equals_every_millisecond() {
    let strategy = multileg_instances(Shape::MULTILEG_CROWDED).prop_map(|mut i| {
        i.unit = if i.t_max % 2 == 0 { 7 } else { 37 };
        i.swap = i.swap.or(Some(SwapSpec {
            time: i.tau,
            max_legs: None,
        }));
        i.requests.truncate(10);
        i
    });
    let result = runner(150, 0x5eed_0034).run(&strategy, |instance| {
        let b = instance.build();
        let coarse = oracle_day(&instance, instance.unit);
        let fine = oracle_day(&instance, 1);
        let mut accepted: Vec<(usize, Plan)> = Vec::new();
        for (i, (c, f)) in coarse.iter().zip(&fine).enumerate() {
            prop_assert_eq!(c.result, f.result, "request {}", b.requests[i].id);
            if let Some(plan) = &c.plan {
                check_trip(&b, &b.requests[i], plan).map_err(TestCaseError::fail)?;
                check_rules(&b, &accepted, plan).map_err(TestCaseError::fail)?;
                accepted.push((i, plan.clone()));
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

// ---------------------------------------------------------------------------------------
// Hand-made cases.

/// A line of stations N0 - N1 - ... joined by edges of `secs` seconds.
fn line(secs: &[u32], t_max: u32, swap: u32) -> Instance {
    let n = secs.len() + 1;
    Instance {
        unit: 1000,
        waypoint: vec![false; n],
        tree: (0..n)
            .map(|i| (i > 0).then(|| (i - 1, secs[i - 1])))
            .collect(),
        extra: vec![],
        tau: 5,
        headway: None,
        g_max: 0,
        t_max,
        requests: vec![],
        zones: vec![],
        swap: Some(SwapSpec {
            time: swap,
            max_legs: None,
        }),
        layers: None,
    }
}

/// The oracle's answers to the instance's requests (in order, each accepted plan added), as
/// `(landing, first take-off, legs)` in ms, after checking the planner against it.
fn both(instance: &Instance) -> Vec<Result<(i64, i64, u32), RejectReason>> {
    let checked = scenario::run(instance);
    let answers = oracle_day(instance, instance.unit)
        .into_iter()
        .map(|a| a.result.map(|t| (t.landing.0, t.first_takeoff.0, t.legs)))
        .collect();
    if let Err(e) = checked {
        panic!("oracle {answers:?}; the planner disagrees: {e}");
    }
    answers
}

#[test]
fn hand_two_legs_and_rejections() {
    // N0 - N1 - N2, 10 s each, T_max 15 s, S 5 s: N0 → N2 lands at N1 at 10 s, takes off at
    // 15 s, lands at 25 s.
    let mut i = line(&[10, 10], 15, 5);
    i.requests = vec![(0, 2, 0)];
    assert_eq!(both(&i), [Ok((25_000, 0, 2))]);
    let b = i.build();
    let free = multileg::free_flow_time(&b.airspace, &b.params, NodeId(0), NodeId(2));
    assert_eq!(free, Some(muse_model::Millis(25_000)));
    // A second drone, 30 s of ground delay: N0 is free from 5 s, but the edge N0 - N1 only
    // from 10 s, and it may land at N1 only from 20 s (tau after the first's take-off stay
    // there at 15 s); it takes off again at 25 s, when N1 - N2 is free: lands at 35 s.
    i.g_max = 30;
    i.requests = vec![(0, 2, 0), (0, 2, 0)];
    assert_eq!(both(&i), [Ok((25_000, 0, 2)), Ok((35_000, 10_000, 2))]);
    // One leg at most, or N1 a waypoint: out of range (free flow: the direct 20 s).
    i.requests = vec![(0, 2, 0)];
    i.swap = Some(SwapSpec {
        time: 5,
        max_legs: Some(1),
    });
    assert_eq!(both(&i), [Err(RejectReason::OutOfRange)]);
    i.swap = Some(SwapSpec {
        time: 5,
        max_legs: Some(2),
    });
    i.waypoint[1] = true;
    assert_eq!(both(&i), [Err(RejectReason::OutOfRange)]);
    let b = i.build();
    let free = multileg::free_flow_time(&b.airspace, &b.params, NodeId(0), NodeId(2));
    assert_eq!(free, Some(muse_model::Millis(20_000)));
    // Back to a station, but closed for good from 0: no feasible plan.
    i.waypoint[1] = false;
    i.zones = vec![ZoneSpec {
        nodes: vec![1],
        edges: vec![],
        start: 0,
        len: 400,
    }];
    assert_eq!(both(&i), [Err(RejectReason::NoFeasiblePlan)]);
}

#[test]
fn hand_fewest_legs_and_latest_takeoff() {
    // N0 - N1 - N2, 10 s each, T_max 30 s, S 0: one leg 0 → 20 s, or land at N1 at 10 s and
    // take off at once; one leg wins the tie.
    let mut i = line(&[10, 10], 30, 0);
    i.requests = vec![(0, 2, 0)];
    assert_eq!(both(&i), [Ok((20_000, 0, 1))]);
    // N2 closed [0 s, 40 s), T_max 25 s, S 5 s, no ground delay: one leg would be airborne
    // 40 s; two legs wait on the ground at N1 from 10 s and take off at 30 s.
    i.t_max = 25;
    i.swap = Some(SwapSpec {
        time: 5,
        max_legs: None,
    });
    i.zones = vec![ZoneSpec {
        nodes: vec![2],
        edges: vec![],
        start: 0,
        len: 40,
    }];
    assert_eq!(both(&i), [Ok((40_000, 0, 2))]);
    // With 20 s of ground delay one leg taking off at 20 s lands at 40 s too, and takes off
    // later than two legs could (15 s at the latest).
    i.g_max = 20;
    assert_eq!(both(&i), [Ok((40_000, 20_000, 1))]);
    // At most one leg and no ground delay: nothing.
    i.g_max = 0;
    i.swap = Some(SwapSpec {
        time: 5,
        max_legs: Some(1),
    });
    assert_eq!(both(&i), [Err(RejectReason::NoFeasiblePlan)]);
}

#[test]
fn hand_three_legs_with_a_loop_forbidden() {
    // N0 - N1 - N2 - N3, 10 s each, T_max 10 s, S 2 s: three legs, landing at 10 + 2 + 10 +
    // 2 + 10 = 34 s.
    let mut i = line(&[10, 10, 10], 10, 2);
    i.requests = vec![(0, 3, 0)];
    assert_eq!(both(&i), [Ok((34_000, 0, 3))]);
    // K = 2: out of range.
    i.swap = Some(SwapSpec {
        time: 2,
        max_legs: Some(2),
    });
    assert_eq!(both(&i), [Err(RejectReason::OutOfRange)]);
    // N0 - N2 - N3 (10 s each) and a waypoint N1 5 s off N0; N2 closed [0, 30 s); T_max 10 s,
    // no ground delay. Flying N0 → N1 → N0 and landing back at N0 at 10 s would let the drone
    // wait out the zone on the ground, but a leg must land somewhere else: no feasible plan.
    let mut i = line(&[10, 10, 10], 10, 2);
    i.waypoint = vec![false, true, false, false];
    i.tree = vec![None, Some((0, 5)), Some((0, 10)), Some((2, 10))];
    i.zones = vec![ZoneSpec {
        nodes: vec![2],
        edges: vec![],
        start: 0,
        len: 30,
    }];
    // Stations N0, N2, N3: N0 → N3.
    i.requests = vec![(0, 2, 0)];
    assert_eq!(both(&i), [Err(RejectReason::NoFeasiblePlan)]);
    // With 20 s of ground delay: take off at 20 s, land at N2 at 30 s, then N3 at 42 s.
    i.g_max = 20;
    assert_eq!(both(&i), [Ok((42_000, 20_000, 2))]);
}

#[test]
fn hand_leg_limit_leaves_no_feasible_plan() {
    // Stations N0, N1, N3 and a waypoint N2: N1 - N2 7 s, N2 - N0 10 s, N1 - N3 5 s; tau 0;
    // T_max 21 s, S 4 s; N0 closed [5 s, 25 s). N1 → N0 departing at 1 s: one leg would reach
    // N0 at 18 s and must hover until 25 s (24 s airborne); N3 → N0 takes 22 s. Three legs
    // go round by N3: N3 at 6 s, back at N1 at 15 s, take off at 19 s, N0 at 36 s. With at
    // most two legs there is no plan (a search that waits on the ground for ever would never
    // say so: found with the planner hanging here).
    let mut i = line(&[10, 10, 10], 21, 4);
    i.waypoint = vec![false, false, true, false];
    i.tree = vec![None, None, Some((1, 7)), Some((1, 5))];
    i.extra = vec![(0, 2, 10)];
    i.tau = 0;
    i.zones = vec![ZoneSpec {
        nodes: vec![0],
        edges: vec![],
        start: 5,
        len: 20,
    }];
    // Stations N0, N1, N3: N1 → N0.
    i.requests = vec![(1, 0, 1)];
    assert_eq!(both(&i), [Ok((36_000, 1_000, 3))]);
    i.swap = Some(SwapSpec {
        time: 4,
        max_legs: Some(3),
    });
    assert_eq!(both(&i), [Ok((36_000, 1_000, 3))]);
    i.swap = Some(SwapSpec {
        time: 4,
        max_legs: Some(2),
    });
    assert_eq!(both(&i), [Err(RejectReason::NoFeasiblePlan)]);
}

#[test]
fn hand_resume() {
    // N0 - N1 - N2 - N3, 10 s each, T_max 25 s, S 5 s.
    let i = line(&[10, 10, 10], 25, 5);
    let b = i.build();
    let resume = |from, legs, goal| {
        multileg::resume(
            &b.airspace,
            &b.params,
            &b.raw,
            &[],
            from,
            Instant(0),
            legs,
            goal,
            1000,
        )
    };
    let trip = |landing, legs| Trip {
        landing: Instant(landing),
        first_takeoff: Instant(0),
        legs,
    };
    // In the air at N1 at 10 s, the leg from N0 at 0: it cannot reach N3 by 25 s; one swap
    // (at N1 or N2) lands at 35 s.
    let air = Resume::Air {
        node: NodeId(1),
        at: Instant(10_000),
        leg_takeoff: Instant(0),
        leg_station: Some(NodeId(0)),
    };
    let (t, plan) = resume(air, 1, Goal::Node(NodeId(3))).unwrap();
    assert_eq!(t, trip(35_000, 2));
    assert_eq!(plan.path[0].node, NodeId(1));
    assert_eq!(plan.leg_count(), 2);
    // With K unbounded, the legs flown before do not matter; with K = 1 the leg in the air
    // would have to reach N3 by itself: none.
    assert!(resume(air, 5, Goal::Node(NodeId(3))).is_some());
    let mut capped = b.params;
    capped.battery_swap = Some(muse_model::BatterySwap {
        time: muse_model::Millis(5_000),
        max_legs: Some(1),
    });
    let none = multileg::resume(
        &b.airspace,
        &capped,
        &b.raw,
        &[],
        air,
        Instant(0),
        1,
        Goal::Node(NodeId(3)),
        1000,
    );
    assert_eq!(none, None);
    // Any station: it lands where it is, at once.
    let (t, plan) = resume(air, 1, Goal::AnyStation).unwrap();
    assert_eq!(t, trip(10_000, 1));
    assert_eq!(plan.path.len(), 1);
    // Off the grid: at N1 at 10.5 s, any station lands at once; N3 at 35.5 s.
    let odd = Resume::Air {
        node: NodeId(1),
        at: Instant(10_500),
        leg_takeoff: Instant(500),
        leg_station: Some(NodeId(0)),
    };
    assert_eq!(
        resume(odd, 1, Goal::Node(NodeId(3))).unwrap().0,
        trip(35_500, 2)
    );
    // On the ground at N2 from 100 s, one leg flown: a second leg to N3 lands at 110 s, one to
    // N0 (20 s away) at 120 s.
    let ground = Resume::Ground {
        station: NodeId(2),
        at: Instant(100_000),
    };
    assert_eq!(
        resume(ground, 1, Goal::Node(NodeId(3))).unwrap().0,
        trip(110_000, 2)
    );
    assert_eq!(
        resume(ground, 1, Goal::Node(NodeId(0))).unwrap().0,
        trip(120_000, 2)
    );
}

// ---------------------------------------------------------------------------------------
// Resuming a trip (docs/reference.md#zones-announced-during-the-day replanning with swaps):
// `Planner::resume` against `multileg::resume`.

/// What the resume property met, to check that the generator reaches every case.
#[derive(Clone, Copy, Debug, Default)]
struct Resumed {
    /// Queries from the air to the destination: answered, of which with a swap still to come,
    /// and unanswerable.
    air: usize,
    air_swapping: usize,
    air_none: usize,
    /// Queries from the ground between legs: answered, unanswerable.
    ground: usize,
    ground_none: usize,
    /// Diversions (from the air to any station): answered, unanswerable.
    diverted: usize,
    diverted_none: usize,
}

impl Resumed {
    fn add(&mut self, o: &Resumed) {
        self.air += o.air;
        self.air_swapping += o.air_swapping;
        self.air_none += o.air_none;
        self.ground += o.ground;
        self.ground_none += o.ground_none;
        self.diverted += o.diverted;
        self.diverted_none += o.diverted_none;
    }
}

/// Plans the day of `instance` without its last zone (with the planner), then takes flight
/// `pick` (modulo the accepted ones; with `swapping`, of those with a swap if any) at the
/// instant `frac`/1000 of the way from its first take-off to its landing (with `swapping`, if
/// it has a swap: of the way through one of its swaps, on the ground), as it then is (in the air: at the first node it reaches at or
/// after that instant; on the ground between legs: free to take off from then or its swap's
/// end), and resumes it against the other flights and every zone, with the planner and the
/// oracle: to its destination, and from the air also to any station. They must agree on
/// whether a trip exists, its landing and its legs (and, diverting, its station); every plan
/// must keep the rules from the resumption on, and to the destination make a well-formed trip
/// with the part already flown.
#[allow(clippy::too_many_lines)]
fn resume_case(
    instance: &Instance,
    pick: usize,
    frac: i64,
    swapping: bool,
) -> Result<Resumed, String> {
    use muse_planner::{Landing, Resume as From};
    let full = instance.build();
    let mut base = instance.clone();
    base.zones.pop();
    let base = base.build();
    let unit = instance.unit;
    let planner = Planner::new(&full.airspace, full.params);
    let mut scratch = Scratch::new();
    let mut day = Schedule::new(&full.airspace, &full.params, &base.closures);
    let context: std::sync::Arc<str> =
        format!("resume {instance:?} pick {pick} frac {frac}").into();
    let outcomes = watched(&context, "(the day)", || {
        muse_planner::plan_day(&planner, &mut day, &base.requests, &mut scratch, |_| {})
    });
    let accepted: Vec<(usize, Plan)> = outcomes
        .into_iter()
        .enumerate()
        .filter_map(|(i, o)| o.result.ok().map(|p| (i, p)))
        .collect();
    let mut counts = Resumed::default();
    if accepted.is_empty() {
        return Ok(counts);
    }
    // With `swapping`, a flight with a swap if there is one.
    let swaps = |p: &Plan| p.leg_count() > 1;
    let candidates: Vec<&(usize, Plan)> = if swapping && accepted.iter().any(|a| swaps(&a.1)) {
        accepted.iter().filter(|a| swaps(&a.1)).collect()
    } else {
        accepted.iter().collect()
    };
    let (f, plan) = candidates[pick % candidates.len()].clone();
    let request = &full.requests[f];
    let others: Vec<(usize, Plan)> = accepted.iter().filter(|a| a.0 != f).cloned().collect();
    let mut schedule = Schedule::new(&full.airspace, &full.params, &full.closures);
    for (i, p) in &others {
        schedule.insert(&full.airspace, FlightId(*i as u64), p);
    }
    let other_plans: Vec<&Plan> = others.iter().map(|a| &a.1).collect();
    let swap = full.params.battery_swap.map_or(0, |s| s.time.0);
    let legs: Vec<&[Stay]> = plan.legs().collect();
    let grounds: Vec<(i64, i64)> = legs
        .windows(2)
        .map(|w| (w[0][w[0].len() - 1].depart.0, w[1][0].arrive.0))
        .filter(|(l, t)| t - l >= 2)
        .collect();
    let n = if swapping && !grounds.is_empty() {
        // Strictly inside the swap.
        let (l, t) = grounds[pick % grounds.len()];
        l + 1 + (t - l - 2) * frac / 1000
    } else {
        plan.takeoff().0 + (plan.landing().0 - plan.takeoff().0) * frac / 1000
    };

    // Where the flight is at `n`: the prefix flown (without the stay resumed from), the
    // oracle's and the planner's starts, and the legs before the part resumed.
    let mut prefix: Vec<Stay> = Vec::new();
    let mut state = None;
    for (k, &leg) in legs.iter().enumerate() {
        // As docs/reference.md#zones-announced-during-the-day replanning sees it
        // (`replan::Commitment::at`): on the ground before leg `k` up to its take-off instant
        // included (k >= 1: n is after the first take-off).
        if n < leg[0].arrive.0 || (k > 0 && n == leg[0].arrive.0) {
            let landed = prefix.last().expect("a leg before").depart.0;
            let at = Instant(n.max(landed + swap));
            let node = leg[0].node;
            let oracle = Resume::Ground { station: node, at };
            let from = From {
                leg_origin: node,
                departure: request.departure,
                node,
                at,
                airborne_since: None,
                first_takeoff: plan.takeoff(),
                legs: k as u32,
            };
            state = Some((oracle, from, k as u32, k as u32));
            break;
        }
        if n <= leg[leg.len() - 1].depart.0 {
            let j = leg
                .iter()
                .position(|s| s.arrive.0 >= n)
                .expect("lands after n");
            prefix.extend_from_slice(&leg[..j]);
            let (node, at, takeoff) = (leg[j].node, leg[j].arrive, leg[0].arrive);
            let oracle = Resume::Air {
                node,
                at,
                leg_takeoff: takeoff,
                leg_station: Some(leg[0].node),
            };
            let from = From {
                leg_origin: leg[0].node,
                departure: request.departure,
                node,
                at,
                airborne_since: Some(takeoff),
                first_takeoff: plan.takeoff(),
                legs: k as u32 + 1,
            };
            // The rest's first leg continues leg `k`: `k` legs before it.
            state = Some((oracle, from, k as u32 + 1, k as u32));
            break;
        }
        prefix.extend_from_slice(leg);
    }
    let Some((oracle_from, from, begun, before)) = state else {
        return Ok(counts);
    };
    let airborne = from.airborne_since.is_some();

    let mut goals = vec![(
        Landing::At(request.destination),
        Goal::Node(request.destination),
    )];
    if airborne {
        goals.push((Landing::AnyStation, Goal::AnyStation));
    }
    for (landing, goal) in goals {
        let divert = matches!(goal, Goal::AnyStation);
        let oracle_from = match (oracle_from, divert) {
            // A diversion may land anywhere, even where its leg took off.
            (
                Resume::Air {
                    node,
                    at,
                    leg_takeoff,
                    ..
                },
                true,
            ) => Resume::Air {
                node,
                at,
                leg_takeoff,
                leg_station: None,
            },
            (o, _) => o,
        };
        let want = multileg::resume(
            &full.airspace,
            &full.params,
            &full.raw,
            &other_plans,
            oracle_from,
            plan.takeoff(),
            begun,
            goal,
            unit,
        );
        let got = watched(&context, &request.id, || {
            planner.resume(&schedule, &from, landing, &mut scratch)
        })
        .result
        .ok();
        let fail = |what: String| {
            format!(
                "{what}\nresume {} ({}→{}) {from:?} to {goal:?}\nflight's plan: {:?}\n\
                 planner: {got:?}\noracle: {want:?}\nothers: {others:?}\nparams: {:?}\n\
                 closures: {:?}",
                request.id,
                request.origin.0,
                request.destination.0,
                plan.path,
                full.params,
                full.raw
            )
        };
        // The whole trip: the part flown, then the rest.
        let whole = |rest: &Plan| {
            let mut path = prefix.clone();
            path.extend_from_slice(&rest.path);
            Plan { path }
        };
        let sound = |rest: &Plan| -> Result<(), String> {
            let first = rest.path.first().ok_or("an empty plan")?;
            let starts = if airborne {
                first.node == from.node && first.arrive == from.at
            } else {
                first.node == from.node && first.arrive >= from.at
            };
            if !starts {
                return Err("does not start where the flight is".into());
            }
            check_rules(&full, &others, rest)?;
            if divert {
                let leg = rest.legs().next().expect("non-empty");
                let lands = leg.len() == rest.path.len()
                    && full.airspace.is_station(leg[leg.len() - 1].node)
                    && rest.landing() - from.airborne_since.expect("airborne")
                        <= full.params.max_flight;
                lands
                    .then_some(())
                    .ok_or_else(|| "not one landing in range".into())
            } else {
                check_trip(&full, request, &whole(rest))
            }
        };
        if let Some((_, rest)) = &want {
            sound(rest).map_err(|v| fail(format!("the ORACLE's plan is unsound: {v}")))?;
        }
        match (&got, &want) {
            (Some(rest), Some((trip, _))) => {
                sound(rest).map_err(|v| fail(format!("unsound plan: {v}")))?;
                let legs = before + rest.leg_count() as u32;
                if (rest.landing(), legs) != (trip.landing, trip.legs) {
                    return Err(fail(format!(
                        "(landing, legs): planner {:?}, oracle {:?}",
                        (rest.landing().0, legs),
                        (trip.landing.0, trip.legs)
                    )));
                }
            }
            (None, None) => {}
            (Some(rest), None) => {
                sound(rest).map_err(|v| fail(format!("unsound plan: {v}")))?;
                return Err(fail("the planner resumed, the oracle cannot".into()));
            }
            (None, Some(_)) => return Err(fail("the oracle resumed, the planner cannot".into())),
        }
        if let (Some(rest), Some((_, mine))) = (&got, &want)
            && divert
            && rest.path.last().map(|s| s.node) != mine.path.last().map(|s| s.node)
        {
            return Err(fail("diverted to another station".into()));
        }
        let found = got.is_some();
        match (divert, airborne) {
            (true, _) => {
                counts.diverted += usize::from(found);
                counts.diverted_none += usize::from(!found);
            }
            (false, true) => {
                counts.air += usize::from(found);
                counts.air_none += usize::from(!found);
                counts.air_swapping += usize::from(got.as_ref().is_some_and(|r| r.leg_count() > 1));
            }
            (false, false) => {
                counts.ground += usize::from(found);
                counts.ground_none += usize::from(!found);
            }
        }
    }
    Ok(counts)
}

/// Runs `cases` random resumptions on instances of `shape`, all with swaps.
fn property_resume(shape: Shape, cases: u32, seed: u64) -> Resumed {
    let total = std::cell::Cell::new(Resumed::default());
    let instances = multileg_instances(shape).prop_map(|mut i| {
        i.swap = i.swap.or(Some(SwapSpec {
            time: i.tau,
            max_legs: None,
        }));
        i
    });
    let swapping = proptest::bool::weighted(0.3);
    let strategy = (instances, 0..100usize, 0..=1000i64, swapping);
    let result = runner(cases, seed).run(&strategy, |(instance, pick, frac, swapping)| {
        let counts = resume_case(&instance, pick, frac, swapping).map_err(TestCaseError::fail)?;
        let mut t = total.get();
        t.add(&counts);
        total.set(t);
        Ok(())
    });
    if let Err(e) = result {
        panic!("seed {seed:#x}: {e}");
    }
    let t = total.get();
    println!("resume {shape:?} (seed {seed:#x}): {t:?}");
    t
}

#[test]
fn resume_matches_multileg_oracle() {
    let t = property_resume(Shape::MULTILEG, 2_000, 0x5eed_0051);
    assert!(
        t.air > 500 && t.air_swapping > 40 && t.air_none > 10 && t.ground > 100,
        "{t:?}"
    );
    assert!(t.diverted > 500 && t.diverted_none > 10, "{t:?}");
}

#[test]
fn resume_matches_multileg_oracle_crowded() {
    let t = property_resume(Shape::MULTILEG_CROWDED, 1_000, 0x5eed_0052);
    assert!(t.air > 200 && t.air_none > 5 && t.ground > 50, "{t:?}");
}
