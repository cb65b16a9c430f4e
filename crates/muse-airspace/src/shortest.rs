//! Dijkstra on integer millisecond traversal times.
//!
//! Edges are undirected, so a search *from* a node gives the shortest times *to* it as well:
//! a planner gets an exact A* heuristic for a destination by one search from that destination.
//!
//! [`free_flow_times`] is the one-shot form. [`Dijkstra`] keeps its arrays and heap between
//! searches, so repeated searches (all pairs, one heuristic per request) allocate nothing after
//! the first.
//!
//! Costs are exact integer milliseconds ([`Millis`]); sums saturate at `i64::MAX` instead of
//! overflowing. Costs must be non-negative (a negative cost is a caller bug and panics).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use muse_model::{Airspace, EdgeId, Millis, NodeId};

/// Marks a node not reached by the last search.
const UNREACHED: i64 = i64::MAX;
/// Marks "no predecessor edge" (the source, or an unreached node).
const NO_EDGE: u32 = u32::MAX;

/// Shortest free-flow times from `source` to every node, indexed by [`NodeId`]; `None` for
/// nodes that cannot be reached. `times` holds each edge's traversal time, indexed by
/// [`EdgeId`], e.g. from [`Airspace::traversal_times`].
///
/// For many searches on the same airspace, reuse a [`Dijkstra`] instead.
///
/// ```
/// use muse_airspace::shortest::free_flow_times;
/// use muse_model::{Airspace, Edge, LonLat, Millis, Node, NodeId, NodeKind, Speed};
///
/// let node = |id: &str, lon| Node {
///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3),
/// };
/// let edge = |a: u32, b: u32, m| Edge {
///     id: format!("{a}-{b}"), from: NodeId(a), to: NodeId(b), length_m: m,
/// };
/// // A - B - C in a line, plus an island D.
/// let airspace = Airspace::new(
///     vec![node("A", 103.80), node("B", 103.81), node("C", 103.82), node("D", 103.9)],
///     vec![edge(0, 1, 1_000.0), edge(1, 2, 500.0)],
/// )
/// .unwrap();
/// let times = airspace.traversal_times(Speed::PAPER); // 30 km/h: 1 km = 120 s
/// let t = free_flow_times(&airspace, &times, NodeId(0));
/// assert_eq!(t, vec![Some(Millis(0)), Some(Millis(120_000)), Some(Millis(180_000)), None]);
/// ```
pub fn free_flow_times(
    airspace: &Airspace,
    times: &[Millis],
    source: NodeId,
) -> Vec<Option<Millis>> {
    let mut search = Dijkstra::new(airspace.node_count());
    search.run(airspace, times, source);
    search.to_vec()
}

/// A reusable Dijkstra search over an [`Airspace`].
///
/// Holds one distance and one predecessor entry per node plus the heap; [`Dijkstra::run`] and
/// friends reuse them, so after the first search nothing is allocated (the arrays grow if a
/// larger airspace comes along). Results of the last search are read with
/// [`Dijkstra::time_to`], [`Dijkstra::path_to`] and [`Dijkstra::to_vec`].
///
/// ```
/// use muse_airspace::shortest::Dijkstra;
/// use muse_model::{Airspace, Edge, LonLat, Millis, Node, NodeId, NodeKind};
///
/// let node = |id: &str, lon| Node {
///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3),
/// };
/// let edge = |a: u32, b: u32| Edge {
///     id: format!("{a}-{b}"), from: NodeId(a), to: NodeId(b), length_m: 100.0,
/// };
/// // A square A-B-C-D-A plus the diagonal A-C.
/// let airspace = Airspace::new(
///     vec![node("A", 103.80), node("B", 103.81), node("C", 103.82), node("D", 103.83)],
///     vec![edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 0), edge(0, 2)],
/// )
/// .unwrap();
/// let times = [Millis(10), Millis(10), Millis(10), Millis(10), Millis(50)];
/// let mut search = Dijkstra::new(airspace.node_count());
/// search.run(&airspace, &times, NodeId(0));
/// assert_eq!(search.time_to(NodeId(2)), Some(Millis(20)));
/// assert_eq!(search.path_to(&airspace, NodeId(2)).unwrap().len(), 3);
/// // Same scratch, another source, and the diagonal made cheap.
/// let cheap = [Millis(10), Millis(10), Millis(10), Millis(10), Millis(5)];
/// search.run(&airspace, &cheap, NodeId(2));
/// assert_eq!(search.time_to(NodeId(0)), Some(Millis(5)));
/// assert_eq!(search.path_to(&airspace, NodeId(0)), Some(vec![NodeId(2), NodeId(0)]));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Dijkstra {
    dist: Vec<i64>,
    pred: Vec<u32>,
    heap: BinaryHeap<Reverse<(i64, u32)>>,
    source: Option<NodeId>,
}

impl Dijkstra {
    /// A workspace sized for airspaces of up to `node_count` nodes (it grows on demand).
    pub fn new(node_count: usize) -> Self {
        Dijkstra {
            dist: Vec::with_capacity(node_count),
            pred: Vec::with_capacity(node_count),
            heap: BinaryHeap::with_capacity(node_count),
            source: None,
        }
    }

    /// Shortest times from `source` to every node, with edge costs `times` (indexed by
    /// [`EdgeId`]).
    ///
    /// Panics if `times` is shorter than the edge list or holds a negative time.
    pub fn run(&mut self, airspace: &Airspace, times: &[Millis], source: NodeId) {
        assert!(
            times.len() >= airspace.edge_count(),
            "one traversal time per edge is needed"
        );
        self.search(airspace, source, None, |e| Some(times[e.index()]));
    }

    /// Like [`Dijkstra::run`], but stops as soon as `target` is settled and returns its time
    /// (`None` if unreachable). Times of nodes settled before `target` are final; others are
    /// upper bounds or unreached.
    pub fn run_to(
        &mut self,
        airspace: &Airspace,
        times: &[Millis],
        source: NodeId,
        target: NodeId,
    ) -> Option<Millis> {
        assert!(
            times.len() >= airspace.edge_count(),
            "one traversal time per edge is needed"
        );
        self.search(airspace, source, Some(target), |e| Some(times[e.index()]));
        self.time_to(target)
    }

    /// The general form: edge costs come from `cost`, and an edge whose cost is `None` is not
    /// used (e.g. a permanently closed corridor). With `target`, the search stops once it is
    /// settled.
    ///
    /// Panics if `cost` returns a negative time.
    pub fn search<F>(
        &mut self,
        airspace: &Airspace,
        source: NodeId,
        target: Option<NodeId>,
        cost: F,
    ) where
        F: FnMut(EdgeId) -> Option<Millis>,
    {
        self.search_from(airspace, &[source], target, false, cost);
        self.source = Some(source);
    }

    /// Shortest times from the nearest of several `sources` to every node (a multi-source
    /// search: each node's time is to whichever source is closest), with edge costs `times`.
    /// [`Dijkstra::source`] is then `None`; [`Dijkstra::path_to`] leads back to the nearest
    /// source.
    ///
    /// ```
    /// use muse_airspace::shortest::Dijkstra;
    /// use muse_model::{Airspace, Edge, LonLat, Millis, Node, NodeId, NodeKind};
    /// let node = |id: &str| Node { id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(103.8, 1.3) };
    /// let edge = |id: &str, a, b, l| Edge { id: id.into(), from: NodeId(a), to: NodeId(b), length_m: l };
    /// let airspace = Airspace::new(
    ///     vec![node("A"), node("B"), node("C")],
    ///     vec![edge("A-B", 0, 1, 1.0), edge("B-C", 1, 2, 1.0)],
    /// ).unwrap();
    /// let mut search = Dijkstra::new(3);
    /// search.run_from_all(&airspace, &[Millis(4), Millis(1)], &[NodeId(0), NodeId(2)]);
    /// assert_eq!(search.time_to(NodeId(1)), Some(Millis(1)), "C is nearer to B than A is");
    /// ```
    ///
    /// Panics if `times` is shorter than the edge list or holds a negative time.
    pub fn run_from_all(&mut self, airspace: &Airspace, times: &[Millis], sources: &[NodeId]) {
        assert!(
            times.len() >= airspace.edge_count(),
            "one traversal time per edge is needed"
        );
        self.search_from(airspace, sources, None, false, |e| Some(times[e.index()]));
    }

    /// Shortest times from every node to the nearest of `targets` (each node's time is to
    /// whichever target it reaches first), searching backwards along the edges: the same as
    /// [`Dijkstra::run_from_all`] unless some corridor is one-way (a heading rule,
    /// docs/reference.md#layered-airspace). [`Dijkstra::path_to`] is not meaningful after it.
    ///
    /// ```
    /// use muse_airspace::shortest::Dijkstra;
    /// use muse_model::{Airspace, HeadingRule, Layers, Millis, NodeId};
    /// // A — B eastward; with the semicircular rule, layer 1 is flown east only, layer 2
    /// // west only: from B to A means climbing to B@2 and flying west.
    /// let air = Airspace::line(&[1_000.0])
    ///     .layered(&Layers { count: 2, heading_rule: HeadingRule::Sectors, ..Layers::default() })
    ///     .unwrap();
    /// let times = air.traversal_times(muse_model::Speed::default());
    /// let mut search = Dijkstra::new(air.node_count());
    /// search.run_towards_all(&air, &times, &[NodeId(0)]);
    /// assert_eq!(search.time_to(NodeId(1)), Some(Millis(1_829 + 120_000 + 1_829)));
    /// search.run_from_all(&air, &times, &[NodeId(0)]);
    /// assert_eq!(search.time_to(NodeId(1)), Some(Millis(120_000)));
    /// ```
    ///
    /// Panics if `times` is shorter than the edge list or holds a negative time.
    pub fn run_towards_all(&mut self, airspace: &Airspace, times: &[Millis], targets: &[NodeId]) {
        assert!(
            times.len() >= airspace.edge_count(),
            "one traversal time per edge is needed"
        );
        self.search_from(airspace, targets, None, true, |e| Some(times[e.index()]));
    }

    fn search_from<F>(
        &mut self,
        airspace: &Airspace,
        sources: &[NodeId],
        target: Option<NodeId>,
        backward: bool,
        mut cost: F,
    ) where
        F: FnMut(EdgeId) -> Option<Millis>,
    {
        let n = airspace.node_count();
        self.dist.clear();
        self.dist.resize(n, UNREACHED);
        self.pred.clear();
        self.pred.resize(n, NO_EDGE);
        self.heap.clear();
        self.source = None;
        for &source in sources {
            assert!(
                source.index() < n,
                "source {source} is not a node of this airspace"
            );
            self.dist[source.index()] = 0;
            self.heap.push(Reverse((0, source.0)));
        }
        while let Some(Reverse((d, u))) = self.heap.pop() {
            if d > self.dist[u as usize] {
                continue; // stale entry
            }
            if target.is_some_and(|t| t.0 == u) {
                break;
            }
            let next = if backward {
                airspace.predecessors(NodeId(u))
            } else {
                airspace.neighbours(NodeId(u))
            };
            for adj in next {
                let Some(w) = cost(adj.edge) else { continue };
                assert!(
                    w.0 >= 0,
                    "negative traversal time {} ms on {}",
                    w.0,
                    adj.edge
                );
                let nd = d.saturating_add(w.0);
                let v = adj.node.index();
                if nd < self.dist[v] {
                    self.dist[v] = nd;
                    self.pred[v] = adj.edge.0;
                    self.heap.push(Reverse((nd, adj.node.0)));
                }
            }
        }
    }

    /// The source of the last search, if any.
    pub fn source(&self) -> Option<NodeId> {
        self.source
    }

    /// Shortest time from the last search's source to `n` (`None` if unreachable or not
    /// searched).
    #[inline]
    pub fn time_to(&self, n: NodeId) -> Option<Millis> {
        match self.dist.get(n.index()) {
            Some(&d) if d != UNREACHED => Some(Millis(d)),
            _ => None,
        }
    }

    /// The edge by which the shortest path from the source enters `n` (`None` for the source
    /// and unreached nodes).
    #[inline]
    pub fn predecessor_edge(&self, n: NodeId) -> Option<EdgeId> {
        match self.pred.get(n.index()) {
            Some(&e) if e != NO_EDGE => Some(EdgeId(e)),
            _ => None,
        }
    }

    /// The nodes of a shortest path from the last search's source to `n`, both included
    /// (`None` if `n` was not reached). `airspace` must be the one searched.
    pub fn path_to(&self, airspace: &Airspace, n: NodeId) -> Option<Vec<NodeId>> {
        self.time_to(n)?;
        let mut path = vec![n];
        let mut cur = n;
        while let Some(e) = self.predecessor_edge(cur) {
            cur = airspace.edge(e).other(cur);
            path.push(cur);
        }
        path.reverse();
        Some(path)
    }

    /// Shortest times from the last search, indexed by [`NodeId`].
    pub fn to_vec(&self) -> Vec<Option<Millis>> {
        self.dist
            .iter()
            .map(|&d| (d != UNREACHED).then_some(Millis(d)))
            .collect()
    }

    /// Raw distances of the last search in milliseconds, indexed by [`NodeId`], with
    /// `i64::MAX` for unreached nodes: the cheapest form for an A* heuristic lookup.
    #[inline]
    pub fn raw_times(&self) -> &[i64] {
        &self.dist
    }
}

#[cfg(test)]
#[allow(clippy::many_single_char_names, clippy::needless_range_loop)]
mod tests {
    use super::*;
    use muse_model::testing::{airspace, named_edge, station};
    use muse_model::{Node, Speed};

    /// `SplitMix64`: a tiny deterministic generator, enough for test graphs.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }

        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }
    }

    fn node(i: usize) -> Node {
        station(&format!("N{i}"), 103.8 + i as f64 * 0.001, 1.3)
    }

    /// A random simple graph with `n` nodes, each pair joined with probability `p_percent`,
    /// and random edge times in `0..=max_ms` (zero included on purpose).
    fn random_graph(
        rng: &mut Rng,
        n: usize,
        p_percent: u64,
        max_ms: u64,
    ) -> (Airspace, Vec<Millis>) {
        let mut edges = Vec::new();
        let mut times = Vec::new();
        for a in 0..n {
            for b in a + 1..n {
                if rng.below(100) < p_percent {
                    // Random orientation, so both directions of the CSR are exercised.
                    let (from, to) = if rng.below(2) == 0 { (a, b) } else { (b, a) };
                    let id = format!("E{}", edges.len());
                    edges.push(named_edge(&id, from as u32, to as u32, 1.0));
                    times.push(Millis(rng.below(max_ms + 1) as i64));
                }
            }
        }
        (airspace((0..n).map(node).collect(), edges), times)
    }

    fn floyd_warshall(airspace: &Airspace, times: &[Millis]) -> Vec<Vec<Option<i64>>> {
        let n = airspace.node_count();
        let mut d = vec![vec![None; n]; n];
        for (i, row) in d.iter_mut().enumerate() {
            row[i] = Some(0);
        }
        for (e, edge) in airspace.edges().iter().enumerate() {
            let (a, b) = (edge.from.index(), edge.to.index());
            let w = times[e].0;
            for (x, y) in [(a, b), (b, a)] {
                if d[x][y].is_none_or(|cur| w < cur) {
                    d[x][y] = Some(w);
                }
            }
        }
        for k in 0..n {
            for i in 0..n {
                for j in 0..n {
                    if let (Some(ik), Some(kj)) = (d[i][k], d[k][j])
                        && d[i][j].is_none_or(|cur| ik + kj < cur)
                    {
                        d[i][j] = Some(ik + kj);
                    }
                }
            }
        }
        d
    }

    #[test]
    fn matches_floyd_warshall_on_random_graphs() {
        let seed = std::env::var("MUSE_TEST_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0x5EED_2026_u64);
        println!("shortest-path oracle test seed: {seed} (set MUSE_TEST_SEED to replay)");
        let mut rng = Rng(seed);
        let mut search = Dijkstra::new(0);
        for round in 0..300 {
            let n = 1 + rng.below(14) as usize;
            let p = rng.below(101);
            let max_ms = [0, 3, 1_000, 3_600_000][rng.below(4) as usize];
            let (airspace, times) = random_graph(&mut rng, n, p, max_ms);
            let oracle = floyd_warshall(&airspace, &times);
            for s in 0..n {
                let source = NodeId(s as u32);
                search.run(&airspace, &times, source);
                let got = search.to_vec();
                let want: Vec<Option<Millis>> = oracle[s].iter().map(|d| d.map(Millis)).collect();
                assert_eq!(got, want, "seed {seed}, round {round}, source {s}");
                assert_eq!(
                    free_flow_times(&airspace, &times, source),
                    want,
                    "seed {seed}, round {round}"
                );
                for t in 0..n {
                    let target = NodeId(t as u32);
                    // The path's edges add up to the distance, and it runs source → target.
                    if let Some(path) = search.path_to(&airspace, target) {
                        assert_eq!(path.first(), Some(&source));
                        assert_eq!(path.last(), Some(&target));
                        let total: i64 = path
                            .windows(2)
                            .map(|w| times[airspace.edge_between(w[0], w[1]).unwrap().index()].0)
                            .sum();
                        assert_eq!(
                            Some(total),
                            oracle[s][t],
                            "seed {seed}, round {round}, {s}->{t}"
                        );
                    } else {
                        assert_eq!(oracle[s][t], None);
                    }
                }
            }
            // Early exit agrees too.
            let (s, t) = (rng.below(n as u64) as usize, rng.below(n as u64) as usize);
            let mut early = Dijkstra::default();
            let got = early.run_to(&airspace, &times, NodeId(s as u32), NodeId(t as u32));
            assert_eq!(
                got,
                oracle[s][t].map(Millis),
                "seed {seed}, round {round}, run_to {s}->{t}"
            );
        }
    }

    #[test]
    fn excluded_edges_are_not_used() {
        // A - B - C, A - C. Excluding A - C forces the detour.
        let airspace = airspace(
            (0..3).map(node).collect(),
            vec![
                named_edge("AB", 0, 1, 1_000.0),
                named_edge("BC", 1, 2, 1_000.0),
                named_edge("AC", 0, 2, 1_500.0),
            ],
        );
        let times = airspace.traversal_times(Speed::PAPER);
        let mut search = Dijkstra::new(3);
        search.run(&airspace, &times, NodeId(0));
        assert_eq!(search.time_to(NodeId(2)), Some(Millis(180_000)));
        assert_eq!(search.predecessor_edge(NodeId(2)), Some(EdgeId(2)));
        search.search(&airspace, NodeId(0), None, |e| {
            (e != EdgeId(2)).then(|| times[e.index()])
        });
        assert_eq!(search.time_to(NodeId(2)), Some(Millis(240_000)));
        assert_eq!(
            search.path_to(&airspace, NodeId(2)),
            Some(vec![NodeId(0), NodeId(1), NodeId(2)])
        );
        assert_eq!(search.source(), Some(NodeId(0)));
        assert_eq!(search.predecessor_edge(NodeId(0)), None);
    }
}
