//! No-fly zones: an area and/or explicit nodes and edges, closed during time periods.
//!
//! This is the data model, with the polygons of a zone's area ([`zone_area_polygons`], a
//! circle as a geodesic polygon by [`circle_polygon`]) that the map, the viewer and the CLI
//! draw; reading ED-318 / ED-269 files lives in `muse-formats`, and turning zones into
//! per-element closure windows lives in `muse-airspace`.

use geo::{Destination, Geodesic};
use geo_types::{LineString, MultiPolygon, Point, Polygon};

use crate::coords::LonLat;
use crate::time::{Instant, Millis, UtcOffset};

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
    /// When the zone becomes known (SPEC §11): it binds every stay and traversal that begins
    /// at or after this instant, and none that begins before. `None`: known from the start.
    pub announced: Option<Instant>,
    /// When an announced zone was withdrawn (SPEC §11, as a service lists it): from this
    /// instant on it binds nothing, so it binds only the stays and traversals that begin in
    /// `[announced, withdrawn)`. `None`: never withdrawn.
    pub withdrawn: Option<Instant>,
}

impl Zone {
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
}
