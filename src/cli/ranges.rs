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
//!
//! The ranges themselves are one table, [`muse_formats::ranges`] (which the Python package and
//! the planning service read too); here each is a clap value parser named for its option.

use std::time::Duration;

use muse_formats::ranges::{self as table, Number, Range};

/// Reads `text` as a `T` within `lo..=hi`; the error says `must be {what} from {lo} to {hi}`.
pub fn in_range<T: Number>(text: &str, lo: T, hi: T, what: &'static str) -> Result<T, String> {
    Range { lo, hi, what }.parse(text)
}

/// Declares one parser per option, reading it within its range of the table:
/// `name: type = RANGE;`.
macro_rules! ranges {
    ($($(#[$doc:meta])* $name:ident: $t:ty = $range:ident;)*) => {$(
        $(#[$doc])*
        pub fn $name(text: &str) -> Result<$t, String> {
            table::$range.parse(text)
        }
    )*};
}

/// The most requests of one day (`--count`, `--counts`, `--requests`).
pub const MAX_REQUESTS: usize = table::REQUESTS.hi;

ranges! {
    /// `--speed-kmh`.
    speed_kmh: f64 = SPEED_KMH;
    /// `--max-flight-min`: up to a day.
    max_flight_min: f64 = MAX_FLIGHT_MIN;
    /// `--node-separation-s` and `--headway-s`: up to an hour.
    separation_s: f64 = SEPARATION_S;
    /// `--max-ground-delay-s` and `--battery-swap-s`: up to a day.
    day_s: f64 = DAY_S;
    /// `--max-legs`.
    max_legs: u32 = MAX_LEGS;
    /// `--max-trip-min`: a deadline of at least a minute, at most a day.
    max_trip_min: f64 = MAX_TRIP_MIN;
    /// `--count` of generated demand (`muse demand`, `muse simulate`, `muse bench-case`).
    requests: usize = REQUESTS;
    /// `muse load --count`.
    load_count: u64 = LOAD_COUNT;
    /// Seeds: any 64-bit number.
    seed: u64 = SEED;
    /// `--nodes` of a synthetic airspace.
    nodes: usize = NODES;
    /// `--spacing-m` of a synthetic airspace.
    spacing_m: f64 = SPACING_M;
    /// `muse airspace build --max-corridor-m`: up to 1,000 km.
    max_corridor_m: f64 = MAX_CORRIDOR_M;
    /// `muse siting --add`.
    add_pads: usize = ADD_PADS;
    /// `muse siting --days`.
    siting_days: usize = SITING_DAYS;
    /// `--separation-m`: up to 1 km.
    separation_m: f64 = SEPARATION_M;
    /// `--last-mile-m`: up to 100 km.
    last_mile_m: f64 = LAST_MILE_M;
    /// `--station-share` of a synthetic airspace.
    station_share: f64 = STATION_SHARE;
    /// `muse sweep --reps`.
    reps: usize = REPS;
    /// `--threads`.
    threads: usize = THREADS;
    /// `muse serve --booking-horizon-days`: up to ten years.
    booking_horizon_days: u32 = BOOKING_HORIZON_DAYS;
    /// `muse serve --archive-after-days`: up to ten years.
    archive_after_days: u32 = ARCHIVE_AFTER_DAYS;
    /// `muse serve --batch-window-ms`: up to 10 s.
    batch_window_ms: u64 = BATCH_WINDOW_MS;
    /// `muse serve --check-recent`.
    check_recent: u64 = CHECK_RECENT;
    /// `muse serve --max-body-kib`: up to 1 MiB.
    max_body_kib: usize = MAX_BODY_KIB;
    /// `muse serve --rate-limit` (0: no limit).
    rate_limit: f64 = RATE_LIMIT;
    /// `muse serve --burst`.
    burst: f64 = BURST;
    /// `muse serve --max-connections`.
    max_connections: usize = MAX_CONNECTIONS;
    /// `muse load --rate`.
    load_rate: f64 = LOAD_RATE;
    /// `muse load --clients`.
    clients: usize = CLIENTS;
    /// `muse load --duration`: up to a day.
    duration_s: f64 = DURATION_S;
    /// `muse load --max-in-flight`.
    max_in_flight: usize = MAX_IN_FLIGHT;
    /// `muse load --timeout`: as the service's timeouts.
    timeout_s: f64 = TIMEOUT_S;
    /// `muse verify --max-listed`.
    max_listed: usize = MAX_LISTED;
    /// `--iterations` of the optimiser.
    iterations: u64 = ITERATIONS;
    /// `--time-budget-s` of the optimiser: up to a day.
    time_budget_s: f64 = TIME_BUDGET_S;
    /// `--restarts` of the optimiser.
    restarts: u32 = RESTARTS;
    /// `--anneal` of the optimiser: a chance.
    anneal: f64 = ANNEAL;
    /// `--neighbourhood` of the optimiser.
    neighbourhood: usize = NEIGHBOURHOOD;
    /// `--layers`.
    layers: u32 = LAYERS;
    /// `--base-altitude-m`.
    altitude_m: f64 = BASE_ALTITUDE_M;
    /// `--layer-spacing-m`.
    layer_spacing_m: f64 = LAYER_SPACING_M;
    /// `--climb-mps`.
    climb_mps: f64 = CLIMB_MPS;
    /// `muse airspace map --width`.
    width_px: u32 = WIDTH_PX;
    /// Minutes of a lead (`muse load --lead-min A:B`'s `A` and `B`).
    lead_min: f64 = LEAD_MIN;
}

/// `muse serve --header-timeout-s`, `--body-timeout-s` and `--idle-timeout-s`: seconds read as
/// a duration within the service's timeouts ([`table::TIMEOUT_S`], which the service checks
/// too).
pub fn http_timeout(text: &str) -> Result<Duration, String> {
    table::TIMEOUT_S.parse_seconds(text)
}

/// The most days (request counts × repetitions) a sweep runs.
pub const MAX_SWEEP_DAYS: usize = 1_000_000;

/// The most request counts a sweep compares (`--counts`).
pub const MAX_COUNTS: usize = 1_000;

/// The most values of a list option that multiplies a sweep's runs (`--leads`, `--swap-min`):
/// as the sweep's own levers.
pub const MAX_LIST: usize = muse_sim::experiment::sweep::levers::MAX_LIST;

/// Minutes of a lead or a swap time in a list option (`--leads`, `--swap-min`, booking and
/// load leads): from 0 to 30 days ([`table::LEAD_MIN`]).
pub const MAX_LEAD_MIN: f64 = table::LEAD_MIN.hi;

#[cfg(test)]
mod tests;
