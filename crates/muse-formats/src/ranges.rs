//! The accepted range of every numeric parameter and option in user units, in one table:
//! the command line's options (`--speed-kmh`, `--count`, `--header-timeout-s`, …), the Python
//! package's keywords (`speed_kmh=`, …) and the planning service's HTTP timeouts refuse the
//! same values with the same words, `must be a speed in km/h from 1 to 1000`. The command
//! line's value parsers (`src/cli/ranges.rs`) and the libraries' own bounds
//! (`muse_sim::demand::MAX_REQUESTS`, the synthetic airspace's node count and spacing) are
//! read from here.
//!
//! ```
//! use muse_formats::ranges::SPEED_KMH;
//! assert_eq!(SPEED_KMH.parse("45"), Ok(45.0));
//! assert_eq!(SPEED_KMH.check(0.0), Err("must be a speed in km/h from 1 to 1000".to_owned()));
//! ```

use std::fmt::Display;
use std::str::FromStr;
use std::time::Duration;

use crate::params::{Field, ParamsError, ParamsRecord};

/// A number a parameter can take: parsed from text, compared, shown.
pub trait Number: FromStr + PartialOrd + Display + Copy {
    /// Whether the value is a finite number (always, for integers).
    fn is_finite_number(self) -> bool;
}

impl Number for f64 {
    fn is_finite_number(self) -> bool {
        self.is_finite()
    }
}

macro_rules! integer_number {
    ($($t:ty),*) => {$(
        impl Number for $t {
            fn is_finite_number(self) -> bool {
                true
            }
        }
    )*};
}
integer_number!(u32, u64, usize);

/// The values `lo..=hi` of a parameter, and what they are (`a speed in km/h`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range<T> {
    /// The least value.
    pub lo: T,
    /// The greatest value.
    pub hi: T,
    /// What a value is, for messages.
    pub what: &'static str,
}

impl<T: Number> Range<T> {
    /// `x` if it lies in the range; else `must be {what} from {lo} to {hi}`.
    pub fn check(&self, x: T) -> Result<T, String> {
        if x.is_finite_number() && self.lo <= x && x <= self.hi {
            Ok(x)
        } else {
            Err(self.message())
        }
    }

    /// `text` read as a number in the range; else the message of [`Range::check`].
    pub fn parse(&self, text: &str) -> Result<T, String> {
        let x: T = text.trim().parse().map_err(|_| self.message())?;
        self.check(x)
    }

    /// What a value out of the range is told: `must be {what} from {lo} to {hi}`.
    pub fn message(&self) -> String {
        format!("must be {} from {} to {}", self.what, self.lo, self.hi)
    }
}

impl Range<f64> {
    /// Whether `d` lies in the range, the range being seconds, compared as durations (to the
    /// nanosecond a number of seconds rounds to).
    pub fn contains_duration(&self, d: Duration) -> bool {
        let lo = Duration::try_from_secs_f64(self.lo).unwrap_or(Duration::ZERO);
        let hi = Duration::try_from_secs_f64(self.hi).unwrap_or(Duration::MAX);
        (lo..=hi).contains(&d)
    }

    /// `text`, a number of seconds (`"10"`, `"2.5"`), read as a duration within the range
    /// ([`Range::contains_duration`]); else the message of [`Range::check`].
    ///
    /// ```
    /// use std::time::Duration;
    /// use muse_formats::ranges::TIMEOUT_S;
    /// assert_eq!(TIMEOUT_S.parse_seconds("2.5"), Ok(Duration::from_millis(2_500)));
    /// assert_eq!(TIMEOUT_S.parse_seconds("0.01"), Err("must be a number of seconds from 0.1 to 86400".to_owned()));
    /// ```
    pub fn parse_seconds(&self, text: &str) -> Result<Duration, String> {
        let secs: f64 = text.trim().parse().map_err(|_| self.message())?;
        if !secs.is_finite() {
            return Err(self.message());
        }
        let d = Duration::try_from_secs_f64(secs).map_err(|_| self.message())?;
        if self.contains_duration(d) {
            Ok(d)
        } else {
            Err(self.message())
        }
    }
}

// The flight model and the layering: the command line's options, the Python package's
// keywords and a summary's recorded parameters.

/// Cruise speed, km/h.
pub const SPEED_KMH: Range<f64> = Range {
    lo: 1.0,
    hi: 1_000.0,
    what: "a speed in km/h",
};
/// Battery limit, minutes: up to a day.
pub const MAX_FLIGHT_MIN: Range<f64> = Range {
    lo: 1.0,
    hi: 1_440.0,
    what: "a number of minutes",
};
/// Node separation and headway, seconds: up to an hour.
pub const SEPARATION_S: Range<f64> = Range {
    lo: 0.0,
    hi: 3_600.0,
    what: "a number of seconds",
};
/// Ground delay and battery swap time, seconds: up to a day.
pub const DAY_S: Range<f64> = Range {
    lo: 0.0,
    hi: 86_400.0,
    what: "a number of seconds",
};
/// Legs of a trip with battery swaps.
pub const MAX_LEGS: Range<u32> = Range {
    lo: 1,
    hi: 100,
    what: "a whole number of legs",
};
/// A delivery deadline, minutes: at least a minute, at most a day.
pub const MAX_TRIP_MIN: Range<f64> = Range {
    lo: 1.0,
    hi: 1_440.0,
    what: "a number of minutes",
};
/// Cruise layers.
pub const LAYERS: Range<u32> = Range {
    lo: 1,
    hi: muse_model::Layers::MAX_COUNT,
    what: "a whole number of layers",
};
/// Altitude of layer 1, metres.
pub const BASE_ALTITUDE_M: Range<f64> = Range {
    lo: 0.0,
    hi: 10_000.0,
    what: "a number of metres",
};
/// Spacing between layers, metres.
pub const LAYER_SPACING_M: Range<f64> = Range {
    lo: 0.001,
    hi: 1_000.0,
    what: "a number of metres",
};
/// Vertical speed, metres per second.
pub const CLIMB_MPS: Range<f64> = Range {
    lo: 0.001,
    hi: 100.0,
    what: "a number of metres per second",
};

// Demand, seeds and synthetic airspaces.

/// Requests of one day (`--count`, `--counts`, `--requests`): at most ten million.
pub const REQUESTS: Range<usize> = Range {
    lo: 1,
    hi: 10_000_000,
    what: "a whole number of requests",
};
/// Requests `muse load` sends (`muse load --count`): as a day's.
pub const LOAD_COUNT: Range<u64> = Range {
    lo: REQUESTS.lo as u64,
    hi: REQUESTS.hi as u64,
    what: REQUESTS.what,
};
/// Seeds: any 64-bit number.
pub const SEED: Range<u64> = Range {
    lo: 0,
    hi: u64::MAX,
    what: "a whole number",
};
/// Nodes of a synthetic airspace (`--nodes`).
pub const NODES: Range<usize> = Range {
    lo: 2,
    hi: 1_000_000,
    what: "a whole number of nodes",
};
/// Spacing of a synthetic airspace, metres (`--spacing-m`).
pub const SPACING_M: Range<f64> = Range {
    lo: 1.0,
    hi: 100_000.0,
    what: "a number of metres",
};
/// Share of a synthetic airspace's nodes that are stations (`--station-share`).
pub const STATION_SHARE: Range<f64> = Range {
    lo: 0.001,
    hi: 1.0,
    what: "a share",
};
/// Longest corridor of an airspace built from pads, metres (`muse airspace build
/// --max-corridor-m`): up to 1,000 km.
pub const MAX_CORRIDOR_M: Range<f64> = Range {
    lo: 1.0,
    hi: 1_000_000.0,
    what: "a number of metres",
};
/// A horizontal separation between flights, metres (`muse airspace info --separation-m`,
/// docs/reference.md#metric-separation): up to 1 km.
pub const SEPARATION_M: Range<f64> = Range {
    lo: 0.0,
    hi: 1_000.0,
    what: "a number of metres",
};
/// The last mile, metres: a customer is served by its nearest pad within it
/// (`--last-mile-m`): up to 100 km.
pub const LAST_MILE_M: Range<f64> = Range {
    lo: 0.0,
    hi: 100_000.0,
    what: "a number of metres",
};
/// Minutes of a lead or a swap time in a list option (`--leads`, `--swap-min`, booking and
/// load leads): from 0 to 30 days.
pub const LEAD_MIN: Range<f64> = Range {
    lo: 0.0,
    hi: 43_200.0,
    what: "a number of minutes",
};

// Siting, sweeps, the optimiser, maps and threads.

/// Pads `muse siting` adds (`--add`).
pub const ADD_PADS: Range<usize> = Range {
    lo: 1,
    hi: 1_000,
    what: "a whole number of pads",
};
/// Days `muse siting` simulates (`--days`).
pub const SITING_DAYS: Range<usize> = Range {
    lo: 1,
    hi: 1_000,
    what: "a whole number of days",
};
/// Repetitions of a sweep (`muse sweep --reps`).
pub const REPS: Range<usize> = Range {
    lo: 1,
    hi: 10_000,
    what: "a whole number of repetitions",
};
/// Threads (`--threads`).
pub const THREADS: Range<usize> = Range {
    lo: 1,
    hi: 1_024,
    what: "a whole number of threads",
};
/// Steps of the optimiser (`--iterations`).
pub const ITERATIONS: Range<u64> = Range {
    lo: 0,
    hi: 1_000_000_000,
    what: "a whole number of steps",
};
/// Time the optimiser may take, seconds (`--time-budget-s`): up to a day.
pub const TIME_BUDGET_S: Range<f64> = Range {
    lo: 0.001,
    hi: 86_400.0,
    what: "a number of seconds",
};
/// Orders the optimiser restarts from (`--restarts`).
pub const RESTARTS: Range<u32> = Range {
    lo: 0,
    hi: 10_000,
    what: "a whole number of orders",
};
/// Chance the optimiser keeps a worse order (`--anneal`).
pub const ANNEAL: Range<f64> = Range {
    lo: 0.0,
    hi: 1.0,
    what: "a chance",
};
/// Flights the optimiser moves at once (`--neighbourhood`).
pub const NEIGHBOURHOOD: Range<usize> = Range {
    lo: 1,
    hi: 1_000,
    what: "a whole number of flights",
};
/// Violations `muse verify` lists (`--max-listed`).
pub const MAX_LISTED: Range<usize> = Range {
    lo: 0,
    hi: 1_000_000,
    what: "a whole number of violations",
};
/// Width of a map, pixels (`muse airspace map --width`).
pub const WIDTH_PX: Range<u32> = Range {
    lo: 100,
    hi: 20_000,
    what: "a whole number of pixels",
};

// The planning service and its load generator.

/// How far ahead bookings open, days (`muse serve --booking-horizon-days`): up to ten years.
pub const BOOKING_HORIZON_DAYS: Range<u32> = Range {
    lo: 1,
    hi: 3_650,
    what: "a whole number of days",
};
/// After how many whole days landed flights are archived (`muse serve
/// --archive-after-days`): up to ten years.
pub const ARCHIVE_AFTER_DAYS: Range<u32> = Range {
    lo: 1,
    hi: 3_650,
    what: "a whole number of days",
};
/// How long requests are gathered into one batch, milliseconds (`muse serve
/// --batch-window-ms`): up to 10 s.
pub const BATCH_WINDOW_MS: Range<u64> = Range {
    lo: 0,
    hi: 10_000,
    what: "a whole number of milliseconds",
};
/// How many of the last flights and events a start checks whole (`muse serve --check-recent`).
pub const CHECK_RECENT: Range<u64> = Range {
    lo: 0,
    hi: 1_000_000_000,
    what: "a whole number of flights",
};
/// Largest request body, KiB (`muse serve --max-body-kib`): up to 1 MiB.
pub const MAX_BODY_KIB: Range<usize> = Range {
    lo: 1,
    hi: 1_024,
    what: "a whole number of KiB",
};
/// Requests per second per token (`muse serve --rate-limit`; 0: no limit).
pub const RATE_LIMIT: Range<f64> = Range {
    lo: 0.0,
    hi: 1_000_000.0,
    what: "a number of requests per second",
};
/// Burst above the rate (`muse serve --burst`).
pub const BURST: Range<f64> = Range {
    lo: 1.0,
    hi: 1_000_000.0,
    what: "a number of requests",
};
/// Connections open at once (`muse serve --max-connections`); the service itself takes any
/// number from the least up.
pub const MAX_CONNECTIONS: Range<usize> = Range {
    lo: 1,
    hi: 1_000_000,
    what: "a whole number of connections",
};
/// The service's HTTP timeouts (`muse serve --header-timeout-s`, `--body-timeout-s`,
/// `--idle-timeout-s`, checked again by the service) and `muse load --timeout`, seconds: up
/// to a day.
pub const TIMEOUT_S: Range<f64> = Range {
    lo: 0.1,
    hi: 86_400.0,
    what: "a number of seconds",
};
/// Requests per second `muse load` sends (`--rate`).
pub const LOAD_RATE: Range<f64> = Range {
    lo: 0.01,
    hi: 1_000_000.0,
    what: "a number of requests per second",
};
/// Clients of `muse load` (`--clients`).
pub const CLIENTS: Range<usize> = Range {
    lo: 1,
    hi: 100_000,
    what: "a whole number of clients",
};
/// How long `muse load` runs, seconds (`--duration`): up to a day.
pub const DURATION_S: Range<f64> = Range {
    lo: 1.0,
    hi: 86_400.0,
    what: "a number of seconds",
};
/// Requests `muse load` keeps in flight at once (`--max-in-flight`).
pub const MAX_IN_FLIGHT: Range<usize> = Range {
    lo: 1,
    hi: 1_000_000,
    what: "a whole number of requests",
};

impl ParamsRecord {
    /// Checks every member against its range (those the command line's options accept).
    ///
    /// ```
    /// use muse_formats::params::{Field, ParamsRecord};
    /// let mut r = ParamsRecord::from(&muse_model::FlightParams::default());
    /// assert!(r.check_ranges().is_ok());
    /// r.speed_kmh = 5_000.0;
    /// let e = r.check_ranges().unwrap_err();
    /// assert_eq!(e.to_string(), "speed_kmh: 5000 must be a speed in km/h from 1 to 1000");
    /// ```
    pub fn check_ranges(&self) -> Result<(), ParamsError> {
        let check = |field: Field, range: Range<f64>, x: f64| {
            range.check(x).map(|_| ()).map_err(|problem| ParamsError {
                field,
                problem: format!("{x} {problem}"),
            })
        };
        check(Field::SpeedKmh, SPEED_KMH, self.speed_kmh)?;
        check(Field::MaxFlightMin, MAX_FLIGHT_MIN, self.max_flight_min)?;
        check(Field::NodeSeparationS, SEPARATION_S, self.node_separation_s)?;
        if let Some(h) = self.headway_s {
            check(Field::HeadwayS, SEPARATION_S, h)?;
        }
        check(Field::MaxGroundDelayS, DAY_S, self.max_ground_delay_s)?;
        if let Some(s) = self.battery_swap_s {
            check(Field::BatterySwapS, DAY_S, s)?;
        }
        if let Some(k) = self.max_legs {
            check(Field::MaxLegs, MAX_LEGS_F64, f64::from(k))?;
        }
        if let Some(m) = self.max_trip_min {
            check(Field::MaxTripMin, MAX_TRIP_MIN, m)?;
        }
        if let Some(d) = self.separation_m {
            check(Field::SeparationM, SEPARATION_M, d)?;
        }
        if let Some(v) = self.vertical_separation_m {
            check(Field::VerticalSeparationM, SEPARATION_M, v)?;
        }
        Ok(())
    }
}

/// [`MAX_LEGS`] as numbers, to check a count the same way as the other members.
const MAX_LEGS_F64: Range<f64> = Range {
    lo: MAX_LEGS.lo as f64,
    hi: MAX_LEGS.hi as f64,
    what: MAX_LEGS.what,
};
