//! Flight-model parameters (docs/reference.md#flight-model-and-separation), shared by the planner
//! and the verifier.

use crate::airspace::Airspace;
use crate::time::Millis;
use crate::units::{Metres, Speed};

/// How two traversals of the same edge must be separated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EdgeRule {
    /// At most one drone on an edge at a time, whatever the direction (the paper).
    Exclusive,
    /// Opposite directions as `Exclusive`; same direction at least `headway` apart at entry.
    Headway(Millis),
}

impl EdgeRule {
    /// The name used on the command line and in summaries.
    pub const fn name(self) -> &'static str {
        match self {
            EdgeRule::Exclusive => "exclusive",
            EdgeRule::Headway(_) => "headway",
        }
    }
}

/// The flight model: speed, battery, separations and ground delay.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FlightParams {
    /// Cruise speed `v`.
    pub speed: Speed,
    /// Maximum airborne time `T_max` (landing − take-off).
    pub max_flight: Millis,
    /// Node separation `tau`.
    pub node_separation: Millis,
    /// Edge separation rule.
    pub edge_rule: EdgeRule,
    /// Maximum ground delay `G_max` (take-off − requested departure).
    pub max_ground_delay: Millis,
    /// Battery swaps at stations (docs/reference.md#multi-leg-trips): `None` (the paper, the
    /// default) plans single legs only.
    pub battery_swap: Option<BatterySwap>,
    /// A delivery deadline: every trip lands at most this long after its requested
    /// departure, or is rejected (`None`, the default: no deadline). An operator's promise
    /// rather than part of the reference: with battery swaps the time on the ground between legs
    /// is otherwise unbounded, and a saturated airspace answers with trips that wait hours.
    pub max_trip: Option<Millis>,
    /// Metric separation (docs/reference.md#metric-separation): off by default.
    pub separation: Separation,
}

/// Metric separation between flights (docs/reference.md#metric-separation): at every instant
/// two flights are both airborne, at least `horizontal` apart horizontally or at least the
/// vertical separation apart vertically.
///
/// ```
/// use muse_model::{Metres, Separation};
/// assert!(!Separation::OFF.is_on());
/// let s = Separation::horizontal(Metres::from_mm(30_000));
/// assert!(s.is_on());
/// // Unless given, the vertical separation is the layers' spacing.
/// assert_eq!(s.vertical_or(Metres::from_mm(9_144)), Metres::from_mm(9_144));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Separation {
    /// `D`: the least horizontal distance; zero, the default, turns the rule off.
    pub horizontal: Metres,
    /// `V`: the vertical distance that separates two drones whatever their horizontal one
    /// (`None`: the layers' spacing `Δ`).
    pub vertical: Option<Metres>,
}

impl Separation {
    /// No metric separation (every plan as under the time rules alone).
    pub const OFF: Separation = Separation {
        horizontal: Metres::ZERO,
        vertical: None,
    };

    /// `D = horizontal`, `V` the layers' spacing.
    #[must_use]
    pub const fn horizontal(horizontal: Metres) -> Separation {
        Separation {
            horizontal,
            vertical: None,
        }
    }

    /// Whether the rule is on (`D > 0`).
    #[must_use]
    pub fn is_on(self) -> bool {
        self.horizontal > Metres::ZERO
    }

    /// Two altitudes this close to `V` apart count as `V` apart, metres (a micrometre, the
    /// resolution of every height MUSE reads): layers exactly `Δ = V` apart are separated
    /// whatever the rounding of their altitudes. The planner and the verifier both apply it.
    pub const VERTICAL_TOLERANCE_M: f64 = 1e-6;

    /// `V`: the vertical separation given, or `spacing` (the layers' `Δ`).
    #[must_use]
    pub fn vertical_or(self, spacing: Metres) -> Metres {
        self.vertical.unwrap_or(spacing)
    }

    /// `V` on `airspace`: the vertical separation given, or its layers' spacing (the default
    /// layers' when flat).
    ///
    /// ```
    /// use muse_model::{Airspace, Metres, Separation};
    /// let flat = Airspace::line(&[1_000.0]);
    /// assert_eq!(Separation::OFF.vertical_in(&flat), Metres::from_mm(9_144));
    /// ```
    #[must_use]
    pub fn vertical_in(self, airspace: &Airspace) -> Metres {
        self.vertical_or(airspace.layers().copied().unwrap_or_default().spacing)
    }
}

/// Multi-leg trips (docs/reference.md#multi-leg-trips): a plan may land at intermediate stations,
/// stay on the ground at least `time` while the battery is swapped, and take off again with a full
/// battery.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BatterySwap {
    /// Minimum time on the ground between a leg's landing and the next take-off (`S`).
    pub time: Millis,
    /// At most this many legs per trip (`None`: no bound).
    pub max_legs: Option<u32>,
}

impl BatterySwap {
    /// Swaps of `time` with no bound on the legs.
    pub const fn new(time: Millis) -> Self {
        BatterySwap {
            time,
            max_legs: None,
        }
    }

    /// The most legs a trip may have (`u32::MAX` when unbounded).
    pub fn leg_limit(self) -> u32 {
        self.max_legs.unwrap_or(u32::MAX)
    }
}

impl FlightParams {
    /// How long after its requested departure a trip may still be flying, as far as zone
    /// calendars need to be resolved: `G_max + T_max` for single legs, and never more than
    /// the delivery deadline. With battery swaps the
    /// time on the ground between legs has no bound (docs/reference.md#multi-leg-trips), so a trip
    /// is given a week: simulations resolve zone windows that far ahead, and a plan beyond it
    /// (never seen in practice) would be caught by the verifier, which resolves the windows of the
    /// plans it reads.
    ///
    /// ```
    /// use muse_model::{BatterySwap, FlightParams, Millis};
    /// assert_eq!(FlightParams::default().trip_span(), Millis::from_mins(20));
    /// let swaps = FlightParams { battery_swap: Some(BatterySwap::new(Millis::from_mins(5))), ..FlightParams::default() };
    /// assert_eq!(swaps.trip_span(), Millis::from_mins(20 + 7 * 24 * 60));
    /// ```
    pub fn trip_span(&self) -> Millis {
        let single = self.max_ground_delay + self.max_flight;
        let span = match self.battery_swap {
            None => single,
            Some(_) => single + Millis::from_mins(7 * 24 * 60),
        };
        self.max_trip.map_or(span, |m| m.min(span))
    }
}

impl Default for FlightParams {
    /// The paper's parameters: 30 km/h, 20 min, `tau` = 5 s, exclusive edges, no ground delay,
    /// no battery swaps.
    fn default() -> Self {
        FlightParams {
            speed: Speed::PAPER,
            max_flight: Millis::from_mins(20),
            node_separation: Millis::from_secs(5),
            edge_rule: EdgeRule::Exclusive,
            max_ground_delay: Millis::ZERO,
            battery_swap: None,
            max_trip: None,
            separation: Separation::OFF,
        }
    }
}
