//! Demand from customers (docs/reference.md#airspace-from-pads): each customer is served by its
//! nearest pad within a last-mile distance (straight line: the geodesic on WGS84), or by none.
//!
//! [`serving_pads`] finds them exactly without comparing every customer with every pad: the
//! stations sorted by latitude, only those whose latitude is within the last mile of the
//! customer's (a degree of latitude is at least 110,574 m long anywhere on WGS84) are
//! measured. Ties go to the station first in the airspace's order.
//!
//! [`trips`] draws the requests between customers, by weight, and turns them into the
//! requests of one airspace: those both of whose customers have a pad in reach, on different
//! pads; the others are [`Unserved`](trips::Unserved).

use muse_model::{Airspace, LonLat, NodeId};

pub mod trips;

/// The shortest length of a degree of latitude on WGS84 (at the equator), metres, a little
/// rounded down.
const MIN_DEGREE_OF_LATITUDE_M: f64 = 110_574.0;

/// A customer's pad: the station and its distance, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServingPad {
    /// The station.
    pub pad: NodeId,
    /// The straight-line (geodesic) distance from the customer, metres.
    pub distance_m: f64,
}

/// For each of `customers`, the nearest station of `airspace` within `last_mile_m` metres
/// (boundary included), or `None` when none is in reach.
///
/// ```
/// use muse_model::{Airspace, LonLat, NodeId};
/// use muse_sim::customers::serving_pads;
/// // A and B, 1 km apart on the equator-ish line of `Airspace::line`.
/// let air = Airspace::line(&[1_000.0]);
/// let a = air.node(NodeId(0)).pos;
/// let near_a = LonLat::new(a.lon + 0.001, a.lat);
/// let far = LonLat::new(a.lon - 0.1, a.lat);
/// let served = serving_pads(&air, &[near_a, far], 500.0);
/// assert_eq!(served[0].map(|s| s.pad), Some(NodeId(0)));
/// assert_eq!(served[1], None);
/// ```
pub fn serving_pads(
    airspace: &Airspace,
    customers: &[LonLat],
    last_mile_m: f64,
) -> Vec<Option<ServingPad>> {
    let stations: Vec<NodeId> = airspace.stations().collect();
    let positions: Vec<LonLat> = stations.iter().map(|&n| airspace.node(n).pos).collect();
    pads_in_reach(&positions, customers, last_mile_m)
        .into_iter()
        .map(|reach| {
            reach.first().map(|&(i, distance_m)| ServingPad {
                pad: stations[i],
                distance_m,
            })
        })
        .collect()
}

/// For each of `customers`, every pad of `pads` within `last_mile_m` metres (boundary
/// included) as `(index into pads, distance in metres)`, nearest first (ties: the lower
/// index). The nearest is the customer's serving pad among these pads; siting keeps the whole
/// list to find a customer's pad among any subset of them.
///
/// ```
/// use muse_model::LonLat;
/// use muse_sim::customers::pads_in_reach;
/// let pads = [LonLat::new(103.80, 1.30), LonLat::new(103.81, 1.30)];
/// let reach = pads_in_reach(&pads, &[LonLat::new(103.807, 1.30)], 1_000.0);
/// let order: Vec<usize> = reach[0].iter().map(|&(i, _)| i).collect();
/// assert_eq!(order, [1, 0]); // 334 m and 779 m away
/// ```
pub fn pads_in_reach(
    pads: &[LonLat],
    customers: &[LonLat],
    last_mile_m: f64,
) -> Vec<Vec<(usize, f64)>> {
    let mut by_lat: Vec<(f64, usize)> = pads.iter().enumerate().map(|(i, p)| (p.lat, i)).collect();
    by_lat.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    // A little more than the last mile in degrees of latitude: never misses a pad.
    let reach = last_mile_m / MIN_DEGREE_OF_LATITUDE_M * 1.000_001 + 1e-9;
    customers
        .iter()
        .map(|&c| {
            let lo = by_lat.partition_point(|s| s.0 < c.lat - reach);
            let hi = by_lat.partition_point(|s| s.0 <= c.lat + reach);
            let mut near: Vec<(usize, f64)> = by_lat[lo..hi]
                .iter()
                .map(|&(_, i)| (i, c.geodesic_distance_m(pads[i])))
                .filter(|&(_, d)| d <= last_mile_m)
                .collect();
            near.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            near
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The nearest station by measuring every one.
    fn brute_force(air: &Airspace, c: LonLat, last_mile_m: f64) -> Option<ServingPad> {
        air.stations()
            .map(|n| ServingPad {
                pad: n,
                distance_m: c.geodesic_distance_m(air.node(n).pos),
            })
            .filter(|s| s.distance_m <= last_mile_m)
            .min_by(|a, b| {
                a.distance_m
                    .total_cmp(&b.distance_m)
                    .then(a.pad.cmp(&b.pad))
            })
    }

    #[test]
    fn the_nearest_pad_in_reach_as_a_brute_force_finds_it() {
        let scenario = grid_airspace();
        for seed in 0..4_u64 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            println!("seed {seed}");
            let customers: Vec<LonLat> = (0..400)
                .map(|_| {
                    LonLat::new(
                        103.6 + 0.45 * rng.random::<f64>(),
                        1.22 + 0.25 * rng.random::<f64>(),
                    )
                })
                .collect();
            for last_mile in [100.0, 1_000.0, 3_000.0] {
                let fast = serving_pads(&scenario, &customers, last_mile);
                for (c, got) in customers.iter().zip(&fast) {
                    assert_eq!(
                        *got,
                        brute_force(&scenario, *c, last_mile),
                        "{c:?} {last_mile}"
                    );
                }
                let served = fast.iter().filter(|s| s.is_some()).count();
                assert!(
                    last_mile < 1_000.0 || served > 0,
                    "some customers are served"
                );
            }
        }
    }

    /// Stations on a grid over Singapore's extent, 2 km apart (no data needed).
    fn grid_airspace() -> Airspace {
        let mut nodes = Vec::new();
        for i in 0..24 {
            for j in 0..14 {
                nodes.push(muse_model::testing::station(
                    &format!("G{i:02}{j:02}"),
                    103.6 + 0.018 * f64::from(i),
                    1.22 + 0.018 * f64::from(j),
                ));
            }
        }
        muse_model::testing::airspace(nodes, Vec::new())
    }
}
