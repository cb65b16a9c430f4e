//! Multi-leg trips (docs/reference.md#multi-leg-trips): how a plan splits into legs, the rules of
//! each leg, and the battery swaps that chain them.
//!
//! A plan lists the stays of all its legs in order. The verifier reads a leg boundary between
//! two consecutive stays
//!
//! - at the same node: the landing `(X, l, l)` and the next take-off `(X, t, d)` (the model's
//!   encoding, [`Plan::legs`](muse_model::Plan::legs)); or
//! - at two stations that no edge joins, where the first stay is instantaneous and reached by a
//!   traversal: a landing at `X` followed by a take-off at another station `Y`. Such a plan does
//!   not chain, and says so ([`Rule::Swap`]), rather than a mere missing edge.
//!
//! Everything between two boundaries is one leg; its consecutive stays must be traversals
//! (checked in `path.rs`).

use std::ops::Range;

use muse_model::{Airspace, FlightParams, NodeId, Stay, UtcOffset};

use crate::{Ending, Flight, Rule, Violation, dur, edge_of, node_name, single, span, stamp};

/// The legs of `path`, as ranges of stay indices, in order (none for an empty path).
pub(crate) fn split(airspace: &Airspace, path: &[Stay]) -> Vec<Range<usize>> {
    let mut legs = Vec::new();
    let mut start = 0;
    for i in 1..path.len() {
        let (x, y) = (&path[i - 1], &path[i]);
        let swap = x.node == y.node;
        let jump = i - 1 > start
            && x.arrive == x.depart
            && station(airspace, x.node)
            && station(airspace, y.node)
            && edge_of(airspace, x.node, y.node).is_none();
        if swap || jump {
            legs.push(start..i);
            start = i;
        }
    }
    if !path.is_empty() {
        legs.push(start..path.len());
    }
    legs
}

fn station(airspace: &Airspace, n: NodeId) -> bool {
    n.index() < airspace.node_count() && airspace.is_station(n)
}

/// How messages name leg `k` (0-based) of `count`: `the plan` for a single leg, else `leg 2`.
fn label(count: usize, k: usize) -> String {
    if count == 1 {
        "the plan".into()
    } else {
        format!("leg {}", k + 1)
    }
}

/// What a message about leg `k` of `count` starts with: nothing for a single leg (the
/// messages of the paper's plans are unchanged), else `leg 2: `.
pub(crate) fn prefix(count: usize, k: usize) -> String {
    if count == 1 {
        String::new()
    } else {
        format!("{}: ", label(count, k))
    }
}

/// The rules of the legs themselves: how many there may be, how they chain (same station, at
/// least `S` apart), and the shape of each (flies an edge, lands instantaneously at a station
/// other than its take-off station).
pub(crate) fn check_legs(
    airspace: &Airspace,
    params: &FlightParams,
    flight: &Flight<'_>,
    legs: &[Range<usize>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    check_count(airspace, params, flight, legs, out, offset);
    check_chain(airspace, params, flight, legs, out, offset);
    check_shape(airspace, flight, legs, out, offset);
}

/// More than one leg with swaps off, or more than `K` legs.
fn check_count(
    airspace: &Airspace,
    params: &FlightParams,
    flight: &Flight<'_>,
    legs: &[Range<usize>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let n = legs.len();
    if n < 2 {
        return;
    }
    let path = &flight.plan.path;
    match params.battery_swap {
        None => {
            let (landing, takeoff) = (&path[legs[0].end - 1], &path[legs[1].start]);
            out.push(single(
                Rule::Swap,
                flight,
                String::new(),
                format!(
                    "the plan has {n} legs (leg 1 lands at `{}` at {}, leg 2 takes off from `{}` \
                     at {}) but battery swaps are off: a trip is a single leg",
                    node_name(airspace, landing.node),
                    stamp(landing.depart, offset),
                    node_name(airspace, takeoff.node),
                    stamp(takeoff.arrive, offset)
                ),
            ));
        }
        Some(swap) => {
            if let Some(k) = swap.max_legs
                && n > k as usize
            {
                out.push(single(
                    Rule::Swap,
                    flight,
                    String::new(),
                    format!("the plan has {n} legs, more than the K = {k} allowed"),
                ));
            }
        }
    }
}

/// Leg `i + 1` takes off where leg `i` landed, at least `S` after the landing.
fn check_chain(
    airspace: &Airspace,
    params: &FlightParams,
    flight: &Flight<'_>,
    legs: &[Range<usize>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let path = &flight.plan.path;
    for (k, pair) in legs.windows(2).enumerate() {
        let (landing, takeoff) = (&path[pair[0].end - 1], &path[pair[1].start]);
        let (here, there) = (
            node_name(airspace, landing.node),
            node_name(airspace, takeoff.node),
        );
        if landing.node != takeoff.node {
            out.push(single(
                Rule::Swap,
                flight,
                there.clone(),
                format!(
                    "the legs do not chain: leg {} takes off from `{there}` at {}, but leg {} \
                     landed at `{here}` at {}; a leg must take off from the station where the \
                     previous one landed",
                    k + 2,
                    stamp(takeoff.arrive, offset),
                    k + 1,
                    stamp(landing.depart, offset)
                ),
            ));
            continue;
        }
        // With swaps off the plan is already rejected as a whole (see `check_count`).
        let Some(swap) = params.battery_swap else {
            continue;
        };
        let earliest = landing.depart + swap.time;
        if takeoff.arrive < earliest {
            out.push(single(
                Rule::Swap,
                flight,
                here.clone(),
                format!(
                    "the legs do not chain: leg {} takes off from `{here}` at {}, less than the \
                     battery swap time S = {} after leg {} landed there at {} (not before {})",
                    k + 2,
                    stamp(takeoff.arrive, offset),
                    dur(swap.time),
                    k + 1,
                    stamp(landing.depart, offset),
                    stamp(earliest, offset)
                ),
            ));
        }
    }
}

/// Each leg flies at least one edge; every leg but the last lands (instantaneously, at a
/// station); a leg lands at another station than the one it took off from.
///
/// The last leg's landing is checked with the plan's ending (`path.rs`). A diverted flight's
/// last leg may land where it took off (turning back is a diversion), and the last leg of a
/// contingency's committed part does not land at all.
fn check_shape(
    airspace: &Airspace,
    flight: &Flight<'_>,
    legs: &[Range<usize>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let path = &flight.plan.path;
    let n = legs.len();
    let mut push = |element: String, detail: String| {
        out.push(single(Rule::Path, flight, element, detail));
    };
    for (k, leg) in legs.iter().enumerate() {
        let last_leg = k + 1 == n;
        if last_leg && flight.ending == Ending::Committed {
            continue;
        }
        let (first, last) = (&path[leg.start], &path[leg.end - 1]);
        let (from, to) = (
            node_name(airspace, first.node),
            node_name(airspace, last.node),
        );
        let name = label(n, k);
        if leg.len() < 2 {
            push(
                from.clone(),
                format!(
                    "{name} has a single stay, at `{from}` {}: a leg must fly at least one edge",
                    span(first.arrive, first.depart, offset)
                ),
            );
            continue;
        }
        if !last_leg {
            if last.arrive != last.depart {
                push(
                    to.clone(),
                    format!(
                        "{name} must end at landing: its last stay, at `{to}`, arrives at {} and \
                         departs at {}",
                        stamp(last.arrive, offset),
                        stamp(last.depart, offset)
                    ),
                );
            }
            if last.node.index() < airspace.node_count() && !airspace.is_station(last.node) {
                push(
                    to.clone(),
                    format!("{name} lands at `{to}`, which is not a station"),
                );
            }
        }
        if first.node == last.node && (!last_leg || flight.ending == Ending::Destination) {
            push(
                to.clone(),
                format!(
                    "{name} takes off from and lands at `{to}`: a leg must land at another \
                     station than the one it took off from"
                ),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use muse_airspace::closures::Closures;
    use muse_model::{BatterySwap, Instant, Millis, Plan, Request};

    use crate::tests::{W, airspace, airspace_with, closures, params, plan, request, rules};
    use crate::{Ending, Flight, Rule, Violation, verify};

    use super::*;

    /// Swaps of 30 s, no bound on the legs.
    fn swaps() -> FlightParams {
        FlightParams {
            battery_swap: Some(BatterySwap::new(Millis::from_secs(30))),
            ..params()
        }
    }

    /// A plan of legs, each `(take-off, [(node, hover)])` as in [`plan`].
    fn legs(a: &Airspace, legs: &[(i64, &[(&str, i64)])]) -> Plan {
        Plan {
            path: legs
                .iter()
                .flat_map(|&(t, nodes)| plan(a, t, nodes).path)
                .collect(),
        }
    }

    fn one_with(a: &Airspace, pr: &FlightParams, p: &Plan, ending: Ending) -> Vec<Violation> {
        let r = request(a, p, p.takeoff().0);
        let r = Request {
            destination: a.node_id("C").unwrap(),
            ..r
        };
        verify(
            a,
            &Closures::none(a),
            pr,
            &[Flight::new("f0", &r, p).ending(ending)],
        )
    }

    /// Verifies one flight to `C`.
    fn one(pr: &FlightParams, p: &Plan) -> Vec<Violation> {
        one_with(&airspace(), pr, p, Ending::Destination)
    }

    fn two_legs(a: &Airspace, second: i64) -> Plan {
        legs(
            a,
            &[(0, &[("A", 0), ("B", 0)]), (second, &[("B", 0), ("C", 0)])],
        )
    }

    fn three_legs(a: &Airspace) -> Plan {
        legs(
            a,
            &[
                (0, &[("A", 0), ("B", 0)]),
                (40_000, &[("B", 0), ("D", 0)]),
                (80_000, &[("D", 0), ("B", 0), ("C", 0)]),
            ],
        )
    }

    #[test]
    fn split_reads_swaps_and_jumps() {
        let a = airspace();
        assert_eq!(split(&a, &[]), []);
        assert_eq!(split(&a, &three_legs(&a).path), [0..2, 2..4, 4..7]);
        // Landing at C, taking off at D (not joined): a boundary. A first stay is never a
        // landing, so A -> C is one leg with a missing edge.
        let jump = legs(
            &a,
            &[(0, &[("A", 0), ("B", 0), ("C", 0)]), (50_000, &[("D", 0)])],
        );
        assert_eq!(split(&a, &jump.path), [0..3, 3..4]);
        let first = legs(&a, &[(0, &[("A", 0)]), (50_000, &[("C", 0)])]);
        assert_eq!(split(&a, &first.path).len(), 1);
        // Hovering at C: not a landing.
        let hover = legs(
            &a,
            &[(0, &[("A", 0), ("B", 0), ("C", 1)]), (50_000, &[("D", 0)])],
        );
        assert_eq!(split(&a, &hover.path).len(), 1);
    }

    #[test]
    fn valid_two_and_three_leg_plans() {
        let a = airspace();
        // Exactly S on the ground at B.
        assert_eq!(one(&swaps(), &two_legs(&a, 40_000)), []);
        assert_eq!(one(&swaps(), &three_legs(&a)), []);
        // The battery limit is per leg: 25 s per leg, 100 s for the whole trip.
        let short = FlightParams {
            max_flight: Millis::from_secs(25),
            battery_swap: Some(BatterySwap {
                time: Millis::from_secs(30),
                max_legs: Some(3),
            }),
            ..params()
        };
        assert_eq!(one(&short, &three_legs(&a)), []);
        // Ground delay concerns the first take-off only.
        let p = three_legs(&a);
        let r = Request {
            destination: a.node_id("C").unwrap(),
            ..request(&a, &p, -30_000)
        };
        let v = verify(
            &a,
            &Closures::none(&a),
            &short,
            &[Flight::new("f0", &r, &p)],
        );
        assert_eq!(v, []);
    }

    #[test]
    fn legs_with_swaps_off() {
        let a = airspace();
        let v = one(&params(), &two_legs(&a, 40_000));
        assert_eq!(rules(&v), [Rule::Swap]);
        assert_eq!(
            v[0].to_string(),
            "swap rule violated by f0: the plan has 2 legs (leg 1 lands at `B` at 1970-01-01T00:00:10.000+00:00, \
             leg 2 takes off from `B` at 1970-01-01T00:00:40.000+00:00) but battery swaps are off: a trip is a single leg"
        );
    }

    #[test]
    fn too_many_legs() {
        let a = airspace();
        let two = FlightParams {
            battery_swap: Some(BatterySwap {
                time: Millis::from_secs(30),
                max_legs: Some(2),
            }),
            ..params()
        };
        assert_eq!(one(&two, &two_legs(&a, 40_000)), []);
        let v = one(&two, &three_legs(&a));
        assert_eq!(rules(&v), [Rule::Swap]);
        assert_eq!(
            v[0].to_string(),
            "swap rule violated by f0: the plan has 3 legs, more than the K = 2 allowed"
        );
    }

    #[test]
    fn swap_shorter_than_s() {
        let a = airspace();
        let v = one(&swaps(), &two_legs(&a, 39_999));
        assert_eq!(rules(&v), [Rule::Swap]);
        assert_eq!(
            v[0].to_string(),
            "swap rule violated by f0 at `B`: the legs do not chain: leg 2 takes off from `B` at \
             1970-01-01T00:00:39.999+00:00, less than the battery swap time S = 30.000s after leg 1 landed there at \
             1970-01-01T00:00:10.000+00:00 (not before 1970-01-01T00:00:40.000+00:00)"
        );
        // Taking off before landing, in the third leg.
        let mut p = three_legs(&a);
        for stay in &mut p.path[4..] {
            stay.arrive = Instant(stay.arrive.0 - 75_000);
            stay.depart = Instant(stay.depart.0 - 75_000);
        }
        let v = one(&swaps(), &p);
        assert_eq!(rules(&v), [Rule::Swap]);
        assert!(
            v[0].detail
                .contains("leg 3 takes off from `D` at 1970-01-01T00:00:05.000+00:00, less than"),
            "{}",
            v[0]
        );
    }

    #[test]
    fn leg_taking_off_elsewhere() {
        let a = airspace();
        // Lands at C, takes off at D: C and D are not joined.
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 0), ("C", 0)]),
                (50_000, &[("D", 0), ("B", 0), ("C", 0)]),
            ],
        );
        let v = one(&swaps(), &p);
        assert_eq!(rules(&v), [Rule::Swap], "{v:#?}");
        assert_eq!(
            v[0].to_string(),
            "swap rule violated by f0 at `D`: the legs do not chain: leg 2 takes off from `D` \
             at 1970-01-01T00:00:50.000+00:00, but leg 1 landed at `C` at 1970-01-01T00:00:20.000+00:00; a leg must take off from the \
             station where the previous one landed"
        );
    }

    #[test]
    fn battery_per_leg() {
        let a = airspace();
        let pr = FlightParams {
            max_flight: Millis::from_secs(15),
            ..swaps()
        };
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 0)]),
                (40_000, &[("B", 6_000), ("C", 0)]),
            ],
        );
        let v = one(&pr, &p);
        assert_eq!(rules(&v), [Rule::Battery]);
        assert_eq!(
            v[0].to_string(),
            "battery rule violated by f0: leg 2: airborne 16.000s (take-off 1970-01-01T00:00:40.000+00:00, landing \
             1970-01-01T00:00:56.000+00:00), more than T_max = 15.000s"
        );
    }

    #[test]
    fn leg_shapes() {
        let a = airspace_with(&["D"]);
        let pr = swaps();
        let check = |p: &Plan| one_with(&a, &pr, p, Ending::Destination);
        // Hovering before the intermediate landing.
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 3_000)]),
                (43_000, &[("B", 0), ("C", 0)]),
            ],
        );
        let v = check(&p);
        assert_eq!(rules(&v), [Rule::Path]);
        assert_eq!(
            v[0].to_string(),
            "path rule violated by f0 at `B`: leg 1 must end at landing: its last stay, at `B`, \
             arrives at 1970-01-01T00:00:10.000+00:00 and departs at 1970-01-01T00:00:13.000+00:00"
        );
        // Landing at a waypoint.
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 0), ("D", 0)]),
                (50_000, &[("D", 0), ("B", 0), ("C", 0)]),
            ],
        );
        let v = check(&p);
        assert_eq!(rules(&v), [Rule::Path]);
        assert_eq!(v[0].detail, "leg 1 lands at `D`, which is not a station");
        // A leg back to where it took off.
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 0), ("A", 0)]),
                (50_000, &[("A", 0), ("B", 0), ("C", 0)]),
            ],
        );
        let v = check(&p);
        assert_eq!(rules(&v), [Rule::Path]);
        assert_eq!(v[0].element, "A");
        assert_eq!(
            v[0].detail,
            "leg 1 takes off from and lands at `A`: a leg must land at another station than \
             the one it took off from"
        );
        // A leg that flies no edge.
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 0)]),
                (40_000, &[("B", 0)]),
                (70_000, &[("B", 0), ("C", 0)]),
            ],
        );
        let v = check(&p);
        assert_eq!(rules(&v), [Rule::Path]);
        assert_eq!(
            v[0].detail,
            "leg 2 has a single stay, at `B` [1970-01-01T00:00:40.000+00:00, 1970-01-01T00:00:40.000+00:00]: a leg must fly at least one edge"
        );
        // The last leg back to the station it took off from, at the destination.
        let p = legs(
            &a,
            &[
                (0, &[("A", 0), ("B", 0), ("C", 0)]),
                (50_000, &[("C", 0), ("B", 0), ("C", 0)]),
            ],
        );
        assert_eq!(rules(&check(&p)), [Rule::Path]);
        // ... is a fine diversion, though.
        assert_eq!(one_with(&a, &pr, &p, Ending::Diverted), []);
    }

    #[test]
    fn hops_of_a_multi_leg_plan_name_their_leg() {
        let a = airspace();
        let mut p = two_legs(&a, 40_000);
        p.path[3].arrive = Instant(50_001);
        p.path[3].depart = Instant(50_001);
        let v = one(&swaps(), &p);
        assert_eq!(rules(&v), [Rule::Path]);
        assert_eq!(v[0].element, "B-C");
        assert!(
            v[0].detail
                .starts_with("leg 2: departs `B` at 1970-01-01T00:00:40.000+00:00"),
            "{}",
            v[0]
        );
    }

    #[test]
    fn committed_part_of_a_multi_leg_trip() {
        let a = airspace();
        // Stranded at D during the second leg, which does not land.
        let p = legs(
            &a,
            &[(0, &[("A", 0), ("B", 0)]), (40_000, &[("B", 0), ("D", 0)])],
        );
        assert_eq!(one_with(&a, &swaps(), &p, Ending::Committed), []);
        // Its first leg must still be whole.
        let p = legs(
            &a,
            &[(0, &[("A", 0), ("B", 1)]), (50_000, &[("B", 0), ("D", 0)])],
        );
        let v = one_with(&a, &swaps(), &p, Ending::Committed);
        assert_eq!(rules(&v), [Rule::Path]);
        assert!(
            v[0].detail.starts_with("leg 1 must end at landing"),
            "{}",
            v[0]
        );
    }

    #[test]
    fn ground_time_between_legs_occupies_nothing() {
        let a = airspace();
        let pr = swaps();
        let first = two_legs(&a, 40_000); // on the ground at B during (10 s, 40 s)
        let through = |arrive: i64| plan(&a, arrive - W, &[("D", 0), ("B", 0), ("E", 0)]);
        let both = |other: Plan| {
            let plans = [first.clone(), other];
            let requests: Vec<Request> = plans
                .iter()
                .map(|p| request(&a, p, p.takeoff().0))
                .collect();
            let flights = [
                Flight::new("f0", &requests[0], &plans[0]),
                Flight::new("f1", &requests[1], &plans[1]),
            ];
            verify(&a, &Closures::none(&a), &pr, &flights)
        };
        // tau = 5 s after the landing, tau before the take-off.
        assert_eq!(both(through(15_000)), []);
        assert_eq!(both(through(35_000)), []);
        let v = both(through(14_999));
        assert_eq!(rules(&v), [Rule::Node]);
        assert!(
            v[0].detail
                .contains("[1970-01-01T00:00:10.000+00:00, 1970-01-01T00:00:10.000+00:00]"),
            "{}",
            v[0]
        );
        let v = both(through(35_001));
        assert_eq!(rules(&v), [Rule::Node]);
        assert!(
            v[0].detail
                .contains("[1970-01-01T00:00:40.000+00:00, 1970-01-01T00:00:40.000+00:00]"),
            "{}",
            v[0]
        );

        // A closure of B while the drone is on the ground there: nothing to break.
        let zone = closures(&["B"], &[], 11_000, 40_000);
        let p = first.clone();
        let r = Request {
            destination: a.node_id("C").unwrap(),
            ..request(&a, &p, 0)
        };
        assert_eq!(verify(&a, &zone, &pr, &[Flight::new("f0", &r, &p)]), []);
        // Until the take-off.
        let zone = closures(&["B"], &[], 11_000, 40_001);
        let v = verify(&a, &zone, &pr, &[Flight::new("f0", &r, &p)]);
        assert_eq!(rules(&v), [Rule::Zone]);
        assert!(
            v[0].detail
                .contains("stay [1970-01-01T00:00:40.000+00:00, 1970-01-01T00:00:40.000+00:00]"),
            "{}",
            v[0]
        );
    }
}
