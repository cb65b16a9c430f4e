//! The flight-model parameters and booking lead, as a summary records them.

use muse_model::{EdgeRule, FlightParams};
use serde::{Deserialize, Serialize};

use crate::demand::BookingLead;

/// The flight-model parameters, as recorded in a summary (and read back by
/// [`read_recorded`](super::recorded::read_recorded): a member this version does not know is an error, a missing
/// optional one is `None`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamsRecord {
    /// Cruise speed, km/h.
    pub speed_kmh: f64,
    /// Battery limit, minutes.
    pub max_flight_min: f64,
    /// Node separation, seconds.
    pub node_separation_s: f64,
    /// `exclusive` or `headway`.
    pub edge_rule: String,
    /// Same-direction headway, seconds (headway rule only).
    #[serde(default)]
    pub headway_s: Option<f64>,
    /// Maximum ground delay, seconds.
    pub max_ground_delay_s: f64,
    /// How far ahead of departure generated requests were booked, minutes (`from` = `to` = 0:
    /// at departure, the paper). Absent when the requests were read from a file, whose
    /// `submitted` column gives each request's own booking instant.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub booking_lead_min: Option<BookingLeadRecord>,
    /// Battery swap time at stations, seconds (SPEC §12); absent when trips are single legs.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub battery_swap_s: Option<f64>,
    /// With swaps: the most legs a trip may have; absent when unbounded.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub max_legs: Option<u32>,
    /// The delivery deadline after the requested departure, minutes; absent when none.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub max_trip_min: Option<f64>,
}

/// A booking lead as recorded in a summary: uniform in `[from, to]` minutes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BookingLeadRecord {
    /// Shortest lead, minutes.
    pub from: f64,
    /// Longest lead, minutes.
    pub to: f64,
}

impl From<BookingLead> for BookingLeadRecord {
    fn from(lead: BookingLead) -> Self {
        BookingLeadRecord {
            from: lead.min.as_secs_f64() / 60.0,
            to: lead.max.as_secs_f64() / 60.0,
        }
    }
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
        }
    }
}
