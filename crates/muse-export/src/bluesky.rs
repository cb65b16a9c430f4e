//! A day of flights as a BlueSky scenario file (`.scn`), to fly MUSE's plans under BlueSky's
//! drone dynamics and conflict detection (docs/reference.md, "BlueSky scenarios").
//!
//! A scenario is a list of timed commands, one a line: `HH:MM:SS.hh>COMMAND args`. The times
//! count from the **time origin**, the earliest take-off floored to the minute (a headless
//! BlueSky steps every 0.05 s, so an origin at midnight would simulate hours of empty sky);
//! the header says the origin's absolute time and a `DATE` command sets BlueSky's clock to it
//! (UTC). Times are rounded to the hundredth of a second, the precision BlueSky reads.
//!
//! Each flight (each leg of a multi-leg trip, docs/reference.md#multi-leg-trips) is:
//!
//! - a comment line `# flight CALLSIGN: request ID, leg K/N, ORIGIN -> DESTINATION, take-off
//!   T, landing L, destination LAT LON` (times in milliseconds);
//! - `CRE` at its take-off over its origin at its cruise altitude, heading for its first node,
//!   at cruise speed (speed 0 when it first hovers at its origin);
//! - one `ADDWPT` per node it flies to, a lat/lon waypoint without altitude or speed
//!   constraint, which BlueSky names `CALLSIGN001`, `CALLSIGN002`, …; flown fly-by (BlueSky's
//!   default), but fly-over where the route turns by more than 90° (`ADDWPT CALLSIGN FLYOVER`
//!   before it, `FLYBY` after), since BlueSky starts a fly-by turn `R·tan(turn/2)` ahead of
//!   the waypoint, without bound as the turn nears a U-turn;
//! - `AT CALLSIGN0NN DO DEL CALLSIGN`: it is deleted (it lands) as it passes its destination;
//! - `RTA CALLSIGN CALLSIGN0NN T`, a required time of arrival at each waypoint, its planned
//!   arrival there, and `VNAV CALLSIGN ON`: BlueSky's autopilot sets the speed, all along, that
//!   reaches the next waypoint at its planned instant (closed loop: turns, accelerations and
//!   BlueSky's Earth model are made up for as they happen), instead of flying open loop at
//!   cruise speed; `Options::open_loop` leaves them out;
//! - a hover at a node, from the planned arrival to the planned departure: `SPD CALLSIGN 0` at
//!   the arrival, the cruise speed again at the departure (timed, so a late drone is never
//!   held for ever), then `VNAV CALLSIGN ON` again (a speed command switches the autopilot's
//!   speed guidance off); a change of layer at a node (docs/reference.md#layered-airspace) is
//!   an `ALT` command at the planned instant, at the layers' vertical speed.
//!
//! Units are BlueSky's: altitudes in feet, speeds in knots calibrated airspeed (the cruise
//! true airspeed converted at the altitude flown, in BlueSky's standard atmosphere), vertical
//! speeds in feet per minute, positions in degrees. Callsigns are the request ids in capitals,
//! every character but `A`–`Z` and `0`–`9` dropped ([`callsign_base`]); see [`scenario`].
//!
//! ```
//! use muse_export::bluesky::{scenario, Flight, Options};
//! use muse_model::{Airspace, Instant, NodeId, Plan, Stay};
//! let airspace = Airspace::line(&[1_000.0]); // A — B
//! let stay = |n, t| Stay { node: NodeId(n), arrive: Instant(t), depart: Instant(t) };
//! let plan = Plan { path: vec![stay(0, 60_000), stay(1, 180_000)] };
//! let written = scenario(&airspace, &[Flight { request: "r1", plan: &plan }], &Options::default())
//!     .unwrap();
//! assert!(written.text.contains("00:00:00.00>CRE R1 M600 "));
//! assert!(written.text.contains("00:00:00.00>AT R1 R1001 DO DEL R1\n"));
//! assert_eq!((written.flights, written.legs), (1, 1));
//! ```

use std::collections::HashSet;
use std::fmt::Write as _;

use muse_model::layers::bearing;
use muse_model::{Airspace, Instant, Layers, LonLat, Metres, NodeId, Plan, Speed, Stay, UtcOffset};

/// Why a scenario cannot be written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BlueskyError {
    /// The aircraft type is not a single word of letters, digits, `-` or `_`.
    #[error("aircraft type `{0}`: give a BlueSky type such as M600 (letters, digits, - or _)")]
    Type(String),
    /// The cruise speed is below 1 kt calibrated: BlueSky would read it as a Mach number.
    #[error(
        "cruise speed {kmh} km/h is {kts:.3} kt calibrated: BlueSky reads speeds below 1 kt as \
         Mach numbers; give at least 2 km/h"
    )]
    Speed {
        /// The cruise speed, km/h.
        kmh: f64,
        /// It in knots calibrated airspeed.
        kts: f64,
    },
    /// A flight's plan has no stays.
    #[error("request {0}: its plan has no stays")]
    EmptyPlan(String),
    /// A plan names a node the airspace does not have.
    #[error("request {request}: node index {node} is not in the airspace")]
    UnknownNode {
        /// The request.
        request: String,
        /// The node index.
        node: u32,
    },
}

/// A flight to write: its request id and its (final) plan.
#[derive(Clone, Copy, Debug)]
pub struct Flight<'a> {
    /// The request id, from which the callsign is derived.
    pub request: &'a str,
    /// The plan flown (every leg of a multi-leg trip).
    pub plan: &'a Plan,
}

/// How to write the scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// BlueSky aircraft type of every flight (an OpenAP rotorcraft: `M600`, `Amzn`, `Mavic`…).
    pub aircraft_type: String,
    /// Cruise speed (true airspeed), as planned.
    pub speed: Speed,
    /// UTC offset of the times said in comments.
    pub offset: UtcOffset,
    /// Without the required times of arrival (and `VNAV` commands): every corridor flown at
    /// cruise speed, open loop, as before they were written.
    pub open_loop: bool,
}

impl Default for Options {
    /// A DJI Matrice 600 (`M600`) at the paper's 30 km/h, times in UTC.
    fn default() -> Self {
        Options {
            aircraft_type: "M600".to_owned(),
            speed: Speed::PAPER,
            offset: UtcOffset(0),
            open_loop: false,
        }
    }
}

/// A scenario written: its text and what it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// The `.scn` text.
    pub text: String,
    /// Flights written (trips).
    pub flights: usize,
    /// Legs written (one BlueSky aircraft each).
    pub legs: usize,
    /// The time origin (`00:00:00.00`), when there is a flight.
    pub origin: Option<Instant>,
}

/// One foot, metres (BlueSky's altitude unit).
const FT_M: f64 = 0.3048;
/// One knot, m/s, as BlueSky converts it.
const KT_MPS: f64 = 0.514_444;
/// The sharpest turn, degrees, flown fly-by; sharper turns are flown fly-over.
const MAX_FLYBY_TURN: f64 = 90.0;

/// A node visit of a leg: consecutive stays at one node, at one or more layers.
struct Visit<'a> {
    stays: &'a [Stay],
}

impl Visit<'_> {
    fn first(&self) -> &Stay {
        &self.stays[0]
    }

    fn last(&self) -> &Stay {
        &self.stays[self.stays.len() - 1]
    }
}

/// The callsign a request id gives before it is made unique: the id in capitals with every
/// character but `A`–`Z` and `0`–`9` dropped, prefixed with `F` when that leaves nothing or
/// starts with a digit.
///
/// ```
/// use muse_export::bluesky::callsign_base;
/// assert_eq!(callsign_base("r000042"), "R000042");
/// assert_eq!(callsign_base("op-7/é 1"), "OP71");
/// assert_eq!(callsign_base("42"), "F42");
/// assert_eq!(callsign_base("--"), "F");
/// ```
pub fn callsign_base(request: &str) -> String {
    let kept: String = request
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_uppercase())
        .collect();
    if kept.starts_with(|c: char| c.is_ascii_alphabetic()) {
        kept
    } else {
        format!("F{kept}")
    }
}

/// Calibrated airspeed, knots, of true airspeed `tas_mps` at altitude `h_m`, in BlueSky's
/// standard atmosphere (its `vtas2cas`).
pub fn cas_kts(tas_mps: f64, h_m: f64) -> f64 {
    const R: f64 = 287.052_87;
    const P0: f64 = 101_325.0;
    const RHO0: f64 = 1.225;
    let temp = (288.15 - 0.0065 * h_m).max(216.65);
    let rho = RHO0 * (temp / 288.15).powf(4.256_848_030_018_761);
    let p = rho * R * temp;
    let qdyn = p * ((1.0 + rho * tas_mps * tas_mps / (7.0 * p)).powf(3.5) - 1.0);
    (7.0 * P0 / RHO0 * ((qdyn / P0 + 1.0).powf(2.0 / 7.0) - 1.0)).sqrt() / KT_MPS
}

/// The scenario of `flights` over `airspace` (docs/reference.md, "BlueSky scenarios").
///
/// Flights are written in order of take-off (then request id), each leg as one aircraft. A
/// flight's callsign is [`callsign_base`] of its request id; a leg of a multi-leg trip adds
/// `L` and its number (`R7L1`, `R7L2`); a callsign already taken adds `X2`, `X3`, … until it
/// is free. The comment line of each flight gives its request id.
///
/// # Errors
/// A bad aircraft type, a cruise speed BlueSky would read as a Mach number, an empty plan or a
/// node outside the airspace.
pub fn scenario(
    airspace: &Airspace,
    flights: &[Flight<'_>],
    options: &Options,
) -> Result<Scenario, BlueskyError> {
    let ty = &options.aircraft_type;
    if ty.is_empty()
        || !ty
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        return Err(BlueskyError::Type(ty.clone()));
    }
    let base = altitude(airspace, NodeId(0));
    let cruise_kts = cas_kts(options.speed.mps(), base.m());
    if cruise_kts < 1.0 {
        return Err(BlueskyError::Speed {
            kmh: options.speed.kmh(),
            kts: cruise_kts,
        });
    }
    for f in flights {
        if f.plan.path.is_empty() {
            return Err(BlueskyError::EmptyPlan(f.request.to_owned()));
        }
        if let Some(s) = f
            .plan
            .path
            .iter()
            .find(|s| s.node.index() >= airspace.node_count())
        {
            return Err(BlueskyError::UnknownNode {
                request: f.request.to_owned(),
                node: s.node.0,
            });
        }
    }
    let mut order: Vec<&Flight<'_>> = flights.iter().collect();
    order.sort_by(|a, b| (a.plan.takeoff(), a.request).cmp(&(b.plan.takeoff(), b.request)));
    let origin = order
        .first()
        .map(|f| Instant(f.plan.takeoff().0.div_euclid(60_000) * 60_000));
    let mut text = header(airspace, options, flights.len(), origin, cruise_kts);
    let mut taken = HashSet::new();
    let mut legs = 0;
    for f in &order {
        let count = f.plan.leg_count();
        let base = callsign_base(f.request);
        for (k, leg) in f.plan.legs().enumerate() {
            let wanted = if count > 1 {
                format!("{base}L{}", k + 1)
            } else {
                base.clone()
            };
            let callsign = unique(&wanted, &mut taken);
            let at = origin.unwrap_or_default();
            let leg_info = LegInfo {
                request: f.request,
                callsign: &callsign,
                number: k + 1,
                count,
            };
            write_leg(&mut text, airspace, options, at, &leg_info, leg);
            legs += 1;
        }
    }
    Ok(Scenario {
        text,
        flights: flights.len(),
        legs,
        origin,
    })
}

/// `wanted`, or it with `X2`, `X3`, … when taken; marked taken.
fn unique(wanted: &str, taken: &mut HashSet<String>) -> String {
    let mut name = wanted.to_owned();
    let mut n = 1;
    while taken.contains(&name) {
        n += 1;
        name = format!("{wanted}X{n}");
    }
    taken.insert(name.clone());
    name
}

/// The altitude node `n` is flown at: its layer's (docs/reference.md#layered-airspace; 60 m when
/// flat).
fn altitude(airspace: &Airspace, n: NodeId) -> Metres {
    let layers = airspace.layers().copied().unwrap_or_default();
    layers.altitude(airspace.node_layer(n))
}

/// The header: what the file is, its time origin (and `DATE`), units and ids.
fn header(
    airspace: &Airspace,
    options: &Options,
    flights: usize,
    origin: Option<Instant>,
    cruise_kts: f64,
) -> String {
    let mut text = String::new();
    let layers = airspace.layers().copied().unwrap_or_default();
    let _ = writeln!(
        text,
        "# BlueSky scenario written by muse export bluesky: {flights} flights, aircraft type {}",
        options.aircraft_type
    );
    let _ = writeln!(
        text,
        "# Cruise {} km/h true airspeed ({cruise_kts:.4} kt calibrated at {} m); altitudes in \
         feet, speeds in knots calibrated, vertical speeds in feet per minute",
        options.speed.kmh(),
        layers.base.m()
    );
    if let Some(o) = origin {
        let utc = o.to_rfc3339(UtcOffset(0));
        let _ = writeln!(
            text,
            "# Time origin 00:00:00.00 = {} ({} UTC): the first take-off floored to the minute",
            o.to_rfc3339(options.offset),
            &utc[..19].replace('T', " ")
        );
        let _ = writeln!(
            text,
            "# Each flight is deleted as it passes its destination (its landing); callsigns \
             are request ids in capitals (see each flight's comment)"
        );
        let date = |from: usize, to: usize| utc[from..to].parse::<u32>().unwrap_or(0);
        let _ = writeln!(
            text,
            "00:00:00.00>DATE {},{},{},{}.00",
            date(8, 10),
            date(5, 7),
            &utc[..4],
            &utc[11..19]
        );
    }
    text
}

/// Who a leg is.
struct LegInfo<'a> {
    request: &'a str,
    callsign: &'a str,
    number: usize,
    count: usize,
}

/// Writes one leg: its comment, creation, route, deletion at its destination, hovers and
/// changes of layer.
fn write_leg(
    text: &mut String,
    airspace: &Airspace,
    options: &Options,
    origin: Instant,
    leg: &LegInfo<'_>,
    stays: &[Stay],
) {
    let flat = |n: NodeId| airspace.flat_node(n);
    let visits: Vec<Visit<'_>> = stays
        .chunk_by(|a, b| flat(a.node) == flat(b.node))
        .map(|stays| Visit { stays })
        .collect();
    let (first, last) = (&visits[0], &visits[visits.len() - 1]);
    let pos = |v: &Visit<'_>| airspace.node(flat(v.first().node)).pos;
    let cs = leg.callsign;
    let t = |i: Instant| clock(i - origin);
    let speed = |n: NodeId| cas_kts(options.speed.mps(), altitude(airspace, n).m());
    let (dest, takeoff) = (pos(last), first.first().arrive);
    let _ = writeln!(
        text,
        "# flight {cs}: request {}, leg {}/{}, {} -> {}, take-off {}, landing {}, destination \
         {:.7} {:.7}",
        leg.request,
        leg.number,
        leg.count,
        airspace.node(flat(first.first().node)).id,
        airspace.node(flat(last.first().node)).id,
        clock_ms(takeoff - origin),
        clock_ms(last.first().arrive - origin),
        dest.lat,
        dest.lon
    );
    let heading = visits
        .get(1)
        .map_or(0.0, |next| bearing(pos(first), pos(next)));
    let hovers_first = first.last().depart > first.first().arrive;
    let start = pos(first);
    let _ = writeln!(
        text,
        "{}>CRE {cs} {} {:.7} {:.7} {heading:.1} {:.3} {:.4}",
        t(takeoff),
        options.aircraft_type,
        start.lat,
        start.lon,
        altitude(airspace, first.first().node).m() / FT_M,
        if hovers_first {
            0.0
        } else {
            speed(first.first().node)
        }
    );
    write_route(
        text,
        cs,
        &t(takeoff),
        &visits.iter().map(pos).collect::<Vec<_>>(),
    );
    // Keep the planned times: a required time of arrival at every waypoint.
    let keep = !options.open_loop && visits.len() > 1;
    if keep {
        for (i, v) in visits.iter().enumerate().skip(1) {
            let _ = writeln!(
                text,
                "{}>RTA {cs} {cs}{i:03} {}",
                t(takeoff),
                t(v.first().arrive)
            );
        }
        let _ = writeln!(text, "{}>VNAV {cs} ON", t(takeoff));
    }
    let climb = airspace
        .layers()
        .map_or(Layers::default().climb_mm_per_s, |l| l.climb_mm_per_s);
    let climb_fpm = f64::from(climb) / 1e3 / FT_M * 60.0;
    for (i, v) in visits[..visits.len() - 1].iter().enumerate() {
        let (arrive, depart) = (t(v.first().arrive), t(v.last().depart));
        // A hover shorter than BlueSky's hundredth of a second is no hover.
        if depart <= arrive {
            continue;
        }
        if i > 0 {
            let _ = writeln!(text, "{arrive}>SPD {cs} 0");
        }
        for w in v.stays.windows(2) {
            let _ = writeln!(
                text,
                "{}>ALT {cs} {:.3} {climb_fpm:.1}",
                t(w[0].depart),
                altitude(airspace, w[1].node).m() / FT_M
            );
        }
        let _ = writeln!(text, "{depart}>SPD {cs} {:.4}", speed(v.last().node));
        if keep {
            let _ = writeln!(text, "{depart}>VNAV {cs} ON");
        }
    }
}

/// Writes the route of a leg created at `at` over `points[0]`: a waypoint per further point,
/// fly-by where the route turns by 90° or less and fly-over where it turns more (BlueSky
/// starts a fly-by turn `R·tan(turn/2)` before the waypoint: without bound as the turn nears
/// 180°), and the deletion as it passes the last.
fn write_route(text: &mut String, cs: &str, at: &str, points: &[LonLat]) {
    let mut flyover = false;
    for (i, p) in points.iter().enumerate().skip(1) {
        let sharp = points.get(i + 1).is_some_and(|next| {
            let turn = (bearing(*p, *next) - bearing(points[i - 1], *p)).rem_euclid(360.0);
            turn.min(360.0 - turn) > MAX_FLYBY_TURN
        });
        if sharp != flyover {
            flyover = sharp;
            let mode = if sharp { "FLYOVER" } else { "FLYBY" };
            let _ = writeln!(text, "{at}>ADDWPT {cs} {mode}");
        }
        let _ = writeln!(text, "{at}>ADDWPT {cs} {:.7} {:.7}", p.lat, p.lon);
    }
    if points.len() > 1 {
        let _ = writeln!(text, "{at}>AT {cs} {cs}{:03} DO DEL {cs}", points.len() - 1);
    }
}

/// `HH:MM:SS.hh` of `ms` milliseconds (rounded to the hundredth; hours may exceed 23).
fn clock(ms: muse_model::Millis) -> String {
    let cs = (ms.0.max(0) + 5) / 10;
    format!(
        "{:02}:{:02}:{:02}.{:02}",
        cs / 360_000,
        cs / 6_000 % 60,
        cs / 100 % 60,
        cs % 100
    )
}

/// `HH:MM:SS.mmm` of `ms` milliseconds (hours may exceed 23).
fn clock_ms(ms: muse_model::Millis) -> String {
    let ms = ms.0.max(0);
    format!(
        "{:02}:{:02}:{:02}.{:03}",
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1_000 % 60,
        ms % 1_000
    )
}

#[cfg(test)]
mod tests;
