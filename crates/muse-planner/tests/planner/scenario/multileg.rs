//! Battery swaps (docs/reference.md#multi-leg-trips) in the random instances: the swap parameters,
//! the shapes and the strategy that draw them, the judging of every multi-leg answer against the
//! multi-leg oracle with checks of a trip by itself and of its rules against the accepted set, and
//! the watchdog that ends a test process whose planner call hangs (tests only).

use std::io::Write as _;
use std::sync::{Arc, Mutex, Once};
use std::thread::ThreadId;
use std::time::{Duration, Instant as Clock};

use muse_model::{EdgeRule, Millis, Plan, RejectReason, Request, Stay};
use muse_planner::Outcome;
use proptest::prelude::*;

use super::{Built, Instance, Shape, Tally, check_valid, describe, instances};
use crate::oracle::multileg;

/// Battery swaps: multi-leg trips with at least `time` units on the ground between legs, at
/// most `max_legs` legs (`None`: unbounded).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SwapSpec {
    /// `S`, units.
    pub time: u32,
    /// `K`.
    pub max_legs: Option<u32>,
}

impl Shape {
    /// For battery swaps ([`multileg_instances`]): short batteries against paths of several
    /// edges, so that many trips need two or three legs (and some cannot be made at all).
    pub const MULTILEG: Shape = Shape {
        nodes: (5, 7),
        edge_secs: (3, 12),
        requests: (5, 20),
        horizon: 100,
        t_max: (6, 24),
        g_max: 30,
        tau: (1, 5),
        zones: 3,
    };

    /// Battery swaps on few nodes with many requests in a short time: heavy conflicts at the
    /// swap stations too.
    pub const MULTILEG_CROWDED: Shape = Shape {
        nodes: (4, 6),
        edge_secs: (2, 10),
        requests: (12, 25),
        horizon: 40,
        t_max: (5, 18),
        g_max: 20,
        tau: (1, 4),
        zones: 2,
    };
}

/// Instances of the given shape (drawn exactly as [`instances`] draws them), half of them with
/// battery swaps: `S` in `0..=6` units, `K` unbounded or `1..=4`.
pub fn multileg_instances(shape: Shape) -> impl Strategy<Value = Instance> {
    let max_legs = prop_oneof![1 => Just(None), 1 => (1..=4u32).prop_map(Some)];
    let swap = prop_oneof![
        1 => Just(None),
        1 => (0..=6u32, max_legs).prop_map(|(time, max_legs)| Some(SwapSpec { time, max_legs })),
    ];
    (instances(shape), swap).prop_map(|(instance, swap)| Instance { swap, ..instance })
}

/// Compares the planner's answer for one request with the multi-leg oracle's
/// (docs/reference.md#multi-leg-trips): free flow, then landing, first take-off and legs or the
/// rejection reason. Both plans must be well-formed trips ([`check_trip`]) that keep every rule
/// against the accepted set ([`check_rules`], written out here) and pass the verifier
/// ([`check_valid`], checked last).
pub(super) fn judge_multileg(
    b: &Built,
    accepted: &[(usize, Plan)],
    request: &Request,
    outcome: &Outcome,
    expected: &multileg::Answer,
    unit: i64,
    tally: &mut Tally,
) -> Result<(), String> {
    let fail = |what: String| {
        let figures = outcome
            .result
            .as_ref()
            .map(|p| (p.landing().0, p.takeoff().0, p.leg_count()));
        format!(
            "{what}\nrequest {} {}→{} dep {}\nplanner: {:?} (landing, first take-off, legs: \
             {figures:?}, free flow {:?})\noracle: {:?}\n{}",
            request.id,
            request.origin.0,
            request.destination.0,
            request.departure.0,
            outcome.result,
            outcome.free_flow,
            expected,
            describe(b, accepted)
        )
    };
    let sound =
        |plan: &Plan| check_trip(b, request, plan).and_then(|()| check_rules(b, accepted, plan));
    // The oracle's own plan must be sound and match its answer.
    if let Some(plan) = &expected.plan {
        sound(plan).map_err(|v| fail(format!("the ORACLE's plan is invalid: {v}")))?;
        let trip = expected.result.expect("a plan means success");
        let figures = (plan.landing(), plan.takeoff(), plan.leg_count());
        if figures != (trip.landing, trip.first_takeoff, trip.legs as usize) {
            return Err(fail("the ORACLE's plan does not match its answer".into()));
        }
    }
    match (&outcome.result, &expected.result) {
        (Ok(plan), Ok(trip)) => {
            sound(plan).map_err(|v| fail(format!("invalid plan: {v}")))?;
            let got = (plan.landing().0, plan.takeoff().0, plan.leg_count());
            let want = (trip.landing.0, trip.first_takeoff.0, trip.legs as usize);
            if got != want {
                return Err(fail(format!(
                    "(landing, first take-off, legs): planner {got:?}, oracle {want:?}"
                )));
            }
        }
        (Err(got), Err(want)) if got == want => {}
        (Ok(plan), Err(_)) => {
            sound(plan).map_err(|v| fail(format!("invalid plan: {v}")))?;
            return Err(fail(
                "the planner found a sound plan, the oracle none".into(),
            ));
        }
        (Err(_), Ok(_)) => {
            return Err(fail("the oracle found a plan, the planner none".into()));
        }
        (Err(_), Err(_)) => return Err(fail("different rejection reasons".into())),
    }
    if outcome.free_flow != expected.free_flow {
        return Err(fail(format!(
            "free flow: planner {:?}, oracle {:?}",
            outcome.free_flow, expected.free_flow
        )));
    }
    // Last, the verifier on both plans (it must accept multi-leg trips).
    if let Some(plan) = &expected.plan {
        check_valid(b, accepted, request, plan)
            .map_err(|v| fail(format!("the verifier rejects the ORACLE's plan: {v}")))?;
    }
    match &outcome.result {
        Ok(plan) => {
            check_valid(b, accepted, request, plan)
                .map_err(|v| fail(format!("the verifier rejects the plan: {v}")))?;
            tally.planned += 1;
            tally.ground_delayed += usize::from(plan.takeoff() > request.departure);
            tally.air_delayed += usize::from(Some(plan.airborne()) > expected.free_flow);
            tally.off_grid += usize::from(plan.takeoff().0 % unit != 0);
            tally.legs[plan.leg_count().clamp(1, 4) - 1] += 1;
            let swap = b.params.battery_swap.map_or(0, |s| s.time.0);
            let legs: Vec<&[Stay]> = plan.legs().collect();
            tally.long_swaps += usize::from(
                legs.windows(2)
                    .any(|w| w[1][0].arrive.0 > w[0][w[0].len() - 1].depart.0 + swap),
            );
        }
        Err(reason) => {
            let k = RejectReason::ALL
                .iter()
                .position(|r| r == reason)
                .unwrap_or(0);
            tally.rejected[k] += 1;
            tally.swap_rejected[k.min(2)] += 1;
        }
    }
    Ok(())
}

/// Whether `plan` is a well-formed trip for `request`
/// (docs/reference.md#flight-model-and-separation, #multi-leg-trips), by itself: it starts at the
/// origin in the take-off window and ends at the destination; every stay has `arrive <= depart`;
/// every leg takes off at a station, follows edges at cruise speed, lands (instantaneous last stay)
/// at another station within `T_max`; the next leg takes off where the previous one landed, at
/// least `S` later; at most `K` legs (one without swaps).
pub fn check_trip(b: &Built, request: &Request, plan: &Plan) -> Result<(), String> {
    let p = &b.params;
    let (Some(first), Some(last)) = (plan.path.first(), plan.path.last()) else {
        return Err("empty plan".into());
    };
    if first.node != request.origin || last.node != request.destination {
        return Err("does not join origin and destination".into());
    }
    let takeoff = plan.takeoff();
    if takeoff < request.departure || takeoff > request.departure + p.max_ground_delay {
        return Err(format!("take-off {} outside the window", takeoff.0));
    }
    if let Some(s) = plan.path.iter().find(|s| s.arrive > s.depart) {
        return Err(format!("stay {s:?} departs before it arrives"));
    }
    let (swap, max_legs) = p
        .battery_swap
        .map_or((Millis(0), 1), |s| (s.time, s.leg_limit()));
    let legs: Vec<&[Stay]> = plan.legs().collect();
    if legs.len() > max_legs as usize {
        return Err(format!("{} legs, at most {max_legs} allowed", legs.len()));
    }
    for (k, leg) in legs.iter().enumerate() {
        let (up, down) = (leg[0], leg[leg.len() - 1]);
        if leg.len() < 2 || up.node == down.node {
            return Err(format!("leg {k} does not go anywhere"));
        }
        if !b.airspace.is_station(up.node) || !b.airspace.is_station(down.node) {
            return Err(format!("leg {k} takes off or lands at a waypoint"));
        }
        if down.arrive != down.depart {
            return Err(format!("leg {k} hovers at its landing"));
        }
        if down.depart - up.arrive > p.max_flight {
            return Err(format!("leg {k} lasts longer than T_max"));
        }
        for w in leg.windows(2) {
            let Some(e) = b.airspace.edge_between(w[0].node, w[1].node) else {
                return Err(format!(
                    "leg {k}: no edge N{}-N{}",
                    w[0].node.0, w[1].node.0
                ));
            };
            let t = Millis(crate::oracle::weight(&b.airspace, p, e));
            if w[1].arrive != w[0].depart + t {
                return Err(format!("leg {k}: traversal of {} not at cruise speed", e.0));
            }
        }
        if k > 0 {
            let landed = legs[k - 1][legs[k - 1].len() - 1];
            if up.arrive < landed.depart + swap {
                return Err(format!("leg {k} takes off less than S after landing"));
            }
        }
    }
    Ok(())
}

/// Whether `plan` keeps the node, edge and zone rules
/// (docs/reference.md#flight-model-and-separation and #no-fly-zones) against the accepted plans and
/// the raw zone windows, every stay and every traversal within a leg of every trip, written out
/// pairwise (independent of the verifier, which checks them too).
pub fn check_rules(built: &Built, accepted: &[(usize, Plan)], plan: &Plan) -> Result<(), String> {
    let params = &built.params;
    let tau = params.node_separation;
    // A traversal: edge, direction, entry, exit.
    let hop = |from: &Stay, to: &Stay| {
        let edge = built
            .airspace
            .edge_between(from.node, to.node)
            .expect("checked");
        let w = Millis(crate::oracle::weight(&built.airspace, params, edge));
        let forward = from.node == built.airspace.edge(edge).from;
        (edge, forward, from.depart, from.depart + w)
    };
    for stay in &plan.path {
        for &(start, end) in &built.raw.nodes[stay.node.index()] {
            if !(stay.depart.0 < start || stay.arrive.0 >= end) {
                return Err(format!("stay {stay:?} in the closure [{start}, {end})"));
            }
        }
        for (i, other) in accepted {
            for o in other.path.iter().filter(|o| o.node == stay.node) {
                if !(stay.arrive >= o.depart + tau || o.arrive >= stay.depart + tau) {
                    return Err(format!("stay {stay:?} too close to {o:?} of flight {i}"));
                }
            }
        }
    }
    for (from, to) in plan.hops() {
        let (edge, forward, enter, leave) = hop(from, to);
        for &(start, end) in &built.raw.edges[edge.index()] {
            if !(leave.0 < start || enter.0 >= end) {
                let at = enter.0;
                return Err(format!(
                    "traversal of {} at {at} in [{start}, {end})",
                    edge.0
                ));
            }
        }
        for (i, other) in accepted {
            for (a, z) in other.hops() {
                let (edge1, forward1, enter1, leave1) = hop(a, z);
                if edge1 != edge {
                    continue;
                }
                let ok = match crate::oracle::rule_of(&built.airspace, params, edge) {
                    EdgeRule::Headway(h) if forward == forward1 => (enter - enter1).0.abs() >= h.0,
                    _ => enter >= leave1 || enter1 >= leave,
                };
                if !ok {
                    return Err(format!(
                        "traversal of {} at {} conflicts with flight {i}'s at {}",
                        edge.0, enter.0, enter1.0
                    ));
                }
            }
        }
    }
    Ok(())
}

/// A planner call that has not answered after this long hangs: a property run cannot time
/// out one case, so the watchdog ([`watched`]) prints the instance and ends the test process.
const HANG: Duration = Duration::from_secs(30);

/// A planner call in progress.
struct Call {
    thread: ThreadId,
    deadline: Clock,
    context: Arc<str>,
    request: String,
}

/// Planner calls in progress.
static CALLS: Mutex<Vec<Call>> = Mutex::new(Vec::new());

fn calls() -> std::sync::MutexGuard<'static, Vec<Call>> {
    CALLS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Runs one planner call for `request` of the instance described by `context` under the
/// watchdog: if it takes longer than [`HANG`], the process prints both and exits.
pub fn watched<T>(context: &Arc<str>, request: &str, call: impl FnOnce() -> T) -> T {
    static WATCHDOG: Once = Once::new();
    WATCHDOG.call_once(|| {
        std::thread::spawn(|| {
            loop {
                std::thread::sleep(Duration::from_secs(1));
                if let Some(c) = calls().iter().find(|c| Clock::now() > c.deadline) {
                    // Straight to the process's stderr: the test harness captures `eprintln!`
                    // (in threads spawned by tests too) and would never show it.
                    let _ = writeln!(
                        std::io::stderr(),
                        "the planner has not answered request {} in {HANG:?}: {}",
                        c.request,
                        c.context
                    );
                    std::process::exit(101);
                }
            }
        });
    });
    let me = std::thread::current().id();
    calls().push(Call {
        thread: me,
        deadline: Clock::now() + HANG,
        context: context.clone(),
        request: request.to_owned(),
    });
    let out = call();
    calls().retain(|c| c.thread != me);
    out
}
