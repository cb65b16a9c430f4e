//! The layered airspace (docs/reference.md#layered-airspace), built once from the flat one: the
//! graph the planner searches, with nothing special in the search.

use super::{Airspace, AirspaceError, Edge, EdgeKind, Layout, Node, NodeKind};
use crate::ids::NodeId;
use crate::layers::{Layers, bearing};

impl Airspace {
    /// This (flat) airspace flown at `layers.count` cruise altitudes
    /// (docs/reference.md#layered-airspace).
    ///
    /// Node `n` at layer `k` is node `n + (k − 1)·N` (`N` the flat node count), so layer 1
    /// keeps the flat indices and ids; the copies above are named `ID@k` and are waypoints
    /// (take-off and landing are at layer 1 of a station). Corridor `e` at layer `k` is named
    /// `ID@k` (`ID` at layer 1); under the `sectors` heading rule it may be flown only in the
    /// directions whose initial bearing lies in layer `k`'s sector: one-way (its ends swapped
    /// when only the reverse is allowed), or absent when neither is. The vertical link at node
    /// `n` between layers `k` and `k + 1`, named `ID@k^k+1`, is crossed in
    /// [`Layers::climb_time`]. With one layer the airspace is returned unchanged.
    ///
    /// ```
    /// use muse_model::{Airspace, EdgeKind, HeadingRule, Layers, Millis, NodeId};
    /// let flat = Airspace::line(&[1_000.0]); // A — B, eastward
    /// let layers = Layers { count: 2, heading_rule: HeadingRule::Sectors, ..Layers::default() };
    /// let air = flat.layered(&layers).unwrap();
    /// assert_eq!((air.node_count(), air.node_layer(NodeId(3)), air.node(NodeId(3)).id.as_str()),
    ///            (4, 2, "B@2"));
    /// // Eastward (bearing 90°) at layer 1 only, westward at layer 2 only; two vertical links.
    /// assert!(air.edge_between(NodeId(0), NodeId(1)).is_some());
    /// assert!(air.edge_between(NodeId(1), NodeId(0)).is_none());
    /// assert!(air.edge_between(NodeId(3), NodeId(2)).is_some());
    /// let up = air.edge_between(NodeId(0), NodeId(2)).unwrap();
    /// assert_eq!(air.edge_kind(up), EdgeKind::Vertical { layer: 1, time: Millis(1_829) });
    /// assert_eq!(air.stations().count(), 2);
    /// ```
    ///
    /// # Errors
    /// When a copy's id (`ID@k`) is already the id of another node or edge.
    pub fn layered(&self, layers: &Layers) -> Result<Airspace, AirspaceError> {
        let flat = self.flat();
        if layers.count <= 1 {
            return Ok(flat.clone());
        }
        let n = flat.node_count();
        let at = |node: NodeId, k: u32| {
            NodeId(u32::try_from(node.index() + (k as usize - 1) * n).expect("checked size"))
        };
        let mut nodes = Vec::with_capacity(n * layers.count as usize);
        for k in 1..=layers.count {
            nodes.extend(flat.nodes().iter().map(|node| Node {
                id: copy_id(&node.id, k),
                kind: if k == 1 {
                    node.kind
                } else {
                    NodeKind::Waypoint
                },
                name: node.name.clone(),
                pos: node.pos,
            }));
        }
        // Each corridor's initial bearing in both directions, once.
        let bearings: Vec<(f64, f64)> = flat
            .edges()
            .iter()
            .map(|e| {
                let (a, b) = (flat.node(e.from).pos, flat.node(e.to).pos);
                (bearing(a, b), bearing(b, a))
            })
            .collect();
        let (mut edges, mut kinds, mut origin) = (Vec::new(), Vec::new(), Vec::new());
        for k in 1..=layers.count {
            for (i, (e, &(ahead, back))) in flat.edges().iter().zip(&bearings).enumerate() {
                let forward = layers.allows(k, ahead);
                let backward = layers.allows(k, back);
                let (from, to) = match (forward, backward) {
                    (false, false) => continue,
                    (true, _) => (e.from, e.to),
                    (false, true) => (e.to, e.from),
                };
                edges.push(Edge {
                    id: copy_id(&e.id, k),
                    from: at(from, k),
                    to: at(to, k),
                    length_m: e.length_m,
                });
                kinds.push(EdgeKind::Corridor {
                    layer: k,
                    one_way: forward != backward,
                });
                origin.push(u32::try_from(i).expect("an edge index"));
            }
        }
        let spacing_m = layers.spacing.m();
        for k in 1..layers.count {
            for (i, node) in flat.nodes().iter().enumerate() {
                let v = NodeId(u32::try_from(i).expect("a node index"));
                edges.push(Edge {
                    id: format!("{}@{k}^{}", node.id, k + 1),
                    from: at(v, k),
                    to: at(v, k + 1),
                    length_m: spacing_m,
                });
                kinds.push(EdgeKind::Vertical {
                    layer: k,
                    time: layers.climb_time(),
                });
                origin.push(v.0);
            }
        }
        let checked = Airspace::new(nodes, edges)?;
        let layout = Layout {
            layers: *layers,
            base: flat.clone(),
            origin,
        };
        let mut layered = Airspace::index(
            checked.nodes,
            checked.edges,
            kinds,
            checked.by_id,
            checked.edge_by_id,
            Some(Box::new(layout)),
        );
        layered.plane.clone_from(&flat.plane);
        Ok(layered)
    }
}

/// The id of the copy at layer `k` of the node or corridor `id`.
fn copy_id(id: &str, k: u32) -> String {
    if k == 1 {
        id.to_owned()
    } else {
        format!("{id}@{k}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layers::HeadingRule;
    use crate::testing::{airspace, edge, station};
    use crate::{EdgeId, Millis};

    /// A cross: a centre C and stations north-east, south-east, south-west and north-west
    /// of it (bearings near 45°, 135°, 225° and 315°: inside the quadrants, not on a bound).
    fn plus() -> Airspace {
        airspace(
            vec![
                station("C", 103.80, 1.30),
                station("NE", 103.81, 1.31),
                station("SE", 103.81, 1.29),
                station("SW", 103.79, 1.29),
                station("NW", 103.79, 1.31),
            ],
            (1..=4).map(|i| edge(0, i, 1_000.0)).collect(),
        )
    }

    #[test]
    fn one_layer_is_the_flat_airspace() {
        let flat = plus();
        let one = flat.layered(&Layers::default()).unwrap();
        assert_eq!(one.nodes(), flat.nodes());
        assert_eq!(one.edges(), flat.edges());
        assert!(one.layers().is_none());
        assert_eq!(one.node_layer(NodeId(3)), 1);
    }

    #[test]
    fn without_a_heading_rule_every_layer_has_every_corridor_both_ways() {
        let layers = Layers {
            count: 3,
            ..Layers::default()
        };
        let air = plus().layered(&layers).unwrap();
        assert_eq!(air.node_count(), 15);
        // 4 corridors × 3 layers, then 5 nodes × 2 vertical links.
        assert_eq!(air.edge_count(), 12 + 10);
        for k in 1..=3 {
            let c = air.at_layer(NodeId(0), k).unwrap();
            let e = air.at_layer(NodeId(2), k).unwrap();
            assert!(air.edge_between(c, e).is_some() && air.edge_between(e, c).is_some());
            let corridor = air.edge_between(c, e).unwrap();
            assert_eq!(air.flat_edge(corridor), Some(EdgeId(1)));
            assert_eq!(air.node_layer(e), k);
            assert_eq!(air.flat_node(e), NodeId(2));
        }
        let up = air.edge_between(NodeId(2), NodeId(7)).unwrap();
        assert_eq!(air.flat_edge(up), None);
        assert_eq!(air.node(NodeId(7)).id, "SE@2");
        assert_eq!(air.edge(up).id, "SE@1^2");
        assert_eq!(air.at_layer(NodeId(2), 4), None);
        let times = air.traversal_times(crate::Speed::default());
        assert_eq!(times[up.index()], Millis(1_829));
        assert_eq!(times[0], times[4]);
    }

    #[test]
    fn quadrantal_sectors_give_each_direction_one_layer() {
        let layers = Layers {
            count: 4,
            heading_rule: HeadingRule::Sectors,
            ..Layers::default()
        };
        let air = plus().layered(&layers).unwrap();
        let c = |k| air.at_layer(NodeId(0), k).unwrap();
        let to = |i, k| air.at_layer(NodeId(i), k).unwrap();
        // Out of C: layer 1 to the north-east, 2 south-east, 3 south-west, 4 north-west;
        // back the opposite quadrant.
        for (i, out_layer, back_layer) in [(1, 1, 3), (2, 2, 4), (3, 3, 1), (4, 4, 2)] {
            for k in 1..=4 {
                assert_eq!(air.edge_between(c(k), to(i, k)).is_some(), k == out_layer);
                assert_eq!(air.edge_between(to(i, k), c(k)).is_some(), k == back_layer);
            }
        }
        // Each corridor flown one way at two layers; 5 nodes × 3 vertical links.
        assert_eq!(air.edge_count(), 8 + 15);
        // Backwards, one-way corridors lead only from where they may be flown.
        let into_ne1: Vec<NodeId> = air.predecessors(to(1, 1)).iter().map(|a| a.node).collect();
        assert_eq!(into_ne1, [c(1), to(1, 2)]);
        let out_of_ne1: Vec<NodeId> = air.neighbours(to(1, 1)).iter().map(|a| a.node).collect();
        assert_eq!(out_of_ne1, [to(1, 2)]);
    }

    #[test]
    fn a_copy_id_taken_by_another_node_is_refused() {
        let flat = airspace(
            vec![station("A", 103.80, 1.30), station("A@2", 103.81, 1.30)],
            vec![edge(0, 1, 1_000.0)],
        );
        let two = Layers {
            count: 2,
            ..Layers::default()
        };
        let err = flat.layered(&two).unwrap_err();
        assert!(err.to_string().contains("A@2"), "{err}");
    }
}
