//! Airspace statistics, as printed by `muse airspace info`.
//!
//! Counts, edge lengths, the free-flow diameter and how many station pairs a drone can serve
//! within its battery limit `T_max` (docs/reference.md#flight-model-and-separation). Station-pair
//! times come from one [`Dijkstra`] search per station, with one reused workspace; the diameter
//! over all nodes from eccentricity bounds and as few further searches as they need (exact, and
//! checked against one search per node by a test).

use std::fmt;

use muse_model::{Airspace, Millis, NodeId, Speed};

use crate::shortest::Dijkstra;

/// Summary statistics of an airspace at a given cruise speed and battery limit.
#[derive(Clone, Debug, PartialEq)]
pub struct AirspaceStats {
    /// Number of nodes (stations and waypoints).
    pub nodes: usize,
    /// Number of stations.
    pub stations: usize,
    /// Number of (undirected) edges.
    pub edges: usize,
    /// Whether every node can reach every other node.
    pub connected: bool,
    /// Shortest edge, metres (`None` without edges).
    pub min_edge_m: Option<f64>,
    /// Median edge length, metres (mean of the two middle lengths for an even count).
    pub median_edge_m: Option<f64>,
    /// Longest edge, metres.
    pub max_edge_m: Option<f64>,
    /// Total length of all edges, metres.
    pub total_edge_m: f64,
    /// The largest shortest free-flow time between any two nodes that are connected
    /// (zero with fewer than two connected nodes).
    pub diameter: Millis,
    /// The largest shortest free-flow time between two connected stations.
    pub station_diameter: Millis,
    /// Ordered pairs of distinct stations: `stations × (stations − 1)`.
    pub station_pairs: usize,
    /// Ordered station pairs joined by some path.
    pub station_pairs_reachable: usize,
    /// Ordered station pairs whose free-flow time is at most `T_max`.
    pub station_pairs_within_t_max: usize,
    /// `station_pairs_within_t_max / station_pairs` (0 when there are no pairs).
    pub share_within_t_max: f64,
    /// The cruise speed the times are for.
    pub speed: Speed,
    /// The battery limit the share is for.
    pub t_max: Millis,
}

/// Computes [`AirspaceStats`] at cruise `speed` with battery limit `t_max`.
///
/// Runs one Dijkstra search per station, then as few more as eccentricity bounds need for
/// the exact diameter over all nodes (usually a handful; Takes & Kosters' method): about
/// `O(S (E + V) log V)` for `S` stations. 1,000 stations among 10,000 nodes take about a
/// second in release.
///
/// ```
/// use muse_airspace::stats::airspace_stats;
/// use muse_model::{Airspace, Edge, LonLat, Millis, Node, NodeId, NodeKind, Speed};
///
/// let node = |id: &str, kind, lon| Node {
///     id: id.into(), kind, name: String::new(), pos: LonLat::new(lon, 1.3),
/// };
/// let edge = |a: u32, b: u32, m| Edge {
///     id: format!("{a}-{b}"), from: NodeId(a), to: NodeId(b), length_m: m,
/// };
/// // S1 --2 km-- W --3 km-- S2: 4 + 6 = 10 minutes at 30 km/h.
/// let airspace = Airspace::new(
///     vec![
///         node("S1", NodeKind::Station, 103.80),
///         node("W", NodeKind::Waypoint, 103.82),
///         node("S2", NodeKind::Station, 103.85),
///     ],
///     vec![edge(0, 1, 2_000.0), edge(1, 2, 3_000.0)],
/// )
/// .unwrap();
/// let stats = airspace_stats(&airspace, Speed::PAPER, Millis::from_mins(20));
/// assert_eq!((stats.nodes, stats.stations, stats.edges), (3, 2, 2));
/// assert_eq!(stats.diameter, Millis::from_mins(10));
/// assert_eq!(stats.median_edge_m, Some(2_500.0));
/// assert_eq!(stats.station_pairs, 2);
/// assert_eq!(stats.share_within_t_max, 1.0);
/// let tight = airspace_stats(&airspace, Speed::PAPER, Millis::from_mins(9));
/// assert_eq!(tight.share_within_t_max, 0.0);
/// ```
pub fn airspace_stats(airspace: &Airspace, speed: Speed, t_max: Millis) -> AirspaceStats {
    let mut lengths: Vec<f64> = airspace.edges().iter().map(|e| e.length_m).collect();
    lengths.sort_by(f64::total_cmp);
    let median_edge_m = match lengths.len() {
        0 => None,
        n if n % 2 == 1 => Some(lengths[n / 2]),
        n => Some(f64::midpoint(lengths[n / 2 - 1], lengths[n / 2])),
    };

    let times = airspace.traversal_times(speed);
    let n = airspace.node_count();
    let mut search = Dijkstra::new(n);
    let mut station_diameter = Millis::ZERO;
    let mut reachable = 0;
    let mut within = 0;
    let mut connected = true;
    let mut diameter = Diameter::new(n);
    // Station pairs: one search per station, which also bounds every eccentricity.
    for source in airspace.stations() {
        search.run(airspace, &times, source);
        for (i, &d) in search.raw_times().iter().enumerate() {
            if d == i64::MAX {
                connected = false;
            } else if i != source.index() && airspace.is_station(NodeId(i as u32)) {
                station_diameter = station_diameter.max(Millis(d));
                reachable += 1;
                if Millis(d) <= t_max {
                    within += 1;
                }
            }
        }
        diameter.record(source, search.raw_times());
    }
    // The diameter over all nodes: more searches only where the bounds leave it open.
    while let Some(source) = diameter.next_source() {
        search.run(airspace, &times, source);
        if search.raw_times().contains(&i64::MAX) {
            connected = false;
        }
        diameter.record(source, search.raw_times());
    }
    let diameter = Millis(diameter.best);

    let stations = airspace.stations().count();
    let station_pairs = stations * stations.saturating_sub(1);
    AirspaceStats {
        nodes: airspace.node_count(),
        stations,
        edges: airspace.edge_count(),
        connected,
        min_edge_m: lengths.first().copied(),
        median_edge_m,
        max_edge_m: lengths.last().copied(),
        total_edge_m: lengths.iter().sum(),
        diameter,
        station_diameter,
        station_pairs,
        station_pairs_reachable: reachable,
        station_pairs_within_t_max: within,
        share_within_t_max: if station_pairs == 0 {
            0.0
        } else {
            within as f64 / station_pairs as f64
        },
        speed,
        t_max,
    }
}

/// The exact diameter (largest finite shortest time) of an undirected graph from few
/// searches, by eccentricity bounds (Takes & Kosters, *Determining the diameter of small
/// world networks*, 2011, adapted to weights): after a search from `v` with eccentricity
/// `e(v)`, every node `w` it reaches at time `d` has `max(d, e(v) − d) ≤ e(w) ≤ e(v) + d`.
/// Searches continue from the unsearched node with the largest upper bound until no
/// unsearched node's upper bound exceeds the largest eccentricity found. A node never
/// reached keeps an infinite upper bound, so every component is searched at least once.
#[derive(Debug)]
struct Diameter {
    lower: Vec<i64>,
    upper: Vec<i64>,
    searched: Vec<bool>,
    /// The largest eccentricity found so far.
    best: i64,
}

impl Diameter {
    fn new(n: usize) -> Self {
        Diameter {
            lower: vec![0; n],
            upper: vec![i64::MAX; n],
            searched: vec![false; n],
            best: 0,
        }
    }

    /// Takes in the times of a search from `source` (`i64::MAX` for unreached nodes).
    fn record(&mut self, source: NodeId, times: &[i64]) {
        let ecc = times
            .iter()
            .copied()
            .filter(|&d| d != i64::MAX)
            .max()
            .unwrap_or(0);
        self.best = self.best.max(ecc);
        self.searched[source.index()] = true;
        self.lower[source.index()] = ecc;
        self.upper[source.index()] = ecc;
        for ((&d, lo), up) in times.iter().zip(&mut self.lower).zip(&mut self.upper) {
            if d != i64::MAX {
                *lo = (*lo).max(d).max(ecc - d);
                *up = (*up).min(ecc.saturating_add(d));
            }
        }
    }

    /// The next node to search from, or `None` when `best` is the diameter: the unsearched
    /// node with the largest upper bound (then the largest lower bound, then the lowest
    /// index) if that bound exceeds `best`.
    fn next_source(&self) -> Option<NodeId> {
        let mut pick: Option<usize> = None;
        for i in 0..self.upper.len() {
            if self.searched[i] || self.upper[i] <= self.best {
                continue;
            }
            if pick.is_none_or(|p| (self.upper[i], self.lower[i]) > (self.upper[p], self.lower[p]))
            {
                pick = Some(i);
            }
        }
        pick.map(|i| NodeId(i as u32))
    }
}

/// A human-readable multi-line report, e.g. for `muse airspace info`.
impl fmt::Display for AirspaceStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let km =
            |m: Option<f64>| m.map_or_else(|| "-".to_owned(), |m| format!("{:.3} km", m / 1_000.0));
        let min = |t: Millis| format!("{:.1} min", t.as_secs_f64() / 60.0);
        writeln!(
            f,
            "nodes:      {} ({} stations, {} waypoints)",
            self.nodes,
            self.stations,
            self.nodes - self.stations
        )?;
        writeln!(
            f,
            "edges:      {} ({:.1} km in total)",
            self.edges,
            self.total_edge_m / 1_000.0
        )?;
        writeln!(
            f,
            "edge length: min {}, median {}, max {}",
            km(self.min_edge_m),
            km(self.median_edge_m),
            km(self.max_edge_m)
        )?;
        writeln!(
            f,
            "connected:  {}",
            if self.connected { "yes" } else { "no" }
        )?;
        writeln!(
            f,
            "diameter:   {} over all nodes, {} between stations (free flow at {} km/h)",
            min(self.diameter),
            min(self.station_diameter),
            self.speed.kmh()
        )?;
        write!(
            f,
            "station pairs: {} ordered, {} reachable, {} ({:.1} %) within T_max = {}",
            self.station_pairs,
            self.station_pairs_reachable,
            self.station_pairs_within_t_max,
            self.share_within_t_max * 100.0,
            min(self.t_max)
        )
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the lengths are exact in binary
mod tests {
    use super::*;
    use muse_model::testing::{airspace, edge, node, station, waypoint};
    use muse_model::{Node, NodeKind};

    /// Hand-checked graph (times at 30 km/h: 1 km = 2 min):
    ///
    /// ```text
    ///  S0 --1 km-- S1 --4 km-- S2
    ///   \                      /
    ///   2 km                 2 km
    ///     \                  /
    ///      W3 ------1 km--- W4          S5 (isolated)
    /// ```
    ///
    /// Shortest distances: S0–S1 1 km (2 min); S1–S2 4 km (8 min; the detour is 6 km);
    /// S0–S2 5 km either way (10 min); S1–W4 4 km; W3–S2 3 km; S0–W4 3 km. The largest is
    /// S0–S2, so both diameters are 10 min.
    fn sample() -> Airspace {
        airspace(
            vec![
                station("S0", 103.8, 1.3),
                station("S1", 103.8, 1.3),
                station("S2", 103.8, 1.3),
                waypoint("W3", 103.8, 1.3),
                waypoint("W4", 103.8, 1.3),
                station("S5", 103.8, 1.3),
            ],
            vec![
                edge(0, 1, 1_000.0),
                edge(1, 2, 4_000.0),
                edge(0, 3, 2_000.0),
                edge(3, 4, 1_000.0),
                edge(4, 2, 2_000.0),
            ],
        )
    }

    #[test]
    fn hand_checked_graph() {
        let s = airspace_stats(&sample(), Speed::PAPER, Millis::from_mins(9));
        assert_eq!((s.nodes, s.stations, s.edges), (6, 4, 5));
        assert!(!s.connected);
        assert_eq!(s.min_edge_m, Some(1_000.0));
        assert_eq!(s.median_edge_m, Some(2_000.0));
        assert_eq!(s.max_edge_m, Some(4_000.0));
        assert_eq!(s.total_edge_m, 10_000.0);
        assert_eq!(s.diameter, Millis::from_mins(10));
        assert_eq!(s.station_diameter, Millis::from_mins(10));
        // 4 stations → 12 ordered pairs; 6 involve the isolated S5.
        assert_eq!(s.station_pairs, 12);
        assert_eq!(s.station_pairs_reachable, 6);
        // Within 9 min: S0-S1 (2), S1-S2 (8), both directions; S0-S2 (10) is not.
        assert_eq!(s.station_pairs_within_t_max, 4);
        assert!((s.share_within_t_max - 4.0 / 12.0).abs() < 1e-12);
        // T_max is inclusive: exactly 10 min fits.
        let s = airspace_stats(&sample(), Speed::PAPER, Millis::from_mins(10));
        assert_eq!(s.station_pairs_within_t_max, 6);
        let text = s.to_string();
        assert!(text.contains("(4 stations, 2 waypoints)"), "{text}");
        assert!(text.contains("connected:  no"), "{text}");
    }

    #[test]
    fn speed_changes_times() {
        // At 60 km/h everything takes half as long.
        let s = airspace_stats(
            &sample(),
            Speed::from_kmh(60.0).unwrap(),
            Millis::from_mins(5),
        );
        assert_eq!(s.diameter, Millis::from_mins(5));
        assert_eq!(s.station_pairs_within_t_max, 6);
    }

    #[test]
    fn empty_and_tiny_airspaces() {
        let empty = airspace(vec![], vec![]);
        let s = airspace_stats(&empty, Speed::PAPER, Millis::from_mins(20));
        assert_eq!((s.nodes, s.edges, s.station_pairs), (0, 0, 0));
        assert!(s.connected);
        assert_eq!(s.median_edge_m, None);
        assert_eq!(s.diameter, Millis::ZERO);
        assert_eq!(s.share_within_t_max, 0.0);
        let one = airspace(vec![station("S0", 103.8, 1.3)], vec![]);
        let s = airspace_stats(&one, Speed::PAPER, Millis::from_mins(20));
        assert!(s.connected);
        assert_eq!(s.station_pairs, 0);
        assert!(s.to_string().contains("median -"));
    }

    /// The diameter by brute force: one search from every node.
    fn brute_force_diameter(a: &Airspace, speed: Speed) -> (Millis, bool) {
        let times = a.traversal_times(speed);
        let mut search = Dijkstra::new(a.node_count());
        let (mut best, mut connected) = (0, true);
        for v in 0..a.node_count() {
            search.run(a, &times, NodeId(v as u32));
            for &d in search.raw_times() {
                if d == i64::MAX {
                    connected = false;
                } else {
                    best = best.max(d);
                }
            }
        }
        (Millis(best), connected)
    }

    #[test]
    fn bounded_diameter_is_exact() {
        use crate::builder::{BuildOptions, build_airspace};
        let mut state: u64 = 99;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for round in 0..40 {
            let count = 3 + round * 5;
            let station_every = 1 + round % 7;
            let nodes: Vec<Node> = (0..count)
                .map(|i| {
                    let kind = if i % station_every == 0 {
                        NodeKind::Station
                    } else {
                        NodeKind::Waypoint
                    };
                    let (lon, lat) = (103.6 + 0.4 * next(), 1.2 + 0.2 * next());
                    node(&format!("N{i}"), kind, lon, lat)
                })
                .collect();
            let a = build_airspace(nodes, &BuildOptions::default()).unwrap();
            // Also a disconnected variant: drop every third edge.
            let cut = airspace(
                a.nodes().to_vec(),
                a.edges()
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| k % 3 != 1)
                    .map(|(_, e)| e.clone())
                    .collect(),
            );
            for air in [&a, &cut] {
                let s = airspace_stats(air, Speed::PAPER, Millis::from_mins(20));
                let (d, connected) = brute_force_diameter(air, Speed::PAPER);
                assert_eq!((s.diameter, s.connected), (d, connected), "round {round}");
            }
        }
        // Without stations, and with isolated nodes.
        let waypoints = airspace(
            (0..4)
                .map(|i| waypoint(&format!("W{i}"), 103.8, 1.3))
                .collect(),
            vec![edge(0, 1, 1_000.0), edge(1, 2, 3_000.0)],
        );
        let s = airspace_stats(&waypoints, Speed::PAPER, Millis::from_mins(20));
        assert_eq!((s.diameter, s.connected), (Millis::from_mins(8), false));
    }
}
