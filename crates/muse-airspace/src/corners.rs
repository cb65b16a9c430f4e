//! The corners of an airspace: at each node, the angle between every two of its corridors, in
//! its local plane (docs/reference.md#metric-separation).
//!
//! Where two corridors leave a node at an angle θ, a drone leaving along one and another
//! arriving along the other `g` apart in time at the node pass within `v·g·sin(θ/2)` of each
//! other (the least distance, halfway between). Keeping them `D` apart needs
//! `g ≥ D / (v·sin(θ/2))`: the sharper the corner, the longer the gap.
//!
//! ```
//! use muse_airspace::corners::{corners, gap_s};
//! use muse_model::Airspace;
//! // A line of three nodes 1 km apart: at the middle one, two corridors at 180°.
//! let air = Airspace::line(&[1000.0, 1000.0]);
//! let plane = [[0.0, 0.0], [1000.0, 0.0], [2000.0, 0.0]];
//! let c = corners(&air, &plane);
//! assert_eq!(c.len(), 1);
//! assert!((c[0].angle_deg - 180.0).abs() < 1e-9);
//! // Head on through the node: 30 m apart needs 30 m / (8.33 m/s · sin 90°) = 3.6 s.
//! assert!((gap_s(c[0].angle_deg, 30.0, 30.0 / 3.6) - 3.6).abs() < 1e-9);
//! ```

use muse_model::{Airspace, EdgeId, NodeId};

/// Two corridors meeting at a node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// The node.
    pub node: NodeId,
    /// The two corridors (the lower id first).
    pub edges: (EdgeId, EdgeId),
    /// The angle between them at the node, degrees, in `[0, 180]`.
    pub angle_deg: f64,
}

/// Every corner of `airspace` (flat: its corridors; `plane[n]` the position of node `n` in
/// metres), the sharpest first (then by node and corridors).
#[must_use]
pub fn corners(airspace: &Airspace, plane: &[[f64; 2]]) -> Vec<Corner> {
    let mut out = Vec::new();
    for n in 0..airspace.node_count() {
        let node = NodeId(n as u32);
        let here = plane[n];
        let arms: Vec<(EdgeId, f64)> = airspace
            .neighbours(node)
            .iter()
            .filter(|adj| airspace.node(adj.node).pos != airspace.node(node).pos)
            .map(|adj| {
                let there = plane[adj.node.index()];
                (adj.edge, (there[1] - here[1]).atan2(there[0] - here[0]))
            })
            .collect();
        for (i, &(e1, b1)) in arms.iter().enumerate() {
            for &(e2, b2) in &arms[i + 1..] {
                let mut angle = (b1 - b2).abs().to_degrees();
                if angle > 180.0 {
                    angle = 360.0 - angle;
                }
                out.push(Corner {
                    node,
                    edges: (e1.min(e2), e1.max(e2)),
                    angle_deg: angle,
                });
            }
        }
    }
    out.sort_by(|a, b| {
        a.angle_deg
            .total_cmp(&b.angle_deg)
            .then(a.node.cmp(&b.node))
            .then(a.edges.cmp(&b.edges))
    });
    out
}

/// The gap in time, seconds, that a departure along one corridor of a corner of `angle_deg`
/// and an arrival along the other need at the node to stay `distance_m` apart at
/// `speed_mps`: `D / (v·sin(θ/2))` (infinite for corridors that leave in one direction).
#[must_use]
pub fn gap_s(angle_deg: f64, distance_m: f64, speed_mps: f64) -> f64 {
    distance_m / (speed_mps * (angle_deg.to_radians() / 2.0).sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::testing::{joined, station};

    #[test]
    fn a_sharp_corner_comes_first_with_its_gap() {
        // Three corridors from A: east, north-east (45°) and a shallow one 5° above east.
        let air = joined(
            vec![
                station("A", 103.80, 1.30),
                station("E", 103.81, 1.30),
                station("N", 103.81, 1.31),
                station("S", 103.81, 1.301),
            ],
            &[("A", "E", 1000.0), ("A", "N", 1414.0), ("A", "S", 1000.0)],
        );
        let plane = [
            [0.0, 0.0],
            [1000.0, 0.0],
            [1000.0, 1000.0],
            [1000.0, 87.488_663],
        ];
        let c = corners(&air, &plane);
        assert_eq!(c.len(), 3);
        assert!((c[0].angle_deg - 5.0).abs() < 1e-4, "{c:?}");
        assert_eq!(air.node(c[0].node).id, "A");
        assert!((c[1].angle_deg - 40.0).abs() < 1e-4 && (c[2].angle_deg - 45.0).abs() < 1e-9);
        // 30 m at 30 km/h at 5°: 30 / (8.333 · sin 2.5°) = 82.5 s.
        let g = gap_s(c[0].angle_deg, 30.0, 30.0 / 3.6);
        assert!(
            (g - 30.0 / (30.0 / 3.6 * 2.5_f64.to_radians().sin())).abs() < 1e-3,
            "{g}"
        );
    }
}
