//! Small random instances with data in whole time units (usually seconds), their proptest
//! strategies, and (in [`judge`]) a driver that plans them with the planner and checks every
//! answer against the oracle and the verifier (tests only). Battery swaps and multi-leg
//! answers, and the watchdog on planner calls, are in [`multileg`].

use muse_airspace::closures::{Closures, resolve};
use muse_model::request::sort_for_planning;
use muse_model::testing::{airspace, named_edge, node, request};
use muse_model::{
    Airspace, BatterySwap, Edge, EdgeId, EdgeKind, EdgeRule, FlightParams, HeadingRule, Instant,
    Layers, Metres, Millis, Node, NodeId, NodeKind, Period, Request, Speed, VerticalLimit,
    VerticalLimits, VerticalReference, Zone,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRunner};

use crate::oracle::RawClosures;
use multileg::SwapSpec;

pub mod announce;
mod judge;
pub mod multileg;

use judge::describe;
pub use judge::{check_valid, run, run_online};

/// 36 km/h = 10 m/s = 1 cm/ms: an edge of `k` cm takes exactly `k` ms.
pub fn speed() -> Speed {
    Speed::from_kmh(36.0).unwrap()
}

/// A zone closing explicit elements during `[start, start + len)` units.
#[derive(Clone, Debug)]
pub struct ZoneSpec {
    /// Node selectors (taken modulo the node count).
    pub nodes: Vec<usize>,
    /// Edge selectors (taken modulo the edge count).
    pub edges: Vec<usize>,
    /// Start, units.
    pub start: i64,
    /// Length, units (> 0).
    pub len: i64,
}

/// A test instance. Every time is a whole number of units of `unit` ms; selectors are reduced
/// modulo the number of candidates, so that shrinking never produces an invalid instance.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The time unit, ms (1000: whole seconds).
    pub unit: i64,
    /// Node `i` is a waypoint when `waypoint[i]` (the first and the last node are always
    /// stations).
    pub waypoint: Vec<bool>,
    /// For node `i >= 1`: a tree edge to node `parent % i` taking `secs` units, or none
    /// (then the graph may be disconnected).
    pub tree: Vec<Option<(usize, u32)>>,
    /// Extra edges `(a, b, secs)` (self-loops and repeats are dropped).
    pub extra: Vec<(usize, usize, u32)>,
    /// Node separation `tau`, units.
    pub tau: u32,
    /// `None`: exclusive edges; `Some(h)`: headway `h` units.
    pub headway: Option<u32>,
    /// `G_max`, units.
    pub g_max: u32,
    /// `T_max`, units.
    pub t_max: u32,
    /// Requests `(origin selector, destination selector, departure in units)`; origin and
    /// destination are stations.
    pub requests: Vec<(usize, usize, i64)>,
    /// Zones.
    pub zones: Vec<ZoneSpec>,
    /// Battery swaps at stations (docs/reference.md#multi-leg-trips), or none: single legs only.
    pub swap: Option<SwapSpec>,
    /// Layers (docs/reference.md#layered-airspace), or none: the flat airspace.
    pub layers: Option<LayerSpec>,
}

/// The layers of a layered instance: vertical links take whole units too.
#[derive(Clone, Debug)]
pub struct LayerSpec {
    /// Number of layers.
    pub count: u32,
    /// Time to cross a vertical link, units (> 0).
    pub climb: u32,
    /// The `sectors` heading rule, or none.
    pub sectors: bool,
    /// Per zone (cycled; empty: every zone the whole sky): the layers `(lo, hi)` its band
    /// covers, or `None` for the whole sky.
    pub bands: Vec<Option<(u32, u32)>>,
}

impl LayerSpec {
    /// The layering: layer 1 at 60 m, climbing at 1 m/s over `climb` units of spacing.
    pub fn layers(&self, unit: i64) -> Layers {
        Layers {
            count: self.count,
            base: Metres::from_mm(60_000),
            spacing: Metres::from_mm(i64::from(self.climb) * unit),
            climb_mm_per_s: 1_000,
            heading_rule: if self.sectors {
                HeadingRule::Sectors
            } else {
                HeadingRule::None
            },
        }
    }

    /// The vertical band of zone `k`.
    fn band(&self, k: usize, layers: &Layers) -> VerticalLimits {
        let Some(&Some((lo, hi))) = self.bands.get(k % self.bands.len().max(1)) else {
            return VerticalLimits::WHOLE_SKY;
        };
        let at = |layer: u32| {
            Some(VerticalLimit {
                height: layers.altitude(layer),
                reference: VerticalReference::default(),
            })
        };
        VerticalLimits {
            lower: at(lo.min(hi)),
            upper: at(lo.max(hi)),
        }
    }
}

/// An instance turned into model types.
pub struct Built {
    /// The airspace.
    pub airspace: Airspace,
    /// The parameters.
    pub params: FlightParams,
    /// Closures as the planner and the verifier see them (`muse_airspace::closures::resolve`).
    pub closures: Closures,
    /// Closures as the oracle sees them (straight from the zone specs).
    pub raw: RawClosures,
    /// Requests in planning order.
    pub requests: Vec<Request>,
}

impl Instance {
    /// Builds the model types.
    pub fn build(&self) -> Built {
        let n = self.waypoint.len();
        let nodes: Vec<Node> = (0..n)
            .map(|i| {
                let kind = if i > 0 && i + 1 < n && self.waypoint[i] {
                    NodeKind::Waypoint
                } else {
                    NodeKind::Station
                };
                let (lon, lat) = (103.8 + 0.01 * i as f64, 1.3 + 0.003 * (i % 3) as f64);
                node(&format!("N{i}"), kind, lon, lat)
            })
            .collect();
        let flat = airspace(nodes, self.edges(n));
        let airspace = match &self.layers {
            None => flat,
            Some(l) => flat
                .layered(&l.layers(self.unit))
                .expect("layered ids are free"),
        };
        let units = |k: u32| Millis(i64::from(k) * self.unit);
        let params = FlightParams {
            speed: speed(),
            max_flight: units(self.t_max),
            node_separation: units(self.tau),
            edge_rule: self
                .headway
                .map_or(EdgeRule::Exclusive, |h| EdgeRule::Headway(units(h))),
            max_ground_delay: units(self.g_max),
            battery_swap: self.swap.map(|s| BatterySwap {
                time: units(s.time),
                max_legs: s.max_legs,
            }),
            max_trip: None,
            separation: muse_model::Separation::OFF,
        };
        let (zones, raw) = self.zones(&airspace);
        let closures =
            resolve(&airspace, &zones, Instant(0), Instant(86_400_000)).expect("zones resolve");
        let stations: Vec<NodeId> = airspace.stations().collect();
        let mut requests: Vec<Request> = self
            .requests
            .iter()
            .enumerate()
            .map(|(i, &(o, d, dep))| {
                let origin = stations[o % stations.len()];
                let mut destination = stations[d % stations.len()];
                if destination == origin {
                    destination = stations[(d + 1) % stations.len()];
                }
                request(
                    &format!("r{i:02}"),
                    origin.0,
                    destination.0,
                    dep * self.unit,
                )
            })
            .collect();
        sort_for_planning(&mut requests);
        Built {
            airspace,
            params,
            closures,
            raw,
            requests,
        }
    }

    /// Edges: the tree edges, then the extra ones (no self-loops, no repeats).
    fn edges(&self, n: usize) -> Vec<Edge> {
        let mut pairs: Vec<(usize, usize, u32)> = Vec::new();
        let mut add = |a: usize, b: usize, secs: u32| {
            let (a, b) = (a.min(b), a.max(b));
            if a != b && !pairs.iter().any(|p| (p.0, p.1) == (a, b)) {
                pairs.push((a, b, secs));
            }
        };
        for (i, t) in self.tree.iter().enumerate().take(n).skip(1) {
            if let Some((parent, secs)) = *t {
                add(parent % i, i, secs);
            }
        }
        for &(a, b, secs) in &self.extra {
            add(a % n, b % n, secs);
        }
        pairs
            .iter()
            .map(|&(a, b, secs)| {
                let length_m = (i64::from(secs) * self.unit) as f64 / 100.0;
                named_edge(&format!("N{a}-N{b}"), a as u32, b as u32, length_m)
            })
            .collect()
    }

    /// Zones as `muse_model` zones, and their windows per element for the oracle (on a
    /// layered airspace, straight from docs/reference.md#layered-airspace: the copies of a listed
    /// node or corridor at the layers in the zone's band, and the vertical links at a listed node
    /// whose span meets the band).
    fn zones(&self, airspace: &Airspace) -> (Vec<Zone>, RawClosures) {
        let flat = airspace.flat();
        let n = flat.node_count();
        let mut raw = RawClosures {
            nodes: vec![Vec::new(); airspace.node_count()],
            edges: vec![Vec::new(); airspace.edge_count()],
        };
        let layers = self.layers.as_ref().map(|l| (l, l.layers(self.unit)));
        let count = layers.as_ref().map_or(1, |(_, l)| l.count);
        let mut zones = Vec::new();
        for (k, z) in self.zones.iter().enumerate() {
            let window = (z.start * self.unit, (z.start + z.len) * self.unit);
            let vertical = layers
                .as_ref()
                .map_or(VerticalLimits::WHOLE_SKY, |(spec, l)| spec.band(k, l));
            let height = |layer: u32| layers.as_ref().map(|(_, l)| l.altitude(layer));
            let in_band = |layer: u32| height(layer).is_none_or(|h| vertical.contains(h));
            let mut zone = Zone {
                id: format!("Z{k}"),
                name: String::new(),
                restriction: "PROHIBITED".into(),
                area: None,
                node_ids: Vec::new(),
                edge_ids: Vec::new(),
                announced: None,
                withdrawn: None,
                vertical,
                periods: vec![Period {
                    start: Some(Instant(window.0)),
                    end: Some(Instant(window.1)),
                    daily: vec![],
                }],
            };
            for &s in &z.nodes {
                let v = NodeId((s % n) as u32);
                zone.node_ids.push(format!("N{}", v.0));
                for layer in (1..=count).filter(|&l| in_band(l)) {
                    let copy = airspace.at_layer(v, layer).expect("a layer");
                    raw.nodes[copy.index()].push(window);
                }
                for layer in 1..count {
                    let (lo, hi) = (height(layer), height(layer + 1));
                    if let (Some(lo), Some(hi)) = (lo, hi)
                        && vertical.meets(lo, hi)
                    {
                        let below = airspace.at_layer(v, layer).expect("a layer");
                        let above = airspace.at_layer(v, layer + 1).expect("a layer");
                        let link = airspace.edge_between(below, above).expect("a link");
                        raw.edges[link.index()].push(window);
                    }
                }
            }
            if flat.edge_count() > 0 {
                for &s in &z.edges {
                    let e = EdgeId((s % flat.edge_count()) as u32);
                    zone.edge_ids.push(flat.edge(e).id.clone());
                    for copy in 0..airspace.edge_count() {
                        let copy = EdgeId(copy as u32);
                        let layer = match airspace.edge_kind(copy) {
                            EdgeKind::Corridor { layer, .. } => layer,
                            EdgeKind::Vertical { .. } => continue,
                        };
                        if airspace.flat_edge(copy) == Some(e) && in_band(layer) {
                            raw.edges[copy.index()].push(window);
                        }
                    }
                }
            }
            zones.push(zone);
        }
        (zones, raw)
    }
}

/// A deterministic proptest runner: `cases` cases from a fixed `ChaCha` seed, no failure
/// persistence files.
///
/// For soak runs (never in CI), `MUSE_SOAK=k` runs `k` times as many cases and
/// `MUSE_SOAK_SEED=n` mixes `n` into the seed, e.g.
/// `MUSE_SOAK=50 MUSE_SOAK_SEED=7 cargo test -p muse-planner --test against_oracle`.
pub fn runner(cases: u32, seed: u64) -> TestRunner {
    let env = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<u64>().ok());
    let scale = env("MUSE_SOAK").unwrap_or(1).max(1);
    let seed = seed
        ^ env("MUSE_SOAK_SEED")
            .unwrap_or(0)
            .wrapping_mul(0x9e37_79b9_7f4a_7c15);
    TestRunner::new(Config {
        cases: u32::try_from(u64::from(cases) * scale).unwrap_or(u32::MAX),
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        max_shrink_iters: 4_096,
        ..Config::default()
    })
}

/// Knobs for the instance strategy.
#[derive(Clone, Copy, Debug)]
pub struct Shape {
    /// Node count range (inclusive).
    pub nodes: (usize, usize),
    /// Edge traversal range, units (inclusive).
    pub edge_secs: (u32, u32),
    /// Request count range (inclusive).
    pub requests: (usize, usize),
    /// Latest requested departure, units.
    pub horizon: i64,
    /// `T_max` range, units (inclusive).
    pub t_max: (u32, u32),
    /// Largest `G_max`, units (`G_max` is zero half of the time).
    pub g_max: u32,
    /// `tau` range, units (inclusive).
    pub tau: (u32, u32),
    /// Largest number of zones.
    pub zones: usize,
}

impl Shape {
    /// A general mix.
    pub const MIXED: Shape = Shape {
        nodes: (3, 7),
        edge_secs: (1, 25),
        requests: (5, 25),
        horizon: 120,
        t_max: (10, 150),
        g_max: 40,
        tau: (1, 6),
        zones: 3,
    };

    /// Few nodes, many requests in a short time: heavy conflicts.
    pub const CROWDED: Shape = Shape {
        nodes: (3, 5),
        edge_secs: (1, 12),
        requests: (12, 25),
        horizon: 40,
        t_max: (15, 90),
        g_max: 30,
        tau: (1, 4),
        zones: 2,
    };

    /// Bigger graphs, long batteries and ground delays, long waits.
    pub const LONG: Shape = Shape {
        nodes: (5, 7),
        edge_secs: (3, 30),
        requests: (15, 25),
        horizon: 150,
        t_max: (60, 300),
        g_max: 120,
        tau: (1, 10),
        zones: 3,
    };

    /// `tau = 0`: stays of different flights may touch.
    pub const TAU_ZERO: Shape = Shape {
        nodes: (3, 6),
        edge_secs: (1, 15),
        requests: (8, 25),
        horizon: 60,
        t_max: (15, 120),
        g_max: 30,
        tau: (0, 0),
        zones: 2,
    };
}

/// Instances of the given shape.
pub fn instances(shape: Shape) -> impl Strategy<Value = Instance> {
    let nodes = shape.nodes.0..=shape.nodes.1;
    let secs = shape.edge_secs.0..=shape.edge_secs.1;
    nodes
        .prop_flat_map(move |n| {
            let secs = secs.clone();
            let tree_edge = prop_oneof![1 => Just(None), 9 => (0..n, secs.clone()).prop_map(Some)];
            (
                proptest::collection::vec(prop::bool::weighted(0.3), n),
                proptest::collection::vec(tree_edge, n),
                proptest::collection::vec((0..n, 0..n, secs), 0..=n),
            )
        })
        .prop_flat_map(move |(waypoint, tree, extra)| {
            // Mostly whole seconds; sometimes other units, down to the millisecond.
            let unit = prop_oneof![3 => Just(1000i64), 1 => prop::sample::select(vec![1i64, 2, 7, 37, 250])];
            let tau = shape.tau.0..=shape.tau.1;
            let headway = prop_oneof![1 => Just(None), 1 => (0..=4u32).prop_map(Some)];
            let g_max = prop_oneof![1 => Just(0u32), 1 => 1..=shape.g_max];
            let t_max = shape.t_max.0..=shape.t_max.1;
            let request = (0..8usize, 0..8usize, 0..=shape.horizon);
            let requests = proptest::collection::vec(request, shape.requests.0..=shape.requests.1);
            let zone = (
                proptest::collection::vec(0..8usize, 0..=2),
                proptest::collection::vec(0..16usize, 0..=2),
                0..=shape.horizon + 60,
                prop_oneof![4 => 1..=60i64, 1 => 60..=400i64],
            )
                .prop_map(|(nodes, edges, start, len)| ZoneSpec { nodes, edges, start, len });
            let zones = proptest::collection::vec(zone, 0..=shape.zones);
            (unit, Just(waypoint), Just(tree), Just(extra), tau, headway, g_max, t_max, requests, zones)
        })
        .prop_map(|(unit, waypoint, tree, extra, tau, headway, g_max, t_max, requests, zones)| Instance {
            unit,
            waypoint,
            tree,
            extra,
            tau,
            headway,
            g_max,
            t_max,
            requests,
            zones,
            swap: None,
            layers: None,
        })
}

/// The instances of `base` made layered: 2 to 4 layers, vertical links of 1 to 3 units, with
/// or without the heading rule, zones with or without a band.
pub fn layered(base: impl Strategy<Value = Instance>) -> impl Strategy<Value = Instance> {
    let band = prop_oneof![1 => Just(None), 2 => (1..=4u32, 1..=4u32).prop_map(Some)];
    let spec = (
        2..=4u32,
        1..=3u32,
        any::<bool>(),
        proptest::collection::vec(band, 1..=3),
    )
        .prop_map(|(count, climb, sectors, bands)| LayerSpec {
            count,
            climb,
            sectors,
            bands,
        });
    (base, spec).prop_map(|(mut instance, spec)| {
        instance.layers = Some(spec);
        instance
    })
}

/// Runs `cases` instances of `strategy` (deterministic runner, [`runner`]) through `run`,
/// adding up their tallies; panics with the seed and the minimal failing instance.
pub fn check_property(
    run: fn(&Instance) -> Result<Tally, String>,
    strategy: impl Strategy<Value = Instance>,
    path: &str,
    cases: u32,
    seed: u64,
) -> Tally {
    let total = std::cell::Cell::new(Tally::default());
    let result = runner(cases, seed).run(&strategy, |instance| {
        let tally = run(&instance).map_err(proptest::test_runner::TestCaseError::fail)?;
        let mut t = total.get();
        t.add(&tally);
        total.set(t);
        Ok(())
    });
    if let Err(e) = result {
        panic!("seed {seed:#x}: {e}");
    }
    let t = total.get();
    println!("{path} (seed {seed:#x}): {t:?}");
    t
}

/// Counts of what happened, to check that the generator exercises every case.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tally {
    /// Accepted requests.
    pub planned: usize,
    /// Accepted with ground delay.
    pub ground_delayed: usize,
    /// Accepted with airborne time above free flow.
    pub air_delayed: usize,
    /// Accepted with a take-off off whole units.
    pub off_grid: usize,
    /// Rejections: out of range, unreachable, no feasible plan.
    pub rejected: [usize; 3],
    /// Online runs: requests whose departure was before the clock's now.
    pub in_past: usize,
    /// Online runs: flights cancelled before take-off.
    pub cancelled: usize,
    /// Online runs: cancellations refused after take-off.
    pub cancel_refused: usize,
    /// Battery swaps on: accepted trips by number of legs (1, 2, 3, 4 or more).
    pub legs: [usize; 4],
    /// Battery swaps on: rejections (out of range, unreachable, no feasible plan).
    pub swap_rejected: [usize; 3],
    /// Battery swaps on: accepted trips that stay on the ground longer than `S` at a swap.
    pub long_swaps: usize,
}

impl Tally {
    /// Adds another tally.
    pub fn add(&mut self, o: &Tally) {
        self.planned += o.planned;
        self.ground_delayed += o.ground_delayed;
        self.air_delayed += o.air_delayed;
        self.off_grid += o.off_grid;
        for (a, b) in self.rejected.iter_mut().zip(o.rejected) {
            *a += b;
        }
        self.in_past += o.in_past;
        self.cancelled += o.cancelled;
        self.cancel_refused += o.cancel_refused;
        for (a, b) in self.legs.iter_mut().zip(o.legs) {
            *a += b;
        }
        for (a, b) in self.swap_rejected.iter_mut().zip(o.swap_rejected) {
            *a += b;
        }
        self.long_swaps += o.long_swaps;
    }
}
