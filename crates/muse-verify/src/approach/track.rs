//! A flight's trajectory in metres (docs/reference.md#metric-separation): straight pieces in the
//! airspace's local plane and altitude, each flown at constant pace between two instants.
//!
//! During a stay the drone is at its node; between two stays of one leg it moves in a straight
//! line from the first node to the second (a corridor, or a vertical link above one node);
//! between legs it is on the ground, in no piece. A stay of no duration (passing a node) adds
//! no piece: the two moves around it meet there.

use muse_model::{Airspace, NodeId, Plan};

/// Where each node of an airspace is: metres east and north in a local plane (about a point
/// near the airspace, so that they stay small), and its altitude.
#[derive(Clone, Debug)]
pub struct Positions {
    xyz: Vec<[f64; 3]>,
}

impl Positions {
    /// The positions of `airspace`'s nodes, given those of its flat nodes in the plane
    /// (`plane[n]` for flat node `n`, metres): at layer `k` a node is at the layer's altitude
    /// (`h_1` when flat).
    ///
    /// # Panics
    /// If `plane` does not hold one position per flat node.
    #[must_use]
    pub fn new(airspace: &Airspace, plane: &[[f64; 2]]) -> Positions {
        assert_eq!(
            plane.len(),
            airspace.flat().node_count(),
            "one position per flat node"
        );
        let (cx, cy) = centre(plane);
        let layers = airspace.layers().copied().unwrap_or_default();
        let xyz = (0..airspace.node_count())
            .map(|n| {
                let id = NodeId(n as u32);
                let flat = airspace.flat_node(id).index();
                let k = airspace.node_layer(id).max(1);
                let z = layers.base.m() + f64::from(k - 1) * layers.spacing.m();
                [plane[flat][0] - cx, plane[flat][1] - cy, z]
            })
            .collect();
        Positions { xyz }
    }

    /// Node `n`'s position.
    #[must_use]
    pub fn at(&self, n: NodeId) -> [f64; 3] {
        self.xyz[n.index()]
    }
}

/// The mean of the positions (the origin the positions are taken about).
fn centre(plane: &[[f64; 2]]) -> (f64, f64) {
    if plane.is_empty() {
        return (0.0, 0.0);
    }
    let n = plane.len() as f64;
    let (x, y) = plane
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p[0], y + p[1]));
    (x / n, y / n)
}

/// One straight piece of a trajectory: from `p0` at `t0` to `p1` at `t1` (seconds after the
/// report's origin of time), at constant pace; `from` and `to` are its end nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Which flight (its index in the list checked).
    pub flight: u32,
    /// When it begins, seconds.
    pub t0: f64,
    /// When it ends, seconds.
    pub t1: f64,
    /// Where it begins, metres (east, north, up).
    pub p0: [f64; 3],
    /// Where it ends.
    pub p1: [f64; 3],
    /// The node it begins at.
    pub from: NodeId,
    /// The node it ends at (the same as `from` for a stay).
    pub to: NodeId,
}

impl Piece {
    /// The position at `t` (within `[t0, t1]`).
    #[must_use]
    pub fn at(&self, t: f64) -> [f64; 3] {
        if self.t1 <= self.t0 {
            return self.p0;
        }
        let f = (t - self.t0) / (self.t1 - self.t0);
        [0, 1, 2].map(|i| self.p0[i] + (self.p1[i] - self.p0[i]) * f)
    }

    /// The velocity, metres per second (zero when still or instantaneous).
    #[must_use]
    pub fn velocity(&self) -> [f64; 3] {
        if self.t1 <= self.t0 {
            return [0.0; 3];
        }
        let d = self.t1 - self.t0;
        [0, 1, 2].map(|i| (self.p1[i] - self.p0[i]) / d)
    }
}

/// Appends the pieces of `plan` (flight number `flight`) to `out`, times in seconds after
/// `origin_ms`.
pub fn pieces(
    positions: &Positions,
    plan: &Plan,
    flight: u32,
    origin_ms: i64,
    out: &mut Vec<Piece>,
) {
    let secs = |ms: i64| (ms - origin_ms) as f64 / 1000.0;
    let path = &plan.path;
    for (i, stay) in path.iter().enumerate() {
        let p = positions.at(stay.node);
        if stay.depart > stay.arrive {
            out.push(Piece {
                flight,
                t0: secs(stay.arrive.0),
                t1: secs(stay.depart.0),
                p0: p,
                p1: p,
                from: stay.node,
                to: stay.node,
            });
        }
        let Some(next) = path.get(i + 1) else { break };
        if next.node == stay.node {
            // Landed; the next leg takes off here later: on the ground between.
            continue;
        }
        out.push(Piece {
            flight,
            t0: secs(stay.depart.0),
            t1: secs(next.arrive.0),
            p0: p,
            p1: positions.at(next.node),
            from: stay.node,
            to: next.node,
        });
    }
}
