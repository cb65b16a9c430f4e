//! No-fly zones: an area and/or explicit nodes and edges, closed during time periods, within
//! a vertical band ([`VerticalLimits`], the whole sky by default).
//!
//! This is the data model, with the polygons of a zone's area ([`zone_area_polygons`], a
//! circle as a geodesic polygon by [`circle_polygon`]) that the map, the viewer and the CLI
//! draw; reading ED-318 / ED-269 files lives in `muse-formats`, and turning zones into
//! per-element closure windows lives in `muse-airspace`.

use geo::{Destination, Geodesic};
use geo_types::{LineString, MultiPolygon, Point, Polygon};

use crate::coords::LonLat;
use crate::time::{Instant, Millis, UtcOffset};
use crate::units::Metres;

/// The horizontal extent of a zone.
#[derive(Clone, Debug, PartialEq)]
pub enum ZoneArea {
    /// One or more polygons in WGS84 degrees (`x` = longitude, `y` = latitude).
    Polygons(MultiPolygon<f64>),
    /// A circle around a centre, radius in metres (geodesic).
    Circle {
        /// Centre.
        centre: LonLat,
        /// Radius, metres.
        radius_m: f64,
    },
}

/// The polygons of a zone's area: as given, or a 72-gon for a circle.
///
/// ```
/// use muse_model::{LonLat, ZoneArea, zone_area_polygons};
/// let circle = ZoneArea::Circle { centre: LonLat::new(103.99, 1.36), radius_m: 5_000.0 };
/// let polygons = zone_area_polygons(&circle);
/// assert_eq!(polygons.len(), 1);
/// assert_eq!(polygons[0].exterior().0.len(), 73);
/// ```
pub fn zone_area_polygons(area: &ZoneArea) -> Vec<Polygon<f64>> {
    match area {
        ZoneArea::Polygons(mp) => mp.0.clone(),
        ZoneArea::Circle { centre, radius_m } => vec![circle_polygon(*centre, *radius_m, 72)],
    }
}

/// A geodesic circle of `radius_m` metres around `centre` as a polygon with `segments`
/// vertices (at least 8), in lon/lat degrees.
pub fn circle_polygon(centre: LonLat, radius_m: f64, segments: usize) -> Polygon<f64> {
    let n = segments.max(8);
    let c = Point::new(centre.lon, centre.lat);
    let mut ring: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let p = Geodesic.destination(c, 360.0 * i as f64 / n as f64, radius_m);
            (p.x(), p.y())
        })
        .collect();
    ring.push(ring[0]);
    Polygon::new(LineString::from(ring), vec![])
}

/// A day of the week.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Weekday {
    /// Monday.
    Mon,
    /// Tuesday.
    Tue,
    /// Wednesday.
    Wed,
    /// Thursday.
    Thu,
    /// Friday.
    Fri,
    /// Saturday.
    Sat,
    /// Sunday.
    Sun,
}

impl Weekday {
    /// All days, Monday first.
    pub const ALL: [Weekday; 7] = [
        Weekday::Mon,
        Weekday::Tue,
        Weekday::Wed,
        Weekday::Thu,
        Weekday::Fri,
        Weekday::Sat,
        Weekday::Sun,
    ];

    /// The ED-318 spelling: `MON` … `SUN`.
    pub const fn as_str(self) -> &'static str {
        match self {
            Weekday::Mon => "MON",
            Weekday::Tue => "TUE",
            Weekday::Wed => "WED",
            Weekday::Thu => "THU",
            Weekday::Fri => "FRI",
            Weekday::Sat => "SAT",
            Weekday::Sun => "SUN",
        }
    }

    /// The weekday of a civil date.
    pub fn of(date: jiff::civil::Date) -> Self {
        Self::ALL[(date.weekday().to_monday_zero_offset()) as usize]
    }
}

/// A daily window: on each of `days`, closed from `start` to `end` local time in `offset`.
/// If `end <= start` the window runs past midnight into the next day.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DailyWindow {
    /// The days it applies (all seven for ED-318 `ANY`).
    pub days: Vec<Weekday>,
    /// Local start time of day.
    pub start: Millis,
    /// Local end time of day (`24:00` allowed).
    pub end: Millis,
    /// The offset the clock times are stated in (required: a schedule without one is an error).
    pub offset: UtcOffset,
}

/// A period during which a zone applies. With no daily windows the zone is closed for the
/// whole of `[start, end)`; with daily windows, during those windows within `[start, end)`.
/// A missing bound is unbounded.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Period {
    /// Start of applicability (inclusive).
    pub start: Option<Instant>,
    /// End of applicability (exclusive).
    pub end: Option<Instant>,
    /// Daily windows inside the period (empty = the whole period).
    pub daily: Vec<DailyWindow>,
}

/// The surface a vertical limit is measured from (ED-318 / ED-269 `CodeVerticalReferenceType`).
///
/// MUSE flies over flat ground at sea level (docs/reference.md#layered-airspace), so every
/// reference measures the same heights: the reference is kept to be shown and written back, never
/// to convert.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum VerticalReference {
    /// Above ground (or water) level.
    #[default]
    Agl,
    /// Above mean sea level.
    Amsl,
    /// Above the WGS84 ellipsoid.
    Wgs84,
}

impl VerticalReference {
    /// The ED-318 spelling: `AGL`, `AMSL`, `WGS84`.
    pub const fn as_str(self) -> &'static str {
        match self {
            VerticalReference::Agl => "AGL",
            VerticalReference::Amsl => "AMSL",
            VerticalReference::Wgs84 => "WGS84",
        }
    }
}

impl std::fmt::Display for VerticalReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One side of a zone's vertical band: a height and the surface it is measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VerticalLimit {
    /// The height.
    pub height: Metres,
    /// What it is measured from.
    pub reference: VerticalReference,
}

impl VerticalLimit {
    /// A height above ground level.
    pub const fn agl(height: Metres) -> Self {
        VerticalLimit {
            height,
            reference: VerticalReference::Agl,
        }
    }
}

/// The vertical band a zone applies to (docs/reference.md#layered-airspace): from `lower` to
/// `upper`, both included; a missing side is open (no floor, no ceiling). The default, both open,
/// is the whole sky, which is what a zone without vertical limits covers.
///
/// Heights are compared as they are, whatever their references (flat ground at sea level,
/// docs/reference.md#layered-airspace). A band whose lower limit is above its upper limit is empty:
/// it contains and meets nothing (the zone readers refuse such a band).
///
/// Displayed for people: `whole sky`, `0–60 m AGL`, `0 m AGL – 121.92 m AMSL`, `up to 60 m
/// AGL`, `from 30 m AMSL up`.
///
/// ```
/// use muse_model::{Metres, VerticalLimit, VerticalLimits};
/// let m = |x: f64| Metres::from_m(x).unwrap();
/// let band = VerticalLimits::agl(Some(m(0.0)), Some(m(60.0)));
/// assert_eq!(band.to_string(), "0–60 m AGL");
/// assert!(band.contains(m(60.0)) && !band.contains(m(69.144)));
/// assert!(VerticalLimits::default().is_whole_sky());
/// assert_eq!(VerticalLimits::default().to_string(), "whole sky");
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct VerticalLimits {
    /// The floor, included; `None`: no floor.
    pub lower: Option<VerticalLimit>,
    /// The ceiling, included; `None`: no ceiling.
    pub upper: Option<VerticalLimit>,
}

impl VerticalLimits {
    /// The whole sky: no floor and no ceiling (the default).
    pub const WHOLE_SKY: VerticalLimits = VerticalLimits {
        lower: None,
        upper: None,
    };

    /// A band with both sides above ground level (a missing side open).
    pub fn agl(lower: Option<Metres>, upper: Option<Metres>) -> Self {
        VerticalLimits {
            lower: lower.map(VerticalLimit::agl),
            upper: upper.map(VerticalLimit::agl),
        }
    }

    /// Whether the band is the whole sky (no floor, no ceiling).
    ///
    /// ```
    /// use muse_model::{Metres, VerticalLimits};
    /// assert!(VerticalLimits::WHOLE_SKY.is_whole_sky());
    /// assert!(!VerticalLimits::agl(None, Some(Metres::from_mm(60_000))).is_whole_sky());
    /// ```
    pub fn is_whole_sky(&self) -> bool {
        self.lower.is_none() && self.upper.is_none()
    }

    /// Whether `altitude` lies in the band: `lower <= altitude <= upper`, a missing side
    /// open.
    ///
    /// ```
    /// use muse_model::{Metres, VerticalLimits};
    /// let m = |x: i64| Metres::from_mm(x * 1_000);
    /// let band = VerticalLimits::agl(Some(m(30)), Some(m(60)));
    /// assert!(band.contains(m(30)) && band.contains(m(45)) && band.contains(m(60)));
    /// assert!(!band.contains(m(29)) && !band.contains(m(61)));
    /// // A missing side is open.
    /// assert!(VerticalLimits::agl(None, Some(m(60))).contains(m(-5)));
    /// assert!(VerticalLimits::agl(Some(m(30)), None).contains(m(10_000)));
    /// assert!(VerticalLimits::WHOLE_SKY.contains(m(0)));
    /// ```
    pub fn contains(&self, altitude: Metres) -> bool {
        self.meets(altitude, altitude)
    }

    /// Whether the closed span between `lo` and `hi` (in either order) shares at least one
    /// height with the band: the test for a vertical link between two layers
    /// (docs/reference.md#layered-airspace).
    ///
    /// ```
    /// use muse_model::{Metres, VerticalLimits};
    /// let m = |x: i64| Metres::from_mm(x);
    /// let band = VerticalLimits::agl(Some(m(0)), Some(m(60_000)));
    /// // The link from 60 m to 69.144 m touches the ceiling: it meets the band.
    /// assert!(band.meets(m(60_000), m(69_144)));
    /// assert!(!band.meets(m(60_001), m(69_144)));
    /// // A span around the whole band meets it; the order of the ends does not matter.
    /// assert!(band.meets(m(70_000), m(-10_000)));
    /// assert!(VerticalLimits::WHOLE_SKY.meets(m(1), m(2)));
    /// ```
    pub fn meets(&self, lo: Metres, hi: Metres) -> bool {
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        let floor = self.lower.map(|l| l.height);
        let ceiling = self.upper.map(|u| u.height);
        if let (Some(f), Some(c)) = (floor, ceiling)
            && f > c
        {
            return false;
        }
        floor.is_none_or(|f| hi >= f) && ceiling.is_none_or(|c| lo <= c)
    }
}

impl std::fmt::Display for VerticalLimits {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.lower, self.upper) {
            (None, None) => f.write_str("whole sky"),
            (Some(l), Some(u)) if l.reference == u.reference => {
                write!(f, "{}–{} m {}", l.height, u.height, u.reference)
            }
            (Some(l), Some(u)) => write!(
                f,
                "{} m {} – {} m {}",
                l.height, l.reference, u.height, u.reference
            ),
            (None, Some(u)) => write!(f, "up to {} m {}", u.height, u.reference),
            (Some(l), None) => write!(f, "from {} m {} up", l.height, l.reference),
        }
    }
}

/// A no-fly zone.
#[derive(Clone, Debug, PartialEq)]
pub struct Zone {
    /// Identifier (ED-318 `identifier`).
    pub id: String,
    /// Name.
    pub name: String,
    /// Restriction as in the file, e.g. `PROHIBITED` (MUSE closes the airspace whatever it is).
    pub restriction: String,
    /// Horizontal extent, if the zone has one.
    pub area: Option<ZoneArea>,
    /// Node ids closed explicitly (the paper's `V_nfz`).
    pub node_ids: Vec<String>,
    /// Edge ids closed explicitly (the paper's `E_nfz`).
    pub edge_ids: Vec<String>,
    /// When it applies; empty = permanent.
    pub periods: Vec<Period>,
    /// When the zone becomes known (docs/reference.md#zones-announced-during-the-day): it binds
    /// every stay and traversal that begins at or after this instant, and none that begins before.
    /// `None`: known from the start.
    pub announced: Option<Instant>,
    /// When an announced zone was withdrawn (docs/reference.md#zones-announced-during-the-day, as a
    /// service lists it): from this instant on it binds nothing, so it binds only the stays and
    /// traversals that begin in `[announced, withdrawn)`. `None`: never withdrawn.
    pub withdrawn: Option<Instant>,
    /// The heights it applies to (docs/reference.md#layered-airspace); the whole sky by default.
    /// MUSE flying one cruise altitude, a zone closes what it covers whatever its band; the band
    /// matters with layers.
    pub vertical: VerticalLimits,
}

impl Zone {
    /// Its area as polygons ([`zone_area_polygons`]); none for a zone given as node and
    /// corridor ids alone.
    pub fn polygons(&self) -> Vec<Polygon<f64>> {
        self.area
            .as_ref()
            .map(zone_area_polygons)
            .unwrap_or_default()
    }

    /// Whether the zone has no time limits.
    pub fn is_permanent(&self) -> bool {
        self.periods.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circles_become_polygons() {
        let p = circle_polygon(LonLat::new(103.8, 1.3), 1_000.0, 36);
        assert_eq!(p.exterior().0.len(), 37);
        let c = p.exterior().0[0];
        let d = LonLat::new(103.8, 1.3).geodesic_distance_m(LonLat::new(c.x, c.y));
        assert!((d - 1_000.0).abs() < 1e-6, "{d}");
    }

    fn m(x: i64) -> Metres {
        Metres::from_mm(x * 1_000)
    }

    #[test]
    fn bands_contain_their_ends_and_open_sides_have_no_end() {
        let band = VerticalLimits::agl(Some(m(30)), Some(m(60)));
        for (h, inside) in [(29, false), (30, true), (45, true), (60, true), (61, false)] {
            assert_eq!(band.contains(m(h)), inside, "{h} m");
        }
        assert!(band.contains(Metres::from_um(60_000_000)));
        assert!(!band.contains(Metres::from_um(60_000_001)));
        let floor_only = VerticalLimits::agl(Some(m(30)), None);
        assert!(floor_only.contains(m(1_000_000)) && !floor_only.contains(m(29)));
        let ceiling_only = VerticalLimits::agl(None, Some(m(60)));
        assert!(ceiling_only.contains(m(-100)) && !ceiling_only.contains(m(61)));
        assert!(VerticalLimits::default().contains(Metres::from_um(i64::MAX)));
        assert_eq!(VerticalLimits::default(), VerticalLimits::WHOLE_SKY);
    }

    #[test]
    fn spans_meet_a_band_when_they_share_a_height() {
        let band = VerticalLimits::agl(Some(m(30)), Some(m(60)));
        for (lo, hi, meets) in [
            (0, 29, false),
            (0, 30, true),
            (40, 50, true),
            (60, 70, true),
            (61, 70, false),
            (0, 100, true),
        ] {
            assert_eq!(band.meets(m(lo), m(hi)), meets, "[{lo}, {hi}]");
            assert_eq!(band.meets(m(hi), m(lo)), meets, "[{hi}, {lo}] reversed");
        }
        assert!(VerticalLimits::agl(None, Some(m(60))).meets(m(60), m(70)));
        assert!(!VerticalLimits::agl(Some(m(71)), None).meets(m(60), m(70)));
        // An inverted band is empty.
        let empty = VerticalLimits::agl(Some(m(60)), Some(m(30)));
        assert!(!empty.contains(m(45)) && !empty.meets(m(0), m(100)));
    }

    #[test]
    fn bands_are_described_for_people() {
        let amsl = |x| VerticalLimit {
            height: m(x),
            reference: VerticalReference::Amsl,
        };
        let cases = [
            (VerticalLimits::WHOLE_SKY, "whole sky"),
            (VerticalLimits::agl(Some(m(0)), Some(m(60))), "0–60 m AGL"),
            (VerticalLimits::agl(None, Some(m(60))), "up to 60 m AGL"),
            (
                VerticalLimits {
                    lower: Some(amsl(30)),
                    upper: None,
                },
                "from 30 m AMSL up",
            ),
            (
                VerticalLimits {
                    lower: Some(VerticalLimit::agl(m(0))),
                    upper: Some(VerticalLimit {
                        height: Metres::from_um(121_920_000),
                        reference: VerticalReference::Wgs84,
                    }),
                },
                "0 m AGL – 121.92 m WGS84",
            ),
        ];
        for (band, text) in cases {
            assert_eq!(band.to_string(), text);
        }
    }
}
