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
//! Every reservation is a *barrier* `(L, R)`: another flight's stay `[x, y]` at the node (or,
//! on an edge, its entry instant `x = y`) is compatible with it exactly when `y ≤ L` or
//! `x ≥ R`. This is the SPEC's rules rewritten once:
//!
//! - a stay `[a, d]` at a node: `(a − τ, d + τ)` (SPEC §3 node rule: `x ≥ d + τ` or
//!   `a ≥ y + τ`). With `τ = 0` a zero-length stay gives `L = R`: nobody may *hover across*
//!   that instant, though others may arrive or leave at it;
//! - a traversal entering edge `e` at `s`: for entries in the same direction `(s − h, s + h)`
//!   (`h = w(e)` under `exclusive`, the headway under `headway`); for entries in the opposite
//!   direction `(s − w, s + w)`;
//! - a zone window `[start, end)`: `(start − 1, end)` at a node and `(start − 1 − w, end)` for
//!   entries of an edge (SPEC §4: allowed only if the stay or traversal ends before `start`
//!   or begins at or after `end`).
//!
//! An instant `t` is *blocked* when `L < t < R` for some barrier. A *safe interval* is a
//! maximal `[lo, hi]` compatible with every barrier: `lo` is the largest `R ≤ t` and `hi` the
//! smallest `L` of the barriers with `R > t`. When `L = R` two safe intervals share that
//! instant; [`Schedule::node_slot`] then answers with the later one, which dominates (a drone
//! arriving at that instant may leave at once, or stay on).
//!
//! Each node keeps one vector of its stays sorted by arrival; each edge keeps, per direction,
//! a sorted vector of entry instants; zone barriers are merged once at construction. Accepted
//! stays at a node are pairwise separated and every list widens its entries by one constant,
//! so every list is sorted by both `L` and `R`, and each question is a binary search per list.
//!
//! Costs, with `k` the entries of the touched list: a query is `O(log k)` per list (two lists
//! for a node, three for an edge); inserting or removing a plan of `n` stays is
//! `O(n · (log k + k))` (a `Vec` insert shifts the tail: `k` is the day's traffic at one node
//! or edge, so this is a short `memmove`). Memory is proportional to the reservations held:
//! 24 bytes per stay and per traversal.

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

/// One reservation: a stay `[start, end]`, an entry instant (`start == end`), or a zone
/// barrier already in `(L, R)` form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Occ {
    start: i64,
    end: i64,
    flight: FlightId,
}

/// A read-only view of a sorted list whose barriers are `(start − grow, end + grow)`.
#[derive(Clone, Copy)]
struct View<'a> {
    occ: &'a [Occ],
    grow: i64,
}

impl View<'_> {
    #[inline]
    fn l(self, o: &Occ) -> i64 {
        o.start - self.grow
    }

    #[inline]
    fn r(self, o: &Occ) -> i64 {
        o.end + self.grow
    }

    /// If `t` is blocked (`L < t < R`), the largest such `R`.
    #[inline]
    fn blocking_end(self, t: i64) -> Option<i64> {
        let i = self.occ.partition_point(|o| self.l(o) < t);
        let r = self.r(self.occ.get(i.checked_sub(1)?)?);
        (r > t).then_some(r)
    }

    /// The largest `R ≤ t` (`NEG_INF` if none): where a safe interval around `t` starts.
    #[inline]
    fn lo_bound(self, t: i64) -> i64 {
        let i = self.occ.partition_point(|o| self.r(o) <= t);
        i.checked_sub(1).map_or(NEG_INF, |i| self.r(&self.occ[i]))
    }

    /// The barrier with the smallest `L` among those with `R > t`, as `(L, R)`.
    #[inline]
    fn hi_bound(self, t: i64) -> (i64, i64) {
        let i = self.occ.partition_point(|o| self.r(o) <= t);
        self.occ
            .get(i)
            .map_or((INF, INF), |o| (self.l(o), self.r(o)))
    }
}

/// What a node (or an edge's entry instants) says about an instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeSlot {
    /// The instant is free; a stay anywhere in `[lo, hi]` is allowed (`NEG_INF` / `INF` when
    /// unbounded). `next` is the earliest instant at which a later safe interval can begin
    /// (`hi` itself when two safe intervals share it, `INF` if none).
    Safe {
        /// First instant of the safe interval.
        lo: i64,
        /// Last instant of the safe interval.
        hi: i64,
        /// Where the next safe interval can begin.
        next: i64,
    },
    /// The instant is blocked; `next_free` is the first instant after it that is not.
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
    /// Per edge: the half-width of same-direction blocking (`w` or the headway).
    same_grow: Vec<i64>,
    /// Per node: accepted stays `[arrive, depart]`, sorted.
    nodes: Vec<Vec<Occ>>,
    /// Per edge and direction (0: `from → to`, 1: `to → from`): entry instants.
    edges: Vec<[Vec<Occ>; 2]>,
    /// Per node: merged zone barriers.
    node_zones: Vec<Vec<Occ>>,
    /// Per edge: merged zone barriers of entry instants.
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
                EdgeRule::Exclusive => w,
                EdgeRule::Headway(h) => h.0,
            })
            .collect();
        // A window [start, end) becomes the barrier (start − 1 − before, end).
        let barriers = |windows: &[muse_airspace::closures::Window], before: i64| -> Vec<Occ> {
            let mut v: Vec<(i64, i64)> = windows
                .iter()
                .filter(|win| win.start < win.end)
                .map(|win| (win.start.0, win.end.0))
                .collect();
            v.sort_unstable();
            let mut merged: Vec<(i64, i64)> = Vec::with_capacity(v.len());
            for (a, b) in v {
                match merged.last_mut() {
                    Some(last) if a <= last.1 => last.1 = last.1.max(b),
                    _ => merged.push((a, b)),
                }
            }
            merged
                .into_iter()
                .map(|(a, b)| Occ {
                    start: a - 1 - before,
                    end: b,
                    flight: FlightId::MAX,
                })
                .collect()
        };
        let node_zones = (0..airspace.node_count())
            .map(|i| barriers(closures.node(NodeId(i as u32)), 0))
            .collect();
        let edge_zones = (0..airspace.edge_count())
            .map(|i| barriers(closures.edge(EdgeId(i as u32)), w[i]))
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
                grow: self.tau,
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
        let same = &self.edges[i][dir];
        let views = [
            // A headway of 0 blocks nothing.
            View {
                occ: if self.same_grow[i] > 0 { same } else { &[] },
                grow: self.same_grow[i],
            },
            View {
                occ: &self.edges[i][1 - dir],
                grow: self.w[i],
            },
            View {
                occ: &self.edge_zones[i],
                grow: 0,
            },
        ];
        let mut p = t;
        loop {
            match slot(&views, p) {
                NodeSlot::Safe { hi, .. } => return (p, hi),
                NodeSlot::Blocked { next_free } => p = next_free,
            }
        }
    }

    /// Adds an accepted plan. The plan must be valid against the schedule (the planner's
    /// plans are); the schedule does not re-check it (the verifier does).
    pub fn insert(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) {
        for_each_reservation(airspace, flight, plan, |target, occ| {
            let list = self.list_mut(target);
            let i = list
                .partition_point(|o| (o.start, o.end, o.flight) < (occ.start, occ.end, occ.flight));
            list.insert(i, occ);
            self.reservations += 1;
        });
        self.flights += 1;
    }

    /// Removes a plan previously inserted with the same `flight` (a cancellation). Returns
    /// `false`, and removes nothing, if any of its reservations is not held.
    pub fn remove(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) -> bool {
        let position = |list: &[Occ], occ: Occ| {
            let i = list
                .partition_point(|o| (o.start, o.end, o.flight) < (occ.start, occ.end, occ.flight));
            (list.get(i) == Some(&occ)).then_some(i)
        };
        let mut all_held = true;
        for_each_reservation(airspace, flight, plan, |target, occ| {
            all_held &= position(self.list(target), occ).is_some();
        });
        if !all_held {
            return false;
        }
        for_each_reservation(airspace, flight, plan, |target, occ| {
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

/// Calls `f` on every reservation a plan makes: a stay per node visited and an entry instant
/// per traversal.
fn for_each_reservation(
    airspace: &Airspace,
    flight: FlightId,
    plan: &Plan,
    mut f: impl FnMut(Target, Occ),
) {
    for (k, stay) in plan.path.iter().enumerate() {
        f(
            Target::Node(stay.node.index()),
            Occ {
                start: stay.arrive.0,
                end: stay.depart.0,
                flight,
            },
        );
        if let Some(next) = plan.path.get(k + 1) {
            let e = airspace
                .edge_between(stay.node, next.node)
                .expect("consecutive stays of a plan are joined by an edge");
            let dir = usize::from(airspace.edge(e).from != stay.node);
            let s = stay.depart.0;
            f(
                Target::Edge(e.index(), dir),
                Occ {
                    start: s,
                    end: s,
                    flight,
                },
            );
        }
    }
}

/// The slot of instant `t` over several views.
#[inline]
fn slot(views: &[View<'_>], t: i64) -> NodeSlot {
    let mut t = t;
    let mut blocked = false;
    // Skip forward over barriers until none blocks `t`.
    loop {
        let end = views.iter().filter_map(|v| v.blocking_end(t)).max();
        match end {
            Some(r) => {
                blocked = true;
                t = r;
            }
            None => break,
        }
    }
    if blocked {
        return NodeSlot::Blocked { next_free: t };
    }
    let lo = views.iter().map(|v| v.lo_bound(t)).max().unwrap_or(NEG_INF);
    let (mut hi, mut next) = (INF, INF);
    for v in views {
        let (l, r) = v.hi_bound(t);
        if l < hi {
            (hi, next) = (l, r);
        } else if l == hi {
            next = next.max(r);
        }
    }
    NodeSlot::Safe { lo, hi, next }
}

/// Milliseconds as a plain integer (the planner works in raw `i64` ms internally).
#[inline]
pub fn ms(m: Millis) -> i64 {
    m.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_airspace::closures::resolve;
    use muse_model::{Edge, Instant, LonLat, Node, NodeKind, Period, Stay, Zone};

    /// A — B, 1 km (120 s at 30 km/h).
    fn line() -> Airspace {
        let n = |id: &str, lon| Node {
            id: id.into(),
            kind: NodeKind::Station,
            name: String::new(),
            pos: LonLat::new(lon, 1.3),
        };
        Airspace::new(
            vec![n("A", 103.8), n("B", 103.81)],
            vec![Edge {
                id: "A-B".into(),
                from: NodeId(0),
                to: NodeId(1),
                length_m: 1_000.0,
            }],
        )
        .unwrap()
    }

    fn plan(stays: &[(u32, i64, i64)]) -> Plan {
        Plan {
            path: stays
                .iter()
                .map(|&(n, a, d)| Stay {
                    node: NodeId(n),
                    arrive: Instant(a),
                    depart: Instant(d),
                })
                .collect(),
        }
    }

    fn schedule(params: &FlightParams, zones: &[Zone]) -> Schedule {
        let a = line();
        let c = resolve(&a, zones, Instant(-86_400_000), Instant(86_400_000)).unwrap();
        Schedule::new(&a, params, &c)
    }

    #[test]
    fn node_barrier_with_tau() {
        let a = line();
        let p = FlightParams::default(); // tau = 5 s
        let mut s = schedule(&p, &[]);
        s.insert(
            &a,
            7,
            &plan(&[(0, 100_000, 110_000), (1, 230_000, 230_000)]),
        );
        let v = NodeId(0);
        // Blocked strictly inside (95 s, 115 s); the ends are free.
        assert_eq!(
            s.node_slot(v, 95_001),
            NodeSlot::Blocked { next_free: 115_000 }
        );
        assert_eq!(
            s.node_slot(v, 114_999),
            NodeSlot::Blocked { next_free: 115_000 }
        );
        assert_eq!(
            s.node_slot(v, 95_000),
            NodeSlot::Safe {
                lo: NEG_INF,
                hi: 95_000,
                next: 115_000
            }
        );
        assert_eq!(
            s.node_slot(v, 115_000),
            NodeSlot::Safe {
                lo: 115_000,
                hi: INF,
                next: INF
            }
        );
        assert_eq!(s.flights(), 1);
        assert_eq!(s.reservations(), 3);
        assert!(s.remove(
            &a,
            7,
            &plan(&[(0, 100_000, 110_000), (1, 230_000, 230_000)])
        ));
        assert_eq!(
            s.node_slot(v, 100_000),
            NodeSlot::Safe {
                lo: NEG_INF,
                hi: INF,
                next: INF
            }
        );
        assert!(!s.remove(
            &a,
            7,
            &plan(&[(0, 100_000, 110_000), (1, 230_000, 230_000)])
        ));
    }

    #[test]
    fn zero_tau_forbids_hovering_across_a_point_stay() {
        let a = line();
        let p = FlightParams {
            node_separation: Millis::ZERO,
            ..FlightParams::default()
        };
        let mut s = schedule(&p, &[]);
        s.insert(&a, 1, &plan(&[(0, 50_000, 50_000), (1, 170_000, 170_000)]));
        // Arriving before 50 s: may stay until 50 s, not beyond.
        assert_eq!(
            s.node_slot(NodeId(0), 40_000),
            NodeSlot::Safe {
                lo: NEG_INF,
                hi: 50_000,
                next: 50_000
            }
        );
        // Arriving at 50 s: the later interval, from 50 s on.
        assert_eq!(
            s.node_slot(NodeId(0), 50_000),
            NodeSlot::Safe {
                lo: 50_000,
                hi: INF,
                next: INF
            }
        );
    }

    #[test]
    fn edge_rules() {
        let a = line();
        let plan1 = plan(&[(0, 0, 0), (1, 120_000, 120_000)]); // enters A→B at 0
        let exclusive = FlightParams::default();
        let mut s = schedule(&exclusive, &[]);
        s.insert(&a, 1, &plan1);
        // Same direction: no entry in (−120 s, 120 s).
        assert_eq!(
            s.edge_free_run(EdgeId(0), 0, -200_000),
            (-200_000, -120_000)
        );
        assert_eq!(s.edge_free_run(EdgeId(0), 0, -119_999), (120_000, INF));
        // Opposite direction: the same under `exclusive`.
        assert_eq!(s.edge_free_run(EdgeId(0), 1, 1), (120_000, INF));
        let headway = FlightParams {
            edge_rule: EdgeRule::Headway(Millis(5_000)),
            ..exclusive
        };
        let mut s = schedule(&headway, &[]);
        s.insert(&a, 1, &plan1);
        assert_eq!(s.edge_free_run(EdgeId(0), 0, 1), (5_000, INF));
        assert_eq!(s.edge_free_run(EdgeId(0), 0, -10_000), (-10_000, -5_000));
        assert_eq!(s.edge_free_run(EdgeId(0), 1, 1), (120_000, INF));
        let zero = FlightParams {
            edge_rule: EdgeRule::Headway(Millis::ZERO),
            ..exclusive
        };
        let mut s = schedule(&zero, &[]);
        s.insert(&a, 1, &plan1);
        assert_eq!(
            s.edge_free_run(EdgeId(0), 0, 0),
            (0, INF),
            "a headway of 0 blocks nothing"
        );
    }

    #[test]
    fn zone_barriers() {
        let zone = Zone {
            id: "Z".into(),
            name: String::new(),
            restriction: "PROHIBITED".into(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: vec!["A-B".into()],
            periods: vec![Period {
                start: Some(Instant(1_000_000)),
                end: Some(Instant(2_000_000)),
                daily: vec![],
            }],
        };
        let s = schedule(&FlightParams::default(), &[zone]);
        // A stay at B must end before 1000 s or begin at or after 2000 s.
        assert_eq!(
            s.node_slot(NodeId(1), 999_999),
            NodeSlot::Safe {
                lo: NEG_INF,
                hi: 999_999,
                next: 2_000_000
            }
        );
        assert_eq!(
            s.node_slot(NodeId(1), 1_000_000),
            NodeSlot::Blocked {
                next_free: 2_000_000
            }
        );
        // A traversal [s, s + 120 s] must end before 1000 s or start at or after 2000 s.
        assert_eq!(s.edge_free_run(EdgeId(0), 0, 0), (0, 879_999));
        assert_eq!(s.edge_free_run(EdgeId(0), 1, 880_000), (2_000_000, INF));
    }
}
