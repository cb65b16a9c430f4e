//! Typed units: cruise speed and the exact edge traversal time.

use crate::time::Millis;

/// A cruise speed. Stored as an exact integer number of micrometres per hour so that the
/// traversal time `w(e) = ceil(length_m * 1000 / v_mps)` ms (SPEC §3) is computed exactly, in
/// integers, for any length given to the micrometre and any speed given to 10⁻⁹ km/h.
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
