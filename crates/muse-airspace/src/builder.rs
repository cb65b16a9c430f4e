//! Building an airspace from nodes: Delaunay triangulation, the paper's "join collinear
//! nodes", an optional maximum edge length, and a connectivity check
//! (docs/reference.md#built-in-scenarios).
//!
//! [`build_airspace`] takes the nodes (stations and waypoints) and returns a connected
//! [`Airspace`] whose edges are chosen as follows:
//!
//! 1. **Projection** to a local metric plane ([`Plane`], docs/reference.md#airspace-from-pads): by
//!    default the UTM zone of the nodes' centroid (the normalised mean of their unit vectors);
//!    `SVY21` (EPSG:3414) for Singapore's built-in scenarios; or an oblique stereographic
//!    projection about the centroid. All nodes must lie strictly within 90° of the centroid (one
//!    hemisphere), between 84° S and 84° N, within 60° of longitude and on one side of the ±180°
//!    meridian ([`check_extent`](crate::plane::check_extent)).
//! 2. **Delaunay triangulation** of the projected points with [`spade`] (exact predicates).
//!    Two nodes at the same position are an error.
//! 3. **Join collinear nodes** (the paper's step): an edge A–C is dropped when some node B
//!    with edges A–B and B–C lies almost on the segment A–C, i.e. the angle ABC measured in
//!    the projection is at least `180° − collinear_tolerance_deg`. Edges are considered
//!    **longest first** (geodesic length in millimetres, ties by the pair of node indices),
//!    and A–C is dropped only if A–B and B–C are *still present* at that moment. A–B and B–C
//!    are both shorter than A–C (the angle at B is obtuse), so every dropped edge is replaced
//!    by a two-edge detour that is itself either kept or replaced later: dropping never
//!    disconnects the graph.
//! 4. **Maximum edge length** (optional): edges with a geodesic length above
//!    `max_edge_length_m` are dropped, e.g. to avoid long corridors across the sea along a
//!    concave coastline. **Exclusions** (optional): edges whose straight segment (in
//!    longitude and latitude) meets an exclusion polygon, its boundary included, are
//!    dropped; a node inside one, or on its boundary, is an error. Both *can* disconnect the
//!    graph.
//! 5. **Connectivity.** The result must be connected; otherwise [`BuildError::Disconnected`].
//!
//! Edge lengths are geodesic on WGS84 ([`muse_model::LonLat::geodesic_distance_m`]) rounded to the
//! millimetre. Each edge joins a lower-index node `from` to a higher-index node `to`, has id
//! `"{from id}-{to id}"`, and edges are sorted by `(from, to)` index. Nodes keep the input
//! order. The whole procedure is deterministic: the same nodes in the same order give the
//! same airspace, byte for byte once written.

use std::collections::BTreeSet;

use geo::Intersects as _;
use geo_types::{Coord, Line, Point, Polygon};
use muse_model::{Airspace, AirspaceError, Edge, Node, NodeId};
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

use crate::plane::{Plane, PlaneError};

/// Options of [`build_airspace`].
#[derive(Clone, Debug, PartialEq)]
pub struct BuildOptions {
    /// The "join collinear nodes" tolerance, degrees: edge A–C is dropped when a node B with
    /// edges A–B and B–C makes an angle ABC of at least `180° − tolerance`. `0` drops only
    /// exactly collinear detours (which Delaunay never produces, so nothing); the default is
    /// [`BuildOptions::DEFAULT_COLLINEAR_TOLERANCE_DEG`].
    pub collinear_tolerance_deg: f64,
    /// Drop edges longer than this many metres (geodesic). `None` (the default) keeps all.
    pub max_edge_length_m: Option<f64>,
    /// The plane the triangulation and the angles are worked out in (default: UTM).
    pub plane: Plane,
    /// Polygons (WGS84 degrees) no corridor may meet; none by default.
    pub exclusions: Vec<Polygon<f64>>,
}

impl BuildOptions {
    /// The default collinear tolerance, 15°: A–C is replaced by A–B–C when the path turns
    /// by at most 15° at B (angle ABC ≥ 165°). The detour A–B–C is then at most
    /// `1 / cos(7.5°) − 1 ≈ 0.9 %` longer than A–C (the worst case is B half way). This
    /// removes the long, thin "sliver" triangles that Delaunay produces along the convex
    /// hull, whose long side is a corridor nearly parallel to two shorter ones; on the
    /// Singapore stations it removes the 14.5 km hull edge along the south-west coast, so
    /// that every remaining edge is shorter than the 10 km a drone flies in 20 minutes.
    pub const DEFAULT_COLLINEAR_TOLERANCE_DEG: f64 = 15.0;
}

impl Default for BuildOptions {
    /// `collinear_tolerance_deg` = [`BuildOptions::DEFAULT_COLLINEAR_TOLERANCE_DEG`] (15°),
    /// no maximum edge length.
    fn default() -> Self {
        BuildOptions {
            collinear_tolerance_deg: Self::DEFAULT_COLLINEAR_TOLERANCE_DEG,
            max_edge_length_m: None,
            plane: Plane::Utm,
            exclusions: Vec::new(),
        }
    }
}

/// Why [`build_airspace`] failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// No nodes were given.
    #[error("cannot build an airspace without nodes")]
    NoNodes,
    /// An option is out of range.
    #[error("invalid build option: {0}")]
    BadOption(String),
    /// A node's position is not a valid WGS84 coordinate.
    #[error("node {index} (`{id}`) has an invalid position ({lon}, {lat})")]
    BadPosition {
        /// Index of the node in the input.
        index: usize,
        /// Its id.
        id: String,
        /// Its longitude.
        lon: f64,
        /// Its latitude.
        lat: f64,
    },
    /// Two nodes are at the same position (or less than half a millimetre apart).
    #[error("nodes `{first}` and `{second}` are at the same position")]
    DuplicatePosition {
        /// Id of the earlier node.
        first: String,
        /// Id of the later node.
        second: String,
    },
    /// A node lies inside an exclusion polygon (or on its boundary).
    #[error("node `{id}` lies in exclusion polygon {polygon} (counted from 0)")]
    Excluded {
        /// The node's id.
        id: String,
        /// The polygon's index in [`BuildOptions::exclusions`].
        polygon: usize,
    },
    /// The nodes cannot be projected to the plane (beyond a hemisphere, or refused).
    #[error(transparent)]
    Plane(#[from] PlaneError),
    /// The triangulation library refused a point.
    #[error("triangulation failed: {0}")]
    Triangulation(String),
    /// The resulting graph is not connected.
    #[error(
        "the airspace is not connected: {components} components; `{unreached}` cannot be \
         reached from `{first}`{hint}"
    )]
    Disconnected {
        /// Number of connected components.
        components: usize,
        /// Id of the first node.
        first: String,
        /// Id of the first node (in input order) not reachable from it.
        unreached: String,
        /// A hint about the cause (empty or starting with `; `).
        hint: String,
    },
    /// The nodes and edges do not form a valid airspace (e.g. duplicate node ids).
    #[error(transparent)]
    Airspace(#[from] AirspaceError),
}

/// A vertex handed to `spade`: projected position and index of the node.
struct Vertex {
    pos: Point2<f64>,
    index: usize,
}

impl HasPosition for Vertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

/// Builds a connected airspace from `nodes`: Delaunay triangulation, join collinear nodes,
/// optional maximum edge length (see the [module documentation](self) for the exact rules).
///
/// ```
/// use muse_airspace::builder::{build_airspace, BuildOptions};
/// use muse_model::{LonLat, Node, NodeKind};
///
/// let node = |id: &str, lon, lat| Node {
///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, lat),
/// };
/// // A triangle and a fourth node almost on its long side A–C.
/// let nodes = vec![
///     node("A", 103.80, 1.30),
///     node("B", 103.81, 1.3001),
///     node("C", 103.82, 1.30),
///     node("D", 103.81, 1.31),
/// ];
/// let airspace = build_airspace(nodes, &BuildOptions::default()).unwrap();
/// let ids: Vec<&str> = airspace.edges().iter().map(|e| e.id.as_str()).collect();
/// // A–C was joined through B.
/// assert_eq!(ids, ["A-B", "A-D", "B-C", "B-D", "C-D"]);
/// assert!(airspace.is_connected());
/// ```
pub fn build_airspace(nodes: Vec<Node>, opts: &BuildOptions) -> Result<Airspace, BuildError> {
    check_options(opts)?;
    if nodes.is_empty() {
        return Err(BuildError::NoNodes);
    }
    for (index, n) in nodes.iter().enumerate() {
        if !n.pos.is_valid() {
            return Err(BuildError::BadPosition {
                index,
                id: n.id.clone(),
                lon: n.pos.lon,
                lat: n.pos.lat,
            });
        }
    }
    check_duplicate_positions(&nodes)?;
    for n in &nodes {
        let p = Point::new(n.pos.lon, n.pos.lat);
        if let Some(polygon) = opts.exclusions.iter().position(|z| z.intersects(&p)) {
            return Err(BuildError::Excluded {
                id: n.id.clone(),
                polygon,
            });
        }
    }
    crate::plane::check_extent(&nodes)?;
    let projected = opts.plane.project(&nodes)?;

    // 2. Delaunay triangulation.
    let mut candidates: Vec<(usize, usize)> = delaunay_edges(&projected)?;

    // Geodesic lengths, millimetre-rounded.
    let mut lengths: Vec<f64> = Vec::with_capacity(candidates.len());
    for &(a, b) in &candidates {
        let len = round_mm(nodes[a].pos.geodesic_distance_m(nodes[b].pos));
        if len <= 0.0 {
            return Err(BuildError::DuplicatePosition {
                first: nodes[a].id.clone(),
                second: nodes[b].id.clone(),
            });
        }
        lengths.push(len);
    }

    // 3. Join collinear nodes.
    let keep = join_collinear(
        nodes.len(),
        &candidates,
        &lengths,
        &projected,
        opts.collinear_tolerance_deg,
    );

    // 4. Maximum edge length.
    let mut kept: Vec<(usize, usize, f64)> = candidates
        .drain(..)
        .zip(lengths)
        .zip(keep)
        .filter(|&((_, len), k)| k && opts.max_edge_length_m.is_none_or(|max| len <= max))
        .filter(|&(((a, b), _), _)| !crosses_exclusion(&nodes[a], &nodes[b], &opts.exclusions))
        .map(|(((a, b), len), _)| (a, b, len))
        .collect();
    kept.sort_by_key(|&(a, b, _)| (a, b));

    // 5. Connectivity.
    check_connected(&nodes, &kept, opts)?;

    let edges = kept
        .iter()
        .map(|&(a, b, length_m)| Edge {
            id: format!("{}-{}", nodes[a].id, nodes[b].id),
            from: NodeId(a as u32),
            to: NodeId(b as u32),
            length_m,
        })
        .collect();
    Ok(Airspace::new(nodes, edges)?)
}

fn check_options(opts: &BuildOptions) -> Result<(), BuildError> {
    let tol = opts.collinear_tolerance_deg;
    if !tol.is_finite() || !(0.0..90.0).contains(&tol) {
        return Err(BuildError::BadOption(format!(
            "collinear tolerance {tol}° must be at least 0° and less than 90°"
        )));
    }
    if let Some(max) = opts
        .max_edge_length_m
        .filter(|m| !m.is_finite() || *m <= 0.0)
    {
        return Err(BuildError::BadOption(format!(
            "maximum edge length {max} m must be a finite number > 0"
        )));
    }
    Ok(())
}

/// Whether the straight segment from `a` to `b` (in longitude and latitude) meets one of
/// `exclusions`, boundary included.
fn crosses_exclusion(a: &Node, b: &Node, exclusions: &[Polygon<f64>]) -> bool {
    let line = Line::new(
        Coord {
            x: a.pos.lon,
            y: a.pos.lat,
        },
        Coord {
            x: b.pos.lon,
            y: b.pos.lat,
        },
    );
    exclusions.iter().any(|z| z.intersects(&line))
}

/// Rounds metres to the millimetre.
fn round_mm(m: f64) -> f64 {
    (m * 1_000.0).round() / 1_000.0
}

fn check_duplicate_positions(nodes: &[Node]) -> Result<(), BuildError> {
    let mut order: Vec<usize> = (0..nodes.len()).collect();
    let key = |i: usize| (nodes[i].pos.lon, nodes[i].pos.lat);
    order.sort_by(|&i, &j| {
        key(i)
            .partial_cmp(&key(j))
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(i.cmp(&j))
    });
    for w in order.windows(2) {
        if key(w[0]) == key(w[1]) {
            let (first, second) = (w[0].min(w[1]), w[0].max(w[1]));
            return Err(BuildError::DuplicatePosition {
                first: nodes[first].id.clone(),
                second: nodes[second].id.clone(),
            });
        }
    }
    Ok(())
}

/// The undirected Delaunay edges as `(lower index, higher index)`, sorted.
fn delaunay_edges(points: &[Point2<f64>]) -> Result<Vec<(usize, usize)>, BuildError> {
    let vertices: Vec<Vertex> = points
        .iter()
        .enumerate()
        .map(|(index, &pos)| Vertex { pos, index })
        .collect();
    let count = vertices.len();
    let dt = DelaunayTriangulation::<Vertex>::bulk_load_stable(vertices)
        .map_err(|e| BuildError::Triangulation(format!("{e:?}")))?;
    if dt.num_vertices() != count {
        // Distinct WGS84 positions that project to the same point (sub-nanometre apart).
        return Err(BuildError::Triangulation(
            "two nodes project to the same point; they are too close together".into(),
        ));
    }
    let mut edges: Vec<(usize, usize)> = dt
        .undirected_edges()
        .map(|e| {
            let [a, b] = e.vertices();
            let (a, b) = (a.data().index, b.data().index);
            (a.min(b), a.max(b))
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    Ok(edges)
}

/// The "join collinear nodes" step; returns which of `edges` to keep.
fn join_collinear(
    node_count: usize,
    edges: &[(usize, usize)],
    lengths: &[f64],
    pos: &[Point2<f64>],
    tolerance_deg: f64,
) -> Vec<bool> {
    let mut keep = vec![true; edges.len()];
    if tolerance_deg <= 0.0 {
        return keep;
    }
    // cos(angle ABC) <= cos(180° − tol) = −cos(tol).
    let threshold = -tolerance_deg.to_radians().cos();
    let mut adjacency: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); node_count];
    for &(a, b) in edges {
        adjacency[a].insert(b);
        adjacency[b].insert(a);
    }
    let mut order: Vec<usize> = (0..edges.len()).collect();
    order.sort_by(|&i, &j| {
        lengths[j]
            .total_cmp(&lengths[i])
            .then(edges[i].cmp(&edges[j]))
    });
    for i in order {
        let (a, c) = edges[i];
        let joined = adjacency[a].intersection(&adjacency[c]).any(|&b| {
            let (ba, bc) = (sub(pos[a], pos[b]), sub(pos[c], pos[b]));
            let denom = (dot(ba, ba) * dot(bc, bc)).sqrt();
            denom > 0.0 && dot(ba, bc) / denom <= threshold
        });
        if joined {
            keep[i] = false;
            adjacency[a].remove(&c);
            adjacency[c].remove(&a);
        }
    }
    keep
}

/// The root of `x` in a union–find forest, with path halving.
fn root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

fn sub(p: Point2<f64>, q: Point2<f64>) -> [f64; 2] {
    [p.x - q.x, p.y - q.y]
}

fn dot(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[0] + u[1] * v[1]
}

fn check_connected(
    nodes: &[Node],
    edges: &[(usize, usize, f64)],
    opts: &BuildOptions,
) -> Result<(), BuildError> {
    // Union–find over node indices.
    let mut parent: Vec<usize> = (0..nodes.len()).collect();
    for &(a, b, _) in edges {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    let roots: Vec<usize> = (0..nodes.len()).map(|i| root(&mut parent, i)).collect();
    let components = roots.iter().enumerate().filter(|&(i, &r)| i == r).count();
    if components <= 1 {
        return Ok(());
    }
    let unreached = roots.iter().position(|&r| r != roots[0]).unwrap_or(0);
    let mut hint = match opts.max_edge_length_m {
        Some(max) => format!("; the maximum edge length ({max} m) may be too small"),
        None => String::new(),
    };
    if !opts.exclusions.is_empty() {
        hint.push_str("; corridors meeting an exclusion are dropped");
    }
    Err(BuildError::Disconnected {
        components,
        first: nodes[0].id.clone(),
        unreached: nodes[unreached].id.clone(),
        hint,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::testing::station;

    fn edge_ids(a: &Airspace) -> Vec<String> {
        a.edges().iter().map(|e| e.id.clone()).collect()
    }

    #[test]
    fn square_with_centre() {
        let d = 0.01;
        let nodes = vec![
            station("SW", 103.8, 1.3),
            station("SE", 103.8 + d, 1.3),
            station("NE", 103.8 + d, 1.3 + d),
            station("NW", 103.8, 1.3 + d),
            station("C", 103.8 + d / 2.0, 1.3 + d / 2.0),
        ];
        let a = build_airspace(nodes, &BuildOptions::default()).unwrap();
        // Four sides and four spokes; no diagonal (the centre blocks both).
        assert_eq!(
            edge_ids(&a),
            [
                "SW-SE", "SW-NW", "SW-C", "SE-NE", "SE-C", "NE-NW", "NE-C", "NW-C"
            ]
        );
        assert!(a.is_connected());
        for e in a.edges() {
            let geo = a.node(e.from).pos.geodesic_distance_m(a.node(e.to).pos);
            assert!(
                (e.length_m - geo).abs() <= 0.000_5,
                "{}: {} vs {geo}",
                e.id,
                e.length_m
            );
            assert_eq!(e.length_m.to_bits(), round_mm(e.length_m).to_bits());
            assert!(e.from < e.to);
        }
    }

    #[test]
    fn collinear_nodes_are_joined() {
        // B is 11 m off the 2.2 km segment A–C: angle ABC ≈ 178.9°.
        let nodes = || {
            vec![
                station("A", 103.80, 1.30),
                station("B", 103.81, 1.3001),
                station("C", 103.82, 1.30),
                station("D", 103.81, 1.31),
            ]
        };
        let joined = build_airspace(nodes(), &BuildOptions::default()).unwrap();
        assert_eq!(edge_ids(&joined), ["A-B", "A-D", "B-C", "B-D", "C-D"]);
        let none = BuildOptions {
            collinear_tolerance_deg: 0.0,
            ..BuildOptions::default()
        };
        let kept = build_airspace(nodes(), &none).unwrap();
        assert_eq!(edge_ids(&kept), ["A-B", "A-C", "A-D", "B-C", "B-D", "C-D"]);
        // 0.5° is too strict for a 1.1° turn.
        let strict = BuildOptions {
            collinear_tolerance_deg: 0.5,
            ..BuildOptions::default()
        };
        assert_eq!(build_airspace(nodes(), &strict).unwrap().edge_count(), 6);
    }

    #[test]
    fn chain_of_nearly_collinear_nodes_stays_connected() {
        // Five nodes on a gentle arc: only consecutive nodes remain joined.
        let nodes: Vec<Node> = (0..5)
            .map(|i| {
                let x = f64::from(i);
                station(
                    &format!("N{i}"),
                    103.8 + 0.01 * x,
                    1.3 + 0.0001 * x * (4.0 - x),
                )
            })
            .collect();
        let a = build_airspace(nodes, &BuildOptions::default()).unwrap();
        assert_eq!(edge_ids(&a), ["N0-N1", "N1-N2", "N2-N3", "N3-N4"]);
        assert!(a.is_connected());
    }

    #[test]
    fn too_small_max_length_disconnects() {
        let nodes = vec![
            station("A", 103.80, 1.30),
            station("B", 103.801, 1.30),
            station("C", 103.90, 1.30),
            station("D", 103.901, 1.301),
        ];
        let opts = BuildOptions {
            max_edge_length_m: Some(1_000.0),
            ..BuildOptions::default()
        };
        let err = build_airspace(nodes.clone(), &opts).unwrap_err();
        assert!(
            matches!(&err, BuildError::Disconnected { components: 2, unreached, .. } if unreached == "C"),
            "{err}"
        );
        assert!(err.to_string().contains("maximum edge length"), "{err}");
        let opts = BuildOptions {
            max_edge_length_m: Some(20_000.0),
            ..BuildOptions::default()
        };
        assert!(build_airspace(nodes, &opts).unwrap().is_connected());
    }

    #[test]
    fn deterministic_and_independent_of_node_order() {
        // A pseudo-random cloud (fixed linear congruential sequence).
        let mut state: u64 = 12_345;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let nodes: Vec<Node> = (0..60)
            .map(|i| {
                station(
                    &format!("P{i:02}"),
                    103.6 + 0.4 * next(),
                    1.25 + 0.2 * next(),
                )
            })
            .collect();
        let first = build_airspace(nodes.clone(), &BuildOptions::default()).unwrap();
        let second = build_airspace(nodes.clone(), &BuildOptions::default()).unwrap();
        assert_eq!(first.edges(), second.edges());
        assert!(first.is_connected());
        let mut reversed = nodes;
        reversed.reverse();
        let rev = build_airspace(reversed, &BuildOptions::default()).unwrap();
        let pairs = |air: &Airspace| {
            let mut list: Vec<(String, String, u64)> = air
                .edges()
                .iter()
                .map(|e| {
                    let (lo, hi) = (air.node(e.from).id.clone(), air.node(e.to).id.clone());
                    let len = (e.length_m * 1_000.0).round() as u64;
                    if lo < hi {
                        (lo, hi, len)
                    } else {
                        (hi, lo, len)
                    }
                })
                .collect();
            list.sort();
            list
        };
        assert_eq!(pairs(&first), pairs(&rev));
    }

    #[test]
    fn input_errors() {
        let dup = vec![
            station("A", 103.8, 1.3),
            station("B", 103.9, 1.3),
            station("C", 103.8, 1.3),
        ];
        assert_eq!(
            build_airspace(dup, &BuildOptions::default()).unwrap_err(),
            BuildError::DuplicatePosition {
                first: "A".into(),
                second: "C".into()
            }
        );
        assert_eq!(
            build_airspace(vec![], &BuildOptions::default()).unwrap_err(),
            BuildError::NoNodes
        );
        let bad = vec![station("A", f64::NAN, 1.3)];
        assert!(matches!(
            build_airspace(bad, &BuildOptions::default()),
            Err(BuildError::BadPosition { index: 0, .. })
        ));
        let same_id = vec![station("A", 103.8, 1.3), station("A", 103.9, 1.3)];
        assert!(matches!(
            build_airspace(same_id, &BuildOptions::default()),
            Err(BuildError::Airspace(AirspaceError::DuplicateNodeId { .. }))
        ));
        let opts = BuildOptions {
            collinear_tolerance_deg: -1.0,
            ..BuildOptions::default()
        };
        assert!(matches!(
            build_airspace(vec![station("A", 103.8, 1.3)], &opts),
            Err(BuildError::BadOption(_))
        ));
        // Round the equator: wider than 60° of longitude (and beyond a hemisphere).
        let round = vec![
            station("A", 0.0, 0.0),
            station("B", 120.0, 0.0),
            station("C", -120.0, 0.0),
        ];
        assert!(matches!(
            build_airspace(round, &BuildOptions::default()),
            Err(BuildError::Plane(crate::plane::PlaneError::TooWide { .. }))
        ));
        // Within 60° of longitude, but from the Arctic to the Antarctic.
        let spread = vec![
            station("A", 0.0, 80.0),
            station("B", 1.0, 80.0),
            station("C", 0.0, 81.0),
            station("D", 50.0, -80.0),
        ];
        assert!(matches!(
            build_airspace(spread, &BuildOptions::default()),
            Err(BuildError::Plane(crate::plane::PlaneError::TooSpread(_)))
        ));
    }

    #[test]
    fn exclusions_drop_the_corridors_they_meet_and_refuse_pads_inside() {
        // The square with its centre; a small box across the SW–C spoke only.
        let d = 0.01;
        let nodes = || {
            vec![
                station("SW", 103.8, 1.3),
                station("SE", 103.8 + d, 1.3),
                station("NE", 103.8 + d, 1.3 + d),
                station("NW", 103.8, 1.3 + d),
                station("C", 103.8 + d / 2.0, 1.3 + d / 2.0),
            ]
        };
        let square = |x0: f64, y0: f64, w: f64| {
            Polygon::new(
                geo_types::LineString::from(vec![
                    (x0, y0),
                    (x0 + w, y0),
                    (x0 + w, y0 + w),
                    (x0, y0 + w),
                    (x0, y0),
                ]),
                vec![],
            )
        };
        let opts = BuildOptions {
            exclusions: vec![square(103.802, 1.302, 0.0005)],
            ..BuildOptions::default()
        };
        let a = build_airspace(nodes(), &opts).unwrap();
        assert_eq!(
            edge_ids(&a),
            ["SW-SE", "SW-NW", "SE-NE", "SE-C", "NE-NW", "NE-C", "NW-C"]
        );
        let inside = BuildOptions {
            exclusions: vec![square(103.0, 1.0, 0.1), square(103.804, 1.304, 0.002)],
            ..BuildOptions::default()
        };
        assert_eq!(
            build_airspace(nodes(), &inside).unwrap_err().to_string(),
            "node `C` lies in exclusion polygon 1 (counted from 0)"
        );
        // A wall across the square cuts it in two.
        let wall = BuildOptions {
            exclusions: vec![Polygon::new(
                geo_types::LineString::from(vec![
                    (103.79, 1.3029),
                    (103.82, 1.3029),
                    (103.82, 1.3031),
                    (103.79, 1.3031),
                    (103.79, 1.3029),
                ]),
                vec![],
            )],
            ..BuildOptions::default()
        };
        let e = build_airspace(nodes(), &wall).unwrap_err().to_string();
        assert!(
            e.contains("not connected") && e.contains("exclusion"),
            "{e}"
        );
    }

    #[test]
    fn single_node_and_pair() {
        let one = build_airspace(vec![station("A", 103.8, 1.3)], &BuildOptions::default()).unwrap();
        assert_eq!(one.edge_count(), 0);
        let two = build_airspace(
            vec![station("B", 103.81, 1.3), station("A", 103.8, 1.3)],
            &BuildOptions::default(),
        )
        .unwrap();
        assert_eq!(edge_ids(&two), ["B-A"]);
        assert!((two.edges()[0].length_m - 1_113.2).abs() < 1.0);
    }
}
