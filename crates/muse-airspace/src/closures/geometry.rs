//! Which elements a zone closes (docs/reference.md#no-fly-zones), time aside: [`closed_elements`].
//!
//! - Every node inside the zone's area, boundary included, and every edge whose straight
//!   segment intersects the area (touching counts).
//! - Polygons: the test is `geo`'s `Intersects` on longitude/latitude coordinates, the edge
//!   taken as a straight segment in longitude/latitude. At city scale the difference from the
//!   geodesic is far below a metre.
//! - Circles: a node is inside when its geodesic (WGS84) distance to the centre is at most the
//!   radius. An edge is closed when an end node is inside or when the point of its segment
//!   closest to the centre is within the radius, measured in a local metric plane around the
//!   centre ([`LocalFrame`]: longitude and latitude scaled by the WGS84 radii of curvature at
//!   the centre's latitude). Good at city scale (radii of a few tens of kilometres);
//!   longitudes are taken modulo 360° around the centre.
//! - Explicit ids (`Zone::node_ids`, `Zone::edge_ids`) close those elements; an edge may be
//!   named by its id or as `FROM-TO` with its end nodes' ids in either order. An id not in the
//!   airspace is an error naming the zone and the id.
//! - Layered airspace (docs/reference.md#layered-airspace): all of the above is decided once, on
//!   the flat airspace ([`Airspace::flat`]), whose ids a zone names (`S001`, not its copy
//!   `S001@2`); the zone's vertical band then chooses the layers: the copies of a closed node or
//!   corridor at the layers whose altitude the band contains, and the vertical links at a closed
//!   node whose span `[h_k, h_{k+1}]` meets the band. A zone without limits closes every layer. On
//!   a flat airspace (one layer) the band is not used: a zone closes what it covers at any height
//!   (docs/reference.md#layered-airspace: one layer is exactly #airspace to #multi-leg-trips).

use geo::{BoundingRect, Intersects};
use geo_types::{Line, MultiPolygon, Point};
use muse_model::{Airspace, EdgeId, LocalFrame, LonLat, NodeId, Zone, ZoneArea};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

use super::ClosureError;
use super::layers::copies_in_band;

/// The nodes and edges a zone closes (area rule and explicit ids), each sorted by index and
/// without repeats. Time is not considered. On a layered airspace, the copies at the layers
/// of the zone's vertical band and the vertical links whose span meets it (see the [module
/// docs](self)).
///
/// ```
/// use geo_types::polygon;
/// use muse_airspace::closures::closed_elements;
/// use muse_model::{
///     Airspace, Edge, Layers, LonLat, Metres, Node, NodeId, NodeKind, VerticalLimits, Zone,
///     ZoneArea,
/// };
/// let node = |id: &str, lon| Node {
///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.30),
/// };
/// let airspace = Airspace::new(
///     vec![node("A", 103.80), node("B", 103.84)],
///     vec![Edge { id: "A-B".into(), from: NodeId(0), to: NodeId(1), length_m: 4_452.0 }],
/// ).unwrap();
/// // A square between the two nodes: neither node is inside, the edge crosses it.
/// let square = polygon![(x: 103.81, y: 1.29), (x: 103.83, y: 1.29), (x: 103.83, y: 1.31),
///                       (x: 103.81, y: 1.31), (x: 103.81, y: 1.29)];
/// let zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: "PROHIBITED".into(),
///     area: Some(ZoneArea::Polygons(square.into())),
///     node_ids: vec![], edge_ids: vec![], periods: vec![], announced: None, withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
/// };
/// let (nodes, edges) = closed_elements(&airspace, &zone).unwrap();
/// assert!(nodes.is_empty());
/// assert_eq!(edges.len(), 1);
///
/// // At two layers, 60 m and 69.144 m, the zone up to 65 m closes A-B at layer 1 only.
/// let layered = airspace.layered(&Layers { count: 2, ..Layers::default() }).unwrap();
/// let low = Zone { vertical: VerticalLimits::agl(None, Some(Metres::from_mm(65_000))), ..zone };
/// let (_, edges) = closed_elements(&layered, &low).unwrap();
/// assert_eq!(edges.iter().map(|&e| layered.edge(e).id.as_str()).collect::<Vec<_>>(), ["A-B"]);
/// ```
pub fn closed_elements(
    airspace: &Airspace,
    zone: &Zone,
) -> Result<(Vec<NodeId>, Vec<EdgeId>), ClosureError> {
    closed_with(airspace, zone, None)
}

/// `[min_lon, min_lat, max_lon, max_lat]`.
type Envelope = [f64; 4];

/// A zone's area, checked and ready for point and segment tests.
enum Shape<'z> {
    Polygons(&'z MultiPolygon<f64>),
    Circle {
        centre: LonLat,
        radius_m: f64,
        plane: LocalFrame,
    },
}

impl<'z> Shape<'z> {
    fn of(zone: &'z Zone) -> Result<Option<Self>, ClosureError> {
        let bad = |reason: String| ClosureError::BadArea {
            zone: zone.id.clone(),
            reason,
        };
        match &zone.area {
            None => Ok(None),
            Some(ZoneArea::Polygons(mp)) => {
                for c in
                    mp.0.iter()
                        .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
                        .flat_map(|r| &r.0)
                {
                    if !LonLat::new(c.x, c.y).is_valid() {
                        return Err(bad(format!(
                            "({}, {}) is not a valid longitude/latitude",
                            c.x, c.y
                        )));
                    }
                }
                Ok(Some(Shape::Polygons(mp)))
            }
            Some(ZoneArea::Circle { centre, radius_m }) => {
                if !centre.is_valid() {
                    return Err(bad(format!(
                        "centre ({}, {}) is not a valid longitude/latitude",
                        centre.lon, centre.lat
                    )));
                }
                if !radius_m.is_finite() || *radius_m < 0.0 {
                    return Err(bad(format!(
                        "radius {radius_m} m is not a finite number >= 0"
                    )));
                }
                Ok(Some(Shape::Circle {
                    centre: *centre,
                    radius_m: *radius_m,
                    plane: LocalFrame::at(*centre),
                }))
            }
        }
    }

    /// A box in degrees that holds everything the shape can close, if one is easy to state.
    fn envelope(&self) -> Option<Envelope> {
        const MARGIN_DEG: f64 = 1e-9;
        match self {
            Shape::Polygons(mp) => mp.bounding_rect().map(|r| {
                [
                    r.min().x - MARGIN_DEG,
                    r.min().y - MARGIN_DEG,
                    r.max().x + MARGIN_DEG,
                    r.max().y + MARGIN_DEG,
                ]
            }),
            Shape::Circle {
                centre,
                radius_m,
                plane,
            } => {
                let k = plane.metres_per_degree();
                // Beyond city scale, or near the poles or the antimeridian: no envelope (scan).
                if *radius_m > 100_000.0 || k.lon < 1_000.0 {
                    return None;
                }
                let dlon = radius_m * 1.01 / k.lon + MARGIN_DEG;
                let dlat = radius_m * 1.01 / k.lat + MARGIN_DEG;
                let env = [
                    centre.lon - dlon,
                    centre.lat - dlat,
                    centre.lon + dlon,
                    centre.lat + dlat,
                ];
                (env[0] >= -180.0 && env[2] <= 180.0).then_some(env)
            }
        }
    }

    fn contains(&self, p: LonLat) -> bool {
        match self {
            Shape::Polygons(mp) => mp.intersects(&Point::new(p.lon, p.lat)),
            Shape::Circle {
                centre, radius_m, ..
            } => centre.geodesic_distance_m(p) <= *radius_m,
        }
    }

    fn crosses(&self, a: LonLat, b: LonLat) -> bool {
        match self {
            Shape::Polygons(mp) => mp.intersects(&Line::new((a.lon, a.lat), (b.lon, b.lat))),
            Shape::Circle {
                radius_m, plane, ..
            } => {
                self.contains(a)
                    || self.contains(b)
                    || distance_to_segment(plane, a, b) <= *radius_m
            }
        }
    }
}

/// Distance from the origin of `plane` to the segment `a`–`b`, metres, longitudes taken
/// modulo 360° around the origin.
fn distance_to_segment(plane: &LocalFrame, a: LonLat, b: LonLat) -> f64 {
    let (ax, ay) = plane.to_xy_wrapped(a);
    let (bx, by) = plane.to_xy_wrapped(b);
    let (dx, dy) = (bx - ax, by - ay);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (-(ax * dx + ay * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ax + t * dx).hypot(ay + t * dy)
}

/// R-trees over node positions and edge envelopes (longitude/latitude degrees).
pub(super) struct Index {
    nodes: RTree<GeomWithData<[f64; 2], u32>>,
    edges: RTree<GeomWithData<Rectangle<[f64; 2]>, u32>>,
}

impl Index {
    pub(super) fn new(airspace: &Airspace) -> Self {
        let pos = |n: NodeId| {
            let p = airspace.node(n).pos;
            [p.lon, p.lat]
        };
        let nodes = (0..airspace.node_count() as u32)
            .map(|i| GeomWithData::new(pos(NodeId(i)), i))
            .collect();
        let edges = airspace
            .edges()
            .iter()
            .enumerate()
            .map(|(i, e)| {
                GeomWithData::new(Rectangle::from_corners(pos(e.from), pos(e.to)), i as u32)
            })
            .collect();
        Index {
            nodes: RTree::bulk_load(nodes),
            edges: RTree::bulk_load(edges),
        }
    }

    fn nodes_in(&self, env: Envelope) -> Vec<NodeId> {
        let aabb = AABB::from_corners([env[0], env[1]], [env[2], env[3]]);
        self.nodes
            .locate_in_envelope(&aabb)
            .map(|g| NodeId(g.data))
            .collect()
    }

    fn edges_in(&self, env: Envelope) -> Vec<EdgeId> {
        let aabb = AABB::from_corners([env[0], env[1]], [env[2], env[3]]);
        self.edges
            .locate_in_envelope_intersecting(&aabb)
            .map(|g| EdgeId(g.data))
            .collect()
    }
}

/// [`closed_elements`], with candidates from `index` (built on [`Airspace::flat`]) when
/// given.
pub(super) fn closed_with(
    airspace: &Airspace,
    zone: &Zone,
    index: Option<&Index>,
) -> Result<(Vec<NodeId>, Vec<EdgeId>), ClosureError> {
    let (nodes, edges) = closed_flat(airspace.flat(), zone, index)?;
    Ok(match airspace.layers() {
        None => (nodes, edges),
        Some(layers) => copies_in_band(airspace, layers, &zone.vertical, &nodes, &edges),
    })
}

/// What a zone closes on a flat airspace, its heights aside.
fn closed_flat(
    airspace: &Airspace,
    zone: &Zone,
    index: Option<&Index>,
) -> Result<(Vec<NodeId>, Vec<EdgeId>), ClosureError> {
    let mut nodes = Vec::new();
    let mut edges = Vec::new();
    if let Some(shape) = Shape::of(zone)? {
        let envelope = shape.envelope();
        let (node_candidates, edge_candidates) = match (index, envelope) {
            (Some(ix), Some(env)) => (ix.nodes_in(env), ix.edges_in(env)),
            _ => (
                (0..airspace.node_count() as u32).map(NodeId).collect(),
                (0..airspace.edge_count() as u32).map(EdgeId).collect(),
            ),
        };
        nodes.extend(
            node_candidates
                .into_iter()
                .filter(|&n| shape.contains(airspace.node(n).pos)),
        );
        edges.extend(edge_candidates.into_iter().filter(|&e| {
            let edge = airspace.edge(e);
            shape.crosses(airspace.node(edge.from).pos, airspace.node(edge.to).pos)
        }));
    }
    for id in &zone.node_ids {
        let n = airspace
            .node_id(id)
            .ok_or_else(|| ClosureError::UnknownNode {
                zone: zone.id.clone(),
                id: id.clone(),
            })?;
        nodes.push(n);
    }
    for id in &zone.edge_ids {
        edges.push(edge_by_name(airspace, zone, id)?);
    }
    nodes.sort_unstable();
    nodes.dedup();
    edges.sort_unstable();
    edges.dedup();
    Ok((nodes, edges))
}

/// An edge by its id, or by `FROM-TO` (either order).
fn edge_by_name(airspace: &Airspace, zone: &Zone, id: &str) -> Result<EdgeId, ClosureError> {
    if let Some(e) = airspace.edge_id(id) {
        return Ok(e);
    }
    let mut found: Vec<EdgeId> = id
        .match_indices('-')
        .filter_map(|(i, _)| {
            let a = airspace.node_id(&id[..i])?;
            let b = airspace.node_id(&id[i + 1..])?;
            airspace.edge_between(a, b)
        })
        .collect();
    found.sort_unstable();
    found.dedup();
    match found.as_slice() {
        [e] => Ok(*e),
        [] => Err(ClosureError::UnknownEdge {
            zone: zone.id.clone(),
            id: id.to_owned(),
        }),
        _ => Err(ClosureError::AmbiguousEdge {
            zone: zone.id.clone(),
            id: id.to_owned(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use geo_types::{Coord, LineString, Polygon};

    use super::*;
    use crate::closures::fixtures::{airspace, names, square, square_airspace, t, zone};
    use crate::closures::resolve;

    #[test]
    fn polygon_closes_inside_boundary_and_crossing() {
        let a = square_airspace();
        let (n, e) = closed_elements(&a, &zone("Z", Some(square()), vec![])).unwrap();
        let (n, e) = names(&a, &n, &e);
        assert_eq!(
            n,
            ["EDGE", "CORNER", "IN"],
            "boundary and vertices are inside"
        );
        // OUT-EDGE ends on the boundary; S-N crosses with both ends outside. W1-W2 passes
        // 500 m west, E-N passes near the north-east corner without touching it.
        assert_eq!(e, ["OUT-EDGE", "S-N"]);
    }

    #[test]
    fn polygon_with_hole() {
        let outer = LineString::from(vec![
            (103.0, 1.0),
            (104.0, 1.0),
            (104.0, 2.0),
            (103.0, 2.0),
            (103.0, 1.0),
        ]);
        let hole = LineString::from(vec![
            (103.4, 1.4),
            (103.6, 1.4),
            (103.6, 1.6),
            (103.4, 1.6),
            (103.4, 1.4),
        ]);
        let area = ZoneArea::Polygons(Polygon::new(outer, vec![hole]).into());
        let a = airspace(
            &[("H", 103.5, 1.5), ("B", 103.4, 1.5), ("X", 103.2, 1.2)],
            &["H-B"],
        );
        let (n, e) = closed_elements(&a, &zone("Z", Some(area), vec![])).unwrap();
        let (n, e) = names(&a, &n, &e);
        assert_eq!(n, ["B", "X"], "the hole is open, its boundary closed");
        assert_eq!(e, ["H-B"]);
    }

    #[test]
    fn circle_nodes_geodesic_and_edges_by_closest_point() {
        let centre = LonLat::new(103.90, 1.30);
        let a = airspace(
            &[
                ("C", 103.90, 1.304), // ~442 m north
                ("F", 103.90, 1.306), // ~663 m north
                ("A1", 103.89, 1.304),
                ("A2", 103.91, 1.304),
                ("B1", 103.89, 1.306),
                ("B2", 103.91, 1.306),
            ],
            &["A1-A2", "B1-B2", "C-F"],
        );
        let radius_m = 500.0;
        assert!(centre.geodesic_distance_m(a.node(NodeId(0)).pos) < radius_m);
        assert!(centre.geodesic_distance_m(a.node(NodeId(1)).pos) > radius_m);
        let circle = zone("Z", Some(ZoneArea::Circle { centre, radius_m }), vec![]);
        let (nodes, edges) = closed_elements(&a, &circle).unwrap();
        let (nodes, edges) = names(&a, &nodes, &edges);
        assert_eq!(nodes, ["C"]);
        assert_eq!(
            edges,
            ["A1-A2", "C-F"],
            "A1-A2 passes ~442 m from the centre, B1-B2 ~663 m"
        );
        let bad = zone(
            "Z",
            Some(ZoneArea::Circle {
                centre,
                radius_m: -1.0,
            }),
            vec![],
        );
        assert!(matches!(
            closed_elements(&a, &bad),
            Err(ClosureError::BadArea { .. })
        ));
    }

    #[test]
    fn explicit_ids_and_errors() {
        let a = square_airspace();
        let mut z = zone("PAPER", None, vec![]);
        z.node_ids = vec!["E".into(), "OUT".into(), "E".into()];
        z.edge_ids = vec!["S-N".into(), "W1-OUT".into()];
        let (n, e) = closed_elements(&a, &z).unwrap();
        let (n, e) = names(&a, &n, &e);
        assert_eq!(n, ["OUT", "E"]);
        assert_eq!(e, ["S-N", "OUT-W1"], "FROM-TO works in either order");

        z.node_ids.push("S999".into());
        let err = closed_elements(&a, &z).unwrap_err();
        assert_eq!(
            err,
            ClosureError::UnknownNode {
                zone: "PAPER".into(),
                id: "S999".into()
            }
        );
        assert!(
            err.to_string().contains("zone `PAPER` closes node `S999`"),
            "{err}"
        );
        z.node_ids.pop();
        z.edge_ids.push("OUT-E".into());
        let err = closed_elements(&a, &z).unwrap_err();
        assert!(
            err.to_string().contains("zone `PAPER` closes edge `OUT-E`"),
            "{err}"
        );
        // The error is raised by `resolve` too, whatever the time.
        assert!(matches!(
            resolve(
                &a,
                &[z],
                t("2026-01-05T00:00:00Z"),
                t("2026-01-05T00:00:00Z")
            ),
            Err(ClosureError::UnknownEdge { .. })
        ));
    }

    /// The R-tree lookup used by `resolve` finds exactly what a full scan finds.
    #[test]
    fn index_agrees_with_scan() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut rand = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut nodes = Vec::new();
        for i in 0..200 {
            nodes.push((format!("N{i}"), 103.6 + 0.4 * rand(), 1.2 + 0.25 * rand()));
        }
        let mut edges = Vec::new();
        for i in 0..199 {
            edges.push(format!("N{i}-N{}", i + 1));
            if i % 3 == 0 && i + 7 < 200 {
                edges.push(format!("N{i}-N{}", i + 7));
            }
        }
        let node_refs: Vec<(&str, f64, f64)> = nodes
            .iter()
            .map(|(id, x, y)| (id.as_str(), *x, *y))
            .collect();
        let edge_refs: Vec<&str> = edges.iter().map(String::as_str).collect();
        let a = airspace(&node_refs, &edge_refs);
        let index = Index::new(&a);
        let mut closed_total = 0;
        for k in 0..60 {
            let (cx, cy) = (103.6 + 0.4 * rand(), 1.2 + 0.25 * rand());
            let area = if k % 2 == 0 {
                ZoneArea::Circle {
                    centre: LonLat::new(cx, cy),
                    radius_m: 200.0 + 5_000.0 * rand(),
                }
            } else {
                let (dx, dy) = (0.05 * rand(), 0.05 * rand());
                let ring: Vec<Coord<f64>> = [
                    (cx, cy),
                    (cx + dx, cy + 0.3 * dy),
                    (cx + 0.5 * dx, cy + dy),
                    (cx, cy),
                ]
                .into_iter()
                .map(|(x, y)| Coord { x, y })
                .collect();
                ZoneArea::Polygons(Polygon::new(LineString(ring), vec![]).into())
            };
            let z = zone("Z", Some(area), vec![]);
            let scan = closed_with(&a, &z, None).unwrap();
            closed_total += scan.0.len() + scan.1.len();
            assert_eq!(closed_with(&a, &z, Some(&index)).unwrap(), scan, "zone {k}");
        }
        assert!(
            closed_total > 100,
            "the zones close something: {closed_total}"
        );
    }
}
