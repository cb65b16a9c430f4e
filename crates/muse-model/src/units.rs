//! Typed units: cruise speed and the exact edge traversal time; lengths and heights exact to
//! the micrometre.

use crate::time::Millis;

/// A cruise speed. Stored as an exact integer number of micrometres per hour so that the
/// traversal time `w(e) = ceil(length_m * 1000 / v_mps)` ms
/// (docs/reference.md#flight-model-and-separation) is computed exactly, in integers, for any length
/// given to the micrometre and any speed given to 10⁻⁹ km/h.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Speed {
    um_per_hour: i128,
}

/// Errors from speeds and lengths.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnitError {
    /// A speed that is not a finite positive number.
    #[error("speed {0} km/h must be a finite number > 0")]
    Speed(f64),
    /// A length that is not a finite number within ±[`Metres::MAX_M`] metres.
    #[error("length {0} m must be a finite number between -1e9 and 1e9 m")]
    Length(f64),
}

impl Speed {
    /// The paper's cruise speed, 30 km/h.
    pub const PAPER: Speed = Speed {
        um_per_hour: 30_000_000_000,
    };

    /// A speed in km/h (rounded to 10⁻⁹ km/h).
    ///
    /// ```
    /// use muse_model::Speed;
    /// assert_eq!(Speed::from_kmh(30.0).unwrap(), Speed::PAPER);
    /// assert!(Speed::from_kmh(0.0).is_err());
    /// ```
    pub fn from_kmh(kmh: f64) -> Result<Self, UnitError> {
        if !kmh.is_finite() || kmh <= 0.0 || kmh > 1e6 {
            return Err(UnitError::Speed(kmh));
        }
        let um_per_hour = (kmh * 1e9).round() as i128;
        if um_per_hour <= 0 {
            return Err(UnitError::Speed(kmh));
        }
        Ok(Speed { um_per_hour })
    }

    /// The speed in km/h.
    pub fn kmh(self) -> f64 {
        self.um_per_hour as f64 / 1e9
    }

    /// The speed in metres per second.
    pub fn mps(self) -> f64 {
        self.um_per_hour as f64 / 3.6e9
    }

    /// Time to fly `length_m` metres: `ceil(length_m * 1000 / v_mps)` milliseconds, computed
    /// exactly with the length rounded to the micrometre.
    ///
    /// ```
    /// use muse_model::Speed;
    /// // 1 km at 30 km/h is exactly 2 minutes.
    /// assert_eq!(Speed::PAPER.traversal_time(1_000.0).0, 120_000);
    /// // 1234.5 m at 30 km/h = 148.14 s.
    /// assert_eq!(Speed::PAPER.traversal_time(1_234.5).0, 148_140);
    /// // A micrometre more needs one more millisecond.
    /// assert_eq!(Speed::PAPER.traversal_time(1_000.000_001).0, 120_001);
    /// ```
    pub fn traversal_time(self, length_m: f64) -> Millis {
        let um = (length_m * 1e6).round() as i128;
        // ms = um * 3_600_000 / um_per_hour, rounded up.
        let num = um * 3_600_000;
        let q = num / self.um_per_hour;
        let r = num % self.um_per_hour;
        Millis((q + i128::from(r > 0)) as i64)
    }

    /// Distance flown in `t`, metres (for reports only; never used for timing).
    pub fn distance_m(self, t: Millis) -> f64 {
        self.mps() * t.as_secs_f64()
    }
}

impl Default for Speed {
    fn default() -> Self {
        Speed::PAPER
    }
}

/// A length or a height in metres, held exactly as an integer number of micrometres, so that
/// comparisons are exact and a height in feet (1 ft = 0.3048 m exactly) converts without
/// drift. Ordered by value; displays as a plain number of metres without a unit (`121.92`).
///
/// ```
/// use muse_model::Metres;
/// let ft = Metres::from_ft(400.0).unwrap();
/// assert_eq!(ft, Metres::from_m(121.92).unwrap());
/// assert_eq!(ft.um(), 121_920_000);
/// assert_eq!(ft.to_string(), "121.92");
/// assert!(Metres::from_m(60.0).unwrap() < ft);
/// assert!(Metres::from_m(f64::NAN).is_err());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Metres {
    um: i64,
}

impl Metres {
    /// Zero.
    pub const ZERO: Metres = Metres { um: 0 };

    /// The largest magnitude accepted by [`Metres::from_m`] and [`Metres::from_ft`]: a
    /// million kilometres, far beyond any airspace, well within exact `f64` micrometres.
    pub const MAX_M: f64 = 1e9;

    /// An exact number of micrometres.
    pub const fn from_um(um: i64) -> Self {
        Metres { um }
    }

    /// An exact number of millimetres (saturating beyond ±9.2·10¹² m, far past any height).
    ///
    /// ```
    /// use muse_model::Metres;
    /// assert_eq!(Metres::from_mm(9_144), Metres::from_ft(30.0).unwrap());
    /// ```
    pub const fn from_mm(mm: i64) -> Self {
        Metres {
            um: mm.saturating_mul(1_000),
        }
    }

    /// A number of metres, rounded to the micrometre; an error if it is not finite or beyond
    /// ±[`Metres::MAX_M`].
    pub fn from_m(m: f64) -> Result<Self, UnitError> {
        if !m.is_finite() || m.abs() > Self::MAX_M {
            return Err(UnitError::Length(m));
        }
        Ok(Metres {
            um: (m * 1e6).round() as i64,
        })
    }

    /// A number of feet (1 ft = 0.3048 m exactly), rounded to the micrometre; an error if the
    /// length is not finite or beyond ±[`Metres::MAX_M`] metres.
    pub fn from_ft(ft: f64) -> Result<Self, UnitError> {
        let m = ft * 0.3048;
        if !ft.is_finite() || m.abs() > Self::MAX_M {
            return Err(UnitError::Length(m));
        }
        Ok(Metres {
            um: (ft * 304_800.0).round() as i64,
        })
    }

    /// The exact number of micrometres.
    pub const fn um(self) -> i64 {
        self.um
    }

    /// The length in metres (the nearest `f64`).
    pub fn m(self) -> f64 {
        self.um as f64 / 1e6
    }
}

impl std::fmt::Display for Metres {
    /// The exact decimal number of metres, without trailing zeros: `60`, `121.92`, `-0.5`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sign = if self.um < 0 { "-" } else { "" };
        let abs = self.um.unsigned_abs();
        let (whole, frac) = (abs / 1_000_000, abs % 1_000_000);
        if frac == 0 {
            write!(f, "{sign}{whole}")
        } else {
            let digits = format!("{frac:06}");
            write!(f, "{sign}{whole}.{}", digits.trim_end_matches('0'))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metres_are_exact_and_display_exactly() {
        assert_eq!(Metres::from_ft(1.0).unwrap().um(), 304_800);
        assert_eq!(Metres::from_ft(30.0).unwrap(), Metres::from_mm(9_144));
        assert_eq!(Metres::from_m(0.000_000_4).unwrap(), Metres::ZERO);
        assert_eq!(Metres::from_m(-0.5).unwrap().to_string(), "-0.5");
        assert_eq!(Metres::from_um(1).to_string(), "0.000001");
        assert_eq!(Metres::from_m(60.0).unwrap().to_string(), "60");
        assert!(Metres::from_m(1e10).is_err());
        assert!(Metres::from_ft(f64::INFINITY).is_err());
        assert!(Metres::from_ft(4e9).is_err());
        // What is written is read back to the same micrometre.
        for um in [1, 121_920_000, 999_999_999_999, 304_800 * 12_345 + 7] {
            let m = Metres::from_um(um);
            assert_eq!(Metres::from_m(m.m()).unwrap(), m);
            assert_eq!(Metres::from_m(m.to_string().parse().unwrap()).unwrap(), m);
        }
    }
}
