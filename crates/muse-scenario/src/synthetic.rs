//! Synthetic airspaces of any size, to study how planning scales: a square grid, or random
//! points joined like the Singapore stations.
//!
//! Both layouts are centred on [`CENTRE`] (1.35° N, 103.82° E, the middle of Singapore), so
//! that the Singapore date, UTC offset and zone clock times apply unchanged; they ignore the
//! land (a large airspace extends over the sea and Malaysia).
//!
//! # The rule, exactly
//!
//! - **Layout [`Grid`](Layout::Grid):** `c = ⌈√n⌉` columns and `⌈n / c⌉` rows, `spacing_m`
//!   apart east–west and north–south; node `i` (0-based) is in row `i / c` (row 0 is the
//!   northernmost) and column `i % c` (column 0 the westernmost), so exactly `n` nodes, the
//!   last row possibly incomplete. Corridors join each node to its east and south
//!   neighbours (4-neighbourhood): `2n − rows − columns` edges for a full grid; connected.
//! - **Layout [`Geometric`](Layout::Geometric):** `n` points uniform in a square of side
//!   `L`, where `L` makes the expected mean nearest-neighbour distance equal `spacing_m`
//!   (Donnelly's edge-corrected estimate for a square, `E = 0.5 L/√n + (0.0514 + 0.041/√n)
//!   · 4L/n`; about `2 · spacing_m · √n`). Drawn from a [`ChaCha8Rng`] seeded with `seed`,
//!   `x` then `y`, uniform numbers made from the raw `u64` output as `(x >> 11) · 2⁻⁵³`; a
//!   point whose rounded position (below) coincides with an earlier one is drawn again.
//!   Corridors: [`build_airspace`] with its default rule (Delaunay, then "join collinear
//!   nodes" with 15°) in the stereographic plane about the points' centroid
//!   ([`BuildPlane::Stereographic`], the plane every airspace was built in before
//!   docs/reference.md#airspace-from-pads, so that a synthetic airspace stays what it was).
//!   Delaunay corridors are longer than the nearest-neighbour distance: their median is about 2.2 ×
//!   `spacing_m` (3.25 km for 10,000 nodes at 1,500 m), and the hull has a few long ones (up to 31
//!   km there) that collinear joining does not remove.
//! - **Positions:** a point `(x, y)` metres east and north of [`CENTRE`] is at latitude
//!   `φ₀ + y / M` and longitude `λ₀ + x / (N cos φ₀)`, with `M`, `N` the WGS84 meridian and
//!   prime-vertical radii of curvature at `φ₀` ([`MetresPer::radian`]; an equirectangular
//!   plane; at 1.35° N its scale error is below 0.1 % within a few hundred kilometres),
//!   rounded to 7 decimals (about 1 cm) like the Singapore stations.
//! - **Stations:** `max(2, round(station_share · n))` of the nodes, the first of a
//!   Fisher–Yates shuffle of `0..n` (from the last index down, swapping `i` with
//!   `⌊u64 · (i + 1) / 2⁶⁴⌋`) driven by the same generator, after the points for
//!   `Geometric`; the others are waypoints.
//! - **Ids:** `N00001`, `N00002`, … in node order (more digits beyond 99,999); names empty.
//!   Edge lengths are geodesic on WGS84 rounded to the millimetre, ids `FROM-TO`, from the
//!   lower to the higher index, sorted, as the builder does.
//!
//! The result is deterministic: the same spec gives the same airspace, byte for byte once
//! written. 10,000 nodes take about 15 ms (grid) or 50 ms (geometric) in release.

use std::collections::HashSet;
use std::fmt;

use muse_airspace::builder::{BuildOptions, build_airspace};
use muse_airspace::plane::Plane as BuildPlane;
use muse_model::{Airspace, Edge, LonLat, MetresPer, Node, NodeId, NodeKind};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

use crate::ScenarioError;
use crate::singapore::round_to_decimals;
use crate::stations::uniform;

/// The centre of every synthetic airspace: 103.82° E, 1.35° N.
pub const CENTRE: LonLat = LonLat::new(103.82, 1.35);

/// The largest number of nodes accepted (the range of `--nodes`,
/// [`muse_formats::ranges::NODES`]).
pub const MAX_NODES: usize = muse_formats::ranges::NODES.hi;

/// The smallest spacing accepted, metres (positions are kept to about 1 cm; the range of
/// `--spacing-m`, [`muse_formats::ranges::SPACING_M`]).
pub const MIN_SPACING_M: f64 = muse_formats::ranges::SPACING_M.lo;

/// The largest side of the square a synthetic airspace may span, metres (2,000 km).
pub const MAX_EXTENT_M: f64 = 2_000_000.0;

/// How the nodes of a synthetic airspace are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// A square grid with 4-neighbour corridors.
    Grid,
    /// Uniform random points joined by Delaunay triangulation and collinear joining.
    Geometric,
}

impl Layout {
    /// `grid` or `geometric`.
    pub const fn as_str(self) -> &'static str {
        match self {
            Layout::Grid => "grid",
            Layout::Geometric => "geometric",
        }
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What synthetic airspace to build (see the [module documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct SyntheticSpec {
    /// Grid or geometric.
    pub layout: Layout,
    /// Number of nodes, at least 2 and at most [`MAX_NODES`].
    pub nodes: usize,
    /// The typical spacing, metres: the corridor length of a grid, the mean
    /// nearest-neighbour distance of a geometric layout. At least [`MIN_SPACING_M`].
    pub spacing_m: f64,
    /// The fraction of nodes that are stations, in `(0, 1]`; the rest are waypoints. At
    /// least 2 stations.
    pub station_share: f64,
    /// Seed of the random points (geometric) and of the choice of stations.
    pub seed: u64,
}

impl Default for SyntheticSpec {
    /// A 100-node grid, 1.5 km spacing, 10 % stations, seed 1.
    fn default() -> Self {
        SyntheticSpec {
            layout: Layout::Grid,
            nodes: 100,
            spacing_m: 1_500.0,
            station_share: 0.1,
            seed: 1,
        }
    }
}

impl SyntheticSpec {
    /// How many nodes are stations: `max(2, round(station_share · nodes))`, at most `nodes`.
    pub fn station_count(&self) -> usize {
        ((self.station_share * self.nodes as f64).round() as usize)
            .max(2)
            .min(self.nodes)
    }

    /// The side of the square the nodes span, metres.
    pub fn extent_m(&self) -> f64 {
        let n = self.nodes as f64;
        match self.layout {
            Layout::Grid => (grid_columns(self.nodes).saturating_sub(1)) as f64 * self.spacing_m,
            Layout::Geometric => {
                // Donnelly: E[NN] = 0.5 L/√n + (0.0514 + 0.041/√n) · 4L/n = spacing.
                let per_side = 0.5 / n.sqrt() + (0.0514 + 0.041 / n.sqrt()) * 4.0 / n;
                self.spacing_m / per_side
            }
        }
    }

    /// Checks the spec; the error says which field is wrong and why.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        let bad = |m: String| Err(ScenarioError::BadSpec(m));
        if !(2..=MAX_NODES).contains(&self.nodes) {
            return bad(format!(
                "nodes = {} must be between 2 and {MAX_NODES}",
                self.nodes
            ));
        }
        if !self.spacing_m.is_finite() || self.spacing_m < MIN_SPACING_M {
            return bad(format!(
                "spacing = {} m must be a number of at least {MIN_SPACING_M} m",
                self.spacing_m
            ));
        }
        if !(self.station_share > 0.0 && self.station_share <= 1.0) {
            return bad(format!(
                "station share = {} must be greater than 0 and at most 1",
                self.station_share
            ));
        }
        let extent = self.extent_m();
        if extent > MAX_EXTENT_M {
            return bad(format!(
                "{} nodes {:.0} m apart span {:.0} km, more than the {:.0} km allowed",
                self.nodes,
                self.spacing_m,
                extent / 1_000.0,
                MAX_EXTENT_M / 1_000.0
            ));
        }
        Ok(())
    }
}

impl fmt::Display for SyntheticSpec {
    /// E.g. `synthetic grid, 100 nodes, spacing 1500 m, 10 stations, seed 1`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "synthetic {}, {} nodes, spacing {} m, {} stations, seed {}",
            self.layout,
            self.nodes,
            self.spacing_m,
            self.station_count(),
            self.seed
        )
    }
}

/// `⌈√n⌉`.
fn grid_columns(n: usize) -> usize {
    let c = n.isqrt();
    if c * c < n { c + 1 } else { c }
}

/// A uniform index in `0..bound` from the raw output of `rng` (multiply–shift).
fn below(rng: &mut ChaCha8Rng, bound: usize) -> usize {
    ((u128::from(rng.next_u64()) * bound as u128) >> 64) as usize
}

/// The point `x` metres east and `y` north of [`CENTRE`] (equirectangular, see the module
/// documentation; `per_radian` is [`MetresPer::radian`] at the centre's latitude), its degrees
/// rounded to 7 decimals. Metres become radians, then degrees: the order every synthetic
/// airspace was made in (a division by metres per degree differs in the last bit, which the
/// rounding can show).
fn to_lon_lat(per_radian: MetresPer, x: f64, y: f64) -> LonLat {
    LonLat::new(
        round_to_decimals(CENTRE.lon + (x / per_radian.lon).to_degrees()),
        round_to_decimals(CENTRE.lat + (y / per_radian.lat).to_degrees()),
    )
}

fn node_id(i: usize) -> String {
    format!("N{:05}", i + 1)
}

/// Builds the synthetic airspace `spec` describes (see the [module documentation](self)).
///
/// ```
/// use muse_scenario::synthetic::{Layout, SyntheticSpec, synthetic};
/// let spec = SyntheticSpec { layout: Layout::Grid, nodes: 12, ..SyntheticSpec::default() };
/// let grid = synthetic(&spec).unwrap();
/// // 4 columns, 3 rows: 3 · 3 east–west and 4 · 2 north–south corridors.
/// assert_eq!((grid.node_count(), grid.edge_count()), (12, 17));
/// assert_eq!(grid.stations().count(), 2);
/// assert_eq!(grid.nodes()[0].id, "N00001");
/// let random = synthetic(&SyntheticSpec { layout: Layout::Geometric, ..spec }).unwrap();
/// assert!(random.is_connected());
/// ```
pub fn synthetic(spec: &SyntheticSpec) -> Result<Airspace, ScenarioError> {
    spec.validate()?;
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let per_radian = MetresPer::radian(CENTRE.lat);
    let n = spec.nodes;
    let node = |i: usize, pos: LonLat| Node {
        id: node_id(i),
        kind: NodeKind::Waypoint,
        name: String::new(),
        pos,
    };
    let (mut nodes, edges) = match spec.layout {
        Layout::Grid => {
            let cols = grid_columns(n);
            let rows = n.div_ceil(cols);
            let s = spec.spacing_m;
            let (x0, y0) = (
                -((cols - 1) as f64) * s / 2.0,
                ((rows - 1) as f64) * s / 2.0,
            );
            let nodes: Vec<Node> = (0..n)
                .map(|i| {
                    let (r, c) = (i / cols, i % cols);
                    node(
                        i,
                        to_lon_lat(per_radian, x0 + c as f64 * s, y0 - r as f64 * s),
                    )
                })
                .collect();
            let mut edges = Vec::with_capacity(2 * n);
            for i in 0..n {
                let east = (i % cols + 1 < cols && i + 1 < n).then_some(i + 1);
                let south = (i + cols < n).then_some(i + cols);
                for j in [east, south].into_iter().flatten() {
                    let length_m = (nodes[i].pos.geodesic_distance_m(nodes[j].pos) * 1_000.0)
                        .round()
                        / 1_000.0;
                    edges.push(Edge {
                        id: format!("{}-{}", nodes[i].id, nodes[j].id),
                        from: NodeId(i as u32),
                        to: NodeId(j as u32),
                        length_m,
                    });
                }
            }
            (nodes, Some(edges))
        }
        Layout::Geometric => {
            let side = spec.extent_m();
            let mut seen: HashSet<(i64, i64)> = HashSet::with_capacity(n);
            let mut nodes = Vec::with_capacity(n);
            while nodes.len() < n {
                let x = (uniform(&mut rng) - 0.5) * side;
                let y = (uniform(&mut rng) - 0.5) * side;
                let pos = to_lon_lat(per_radian, x, y);
                let key = (
                    (pos.lon * 1e7).round() as i64,
                    (pos.lat * 1e7).round() as i64,
                );
                if seen.insert(key) {
                    nodes.push(node(nodes.len(), pos));
                }
            }
            (nodes, None)
        }
    };

    // Stations: the first `station_count` of a seeded Fisher–Yates shuffle.
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        order.swap(i, below(&mut rng, i + 1));
    }
    for &i in &order[..spec.station_count()] {
        nodes[i].kind = NodeKind::Station;
    }

    Ok(match edges {
        Some(edges) => {
            Airspace::new(nodes, edges).map_err(muse_airspace::builder::BuildError::from)?
        }
        None => build_airspace(
            nodes,
            &BuildOptions {
                plane: BuildPlane::Stereographic,
                ..BuildOptions::default()
            },
        )?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(layout: Layout, nodes: usize) -> SyntheticSpec {
        SyntheticSpec {
            layout,
            nodes,
            ..SyntheticSpec::default()
        }
    }

    #[test]
    fn grid_counts_and_lengths() {
        for n in [2, 3, 5, 10, 16, 17, 99, 100, 101, 1_000] {
            let s = spec(Layout::Grid, n);
            let a = synthetic(&s).unwrap();
            let cols = grid_columns(n);
            let rows = n.div_ceil(cols);
            assert_eq!(a.node_count(), n);
            assert_eq!(a.stations().count(), s.station_count());
            assert_eq!(
                s.station_count(),
                ((n as f64 * 0.1).round() as usize).max(2)
            );
            assert!(a.is_connected(), "{n}");
            // Full rows: cols − 1 each; the last row: its length − 1; columns: n − cols.
            let last = n - (rows - 1) * cols;
            assert_eq!(
                a.edge_count(),
                (rows - 1) * (cols - 1) + (last - 1) + (n - cols),
                "{n}"
            );
            for e in a.edges() {
                assert!(
                    (e.length_m - 1_500.0).abs() < 1.0,
                    "{}: {}",
                    e.id,
                    e.length_m
                );
                assert!(e.from < e.to);
            }
            assert_eq!(a.nodes()[n - 1].id, format!("N{n:05}"));
        }
        let a = synthetic(&spec(Layout::Grid, 10_000)).unwrap();
        assert_eq!((a.node_count(), a.edge_count()), (10_000, 19_800));
        assert_eq!(a.stations().count(), 1_000);
    }

    #[test]
    fn geometric_counts_and_spacing() {
        for n in [2, 3, 10, 500] {
            let s = spec(Layout::Geometric, n);
            let a = synthetic(&s).unwrap();
            assert_eq!(a.node_count(), n);
            assert_eq!(a.stations().count(), s.station_count());
            assert!(a.is_connected(), "{n}");
        }
        // The nearest neighbour of a node is among its corridors (collinear joining never
        // drops the shortest edge at a node), so the mean nearest-neighbour distance is the
        // mean of each node's shortest corridor.
        for seed in 1..=3 {
            let s = SyntheticSpec {
                layout: Layout::Geometric,
                nodes: 3_000,
                spacing_m: 1_000.0,
                station_share: 0.5,
                seed,
            };
            let a = synthetic(&s).unwrap();
            assert_eq!(a.stations().count(), 1_500);
            let mut nearest = vec![f64::INFINITY; a.node_count()];
            for e in a.edges() {
                for v in [e.from, e.to] {
                    nearest[v.index()] = nearest[v.index()].min(e.length_m);
                }
            }
            let mean = nearest.iter().sum::<f64>() / nearest.len() as f64;
            assert!(
                (mean - 1_000.0).abs() < 40.0,
                "mean nearest neighbour {mean}"
            );
        }
    }

    #[test]
    fn everything_is_a_station_with_share_one() {
        for layout in [Layout::Grid, Layout::Geometric] {
            let s = SyntheticSpec {
                layout,
                nodes: 50,
                station_share: 1.0,
                ..SyntheticSpec::default()
            };
            assert_eq!(synthetic(&s).unwrap().stations().count(), 50);
        }
    }

    #[test]
    fn deterministic_and_seeded() {
        for layout in [Layout::Grid, Layout::Geometric] {
            let s = spec(layout, 400);
            let (a, b) = (synthetic(&s).unwrap(), synthetic(&s).unwrap());
            assert_eq!(a.nodes(), b.nodes());
            assert_eq!(a.edges(), b.edges());
            let other = synthetic(&SyntheticSpec { seed: 2, ..s }).unwrap();
            let stations = |x: &Airspace| x.stations().collect::<Vec<_>>();
            assert_ne!(stations(&a), stations(&other), "{layout}: stations differ");
            if layout == Layout::Geometric {
                assert_ne!(a.nodes()[0].pos, other.nodes()[0].pos, "positions differ");
            }
        }
    }

    #[test]
    fn centred_on_singapore() {
        for layout in [Layout::Grid, Layout::Geometric] {
            let a = synthetic(&spec(layout, 2_500)).unwrap();
            let n = a.node_count() as f64;
            let lon = a.nodes().iter().map(|v| v.pos.lon).sum::<f64>() / n;
            let lat = a.nodes().iter().map(|v| v.pos.lat).sum::<f64>() / n;
            assert!((lon - CENTRE.lon).abs() < 0.05 && (lat - CENTRE.lat).abs() < 0.05);
        }
    }

    #[test]
    fn nonsense_is_refused() {
        let bad = |s: SyntheticSpec| match synthetic(&s) {
            Err(ScenarioError::BadSpec(m)) => m,
            other => panic!("{s:?}: {other:?}"),
        };
        let base = SyntheticSpec::default();
        for nodes in [0, 1, MAX_NODES + 1] {
            assert!(
                bad(SyntheticSpec {
                    nodes,
                    ..base.clone()
                })
                .contains("nodes")
            );
        }
        for spacing_m in [0.0, -5.0, 0.5, f64::NAN, f64::INFINITY] {
            let m = bad(SyntheticSpec {
                spacing_m,
                ..base.clone()
            });
            assert!(m.contains("spacing"), "{m}");
        }
        for station_share in [0.0, -0.1, 1.01, f64::NAN] {
            let m = bad(SyntheticSpec {
                station_share,
                ..base.clone()
            });
            assert!(m.contains("station share"), "{m}");
        }
        let m = bad(SyntheticSpec {
            spacing_m: 100_000.0,
            nodes: 10_000,
            ..base.clone()
        });
        assert!(m.contains("more than the 2000 km allowed"), "{m}");
        let m = ScenarioError::BadSpec("x".into()).to_string();
        assert_eq!(m, "invalid synthetic airspace: x");
    }
}
