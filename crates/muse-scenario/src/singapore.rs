//! The Singapore default scenario `singapore-77` (docs/reference.md#built-in-scenarios): building
//! it from the embedded source data, and loading the committed, generated files.

use std::sync::LazyLock;

use muse_airspace::builder::{BuildOptions, build_airspace};
use muse_airspace::plane::Plane;
use muse_model::time::parse_clock;
use muse_model::{
    Airspace, DailyWindow, LonLat, Node, NodeKind, Period, UtcOffset, Weekday, Zone, ZoneArea,
};

use crate::carparks::multi_storey_car_parks;
use crate::land::downtown_core;
use crate::stations::select_stations;
use crate::{AIRSPACE_GEOJSON, CBD_ZONE_GEOJSON, STADIUM_ZONE_GEOJSON, ScenarioError};

/// The scenario's name, also the folder of its files: `scenarios/singapore-77/`.
pub const SINGAPORE_77: &str = "singapore-77";

/// Number of stations.
pub const STATION_COUNT: usize = 77;

/// The k-means seed of the station selection.
pub const KMEANS_SEED: u64 = 77;

/// Decimal places of the station coordinates (10⁻⁷° ≈ 1 cm).
pub const COORDINATE_DECIMALS: i32 = 7;

/// Identifier of the CBD no-fly zone.
pub const CBD_ZONE_ID: &str = "SG-CBD-DOWNTOWN-CORE";

/// Name of the CBD no-fly zone.
pub const CBD_ZONE_NAME: &str = "Downtown Core (CBD) no-fly zone 10:00–12:00";

/// File name of the generated airspace inside `scenarios/singapore-77/`.
pub const AIRSPACE_FILE: &str = "airspace.geojson";

/// File name of the generated zone file inside `scenarios/singapore-77/`.
pub const CBD_ZONE_FILE: &str = "cbd_zone.geojson";

/// Identifier of the announced National Stadium event zone ([`stadium_zone`]).
pub const STADIUM_ZONE_ID: &str = "SG-NATIONAL-STADIUM-EVENT";

/// File name of the hand-written stadium zone file inside `scenarios/singapore-77/`.
pub const STADIUM_ZONE_FILE: &str = "stadium_zone.geojson";

/// The generated files of a scenario, as text (each ends with a newline).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BuiltFiles {
    /// The airspace `GeoJSON` (`airspace.geojson`).
    pub airspace_geojson: String,
    /// The no-fly zones in the ED-318 `GeoJSON` profile (`cbd_zone.geojson`).
    pub zones_geojson: String,
}

/// A ready-to-run scenario: airspace, zones and the day they are planned on.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// Name, e.g. `singapore-77`.
    pub name: String,
    /// A one-line description, e.g. for map titles: `Singapore, 77 HDB car-park stations`.
    pub title: String,
    /// The airspace.
    pub airspace: Airspace,
    /// The no-fly zones.
    pub zones: Vec<Zone>,
    /// The local date of the simulated day.
    pub date: jiff::civil::Date,
    /// The local UTC offset.
    pub offset: UtcOffset,
    /// Whether the scenario is on Singapore's land, so that its outline
    /// ([`singapore_land`](crate::singapore_land)) belongs on maps, with the data
    /// [`ATTRIBUTION`](crate::ATTRIBUTION).
    pub land: bool,
}

/// `v` rounded to [`COORDINATE_DECIMALS`] decimals.
pub(crate) fn round_to_decimals(v: f64) -> f64 {
    let scale = 10_f64.powi(COORDINATE_DECIMALS);
    (v * scale).round() / scale
}

/// The 77 station nodes: the car parks chosen by
/// [`select_stations`] (seed [`KMEANS_SEED`]) among the multi-storey car parks, numbered
/// `S001`… north to south, named `"{car_park_no} {address}"`, at their SVY21 position
/// converted to WGS84 and rounded to [`COORDINATE_DECIMALS`] decimals.
pub fn station_nodes() -> Result<Vec<Node>, ScenarioError> {
    let chosen = select_stations(&multi_storey_car_parks()?, STATION_COUNT, KMEANS_SEED)?;
    chosen
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let p = c.svy21.to_wgs84()?;
            Ok(Node {
                id: format!("S{:03}", i + 1),
                kind: NodeKind::Station,
                name: c.station_name(),
                pos: LonLat::new(round_to_decimals(p.lon), round_to_decimals(p.lat)),
            })
        })
        .collect()
}

/// The Singapore rule (docs/reference.md#built-in-scenarios, #airspace-from-pads):
/// [`build_airspace`]'s defaults in SVY21 (EPSG:3414), the grid the car parks' positions are
/// published in. `muse airspace build --pads P --crs EPSG:3414` builds with the same options.
pub fn singapore_build_options() -> BuildOptions {
    BuildOptions {
        plane: Plane::Epsg(3414),
        ..BuildOptions::default()
    }
}

/// The `singapore-77` airspace built from the source data: [`station_nodes`] joined by
/// [`build_airspace`] with [`singapore_build_options`].
pub fn build_singapore_77_airspace() -> Result<Airspace, ScenarioError> {
    Ok(build_airspace(
        station_nodes()?,
        &singapore_build_options(),
    )?)
}

/// The CBD no-fly zone built from the source data: the URA MP2019 Downtown Core planning
/// area, closed daily (all seven days) 10:00–12:00 `+08:00`, restriction `PROHIBITED`.
/// The zone is in the canonical form of [`muse_formats::zones::normalize`] (coordinates
/// rounded to 7 decimals, about 1 cm), which is exactly what the written file holds.
///
/// ```
/// let zone = muse_scenario::cbd_zone().unwrap();
/// assert_eq!(zone.id, "SG-CBD-DOWNTOWN-CORE");
/// assert_eq!(zone.periods[0].daily[0].days.len(), 7);
/// ```
pub fn cbd_zone() -> Result<Zone, ScenarioError> {
    let clock = |t: &str| parse_clock(t).expect("a valid clock time");
    let zone = Zone {
        id: CBD_ZONE_ID.to_owned(),
        name: CBD_ZONE_NAME.to_owned(),
        restriction: "PROHIBITED".to_owned(),
        area: Some(ZoneArea::Polygons(downtown_core()?)),
        node_ids: Vec::new(),
        edge_ids: Vec::new(),
        announced: None,
        withdrawn: None,
        vertical: muse_model::VerticalLimits::WHOLE_SKY,
        periods: vec![Period {
            start: None,
            end: None,
            daily: vec![DailyWindow {
                days: Weekday::ALL.to_vec(),
                start: clock("10:00"),
                end: clock("12:00"),
                offset: UtcOffset::SINGAPORE,
            }],
        }],
    };
    Ok(muse_formats::zones::normalize(&zone))
}

/// The announced National Stadium event zone, parsed from the embedded
/// `scenarios/singapore-77/stadium_zone.geojson` ([`STADIUM_ZONE_GEOJSON`]): a circle of
/// 1.5 km around the National Stadium, Singapore Sports Hub (lon 103.874222, lat 1.300694),
/// restriction `PROHIBITED`, closed on the scenario's day 2026-01-05 from 15:00 to 18:00
/// `+08:00` and announced at 14:00 `+08:00` (docs/reference.md#zones-announced-during-the-day). It
/// is not one of [`singapore_77`]'s zones: it is offered as a zone to announce during the day.
///
/// ```
/// use muse_model::{Instant, ZoneArea};
/// let zone = muse_scenario::stadium_zone().unwrap();
/// assert_eq!(zone.id, muse_scenario::STADIUM_ZONE_ID);
/// assert_eq!(zone.announced, Some(Instant::parse_rfc3339("2026-01-05T14:00:00+08:00").unwrap()));
/// assert!(matches!(zone.area, Some(ZoneArea::Circle { radius_m, .. }) if radius_m == 1_500.0));
/// assert!(!muse_scenario::singapore_77().zones.contains(&zone));
/// ```
pub fn stadium_zone() -> Result<Zone, ScenarioError> {
    let file = format!("scenarios/{SINGAPORE_77}/{STADIUM_ZONE_FILE}");
    let mut zones = muse_formats::zones::read_zones(STADIUM_ZONE_GEOJSON, &file)?;
    match zones.pop() {
        Some(zone) if zones.is_empty() => Ok(zone),
        _ => Err(ScenarioError::Geo {
            file,
            message: "expected exactly one zone".to_owned(),
        }),
    }
}

/// Builds the files of `scenarios/singapore-77/` from the embedded source data (what
/// `muse airspace build` writes). The result is byte-identical to the committed files
/// ([`AIRSPACE_GEOJSON`], [`CBD_ZONE_GEOJSON`]); a test checks it.
///
/// ```
/// let files = muse_scenario::build_singapore_77().unwrap();
/// assert_eq!(files.airspace_geojson, muse_scenario::AIRSPACE_GEOJSON);
/// assert_eq!(files.zones_geojson, muse_scenario::CBD_ZONE_GEOJSON);
/// ```
pub fn build_singapore_77() -> Result<BuiltFiles, ScenarioError> {
    let airspace = build_singapore_77_airspace()?;
    let zone = cbd_zone()?;
    Ok(BuiltFiles {
        airspace_geojson: muse_formats::airspace_geojson::write_airspace(&airspace),
        zones_geojson: muse_formats::zones::write_ed318(&[zone]),
    })
}

pub(crate) static SINGAPORE_77_SCENARIO: LazyLock<Scenario> = LazyLock::new(|| {
    let path = |file: &str| format!("scenarios/{SINGAPORE_77}/{file}");
    let airspace =
        muse_formats::airspace_geojson::read_airspace(AIRSPACE_GEOJSON, &path(AIRSPACE_FILE))
            .expect("the embedded singapore-77 airspace is valid (checked by the tests)");
    let zones = muse_formats::zones::read_zones(CBD_ZONE_GEOJSON, &path(CBD_ZONE_FILE))
        .expect("the embedded singapore-77 zones are valid (checked by the tests)");
    Scenario {
        name: SINGAPORE_77.to_owned(),
        title: format!("Singapore, {STATION_COUNT} HDB car-park stations"),
        airspace,
        zones,
        date: jiff::civil::date(2026, 1, 5),
        offset: UtcOffset::SINGAPORE,
        land: true,
    }
});

/// The default scenario, parsed from the committed files embedded in the binary: 77
/// stations, the CBD zone, Monday 2026-01-05 at `+08:00`.
///
/// ```
/// let s = muse_scenario::singapore_77();
/// assert_eq!(s.name, "singapore-77");
/// assert_eq!(s.airspace.stations().count(), 77);
/// assert!(s.airspace.is_connected());
/// assert_eq!(s.zones.len(), 1);
/// assert_eq!(s.date.to_string(), "2026-01-05");
/// ```
pub fn singapore_77() -> Scenario {
    SINGAPORE_77_SCENARIO.clone()
}

#[cfg(test)]
mod tests {
    use geo::Intersects;
    use muse_airspace::closures::{Window, closed_elements, resolve, zone_windows};
    use muse_model::{Instant, Millis, NodeId, Svy21};

    use super::*;
    use crate::land::planning_areas;

    /// Where the committed files live.
    fn scenario_dir() -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios")
            .join(SINGAPORE_77)
    }

    /// Regenerates the committed files: `cargo test -p muse-scenario -- --ignored write_files`.
    #[test]
    #[ignore = "writes scenarios/singapore-77/; run by hand after changing the rule"]
    fn write_files() {
        let files = build_singapore_77().unwrap();
        let dir = scenario_dir();
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(AIRSPACE_FILE), files.airspace_geojson).unwrap();
        std::fs::write(dir.join(CBD_ZONE_FILE), files.zones_geojson).unwrap();
    }

    #[test]
    fn rebuilding_gives_the_committed_bytes() {
        let files = build_singapore_77().unwrap();
        assert!(
            files.airspace_geojson == AIRSPACE_GEOJSON,
            "scenarios/singapore-77/airspace.geojson is not what the source data gives; \
             regenerate it with `muse airspace build`"
        );
        assert!(
            files.zones_geojson == CBD_ZONE_GEOJSON,
            "scenarios/singapore-77/cbd_zone.geojson is not what the source data gives; \
             regenerate it with `muse airspace build`"
        );
    }

    #[test]
    fn committed_airspace_is_the_built_one() {
        let built = build_singapore_77_airspace().unwrap();
        let s = singapore_77();
        assert_eq!(
            s.airspace.nodes(),
            built.nodes(),
            "positions survive the round trip exactly"
        );
        assert_eq!(s.airspace.edges(), built.edges());
        assert_eq!(s.date, jiff::civil::date(2026, 1, 5));
        assert_eq!(Weekday::of(s.date), Weekday::Mon);
        assert_eq!(s.offset, UtcOffset::SINGAPORE);
    }

    #[test]
    fn seventy_seven_connected_stations() {
        let a = singapore_77().airspace;
        assert_eq!(a.node_count(), STATION_COUNT);
        assert_eq!(a.stations().count(), STATION_COUNT);
        for (i, n) in a.nodes().iter().enumerate() {
            assert_eq!(n.id, format!("S{:03}", i + 1));
            assert!(!n.name.is_empty());
        }
        assert!(
            a.nodes().windows(2).all(|w| w[0].pos.lat >= w[1].pos.lat),
            "north to south"
        );
        assert!(a.is_connected());
        let mut names: Vec<&str> = a.nodes().iter().map(|n| n.name.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), STATION_COUNT, "distinct car parks");
    }

    /// Twice the signed area of the triangle `p q r`.
    fn orient(p: Svy21, q: Svy21, r: Svy21) -> f64 {
        (q.easting - p.easting) * (r.northing - p.northing)
            - (q.northing - p.northing) * (r.easting - p.easting)
    }

    #[test]
    fn no_two_edges_cross() {
        let air = singapore_77().airspace;
        let grid: Vec<Svy21> = air
            .nodes()
            .iter()
            .map(|n| n.pos.to_svy21().unwrap())
            .collect();
        let at = |n: NodeId| grid[n.index()];
        for (i, e1) in air.edges().iter().enumerate() {
            let (a, b) = (e1.from, e1.to);
            for e2 in &air.edges()[i + 1..] {
                let (c, d) = (e2.from, e2.to);
                if a == c || a == d || b == c || b == d {
                    continue;
                }
                // Proper crossing (or touching): c and d not strictly on one side of a–b,
                // and a and b not strictly on one side of c–d.
                let sides_ab = orient(at(a), at(b), at(c)) * orient(at(a), at(b), at(d));
                let sides_cd = orient(at(c), at(d), at(a)) * orient(at(c), at(d), at(b));
                assert!(
                    sides_ab > 0.0 || sides_cd > 0.0,
                    "edges {} and {} cross (or touch)",
                    e1.id,
                    e2.id
                );
            }
            // No station lies within a metre of an edge it is not an end of.
            let (pa, pb) = (at(a), at(b));
            let len = (pb.easting - pa.easting).hypot(pb.northing - pa.northing);
            for (k, &pn) in grid.iter().enumerate() {
                if k == a.index() || k == b.index() {
                    continue;
                }
                let along = ((pn.easting - pa.easting) * (pb.easting - pa.easting)
                    + (pn.northing - pa.northing) * (pb.northing - pa.northing))
                    / (len * len);
                if (0.0..=1.0).contains(&along) {
                    let dist = orient(pa, pb, pn).abs() / len;
                    assert!(
                        dist > 1.0,
                        "station {} is on edge {}",
                        air.nodes()[k].id,
                        e1.id
                    );
                }
            }
        }
    }

    #[test]
    fn every_station_is_on_land_and_outside_the_cbd() {
        let s = singapore_77();
        let land = crate::singapore_land();
        let Some(ZoneArea::Polygons(cbd)) = &s.zones[0].area else {
            panic!("CBD polygon")
        };
        for n in s.airspace.nodes() {
            let p = geo_types::Point::new(n.pos.lon, n.pos.lat);
            assert!(land.intersects(&p), "{} ({}) is not on land", n.id, n.name);
            assert!(!cbd.intersects(&p), "{} is in the CBD", n.id);
            let area = planning_areas()
                .iter()
                .find(|a| a.area.intersects(&p))
                .unwrap();
            assert_ne!(area.name, "DOWNTOWN CORE");
        }
    }

    #[test]
    fn cbd_zone_matches_the_source() {
        let s = singapore_77();
        let zone = cbd_zone().unwrap();
        assert_eq!(
            s.zones,
            vec![zone.clone()],
            "the committed zone is the built one"
        );
        let Some(ZoneArea::Polygons(area)) = &zone.area else {
            panic!("CBD polygon")
        };
        // The source polygon, to the centimetre (the file keeps 7 decimals).
        let source = crate::land::downtown_core().unwrap();
        let gap = crate::land::max_vertex_gap(area, &source).expect("same structure");
        assert!(gap <= 5.000_001e-8, "{gap}");
        let dt = planning_areas()
            .iter()
            .find(|a| a.name == "DOWNTOWN CORE")
            .unwrap();
        assert!(crate::land::max_vertex_gap(area, &dt.area).unwrap() <= 5.01e-8);
        let window = &zone.periods[0].daily[0];
        assert_eq!((window.start.0, window.end.0), (36_000_000, 43_200_000));
        assert_eq!(window.days, Weekday::ALL.to_vec());
        assert_eq!(window.offset, UtcOffset::SINGAPORE);
        assert_eq!(zone.restriction, "PROHIBITED");
        assert_eq!(zone.name, CBD_ZONE_NAME);
        assert_eq!(zone.id, CBD_ZONE_ID);
    }

    fn t(s: &str) -> Instant {
        Instant::parse_rfc3339(s).unwrap()
    }

    /// The scenario's day, `[00:00, 24:00)` local.
    fn scenario_day(s: &Scenario) -> (Instant, Instant) {
        let from = Instant::at_local(s.date, Millis::ZERO, s.offset);
        (from, from + Millis(86_400_000))
    }

    #[test]
    fn stadium_zone_parses_with_its_announcement_and_window() {
        let zone = stadium_zone().unwrap();
        assert_eq!(zone.id, STADIUM_ZONE_ID);
        assert_eq!(
            zone.name,
            "National Stadium event zone (1.5 km), 15:00–18:00"
        );
        assert_eq!(zone.restriction, "PROHIBITED");
        assert_eq!(
            zone.area,
            Some(ZoneArea::Circle {
                centre: STADIUM,
                radius_m: 1_500.0
            })
        );
        assert!(zone.node_ids.is_empty() && zone.edge_ids.is_empty());
        assert_eq!(zone.announced, Some(t("2026-01-05T14:00:00+08:00")));
        assert_eq!(
            zone.periods,
            [Period {
                start: Some(t("2026-01-05T15:00:00+08:00")),
                end: Some(t("2026-01-05T18:00:00+08:00")),
                daily: vec![],
            }]
        );
        // On the scenario's day: one window, 15:00-18:00 +08:00 = 07:00-10:00 UTC.
        let s = singapore_77();
        let (from, to) = scenario_day(&s);
        assert_eq!(
            zone_windows(&zone, from, to).unwrap(),
            [Window::new(
                t("2026-01-05T07:00:00Z"),
                t("2026-01-05T10:00:00Z")
            )]
        );
        // Canonical: the ED-318 writer's output reads back to the same zone.
        assert_eq!(muse_formats::zones::normalize(&zone), zone);
        let written = muse_formats::zones::write_ed318(std::slice::from_ref(&zone));
        assert_eq!(
            muse_formats::zones::read_zones(&written, "written").unwrap(),
            [zone]
        );
        // Offered as an announced zone: the default scenario keeps the CBD zone alone.
        let ids: Vec<&str> = s.zones.iter().map(|z| z.id.as_str()).collect();
        assert_eq!(ids, [CBD_ZONE_ID]);
    }

    /// The stadium's position (`data/SOURCES.md`, "Points of interest").
    const STADIUM: LonLat = LonLat {
        lon: 103.874_222,
        lat: 1.300_694,
    };

    #[test]
    fn stadium_zone_closes_four_corridors_and_no_station() {
        let s = singapore_77();
        let zone = stadium_zone().unwrap();
        let (nodes, edges) = closed_elements(&s.airspace, &zone).unwrap();
        assert_eq!((nodes.len(), edges.len()), (0, 4));
        let ids: Vec<&str> = edges
            .iter()
            .map(|&e| s.airspace.edge(e).id.as_str())
            .collect();
        assert_eq!(ids, ["S066-S069", "S069-S070", "S069-S076", "S071-S076"]);
        // The nearest station, S069 (KM4 BLK 49A JALAN TIGA), lies just outside the circle.
        let (d, nearest) = s
            .airspace
            .nodes()
            .iter()
            .map(|n| (STADIUM.geodesic_distance_m(n.pos), n.id.as_str()))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap();
        assert_eq!(nearest, "S069");
        assert!((1_505.0..1_515.0).contains(&d), "{d}");

        // With the CBD zone: resolving both is adding the two resolutions.
        let (from, to) = scenario_day(&s);
        let mut c = resolve(&s.airspace, &s.zones, from, to).unwrap();
        c.add(&resolve(&s.airspace, std::slice::from_ref(&zone), from, to).unwrap());
        let both: Vec<Zone> = s.zones.iter().cloned().chain([zone]).collect();
        assert_eq!(c, resolve(&s.airspace, &both, from, to).unwrap());
        assert_eq!(c.closed_node_count(), 0);
        let at = |from: &str, to: &str| Window::new(t(from), t(to));
        let cbd = at("2026-01-05T10:00:00+08:00", "2026-01-05T12:00:00+08:00");
        let event = at("2026-01-05T15:00:00+08:00", "2026-01-05T18:00:00+08:00");
        for (e, id) in edges.iter().zip(ids) {
            // The two corridors to S076 (Kreta Ayer) also cross the Downtown Core.
            let want = if id.ends_with("S076") {
                vec![cbd, event]
            } else {
                vec![event]
            };
            assert_eq!(c.edge(*e), want, "{id}");
        }
    }
}
