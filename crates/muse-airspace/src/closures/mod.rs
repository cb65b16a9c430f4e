//! Zone resolution (docs/reference.md#no-fly-zones): zones and a time range → each node's and
//! edge's closure windows.
//!
//! - [`geometry`]: which elements a zone closes ([`closed_elements`]); on a layered airspace
//!   (docs/reference.md#layered-airspace) the copies, at the layers its vertical band covers, of
//!   what it closes on the flat one, and the vertical links at its nodes whose span meets the band;
//! - [`windows`]: when it closes them ([`zone_windows`], [`MAX_RANGE_DAYS`]);
//! - here: [`resolve`] puts the two together into [`Closures`]. Per element, windows of all
//!   zones are sorted and overlapping or touching ones merged; [`Closures::add`] forms the
//!   union of two resolutions the same way;
//! - [`idle`]: whether a zone does nothing (closes nothing, or is announced after its last
//!   window), which the command line warns of.
//!
//! A [`Window`] is half-open, `[start, end)`. A stay `[a, d]` at a closed node (or a
//! traversal `[s, f]` of a closed edge) may not share an instant with it: it is allowed only
//! when `d < start` or `a >= end` ([`Window::blocks`]).

pub mod geometry;
pub mod idle;
mod layers;
pub mod windows;

pub use geometry::closed_elements;
pub use windows::{MAX_RANGE_DAYS, zone_windows};

use muse_model::{Airspace, EdgeId, Instant, NodeId, UtcOffset, Zone};

use geometry::{Index, closed_with};
use windows::check_range;

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
    /// with the window. It is allowed only when `d < start` or `a >= end`
    /// (docs/reference.md#no-fly-zones).
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

    /// Adds `other`'s windows to these: afterwards an element is closed at an instant when it
    /// was closed then in `self` or in `other`, and its windows are again sorted, disjoint and
    /// merged (overlapping or touching windows become one, as in [`resolve`]). Resolving two
    /// lists of zones over a range and adding the results gives what resolving both lists
    /// together over that range gives.
    ///
    /// Both must be for the same airspace (made by [`resolve`] or [`Closures::none`] for it).
    /// Debug builds check that they have as many nodes and edges; release builds do not, and
    /// keep every element's windows: elements that only one of them has are taken as having
    /// no windows in the other.
    ///
    /// ```
    /// use muse_airspace::closures::resolve;
    /// use muse_model::{Airspace, Instant, Node, NodeId, NodeKind, LonLat, Period, Zone};
    /// let airspace = Airspace::new(
    ///     vec![Node { id: "S001".into(), kind: NodeKind::Station, name: String::new(),
    ///                 pos: LonLat::new(103.85, 1.29) }],
    ///     vec![],
    /// ).unwrap();
    /// let closing = |id: &str, start: i64, end: i64| Zone {
    ///     id: id.into(), name: String::new(), restriction: "PROHIBITED".into(), area: None,
    ///     node_ids: vec!["S001".into()], edge_ids: vec![], announced: None, withdrawn: None,
    ///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
    ///     periods: vec![Period { start: Some(Instant(start)), end: Some(Instant(end)),
    ///                            daily: vec![] }],
    /// };
    /// let (from, to) = (Instant(0), Instant(1_000));
    /// let mut c = resolve(&airspace, &[closing("A", 100, 200)], from, to).unwrap();
    /// c.add(&resolve(&airspace, &[closing("B", 200, 300), closing("C", 500, 600)], from, to).unwrap());
    /// let windows: Vec<(i64, i64)> = c.node(NodeId(0)).iter().map(|w| (w.start.0, w.end.0)).collect();
    /// assert_eq!(windows, [(100, 300), (500, 600)], "touching windows merge");
    /// ```
    pub fn add(&mut self, other: &Closures) {
        debug_assert!(
            self.nodes.len() == other.nodes.len() && self.edges.len() == other.edges.len(),
            "Closures::add: closures of different airspaces ({} nodes, {} edges vs {} nodes, \
             {} edges)",
            self.nodes.len(),
            self.edges.len(),
            other.nodes.len(),
            other.edges.len()
        );
        union_lists(&mut self.nodes, &other.nodes);
        union_lists(&mut self.edges, &other.edges);
    }
}

/// Per element, `mine[i] ∪= theirs[i]`; `mine` grows to `theirs`'s length if shorter.
fn union_lists(mine: &mut Vec<Vec<Window>>, theirs: &[Vec<Window>]) {
    if mine.len() < theirs.len() {
        mine.resize_with(theirs.len(), Vec::new);
    }
    for (a, b) in mine.iter_mut().zip(theirs) {
        union(a, b);
    }
}

/// `mine ∪= theirs` for two sorted, disjoint and merged lists; the result is too. Linear.
fn union(mine: &mut Vec<Window>, theirs: &[Window]) {
    if theirs.is_empty() {
        return;
    }
    if mine.is_empty() {
        mine.extend_from_slice(theirs);
        return;
    }
    let mut out: Vec<Window> = Vec::with_capacity(mine.len() + theirs.len());
    let (mut i, mut j) = (0, 0);
    while i < mine.len() || j < theirs.len() {
        let next = if j == theirs.len() || (i < mine.len() && mine[i].start <= theirs[j].start) {
            i += 1;
            mine[i - 1]
        } else {
            j += 1;
            theirs[j - 1]
        };
        match out.last_mut() {
            Some(last) if next.start <= last.end => last.end = last.end.max(next.end),
            _ => out.push(next),
        }
    }
    *mine = out;
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
    #[error(
        "cannot resolve zones over [{}, {}): {reason}",
        Instant(*from).to_rfc3339(UtcOffset(0)),
        Instant(*to).to_rfc3339(UtcOffset(0))
    )]
    BadRange {
        /// Start of the range, ms since the epoch.
        from: i64,
        /// End of the range, ms since the epoch.
        to: i64,
        /// What is wrong.
        reason: String,
    },
}

/// Resolves zones over `[from, to)` into per-element closure windows: of every node and edge
/// of `airspace`, the copies at each layer when it is layered (each zone closing only the
/// layers of its vertical band, [`closed_elements`]).
///
/// Errors: an explicit node or edge id not in the airspace, an invalid area or schedule, or a
/// range that ends before it starts, lies outside the years 0000–9998 (UTC) or is longer than
/// [`MAX_RANGE_DAYS`] (no zones close nothing, over any range).
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
///     node_ids: vec!["S001".into()], edge_ids: vec![], announced: None, withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
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
    if zones.is_empty() {
        return Ok(Closures::none(airspace));
    }
    check_range(from, to)?;
    let index = zones
        .iter()
        .any(|z| z.area.is_some())
        .then(|| Index::new(airspace.flat()));
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

/// Test helpers shared by the tests of this module and its submodules.
#[cfg(test)]
mod fixtures {
    use geo_types::polygon;
    use muse_model::testing::{joined, station};
    use muse_model::{
        Airspace, DailyWindow, EdgeId, Instant, NodeId, Period, UtcOffset, Weekday, Zone, ZoneArea,
    };

    use super::Window;

    pub(super) fn t(s: &str) -> Instant {
        Instant::parse_rfc3339(s).unwrap()
    }

    pub(super) fn w(a: &str, b: &str) -> Window {
        Window::new(t(a), t(b))
    }

    /// Stations by (id, lon, lat); edges of 1 km as "A-B" between named nodes.
    pub(super) fn airspace(nodes: &[(&str, f64, f64)], edges: &[&str]) -> Airspace {
        let edges: Vec<(&str, &str, f64)> = edges
            .iter()
            .map(|e| {
                let (a, b) = e.split_once('-').unwrap();
                (a, b, 1_000.0)
            })
            .collect();
        let nodes = nodes.iter().map(|&(id, lon, lat)| station(id, lon, lat));
        joined(nodes.collect(), &edges)
    }

    pub(super) fn zone(id: &str, area: Option<ZoneArea>, periods: Vec<Period>) -> Zone {
        Zone {
            id: id.into(),
            name: String::new(),
            restriction: "PROHIBITED".into(),
            area,
            node_ids: vec![],
            edge_ids: vec![],
            periods,
            announced: None,
            withdrawn: None,
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
        }
    }

    pub(super) fn daily(days: &[Weekday], start: &str, end: &str, offset: &str) -> Period {
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
    pub(super) fn square() -> ZoneArea {
        ZoneArea::Polygons(
            polygon![(x: 103.81, y: 1.29), (x: 103.83, y: 1.29), (x: 103.83, y: 1.31),
                     (x: 103.81, y: 1.31), (x: 103.81, y: 1.29)]
            .into(),
        )
    }

    pub(super) fn square_airspace() -> Airspace {
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

    pub(super) fn names(
        a: &Airspace,
        nodes: &[NodeId],
        edges: &[EdgeId],
    ) -> (Vec<String>, Vec<String>) {
        (
            nodes.iter().map(|&n| a.node(n).id.clone()).collect(),
            edges.iter().map(|&e| a.edge(e).id.clone()).collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use muse_model::testing::{airspace, named_edge, station};
    use muse_model::{DailyWindow, Millis, Period, UtcOffset, Weekday};
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRunner};

    use super::fixtures::{daily, square, square_airspace, t, w, zone};
    use super::*;

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
    fn add_is_the_union_merged() {
        let a = square_airspace();
        let node = |id: &str| a.node_id(id).unwrap();
        let (from, to) = (t("2026-01-05T00:00:00Z"), t("2026-01-07T00:00:00Z"));
        let mut z1 = zone(
            "Z1",
            None,
            vec![daily(&Weekday::ALL, "10:00", "12:00", "Z")],
        );
        z1.node_ids = vec!["E".into()];
        let mut z2 = zone(
            "Z2",
            None,
            vec![daily(&Weekday::ALL, "12:00", "13:00", "Z")],
        );
        z2.node_ids = vec!["E".into(), "OUT".into()];
        z2.edge_ids = vec!["E-N".into()];
        let mut z3 = zone(
            "Z3",
            None,
            vec![Period {
                start: Some(t("2026-01-05T11:00:00Z")),
                end: Some(t("2026-01-06T12:00:00Z")),
                daily: vec![],
            }],
        );
        z3.node_ids = vec!["OUT".into()];
        let permanent = zone("P", Some(square()), vec![]);

        let mut c = resolve(&a, &[z1.clone(), permanent.clone()], from, to).unwrap();
        c.add(&resolve(&a, &[z2.clone(), z3.clone()], from, to).unwrap());
        assert_eq!(c, resolve(&a, &[z1, z2, z3, permanent], from, to).unwrap());
        assert_eq!(
            c.node(node("E")),
            [
                w("2026-01-05T10:00:00Z", "2026-01-05T13:00:00Z"),
                w("2026-01-06T10:00:00Z", "2026-01-06T13:00:00Z"),
            ],
            "touching windows merge"
        );
        assert_eq!(
            c.node(node("OUT")),
            [w("2026-01-05T11:00:00Z", "2026-01-06T13:00:00Z")],
            "overlapping and touching windows merge, across lists"
        );
        assert_eq!(c.node(node("IN")), [Window::new(from, to)]);
        assert_eq!(
            c.edge(a.edge_id("E-N").unwrap()),
            [
                w("2026-01-05T12:00:00Z", "2026-01-05T13:00:00Z"),
                w("2026-01-06T12:00:00Z", "2026-01-06T13:00:00Z"),
            ]
        );

        // None is the identity, on either side; adding itself changes nothing.
        let before = c.clone();
        c.add(&Closures::none(&a));
        assert_eq!(c, before);
        let mut none = Closures::none(&a);
        none.add(&before);
        assert_eq!(none, before);
        c.add(&before);
        assert_eq!(c, before);
    }

    #[test]
    fn union_of_sorted_lists() {
        let win = |a: i64, b: i64| Window::new(Instant(a), Instant(b));
        let cases: [(&[Window], &[Window], &[Window]); 5] = [
            (&[], &[win(1, 2)], &[win(1, 2)]),
            (&[win(1, 2)], &[], &[win(1, 2)]),
            (
                &[win(0, 5), win(10, 12)],
                &[win(5, 6), win(20, 30)],
                &[win(0, 6), win(10, 12), win(20, 30)],
            ),
            (
                &[win(0, 3), win(4, 5), win(8, 9)],
                &[win(2, 8)],
                &[win(0, 9)],
            ),
            (
                &[win(10, 11)],
                &[win(0, 1), win(2, 3)],
                &[win(0, 1), win(2, 3), win(10, 11)],
            ),
        ];
        for (a, b, want) in cases {
            let mut got = a.to_vec();
            union(&mut got, b);
            assert_eq!(got, want, "{a:?} ∪ {b:?}");
            let mut other_way = b.to_vec();
            union(&mut other_way, a);
            assert_eq!(other_way, want, "{b:?} ∪ {a:?}");
        }
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "closures of different airspaces")]
    fn add_checks_the_sizes_in_debug_builds() {
        let a = square_airspace();
        let mut c = Closures::none(&a);
        c.add(&Closures::default());
    }

    /// Nodes `N0`… on a line, edges `E0`… between consecutive nodes, then chords `Ni`–`Ni+2`
    /// where `chords[i]`.
    fn line_airspace(n: usize, chords: &[bool]) -> Airspace {
        let nodes = (0..n)
            .map(|i| {
                let pos = (103.80 + 0.01 * i as f64, 1.30 + 0.002 * (i % 2) as f64);
                station(&format!("N{i}"), pos.0, pos.1)
            })
            .collect();
        let pairs = (0..n - 1).map(|i| (i, i + 1)).chain(
            (0..n.saturating_sub(2))
                .filter(|&i| chords[i])
                .map(|i| (i, i + 2)),
        );
        let edges = pairs
            .enumerate()
            .map(|(k, (i, j))| named_edge(&format!("E{k}"), i as u32, j as u32, 1_000.0))
            .collect();
        airspace(nodes, edges)
    }

    const HOUR_MS: i64 = 3_600_000;

    /// A zone of explicit node and edge ids (edges by id or as `FROM-TO` either way) with up
    /// to two periods: dated (either side may be open, with hour-aligned bounds around the
    /// range so that windows often overlap or touch), with or without a daily window.
    fn arb_zone(n: usize, m: usize) -> impl Strategy<Value = Zone> + Clone {
        let base = t("2026-01-05T00:00:00Z").0;
        let bound = proptest::option::weighted(0.8, -12..60_i64);
        let days = proptest::sample::subsequence(Weekday::ALL.to_vec(), 1..=7);
        let window = proptest::option::of((days, 0..24_i64, 0..=24_i64));
        let period = (bound.clone(), bound, window).prop_map(move |(s, e, window)| Period {
            start: s.map(|h| Instant(base + h * HOUR_MS)),
            end: e.map(|h| Instant(base + h * HOUR_MS)),
            daily: window
                .into_iter()
                .map(|(days, s, e)| DailyWindow {
                    days,
                    start: Millis(s * HOUR_MS),
                    end: Millis(e * HOUR_MS),
                    offset: UtcOffset::SINGAPORE,
                })
                .collect(),
        });
        (
            proptest::collection::vec(0..n, 0..=3),
            proptest::collection::vec((0..m, 0..3_u8), 0..=3),
            proptest::collection::vec(period, 0..=2),
        )
            .prop_map(move |(nodes, edges, periods)| {
                let mut z = zone("", None, periods);
                z.node_ids = nodes.into_iter().map(|i| format!("N{i}")).collect();
                z.edge_ids = edges
                    .into_iter()
                    .map(|(k, how)| format!("{k}/{how}"))
                    .collect();
                z
            })
    }

    /// Edge names of `arb_zone`, `k/how`, made real for an airspace: `how` 0 the id, 1
    /// `FROM-TO`, 2 `TO-FROM`.
    fn name_edges(a: &Airspace, z: &mut Zone) {
        for id in &mut z.edge_ids {
            let (k, how) = id.split_once('/').unwrap();
            let e = a.edge(EdgeId(k.parse().unwrap()));
            let (from, to) = (&a.node(e.from).id, &a.node(e.to).id);
            *id = match how {
                "0" => e.id.clone(),
                "1" => format!("{from}-{to}"),
                _ => format!("{to}-{from}"),
            };
        }
    }

    /// Resolving zones A and B apart and adding the results is resolving A ∪ B, whichever is
    /// added to which.
    #[test]
    fn add_of_resolutions_is_resolution_of_the_union() {
        let instance = (2..=6_usize, proptest::collection::vec(any::<bool>(), 4)).prop_flat_map(
            |(n, chords)| {
                let m = (n - 1) + (0..n.saturating_sub(2)).filter(|&i| chords[i]).count();
                let zones = proptest::collection::vec(arb_zone(n, m), 0..=3);
                (
                    Just(n),
                    Just(chords),
                    zones.clone(),
                    zones,
                    -6..30_i64,
                    0..48_i64,
                )
            },
        );
        let mut runner = TestRunner::new(Config {
            cases: 512,
            rng_algorithm: RngAlgorithm::ChaCha,
            rng_seed: RngSeed::Fixed(0x4d55_5345_4144_4400),
            failure_persistence: None,
            ..Config::default()
        });
        let result = runner.run(&instance, |(n, chords, mut za, mut zb, from_h, len_h)| {
            let a = line_airspace(n, &chords);
            for (i, z) in za.iter_mut().enumerate() {
                z.id = format!("A{i}");
                name_edges(&a, z);
            }
            for (i, z) in zb.iter_mut().enumerate() {
                z.id = format!("B{i}");
                name_edges(&a, z);
            }
            let base = t("2026-01-05T00:00:00Z");
            let from = base + Millis(from_h * HOUR_MS);
            let to = from + Millis(len_h * HOUR_MS);
            let ra = resolve(&a, &za, from, to).unwrap();
            let rb = resolve(&a, &zb, from, to).unwrap();
            let both: Vec<Zone> = za.iter().chain(&zb).cloned().collect();
            let want = resolve(&a, &both, from, to).unwrap();
            let mut ab = ra.clone();
            ab.add(&rb);
            prop_assert_eq!(&ab, &want);
            let mut ba = rb;
            ba.add(&ra);
            prop_assert_eq!(&ba, &want);
            Ok(())
        });
        if let Err(e) = result {
            panic!("{e}");
        }
    }
}
