//! The reservation schedule: the paper's *CurrentSchedule*.
//!
//! For every node and every edge it holds what the accepted plans occupy, plus the closure
//! windows of the no-fly zones (the paper's "virtual drones"), and answers the two questions
//! the search asks:
//!
//! - [`Schedule::node_slot`]: is a drone allowed at node `v` at instant `t`, and if so, what is
//!   the maximal *safe interval* `[lo, hi]` around `t` in which it may stay?
//! - [`Schedule::edge_free_run`]: what is the earliest instant `≥ t` at which a drone may
//!   *enter* edge `e` in a given direction, and until when may it keep entering?
//!
//! # Data structure
//!
//! Everything is expressed as *blocked integer spans* `[lo, hi]` (inclusive, milliseconds):
//!
//! - a stay `[a, d]` of an accepted flight at a node blocks `[a − τ + 1, d + τ − 1]` for
//!   arrivals and hovering of other flights (SPEC §3 node rule: a stay may not intersect the
//!   open interval `(a − τ, d + τ)`);
//! - a traversal entering edge `e` at `s` blocks, for entries in the *same* direction,
//!   `[s − h + 1, s + h − 1]` (`h = w(e)` under `exclusive`, the headway under `headway`),
//!   and for entries in the *opposite* direction `[s − w + 1, s + w − 1]`;
//! - a zone window `[start, end)` blocks `[start, end − 1]` at a node and entry times
//!   `[start − w, end − 1]` on an edge (SPEC §4: the stay or traversal may not share an
//!   instant with the window).
//!
//! Each node keeps one sorted vector of its stays' spans; each edge keeps, per direction, a
//! sorted vector of entry times; zone spans are merged once at construction. Because
//! accepted stays at a node are pairwise separated and every list widens its entries by one
//! constant, every list is sorted by both `lo` and `hi`, so "the span containing `t`", "the
//! last span before `t`" and "the first span after `t`" are each one binary search.
//!
//! Costs, with `k` the entries of the touched list: a query is `O(log k)` per list (at most
//! three lists per question); inserting or removing a plan of `n` stays is
//! `O(n · (log k + k))` (a `Vec` insert shifts the tail: `k` is the day's traffic at one
//! node or edge, so this is a short `memmove`). Memory is proportional to the reservations
//! held: 24 bytes per stay and per traversal.

use muse_airspace::closures::Closures;
use muse_model::{Airspace, EdgeId, EdgeRule, FlightParams, Millis, NodeId, Plan};

/// "Never": later than any instant MUSE handles (±1.4 × 10¹⁵ years in ms, with headroom so
/// that adding durations cannot overflow).
pub const INF: i64 = i64::MAX / 4;
/// "Always": earlier than any instant MUSE handles.
pub const NEG_INF: i64 = i64::MIN / 4;

/// An identifier of an accepted flight in a schedule (the caller's choice, e.g. the request's
/// position in the day).
pub type FlightId = u32;

/// One occupancy entry: a span for nodes and zones, an entry instant (`lo == hi`) for edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Occ {
    lo: i64,
    hi: i64,
    flight: FlightId,
}

/// A read-only view of a sorted list whose spans are `[lo − grow, hi + grow]`.
#[derive(Clone, Copy)]
struct View<'a> {
    occ: &'a [Occ],
    grow: i64,
}

impl View<'_> {
    /// The end of the span containing `t`, if any.
    #[inline]
    fn containing(self, t: i64) -> Option<i64> {
        let i = self.occ.partition_point(|o| o.lo - self.grow <= t);
        let hi = self.occ.get(i.checked_sub(1)?)?.hi + self.grow;
        (hi >= t).then_some(hi)
    }

    /// The end of the last span ending before `t` (`NEG_INF` if none).
    #[inline]
    fn prev_hi(self, t: i64) -> i64 {
        let i = self.occ.partition_point(|o| o.hi + self.grow < t);
        i.checked_sub(1)
            .map_or(NEG_INF, |i| self.occ[i].hi + self.grow)
    }

    /// The start of the first span starting after `t` (`INF` if none).
    #[inline]
    fn next_lo(self, t: i64) -> i64 {
        let i = self.occ.partition_point(|o| o.lo - self.grow <= t);
        self.occ.get(i).map_or(INF, |o| o.lo - self.grow)
    }
}

/// What a node says about an instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeSlot {
    /// The instant is free; the drone may stay anywhere in `[lo, hi]` (inclusive; `NEG_INF`
    /// / `INF` when unbounded).
    Safe {
        /// First free instant of the safe interval.
        lo: i64,
        /// Last free instant of the safe interval.
        hi: i64,
    },
    /// The instant is blocked; `next_free` is the first free instant after it.
    Blocked {
        /// The first free instant after the blocked one.
        next_free: i64,
    },
}

/// The reservation schedule for one airspace, parameter set and set of zone closures.
#[derive(Clone, Debug)]
pub struct Schedule {
    tau: i64,
    /// Per edge: traversal time (ms).
    w: Vec<i64>,
    /// Per edge: the half-width minus one of same-direction blocking.
    same_grow: Vec<i64>,
    /// Per node: blocked spans of accepted stays.
    nodes: Vec<Vec<Occ>>,
    /// Per edge and direction (0: `from → to`, 1: `to → from`): entry instants.
    edges: Vec<[Vec<Occ>; 2]>,
    /// Per node: merged zone spans.
    node_zones: Vec<Vec<Occ>>,
    /// Per edge: merged zone spans of entry instants.
    edge_zones: Vec<Vec<Occ>>,
    flights: usize,
    reservations: usize,
}

impl Schedule {
    /// An empty schedule (no flights) with the zone closures as permanent blocks.
    pub fn new(airspace: &Airspace, params: &FlightParams, closures: &Closures) -> Self {
        let w: Vec<i64> = airspace
            .traversal_times(params.speed)
            .iter()
            .map(|m| m.0)
            .collect();
        let same_grow = w
            .iter()
            .map(|&w| match params.edge_rule {
                EdgeRule::Exclusive => w - 1,
                EdgeRule::Headway(h) => h.0 - 1,
            })
            .collect();
        let spans = |windows: &[muse_airspace::closures::Window], before: i64| -> Vec<Occ> {
            let mut v: Vec<Occ> = windows
                .iter()
                .map(|win| Occ {
                    lo: win.start.0 - before,
                    hi: win.end.0 - 1,
                    flight: FlightId::MAX,
                })
                .filter(|o| o.lo <= o.hi)
                .collect();
            v.sort_by_key(|o| o.lo);
            merge(v)
        };
        let node_zones = (0..airspace.node_count())
            .map(|i| spans(closures.node(NodeId(i as u32)), 0))
            .collect();
        let edge_zones = (0..airspace.edge_count())
            .map(|i| spans(closures.edge(EdgeId(i as u32)), w[i]))
            .collect();
        Schedule {
            tau: params.node_separation.0,
            same_grow,
            nodes: vec![Vec::new(); airspace.node_count()],
            edges: vec![[Vec::new(), Vec::new()]; airspace.edge_count()],
            node_zones,
            edge_zones,
            w,
            flights: 0,
            reservations: 0,
        }
    }

    /// The traversal time of edge `e`, ms.
    #[inline]
    pub fn traversal_ms(&self, e: EdgeId) -> i64 {
        self.w[e.index()]
    }

    /// Number of flights held.
    pub fn flights(&self) -> usize {
        self.flights
    }

    /// Number of reservations held (stays plus traversals).
    pub fn reservations(&self) -> usize {
        self.reservations
    }

    /// Whether instant `t` is free at node `v`, and the safe interval around it.
    #[inline]
    pub fn node_slot(&self, v: NodeId, t: i64) -> NodeSlot {
        let views = [
            View {
                occ: &self.nodes[v.index()],
                grow: 0,
            },
            View {
                occ: &self.node_zones[v.index()],
                grow: 0,
            },
        ];
        slot(&views, t)
    }

    /// The first instant `p ≥ t` at which edge `e` may be entered in direction `dir`
    /// (`0`: from its `from` node, `1`: from its `to` node), and the last instant `q ≥ p` such
    /// that every entry in `[p, q]` is allowed.
    #[inline]
    pub fn edge_free_run(&self, e: EdgeId, dir: usize, t: i64) -> (i64, i64) {
        let i = e.index();
        let same = View {
            occ: &self.edges[i][dir],
            grow: self.same_grow[i],
        };
        let views = [
            if same.grow >= 0 {
                same
            } else {
                View { occ: &[], grow: 0 }
            },
            View {
                occ: &self.edges[i][1 - dir],
                grow: self.w[i] - 1,
            },
            View {
                occ: &self.edge_zones[i],
                grow: 0,
            },
        ];
        match slot(&views, t) {
            NodeSlot::Safe { hi, .. } => (t, hi),
            NodeSlot::Blocked { next_free } => match slot(&views, next_free) {
                NodeSlot::Safe { hi, .. } => (next_free, hi),
                NodeSlot::Blocked { .. } => unreachable!("next_free is free by construction"),
            },
        }
    }

    /// Adds an accepted plan. The plan must be valid against the schedule (the planner's
    /// plans are); the schedule does not re-check it (the verifier does).
    pub fn insert(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) {
        let tau = self.tau;
        for_each_reservation(airspace, tau, flight, plan, |target, occ| {
            let list = self.list_mut(target);
            let i = list.partition_point(|o| (o.lo, o.flight) < (occ.lo, occ.flight));
            list.insert(i, occ);
            self.reservations += 1;
        });
        self.flights += 1;
    }

    /// Removes a plan previously inserted with the same `flight` (a cancellation). Returns
    /// `false`, and removes nothing, if any of its reservations is not held.
    pub fn remove(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) -> bool {
        let position = |list: &[Occ], occ: Occ| {
            let i = list.partition_point(|o| (o.lo, o.flight) < (occ.lo, occ.flight));
            (list.get(i) == Some(&occ)).then_some(i)
        };
        let tau = self.tau;
        let mut all_held = true;
        for_each_reservation(airspace, tau, flight, plan, |target, occ| {
            all_held &= position(self.list(target), occ).is_some();
        });
        if !all_held {
            return false;
        }
        for_each_reservation(airspace, tau, flight, plan, |target, occ| {
            let list = self.list_mut(target);
            if let Some(i) = position(list, occ) {
                list.remove(i);
                self.reservations -= 1;
            }
        });
        self.flights -= 1;
        true
    }

    fn list(&self, target: Target) -> &[Occ] {
        match target {
            Target::Node(i) => &self.nodes[i],
            Target::Edge(i, d) => &self.edges[i][d],
        }
    }

    fn list_mut(&mut self, target: Target) -> &mut Vec<Occ> {
        match target {
            Target::Node(i) => &mut self.nodes[i],
            Target::Edge(i, d) => &mut self.edges[i][d],
        }
    }
}

/// Where a reservation is held.
#[derive(Clone, Copy, Debug)]
enum Target {
    Node(usize),
    Edge(usize, usize),
}

/// Calls `f` on every reservation a plan makes: a span per stay (unless empty, as a
/// zero-length stay is with `τ = 0`) and an entry instant per traversal.
fn for_each_reservation(
    airspace: &Airspace,
    tau: i64,
    flight: FlightId,
    plan: &Plan,
    mut f: impl FnMut(Target, Occ),
) {
    for (k, stay) in plan.path.iter().enumerate() {
        let occ = Occ {
            lo: stay.arrive.0 - tau + 1,
            hi: stay.depart.0 + tau - 1,
            flight,
        };
        if occ.lo <= occ.hi {
            f(Target::Node(stay.node.index()), occ);
        }
        if let Some(next) = plan.path.get(k + 1) {
            let e = airspace
                .edge_between(stay.node, next.node)
                .expect("consecutive stays of a plan are joined by an edge");
            let dir = usize::from(airspace.edge(e).from != stay.node);
            let s = stay.depart.0;
            f(
                Target::Edge(e.index(), dir),
                Occ {
                    lo: s,
                    hi: s,
                    flight,
                },
            );
        }
    }
}

/// Merges overlapping or touching spans of a list sorted by `lo`.
fn merge(v: Vec<Occ>) -> Vec<Occ> {
    let mut out: Vec<Occ> = Vec::with_capacity(v.len());
    for o in v {
        match out.last_mut() {
            Some(last) if o.lo <= last.hi + 1 => last.hi = last.hi.max(o.hi),
            _ => out.push(o),
        }
    }
    out
}

/// The slot of instant `t` over several monotone views.
#[inline]
fn slot(views: &[View<'_>], t: i64) -> NodeSlot {
    let mut t = t;
    let mut blocked = false;
    // Skip forward over blocked spans until no view blocks `t`.
    loop {
        let mut end = None;
        for v in views {
            if let Some(h) = v.containing(t) {
                end = Some(end.map_or(h, |e: i64| e.max(h)));
            }
        }
        match end {
            Some(h) => {
                blocked = true;
                t = h + 1;
            }
            None => break,
        }
    }
    if blocked {
        return NodeSlot::Blocked { next_free: t };
    }
    let lo = views.iter().map(|v| v.prev_hi(t)).max().unwrap_or(NEG_INF);
    let hi = views.iter().map(|v| v.next_lo(t)).min().unwrap_or(INF);
    NodeSlot::Safe {
        lo: if lo == NEG_INF { NEG_INF } else { lo + 1 },
        hi: if hi == INF { INF } else { hi - 1 },
    }
}

/// Milliseconds as a plain integer (the planner works in raw `i64` ms internally).
#[inline]
pub fn ms(m: Millis) -> i64 {
    m.0
}
