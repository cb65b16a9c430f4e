//! The accepted range of every numeric option: clap value parsers that read a number and
//! refuse anything outside its range — not a number, NaN, infinite, negative, zero where zero
//! means nothing, absurdly large — with a message that states the range, before anything
//! runs or is allocated. clap prints it as ``invalid value '1e12' for '--max-flight-min
//! <MIN>': must be a number of minutes from 1 to 1440`` and exits 2.
//!
//! Every option's `--help` states the same range (`from 1 to 1440`); the tests of this module
//! check that for every option of every command, and that no numeric option is left
//! without a range. Numeric options also take `allow_negative_numbers`, so that `-30` is
//! read as a value (and refused here) rather than as an unknown option.

pub use muse_formats::ranges::Number;
use muse_formats::ranges::{
    BASE_ALTITUDE_M, CLIMB_MPS, DAY_S, LAYER_SPACING_M, LAYERS, MAX_FLIGHT_MIN, MAX_LEGS,
    MAX_TRIP_MIN, REQUESTS, Range, SEED, SEPARATION_S, SPEED_KMH,
};

/// Reads `text` as a `T` within `lo..=hi`; the error says `must be {what} from {lo} to {hi}`.
pub fn in_range<T: Number>(text: &str, lo: T, hi: T, what: &'static str) -> Result<T, String> {
    Range { lo, hi, what }.parse(text)
}

/// Declares one parser per option: `name: type = lo, hi, "what it is";`.
macro_rules! ranges {
    ($($(#[$doc:meta])* $name:ident: $t:ty = $lo:expr, $hi:expr, $what:expr;)*) => {$(
        $(#[$doc])*
        pub fn $name(text: &str) -> Result<$t, String> {
            in_range::<$t>(text, $lo, $hi, $what)
        }
    )*};
}

/// The most requests of one day (`--count`, `--counts`, `--requests`): see
/// [`muse_sim::demand::MAX_REQUESTS`].
pub const MAX_REQUESTS: usize = muse_sim::demand::MAX_REQUESTS;

ranges! {
    /// `--speed-kmh`.
    speed_kmh: f64 = SPEED_KMH.lo, SPEED_KMH.hi, SPEED_KMH.what;
    /// `--max-flight-min`: up to a day.
    max_flight_min: f64 = MAX_FLIGHT_MIN.lo, MAX_FLIGHT_MIN.hi, MAX_FLIGHT_MIN.what;
    /// `--node-separation-s` and `--headway-s`: up to an hour.
    separation_s: f64 = SEPARATION_S.lo, SEPARATION_S.hi, SEPARATION_S.what;
    /// `--max-ground-delay-s` and `--battery-swap-s`: up to a day.
    day_s: f64 = DAY_S.lo, DAY_S.hi, DAY_S.what;
    /// `--max-legs`.
    max_legs: u32 = MAX_LEGS.lo, MAX_LEGS.hi, MAX_LEGS.what;
    /// `--max-trip-min`: a deadline of at least a minute, at most a day.
    max_trip_min: f64 = MAX_TRIP_MIN.lo, MAX_TRIP_MIN.hi, MAX_TRIP_MIN.what;
    /// `--count` of generated demand (`muse demand`, `muse simulate`, `muse bench-case`).
    requests: usize = REQUESTS.lo, REQUESTS.hi, REQUESTS.what;
    /// `muse load --count`.
    load_count: u64 = REQUESTS.lo as u64, REQUESTS.hi as u64, REQUESTS.what;
    /// Seeds: any 64-bit number.
    seed: u64 = SEED.lo, SEED.hi, SEED.what;
    /// `--nodes` of a synthetic airspace.
    nodes: usize = 2, muse_scenario::synthetic::MAX_NODES, "a whole number of nodes";
    /// `--spacing-m` of a synthetic airspace.
    spacing_m: f64 = muse_scenario::synthetic::MIN_SPACING_M, 100_000.0, "a number of metres";
    /// `muse airspace build --max-corridor-m`: up to 1,000 km.
    max_corridor_m: f64 = 1.0, 1_000_000.0, "a number of metres";
    /// `muse siting --add`.
    add_pads: usize = 1, 1_000, "a whole number of pads";
    /// `muse siting --days`.
    siting_days: usize = 1, 1_000, "a whole number of days";
    /// `--last-mile-m`: up to 100 km.
    last_mile_m: f64 = 0.0, 100_000.0, "a number of metres";
    /// `--station-share` of a synthetic airspace.
    station_share: f64 = 0.001, 1.0, "a share";
    /// `muse sweep --reps`.
    reps: usize = 1, MAX_REPS, "a whole number of repetitions";
    /// `--threads`.
    threads: usize = 1, 1_024, "a whole number of threads";
    /// `muse serve --booking-horizon-days`: up to ten years.
    booking_horizon_days: u32 = 1, 3_650, "a whole number of days";
    /// `muse serve --batch-window-ms`: up to 10 s.
    batch_window_ms: u64 = 0, 10_000, "a whole number of milliseconds";
    /// `muse serve --max-body-kib`: up to 1 MiB.
    max_body_kib: usize = 1, 1_024, "a whole number of KiB";
    /// `muse serve --rate-limit` (0: no limit).
    rate_limit: f64 = 0.0, 1_000_000.0, "a number of requests per second";
    /// `muse serve --burst`.
    burst: f64 = 1.0, 1_000_000.0, "a number of requests";
    /// `muse serve --max-connections`.
    max_connections: usize = 1, 1_000_000, "a whole number of connections";
    /// `muse load --rate`.
    load_rate: f64 = 0.01, 1_000_000.0, "a number of requests per second";
    /// `muse load --clients`.
    clients: usize = 1, 100_000, "a whole number of clients";
    /// `muse load --duration`: up to a day.
    duration_s: f64 = 1.0, 86_400.0, "a number of seconds";
    /// `muse load --max-in-flight`.
    max_in_flight: usize = 1, 1_000_000, "a whole number of requests";
    /// `muse load --timeout`: as the service's timeouts.
    timeout_s: f64 = 0.1, 86_400.0, "a number of seconds";
    /// `muse verify --max-listed`.
    max_listed: usize = 0, 1_000_000, "a whole number of violations";
    /// `--iterations` of the optimiser.
    iterations: u64 = 0, 1_000_000_000, "a whole number of steps";
    /// `--time-budget-s` of the optimiser: up to a day.
    time_budget_s: f64 = 0.001, 86_400.0, "a number of seconds";
    /// `--restarts` of the optimiser.
    restarts: u32 = 0, 10_000, "a whole number of orders";
    /// `--anneal` of the optimiser: a chance.
    anneal: f64 = 0.0, 1.0, "a chance";
    /// `--neighbourhood` of the optimiser.
    neighbourhood: usize = 1, 1_000, "a whole number of flights";
    /// `--layers`.
    layers: u32 = LAYERS.lo, LAYERS.hi, LAYERS.what;
    /// `--base-altitude-m`.
    altitude_m: f64 = BASE_ALTITUDE_M.lo, BASE_ALTITUDE_M.hi, BASE_ALTITUDE_M.what;
    /// `--layer-spacing-m`.
    layer_spacing_m: f64 = LAYER_SPACING_M.lo, LAYER_SPACING_M.hi, LAYER_SPACING_M.what;
    /// `--climb-mps`.
    climb_mps: f64 = CLIMB_MPS.lo, CLIMB_MPS.hi, CLIMB_MPS.what;
    /// `muse airspace map --width`.
    width_px: u32 = 100, 20_000, "a whole number of pixels";
}

/// The most repetitions of a sweep (`--reps`).
pub const MAX_REPS: usize = 10_000;

/// The most days (request counts × repetitions) a sweep runs.
pub const MAX_SWEEP_DAYS: usize = 1_000_000;

/// The most request counts a sweep compares (`--counts`).
pub const MAX_COUNTS: usize = 1_000;

/// The most values of a list option that multiplies a sweep's runs (`--leads`, `--swap-min`).
pub const MAX_LIST: usize = 100;

/// Minutes of a lead or a swap time in a list option (`--leads`, `--swap-min`, booking and
/// load leads): from 0 to 30 days.
pub const MAX_LEAD_MIN: f64 = 43_200.0;

#[cfg(test)]
mod tests;
