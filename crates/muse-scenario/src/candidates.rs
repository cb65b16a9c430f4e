//! Singapore's siting inputs (docs/reference.md#airspace-from-pads): the candidate pads — the
//! multi-storey car parks the 77 stations were not chosen from — and the residential customers,
//! every HDB car park.
//!
//! The HDB car park list stands in for where people live: each car park serves blocks of
//! public housing. It is a proxy, not a demand survey: every car park weighs the same,
//! whatever the number of homes it serves.

use muse_formats::customers::Customer;
use muse_model::{LonLat, Node, NodeKind};

use crate::ScenarioError;
use crate::carparks::{CarPark, car_parks, multi_storey_car_parks};
use crate::singapore::{KMEANS_SEED, STATION_COUNT, round_to_decimals};
use crate::stations::select_stations;

/// A car park's position in WGS84, rounded as station positions are.
fn position(c: &CarPark) -> Result<LonLat, ScenarioError> {
    let p = c.svy21.to_wgs84()?;
    Ok(LonLat::new(
        round_to_decimals(p.lon),
        round_to_decimals(p.lat),
    ))
}

/// The multi-storey car parks that are not among the 77 stations (1,038), in file order, as
/// pads: id the car park number, name its number and address.
///
/// ```
/// let pads = muse_scenario::candidates::candidate_pads().unwrap();
/// assert_eq!(pads.len(), 1_115 - 77);
/// ```
pub fn candidate_pads() -> Result<Vec<Node>, ScenarioError> {
    let all = multi_storey_car_parks()?;
    let stations = select_stations(&all, STATION_COUNT, KMEANS_SEED)?;
    all.iter()
        .filter(|c| !stations.iter().any(|s| s.number == c.number))
        .map(|c| {
            Ok(Node {
                id: c.number.clone(),
                kind: NodeKind::Station,
                name: c.station_name(),
                pos: position(c)?,
            })
        })
        .collect()
}

/// Every HDB car park (2,257) as a customer of weight 1 (see the [module
/// documentation](self)), id the car park number.
///
/// ```
/// let customers = muse_scenario::candidates::residential_customers().unwrap();
/// assert_eq!(customers.len(), 2_257);
/// ```
pub fn residential_customers() -> Result<Vec<Customer>, ScenarioError> {
    car_parks()?
        .iter()
        .map(|c| {
            Ok(Customer {
                id: c.number.clone(),
                pos: position(c)?,
                weight: 1.0,
            })
        })
        .collect()
}
