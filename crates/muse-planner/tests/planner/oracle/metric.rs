//! A brute-force reference planner under metric separation
//! (docs/reference.md#metric-separation), for small instances (tests only).
//!
//! It shares nothing with the planner's geometry: the other flights are flown as the verifier
//! flies them (`muse_verify::approach::track`) and every candidate stay and traversal is
//! compared with their pieces by the verifier's exact closest approach
//! (`muse_verify::approach::pair`); the time rules are the reference's formulas, pairwise.
//!
//! It searches a grid of whole seconds (every duration of the instances is whole seconds; the
//! other flights' plans may use any millisecond), so it finds the best plan *on that grid*:
//! the planner, exact on milliseconds, must land no later, and, landing at the same instant,
//! take off no earlier. Plans are kept `margin` further apart than `D` (the rule's margin of
//! `v × 4 ms`, within which the planner's whole-millisecond widening may forbid a plan).
//!
//! States are arrivals `(node, instant)` valued by the latest take-off reaching them (only the
//! battery links a plan's past to its future); from each, every stay `[a, d]` that the rules
//! allow (they are monotone in `d`: a stay that breaks one, longer, still does), then every
//! corridor or vertical link.

// The names follow the reference (u, v, e, s, w, a, d).
#![allow(clippy::many_single_char_names)]

use std::collections::BTreeMap;

use muse_model::{
    Airspace, FlightParams, Instant, Millis, NodeId, Plan, Request, Separation, Stay,
};
use muse_verify::approach::pair::closest;
use muse_verify::approach::track::{Piece, Positions, pieces};

/// The grid, ms.
const STEP: i64 = 1_000;

/// The earliest landing on the grid and the latest take-off achieving it, with a plan, or
/// `None` when no plan on the grid keeps every rule.
pub fn earliest(
    airspace: &Airspace,
    params: &FlightParams,
    others: &[Plan],
    request: &Request,
    margin_m: f64,
) -> Option<(Instant, Instant, Plan)> {
    let positions = Positions::new(airspace, &airspace.plane());
    let world = World {
        airspace,
        params,
        positions: &positions,
        others,
        theirs: their_pieces(&positions, others),
        distance: params.separation.horizontal.m() + margin_m,
        vertical: params.separation.vertical_in(airspace).m() - Separation::VERTICAL_TOLERANCE_M,
    };
    world.search(request)
}

/// Everything a check reads.
struct World<'a> {
    airspace: &'a Airspace,
    params: &'a FlightParams,
    positions: &'a Positions,
    others: &'a [Plan],
    /// The other flights' pieces, times in seconds since instant 0.
    theirs: Vec<Piece>,
    distance: f64,
    vertical: f64,
}

/// The other flights' pieces (times in seconds since instant 0).
fn their_pieces(positions: &Positions, others: &[Plan]) -> Vec<Piece> {
    let mut out = Vec::new();
    for (k, plan) in others.iter().enumerate() {
        pieces(positions, plan, k as u32, 0, &mut out);
    }
    out
}

/// How a state was reached: the previous state's arrival and the stay's end there.
type Parent = Option<((NodeId, i64), i64)>;

impl World<'_> {
    fn search(&self, r: &Request) -> Option<(Instant, Instant, Plan)> {
        let p = self.params;
        let t_max = p.max_flight.0;
        // (arrival, node) → (latest take-off, parent), explored in arrival order.
        let mut best: BTreeMap<(i64, NodeId), (i64, Parent)> = BTreeMap::new();
        let mut takeoff = r.departure.0;
        while takeoff <= r.departure.0 + p.max_ground_delay.0 {
            best.insert((takeoff, r.origin), (takeoff, None));
            takeoff += STEP;
        }
        let mut done: BTreeMap<(NodeId, i64), (i64, Parent)> = BTreeMap::new();
        while let Some(((a, u), (t0, parent))) = best.pop_first() {
            done.insert((u, a), (t0, parent));
            if u == r.destination && a > t0 {
                if !self.stay_ok(u, a, a) {
                    continue;
                }
                let plan = rebuild(&done, (u, a));
                return Some((Instant(a), Instant(t0), plan));
            }
            let mut d = a;
            while d - t0 <= t_max && self.stay_ok(u, a, d) {
                for adj in self.airspace.neighbours(u) {
                    let w = self.w(adj.edge);
                    let arrive = d + w.0;
                    if arrive - t0 > t_max || !self.traversal_ok(u, adj.node, adj.edge, d, arrive) {
                        continue;
                    }
                    let key = (arrive, adj.node);
                    let better = best.get(&key).is_none_or(|&(t, _)| t < t0)
                        && !done.contains_key(&(adj.node, arrive));
                    if better {
                        best.insert(key, (t0, Some(((u, a), d))));
                    }
                }
                d += STEP;
            }
        }
        None
    }

    fn w(&self, e: muse_model::EdgeId) -> Millis {
        self.airspace.traversal_times(self.params.speed)[e.index()]
    }

    /// Whether a stay `[a, d]` at `v` keeps the node rule with every other stay there and is
    /// never too close to another flight.
    fn stay_ok(&self, v: NodeId, a: i64, d: i64) -> bool {
        let tau = self.params.node_separation.0;
        let apart = self
            .others
            .iter()
            .flat_map(|p| &p.path)
            .all(|s: &Stay| s.node != v || d + tau <= s.arrive.0 || s.depart.0 + tau <= a);
        let at = self.positions.at(v);
        apart && self.clear(at, at, a, d)
    }

    /// Whether a traversal of `e` from `u` to `v` over `[s, arrive]` keeps the edge rule
    /// (exclusive, or a same-direction headway) and is never too close to another flight.
    fn traversal_ok(
        &self,
        u: NodeId,
        v: NodeId,
        e: muse_model::EdgeId,
        s: i64,
        arrive: i64,
    ) -> bool {
        let w = arrive - s;
        let same_grow = match (self.airspace.edge_kind(e), self.params.edge_rule) {
            (muse_model::EdgeKind::Vertical { .. }, _) | (_, muse_model::EdgeRule::Exclusive) => w,
            (_, muse_model::EdgeRule::Headway(h)) => h.0,
        };
        for plan in self.others {
            for (x, y) in plan.hops() {
                let Some(f) = self.airspace.edge_between(x.node, y.node) else {
                    continue;
                };
                if f != e {
                    continue;
                }
                let s1 = x.depart.0;
                let grow = if x.node == u { same_grow } else { w };
                if s1 - grow < s && s < s1 + grow {
                    return false;
                }
            }
        }
        self.clear(self.positions.at(u), self.positions.at(v), s, arrive)
    }

    /// Whether a piece from `p0` at `t0` to `p1` at `t1` (ms) stays far enough from every
    /// other flight's pieces.
    fn clear(&self, p0: [f64; 3], p1: [f64; 3], t0: i64, t1: i64) -> bool {
        let ours = Piece {
            flight: u32::MAX,
            t0: t0 as f64 / 1000.0,
            t1: t1 as f64 / 1000.0,
            p0,
            p1,
            from: NodeId(0),
            to: NodeId(0),
        };
        self.theirs.iter().all(|theirs| {
            closest(
                &ours,
                theirs,
                f64::NEG_INFINITY,
                f64::INFINITY,
                self.vertical,
            )
            .is_none_or(|(d, _)| d >= self.distance)
        })
    }
}

/// The plan ending with the arrival `end`, from the parents.
fn rebuild(done: &BTreeMap<(NodeId, i64), (i64, Parent)>, end: (NodeId, i64)) -> Plan {
    let mut path = vec![Stay {
        node: end.0,
        arrive: Instant(end.1),
        depart: Instant(end.1),
    }];
    let mut at = end;
    while let Some(&(_, Some((prev, depart)))) = done.get(&at) {
        path.push(Stay {
            node: prev.0,
            arrive: Instant(prev.1),
            depart: Instant(depart),
        });
        at = prev;
    }
    path.reverse();
    Plan { path }
}
