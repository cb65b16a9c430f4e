//! The accepted range of every flight-model and layering parameter in user units, and of a
//! generated day's request count and seed, in one place: the command line's options
//! (`--speed-kmh`, `--count`, …) and the Python package's keywords (`speed_kmh=`, `count=`, …)
//! refuse the same values with the same words, `must be a speed in km/h from 1 to 1000`.
//!
//! ```
//! use muse_formats::ranges::SPEED_KMH;
//! assert_eq!(SPEED_KMH.parse("45"), Ok(45.0));
//! assert_eq!(SPEED_KMH.check(0.0), Err("must be a speed in km/h from 1 to 1000".to_owned()));
//! ```

use std::fmt::Display;
use std::str::FromStr;

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

    fn message(&self) -> String {
        format!("must be {} from {} to {}", self.what, self.lo, self.hi)
    }
}

/// The most requests of one day (generated, or read from a requests file).
pub const MAX_REQUESTS: usize = 10_000_000;

/// Requests of a generated day (`--count`, Python's `count=`).
pub const REQUESTS: Range<usize> = Range {
    lo: 1,
    hi: MAX_REQUESTS,
    what: "a whole number of requests",
};
/// Seeds: any 64-bit number (`--seed`, Python's `seed=`).
pub const SEED: Range<u64> = Range {
    lo: 0,
    hi: u64::MAX,
    what: "a whole number",
};
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
        Ok(())
    }
}

/// [`MAX_LEGS`] as numbers, to check a count the same way as the other members.
const MAX_LEGS_F64: Range<f64> = Range {
    lo: MAX_LEGS.lo as f64,
    hi: MAX_LEGS.hi as f64,
    what: MAX_LEGS.what,
};
