//! The rules between flights: node separation and edge separation
//! (docs/reference.md#flight-model-and-separation), checked per element on occupations sorted by
//! start.

use muse_model::{
    Airspace, EdgeId, EdgeKind, EdgeRule, FlightParams, Instant, NodeId, Plan, UtcOffset,
};

use crate::{Flight, Rule, Violation, dur, edge_of, node_name, span, stamp, traversal_time};

/// A stay `[start, end]` at a node, or a traversal `[start, end]` of an edge.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Occupation {
    /// Index into the `flights` slice.
    flight: usize,
    start: Instant,
    end: Instant,
    /// For traversals: whether the edge is flown from `Edge::from` to `Edge::to`.
    forward: bool,
}

/// Stays per node and traversals per edge of one plan (of every leg; the time on the ground
/// between two legs is neither).
pub(crate) fn collect(
    airspace: &Airspace,
    params: &FlightParams,
    flight: usize,
    plan: &Plan,
    stays: &mut [Vec<Occupation>],
    traversals: &mut [Vec<Occupation>],
) {
    for stay in &plan.path {
        if let Some(list) = stays.get_mut(stay.node.index()) {
            list.push(Occupation {
                flight,
                start: stay.arrive,
                end: stay.depart,
                forward: true,
            });
        }
    }
    for (x, y) in plan.hops() {
        if let Some(e) = edge_of(airspace, x.node, y.node) {
            let s = x.depart;
            let forward = airspace.edge(e).from == x.node;
            traversals[e.index()].push(Occupation {
                flight,
                start: s,
                end: s + traversal_time(airspace, params, e),
                forward,
            });
        }
    }
}

fn sort(list: &mut [Occupation]) {
    list.sort_by_key(|o| (o.start, o.end, o.flight));
}

fn pair_names(flights: &[Flight<'_>], x: &Occupation, y: &Occupation) -> Vec<String> {
    vec![
        flights[x.flight].id.to_string(),
        flights[y.flight].id.to_string(),
    ]
}

/// Node rule at one node: `a2 >= d1 + tau || a1 >= d2 + tau` for stays of different flights.
pub(crate) fn node_rule(
    airspace: &Airspace,
    params: &FlightParams,
    flights: &[Flight<'_>],
    n: NodeId,
    list: &mut [Occupation],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let tau = params.node_separation;
    sort(list);
    for (i, x) in list.iter().enumerate() {
        // Sorted by arrival: once `a_j >= d_i + tau`, no later stay can conflict with `x`.
        for y in list[i + 1..].iter().take_while(|y| y.start < x.end + tau) {
            if y.flight == x.flight || x.start >= y.end + tau {
                continue;
            }
            out.push(Violation {
                rule: Rule::Node,
                flights: pair_names(flights, x, y),
                element: node_name(airspace, n),
                detail: format!(
                    "stays {} and {} are less than tau = {} apart",
                    span(x.start, x.end, offset),
                    span(y.start, y.end, offset),
                    dur(tau)
                ),
            });
        }
    }
}

/// Edge rule on one edge: exclusive, or headway in the same direction.
pub(crate) fn edge_rule(
    airspace: &Airspace,
    params: &FlightParams,
    flights: &[Flight<'_>],
    e: EdgeId,
    list: &mut [Occupation],
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    sort(list);
    let edge = airspace.edge(e);
    // Vertical links are exclusive whatever the corridors' rule
    // (docs/reference.md#layered-airspace).
    let rule = match airspace.edge_kind(e) {
        EdgeKind::Vertical { .. } => EdgeRule::Exclusive,
        EdgeKind::Corridor { .. } => params.edge_rule,
    };
    let direction = |o: &Occupation| {
        let (a, b) = if o.forward {
            (edge.from, edge.to)
        } else {
            (edge.to, edge.from)
        };
        format!("{}->{}", node_name(airspace, a), node_name(airspace, b))
    };
    for (i, x) in list.iter().enumerate() {
        // Sorted by entry: once `s_j >= f_i` (and `s_j >= s_i + h` under headway), no later
        // traversal can conflict with `x`.
        let horizon = match rule {
            EdgeRule::Exclusive => x.end,
            EdgeRule::Headway(h) => x.end.max(x.start + h),
        };
        for y in list[i + 1..].iter().take_while(|y| y.start < horizon) {
            if y.flight == x.flight {
                continue;
            }
            let detail = match rule {
                EdgeRule::Headway(h) if x.forward == y.forward => {
                    if (y.start - x.start).0.abs() >= h.0 {
                        continue;
                    }
                    format!(
                        "same-direction traversals ({}) enter at {} and {}, less than the headway {} apart",
                        direction(x),
                        stamp(x.start, offset),
                        stamp(y.start, offset),
                        dur(h)
                    )
                }
                _ => {
                    if y.start >= x.end || x.start >= y.end {
                        continue;
                    }
                    format!(
                        "traversals {} ({}) and {} ({}) overlap",
                        span(x.start, x.end, offset),
                        direction(x),
                        span(y.start, y.end, offset),
                        direction(y)
                    )
                }
            };
            out.push(Violation {
                rule: Rule::Edge,
                flights: pair_names(flights, x, y),
                element: crate::edge_name(airspace, e),
                detail,
            });
        }
    }
}
