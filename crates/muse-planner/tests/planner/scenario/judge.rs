//! Planning an instance with the planner (batch or online) and judging every answer against
//! the oracle and the verifier.

use std::fmt::Write as _;
use std::sync::Arc;

use muse_model::{Instant, Millis, Plan, RejectReason, Request};
use muse_planner::CancelError;
use muse_planner::{FlightId, Live, Outcome, Planner, Schedule, Scratch};
use muse_verify::{Flight, verify};

use super::multileg::{judge_multileg, watched};
use super::{Built, Instance, Tally};
use crate::oracle;

pub(super) fn describe(b: &Built, accepted: &[(usize, Plan)]) -> String {
    let mut s = String::new();
    let a = &b.airspace;
    let _ = writeln!(s, "params: {:?}", b.params);
    for (i, e) in a.edges().iter().enumerate() {
        let w = crate::oracle::weight(a, &b.params, muse_model::EdgeId(i as u32));
        let _ = writeln!(s, "edge {} w = {w} ms", e.id);
    }
    for n in a.nodes() {
        let _ = writeln!(s, "node {} {:?}", n.id, n.kind);
    }
    let _ = writeln!(s, "closures: {:?}", b.raw);
    for (i, p) in accepted {
        let r = &b.requests[*i];
        let _ = write!(
            s,
            "accepted {} ({}→{}, dep {}):",
            r.id, r.origin.0, r.destination.0, r.departure.0
        );
        for st in &p.path {
            let _ = write!(s, " N{}[{},{}]", st.node.0, st.arrive.0, st.depart.0);
        }
        let _ = writeln!(s);
    }
    s
}

/// Plans the instance's requests in order and checks every answer. Returns what happened,
/// or a description of the first disagreement.
pub fn run(instance: &Instance) -> Result<Tally, String> {
    let context: Arc<str> = format!("batch {instance:?}").into();
    let b = instance.build();
    let planner = Planner::new(&b.airspace, b.params);
    let mut schedule = Schedule::new(&b.airspace, &b.params, &b.closures);
    let mut scratch = Scratch::new();
    let mut accepted: Vec<(usize, Plan)> = Vec::new();
    let mut tally = Tally::default();
    for (i, request) in b.requests.iter().enumerate() {
        // As `plan_day` does: the request's departure is the horizon (exercises the skipping
        // of past reservations, and its reset when an instance is not in departure order).
        schedule.set_horizon(request.departure);
        let outcome = watched(&context, &request.id, || {
            planner.plan(&schedule, request, &mut scratch)
        });
        judge_with_oracle(&b, &accepted, request, &outcome, instance.unit, &mut tally)?;
        if let Ok(plan) = &outcome.result {
            schedule.insert(&b.airspace, FlightId(i as u64), plan);
            accepted.push((i, plan.clone()));
        }
    }
    // The whole accepted set, together.
    check_all(&b, &accepted)?;
    Ok(tally)
}

/// The online path (docs/reference.md#the-planning-service) against the oracle: the instance's
/// requests arrive in their generated order, not by departure, while the clock moves evenly over
/// three quarters of the instance's departures (forgetting the past at every step), so some
/// departures are already past and must be rejected as such; after every third booking, an older
/// booked flight is cancelled (refused once it has taken off). Every answer is compared with the
/// oracle's against the flights still booked, and the final booked set must pass the verifier.
pub fn run_online(instance: &Instance) -> Result<Tally, String> {
    let context: Arc<str> = format!("online {instance:?}").into();
    let mut b = instance.build();
    // Arrival order: the generated order (ids are `r` + the generated index).
    b.requests
        .sort_by_key(|r| r.id[1..].parse::<usize>().expect("numeric ids"));
    let last = b.requests.iter().map(|r| r.departure.0).max().unwrap_or(0);
    let n = b.requests.len().max(1) as i64;
    let planner = Planner::new(&b.airspace, b.params);
    let mut live =
        Live::new(planner, &b.closures, Instant(0)).with_forget_every(Millis(instance.unit));
    let mut accepted: Vec<(usize, Plan)> = Vec::new();
    let mut tally = Tally::default();
    let mut booked = 0usize;
    for (i, request) in b.requests.iter().enumerate() {
        live.advance(Instant(last * 3 * i as i64 / (4 * n)));
        let outcome = watched(&context, &request.id, || {
            live.book(FlightId(i as u64), request)
        });
        if request.departure < live.now() {
            if outcome.result != Err(RejectReason::DepartureInPast) {
                return Err(format!(
                    "request {} departs at {} before now {}: got {:?}",
                    request.id,
                    request.departure.0,
                    live.now().0,
                    outcome.result
                ));
            }
            tally.in_past += 1;
            continue;
        }
        judge_with_oracle(&b, &accepted, request, &outcome, instance.unit, &mut tally)?;
        let Ok(plan) = outcome.result else { continue };
        accepted.push((i, plan));
        booked += 1;
        if !booked.is_multiple_of(3) {
            continue;
        }
        // Cancel an older booking: the one halfway down the list of those still booked.
        let k = accepted.len() / 2;
        let (j, plan) = accepted[k].clone();
        let took_off = plan.takeoff() <= live.now();
        match (live.cancel(FlightId(j as u64)), took_off) {
            (Ok(held), false) if held == plan => {
                accepted.remove(k);
                tally.cancelled += 1;
            }
            (Err(CancelError::TookOff), true) => tally.cancel_refused += 1,
            // Landed, and dropped from the live schedule at the last sweep.
            (Err(CancelError::NotHeld), true) if plan.landing() < live.now() => {
                tally.cancel_refused += 1;
            }
            (other, _) => {
                return Err(format!(
                    "cancel of {} (take-off {}, now {}): {other:?}",
                    b.requests[j].id,
                    plan.takeoff().0,
                    live.now().0
                ));
            }
        }
    }
    check_all(&b, &accepted)?;
    Ok(tally)
}

/// Verifies the whole accepted set together.
fn check_all(b: &Built, accepted: &[(usize, Plan)]) -> Result<(), String> {
    let flights: Vec<Flight<'_>> = accepted
        .iter()
        .map(|(i, plan)| Flight::new(&b.requests[*i].id, &b.requests[*i], plan))
        .collect();
    let violations = verify(&b.airspace, &b.closures, &b.params, &flights);
    if violations.is_empty() {
        return Ok(());
    }
    let list: Vec<String> = violations.iter().map(ToString::to_string).collect();
    Err(format!(
        "the accepted set is invalid:\n{}\n{}",
        list.join("\n"),
        describe(b, accepted)
    ))
}

/// Asks the oracle about `request` against the accepted plans and [`judge`]s the planner's
/// answer with it.
fn judge_with_oracle(
    b: &Built,
    accepted: &[(usize, Plan)],
    request: &Request,
    outcome: &Outcome,
    unit: i64,
    tally: &mut Tally,
) -> Result<(), String> {
    let others: Vec<&Plan> = accepted.iter().map(|(_, p)| p).collect();
    if b.params.battery_swap.is_some() {
        let expected =
            oracle::multileg::solve(&b.airspace, &b.params, &b.raw, &others, request, unit);
        return judge_multileg(b, accepted, request, outcome, &expected, unit, tally);
    }
    let expected = oracle::solve(&b.airspace, &b.params, &b.raw, &others, request, unit);
    judge(b, accepted, request, outcome, &expected, unit, tally)
}

/// Compares the planner's answer for one request with the oracle's, checking both plans with
/// the verifier against the accepted set.
fn judge(
    b: &Built,
    accepted: &[(usize, Plan)],
    request: &Request,
    outcome: &Outcome,
    expected: &oracle::Answer,
    unit: i64,
    tally: &mut Tally,
) -> Result<(), String> {
    let fail = |what: String| {
        format!(
            "{what}\nrequest {} {}→{} dep {}\nplanner: {:?}\noracle: {:?}\n{}",
            request.id,
            request.origin.0,
            request.destination.0,
            request.departure.0,
            outcome.result,
            expected,
            describe(b, accepted)
        )
    };
    if outcome.free_flow != expected.free_flow {
        return Err(fail(format!(
            "free flow: planner {:?}, oracle {:?}",
            outcome.free_flow, expected.free_flow
        )));
    }
    // The oracle's own plan must be valid and match its answer.
    if let Some(plan) = &expected.plan {
        check_valid(b, accepted, request, plan)
            .map_err(|v| fail(format!("the ORACLE's plan is invalid: {v}")))?;
        let (takeoff, landing) = expected.result.expect("a plan means success");
        if (plan.takeoff(), plan.landing()) != (takeoff, landing) {
            return Err(fail("the ORACLE's plan does not match its answer".into()));
        }
    }
    match (&outcome.result, &expected.result) {
        (Ok(plan), Ok((takeoff, landing))) => {
            check_valid(b, accepted, request, plan)
                .map_err(|v| fail(format!("invalid plan: {v}")))?;
            if plan.landing() != *landing {
                return Err(fail(format!(
                    "landing: planner {}, oracle {}",
                    plan.landing().0,
                    landing.0
                )));
            }
            if plan.takeoff() != *takeoff {
                return Err(fail(format!(
                    "take-off: planner {}, oracle {}",
                    plan.takeoff().0,
                    takeoff.0
                )));
            }
            tally.planned += 1;
            tally.ground_delayed += usize::from(plan.takeoff() > request.departure);
            tally.air_delayed += usize::from(Some(plan.airborne()) > expected.free_flow);
            tally.off_grid += usize::from(plan.takeoff().0 % unit != 0);
        }
        (Err(got), Err(want)) if got == want => {
            let k = RejectReason::ALL.iter().position(|r| r == got).unwrap_or(0);
            tally.rejected[k] += 1;
        }
        (Ok(plan), Err(_)) => {
            check_valid(b, accepted, request, plan)
                .map_err(|v| fail(format!("invalid plan: {v}")))?;
            return Err(fail(
                "the planner found a valid plan, the oracle none".into(),
            ));
        }
        (Err(_), Ok(_)) => {
            return Err(fail("the oracle found a plan, the planner none".into()));
        }
        (Err(_), Err(_)) => return Err(fail("different rejection reasons".into())),
    }
    Ok(())
}

/// Verifies `plan` for `request` together with the accepted plans.
pub fn check_valid(
    b: &Built,
    accepted: &[(usize, Plan)],
    request: &Request,
    plan: &Plan,
) -> Result<(), String> {
    let mut flights: Vec<Flight<'_>> = accepted
        .iter()
        .map(|(i, p)| Flight::new(&b.requests[*i].id, &b.requests[*i], p))
        .collect();
    flights.push(Flight::new(&request.id, request, plan));
    let violations = verify(&b.airspace, &b.closures, &b.params, &flights);
    if violations.is_empty() {
        Ok(())
    } else {
        let list: Vec<String> = violations.iter().map(ToString::to_string).collect();
        Err(list.join("; "))
    }
}
