//! The flight-model parameters in the units a user gives them — km/h, minutes, seconds — as a
//! summary records them, `/healthz` reports them and the command line takes them: one type,
//! [`ParamsRecord`], read and written with serde, and turned into the model's
//! [`FlightParams`] by one function, [`ParamsRecord::to_params`].
//!
//! ```
//! use muse_formats::params::ParamsRecord;
//! let record: ParamsRecord = serde_json::from_str(
//!     r#"{"speed_kmh": 30.0, "max_flight_min": 20.0, "node_separation_s": 5.0,
//!         "edge_rule": "headway", "headway_s": 2.5, "max_ground_delay_s": 0.0}"#,
//! ).unwrap();
//! let params = record.to_params().unwrap();
//! assert_eq!(params.node_separation.0, 5_000);
//! assert_eq!(ParamsRecord::from(&params), record);
//! ```

use std::fmt;

use muse_model::{BatterySwap, EdgeRule, FlightParams, Metres, Millis, Separation, Speed};
use serde::{Deserialize, Serialize};

/// The flight-model parameters in user units (docs/reference.md#flight-model-and-separation,
/// #multi-leg-trips). Read back strictly: a member this version does not know is an error; a
/// missing optional one is `None`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamsRecord {
    /// Cruise speed, km/h.
    pub speed_kmh: f64,
    /// Battery limit, minutes.
    pub max_flight_min: f64,
    /// Node separation τ, seconds.
    pub node_separation_s: f64,
    /// `exclusive` or `headway`.
    pub edge_rule: String,
    /// Same-direction headway, seconds (headway rule only; `null` with it: τ).
    #[serde(default)]
    pub headway_s: Option<f64>,
    /// Maximum ground delay, seconds.
    pub max_ground_delay_s: f64,
    /// How far ahead of departure generated requests were booked, minutes (`from` = `to` = 0:
    /// at departure, the paper). Recorded by simulations of generated demand only; absent when
    /// the requests were read from a file, whose `submitted` column gives each request's own
    /// booking instant, and in what the service reports.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub booking_lead_min: Option<BookingLeadRecord>,
    /// Battery swap time at stations, seconds (docs/reference.md#multi-leg-trips); absent when
    /// trips are single legs.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub battery_swap_s: Option<f64>,
    /// With swaps: the most legs a trip may have; absent when unbounded.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub max_legs: Option<u32>,
    /// The delivery deadline after the requested departure, minutes; absent when none.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub max_trip_min: Option<f64>,
    /// Metric separation `D`, metres (docs/reference.md#metric-separation); absent when off.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub separation_m: Option<f64>,
    /// Vertical separation `V`, metres; absent when it is the layers' spacing.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub vertical_separation_m: Option<f64>,
}

/// A booking lead as recorded: uniform in `[from, to]` minutes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BookingLeadRecord {
    /// Shortest lead, minutes.
    pub from: f64,
    /// Longest lead, minutes.
    pub to: f64,
}

crate::fields::fields! {
    /// A member of [`ParamsRecord`], to name in an error: as a record member (`speed_kmh`) or
    /// as the command-line option that sets it (`--speed-kmh`); in the order a summary writes
    /// them.
    pub enum Field {
        SpeedKmh = "speed_kmh",
        MaxFlightMin = "max_flight_min",
        NodeSeparationS = "node_separation_s",
        EdgeRule = "edge_rule",
        HeadwayS = "headway_s",
        MaxGroundDelayS = "max_ground_delay_s",
        BatterySwapS = "battery_swap_s",
        MaxLegs = "max_legs",
        MaxTripMin = "max_trip_min",
        SeparationM = "separation_m",
        VerticalSeparationM = "vertical_separation_m",
    }
}

/// Why a [`ParamsRecord`] stands for no flight parameters: the member and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}: {problem}", field.name())]
pub struct ParamsError {
    /// The member.
    pub field: Field,
    /// What is wrong with it, with the value and what is accepted.
    pub problem: String,
}

impl ParamsError {
    fn new(field: Field, problem: impl fmt::Display) -> Self {
        ParamsError {
            field,
            problem: problem.to_string(),
        }
    }

    /// The message with the member named as its command-line option (`--speed-kmh 0: …`).
    pub fn as_option(&self) -> String {
        format!("{}: {}", self.field.option(), self.problem)
    }
}

/// A duration of `value` (in `unit`s of `scale` seconds) as the model's milliseconds.
fn duration(field: Field, value: f64, scale: f64, unit: &str) -> Result<Millis, ParamsError> {
    Millis::from_secs_f64(value * scale)
        .map_err(|_| ParamsError::new(field, format!("{value} must be a number of {unit} >= 0")))
}

impl ParamsRecord {
    /// The flight parameters these stand for. With the headway rule, a headway not given is τ;
    /// a headway given with the exclusive rule is an error.
    ///
    /// ```
    /// use muse_formats::params::{Field, ParamsRecord};
    /// use muse_model::FlightParams;
    /// let mut r = ParamsRecord::from(&FlightParams::default());
    /// r.max_flight_min = -1.0;
    /// assert_eq!(r.to_params().unwrap_err().field, Field::MaxFlightMin);
    /// ```
    pub fn to_params(&self) -> Result<FlightParams, ParamsError> {
        let speed =
            Speed::from_kmh(self.speed_kmh).map_err(|e| ParamsError::new(Field::SpeedKmh, e))?;
        let max_flight = duration(Field::MaxFlightMin, self.max_flight_min, 60.0, "minutes")?;
        if max_flight.0 <= 0 {
            return Err(ParamsError::new(
                Field::MaxFlightMin,
                format!("{} must be more than 0 minutes", self.max_flight_min),
            ));
        }
        let tau = duration(
            Field::NodeSeparationS,
            self.node_separation_s,
            1.0,
            "seconds",
        )?;
        let edge_rule = match (self.edge_rule.as_str(), self.headway_s) {
            ("exclusive", None) => EdgeRule::Exclusive,
            ("exclusive", Some(_)) => {
                return Err(ParamsError::new(
                    Field::HeadwayS,
                    "applies only with the headway edge rule",
                ));
            }
            ("headway", h) => EdgeRule::Headway(match h {
                None => tau,
                Some(h) => duration(Field::HeadwayS, h, 1.0, "seconds")?,
            }),
            (other, _) => {
                return Err(ParamsError::new(
                    Field::EdgeRule,
                    format!("`{other}` is not `exclusive` or `headway`"),
                ));
            }
        };
        let max_ground_delay = duration(
            Field::MaxGroundDelayS,
            self.max_ground_delay_s,
            1.0,
            "seconds",
        )?;
        let battery_swap = match self.battery_swap_s {
            None if self.max_legs.is_some() => {
                return Err(ParamsError::new(
                    Field::MaxLegs,
                    "applies only with battery swaps",
                ));
            }
            None => None,
            Some(s) => Some(BatterySwap {
                time: duration(Field::BatterySwapS, s, 1.0, "seconds")?,
                max_legs: self.max_legs,
            }),
        };
        let max_trip = self
            .max_trip_min
            .map(|m| duration(Field::MaxTripMin, m, 60.0, "minutes"))
            .transpose()?;
        let separation = Separation {
            horizontal: self
                .separation_m
                .map(|d| metres(Field::SeparationM, d, false))
                .transpose()?
                .unwrap_or(Metres::ZERO),
            vertical: self
                .vertical_separation_m
                .map(|v| metres(Field::VerticalSeparationM, v, true))
                .transpose()?,
        };
        Ok(FlightParams {
            speed,
            max_flight,
            node_separation: tau,
            edge_rule,
            max_ground_delay,
            battery_swap,
            max_trip,
            separation,
        })
    }
}

/// The most a separation may be, metres: a kilometre.
const SEPARATION_MAX_M: f64 = 1_000.0;

/// A separation of `value` metres: from 0 (more than 0 when `positive`) to a kilometre.
fn metres(field: Field, value: f64, positive: bool) -> Result<Metres, ParamsError> {
    let low_ok = if positive { value > 0.0 } else { value >= 0.0 };
    if !(low_ok && value <= SEPARATION_MAX_M) {
        let low = if positive { "more than 0" } else { "from 0" };
        return Err(ParamsError::new(
            field,
            format!("{value} must be a number of metres {low} to {SEPARATION_MAX_M}"),
        ));
    }
    Metres::from_m(value).map_err(|e| ParamsError::new(field, e))
}

impl From<&FlightParams> for ParamsRecord {
    fn from(p: &FlightParams) -> Self {
        ParamsRecord {
            speed_kmh: p.speed.kmh(),
            max_flight_min: p.max_flight.as_secs_f64() / 60.0,
            node_separation_s: p.node_separation.as_secs_f64(),
            edge_rule: p.edge_rule.name().to_owned(),
            headway_s: match p.edge_rule {
                EdgeRule::Exclusive => None,
                EdgeRule::Headway(h) => Some(h.as_secs_f64()),
            },
            max_ground_delay_s: p.max_ground_delay.as_secs_f64(),
            booking_lead_min: None,
            battery_swap_s: p.battery_swap.map(|s| s.time.as_secs_f64()),
            max_legs: p.battery_swap.and_then(|s| s.max_legs),
            max_trip_min: p.max_trip.map(|m| m.as_secs_f64() / 60.0),
            separation_m: p.separation.is_on().then(|| p.separation.horizontal.m()),
            vertical_separation_m: p.separation.vertical.map(Metres::m),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> ParamsRecord {
        ParamsRecord::from(&FlightParams::default())
    }

    #[test]
    fn every_kind_of_parameters_goes_there_and_back() {
        let headway = FlightParams {
            edge_rule: EdgeRule::Headway(Millis(2_500)),
            battery_swap: Some(BatterySwap {
                time: Millis(300_000),
                max_legs: Some(3),
            }),
            max_trip: Some(Millis(3_600_000)),
            separation: Separation {
                horizontal: Metres::from_mm(30_000),
                vertical: Some(Metres::from_mm(12_500)),
            },
            ..FlightParams::default()
        };
        for p in [FlightParams::default(), headway] {
            let r = ParamsRecord::from(&p);
            assert_eq!(r.to_params(), Ok(p));
            let text = serde_json::to_string(&r).unwrap();
            assert_eq!(serde_json::from_str::<ParamsRecord>(&text).unwrap(), r);
        }
    }

    #[test]
    fn a_headway_rule_without_a_headway_takes_tau() {
        let mut r = paper();
        r.edge_rule = "headway".into();
        let p = r.to_params().unwrap();
        assert_eq!(p.edge_rule, EdgeRule::Headway(p.node_separation));
    }

    #[test]
    fn each_bad_member_is_named_with_its_value() {
        type Spoil = fn(&mut ParamsRecord);
        let cases: [(Spoil, Field, &str); 9] = [
            (|r| r.speed_kmh = 0.0, Field::SpeedKmh, "speed 0 km/h"),
            (
                |r| r.max_flight_min = 0.0,
                Field::MaxFlightMin,
                "more than 0",
            ),
            (
                |r| r.node_separation_s = -1.0,
                Field::NodeSeparationS,
                "-1 must be",
            ),
            (
                |r| r.edge_rule = "corridor".into(),
                Field::EdgeRule,
                "`corridor`",
            ),
            (|r| r.headway_s = Some(3.0), Field::HeadwayS, "only with"),
            (
                |r| r.max_legs = Some(2),
                Field::MaxLegs,
                "only with battery",
            ),
            (
                |r| r.max_trip_min = Some(f64::NAN),
                Field::MaxTripMin,
                "NaN",
            ),
            (
                |r| r.separation_m = Some(1_000.5),
                Field::SeparationM,
                "1000.5 must be a number of metres from 0 to 1000",
            ),
            (
                |r| r.vertical_separation_m = Some(0.0),
                Field::VerticalSeparationM,
                "more than 0",
            ),
        ];
        for (spoil, field, said) in cases {
            let mut r = paper();
            spoil(&mut r);
            let e = r.to_params().unwrap_err();
            assert_eq!(e.field, field, "{e}");
            assert!(e.to_string().contains(said), "{e}");
            assert!(e.to_string().starts_with(field.name()), "{e}");
            assert!(
                e.as_option().starts_with(&field.option()),
                "{}",
                e.as_option()
            );
        }
    }

    #[test]
    fn an_unknown_member_is_refused() {
        let text = r#"{"speed_kmh": 30.0, "max_flight_min": 20.0, "node_separation_s": 5.0,
            "edge_rule": "exclusive", "max_ground_delay_s": 0.0, "wind_kmh": 3.0}"#;
        let e = serde_json::from_str::<ParamsRecord>(text).unwrap_err();
        assert!(e.to_string().contains("wind_kmh"), "{e}");
    }
}
