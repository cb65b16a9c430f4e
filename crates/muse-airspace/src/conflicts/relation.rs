//! The conflict relation of an airspace (docs/reference.md#metric-separation): for every
//! movement a schedule keeps reservations of (the stays at a node, the traversals of an edge in
//! one direction), the other movements whose reservations forbid some of its own, and which.
//!
//! A reservation of movement `S` is a stay `[start, end]` at a node or an entry instant
//! `start = end` of a corridor or vertical link. Each [`Link`] of a target movement `T` says
//! that such a reservation of its `source` forbids `T`'s own reservations as the barrier
//! `(start + lo, end + hi)` of the schedule (docs/reference.md#flight-model-and-separation):
//! a stay `[x, y]` of `T` is allowed when `y ≤ L` or `x ≥ R`, an entry `s` when `s ≤ L` or
//! `s ≥ R`. The exact intervals of [`super::offsets`] and [`super::near_window`] are widened
//! outward to whole milliseconds (by at most a millisecond at each end). Links whose barrier
//! the time rules already impose (the node separation `τ` between stays at one node, the edge
//! rule between entries of one edge) are left out: they would forbid nothing more.
//!
//! ```
//! use muse_airspace::conflicts::{Movement, Relation};
//! use muse_model::{Airspace, FlightParams, Metres, Millis, NodeId, Separation};
//! // A — B — C in a straight line: no corner, nothing but the time rules.
//! let params = FlightParams {
//!     separation: Separation::horizontal(Metres::from_mm(30_000)),
//!     ..FlightParams::default()
//! };
//! let line = Airspace::line(&[1_000.0, 1_000.0]);
//! let straight = Relation::new(&line, &params);
//! assert_eq!(straight.links(Movement::Stay(NodeId(1))).len(), 0);
//!
//! // Bend B's second corridor back to 10° from the first: a departure from B towards C and an
//! // arrival at B from A now pass within 30 m unless 41.3 s apart (30 m / (8.33 m/s · sin 5°)).
//! let bent = line.with_plane(vec![[0.0, 0.0], [1_000.0, 0.0], [15.2, 173.6]]).unwrap();
//! let r = Relation::new(&bent, &params);
//! let a_to_b = Movement::Traversal(bent.edge_between(NodeId(0), NodeId(1)).unwrap(), true);
//! let b_to_c = Movement::Traversal(bent.edge_between(NodeId(1), NodeId(2)).unwrap(), true);
//! let link = r.links(b_to_c).iter().find(|l| l.source == a_to_b).unwrap();
//! // A→B entered at s reaches B at s + 120 s: B→C may not be entered from 41.3 s before
//! // that until then (after it, the drone at B is a stay, which τ keeps apart already).
//! assert!(link.lo > Millis(120_000 - 41_400) && link.lo < Millis(120_000 - 41_200));
//! assert_eq!(link.hi, Millis(120_001));
//! ```

use muse_model::{
    Airspace, EdgeId, EdgeKind, EdgeRule, FlightParams, Layers, Millis, NodeId, Separation,
};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree, RTreeObject};

use super::{Motion, near_window, offsets};

/// A movement a schedule keeps the reservations of in one list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Movement {
    /// The stays at a node.
    Stay(NodeId),
    /// The traversals of an edge, forward (from its `from` node to its `to` node) or not.
    Traversal(EdgeId, bool),
}

/// One way a source movement's reservations forbid a target's (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Link {
    /// The movement whose reservations forbid.
    pub source: Movement,
    /// Added to a reservation's start: the barrier's `L`.
    pub lo: Millis,
    /// Added to a reservation's end: the barrier's `R`.
    pub hi: Millis,
}

/// The conflict relation of an airspace under a separation (see the module docs): computed
/// once, read by every schedule of the airspace.
#[derive(Clone, Debug)]
pub struct Relation {
    nodes: usize,
    /// Per target movement (its [`Relation::index`]), where its links begin in `links`.
    starts: Vec<u32>,
    links: Vec<Link>,
    /// Per source movement, the largest `hi` of its links (how long after its end a
    /// reservation still forbids anything); zero when it has none.
    reach: Vec<Millis>,
}

/// What the relation is built from: each movement's motion and the facts of the time rules.
struct Geometry<'a> {
    airspace: &'a Airspace,
    xyz: Vec<[f64; 3]>,
    w: Vec<Millis>,
    distance: f64,
    vertical: f64,
    tau: Millis,
    edge_rule: EdgeRule,
}

impl<'a> Geometry<'a> {
    /// The motions of `airspace`'s movements under `params`: nodes where [`Airspace::plane`]
    /// puts them, at their layers' altitudes; each edge flown in its traversal time.
    fn new(airspace: &'a Airspace, params: &FlightParams) -> Geometry<'a> {
        let layers = airspace.layers().copied().unwrap_or_default();
        let plane = airspace.plane();
        let xyz = (0..airspace.node_count())
            .map(|n| {
                let id = NodeId(n as u32);
                let p = plane[airspace.flat_node(id).index()];
                [p[0], p[1], altitude(&layers, airspace.node_layer(id))]
            })
            .collect();
        Geometry {
            airspace,
            xyz,
            w: airspace.traversal_times(params.speed),
            distance: params.separation.horizontal.m(),
            // Altitudes `V` apart to within a micrometre are `V` apart, as the verifier
            // counts them.
            vertical: params.separation.vertical_in(airspace).m()
                - Separation::VERTICAL_TOLERANCE_M,
            tau: params.node_separation,
            edge_rule: params.edge_rule,
        }
    }
}

impl Relation {
    /// The relation of `airspace` (its nodes where [`Airspace::plane`] puts them, at their
    /// layers' altitudes) under `params`' metric separation, speed and time rules. Empty when
    /// the separation is off.
    #[must_use]
    pub fn new(airspace: &Airspace, params: &FlightParams) -> Relation {
        let g = Geometry::new(airspace, params);
        let count = airspace.node_count() + 2 * airspace.edge_count();
        let mut per_target: Vec<Vec<Link>> = vec![Vec::new(); count];
        if params.separation.is_on() {
            g.collect(|target, link| {
                if !g.implied(target, link) {
                    per_target[index_of(airspace, target)].push(link);
                }
            });
        }
        let mut reach = vec![Millis::ZERO; count];
        let mut starts = Vec::with_capacity(count + 1);
        let mut links = Vec::new();
        for list in &mut per_target {
            list.sort_by_key(|l| (index_of(airspace, l.source), l.lo, l.hi));
            list.dedup();
            starts.push(u32::try_from(links.len()).expect("fewer than 2³² links"));
            for l in list.iter() {
                let r = &mut reach[index_of(airspace, l.source)];
                *r = (*r).max(l.hi);
            }
            links.extend_from_slice(list);
        }
        starts.push(u32::try_from(links.len()).expect("fewer than 2³² links"));
        Relation {
            nodes: airspace.node_count(),
            starts,
            links,
            reach,
        }
    }

    /// The index of a movement in per-movement tables: a node's stays at its own index, then
    /// each edge's forward and backward traversals.
    #[inline]
    #[must_use]
    pub fn index(&self, m: Movement) -> usize {
        movement_index(self.nodes, m)
    }

    /// The links of target `m`: every barrier other movements' reservations put on it.
    #[inline]
    #[must_use]
    pub fn links(&self, m: Movement) -> &[Link] {
        let i = self.index(m);
        &self.links[self.starts[i] as usize..self.starts[i + 1] as usize]
    }

    /// How long after its end a reservation of `m` still forbids anything on another
    /// movement (the largest `hi` of `m`'s links, zero when none).
    #[inline]
    #[must_use]
    pub fn reach(&self, m: Movement) -> Millis {
        self.reach[self.index(m)]
    }

    /// Every movement with links, and its links.
    pub fn targets(&self) -> impl Iterator<Item = (Movement, &[Link])> + '_ {
        (0..self.starts.len() - 1).filter_map(move |i| {
            let links = &self.links[self.starts[i] as usize..self.starts[i + 1] as usize];
            let m = match i.checked_sub(self.nodes) {
                None => Movement::Stay(NodeId(i as u32)),
                Some(k) => Movement::Traversal(EdgeId((k / 2) as u32), k % 2 == 0),
            };
            (!links.is_empty()).then_some((m, links))
        })
    }

    /// The number of links.
    #[must_use]
    pub fn len(&self) -> usize {
        self.links.len()
    }

    /// Whether there are no links (the separation is off, or the time rules already keep it).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.links.is_empty()
    }
}

/// The altitude of layer `k` (1 when flat), metres.
fn altitude(layers: &Layers, k: u32) -> f64 {
    layers.altitude(k.max(1)).m()
}

/// [`Relation::index`] of `m` in an airspace of `nodes` nodes.
fn movement_index(nodes: usize, m: Movement) -> usize {
    match m {
        Movement::Stay(v) => v.index(),
        Movement::Traversal(e, forward) => nodes + 2 * e.index() + usize::from(!forward),
    }
}

/// [`Relation::index`] before the relation exists.
fn index_of(airspace: &Airspace, m: Movement) -> usize {
    movement_index(airspace.node_count(), m)
}

/// An item of the spatial index: a node (`None`) or an edge, by its box.
type Boxed = GeomWithData<Rectangle<[f64; 2]>, (Option<EdgeId>, NodeId)>;

impl Geometry<'_> {
    /// Calls `f(target, link)` on every link of every pair of movements that come closer
    /// than allowed at some offset.
    fn collect(&self, mut f: impl FnMut(Movement, Link)) {
        let a = self.airspace;
        let items: Vec<Boxed> = (0..a.node_count())
            .map(|n| {
                let p = self.xyz[n];
                Boxed::new(
                    Rectangle::from_corners([p[0], p[1]], [p[0], p[1]]),
                    (None, NodeId(n as u32)),
                )
            })
            .chain(a.edges().iter().enumerate().map(|(i, e)| {
                let (p, q) = (self.xyz[e.from.index()], self.xyz[e.to.index()]);
                Boxed::new(
                    Rectangle::from_corners([p[0], p[1]], [q[0], q[1]]),
                    (Some(EdgeId(i as u32)), e.from),
                )
            }))
            .collect();
        let tree = RTree::bulk_load(items.clone());
        let d = self.distance;
        for item in &items {
            let env = item.geom().envelope();
            let (lo, hi) = (env.lower(), env.upper());
            let near = AABB::from_corners([lo[0] - d, lo[1] - d], [hi[0] + d, hi[1] + d]);
            for other in tree.locate_in_envelope_intersecting(&near) {
                self.pair(item.data, other.data, &mut f);
            }
        }
    }

    /// The links between two items of the index, each unordered pair once (and an item with
    /// itself).
    fn pair(
        &self,
        (e1, n1): (Option<EdgeId>, NodeId),
        (e2, n2): (Option<EdgeId>, NodeId),
        f: &mut impl FnMut(Movement, Link),
    ) {
        match (e1, e2) {
            (None, None) if n1 <= n2 => self.stays(n1, n2, f),
            (None, Some(e)) => self.stay_and_edge(n1, e, f),
            (Some(x), Some(y)) if x <= y => self.edges(x, y, f),
            _ => {}
        }
    }

    /// Two nodes: stays at both at one instant conflict if they are within the separation.
    fn stays(&self, u: NodeId, v: NodeId, f: &mut impl FnMut(Movement, Link)) {
        let (here, there) = (self.xyz[u.index()], self.xyz[v.index()]);
        let horizontal = (here[0] - there[0]).hypot(here[1] - there[1]);
        if horizontal >= self.distance || (here[2] - there[2]).abs() >= self.vertical {
            return;
        }
        // Stays overlap unless one ends a millisecond before the other begins.
        let link = |source| Link {
            source,
            lo: Millis(-1),
            hi: Millis(1),
        };
        f(Movement::Stay(v), link(Movement::Stay(u)));
        if u != v {
            f(Movement::Stay(u), link(Movement::Stay(v)));
        }
    }

    /// A node and an edge's traversals: a traversal near the node during `(w0, w1)` after its
    /// entry conflicts with the stays there that meet that window.
    fn stay_and_edge(&self, u: NodeId, e: EdgeId, f: &mut impl FnMut(Movement, Link)) {
        let point = self.xyz[u.index()];
        for (m, motion) in self.motions(e) {
            let Some((w0, w1)) = near_window(point, &motion, self.distance, self.vertical) else {
                continue;
            };
            // An entry s' conflicts with a stay [a, d] when s' ∈ [a − w1, d − w0].
            f(
                m,
                Link {
                    source: Movement::Stay(u),
                    lo: below(-w1),
                    hi: above(-w0),
                },
            );
            // A stay [x, y] conflicts with an entry s when [x, y] meets [s + w0, s + w1].
            f(
                Movement::Stay(u),
                Link {
                    source: m,
                    lo: below(w0),
                    hi: above(w1),
                },
            );
        }
    }

    /// Two edges' traversals (or one edge's with themselves).
    fn edges(&self, x: EdgeId, y: EdgeId, f: &mut impl FnMut(Movement, Link)) {
        if !self.close(x, y) {
            return;
        }
        for (mx, a) in self.motions(x) {
            for (my, b) in self.motions(y) {
                if x == y && index_key(mx) > index_key(my) {
                    continue; // the same pair as the other way round
                }
                let Some((lo, hi)) = offsets(&a, &b, self.distance, self.vertical) else {
                    continue;
                };
                // `my` entered δ ∈ [lo, hi] after `mx` conflicts with it, and the reverse.
                f(
                    my,
                    Link {
                        source: mx,
                        lo: below(lo),
                        hi: above(hi),
                    },
                );
                if mx != my {
                    f(
                        mx,
                        Link {
                            source: my,
                            lo: below(-hi),
                            hi: above(-lo),
                        },
                    );
                }
            }
        }
    }

    /// Whether two edges' segments come within the separation horizontally, with altitudes
    /// that overlap within the vertical one (a quick test before the exact one).
    fn close(&self, x: EdgeId, y: EdgeId) -> bool {
        let ends = |e: EdgeId| {
            let edge = self.airspace.edge(e);
            (self.xyz[edge.from.index()], self.xyz[edge.to.index()])
        };
        let ((p1, p2), (q1, q2)) = (ends(x), ends(y));
        let (za, zb) = (
            (p1[2].min(p2[2]), p1[2].max(p2[2])),
            (q1[2].min(q2[2]), q1[2].max(q2[2])),
        );
        if za.0 - zb.1 >= self.vertical || zb.0 - za.1 >= self.vertical {
            return false;
        }
        segment_distance(
            [p1[0], p1[1]],
            [p2[0], p2[1]],
            [q1[0], q1[1]],
            [q2[0], q2[1]],
        ) < self.distance
    }

    /// The movements of edge `e` that may be flown, with their motions.
    fn motions(&self, e: EdgeId) -> impl Iterator<Item = (Movement, Motion)> + '_ {
        let edge = self.airspace.edge(e);
        let (p, q) = (self.xyz[edge.from.index()], self.xyz[edge.to.index()]);
        let secs = self.w[e.index()].0 as f64 / 1_000.0;
        let one_way = matches!(
            self.airspace.edge_kind(e),
            EdgeKind::Corridor { one_way: true, .. }
        );
        let forward = (Movement::Traversal(e, true), Motion::between(p, q, secs));
        let backward = (Movement::Traversal(e, false), Motion::between(q, p, secs));
        std::iter::once(forward).chain((!one_way).then_some(backward))
    }

    /// Whether the time rules already forbid everything `link` forbids on `target`: the node
    /// separation between stays at one node (a traversal's stay at the node it leaves from
    /// or arrives at included), the edge rule between entries of one edge.
    fn implied(&self, target: Movement, link: Link) -> bool {
        let inside = |(l, r): (Millis, Millis)| link.lo >= l && link.hi <= r;
        let tau = self.tau;
        // Where each movement touches each node: (node, time after its start).
        let touch = |m: Movement| -> [Option<(NodeId, Millis)>; 2] {
            match m {
                Movement::Stay(v) => [Some((v, Millis::ZERO)), None],
                Movement::Traversal(e, forward) => {
                    let edge = self.airspace.edge(e);
                    let (from, to) = if forward {
                        (edge.from, edge.to)
                    } else {
                        (edge.to, edge.from)
                    };
                    [Some((from, Millis::ZERO)), Some((to, self.w[e.index()]))]
                }
            }
        };
        let stays_apart = touch(target).into_iter().flatten().any(|(v, kt)| {
            touch(link.source).into_iter().flatten().any(|(u, ks)| {
                // Two stays at one node, at `s + ks` and `s' + kt`, are `τ` apart. For two
                // stays themselves the barrier is `(start − τ, end + τ)`.
                u == v && inside((ks - kt - tau, ks - kt + tau))
            })
        });
        if stays_apart {
            return true;
        }
        match (target, link.source) {
            (Movement::Traversal(e, d1), Movement::Traversal(f, d2)) if e == f => {
                let w = self.w[e.index()];
                let grow = if d1 == d2 {
                    match (self.airspace.edge_kind(e), self.edge_rule) {
                        (EdgeKind::Vertical { .. }, _) | (_, EdgeRule::Exclusive) => w,
                        (_, EdgeRule::Headway(h)) => h,
                    }
                } else {
                    w
                };
                inside((Millis(-grow.0), grow))
            }
            _ => false,
        }
    }
}

/// An order of movements, to take each pair of one edge's directions once.
fn index_key(m: Movement) -> (u8, u32, bool) {
    match m {
        Movement::Stay(v) => (0, v.0, false),
        Movement::Traversal(e, forward) => (1, e.0, !forward),
    }
}

/// The barrier end below an interval that begins at `seconds` (closed or open): the whole
/// millisecond before its first whole millisecond.
fn below(seconds: f64) -> Millis {
    Millis((seconds * 1_000.0).ceil() as i64 - 1)
}

/// The barrier end above an interval that ends at `seconds`: the whole millisecond after its
/// last whole millisecond.
fn above(seconds: f64) -> Millis {
    Millis((seconds * 1_000.0).floor() as i64 + 1)
}

/// The least distance between segments `p1p2` and `q1q2` in the plane.
fn segment_distance(p1: [f64; 2], p2: [f64; 2], q1: [f64; 2], q2: [f64; 2]) -> f64 {
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let (d1, d2) = (cross(q1, q2, p1), cross(q1, q2, p2));
    let (d3, d4) = (cross(p1, p2, q1), cross(p1, p2, q2));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return 0.0; // they cross
    }
    point_segment(p1, q1, q2)
        .min(point_segment(p2, q1, q2))
        .min(point_segment(q1, p1, p2))
        .min(point_segment(q2, p1, p2))
}

/// The distance from `p` to segment `ab`.
fn point_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances() {
        let d = segment_distance([0.0, 0.0], [10.0, 0.0], [5.0, -1.0], [5.0, 1.0]);
        assert!(d.abs() < 1e-12, "crossing");
        let d = segment_distance([0.0, 0.0], [10.0, 0.0], [12.0, 3.0], [20.0, 3.0]);
        assert!((d - 13f64.sqrt()).abs() < 1e-12, "end to end: {d}");
        let d = segment_distance([0.0, 0.0], [10.0, 0.0], [3.0, 2.0], [7.0, 2.0]);
        assert!((d - 2.0).abs() < 1e-12, "parallel");
    }

    /// On random airspaces of close nodes (the time rules made as weak as they go: `τ = 0`, a
    /// same-direction headway of 0), every offset at which two traversals of different edges,
    /// or of one edge one way, come closer than `D` (by the motions' exact least distance,
    /// sampled every 50 ms) is inside a barrier of the relation; and every stay instant at
    /// which a traversal is that close to a node.
    #[test]
    fn the_relation_misses_no_conflict() {
        use muse_model::testing::{airspace, edge, station};
        use muse_model::{EdgeRule, Metres, Separation, Speed};

        use crate::conflicts::approach;
        let mut seed = 0x5eed_0039_u64;
        let mut unit = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let params = FlightParams {
            speed: Speed::from_kmh(36.0).unwrap(),
            node_separation: Millis::ZERO,
            edge_rule: EdgeRule::Headway(Millis::ZERO),
            separation: Separation::horizontal(Metres::from_mm(30_000)),
            ..FlightParams::default()
        };
        let mut checked = 0;
        for _ in 0..20 {
            let plane: Vec<[f64; 2]> = (0..5).map(|_| [unit() * 300.0, unit() * 300.0]).collect();
            let nodes = (0..5)
                .map(|i| station(&format!("N{i}"), 103.8, 1.3))
                .collect();
            let length = |a: usize, b: usize| {
                let d = (plane[a][0] - plane[b][0]).hypot(plane[a][1] - plane[b][1]);
                (d / 10.0).ceil().max(1.0) * 10.0
            };
            let edges = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0), (0, 2)]
                .iter()
                .map(|&(a, b)| edge(a, b, length(a as usize, b as usize)))
                .collect();
            let air = airspace(nodes, edges).with_plane(plane.clone()).unwrap();
            let relation = Relation::new(&air, &params);
            let g = Geometry::new(&air, &params);
            let blocked = |target: Movement, source: Movement, at: i64| {
                relation
                    .links(target)
                    .iter()
                    .any(|l| l.source == source && l.lo.0 < at && at < l.hi.0)
            };
            let edges: Vec<EdgeId> = (0..air.edge_count()).map(|e| EdgeId(e as u32)).collect();
            for &x in &edges {
                for &y in &edges {
                    for (mx, a) in g.motions(x) {
                        for (my, b) in g.motions(y) {
                            let reverse = x == y && mx != my;
                            if reverse {
                                continue; // the edge rule's, whatever the metres
                            }
                            let (lo, hi) = (-(b.duration * 1e3) as i64, (a.duration * 1e3) as i64);
                            for at in (lo..=hi).step_by(50) {
                                let delta = at as f64 / 1e3;
                                if approach(&a, &b, delta, 9.144).is_some_and(|d| d < 29.99) {
                                    assert!(blocked(my, mx, at), "{my:?} {at} ms after {mx:?}");
                                    checked += 1;
                                }
                            }
                        }
                    }
                }
                for v in 0..5u32 {
                    let point = g.xyz[v as usize];
                    for (m, motion) in g.motions(x) {
                        let Some((w0, w1)) = near_window(point, &motion, 29.99, 9.144) else {
                            continue;
                        };
                        // A stay at v over the instant s + t, t in the window, conflicts.
                        let t = 0.5 * (w0 + w1);
                        let at = (t * 1e3).round() as i64;
                        let stay = Movement::Stay(NodeId(v));
                        // The stay [s + at, s + at] against an entry at s: a barrier on the
                        // stay from the traversal, and on the entry from the stay.
                        let on_stay = relation
                            .links(stay)
                            .iter()
                            .any(|l| l.source == m && l.lo.0 < at && at < l.hi.0);
                        let on_entry = relation
                            .links(m)
                            .iter()
                            .any(|l| l.source == stay && l.lo.0 < -at && -at < l.hi.0);
                        assert!(on_stay && on_entry, "{m:?} near node {v} {at} ms in");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 1_000, "{checked}");
    }

    #[test]
    fn barrier_ends_take_whole_milliseconds_outward() {
        assert_eq!(below(1.0), Millis(999));
        assert_eq!(below(1.000_4), Millis(1_000));
        assert_eq!(above(1.0), Millis(1_001));
        assert_eq!(above(0.999_9), Millis(1_000));
        assert_eq!(below(-0.5), Millis(-501));
    }
}
