//! Zone resolution (SPEC §4): zones and a time range → each node's and edge's closure windows.
//!
//! # Which elements a zone closes
//!
//! - Every node inside the zone's area, boundary included, and every edge whose straight
//!   segment intersects the area (touching counts).
//! - Polygons: the test is `geo`'s `Intersects` on longitude/latitude coordinates, the edge
//!   taken as a straight segment in longitude/latitude. At city scale the difference from the
//!   geodesic is far below a metre.
//! - Circles: a node is inside when its geodesic (WGS84) distance to the centre is at most the
//!   radius. An edge is closed when an end node is inside or when the point of its segment
//!   closest to the centre is within the radius, measured in a local metric plane around the
//!   centre (longitude and latitude scaled by the WGS84 radii of curvature at the centre's
//!   latitude). Good at city scale (radii of a few tens of kilometres); longitudes are taken
//!   modulo 360° around the centre.
//! - Explicit ids (`Zone::node_ids`, `Zone::edge_ids`) close those elements; an edge may be
//!   named by its id or as `FROM-TO` with its end nodes' ids in either order. An id not in the
//!   airspace is an error naming the zone and the id.
//!
//! # When
//!
//! Each period of a zone becomes windows inside `[from, to)`: a period with daily windows
//! gives, for every local date (in the daily window's offset) whose window can touch the
//! range, on the listed weekdays (the weekday of the date the window starts), the window
//! clipped to the period's `[start, end)`; a period without daily windows closes its own
//! `[start, end)` (unbounded sides clipped to `[from, to)`); a permanent zone closes all of
//! `[from, to)`. Per element, windows of all zones are sorted and overlapping or touching
//! ones merged.
//!
//! A [`Window`] is half-open, `[start, end)`. A stay `[a, d]` at a closed node (or a
//! traversal `[s, f]` of a closed edge) may not share an instant with it: it is allowed only
//! when `d < start` or `a >= end` ([`Window::blocks`]).

use std::f64::consts::PI;

use geo::{BoundingRect, Intersects};
use geo_types::{Line, MultiPolygon, Point};
use muse_model::{
    Airspace, DailyWindow, EdgeId, Instant, LonLat, Millis, NodeId, Period, Weekday, Zone, ZoneArea,
};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

const DAY_MS: i64 = 86_400_000;

/// The longest range [`resolve`] expands, in days (about 100 years).
pub const MAX_RANGE_DAYS: i64 = 36_525;

/// A half-open closure window `[start, end)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Window {
    /// First closed instant.
    pub start: Instant,
    /// First instant after the closure.
    pub end: Instant,
}

impl Window {
    /// The window `[start, end)`.
    pub const fn new(start: Instant, end: Instant) -> Self {
        Window { start, end }
    }

    /// Whether the window contains no instant (`end <= start`).
    pub fn is_empty(self) -> bool {
        self.end <= self.start
    }

    /// Whether instant `t` is closed.
    pub fn contains(self, t: Instant) -> bool {
        self.start <= t && t < self.end
    }

    /// Whether an occupation `[a, d]` (a stay, or an edge traversal `[s, f]`) shares an instant
    /// with the window. It is allowed only when `d < start` or `a >= end` (SPEC §4).
    ///
    /// ```
    /// use muse_airspace::closures::Window;
    /// use muse_model::Instant;
    /// let w = Window::new(Instant(100), Instant(200));
    /// assert!(w.blocks(Instant(50), Instant(100)), "arriving at the start is too late");
    /// assert!(!w.blocks(Instant(50), Instant(99)));
    /// assert!(!w.blocks(Instant(200), Instant(300)), "the end is open");
    /// ```
    pub fn blocks(self, a: Instant, d: Instant) -> bool {
        d >= self.start && a < self.end
    }
}

/// Closure windows of every node and edge of an airspace: per element, sorted, disjoint and
/// not touching (merged).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Closures {
    nodes: Vec<Vec<Window>>,
    edges: Vec<Vec<Window>>,
}

impl Closures {
    /// No closures, for an airspace's nodes and edges.
    pub fn none(airspace: &Airspace) -> Self {
        Closures {
            nodes: vec![Vec::new(); airspace.node_count()],
            edges: vec![Vec::new(); airspace.edge_count()],
        }
    }

    /// The windows of node `n` (empty for an unknown index).
    pub fn node(&self, n: NodeId) -> &[Window] {
        self.nodes.get(n.index()).map_or(&[], Vec::as_slice)
    }

    /// The windows of edge `e` (empty for an unknown index).
    pub fn edge(&self, e: EdgeId) -> &[Window] {
        self.edges.get(e.index()).map_or(&[], Vec::as_slice)
    }

    /// Whether no element has any window.
    pub fn is_empty(&self) -> bool {
        self.nodes.iter().chain(&self.edges).all(Vec::is_empty)
    }

    /// How many nodes have at least one window.
    pub fn closed_node_count(&self) -> usize {
        self.nodes.iter().filter(|w| !w.is_empty()).count()
    }

    /// How many edges have at least one window.
    pub fn closed_edge_count(&self) -> usize {
        self.edges.iter().filter(|w| !w.is_empty()).count()
    }

    /// How many windows there are in all, nodes and edges.
    pub fn window_count(&self) -> usize {
        self.nodes.iter().chain(&self.edges).map(Vec::len).sum()
    }

    /// The first window of node `n` that a stay `[a, d]` would share an instant with.
    ///
    /// ```
    /// # use muse_airspace::closures::{Closures, Window};
    /// # use muse_model::{Instant, NodeId};
    /// # fn demo(c: &Closures) {
    /// if let Some(w) = c.node_conflict(NodeId(0), Instant(0), Instant(1_000)) {
    ///     println!("closed from {:?} to {:?}", w.start, w.end);
    /// }
    /// # }
    /// ```
    pub fn node_conflict(&self, n: NodeId, a: Instant, d: Instant) -> Option<Window> {
        first_conflict(self.node(n), a, d)
    }

    /// The first window of edge `e` that a traversal `[s, f]` would share an instant with.
    pub fn edge_conflict(&self, e: EdgeId, s: Instant, f: Instant) -> Option<Window> {
        first_conflict(self.edge(e), s, f)
    }

    /// Nodes with their windows, closed nodes only, in index order.
    pub fn closed_nodes(&self) -> impl Iterator<Item = (NodeId, &[Window])> + '_ {
        self.nodes
            .iter()
            .enumerate()
            .filter(|(_, w)| !w.is_empty())
            .map(|(i, w)| (NodeId(i as u32), w.as_slice()))
    }

    /// Edges with their windows, closed edges only, in index order.
    pub fn closed_edges(&self) -> impl Iterator<Item = (EdgeId, &[Window])> + '_ {
        self.edges
            .iter()
            .enumerate()
            .filter(|(_, w)| !w.is_empty())
            .map(|(i, w)| (EdgeId(i as u32), w.as_slice()))
    }
}

fn first_conflict(windows: &[Window], a: Instant, d: Instant) -> Option<Window> {
    // Windows are sorted and disjoint, so their ends increase too.
    let i = windows.partition_point(|w| w.end <= a);
    windows.get(i).filter(|w| w.start <= d).copied()
}

/// Why zones cannot be resolved against an airspace.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClosureError {
    /// A zone lists a node id that is not in the airspace.
    #[error("zone `{zone}` closes node `{id}`, which is not in the airspace")]
    UnknownNode {
        /// The zone's id.
        zone: String,
        /// The node id.
        id: String,
    },
    /// A zone lists an edge id that is not in the airspace.
    #[error(
        "zone `{zone}` closes edge `{id}`, which is not in the airspace (name an edge by its id \
         or as FROM-TO)"
    )]
    UnknownEdge {
        /// The zone's id.
        zone: String,
        /// The edge id.
        id: String,
    },
    /// An edge id that is not an edge's id matches several `FROM-TO` readings.
    #[error(
        "zone `{zone}`: edge `{id}` is ambiguous: it can be read as FROM-TO in more than one way"
    )]
    AmbiguousEdge {
        /// The zone's id.
        zone: String,
        /// The edge id.
        id: String,
    },
    /// A zone's area is not usable (invalid coordinates, negative radius, …).
    #[error("zone `{zone}` has an invalid area: {reason}")]
    BadArea {
        /// The zone's id.
        zone: String,
        /// What is wrong.
        reason: String,
    },
    /// A zone's daily window is not usable.
    #[error("zone `{zone}` has an invalid daily schedule: {reason}")]
    BadSchedule {
        /// The zone's id.
        zone: String,
        /// What is wrong.
        reason: String,
    },
    /// The time range to resolve is not usable.
    #[error("cannot resolve zones over [{from} ms, {to} ms): {reason}")]
    BadRange {
        /// Start of the range, ms since the epoch.
        from: i64,
        /// End of the range, ms since the epoch.
        to: i64,
        /// What is wrong.
        reason: String,
    },
}

/// The nodes and edges a zone closes (area rule and explicit ids), each sorted by index and
/// without repeats. Time is not considered.
///
/// ```
/// use geo_types::polygon;
/// use muse_airspace::closures::closed_elements;
/// use muse_model::{Airspace, Edge, LonLat, Node, NodeId, NodeKind, Zone, ZoneArea};
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
///     node_ids: vec![], edge_ids: vec![], periods: vec![], announced: None,
/// };
/// let (nodes, edges) = closed_elements(&airspace, &zone).unwrap();
/// assert!(nodes.is_empty());
/// assert_eq!(edges.len(), 1);
/// ```
pub fn closed_elements(
    airspace: &Airspace,
    zone: &Zone,
) -> Result<(Vec<NodeId>, Vec<EdgeId>), ClosureError> {
    closed_with(airspace, zone, None)
}

/// Resolves zones over `[from, to)` into per-element closure windows.
///
/// Errors: an explicit node or edge id not in the airspace, an invalid area or schedule, or a
/// range that ends before it starts, lies outside the years 1000–9000 or is longer than
/// [`MAX_RANGE_DAYS`].
///
/// ```
/// use muse_airspace::closures::resolve;
/// use muse_model::{
///     Airspace, DailyWindow, Instant, LonLat, Millis, Node, NodeId, NodeKind, Period, UtcOffset,
///     Weekday, Zone,
/// };
/// let airspace = Airspace::new(
///     vec![Node { id: "S001".into(), kind: NodeKind::Station, name: String::new(),
///                 pos: LonLat::new(103.85, 1.29) }],
///     vec![],
/// ).unwrap();
/// let zone = Zone {
///     id: "CBD".into(), name: String::new(), restriction: "PROHIBITED".into(), area: None,
///     node_ids: vec!["S001".into()], edge_ids: vec![], announced: None,
///     periods: vec![Period { start: None, end: None, daily: vec![DailyWindow {
///         days: Weekday::ALL.to_vec(), start: Millis::from_secs(10 * 3600),
///         end: Millis::from_secs(12 * 3600), offset: UtcOffset::SINGAPORE,
///     }] }],
/// };
/// let day = |t: &str| Instant::parse_rfc3339(t).unwrap();
/// let c = resolve(&airspace, &[zone], day("2026-01-05T00:00:00+08:00"),
///                 day("2026-01-06T00:00:00+08:00")).unwrap();
/// assert_eq!(c.node(NodeId(0)).len(), 1);
/// assert_eq!(c.node(NodeId(0))[0].start, day("2026-01-05T02:00:00Z"));
/// ```
pub fn resolve(
    airspace: &Airspace,
    zones: &[Zone],
    from: Instant,
    to: Instant,
) -> Result<Closures, ClosureError> {
    check_range(from, to)?;
    let index = zones
        .iter()
        .any(|z| z.area.is_some())
        .then(|| Index::new(airspace));
    let mut closures = Closures::none(airspace);
    for zone in zones {
        let (nodes, edges) = closed_with(airspace, zone, index.as_ref())?;
        let windows = zone_windows(zone, from, to)?;
        if windows.is_empty() {
            continue;
        }
        for n in nodes {
            closures.nodes[n.index()].extend_from_slice(&windows);
        }
        for e in edges {
            closures.edges[e.index()].extend_from_slice(&windows);
        }
    }
    for list in closures.nodes.iter_mut().chain(closures.edges.iter_mut()) {
        merge(list);
    }
    Ok(closures)
}

/// The windows during which a zone is closed within `[from, to)`, sorted and merged.
///
/// ```
/// use muse_airspace::closures::zone_windows;
/// use muse_model::{Instant, Period, Zone};
/// let t = |s: &str| Instant::parse_rfc3339(s).unwrap();
/// let zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: String::new(), area: None,
///     node_ids: vec![], edge_ids: vec![], announced: None,
///     periods: vec![Period { start: Some(t("2026-01-05T09:00:00Z")), end: None, daily: vec![] }],
/// };
/// let w = zone_windows(&zone, t("2026-01-05T00:00:00Z"), t("2026-01-06T00:00:00Z")).unwrap();
/// assert_eq!((w[0].start, w[0].end), (t("2026-01-05T09:00:00Z"), t("2026-01-06T00:00:00Z")));
/// ```
pub fn zone_windows(zone: &Zone, from: Instant, to: Instant) -> Result<Vec<Window>, ClosureError> {
    check_range(from, to)?;
    let mut out = Vec::new();
    if from == to {
        return Ok(out);
    }
    if zone.is_permanent() {
        out.push(Window::new(from, to));
        return Ok(out);
    }
    for period in &zone.periods {
        period_windows(zone, period, from, to, &mut out)?;
    }
    merge(&mut out);
    Ok(out)
}

fn check_range(from: Instant, to: Instant) -> Result<(), ClosureError> {
    let bad = |reason: &str| ClosureError::BadRange {
        from: from.0,
        to: to.0,
        reason: reason.into(),
    };
    let lo = Instant::at_local(
        jiff::civil::date(1000, 1, 1),
        Millis::ZERO,
        muse_model::UtcOffset(0),
    );
    let hi = Instant::at_local(
        jiff::civil::date(9000, 1, 1),
        Millis::ZERO,
        muse_model::UtcOffset(0),
    );
    if to < from {
        return Err(bad("the end is before the start"));
    }
    if from < lo || to > hi {
        return Err(bad("outside the supported years 1000-9000"));
    }
    if (to - from).0 > MAX_RANGE_DAYS * DAY_MS {
        return Err(bad(&format!("longer than {MAX_RANGE_DAYS} days")));
    }
    Ok(())
}

fn period_windows(
    zone: &Zone,
    p: &Period,
    from: Instant,
    to: Instant,
    out: &mut Vec<Window>,
) -> Result<(), ClosureError> {
    let lo = p.start.map_or(from, |s| s.max(from));
    let hi = p.end.map_or(to, |e| e.min(to));
    if lo >= hi {
        return Ok(());
    }
    if p.daily.is_empty() {
        out.push(Window::new(lo, hi));
        return Ok(());
    }
    for dw in &p.daily {
        check_daily(zone, dw)?;
        // A window starting the day before `lo` (local) may run past midnight into the range.
        let mut date = lo
            .local_date(dw.offset)
            .yesterday()
            .unwrap_or(lo.local_date(dw.offset));
        let last = (hi - Millis(1)).local_date(dw.offset);
        while date <= last {
            if dw.days.contains(&Weekday::of(date)) {
                let start = Instant::at_local(date, dw.start, dw.offset);
                let mut end = Instant::at_local(date, dw.end, dw.offset);
                if dw.end <= dw.start {
                    end += Millis(DAY_MS);
                }
                let w = Window::new(start.max(lo), end.min(hi));
                if !w.is_empty() {
                    out.push(w);
                }
            }
            let Ok(next) = date.tomorrow() else { break };
            date = next;
        }
    }
    Ok(())
}

fn check_daily(zone: &Zone, dw: &DailyWindow) -> Result<(), ClosureError> {
    let bad = |reason: String| ClosureError::BadSchedule {
        zone: zone.id.clone(),
        reason,
    };
    if !(0..DAY_MS).contains(&dw.start.0) {
        return Err(bad(format!(
            "start {} ms is not a time of day in [00:00, 24:00)",
            dw.start.0
        )));
    }
    if !(0..=DAY_MS).contains(&dw.end.0) {
        return Err(bad(format!(
            "end {} ms is not a time of day in [00:00, 24:00]",
            dw.end.0
        )));
    }
    if dw.offset.0.abs() > 18 * 3_600 {
        return Err(bad(format!("offset {} s is beyond ±18 h", dw.offset.0)));
    }
    Ok(())
}

/// Sorts windows and merges overlapping or touching ones; drops empty ones.
fn merge(list: &mut Vec<Window>) {
    list.retain(|w| !w.is_empty());
    if list.len() < 2 {
        return;
    }
    list.sort_unstable();
    let mut merged: Vec<Window> = Vec::with_capacity(list.len());
    for w in list.drain(..) {
        match merged.last_mut() {
            Some(last) if w.start <= last.end => last.end = last.end.max(w.end),
            _ => merged.push(w),
        }
    }
    *list = merged;
}

// ---------------------------------------------------------------------------------------------
// Geometry.
// ---------------------------------------------------------------------------------------------

/// `[min_lon, min_lat, max_lon, max_lat]`.
type Envelope = [f64; 4];

/// A zone's area, checked and ready for point and segment tests.
enum Shape<'z> {
    Polygons(&'z MultiPolygon<f64>),
    Circle {
        centre: LonLat,
        radius_m: f64,
        plane: LocalPlane,
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
                    plane: LocalPlane::at(*centre),
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
                // Beyond city scale, or near the poles or the antimeridian: no envelope (scan).
                if *radius_m > 100_000.0 || plane.kx < 1_000.0 {
                    return None;
                }
                let dlon = radius_m * 1.01 / plane.kx + MARGIN_DEG;
                let dlat = radius_m * 1.01 / plane.ky + MARGIN_DEG;
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
                self.contains(a) || self.contains(b) || plane.distance_to_segment(a, b) <= *radius_m
            }
        }
    }
}

/// A local metric plane around an origin: metres east and north.
struct LocalPlane {
    origin: LonLat,
    /// Metres per degree of longitude at the origin.
    kx: f64,
    /// Metres per degree of latitude at the origin.
    ky: f64,
}

impl LocalPlane {
    fn at(origin: LonLat) -> Self {
        const A: f64 = 6_378_137.0;
        const F: f64 = 1.0 / 298.257_223_563;
        let e2 = F * (2.0 - F);
        let phi = origin.lat.to_radians();
        let w = (1.0 - e2 * phi.sin() * phi.sin()).sqrt();
        let n = A / w; // prime vertical radius of curvature
        let m = A * (1.0 - e2) / (w * w * w); // meridional radius of curvature
        LocalPlane {
            origin,
            kx: n * phi.cos() * PI / 180.0,
            ky: m * PI / 180.0,
        }
    }

    fn project(&self, p: LonLat) -> (f64, f64) {
        let dlon = (p.lon - self.origin.lon + 540.0).rem_euclid(360.0) - 180.0;
        (dlon * self.kx, (p.lat - self.origin.lat) * self.ky)
    }

    /// Distance from the origin to the segment `a`–`b`, metres.
    fn distance_to_segment(&self, a: LonLat, b: LonLat) -> f64 {
        let (ax, ay) = self.project(a);
        let (bx, by) = self.project(b);
        let (dx, dy) = (bx - ax, by - ay);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (-(ax * dx + ay * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (ax + t * dx).hypot(ay + t * dy)
    }
}

/// R-trees over node positions and edge envelopes (longitude/latitude degrees).
struct Index {
    nodes: RTree<GeomWithData<[f64; 2], u32>>,
    edges: RTree<GeomWithData<Rectangle<[f64; 2]>, u32>>,
}

impl Index {
    fn new(airspace: &Airspace) -> Self {
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

/// [`closed_elements`], with candidates from `index` when given.
fn closed_with(
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
    use geo_types::{Coord, LineString, Polygon, polygon};
    use muse_model::{Edge, Node, NodeKind, UtcOffset};

    use super::*;

    fn t(s: &str) -> Instant {
        Instant::parse_rfc3339(s).unwrap()
    }

    fn w(a: &str, b: &str) -> Window {
        Window::new(t(a), t(b))
    }

    /// Nodes by (id, lon, lat); edges as "A-B" between named nodes.
    fn airspace(nodes: &[(&str, f64, f64)], edges: &[&str]) -> Airspace {
        let ns = nodes
            .iter()
            .map(|&(id, lon, lat)| Node {
                id: id.into(),
                kind: NodeKind::Station,
                name: String::new(),
                pos: LonLat::new(lon, lat),
            })
            .collect();
        let idx = |id: &str| NodeId(nodes.iter().position(|n| n.0 == id).unwrap() as u32);
        let es = edges
            .iter()
            .map(|e| {
                let (a, b) = e.split_once('-').unwrap();
                Edge {
                    id: (*e).into(),
                    from: idx(a),
                    to: idx(b),
                    length_m: 1_000.0,
                }
            })
            .collect();
        Airspace::new(ns, es).unwrap()
    }

    fn zone(id: &str, area: Option<ZoneArea>, periods: Vec<Period>) -> Zone {
        Zone {
            id: id.into(),
            name: String::new(),
            restriction: "PROHIBITED".into(),
            area,
            node_ids: vec![],
            edge_ids: vec![],
            periods,
            announced: None,
        }
    }

    fn daily(days: &[Weekday], start: &str, end: &str, offset: &str) -> Period {
        let clock = |s: &str| muse_model::time::parse_clock(s).unwrap();
        Period {
            start: None,
            end: None,
            daily: vec![DailyWindow {
                days: days.to_vec(),
                start: clock(start),
                end: clock(end),
                offset: UtcOffset::parse(offset).unwrap(),
            }],
        }
    }

    /// A square lon [103.81, 103.83] × lat [1.29, 1.31].
    fn square() -> ZoneArea {
        ZoneArea::Polygons(
            polygon![(x: 103.81, y: 1.29), (x: 103.83, y: 1.29), (x: 103.83, y: 1.31),
                     (x: 103.81, y: 1.31), (x: 103.81, y: 1.29)]
            .into(),
        )
    }

    fn square_airspace() -> Airspace {
        airspace(
            &[
                ("OUT", 103.80, 1.30),
                ("EDGE", 103.81, 1.30),   // on the left side of the square
                ("CORNER", 103.83, 1.31), // a vertex
                ("IN", 103.82, 1.30),
                ("S", 103.825, 1.28),
                ("N", 103.825, 1.32),
                ("W1", 103.805, 1.28),
                ("W2", 103.805, 1.32),
                ("E", 103.85, 1.30),
            ],
            &["OUT-EDGE", "S-N", "W1-W2", "E-N", "OUT-W1"],
        )
    }

    fn names(a: &Airspace, nodes: &[NodeId], edges: &[EdgeId]) -> (Vec<String>, Vec<String>) {
        (
            nodes.iter().map(|&n| a.node(n).id.clone()).collect(),
            edges.iter().map(|&e| a.edge(e).id.clone()).collect(),
        )
    }

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

    #[test]
    fn daily_expansion_with_weekday_filter() {
        // 2026-01-05 is a Monday.
        let z = zone(
            "Z",
            None,
            vec![daily(
                &[Weekday::Mon, Weekday::Wed],
                "10:00",
                "12:00",
                "+08:00",
            )],
        );
        let got = zone_windows(
            &z,
            t("2026-01-05T00:00:00+08:00"),
            t("2026-01-12T00:00:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-05T10:00:00+08:00", "2026-01-05T12:00:00+08:00"),
                w("2026-01-07T10:00:00+08:00", "2026-01-07T12:00:00+08:00"),
            ]
        );
        // Clipped at both ends of the range.
        let got = zone_windows(
            &z,
            t("2026-01-05T11:00:00+08:00"),
            t("2026-01-07T11:30:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-05T11:00:00+08:00", "2026-01-05T12:00:00+08:00"),
                w("2026-01-07T10:00:00+08:00", "2026-01-07T11:30:00+08:00"),
            ]
        );
    }

    #[test]
    fn window_across_midnight() {
        // 2026-01-10 is a Saturday.
        let z = zone(
            "Z",
            None,
            vec![daily(&[Weekday::Sat], "22:00", "02:00", "+08:00")],
        );
        let got = zone_windows(
            &z,
            t("2026-01-10T00:00:00+08:00"),
            t("2026-01-12T00:00:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [w("2026-01-10T22:00:00+08:00", "2026-01-11T02:00:00+08:00")]
        );
        // A range starting on Sunday still sees the tail of Saturday's window.
        let got = zone_windows(
            &z,
            t("2026-01-11T00:00:00+08:00"),
            t("2026-01-12T00:00:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [w("2026-01-11T00:00:00+08:00", "2026-01-11T02:00:00+08:00")]
        );
        // end == start: a full day; end 24:00: until midnight.
        let z = zone(
            "Z",
            None,
            vec![
                daily(&[Weekday::Sat], "06:00", "06:00", "Z"),
                daily(&[Weekday::Mon], "20:00", "24:00", "Z"),
            ],
        );
        let got = zone_windows(&z, t("2026-01-10T00:00:00Z"), t("2026-01-13T00:00:00Z")).unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-10T06:00:00Z", "2026-01-11T06:00:00Z"),
                w("2026-01-12T20:00:00Z", "2026-01-13T00:00:00Z"),
            ]
        );
    }

    #[test]
    fn offsets_give_the_right_utc_instants() {
        let range = (t("2026-01-05T00:00:00Z"), t("2026-01-06T00:00:00Z"));
        let sg = zone(
            "SG",
            None,
            vec![daily(&Weekday::ALL, "10:00", "12:00", "+08:00")],
        );
        let utc = zone(
            "UTC",
            None,
            vec![daily(&Weekday::ALL, "02:00", "04:00", "Z")],
        );
        let a = zone_windows(&sg, range.0, range.1).unwrap();
        let b = zone_windows(&utc, range.0, range.1).unwrap();
        assert_eq!(a, b);
        assert_eq!(a, [w("2026-01-05T02:00:00Z", "2026-01-05T04:00:00Z")]);
        // The weekday is the local one: Monday 01:00 +08:00 is Sunday 17:00 UTC.
        let mon = zone(
            "M",
            None,
            vec![daily(&[Weekday::Mon], "01:00", "02:00", "+08:00")],
        );
        let got = zone_windows(&mon, t("2026-01-04T00:00:00Z"), t("2026-01-06T00:00:00Z")).unwrap();
        assert_eq!(got, [w("2026-01-04T17:00:00Z", "2026-01-04T18:00:00Z")]);
        let neg = zone(
            "N",
            None,
            vec![daily(&[Weekday::Sun], "20:00", "21:00", "-05:30")],
        );
        let got = zone_windows(&neg, t("2026-01-04T00:00:00Z"), t("2026-01-06T00:00:00Z")).unwrap();
        assert_eq!(got, [w("2026-01-05T01:30:00Z", "2026-01-05T02:30:00Z")]);
    }

    #[test]
    fn periods_clip_daily_windows_and_stand_alone() {
        let mut p = daily(&Weekday::ALL, "10:00", "12:00", "Z");
        p.start = Some(t("2026-01-05T11:00:00Z"));
        p.end = Some(t("2026-01-06T11:30:00Z"));
        let whole = Period {
            start: Some(t("2026-01-07T08:00:00Z")),
            end: Some(t("2026-01-07T09:00:00Z")),
            daily: vec![],
        };
        let open = Period {
            start: Some(t("2026-01-08T23:00:00Z")),
            end: None,
            daily: vec![],
        };
        let z = zone("Z", None, vec![p, whole, open]);
        let got = zone_windows(&z, t("2026-01-05T00:00:00Z"), t("2026-01-09T00:00:00Z")).unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-05T11:00:00Z", "2026-01-05T12:00:00Z"),
                w("2026-01-06T10:00:00Z", "2026-01-06T11:30:00Z"),
                w("2026-01-07T08:00:00Z", "2026-01-07T09:00:00Z"),
                w("2026-01-08T23:00:00Z", "2026-01-09T00:00:00Z"),
            ]
        );
    }

    #[test]
    fn merging_windows_from_two_zones_and_permanent_zones() {
        let a = square_airspace();
        let node = |id: &str| a.node_id(id).unwrap();
        let mut z1 = zone(
            "Z1",
            None,
            vec![daily(&Weekday::ALL, "10:00", "12:00", "Z")],
        );
        z1.node_ids = vec!["E".into()];
        let mut z2 = zone(
            "Z2",
            None,
            vec![daily(&Weekday::ALL, "11:00", "13:00", "Z")],
        );
        z2.node_ids = vec!["E".into(), "OUT".into()];
        let mut z3 = zone(
            "Z3",
            None,
            vec![daily(&Weekday::ALL, "13:00", "14:00", "Z")],
        );
        z3.node_ids = vec!["E".into()];
        let permanent = zone("P", Some(square()), vec![]);
        let (from, to) = (t("2026-01-05T00:00:00Z"), t("2026-01-06T00:00:00Z"));
        let c = resolve(&a, &[z1, z2, z3, permanent], from, to).unwrap();
        assert_eq!(
            c.node(node("E")),
            [w("2026-01-05T10:00:00Z", "2026-01-05T14:00:00Z")],
            "overlapping and touching windows merge"
        );
        assert_eq!(
            c.node(node("OUT")),
            [w("2026-01-05T11:00:00Z", "2026-01-05T13:00:00Z")]
        );
        assert_eq!(c.node(node("IN")), [Window::new(from, to)]);
        assert_eq!(c.edge(a.edge_id("S-N").unwrap()), [Window::new(from, to)]);
        assert!(c.node(node("W1")).is_empty());
        assert_eq!((c.closed_node_count(), c.closed_edge_count()), (5, 2));
        assert!(!c.is_empty());
        assert_eq!(c.closed_nodes().count(), 5);
        assert_eq!(
            c.closed_edges().map(|(e, _)| e).collect::<Vec<_>>().len(),
            2
        );
        assert!(resolve(&a, &[], from, to).unwrap().is_empty());
        assert_eq!(Closures::none(&a).window_count(), 0);
    }

    #[test]
    fn conflicts_follow_the_spec() {
        let a = square_airspace();
        let mut z = zone("Z", None, vec![daily(&Weekday::ALL, "10:00", "12:00", "Z")]);
        z.node_ids = vec!["E".into()];
        z.edge_ids = vec!["S-N".into()];
        let c = resolve(
            &a,
            &[z],
            t("2026-01-05T00:00:00Z"),
            t("2026-01-07T00:00:00Z"),
        )
        .unwrap();
        let node = a.node_id("E").unwrap();
        let edge = a.edge_id("S-N").unwrap();
        let ten = t("2026-01-05T10:00:00Z");
        let noon = t("2026-01-05T12:00:00Z");
        assert_eq!(
            c.node_conflict(node, ten - Millis(5), ten),
            Some(Window::new(ten, noon)),
            "d == start conflicts"
        );
        assert_eq!(
            c.node_conflict(node, ten - Millis(5), ten - Millis(1)),
            None
        );
        assert_eq!(
            c.node_conflict(node, noon, noon + Millis(10)),
            None,
            "a == end is allowed"
        );
        assert!(
            c.edge_conflict(edge, t("2026-01-05T09:00:00Z"), t("2026-01-06T09:00:00Z"))
                .is_some()
        );
        assert_eq!(
            c.edge_conflict(edge, noon, t("2026-01-06T10:00:00Z")),
            Some(w("2026-01-06T10:00:00Z", "2026-01-06T12:00:00Z"))
        );
        assert_eq!(c.node_conflict(NodeId(999), ten, noon), None);
    }

    #[test]
    fn bad_ranges_and_schedules() {
        let z = zone("Z", None, vec![]);
        assert!(matches!(
            zone_windows(&z, Instant(10), Instant(5)),
            Err(ClosureError::BadRange { .. })
        ));
        assert!(matches!(
            zone_windows(&z, Instant(0), Instant(MAX_RANGE_DAYS * DAY_MS + 1)),
            Err(ClosureError::BadRange { .. })
        ));
        assert!(matches!(
            zone_windows(&z, Instant(i64::MIN), Instant(0)),
            Err(ClosureError::BadRange { .. })
        ));
        assert!(zone_windows(&z, Instant(5), Instant(5)).unwrap().is_empty());
        let mut p = daily(&Weekday::ALL, "10:00", "12:00", "Z");
        p.daily[0].end = Millis(DAY_MS + 1);
        let bad = zone("B", None, vec![p]);
        let err = zone_windows(&bad, Instant(0), Instant(DAY_MS)).unwrap_err();
        assert!(
            err.to_string()
                .contains("zone `B` has an invalid daily schedule"),
            "{err}"
        );
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
