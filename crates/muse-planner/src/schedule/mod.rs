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
//! `x ≥ R`. This is the reference's rules rewritten once:
//!
//! - a stay `[a, d]` at a node: `(a − τ, d + τ)` (docs/reference.md#flight-model-and-separation
//!   node rule: `x ≥ d + τ` or `a ≥ y + τ`). With `τ = 0` a zero-length stay gives `L = R`: nobody
//!   may *hover across* that instant, though others may arrive or leave at it;
//! - a traversal entering edge `e` at `s`: for entries in the same direction `(s − h, s + h)`
//!   (`h = w(e)` under `exclusive`, the headway under `headway`); for entries in the opposite
//!   direction `(s − w, s + w)`;
//! - a zone window `[start, end)`: `(start − 1, end)` at a node and `(start − 1 − w, end)` for
//!   entries of an edge (docs/reference.md#no-fly-zones: allowed only if the stay or traversal ends
//!   before `start` or begins at or after `end`).
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

mod barriers;

use std::sync::Arc;

use muse_airspace::closures::Closures;
use muse_airspace::conflicts::{Movement, Relation};
use muse_model::{
    Airspace, EdgeId, EdgeKind, EdgeRule, FlightParams, Instant, Millis, NodeId, Plan,
};

use crate::time::Unbounded;
use barriers::{Book, Occ, View, barriers, insertion_point, position, slot, slot_of_views};

/// An identifier of an accepted flight in a schedule (the caller's choice, e.g. the request's
/// position in the day, or the service's sequence number).
///
/// ```
/// use muse_planner::FlightId;
/// assert_eq!(FlightId::from(7_usize), FlightId(7));
/// assert_eq!(FlightId(7).to_string(), "#7");
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct FlightId(pub u64);

impl FlightId {
    /// The position this id stands for, when the caller numbered flights by position (as
    /// [`FlightId::from`] a `usize` does).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl From<usize> for FlightId {
    fn from(index: usize) -> Self {
        FlightId(index as u64)
    }
}

impl std::fmt::Display for FlightId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// What a node (or an edge's entry instants) says about an instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NodeSlot {
    /// The instant is free; a stay anywhere in `[lo, hi]` is allowed (`Instant::NEG_INF` /
    /// `Instant::INF` when unbounded). `next` is the earliest instant at which a later safe
    /// interval can begin (`hi` itself when two safe intervals share it, `Instant::INF` if
    /// none).
    Safe {
        /// First instant of the safe interval.
        lo: Instant,
        /// Last instant of the safe interval.
        hi: Instant,
        /// Where the next safe interval can begin.
        next: Instant,
    },
    /// The instant is blocked; `next_free` is the first instant after it that is not.
    Blocked {
        /// The first free instant after the blocked one.
        next_free: Instant,
    },
}

/// The direction a corridor is flown in, against its edge's `from` and `to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Dir {
    /// From the edge's `from` node to its `to` node.
    Forward,
    /// From the edge's `to` node to its `from` node.
    Backward,
}

impl Dir {
    /// `Forward` when `forward`.
    #[inline]
    pub(crate) fn of(forward: bool) -> Dir {
        if forward { Dir::Forward } else { Dir::Backward }
    }

    /// The other direction.
    #[inline]
    fn opposite(self) -> Dir {
        match self {
            Dir::Forward => Dir::Backward,
            Dir::Backward => Dir::Forward,
        }
    }

    /// The index of the direction in per-direction arrays.
    #[inline]
    fn index(self) -> usize {
        self as usize
    }
}

/// The reservation schedule for one airspace, parameter set and set of zone closures.
#[derive(Clone, Debug)]
pub struct Schedule {
    tau: Millis,
    /// Per node: its stays and zone barriers.
    nodes: Vec<NodeBook>,
    /// Per edge: its entries per direction, timing and zone barriers.
    edges: Vec<EdgeBook>,
    /// No query before this instant is expected (see [`Schedule::set_horizon`]).
    horizon: Instant,
    /// No node or edge changes between free and blocked after this instant (an upper bound:
    /// removals leave it).
    quiet_from: Instant,
    flights: usize,
    reservations: usize,
    /// Metric separation's barriers between movements (docs/reference.md#metric-separation),
    /// when it is on and adds any.
    relation: Option<Arc<Relation>>,
}

/// Everything a query about one node reads, kept together.
#[derive(Clone, Debug, Default)]
struct NodeBook {
    /// Accepted stays `[arrive, depart]`, sorted.
    stays: Book,
    /// Merged zone barriers.
    zones: Vec<Occ>,
}

/// Everything a query about one edge reads, kept together (one or two cache lines).
#[derive(Clone, Debug)]
struct EdgeBook {
    /// Entry instants per direction (indexed by [`Dir::index`]), sorted.
    dirs: [Book; 2],
    /// Traversal time.
    w: Millis,
    /// Half-width of same-direction blocking (`w` or the headway).
    same_grow: Millis,
    /// Merged zone barriers of entry instants.
    zones: Vec<Occ>,
}

impl Schedule {
    /// An empty schedule (no flights) with the zone closures as permanent blocks. With metric
    /// separation on (`params.separation`), the airspace's conflict relation is worked out here
    /// ([`Relation::new`]); [`Schedule::with_relation`] takes one already made.
    pub fn new(airspace: &Airspace, params: &FlightParams, closures: &Closures) -> Self {
        let relation = params
            .separation
            .is_on()
            .then(|| Arc::new(Relation::new(airspace, params)));
        Schedule::with_relation(airspace, params, closures, relation)
    }

    /// [`Schedule::new`] with the conflict relation of `airspace` under `params` given (or
    /// `None`: the time rules only), as [`crate::Planner::schedule`] passes the one it keeps.
    pub fn with_relation(
        airspace: &Airspace,
        params: &FlightParams,
        closures: &Closures,
        relation: Option<Arc<Relation>>,
    ) -> Self {
        let relation = relation.filter(|r| !r.is_empty());
        let nodes = (0..airspace.node_count())
            .map(|i| NodeBook {
                stays: Book::default(),
                zones: barriers(closures.node(NodeId(i as u32)), Millis::ZERO),
            })
            .collect();
        let edges = airspace
            .traversal_times(params.speed)
            .iter()
            .enumerate()
            .map(|(i, &w)| EdgeBook {
                dirs: [Book::default(), Book::default()],
                w,
                // Vertical links are exclusive whatever the corridors' rule
                // (docs/reference.md#layered-airspace).
                same_grow: match (airspace.edge_kind(EdgeId(i as u32)), params.edge_rule) {
                    (EdgeKind::Vertical { .. }, _) | (_, EdgeRule::Exclusive) => w,
                    (_, EdgeRule::Headway(h)) => h,
                },
                zones: barriers(closures.edge(EdgeId(i as u32)), w),
            })
            .collect();
        let mut schedule = Schedule {
            tau: params.node_separation,
            nodes,
            edges,
            horizon: Instant::NEG_INF,
            quiet_from: Instant::NEG_INF,
            flights: 0,
            reservations: 0,
            relation,
        };
        schedule.note_zone_changes();
        schedule
    }

    /// From this instant on, every node and every edge stays as it is (free, or blocked for
    /// good) as far as the schedule knows: the answers to every query are the same for all
    /// later instants. The planner uses it to stop exploring later and later copies of the
    /// same move. An upper bound: it never moves back when flights are removed.
    pub(crate) fn quiet_from(&self) -> Instant {
        self.quiet_from
    }

    /// Moves [`Schedule::quiet_from`] past every zone barrier.
    fn note_zone_changes(&mut self) {
        let zones = self
            .nodes
            .iter()
            .flat_map(|n| &n.zones)
            .chain(self.edges.iter().flat_map(|e| &e.zones));
        for o in zones {
            // A barrier's last change is its end, or its start when it never ends.
            let last = if o.end >= Instant::INF {
                o.start
            } else {
                o.end
            };
            self.quiet_from = self.quiet_from.max(last + Millis(1));
        }
    }

    /// Replaces the zone closures (a zone announced or withdrawn during the day,
    /// docs/reference.md#zones-announced-during-the-day); the flights held are kept as they are.
    /// `closures` must be for the same airspace.
    pub fn set_closures(&mut self, closures: &Closures) {
        for (i, book) in self.nodes.iter_mut().enumerate() {
            book.zones = barriers(closures.node(NodeId(i as u32)), Millis::ZERO);
        }
        for (i, book) in self.edges.iter_mut().enumerate() {
            book.zones = barriers(closures.edge(EdgeId(i as u32)), book.w);
        }
        self.note_zone_changes();
    }

    /// The traversal time of edge `e`.
    #[inline]
    pub(crate) fn traversal(&self, e: EdgeId) -> Millis {
        self.edges[e.index()].w
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
    pub(crate) fn node_slot(&self, v: NodeId, t: Instant) -> NodeSlot {
        let book = &self.nodes[v.index()];
        let views = [
            book.stays.view(self.tau, t, self.horizon),
            View {
                occ: &book.zones,
                ..View::EMPTY
            },
        ];
        match &self.relation {
            Some(r) if !r.links(Movement::Stay(v)).is_empty() => {
                self.slot_separated(&views, r, Movement::Stay(v), t)
            }
            _ => slot(&views, t),
        }
    }

    /// The slot of `t` over `views` and the barriers metric separation puts on `target`.
    fn slot_separated(
        &self,
        views: &[View<'_>],
        relation: &Relation,
        target: Movement,
        t: Instant,
    ) -> NodeSlot {
        let links = relation.links(target);
        let (horizon, base) = (self.horizon, views.len());
        let view = |i: usize| match i.checked_sub(base) {
            None => views[i],
            Some(k) => {
                let link = &links[k];
                self.book(target_of(link.source))
                    .view_within(link.lo, link.hi, t, horizon)
            }
        };
        slot_of_views(base + links.len(), view, t)
    }

    /// The first instant `p ≥ t` at which edge `e` may be entered in direction `dir`, and the
    /// last instant `q ≥ p` such that every entry in `[p, q]` is allowed.
    #[inline]
    pub(crate) fn edge_free_run(&self, e: EdgeId, dir: Dir, t: Instant) -> (Instant, Instant) {
        let book = &self.edges[e.index()];
        let h = self.horizon;
        let views = [
            // A headway of 0 blocks nothing.
            if book.same_grow > Millis::ZERO {
                book.dirs[dir.index()].view(book.same_grow, t, h)
            } else {
                View::EMPTY
            },
            book.dirs[dir.opposite().index()].view(book.w, t, h),
            View {
                occ: &book.zones,
                ..View::EMPTY
            },
        ];
        let target = Movement::Traversal(e, dir == Dir::Forward);
        let separated = self
            .relation
            .as_deref()
            .filter(|r| !r.links(target).is_empty());
        let mut p = t;
        loop {
            let at = match separated {
                Some(rel) => self.slot_separated(&views, rel, target, p),
                None => slot(&views, p),
            };
            match at {
                NodeSlot::Safe { hi, .. } => return (p, hi),
                NodeSlot::Blocked { next_free } => p = next_free,
            }
        }
    }

    /// Declares that queries from now on are about instants `≥ t` (for first-come,
    /// first-served planning: the next request's departure). Searches then skip every
    /// reservation that can no longer matter, so they stay fast however long the day grows.
    /// Queries before the horizon remain correct, only slower; moving the horizon back resets
    /// the skipping.
    pub fn set_horizon(&mut self, t: Instant) {
        if t < self.horizon {
            for b in &mut self.nodes {
                b.stays.floor = 0;
            }
            for e in &mut self.edges {
                for b in &mut e.dirs {
                    b.floor = 0;
                }
            }
        }
        self.horizon = t;
    }

    /// The current horizon (see [`Schedule::set_horizon`]).
    pub fn horizon(&self) -> Instant {
        self.horizon
    }

    /// Drops from memory every reservation that can no longer matter to a query at or after
    /// the horizon (those the searches already skip), keeping in each list only the last of
    /// them, whose end still bounds the safe interval that follows it. Returns how many were
    /// dropped. After this, queries before the horizon may miss reservations and the flights
    /// they belonged to can no longer be [removed](Schedule::remove): call it only once the
    /// horizon is a clock that never goes back (the online planner's now).
    pub fn forget_past(&mut self) -> usize {
        let mut dropped = 0;
        let books = self
            .nodes
            .iter_mut()
            .map(|n| &mut n.stays)
            .chain(self.edges.iter_mut().flat_map(|e| e.dirs.iter_mut()));
        for book in books {
            if book.floor > 1 {
                let n = book.floor - 1;
                book.occ.drain(..n);
                book.floor = 1;
                dropped += n;
            }
        }
        self.reservations -= dropped;
        dropped
    }

    /// Bytes of reservation memory in use (the lists' capacities), for monitoring.
    pub fn reservation_bytes(&self) -> usize {
        let books = self
            .nodes
            .iter()
            .map(|n| &n.stays)
            .chain(self.edges.iter().flat_map(|e| e.dirs.iter()));
        books
            .map(|b| b.occ.capacity() * std::mem::size_of::<Occ>())
            .sum()
    }

    /// The widest widening any view applies to a list: how long after its end a
    /// reservation there still forbids anything.
    fn grow_max(&self, target: Target) -> Millis {
        let rules = match target {
            Target::Node(_) => self.tau,
            Target::Edge(e, _) => {
                let book = &self.edges[e.index()];
                book.same_grow.max(book.w)
            }
        };
        self.relation
            .as_deref()
            .map_or(rules, |r| rules.max(r.reach(movement_of(target))))
    }

    /// Adds an accepted plan. The plan must be valid against the schedule (the planner's
    /// plans are); the schedule does not re-check it (the verifier does).
    pub fn insert(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) {
        let horizon = self.horizon;
        for_each_reservation(airspace, flight, plan, |target, occ| {
            let grow_max = self.grow_max(target);
            self.quiet_from = self.quiet_from.max(occ.end + grow_max + Millis(1));
            let book = self.book_mut(target);
            let i = insertion_point(&book.occ, occ);
            book.occ.insert(i, occ);
            if i < book.floor {
                book.floor += 1;
            }
            book.advance(horizon, grow_max);
            self.reservations += 1;
        });
        self.flights += 1;
    }

    /// Removes a plan previously inserted with the same `flight` (a cancellation). Returns
    /// `false`, and removes nothing, if any of its reservations is not held.
    pub fn remove(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) -> bool {
        let mut all_held = true;
        for_each_reservation(airspace, flight, plan, |target, occ| {
            all_held &= position(&self.book(target).occ, occ).is_some();
        });
        if all_held {
            self.release(airspace, flight, plan);
        }
        all_held
    }

    /// Removes every reservation of a plan previously inserted with the same `flight` that
    /// the schedule still holds, and counts the flight out. Unlike [`Schedule::remove`] it
    /// does not mind reservations already [forgotten](Schedule::forget_past): replanning an
    /// airborne flight (docs/reference.md#zones-announced-during-the-day) releases plans that began
    /// before now.
    pub fn release(&mut self, airspace: &Airspace, flight: FlightId, plan: &Plan) {
        for_each_reservation(airspace, flight, plan, |target, occ| {
            let book = self.book_mut(target);
            if let Some(i) = position(&book.occ, occ) {
                book.occ.remove(i);
                if i < book.floor {
                    book.floor -= 1;
                }
                self.reservations -= 1;
            }
        });
        self.flights = self.flights.saturating_sub(1);
    }

    fn book(&self, target: Target) -> &Book {
        match target {
            Target::Node(v) => &self.nodes[v.index()].stays,
            Target::Edge(e, dir) => &self.edges[e.index()].dirs[dir.index()],
        }
    }

    fn book_mut(&mut self, target: Target) -> &mut Book {
        match target {
            Target::Node(v) => &mut self.nodes[v.index()].stays,
            Target::Edge(e, dir) => &mut self.edges[e.index()].dirs[dir.index()],
        }
    }
}

/// Where a reservation is held.
#[derive(Clone, Copy, Debug)]
enum Target {
    Node(NodeId),
    Edge(EdgeId, Dir),
}

/// The movement whose reservations a list holds.
fn movement_of(target: Target) -> Movement {
    match target {
        Target::Node(v) => Movement::Stay(v),
        Target::Edge(e, dir) => Movement::Traversal(e, dir == Dir::Forward),
    }
}

/// The list that holds a movement's reservations.
fn target_of(m: Movement) -> Target {
    match m {
        Movement::Stay(v) => Target::Node(v),
        Movement::Traversal(e, forward) => Target::Edge(e, Dir::of(forward)),
    }
}

/// Calls `f` on every reservation a plan makes: a stay per node visited and an entry instant
/// per traversal (a multi-leg plan's time on the ground between legs reserves nothing).
fn for_each_reservation(
    airspace: &Airspace,
    flight: FlightId,
    plan: &Plan,
    mut f: impl FnMut(Target, Occ),
) {
    for stay in &plan.path {
        f(
            Target::Node(stay.node),
            Occ {
                start: stay.arrive,
                end: stay.depart,
                flight,
            },
        );
    }
    for (from, to) in plan.hops() {
        let e = airspace
            .edge_between(from.node, to.node)
            .expect("consecutive stays of a leg are joined by an edge");
        let dir = Dir::of(airspace.edge(e).from == from.node);
        let s = from.depart;
        f(
            Target::Edge(e, dir),
            Occ {
                start: s,
                end: s,
                flight,
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_airspace::closures::resolve;
    use muse_model::testing::plan;
    use muse_model::{Period, Zone};

    /// A — B, 1 km (120 s at 30 km/h).
    fn line() -> Airspace {
        Airspace::line(&[1_000.0])
    }

    /// The free run of entries of the line's edge from `t` on, in ms.
    fn run(s: &Schedule, dir: Dir, t: i64) -> (i64, i64) {
        let (first, last) = s.edge_free_run(EdgeId(0), dir, Instant(t));
        (first.0, last.0)
    }

    /// "Never", in ms.
    const INF: i64 = Instant::INF.0;

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
            FlightId(7),
            &plan(&[(0, 100_000, 110_000), (1, 230_000, 230_000)]),
        );
        let v = NodeId(0);
        // Blocked strictly inside (95 s, 115 s); the ends are free.
        assert_eq!(
            s.node_slot(v, Instant(95_001)),
            NodeSlot::Blocked {
                next_free: Instant(115_000)
            }
        );
        assert_eq!(
            s.node_slot(v, Instant(114_999)),
            NodeSlot::Blocked {
                next_free: Instant(115_000)
            }
        );
        assert_eq!(
            s.node_slot(v, Instant(95_000)),
            NodeSlot::Safe {
                lo: Instant::NEG_INF,
                hi: Instant(95_000),
                next: Instant(115_000)
            }
        );
        assert_eq!(
            s.node_slot(v, Instant(115_000)),
            NodeSlot::Safe {
                lo: Instant(115_000),
                hi: Instant::INF,
                next: Instant::INF
            }
        );
        assert_eq!(s.flights(), 1);
        assert_eq!(s.reservations(), 3);
        assert!(s.remove(
            &a,
            FlightId(7),
            &plan(&[(0, 100_000, 110_000), (1, 230_000, 230_000)])
        ));
        assert_eq!(
            s.node_slot(v, Instant(100_000)),
            NodeSlot::Safe {
                lo: Instant::NEG_INF,
                hi: Instant::INF,
                next: Instant::INF
            }
        );
        assert!(!s.remove(
            &a,
            FlightId(7),
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
        s.insert(
            &a,
            FlightId(1),
            &plan(&[(0, 50_000, 50_000), (1, 170_000, 170_000)]),
        );
        // Arriving before 50 s: may stay until 50 s, not beyond.
        assert_eq!(
            s.node_slot(NodeId(0), Instant(40_000)),
            NodeSlot::Safe {
                lo: Instant::NEG_INF,
                hi: Instant(50_000),
                next: Instant(50_000)
            }
        );
        // Arriving at 50 s: the later interval, from 50 s on.
        assert_eq!(
            s.node_slot(NodeId(0), Instant(50_000)),
            NodeSlot::Safe {
                lo: Instant(50_000),
                hi: Instant::INF,
                next: Instant::INF
            }
        );
    }

    #[test]
    fn edge_rules() {
        let a = line();
        let plan1 = plan(&[(0, 0, 0), (1, 120_000, 120_000)]); // enters A→B at 0
        let exclusive = FlightParams::default();
        let mut s = schedule(&exclusive, &[]);
        s.insert(&a, FlightId(1), &plan1);
        // Same direction: no entry in (−120 s, 120 s).
        assert_eq!(run(&s, Dir::Forward, -200_000), (-200_000, -120_000));
        assert_eq!(run(&s, Dir::Forward, -119_999), (120_000, INF));
        // Opposite direction: the same under `exclusive`.
        assert_eq!(run(&s, Dir::Backward, 1), (120_000, INF));
        let headway = FlightParams {
            edge_rule: EdgeRule::Headway(Millis(5_000)),
            ..exclusive
        };
        let mut s = schedule(&headway, &[]);
        s.insert(&a, FlightId(1), &plan1);
        assert_eq!(run(&s, Dir::Forward, 1), (5_000, INF));
        assert_eq!(run(&s, Dir::Forward, -10_000), (-10_000, -5_000));
        assert_eq!(run(&s, Dir::Backward, 1), (120_000, INF));
        let zero = FlightParams {
            edge_rule: EdgeRule::Headway(Millis::ZERO),
            ..exclusive
        };
        let mut s = schedule(&zero, &[]);
        s.insert(&a, FlightId(1), &plan1);
        assert_eq!(
            run(&s, Dir::Forward, 0),
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
            announced: None,
            withdrawn: None,
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
            periods: vec![Period {
                start: Some(Instant(1_000_000)),
                end: Some(Instant(2_000_000)),
                daily: vec![],
            }],
        };
        let s = schedule(&FlightParams::default(), &[zone]);
        // A stay at B must end before 1000 s or begin at or after 2000 s.
        assert_eq!(
            s.node_slot(NodeId(1), Instant(999_999)),
            NodeSlot::Safe {
                lo: Instant::NEG_INF,
                hi: Instant(999_999),
                next: Instant(2_000_000)
            }
        );
        assert_eq!(
            s.node_slot(NodeId(1), Instant(1_000_000)),
            NodeSlot::Blocked {
                next_free: Instant(2_000_000)
            }
        );
        // A traversal [s, s + 120 s] must end before 1000 s or start at or after 2000 s.
        assert_eq!(run(&s, Dir::Forward, 0), (0, 879_999));
        assert_eq!(run(&s, Dir::Backward, 880_000), (2_000_000, INF));
    }
}
