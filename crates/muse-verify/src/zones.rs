//! The zone rule (SPEC §4), with zones announced during the day (SPEC §11).

use muse_airspace::announced::Announced;
use muse_airspace::closures::{Closures, Window};
use muse_model::{Airspace, FlightParams, Instant, UtcOffset};

use crate::{Ending, Flight, Rule, Violation, edge_of, node_name, span, stamp, traversal_time};

/// Whether an occupation `[a, d]` shares an instant with the window `[start, end)`:
/// it is allowed only when `d < start` or `a >= end` (SPEC §4).
fn shares_instant(w: Window, a: Instant, d: Instant) -> bool {
    !(d < w.start || a >= w.end)
}

/// Zone rule for every stay and traversal of one flight (of every leg: on the ground between
/// two legs the drone is outside the airspace).
pub(crate) fn zone_rule(
    airspace: &Airspace,
    closures: &Closures,
    announced: &[Announced],
    params: &FlightParams,
    flight: &Flight<'_>,
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let mut push = |element: String, what: &str, a: Instant, d: Instant, w: Window, by: &str| {
        out.push(Violation {
            rule: Rule::Zone,
            flights: vec![flight.id.to_string()],
            element,
            detail: format!(
                "{what} {} shares an instant with the closure [{}, {}){by}",
                span(a, d, offset),
                stamp(w.start, offset),
                stamp(w.end, offset)
            ),
        });
    };
    // The zones that bind an occupation beginning at `t`: those known from the start, and
    // the announced ones announced by then (SPEC §11).
    let binding = |t: Instant| {
        std::iter::once((closures, String::new())).chain(
            announced.iter().filter(move |a| a.binds(t)).map(|a| {
                (
                    &a.closures,
                    format!(" of zone `{}` announced at {}", a.zone, stamp(a.at, offset)),
                )
            }),
        )
    };
    if flight.ending == Ending::Committed {
        return; // a contingency: see the crate docs
    }
    let path = &flight.plan.path;
    for stay in path {
        if stay.node.index() >= airspace.node_count() {
            continue;
        }
        for (layer, by) in binding(stay.arrive) {
            for &w in layer.node(stay.node) {
                if shares_instant(w, stay.arrive, stay.depart) {
                    push(
                        node_name(airspace, stay.node),
                        "stay",
                        stay.arrive,
                        stay.depart,
                        w,
                        &by,
                    );
                }
            }
        }
    }
    for (x, y) in flight.plan.hops() {
        let Some(e) = edge_of(airspace, x.node, y.node) else {
            continue;
        };
        let s = x.depart;
        let f = s + traversal_time(airspace, params, e);
        for (layer, by) in binding(s) {
            for &w in layer.edge(e) {
                if shares_instant(w, s, f) {
                    push(airspace.edge(e).id.clone(), "traversal", s, f, w, &by);
                }
            }
        }
    }
}
