//! Random small batches: a 2 × 3 grid of stations whose corridors are 400 to 1,200 m long,
//! and requests between random stations departing in the first ten minutes, in whole seconds.

use muse_airspace::closures::Closures;
use muse_model::testing::{airspace, edge, request, station};
use muse_model::{Airspace, BatterySwap, FlightParams, Millis, Request};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One batch to plan.
pub struct Instance {
    pub airspace: Airspace,
    pub params: FlightParams,
    pub requests: Vec<Request>,
}

impl Instance {
    /// The closures of an instance: none.
    pub fn closures(&self) -> Closures {
        Closures::none(&self.airspace)
    }
}

/// The instance of `seed`: `count` requests; with `swaps`, batteries of 3 minutes and swaps
/// of 1 minute (up to 3 legs), so that long trips need two or three legs.
pub fn instance(seed: u64, count: usize, swaps: bool) -> Instance {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let nodes = (0..6)
        .map(|i| {
            station(
                &format!("S{i}"),
                103.80 + 0.01 * f64::from(i % 3),
                1.30 + 0.01 * f64::from(i / 3),
            )
        })
        .collect();
    let mut length = || f64::from(rng.random_range(4..=12_u32)) * 100.0;
    let edges = vec![
        edge(0, 1, length()),
        edge(1, 2, length()),
        edge(3, 4, length()),
        edge(4, 5, length()),
        edge(0, 3, length()),
        edge(1, 4, length()),
        edge(2, 5, length()),
    ];
    let airspace = airspace(nodes, edges);
    let mut params = FlightParams {
        max_ground_delay: Millis::from_secs(i64::from(rng.random_range(0..=2_u32)) * 30),
        ..FlightParams::default()
    };
    if swaps {
        params.max_flight = Millis::from_mins(3);
        params.battery_swap = Some(BatterySwap {
            time: Millis::from_mins(1),
            max_legs: Some(3),
        });
    }
    let requests = (0..count)
        .map(|k| {
            let origin = rng.random_range(0..6_u32);
            let destination = (origin + rng.random_range(1..6_u32)) % 6;
            let departure = i64::from(rng.random_range(0..600_u32)) * 1_000;
            request(&format!("r{k}"), origin, destination, departure)
        })
        .collect();
    Instance {
        airspace,
        params,
        requests,
    }
}
