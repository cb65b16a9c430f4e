//! Layered airspace (docs/reference.md#layered-airspace): the corridor graph flown at several
//! cruise altitudes, joined by vertical links at every node, with an optional heading rule per
//! layer.

use std::fmt;

use crate::coords::LonLat;
use crate::time::Millis;
use crate::units::Metres;

/// Which corridor directions a layer may be flown in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HeadingRule {
    /// Every direction at every layer.
    #[default]
    None,
    /// Layer `k` of `L` only for initial bearings in `[(k−1)·360/L, k·360/L)` degrees
    /// (`L` = 2: the semicircular rule; 4: quadrantal; 8: 45° bins).
    Sectors,
}

impl HeadingRule {
    /// The name used on the command line and in summaries: `none` or `sectors`.
    pub const fn name(self) -> &'static str {
        match self {
            HeadingRule::None => "none",
            HeadingRule::Sectors => "sectors",
        }
    }

    /// The rule named `name` (`none` or `sectors`).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "none" => Some(HeadingRule::None),
            "sectors" => Some(HeadingRule::Sectors),
            _ => None,
        }
    }
}

impl fmt::Display for HeadingRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a layering is refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LayersError {
    /// The number of layers is out of range.
    #[error("{0} layers: give 1 to {max}", max = Layers::MAX_COUNT)]
    Count(u32),
    /// The spacing between layers is not positive.
    #[error("layer spacing {0} m: it must be more than 0")]
    Spacing(Metres),
    /// The vertical speed is not positive.
    #[error("vertical speed {0} mm/s: it must be more than 0")]
    Climb(u32),
}

/// How the airspace is layered (docs/reference.md#layered-airspace). `count` = 1 is the flat
/// airspace of #airspace to #multi-leg-trips.
///
/// ```
/// use muse_model::{HeadingRule, Layers, Metres, Millis};
/// let layers = Layers { count: 4, heading_rule: HeadingRule::Sectors, ..Layers::default() };
/// assert_eq!(layers.altitude(1), Metres::from_mm(60_000));
/// assert_eq!(layers.altitude(3), Metres::from_mm(60_000 + 2 * 9_144));
/// // 9.144 m at 5 m/s, rounded up to the millisecond.
/// assert_eq!(layers.climb_time(), Millis(1_829));
/// // Quadrantal: layer 2 is flown eastward to south (90° to 180°).
/// assert!(layers.allows(2, 90.0) && layers.allows(2, 179.9) && !layers.allows(2, 180.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Layers {
    /// Number of cruise layers `L`.
    pub count: u32,
    /// Altitude of layer 1, `h_1`.
    pub base: Metres,
    /// Spacing between consecutive layers, `Δ`.
    pub spacing: Metres,
    /// Vertical speed `c`, in millimetres per second.
    pub climb_mm_per_s: u32,
    /// Which directions each layer may be flown in.
    pub heading_rule: HeadingRule,
}

impl Default for Layers {
    /// One layer (flat) at 60 m; when layered, 9.144 m (30 ft) apart, climbing at 5 m/s,
    /// no heading rule.
    fn default() -> Self {
        Layers {
            count: 1,
            base: Metres::from_mm(60_000),
            spacing: Metres::from_mm(9_144),
            climb_mm_per_s: 5_000,
            heading_rule: HeadingRule::None,
        }
    }
}

impl Layers {
    /// The most layers accepted.
    pub const MAX_COUNT: u32 = 64;

    /// Checks the values: 1 to [`Layers::MAX_COUNT`] layers, positive spacing and speed.
    ///
    /// # Errors
    /// The first value out of range.
    pub fn validate(&self) -> Result<(), LayersError> {
        if !(1..=Self::MAX_COUNT).contains(&self.count) {
            return Err(LayersError::Count(self.count));
        }
        if self.spacing <= Metres::ZERO {
            return Err(LayersError::Spacing(self.spacing));
        }
        if self.climb_mm_per_s == 0 {
            return Err(LayersError::Climb(self.climb_mm_per_s));
        }
        Ok(())
    }

    /// Whether there is more than one layer.
    pub fn is_layered(&self) -> bool {
        self.count > 1
    }

    /// Altitude of layer `k` (1-based): `h_1 + (k − 1)·Δ`.
    pub fn altitude(&self, k: u32) -> Metres {
        Metres::from_um(self.base.um() + i64::from(k.saturating_sub(1)) * self.spacing.um())
    }

    /// Time to cross one vertical link: `ceil(Δ_mm · 1000 / c_mm_per_s)` ms, in integers.
    pub fn climb_time(&self) -> Millis {
        let rate = i64::from(self.climb_mm_per_s.max(1));
        // Δ in µm over c in mm/s is ms.
        Millis((self.spacing.um() + rate - 1).div_euclid(rate))
    }

    /// Whether layer `k` may be flown on a corridor direction of initial bearing `degrees`
    /// (in `[0, 360)`).
    pub fn allows(&self, k: u32, degrees: f64) -> bool {
        match self.heading_rule {
            HeadingRule::None => true,
            HeadingRule::Sectors => {
                let width = 360.0 / f64::from(self.count);
                let low = f64::from(k - 1) * width;
                let high = f64::from(k) * width;
                degrees >= low && (degrees < high || k == self.count && degrees < 360.0)
            }
        }
    }
}

/// Initial bearing from `a` to `b` on the sphere, in degrees in `[0, 360)`
/// (docs/reference.md#layered-airspace): `θ = atan2(sin Δλ·cos φ2, cos φ1·sin φ2 − sin φ1·cos
/// φ2·cos Δλ)`.
///
/// ```
/// use muse_model::{LonLat, layers::bearing};
/// let here = LonLat::new(103.8, 1.3);
/// assert!((bearing(here, LonLat::new(103.9, 1.3)) - 90.0).abs() < 0.01);
/// assert!((bearing(here, LonLat::new(103.8, 1.2)) - 180.0).abs() < 1e-9);
/// assert!((bearing(here, LonLat::new(103.7, 1.3)) - 270.0).abs() < 0.01);
/// ```
pub fn bearing(a: LonLat, b: LonLat) -> f64 {
    let (p1, p2) = (a.lat.to_radians(), b.lat.to_radians());
    let dl = (b.lon - a.lon).to_radians();
    let y = dl.sin() * p2.cos();
    let x = p1.cos() * p2.sin() - p1.sin() * p2.cos() * dl.cos();
    let deg = y.atan2(x).to_degrees();
    let wrapped = deg.rem_euclid(360.0);
    if wrapped >= 360.0 { 0.0 } else { wrapped }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sectors_cover_the_circle_once() {
        for count in [1, 2, 3, 4, 7, 8] {
            let layers = Layers {
                count,
                heading_rule: HeadingRule::Sectors,
                ..Layers::default()
            };
            for tenth in 0..3600 {
                let deg = f64::from(tenth) / 10.0;
                let n = (1..=count).filter(|&k| layers.allows(k, deg)).count();
                assert_eq!(n, 1, "{count} layers, {deg}°");
            }
        }
        let none = Layers {
            count: 4,
            ..Layers::default()
        };
        assert!((1..=4).all(|k| none.allows(k, 123.0)));
    }

    #[test]
    fn climb_time_rounds_up_in_integers() {
        let l = |mm, rate| Layers {
            spacing: Metres::from_mm(mm),
            climb_mm_per_s: rate,
            ..Layers::default()
        };
        assert_eq!(l(9_144, 5_000).climb_time(), Millis(1_829));
        assert_eq!(l(10_000, 5_000).climb_time(), Millis(2_000));
        assert_eq!(l(1, 3_000).climb_time(), Millis(1));
    }

    #[test]
    fn out_of_range_values_are_refused() {
        let bad = |l: Layers| l.validate().unwrap_err().to_string();
        assert!(
            bad(Layers {
                count: 0,
                ..Layers::default()
            })
            .contains("give 1 to 64")
        );
        assert!(
            bad(Layers {
                count: 65,
                ..Layers::default()
            })
            .contains("65 layers")
        );
        let flat = Layers {
            spacing: Metres::ZERO,
            ..Layers::default()
        };
        assert!(bad(flat).contains("spacing"));
        let stuck = Layers {
            climb_mm_per_s: 0,
            ..Layers::default()
        };
        assert!(bad(stuck).contains("vertical speed"));
        assert!(Layers::default().validate().is_ok());
    }
}
