//! Minimal instances on which the planner once disagreed with the oracle or the verifier.
//! Self-contained: each builds its airspace and traffic by hand and checks the planner's
//! answer with the independent verifier.

use muse_airspace::closures::{Closures, resolve};
use muse_model::testing::{joined, plan as plan_of, request, station};
use muse_model::{
    Airspace, EdgeRule, FlightParams, Instant, Millis, Period, Plan, Request, Speed, Zone,
};
use muse_planner::{FlightId, Planner, Schedule, Scratch};
use muse_verify::{Flight, verify};

/// `A - H - B`, 10 s each at 36 km/h.
fn a_h_b() -> Airspace {
    joined(
        vec![
            station("A", 103.80, 1.3),
            station("H", 103.81, 1.3),
            station("B", 103.82, 1.3),
        ],
        &[("A", "H", 100.0), ("H", "B", 100.0)],
    )
}

/// tau = 0, exclusive edges, no ground delay.
fn tau_zero() -> FlightParams {
    FlightParams {
        speed: Speed::from_kmh(36.0).unwrap(),
        max_flight: Millis::from_secs(100),
        node_separation: Millis::ZERO,
        edge_rule: EdgeRule::Exclusive,
        max_ground_delay: Millis::ZERO,
        battery_swap: None,
        max_trip: None,
        separation: muse_model::Separation::OFF,
    }
}

/// `B` closed during `[0, 25 s)`.
fn b_closed(a: &Airspace) -> Closures {
    let zone = Zone {
        id: "Z".into(),
        name: String::new(),
        restriction: String::new(),
        area: None,
        node_ids: vec!["B".into()],
        edge_ids: vec![],
        announced: None,
        withdrawn: None,
        vertical: muse_model::VerticalLimits::WHOLE_SKY,
        periods: vec![Period {
            start: Some(Instant(0)),
            end: Some(Instant(25_000)),
            daily: vec![],
        }],
    };
    resolve(a, &[zone], Instant(0), Instant(86_400_000)).unwrap()
}

/// Plans A → B (departure 0) against `other` (already accepted) and checks the answer.
fn plan_against(other: &Plan) -> Plan {
    let a = a_h_b();
    let params = tau_zero();
    let closures = b_closed(&a);
    let planner = Planner::new(&a, params);
    let mut schedule = Schedule::new(&a, &params, &closures);
    schedule.insert(&a, FlightId(0), other);
    let other_request = Request {
        id: "other".into(),
        origin: other.path[0].node,
        destination: other.path.last().unwrap().node,
        departure: other.takeoff(),
        submitted: other.takeoff(),
    };
    let request = request("r", 0, 2, 0);
    let plan = planner
        .plan(&schedule, &request, &mut Scratch::new())
        .result
        .expect("a plan exists");
    let flights = [
        Flight::new("other", &other_request, other),
        Flight::new("r", &request, &plan),
    ];
    let violations = verify(&a, &closures, &params, &flights);
    assert!(
        violations.is_empty(),
        "{plan:?}: {}",
        violations
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("; ")
    );
    plan
}

/// With `tau = 0`, another flight's *instantaneous* stay `[12 s, 12 s]` at `H` must not lie
/// strictly inside our stay there: `[10 s, 15 s]` breaks the node rule (`12 >= 15 + 0` and
/// `10 >= 12 + 0` are both false), although no millisecond lies strictly between 12 s - tau and
/// 12 s + tau. The best plan still lands at 25 s (B is closed until then) with take-off 0: hover
/// at A until 2 s, reach H at 12 s exactly (touching is fine) and leave it at 15 s.
///
/// Found by the oracle: the planner returned `A[0,0] H[10 s,15 s] B[25 s]`.
#[test]
fn tau_zero_hover_across_an_instantaneous_stay() {
    // The other flight takes off at H at 12 s and lands at A at 22 s.
    let other = plan_of(&[(1, 12_000, 12_000), (0, 22_000, 22_000)]);
    let plan = plan_against(&other);
    assert_eq!(
        (plan.takeoff(), plan.landing()),
        (Instant(0), Instant(25_000))
    );
}

/// The same with a 1 ms stay `[12 s, 12.001 s]`: no millisecond lies strictly inside it either.
///
/// Found by the oracle (as `[40.999 s, 41 s]` inside a hover `[36 s, 46 s]`).
#[test]
fn tau_zero_hover_across_a_one_millisecond_stay() {
    let other = plan_of(&[(1, 12_000, 12_001), (0, 22_001, 22_001)]);
    let plan = plan_against(&other);
    assert_eq!(
        (plan.takeoff(), plan.landing()),
        (Instant(0), Instant(25_000))
    );
}

/// Touching is allowed with `tau = 0`: the other flight at H during `[10 s, 10 s]`, ours
/// arriving at 10 s and hovering to 15 s (`a_ours >= d_other`).
#[test]
fn tau_zero_touching_stays_are_fine() {
    // A second way into H, from C, so that the other flight does not use A - H.
    let a = joined(
        vec![
            station("A", 103.80, 1.3),
            station("H", 103.81, 1.3),
            station("B", 103.82, 1.3),
            station("C", 103.83, 1.3),
        ],
        &[("A", "H", 100.0), ("H", "B", 100.0), ("C", "H", 100.0)],
    );
    let params = tau_zero();
    let closures = b_closed(&a);
    let planner = Planner::new(&a, params);
    let mut schedule = Schedule::new(&a, &params, &closures);
    let other = plan_of(&[(3, 0, 0), (1, 10_000, 10_000), (3, 20_000, 20_000)]);
    schedule.insert(&a, FlightId(0), &other);
    let request = request("r", 0, 2, 0);
    let plan = planner
        .plan(&schedule, &request, &mut Scratch::new())
        .result
        .unwrap();
    assert_eq!(
        (plan.takeoff(), plan.landing()),
        (Instant(0), Instant(25_000))
    );
}
