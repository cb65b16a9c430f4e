//! The scenario `singapore-all`: every HDB multi-storey car park as a station, with the
//! CBD no-fly zone of `singapore-77`, built at run time from the embedded source data.
//!
//! The rule (see also the [crate documentation](crate)):
//!
//! 1. **Candidates:** the 1,115 rows with `car_park_type` = `MULTI-STOREY CAR PARK`.
//! 2. **Positions:** the SVY21 position converted to WGS84 by `muse-model` and rounded to
//!    7 decimals (about 1 cm), exactly as for `singapore-77`.
//! 3. **Order and ids:** sorted by car-park number (`car_park_no`, byte order; it is unique
//!    in the file); the id is the car-park number (e.g. `ACM`), the name the address
//!    (e.g. `BLK 98A ALJUNIED CRESCENT`).
//! 4. **Shared positions:** when several car parks have the same rounded position, the one
//!    with the lowest car-park number is kept and the others are dropped (two stations
//!    cannot share a pad, and the airspace builder refuses two nodes at one position). The
//!    dropped ones are listed in [`AllStations::dropped`]; in the embedded data there are
//!    **none** ([`SINGAPORE_ALL_DROPPED`] = 0, checked by a test): the two closest car parks
//!    (`BJ15`, `BJ16`) are 18 m apart.
//! 5. **Edges:** [`build_airspace`] with [`singapore_build_options`] (in SVY21), as for
//!    `singapore-77`.
//!
//! Building takes a few milliseconds, so nothing is committed: [`singapore_all`] builds the
//! scenario on first use and keeps it for the life of the process.

use std::sync::OnceLock;

use muse_airspace::builder::build_airspace;
use muse_model::{Airspace, LonLat, Node, NodeKind, UtcOffset};

use crate::ScenarioError;
use crate::carparks::{CarPark, multi_storey_car_parks};
use crate::singapore::{Scenario, cbd_zone, round_to_decimals, singapore_build_options};

/// The scenario's name.
pub const SINGAPORE_ALL: &str = "singapore-all";

/// Number of multi-storey car parks dropped because an earlier one (by car-park number) has
/// the same position: none in the embedded data.
pub const SINGAPORE_ALL_DROPPED: usize = 0;

/// A car park left out of `singapore-all` because another one has the same position.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DroppedCarPark {
    /// The car-park number left out.
    pub number: String,
    /// The car-park number kept at that position (lower than `number`).
    pub kept: String,
}

/// The station nodes of `singapore-all` and the car parks left out.
#[derive(Clone, Debug, PartialEq)]
pub struct AllStations {
    /// One station per kept car park, sorted by car-park number.
    pub nodes: Vec<Node>,
    /// The car parks dropped for sharing a position, in car-park-number order.
    pub dropped: Vec<DroppedCarPark>,
}

/// The stations of `singapore-all` from the given multi-storey car parks, by the rule in
/// the [module documentation](self).
pub fn all_stations_from(car_parks: &[CarPark]) -> Result<AllStations, ScenarioError> {
    let mut sorted: Vec<&CarPark> = car_parks.iter().collect();
    sorted.sort_by(|a, b| a.number.cmp(&b.number));
    let mut nodes: Vec<Node> = Vec::with_capacity(sorted.len());
    let mut dropped = Vec::new();
    // Rounded position (in units of 10⁻⁷°) → index of the node kept there.
    let mut taken: std::collections::HashMap<(i64, i64), usize> =
        std::collections::HashMap::with_capacity(sorted.len());
    for c in sorted {
        let p = c.svy21.to_wgs84()?;
        let pos = LonLat::new(round_to_decimals(p.lon), round_to_decimals(p.lat));
        let key = (
            (pos.lon * 1e7).round() as i64,
            (pos.lat * 1e7).round() as i64,
        );
        if let Some(&kept) = taken.get(&key) {
            dropped.push(DroppedCarPark {
                number: c.number.clone(),
                kept: nodes[kept].id.clone(),
            });
            continue;
        }
        taken.insert(key, nodes.len());
        nodes.push(Node {
            id: c.number.clone(),
            kind: NodeKind::Station,
            name: c.address.clone(),
            pos,
        });
    }
    Ok(AllStations { nodes, dropped })
}

/// The stations of `singapore-all` from the embedded car park list.
///
/// ```
/// let all = muse_scenario::all_stations().unwrap();
/// assert_eq!(all.nodes.len(), 1_115);
/// assert!(all.dropped.is_empty());
/// assert_eq!(all.nodes[0].id, "A101");
/// ```
pub fn all_stations() -> Result<AllStations, ScenarioError> {
    all_stations_from(&multi_storey_car_parks()?)
}

/// The `singapore-all` airspace: [`all_stations`] joined by [`build_airspace`] with
/// [`singapore_build_options`] (SVY21).
pub fn build_singapore_all_airspace() -> Result<Airspace, ScenarioError> {
    Ok(build_airspace(
        all_stations()?.nodes,
        &singapore_build_options(),
    )?)
}

/// Builds the whole `singapore-all` scenario (uncached; see [`singapore_all`]).
pub fn build_singapore_all() -> Result<Scenario, ScenarioError> {
    let airspace = build_singapore_all_airspace()?;
    Ok(Scenario {
        name: SINGAPORE_ALL.to_owned(),
        title: format!(
            "Singapore, all {} HDB multi-storey car parks as stations",
            airspace.stations().count()
        ),
        airspace,
        zones: vec![cbd_zone()?],
        date: jiff::civil::date(2026, 1, 5),
        offset: UtcOffset::SINGAPORE,
        land: true,
    })
}

static SINGAPORE_ALL_SCENARIO: OnceLock<Result<Scenario, ScenarioError>> = OnceLock::new();

/// The `singapore-all` scenario: 1,115 stations, the CBD zone, Monday 2026-01-05 at
/// `+08:00`. Built from the embedded data on first use (a few milliseconds), then cached.
///
/// ```
/// let s = muse_scenario::singapore_all().unwrap();
/// assert_eq!(s.name, "singapore-all");
/// assert_eq!(s.airspace.stations().count(), 1_115);
/// assert!(s.airspace.is_connected());
/// assert_eq!(s.zones.len(), 1);
/// ```
pub fn singapore_all() -> Result<&'static Scenario, ScenarioError> {
    SINGAPORE_ALL_SCENARIO
        .get_or_init(build_singapore_all)
        .as_ref()
        .map_err(Clone::clone)
}

#[cfg(test)]
mod tests {
    use geo::Intersects;
    use muse_model::{Svy21, Weekday, ZoneArea};

    use super::*;
    use crate::carparks::MULTI_STOREY;

    fn car_park(number: &str, e: f64, n: f64) -> CarPark {
        CarPark {
            number: number.to_owned(),
            address: format!("BLK {number}"),
            car_park_type: MULTI_STOREY.to_owned(),
            svy21: Svy21::new(e, n),
        }
    }

    #[test]
    fn every_multi_storey_car_park_is_a_station() {
        let all = all_stations().unwrap();
        assert_eq!(
            all.dropped.len(),
            SINGAPORE_ALL_DROPPED,
            "dropped: {:?}",
            all.dropped
        );
        assert_eq!(all.nodes.len(), 1_115 - SINGAPORE_ALL_DROPPED);
        assert!(all.nodes.windows(2).all(|w| w[0].id < w[1].id), "sorted");
        let s = singapore_all().unwrap();
        let a = &s.airspace;
        assert_eq!(a.node_count(), 1_115);
        assert_eq!(a.stations().count(), 1_115);
        assert!(a.is_connected());
        assert_eq!(a.nodes(), all.nodes.as_slice());
        let acm = &a.nodes()[a.node_id("ACM").unwrap().index()];
        assert_eq!(acm.name, "BLK 98A ALJUNIED CRESCENT");
        // The same car park, at the same position, as in singapore-77.
        let s77 = crate::singapore_77();
        for n in s77.airspace.nodes() {
            let (number, address) = n.name.split_once(' ').unwrap();
            let m = &a.nodes()[a.node_id(number).unwrap().index()];
            assert_eq!((m.name.as_str(), m.pos), (address, n.pos), "{}", n.id);
        }
    }

    #[test]
    fn same_zone_date_and_offset_as_singapore_77() {
        let s = singapore_all().unwrap();
        let s77 = crate::singapore_77();
        assert_eq!(s.zones, s77.zones);
        assert_eq!((s.date, s.offset), (s77.date, s77.offset));
        assert_eq!(Weekday::of(s.date), Weekday::Mon);
        assert!(s.land && s77.land);
        let Some(ZoneArea::Polygons(cbd)) = &s.zones[0].area else {
            panic!("CBD polygon")
        };
        for n in s.airspace.nodes() {
            let p = geo_types::Point::new(n.pos.lon, n.pos.lat);
            assert!(!cbd.intersects(&p), "{} is in the CBD", n.id);
        }
    }

    #[test]
    fn rebuilding_is_deterministic() {
        let a = build_singapore_all_airspace().unwrap();
        let b = &singapore_all().unwrap().airspace;
        assert_eq!(a.nodes(), b.nodes());
        assert_eq!(a.edges(), b.edges());
    }

    #[test]
    fn shared_positions_keep_the_lowest_number() {
        let parks = [
            car_park("B2", 30_000.0, 30_000.0),
            car_park("A1", 31_000.0, 30_000.0),
            car_park("B1", 30_000.0, 30_000.0),
            // 1 mm away: the same position once rounded to 1 cm.
            car_park("A9", 31_000.001, 30_000.0),
            car_park("C1", 30_500.0, 31_000.0),
        ];
        let all = all_stations_from(&parks).unwrap();
        let ids: Vec<&str> = all.nodes.iter().map(|n| n.id.as_str()).collect();
        assert_eq!(ids, ["A1", "B1", "C1"]);
        assert_eq!(
            all.dropped,
            [
                DroppedCarPark {
                    number: "A9".into(),
                    kept: "A1".into()
                },
                DroppedCarPark {
                    number: "B2".into(),
                    kept: "B1".into()
                },
            ]
        );
        let air = build_airspace(all.nodes, &singapore_build_options()).unwrap();
        assert_eq!(air.edge_count(), 3);
    }
}
