//! The rules of one flight alone: its path (docs/reference.md#flight-model-and-separation), its
//! legs (docs/reference.md#multi-leg-trips), battery and ground delay.

use std::ops::Range;

use muse_model::{Airspace, FlightParams, UtcOffset};

use crate::legs::{check_legs, prefix, split};
use crate::{
    Ending, Flight, Rule, Violation, dur, edge_of, node_name, single, stamp, traversal_time,
};

/// Path rules of one flight, the rules of its legs, then its battery and ground-delay rules.
pub(crate) fn check_flight(
    airspace: &Airspace,
    params: &FlightParams,
    flight: &Flight<'_>,
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let one = |rule, element: String, detail: String| single(rule, flight, element, detail);
    let path = &flight.plan.path;
    let (Some(first), Some(last)) = (path.first(), path.last()) else {
        out.push(one(
            Rule::Path,
            String::new(),
            "the plan has no stays".into(),
        ));
        return;
    };
    let request = flight.request;
    if first.node != request.origin {
        out.push(one(
            Rule::Path,
            node_name(airspace, first.node),
            format!(
                "the plan starts at `{}`, the request's origin is `{}`",
                node_name(airspace, first.node),
                node_name(airspace, request.origin)
            ),
        ));
    }
    let stranded = flight.ending == Ending::Committed;
    if flight.ending == Ending::Diverted
        && (last.node.index() >= airspace.node_count() || !airspace.is_station(last.node))
    {
        out.push(one(
            Rule::Path,
            node_name(airspace, last.node),
            format!(
                "the diverted plan ends at `{}`, which is not a station",
                node_name(airspace, last.node)
            ),
        ));
    }
    if flight.ending == Ending::Destination && last.node != request.destination {
        out.push(one(
            Rule::Path,
            node_name(airspace, last.node),
            format!(
                "the plan ends at `{}`, the request's destination is `{}`",
                node_name(airspace, last.node),
                node_name(airspace, request.destination)
            ),
        ));
    }
    for (i, stay) in path.iter().enumerate() {
        if stay.node.index() >= airspace.node_count() {
            out.push(one(
                Rule::Path,
                stay.node.to_string(),
                format!("stay {i} is at a node that is not in the airspace"),
            ));
        }
        if stay.arrive > stay.depart {
            out.push(one(
                Rule::Path,
                node_name(airspace, stay.node),
                format!(
                    "stay {i} arrives at {} after it departs at {}",
                    stamp(stay.arrive, offset),
                    stamp(stay.depart, offset)
                ),
            ));
        }
    }
    let legs = split(airspace, path);
    check_hops(airspace, params, flight, &legs, out, offset);
    check_legs(airspace, params, flight, &legs, out, offset);
    if last.depart != last.arrive {
        let what = if stranded {
            "a committed part must end with its arrival"
        } else {
            "the last stay must end at landing"
        };
        out.push(one(
            Rule::Path,
            node_name(airspace, last.node),
            format!(
                "{what}: it arrives at {} and departs at {}",
                stamp(last.arrive, offset),
                stamp(last.depart, offset)
            ),
        ));
    }
    check_times(params, flight, &legs, out, offset);
}

/// Path rules between consecutive stays of each leg: joined by an edge,
/// `arrive_{i+1} = depart_i + w(e)`. In a multi-leg plan the messages name the leg.
fn check_hops(
    airspace: &Airspace,
    params: &FlightParams,
    flight: &Flight<'_>,
    legs: &[Range<usize>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let one = |rule, element: String, detail: String| single(rule, flight, element, detail);
    let path = &flight.plan.path;
    for (k, leg) in legs.iter().enumerate() {
        let prefix = prefix(legs.len(), k);
        for i in leg.start..leg.end - 1 {
            let (x, y) = (path[i], path[i + 1]);
            let Some(e) = edge_of(airspace, x.node, y.node) else {
                out.push(one(
                    Rule::Path,
                    format!(
                        "{}-{}",
                        node_name(airspace, x.node),
                        node_name(airspace, y.node)
                    ),
                    format!("{prefix}stays {i} and {} are not joined by an edge", i + 1),
                ));
                continue;
            };
            let w = traversal_time(airspace, params, e);
            if y.arrive != x.depart + w {
                out.push(one(
                    Rule::Path,
                    crate::edge_name(airspace, e),
                    format!(
                        "{prefix}departs `{}` at {} and arrives at `{}` at {}; the traversal \
                         takes {}, so the arrival must be {}",
                        node_name(airspace, x.node),
                        stamp(x.depart, offset),
                        node_name(airspace, y.node),
                        stamp(y.arrive, offset),
                        dur(w),
                        stamp(x.depart + w, offset)
                    ),
                ));
            }
        }
    }
}

/// Battery (per leg) and ground-delay (first take-off) rules of one flight.
fn check_times(
    params: &FlightParams,
    flight: &Flight<'_>,
    legs: &[Range<usize>],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let one = |rule, detail: String| Violation {
        rule,
        flights: vec![flight.id.to_string()],
        element: String::new(),
        detail,
    };
    let path = &flight.plan.path;
    for (k, leg) in legs.iter().enumerate() {
        let (takeoff, landing) = (path[leg.start].arrive, path[leg.end - 1].depart);
        if landing - takeoff > params.max_flight {
            let prefix = prefix(legs.len(), k);
            out.push(one(
                Rule::Battery,
                format!(
                    "{prefix}airborne {} (take-off {}, landing {}), more than T_max = {}",
                    dur(landing - takeoff),
                    stamp(takeoff, offset),
                    stamp(landing, offset),
                    dur(params.max_flight)
                ),
            ));
        }
    }
    let request = flight.request;
    if let (Ending::Destination, Some(m)) = (flight.ending, params.max_trip) {
        let landing = flight.plan.landing();
        if landing > request.departure + m {
            out.push(one(
                Rule::Deadline,
                format!(
                    "lands at {}, later than {} (departure {} + the delivery deadline {})",
                    stamp(landing, offset),
                    stamp(request.departure + m, offset),
                    stamp(request.departure, offset),
                    dur(m)
                ),
            ));
        }
    }
    let takeoff = flight.plan.takeoff();
    let latest = request.departure + params.max_ground_delay;
    if takeoff < request.departure || takeoff > latest {
        out.push(one(
            Rule::GroundDelay,
            format!(
                "take-off at {} is outside [{}, {}] (departure {}, G_max = {})",
                stamp(takeoff, offset),
                stamp(request.departure, offset),
                stamp(latest, offset),
                stamp(request.departure, offset),
                dur(params.max_ground_delay)
            ),
        ));
    }
}
