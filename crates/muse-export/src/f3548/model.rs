//! The part of the F3548-21 data model (UTM API 1.0.0, the standard's `OpenAPI`) that an
//! operational intent needs, with the standard's field names and spellings.
//!
//! Optional fields that MUSE leaves empty are omitted rather than written `null`; enums that
//! admit a single value for UTM (radius and altitude units, altitude reference, time format)
//! are written as that value.

use serde::Serialize;

/// One entry of the export: the MUSE request a flight answers, and its operational intent.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IntentEntry {
    /// The MUSE request id (not part of the standard: the link back to the plans file).
    pub request: String,
    /// The operational intent, as a USS would return it to a peer
    /// (`GetOperationalIntentDetailsResponse.operational_intent`).
    pub operational_intent: OperationalIntent,
}

/// `OperationalIntent`: the full description of an operational intent.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OperationalIntent {
    /// What the DSS stores.
    pub reference: OperationalIntentReference,
    /// What the managing USS shares with its peers.
    pub details: OperationalIntentDetails,
}

/// `OperationalIntentReference`: the high-level information the DSS keeps. Every field the
/// standard requires is written; `ovn` (created by the DSS) is omitted.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OperationalIntentReference {
    /// `EntityID`: a version-4-formatted UUID.
    pub id: String,
    /// The managing USS's client id.
    pub manager: String,
    /// `UssAvailabilityState`: `Unknown`, as a USS is presumed absent arbitration.
    pub uss_availability: &'static str,
    /// `EntityVersion`: 1, the first version.
    pub version: u32,
    /// `OperationalIntentState`: `Accepted` (created and shared, not yet flown).
    pub state: &'static str,
    /// Beginning of the operational intent: the start of its first volume.
    pub time_start: Time,
    /// End of the operational intent: the end of its last volume.
    pub time_end: Time,
    /// Base URL of the managing USS (no trailing `/`).
    pub uss_base_url: String,
    /// `SubscriptionID`: a version-4-formatted UUID.
    pub subscription_id: String,
}

/// `OperationalIntentDetails`: the volumes of a flight and its priority.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OperationalIntentDetails {
    /// Volumes that wholly contain the flight: one per stay and per traversal.
    pub volumes: Vec<Volume4D>,
    /// Off-nominal volumes: none while Accepted (the standard forbids any).
    pub off_nominal_volumes: Vec<Volume4D>,
    /// `Priority`: 0.
    pub priority: i32,
}

/// `Volume4D`: a contiguous block of geographic spacetime.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Volume4D {
    /// Where.
    pub volume: Volume3D,
    /// From when.
    pub time_start: Time,
    /// Until when (after `time_start`).
    pub time_end: Time,
}

/// `Volume3D`: a vertically extruded shape; exactly one outline is given.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Volume3D {
    /// A circle, for a stay or a vertical link.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outline_circle: Option<Circle>,
    /// A polygon, for a corridor traversal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outline_polygon: Option<Polygon>,
    /// Bottom (below `altitude_upper`).
    pub altitude_lower: Altitude,
    /// Top.
    pub altitude_upper: Altitude,
}

/// `Circle`: a circular area.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Circle {
    /// Centre.
    pub center: LatLngPoint,
    /// Radius.
    pub radius: Radius,
}

/// `Polygon`: an enclosed area; the last vertex is not a repeat of the first.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Polygon {
    /// Vertices, in order.
    pub vertices: Vec<LatLngPoint>,
}

/// `LatLngPoint`: a point on the WGS84 ellipsoid, degrees.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LatLngPoint {
    /// Latitude, degrees north.
    pub lat: f64,
    /// Longitude, degrees east.
    pub lng: f64,
}

/// `Radius`: a distance in metres (`units` is always `M`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Radius {
    /// Metres.
    pub value: f64,
    /// `M`.
    pub units: &'static str,
}

impl Radius {
    /// `value` metres.
    pub fn metres(value: f64) -> Self {
        Radius { value, units: "M" }
    }
}

/// `Altitude`: metres above the WGS84 ellipsoid (`reference` `W84`, `units` `M`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Altitude {
    /// Metres.
    pub value: f64,
    /// `W84`.
    pub reference: &'static str,
    /// `M`.
    pub units: &'static str,
}

impl Altitude {
    /// `value` metres above the WGS84 ellipsoid.
    pub fn w84_metres(value: f64) -> Self {
        Altitude {
            value,
            reference: "W84",
            units: "M",
        }
    }
}

/// `Time`: an RFC 3339 UTC time (`Z`), to the millisecond.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Time {
    /// E.g. `2026-01-05T00:15:03.250Z`.
    pub value: String,
    /// `RFC3339`.
    pub format: &'static str,
}

impl Time {
    /// The time `value` (already RFC 3339 with `Z`).
    pub fn rfc3339(value: String) -> Self {
        Time {
            value,
            format: "RFC3339",
        }
    }
}
