//! Flights as ASTM F3548-21 operational intents: the form in which a UAS service supplier
//! (USS) shares its flights with the others through a DSS (UTM API 1.0.0).
//!
//! Each planned flight becomes one [`OperationalIntent`] in state `Accepted`, priority 0,
//! whose volumes ([`Volume4D`]) wholly contain it:
//!
//! - a **stay** that lasts (hover, `arrive < depart`): a circle of radius `B` (the buffer)
//!   around the node, from `arrive` to `depart`; a stay of no duration (flying through a node,
//!   landing) has no volume of its own — the traversals before and after it cover the node;
//! - a **corridor traversal**: the corridor buffered by `B` — every point within `B` of the
//!   segment, drawn as a polygon with rounded ends ([`corridor_outline`]) — from entering to
//!   leaving the corridor;
//! - a **vertical link** (layered airspace): a circle of radius `B` at the node spanning both
//!   layers' bands, for the climb or descent.
//!
//! Each volume's altitude band is its layer's cruise altitude `h_k`
//! (docs/reference.md#layered-airspace; 60 m when flat) ± the vertical buffer, written as metres
//! above the WGS84 ellipsoid (MUSE assumes flat ground at height 0). Times are RFC 3339 UTC (`Z`)
//! to the millisecond.
//!
//! `B` = 0 is written as 1 cm ([`MIN_OUTLINE_M`]), the standard's intersection precision:
//! a circle of radius 0 or a corridor of no width is no valid outline.
//!
//! Ids: the intent's id and its subscription's id are version-4-formatted UUIDs derived from
//! the request id ([`entity_id`]), so an export is reproducible and its ids stable.
//!
//! Limits: at most [`OI_MAX_VERTICES`] polygon vertices per intent; times within years
//! 0000–9999 (RFC 3339); with [`Options::shared_at`], every intent ends after that instant
//! and starts within [`OI_MAX_PLAN_HORIZON_DAYS`] of it. A flight beyond a limit is an error
//! naming its request, never silently cut.
//!
//! [`intersect`] counts the pairs of flights whose volumes meet in 4-D.

mod geometry;
pub mod intersect;
mod model;

use std::collections::HashSet;

use muse_model::{
    Airspace, EdgeKind, Instant, Layers, LocalFrame, Millis, NodeId, Plan, UtcOffset,
};

pub use geometry::{CAP_VERTICES, corridor_outline};
pub use model::{
    Altitude, Circle, IntentEntry, LatLngPoint, OperationalIntent, OperationalIntentDetails,
    OperationalIntentReference, Polygon, Radius, Time, Volume3D, Volume4D,
};

/// The standard's most vertices of an operational intent (`OiMaxVertices`).
pub const OI_MAX_VERTICES: usize = 10_000;

/// The standard's planning horizon of an operational intent, days (`OiMaxPlanHorizonDays`).
pub const OI_MAX_PLAN_HORIZON_DAYS: i64 = 30;

/// The largest buffer accepted, metres (1 km: more than a corridor's spacing means nothing).
pub const MAX_BUFFER_M: f64 = 1_000.0;

/// The smallest outline written, metres: the standard's intersection precision (1 cm,
/// `IntersectionMinimumPrecisionCm`). A buffer below it is written as it.
pub const MIN_OUTLINE_M: f64 = 0.01;

/// The smallest vertical buffer, metres (a band's bottom must lie below its top).
pub const MIN_VERTICAL_BUFFER_M: f64 = 0.01;

/// The earliest instant written: `0000-01-01T00:00:00Z` (RFC 3339 has four-digit years).
const TIME_MIN: Instant = Instant(-62_167_219_200_000);
/// The latest instant written: `9999-12-31T23:59:59.999Z`.
const TIME_MAX: Instant = Instant(253_402_300_799_999);

/// How the intents are built.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Horizontal buffer `B`, metres, from 0 to [`MAX_BUFFER_M`].
    pub buffer_m: f64,
    /// Vertical buffer above and below each layer's altitude, metres, from
    /// [`MIN_VERTICAL_BUFFER_M`] to [`MAX_BUFFER_M`].
    pub vertical_buffer_m: f64,
    /// The managing USS's client id (`manager`).
    pub manager: String,
    /// The managing USS's base URL (`uss_base_url`), without a trailing `/`.
    pub uss_base_url: String,
    /// When the intents are to be shared, if known: each must then end after it and start
    /// within the planning horizon of it.
    pub shared_at: Option<Instant>,
}

impl Default for Options {
    /// `B` = 10 m, vertical buffer 3 m (below half the default layer spacing of 9.144 m, so
    /// layers stay apart), manager `muse`, base URL `https://uss.example.com`, no sharing time.
    fn default() -> Self {
        Options {
            buffer_m: 10.0,
            vertical_buffer_m: 3.0,
            manager: "muse".to_owned(),
            uss_base_url: "https://uss.example.com".to_owned(),
            shared_at: None,
        }
    }
}

/// A flight to export: the request it answers and its plan (on the airspace given alongside).
#[derive(Clone, Copy, Debug)]
pub struct Flight<'a> {
    /// The request id.
    pub request: &'a str,
    /// Its (final) plan.
    pub plan: &'a Plan,
}

/// Why flights cannot be exported.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum F3548Error {
    /// The buffer is not a number from 0 to [`MAX_BUFFER_M`].
    #[error("buffer {0} m: must be a number of metres from 0 to {MAX_BUFFER_M}")]
    Buffer(f64),
    /// The vertical buffer is out of range.
    #[error(
        "vertical buffer {0} m: must be a number of metres from {MIN_VERTICAL_BUFFER_M} to {MAX_BUFFER_M}"
    )]
    VerticalBuffer(f64),
    /// The base URL is not `http(s)://…` without a trailing `/`.
    #[error("USS base URL `{0}`: must start with http:// or https:// and not end with /")]
    BaseUrl(String),
    /// The manager is empty.
    #[error("the manager (the USS's client id) is empty")]
    Manager,
    /// Two flights answer the same request.
    #[error("request {0}: two flights answer it; request ids must be unique")]
    DuplicateRequest(String),
    /// A plan names a node or a hop the airspace does not have.
    #[error("request {request}: {what} is not in the airspace")]
    NotInAirspace {
        /// The request.
        request: String,
        /// The node or hop.
        what: String,
    },
    /// A plan's times do not move forward (a traversal that ends before it starts).
    #[error(
        "request {request}: the traversal from {from} to {to} does not last (plans must move forward in time)"
    )]
    Backwards {
        /// The request.
        request: String,
        /// Node left.
        from: String,
        /// Node reached.
        to: String,
    },
    /// A plan with no volume: no traversal and no hover.
    #[error("request {0}: the plan has no traversal")]
    Empty(String),
    /// Too many polygon vertices for one intent.
    #[error(
        "request {request}: {vertices} polygon vertices, over the standard's {OI_MAX_VERTICES} per operational intent"
    )]
    TooManyVertices {
        /// The request.
        request: String,
        /// Its vertices.
        vertices: usize,
    },
    /// A time outside years 0000–9999.
    #[error(
        "request {request}: instant {ms} ms is outside the years 0000 to 9999 that RFC 3339 writes"
    )]
    Time {
        /// The request.
        request: String,
        /// The instant, ms since 1970.
        ms: i64,
    },
    /// An intent outside the planning horizon of the sharing time.
    #[error("request {request}: {problem} (shared at {shared_at})")]
    Horizon {
        /// The request.
        request: String,
        /// What is wrong.
        problem: String,
        /// The sharing time.
        shared_at: String,
    },
}

/// The operational intents of `flights` over `airspace`, in the order given.
///
/// ```
/// use muse_export::f3548::{Flight, Options, operational_intents};
/// use muse_model::{Airspace, Instant, NodeId, Plan, Stay};
/// let air = Airspace::line(&[1_000.0]); // A — B
/// let stay = |n, a, d| Stay { node: NodeId(n), arrive: Instant(a), depart: Instant(d) };
/// // Take off at A, hover 10 s, fly to B in 120 s, land.
/// let plan = Plan { path: vec![stay(0, 0, 10_000), stay(1, 130_000, 130_000)] };
/// let flights = [Flight { request: "r1", plan: &plan }];
/// let intents = operational_intents(&air, &flights, &Options::default()).unwrap();
/// let oi = &intents[0].operational_intent;
/// assert_eq!((oi.reference.state, oi.details.priority), ("Accepted", 0));
/// assert_eq!(oi.details.volumes.len(), 2); // the hover at A, the corridor A–B
/// assert_eq!(oi.reference.time_end.value, "1970-01-01T00:02:10.000Z");
/// let band = &oi.details.volumes[1].volume;
/// assert_eq!((band.altitude_lower.value, band.altitude_upper.value), (57.0, 63.0));
/// ```
///
/// # Errors
/// Options out of range, a request answered twice, a plan that does not fit the airspace or
/// moves backwards in time, or an intent beyond the standard's limits ([`F3548Error`]).
pub fn operational_intents(
    airspace: &Airspace,
    flights: &[Flight<'_>],
    options: &Options,
) -> Result<Vec<IntentEntry>, F3548Error> {
    options.validate()?;
    let builder = Builder::new(airspace, options);
    let mut seen = HashSet::new();
    let mut out = Vec::with_capacity(flights.len());
    for flight in flights {
        if !seen.insert(flight.request) {
            return Err(F3548Error::DuplicateRequest(flight.request.to_owned()));
        }
        out.push(builder.intent(flight)?);
    }
    Ok(out)
}

impl Options {
    /// Checks the options: the buffers in range, a base URL `http(s)://…` without a
    /// trailing `/`, a manager that is not blank.
    ///
    /// ```
    /// use muse_export::f3548::{F3548Error, Options};
    /// assert!(Options::default().validate().is_ok());
    /// let wide = Options { buffer_m: 1_500.0, ..Options::default() };
    /// assert_eq!(wide.validate(), Err(F3548Error::Buffer(1_500.0)));
    /// ```
    pub fn validate(&self) -> Result<(), F3548Error> {
        let options = self;
        if !(0.0..=MAX_BUFFER_M).contains(&options.buffer_m) {
            return Err(F3548Error::Buffer(options.buffer_m));
        }
        if !(MIN_VERTICAL_BUFFER_M..=MAX_BUFFER_M).contains(&options.vertical_buffer_m) {
            return Err(F3548Error::VerticalBuffer(options.vertical_buffer_m));
        }
        let url = &options.uss_base_url;
        let scheme = url
            .strip_prefix("https://")
            .or_else(|| url.strip_prefix("http://"));
        if scheme.is_none_or(str::is_empty)
            || url.ends_with('/')
            || url.contains(char::is_whitespace)
        {
            return Err(F3548Error::BaseUrl(url.clone()));
        }
        if options.manager.trim().is_empty() {
            return Err(F3548Error::Manager);
        }
        Ok(())
    }
}

/// A version-4-formatted UUID derived from `name`: the 128-bit FNV-1a hash of the bytes of
/// `name`, mixed by a xorshift-multiply finaliser (a bijection, so that names differing in
/// one character give unrelated-looking ids), with the version nibble set to 4 and the
/// variant bits to `10`. The same name always gives the same id; the intent of request `R`
/// is named `muse:f3548:intent:R`, its subscription `muse:f3548:subscription:R`.
///
/// ```
/// use muse_export::f3548::entity_id;
/// let id = entity_id("muse:f3548:intent:r000001");
/// assert_eq!(id, entity_id("muse:f3548:intent:r000001"));
/// assert_ne!(id, entity_id("muse:f3548:intent:r000002"));
/// assert_eq!((id.len(), &id[14..15]), (36, "4"));
/// assert!(matches!(&id[19..20], "8" | "9" | "a" | "b"));
/// ```
pub fn entity_id(name: &str) -> String {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;
    const MIX_1: u128 = 0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c835;
    const MIX_2: u128 = 0xbf58_476d_1ce4_e5b9_94d0_49bb_1331_11eb;
    let mut h = OFFSET;
    for &byte in name.as_bytes() {
        h ^= u128::from(byte);
        h = h.wrapping_mul(PRIME);
    }
    h ^= h >> 67;
    h = h.wrapping_mul(MIX_1);
    h ^= h >> 59;
    h = h.wrapping_mul(MIX_2);
    h ^= h >> 71;
    // Version 4 in bits 76–79, variant `10` in bits 62–63.
    h = (h & !(0xf << 76)) | (0x4 << 76);
    h = (h & !(0x3 << 62)) | (0x2 << 62);
    let hex = format!("{h:032x}");
    format!(
        "{}-{}-{}-{}-{}",
        &hex[..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..]
    )
}

/// `t` as an F3548 time (RFC 3339, UTC, `Z`, milliseconds), if its year has four digits.
fn time(t: Instant) -> Option<Time> {
    if !(TIME_MIN..=TIME_MAX).contains(&t) {
        return None;
    }
    let text = t.to_rfc3339(UtcOffset(0));
    let value = text.strip_suffix("+00:00").map(|s| format!("{s}Z"))?;
    Some(Time::rfc3339(value))
}

/// Metres rounded to the millimetre.
fn mm(m: f64) -> f64 {
    (m * 1_000.0).round() / 1_000.0
}

/// Builds the intents of one airspace with one set of options.
struct Builder<'a> {
    airspace: &'a Airspace,
    options: &'a Options,
    layers: Layers,
    frame: LocalFrame,
    radius: f64,
}

/// One volume before its times are written.
struct Draft {
    volume: Volume3D,
    start: Instant,
    end: Instant,
}

impl<'a> Builder<'a> {
    fn new(airspace: &'a Airspace, options: &'a Options) -> Self {
        Builder {
            airspace,
            options,
            layers: airspace.layers().copied().unwrap_or_default(),
            frame: LocalFrame::around(airspace.flat().nodes().iter().map(|n| n.pos)),
            radius: options.buffer_m.max(MIN_OUTLINE_M),
        }
    }

    /// The intent of one flight.
    fn intent(&self, flight: &Flight<'_>) -> Result<IntentEntry, F3548Error> {
        let request = flight.request;
        let drafts = self.drafts(flight)?;
        let (Some(first), Some(last)) = (drafts.first(), drafts.last()) else {
            return Err(F3548Error::Empty(request.to_owned()));
        };
        let (start, end) = (first.start, last.end);
        self.check_horizon(request, start, end)?;
        let vertices: usize = drafts
            .iter()
            .filter_map(|d| d.volume.outline_polygon.as_ref())
            .map(|p| p.vertices.len())
            .sum();
        if vertices > OI_MAX_VERTICES {
            return Err(F3548Error::TooManyVertices {
                request: request.to_owned(),
                vertices,
            });
        }
        let at = |t: Instant| {
            time(t).ok_or_else(|| F3548Error::Time {
                request: request.to_owned(),
                ms: t.0,
            })
        };
        let volumes = drafts
            .into_iter()
            .map(|d| {
                Ok(Volume4D {
                    volume: d.volume,
                    time_start: at(d.start)?,
                    time_end: at(d.end)?,
                })
            })
            .collect::<Result<Vec<_>, F3548Error>>()?;
        Ok(IntentEntry {
            request: request.to_owned(),
            operational_intent: OperationalIntent {
                reference: OperationalIntentReference {
                    id: entity_id(&format!("muse:f3548:intent:{request}")),
                    manager: self.options.manager.clone(),
                    uss_availability: "Unknown",
                    version: 1,
                    state: "Accepted",
                    time_start: at(start)?,
                    time_end: at(end)?,
                    uss_base_url: self.options.uss_base_url.clone(),
                    subscription_id: entity_id(&format!("muse:f3548:subscription:{request}")),
                },
                details: OperationalIntentDetails {
                    volumes,
                    off_nominal_volumes: Vec::new(),
                    priority: 0,
                },
            },
        })
    }

    /// With a sharing time: the intent must end after it and start within the horizon.
    fn check_horizon(&self, request: &str, start: Instant, end: Instant) -> Result<(), F3548Error> {
        let Some(shared) = self.options.shared_at else {
            return Ok(());
        };
        let horizon = Millis::from_mins(OI_MAX_PLAN_HORIZON_DAYS * 24 * 60);
        let problem = if end <= shared {
            "it ends before it is shared (an operational intent may not end in the past)"
        } else if start > shared + horizon {
            "it starts more than the standard's 30-day planning horizon after it is shared"
        } else {
            return Ok(());
        };
        Err(F3548Error::Horizon {
            request: request.to_owned(),
            problem: problem.to_owned(),
            shared_at: time(shared).map_or_else(|| format!("{} ms", shared.0), |t| t.value),
        })
    }

    /// The volumes of a flight, in time order, before their times are written.
    fn drafts(&self, flight: &Flight<'_>) -> Result<Vec<Draft>, F3548Error> {
        let request = flight.request;
        let path = &flight.plan.path;
        let count = self.airspace.node_count();
        if let Some(s) = path.iter().find(|s| s.node.index() >= count) {
            return Err(F3548Error::NotInAirspace {
                request: request.to_owned(),
                what: format!("node #{}", s.node.0),
            });
        }
        let mut drafts = Vec::with_capacity(2 * path.len());
        for (i, stay) in path.iter().enumerate() {
            if stay.depart > stay.arrive {
                let band = self.band(self.airspace.node_layer(stay.node), 0);
                drafts.push(self.circle(stay.node, band, stay.arrive, stay.depart));
            }
            let Some(next) = path.get(i + 1).filter(|n| n.node != stay.node) else {
                continue; // the last stay, or a landing before a battery swap
            };
            if next.arrive <= stay.depart {
                return Err(F3548Error::Backwards {
                    request: request.to_owned(),
                    from: self.airspace.node(stay.node).id.clone(),
                    to: self.airspace.node(next.node).id.clone(),
                });
            }
            drafts.push(self.hop(request, stay.node, next.node, stay.depart, next.arrive)?);
        }
        Ok(drafts)
    }

    /// The volume of the traversal from `a` to `b` during `[start, end)`.
    fn hop(
        &self,
        request: &str,
        a: NodeId,
        b: NodeId,
        start: Instant,
        end: Instant,
    ) -> Result<Draft, F3548Error> {
        let air = self.airspace;
        let edge = air
            .edge_between(a, b)
            .or_else(|| air.edge_between(b, a))
            .ok_or_else(|| F3548Error::NotInAirspace {
                request: request.to_owned(),
                what: format!("a corridor from {} to {}", air.node(a).id, air.node(b).id),
            })?;
        Ok(match air.edge_kind(edge) {
            EdgeKind::Vertical { layer, .. } => self.circle(a, self.band(layer, 1), start, end),
            EdgeKind::Corridor { layer, .. } => {
                let (pa, pb) = (air.node(a).pos, air.node(b).pos);
                let outline =
                    corridor_outline(self.frame.to_xy(pa), self.frame.to_xy(pb), self.radius);
                match outline {
                    None => self.circle(a, self.band(layer, 0), start, end),
                    Some(xy) => Draft {
                        volume: Volume3D {
                            outline_circle: None,
                            outline_polygon: Some(Polygon {
                                vertices: xy
                                    .into_iter()
                                    .map(|p| geometry::to_lat_lng(&self.frame, p))
                                    .collect(),
                            }),
                            ..self.band(layer, 0)
                        },
                        start,
                        end,
                    },
                }
            }
        })
    }

    /// A circle of the buffer's radius at node `n` with the altitudes of `band`.
    fn circle(&self, n: NodeId, band: Volume3D, start: Instant, end: Instant) -> Draft {
        let pos = self.airspace.node(n).pos;
        Draft {
            volume: Volume3D {
                outline_circle: Some(Circle {
                    center: LatLngPoint {
                        lat: geometry::round_degrees(pos.lat),
                        lng: geometry::round_degrees(pos.lon),
                    },
                    radius: Radius::metres(self.radius),
                }),
                ..band
            },
            start,
            end,
        }
    }

    /// A volume with no outline yet, from layer `k`'s altitude to layer `k + above`'s, each
    /// widened by the vertical buffer.
    fn band(&self, k: u32, above: u32) -> Volume3D {
        let v = self.options.vertical_buffer_m;
        Volume3D {
            outline_circle: None,
            outline_polygon: None,
            altitude_lower: Altitude::w84_metres(mm(self.layers.altitude(k).m() - v)),
            altitude_upper: Altitude::w84_metres(mm(self.layers.altitude(k + above).m() + v)),
        }
    }
}

#[cfg(test)]
mod tests;
