//! The airspace graph: nodes (stations and waypoints) joined by undirected corridors, flat
//! (one cruise altitude) or layered ([`Airspace::layered`], docs/reference.md#layered-airspace:
//! every node and corridor at each layer, vertical links between layers, corridors one-way under a
//! heading rule).
//!
//! Built once, queried many times. Node and edge ids from files map to dense indices;
//! adjacency is stored in compressed-sparse-row form (one offsets array and one flat array
//! of `(neighbour, edge)` pairs) so that a search touches contiguous memory.

use std::collections::HashMap;
use std::sync::Arc;

mod layered;
mod plane;

use crate::coords::LonLat;
use crate::ids::{EdgeId, NodeId};
use crate::layers::Layers;
use crate::time::Millis;
use crate::units::Speed;

/// Whether a node is a landing pad.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NodeKind {
    /// A pad where trips start and end; can also be flown through.
    Station,
    /// A point in the air that can be flown through and hovered at, but not landed on.
    Waypoint,
}

impl NodeKind {
    /// The spelling used in files: `station` or `waypoint`.
    pub const fn as_str(self) -> &'static str {
        match self {
            NodeKind::Station => "station",
            NodeKind::Waypoint => "waypoint",
        }
    }
}

/// A node of the airspace.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Unique id as in files, e.g. `S001`.
    pub id: String,
    /// Station or waypoint.
    pub kind: NodeKind,
    /// Human-readable name (may be empty).
    pub name: String,
    /// Position.
    pub pos: LonLat,
}

/// An undirected corridor between two nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// Unique id as in files (by convention `FROM-TO`).
    pub id: String,
    /// One end.
    pub from: NodeId,
    /// The other end.
    pub to: NodeId,
    /// Length in metres; authoritative for timing.
    pub length_m: f64,
}

impl Edge {
    /// The end that is not `n` (or `from` if `n` is neither end).
    #[inline]
    pub fn other(&self, n: NodeId) -> NodeId {
        if n == self.from { self.to } else { self.from }
    }
}

/// What an edge of the graph is: a corridor (at a layer) or a vertical link between layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// A corridor, flown at cruise speed, at layer `layer` (1 in a flat airspace); when
    /// `one_way`, only from its `from` end to its `to` end (a heading rule).
    Corridor {
        /// The layer (1-based).
        layer: u32,
        /// Whether it may be flown only from `from` to `to`.
        one_way: bool,
    },
    /// The vertical link at a node between layer `layer` (its `from` end) and `layer + 1`
    /// (its `to` end), crossed in `time`, one drone at a time (docs/reference.md#layered-airspace).
    Vertical {
        /// The lower layer.
        layer: u32,
        /// Time to cross it.
        time: Millis,
    },
}

impl EdgeKind {
    /// A corridor of the flat airspace.
    pub const FLAT: EdgeKind = EdgeKind::Corridor {
        layer: 1,
        one_way: false,
    };
}

/// One entry of a node's adjacency list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Adjacent {
    /// The neighbour.
    pub node: NodeId,
    /// The edge leading to it.
    pub edge: EdgeId,
    /// Whether the edge is flown from its `from` end to its `to` end in this direction.
    pub forward: bool,
}

/// Why a set of nodes and edges is not a valid airspace. Indices refer to the input vectors,
/// so that readers can point at the offending feature.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AirspaceError {
    /// Two nodes share an id.
    #[error("duplicate node id `{id}` (nodes {first} and {second})")]
    DuplicateNodeId {
        /// The id.
        id: String,
        /// Index of the first node with it.
        first: usize,
        /// Index of the second node with it.
        second: usize,
    },
    /// Two edges share an id.
    #[error("duplicate edge id `{id}` (edges {first} and {second})")]
    DuplicateEdgeId {
        /// The id.
        id: String,
        /// Index of the first edge with it.
        first: usize,
        /// Index of the second edge with it.
        second: usize,
    },
    /// Two edges join the same pair of nodes.
    #[error("edges {first} and {second} both join `{a}` and `{b}`")]
    ParallelEdge {
        /// One end's id.
        a: String,
        /// The other end's id.
        b: String,
        /// Index of the first edge.
        first: usize,
        /// Index of the second edge.
        second: usize,
    },
    /// An edge joins a node to itself.
    #[error("edge {index} (`{id}`) is a self-loop at `{node}`")]
    SelfLoop {
        /// Edge index.
        index: usize,
        /// Edge id.
        id: String,
        /// Node id.
        node: String,
    },
    /// An edge's length is not a finite positive number.
    #[error("edge {index} (`{id}`) has length {length_m} m; it must be a finite number > 0")]
    BadLength {
        /// Edge index.
        index: usize,
        /// Edge id.
        id: String,
        /// The length.
        length_m: f64,
    },
    /// An edge refers to a node index that does not exist.
    #[error("edge {index} (`{id}`) refers to a node index that does not exist")]
    NodeOutOfRange {
        /// Edge index.
        index: usize,
        /// Edge id.
        id: String,
    },
    /// A node position is not a valid WGS84 coordinate.
    #[error("node {index} (`{id}`) has an invalid position")]
    BadPosition {
        /// Node index.
        index: usize,
        /// Node id.
        id: String,
    },
    /// More nodes or edges than fit a `u32` index.
    #[error("too many nodes or edges")]
    TooLarge,
    /// Positions in the plane that are not one finite position per flat node.
    #[error("{given} positions in the plane for {nodes} nodes (one finite position each)")]
    Plane {
        /// Positions given.
        given: usize,
        /// Flat nodes.
        nodes: usize,
    },
}

/// The airspace graph. Immutable once built.
#[derive(Clone, Debug)]
pub struct Airspace {
    nodes: Vec<Node>,
    edges: Vec<Edge>,
    kinds: Vec<EdgeKind>,
    by_id: HashMap<String, NodeId>,
    edge_by_id: HashMap<String, EdgeId>,
    offsets: Vec<u32>,
    adjacent: Vec<Adjacent>,
    in_offsets: Vec<u32>,
    incoming: Vec<Adjacent>,
    layout: Option<Box<Layout>>,
    /// Where the flat nodes are in the airspace's local metric plane, if set
    /// ([`Airspace::with_plane`]).
    plane: Option<Arc<[[f64; 2]]>>,
}

/// Compressed-sparse-row adjacency of `n` nodes from `(at, other, edge, forward)` entries:
/// each node's entries `(other, edge, forward)`, sorted by `other`.
fn csr(
    n: usize,
    entries: impl Iterator<Item = (NodeId, NodeId, EdgeId, bool)> + Clone,
) -> (Vec<u32>, Vec<Adjacent>) {
    let mut degree = vec![0u32; n];
    for (at, ..) in entries.clone() {
        degree[at.index()] += 1;
    }
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    for d in &degree {
        offsets.push(offsets.last().copied().unwrap_or(0) + d);
    }
    let mut fill: Vec<u32> = offsets[..n].to_vec();
    let blank = Adjacent {
        node: NodeId(0),
        edge: EdgeId(0),
        forward: true,
    };
    let mut list = vec![blank; offsets[n] as usize];
    for (at, node, edge, forward) in entries {
        list[fill[at.index()] as usize] = Adjacent {
            node,
            edge,
            forward,
        };
        fill[at.index()] += 1;
    }
    for v in 0..n {
        list[offsets[v] as usize..offsets[v + 1] as usize].sort_by_key(|a| a.node);
    }
    (offsets, list)
}

/// How a layered airspace was built from its flat one.
#[derive(Clone, Debug)]
struct Layout {
    layers: Layers,
    /// The flat airspace: node `n` at layer `k` is node `n + (k − 1)·N` here.
    base: Airspace,
    /// Per edge: the flat corridor it is a copy of, or the flat node of a vertical link.
    origin: Vec<u32>,
}

impl Airspace {
    /// A straight line of stations `A`, `B`, `C`, … joined in order by corridors `A-B`,
    /// `B-C`, … of the given lengths (metres), eastwards from 103.80° E, 1.30° N in steps of
    /// 0.01°: the smallest airspaces, for examples and tests.
    ///
    /// ```
    /// use muse_model::{Airspace, NodeId};
    /// let a = Airspace::line(&[1_000.0, 2_000.0]);
    /// assert_eq!((a.node_count(), a.node_id("C")), (3, Some(NodeId(2))));
    /// assert_eq!(a.edge(a.edge_between(NodeId(1), NodeId(2)).unwrap()).id, "B-C");
    /// ```
    ///
    /// # Panics
    /// With more than 25 lengths (the letters run out) or a length that is not positive.
    pub fn line(lengths_m: &[f64]) -> Airspace {
        assert!(lengths_m.len() < 26, "at most 25 corridors in a line");
        let name = |i: usize| char::from(b'A' + i as u8).to_string();
        let nodes = (0..=lengths_m.len())
            .map(|i| Node {
                id: name(i),
                kind: NodeKind::Station,
                name: String::new(),
                pos: LonLat::new(103.8 + 0.01 * i as f64, 1.3),
            })
            .collect();
        let edges = lengths_m
            .iter()
            .enumerate()
            .map(|(i, &length_m)| Edge {
                id: format!("{}-{}", name(i), name(i + 1)),
                from: NodeId(i as u32),
                to: NodeId(i as u32 + 1),
                length_m,
            })
            .collect();
        let mut x = 0.0;
        let plane = std::iter::once([0.0, 0.0])
            .chain(lengths_m.iter().map(|l| {
                x += l;
                [x, 0.0]
            }))
            .collect();
        Airspace::new(nodes, edges)
            .and_then(|a| a.with_plane(plane))
            .expect("a line of positive lengths is a valid airspace")
    }

    /// Validates and indexes nodes and edges.
    ///
    /// ```
    /// use muse_model::{Airspace, Edge, LonLat, Node, NodeId, NodeKind};
    /// let node = |id: &str, lon| Node {
    ///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3),
    /// };
    /// let a = Airspace::new(
    ///     vec![node("A", 103.80), node("B", 103.81)],
    ///     vec![Edge { id: "A-B".into(), from: NodeId(0), to: NodeId(1), length_m: 1_113.2 }],
    /// ).unwrap();
    /// assert_eq!(a.neighbours(NodeId(0))[0].node, NodeId(1));
    /// assert_eq!(a.node_id("B"), Some(NodeId(1)));
    /// ```
    pub fn new(nodes: Vec<Node>, edges: Vec<Edge>) -> Result<Self, AirspaceError> {
        if nodes.len() >= u32::MAX as usize || edges.len() >= u32::MAX as usize {
            return Err(AirspaceError::TooLarge);
        }
        let mut by_id = HashMap::with_capacity(nodes.len());
        for (i, n) in nodes.iter().enumerate() {
            if !n.pos.is_valid() {
                return Err(AirspaceError::BadPosition {
                    index: i,
                    id: n.id.clone(),
                });
            }
            if let Some(prev) = by_id.insert(n.id.clone(), NodeId(i as u32)) {
                return Err(AirspaceError::DuplicateNodeId {
                    id: n.id.clone(),
                    first: prev.index(),
                    second: i,
                });
            }
        }
        let mut edge_by_id = HashMap::with_capacity(edges.len());
        let mut pairs: HashMap<(NodeId, NodeId), usize> = HashMap::with_capacity(edges.len());
        for (i, e) in edges.iter().enumerate() {
            if e.from.index() >= nodes.len() || e.to.index() >= nodes.len() {
                return Err(AirspaceError::NodeOutOfRange {
                    index: i,
                    id: e.id.clone(),
                });
            }
            if e.from == e.to {
                return Err(AirspaceError::SelfLoop {
                    index: i,
                    id: e.id.clone(),
                    node: nodes[e.from.index()].id.clone(),
                });
            }
            if !e.length_m.is_finite() || e.length_m <= 0.0 {
                return Err(AirspaceError::BadLength {
                    index: i,
                    id: e.id.clone(),
                    length_m: e.length_m,
                });
            }
            if let Some(prev) = edge_by_id.insert(e.id.clone(), EdgeId(i as u32)) {
                return Err(AirspaceError::DuplicateEdgeId {
                    id: e.id.clone(),
                    first: prev.index(),
                    second: i,
                });
            }
            let key = (e.from.min(e.to), e.from.max(e.to));
            if let Some(prev) = pairs.insert(key, i) {
                return Err(AirspaceError::ParallelEdge {
                    a: nodes[key.0.index()].id.clone(),
                    b: nodes[key.1.index()].id.clone(),
                    first: prev,
                    second: i,
                });
            }
        }
        let kinds = vec![EdgeKind::FLAT; edges.len()];
        Ok(Self::index(nodes, edges, kinds, by_id, edge_by_id, None))
    }

    /// Builds the adjacency of validated nodes and edges: both directions of every edge but
    /// the one-way corridors'.
    fn index(
        nodes: Vec<Node>,
        edges: Vec<Edge>,
        kinds: Vec<EdgeKind>,
        by_id: HashMap<String, NodeId>,
        edge_by_id: HashMap<String, EdgeId>,
        layout: Option<Box<Layout>>,
    ) -> Self {
        let one_way = |i: usize| matches!(kinds[i], EdgeKind::Corridor { one_way: true, .. });
        // Every direction an edge may be flown in, as (from, to, edge, forward).
        let moves: Vec<(NodeId, NodeId, EdgeId, bool)> = edges
            .iter()
            .enumerate()
            .flat_map(|(i, e)| {
                let eid = EdgeId(i as u32);
                let both = [(e.from, e.to, eid, true), (e.to, e.from, eid, false)];
                both.into_iter().take(if one_way(i) { 1 } else { 2 })
            })
            .collect();
        let (offsets, adjacent) = csr(nodes.len(), moves.iter().map(|&(x, y, e, f)| (x, y, e, f)));
        let (in_offsets, incoming) =
            csr(nodes.len(), moves.iter().map(|&(x, y, e, f)| (y, x, e, f)));
        Airspace {
            nodes,
            edges,
            kinds,
            by_id,
            edge_by_id,
            offsets,
            adjacent,
            in_offsets,
            incoming,
            layout,
            plane: None,
        }
    }

    /// All nodes, indexed by [`NodeId`].
    #[inline]
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// All edges, indexed by [`EdgeId`].
    #[inline]
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Number of nodes.
    #[inline]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of edges.
    #[inline]
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// The node with index `n`.
    #[inline]
    pub fn node(&self, n: NodeId) -> &Node {
        &self.nodes[n.index()]
    }

    /// The edge with index `e`.
    #[inline]
    pub fn edge(&self, e: EdgeId) -> &Edge {
        &self.edges[e.index()]
    }

    /// The index of the node with file id `id`.
    pub fn node_id(&self, id: &str) -> Option<NodeId> {
        self.by_id.get(id).copied()
    }

    /// The index of the edge with file id `id`.
    pub fn edge_id(&self, id: &str) -> Option<EdgeId> {
        self.edge_by_id.get(id).copied()
    }

    /// The neighbours of `n`, sorted by node index.
    #[inline]
    pub fn neighbours(&self, n: NodeId) -> &[Adjacent] {
        &self.adjacent[self.offsets[n.index()] as usize..self.offsets[n.index() + 1] as usize]
    }

    /// The nodes from which `n` can be reached in one edge, sorted by node index: each with
    /// the edge and whether it is flown from its `from` end (`forward`). The same nodes as
    /// [`Airspace::neighbours`] unless some corridor is one-way.
    #[inline]
    pub fn predecessors(&self, n: NodeId) -> &[Adjacent] {
        &self.incoming[self.in_offsets[n.index()] as usize..self.in_offsets[n.index() + 1] as usize]
    }

    /// The edge that may be flown from `a` to `b`, if any (a one-way corridor only in its
    /// direction).
    pub fn edge_between(&self, a: NodeId, b: NodeId) -> Option<EdgeId> {
        let adj = self.neighbours(a);
        adj.binary_search_by_key(&b, |x| x.node)
            .ok()
            .map(|i| adj[i].edge)
    }

    /// Indices of all stations, in index order.
    pub fn stations(&self) -> impl Iterator<Item = NodeId> + '_ {
        self.nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| n.kind == NodeKind::Station)
            .map(|(i, _)| NodeId(i as u32))
    }

    /// Whether node `n` is a station.
    #[inline]
    pub fn is_station(&self, n: NodeId) -> bool {
        self.nodes[n.index()].kind == NodeKind::Station
    }

    /// Traversal time of every edge, indexed by [`EdgeId`]: a corridor's at cruise `speed`,
    /// a vertical link's its climb time.
    pub fn traversal_times(&self, speed: Speed) -> Vec<Millis> {
        self.edges
            .iter()
            .zip(&self.kinds)
            .map(|(e, k)| match *k {
                EdgeKind::Vertical { time, .. } => time,
                EdgeKind::Corridor { .. } => speed.traversal_time(e.length_m),
            })
            .collect()
    }

    /// What edge `e` is.
    #[inline]
    pub fn edge_kind(&self, e: EdgeId) -> EdgeKind {
        self.kinds[e.index()]
    }

    /// The layering, if the airspace has more than one layer.
    pub fn layers(&self) -> Option<&Layers> {
        self.layout.as_ref().map(|l| &l.layers)
    }

    /// The flat airspace this one was layered from (itself when flat).
    pub fn flat(&self) -> &Airspace {
        self.layout.as_ref().map_or(self, |l| &l.base)
    }

    /// The layer of node `n` (1-based; 1 in a flat airspace).
    #[inline]
    pub fn node_layer(&self, n: NodeId) -> u32 {
        self.layout.as_ref().map_or(1, |l| {
            u32::try_from(n.index() / l.base.node_count()).map_or(u32::MAX, |k| k + 1)
        })
    }

    /// The node of the flat airspace that `n` is a copy of (`n` itself when flat).
    #[inline]
    pub fn flat_node(&self, n: NodeId) -> NodeId {
        self.layout.as_ref().map_or(n, |l| {
            NodeId(u32::try_from(n.index() % l.base.node_count()).expect("a node index"))
        })
    }

    /// The copy at layer `layer` (1-based) of flat node `n`, if there is such a layer.
    pub fn at_layer(&self, n: NodeId, layer: u32) -> Option<NodeId> {
        match &self.layout {
            None => (layer == 1).then_some(n),
            Some(l) => (1..=l.layers.count).contains(&layer).then(|| {
                let flat = l.base.node_count();
                NodeId(u32::try_from(n.index() + (layer as usize - 1) * flat).expect("an index"))
            }),
        }
    }

    /// The flat corridor that edge `e` is a copy of (`e` itself when flat), or `None` for a
    /// vertical link.
    pub fn flat_edge(&self, e: EdgeId) -> Option<EdgeId> {
        match (&self.layout, self.kinds[e.index()]) {
            (_, EdgeKind::Vertical { .. }) => None,
            (None, _) => Some(e),
            (Some(l), _) => Some(EdgeId(l.origin[e.index()])),
        }
    }

    /// Whether every node can reach every other node.
    pub fn is_connected(&self) -> bool {
        if self.nodes.is_empty() {
            return true;
        }
        let mut seen = vec![false; self.nodes.len()];
        let mut stack = vec![NodeId(0)];
        seen[0] = true;
        let mut count = 1;
        while let Some(n) = stack.pop() {
            for a in self.neighbours(n) {
                if !seen[a.node.index()] {
                    seen[a.node.index()] = true;
                    count += 1;
                    stack.push(a.node);
                }
            }
        }
        count == self.nodes.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{named_edge, station};

    #[test]
    fn csr_adjacency_and_lookup() {
        let a = Airspace::new(
            vec![
                station("A", 103.8, 1.3),
                station("B", 103.81, 1.3),
                station("C", 103.82, 1.3),
            ],
            vec![named_edge("A-B", 0, 1, 10.0), named_edge("B-C", 1, 2, 20.0)],
        )
        .unwrap();
        assert_eq!(a.neighbours(NodeId(1)).len(), 2);
        assert_eq!(a.edge_between(NodeId(2), NodeId(1)), Some(EdgeId(1)));
        assert_eq!(a.edge_between(NodeId(0), NodeId(2)), None);
        assert!(a.is_connected());
        assert_eq!(a.edge_id("B-C"), Some(EdgeId(1)));
    }

    #[test]
    fn validation_errors() {
        let two = || vec![station("A", 103.8, 1.3), station("B", 103.81, 1.3)];
        let err = Airspace::new(vec![station("A", 1.0, 1.3), station("A", 2.0, 1.3)], vec![])
            .unwrap_err();
        assert!(matches!(
            err,
            AirspaceError::DuplicateNodeId { second: 1, .. }
        ));
        let err = Airspace::new(two(), vec![named_edge("x", 0, 0, 1.0)]).unwrap_err();
        assert!(err.to_string().contains("self-loop"));
        let err = Airspace::new(two(), vec![named_edge("x", 0, 1, 0.0)]).unwrap_err();
        assert!(matches!(err, AirspaceError::BadLength { .. }));
        let err = Airspace::new(
            two(),
            vec![named_edge("x", 0, 1, 1.0), named_edge("y", 1, 0, 1.0)],
        )
        .unwrap_err();
        assert!(matches!(err, AirspaceError::ParallelEdge { .. }));
        let err = Airspace::new(
            two(),
            vec![named_edge("x", 0, 1, 1.0), named_edge("x", 0, 1, 1.0)],
        )
        .unwrap_err();
        assert!(matches!(err, AirspaceError::DuplicateEdgeId { .. }));
        let err = Airspace::new(two(), vec![named_edge("x", 0, 5, 1.0)]).unwrap_err();
        assert!(matches!(err, AirspaceError::NodeOutOfRange { .. }));
        let disconnected = Airspace::new(two(), vec![]).unwrap();
        assert!(!disconnected.is_connected());
    }
}
