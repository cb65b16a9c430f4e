//! What the service plans on and shares between its planner task and its handlers.

use std::sync::RwLock;

use muse_airspace::closures::{ClosureError, Closures, resolve};
use muse_model::{Airspace, FlightParams, Instant, Millis, UtcOffset, Zone};

use crate::events::Events;
use crate::flights::FlightIndex;
use crate::metrics::Metrics;
use crate::zones::ZoneBook;

/// How far ahead zone calendars are expanded at start: a service that runs longer must be
/// restarted to plan beyond it (bookings are limited to [`ServiceWorld::booking_horizon`]).
pub const CALENDAR: Millis = Millis::from_secs(366 * 86_400);

/// How far back zone calendars are expanded: from a day before start (base zones) or before
/// the announcement (announced zones).
pub const CALENDAR_BEFORE: Millis = Millis::from_secs(86_400);

/// The airspace, zones and flight parameters a service plans with.
#[derive(Debug)]
pub struct ServiceWorld {
    /// A short description, for messages (e.g. `embedded singapore-77`).
    pub label: String,
    /// The airspace.
    pub airspace: Airspace,
    /// The zones.
    pub zones: Vec<Zone>,
    /// Their closures, resolved from a day before start to [`CALENDAR`] after it.
    pub closures: Closures,
    /// The flight parameters.
    pub params: FlightParams,
    /// The UTC offset of times in answers.
    pub offset: UtcOffset,
    /// Departures may be booked at most this far ahead of now.
    pub booking_horizon: Millis,
    /// The end of the resolved zone calendar.
    pub calendar_end: Instant,
}

impl ServiceWorld {
    /// Prepares a world, resolving the zones' calendars around `start`.
    pub fn new(
        label: String,
        airspace: Airspace,
        zones: Vec<Zone>,
        params: FlightParams,
        offset: UtcOffset,
        booking_horizon: Millis,
        start: Instant,
    ) -> Result<Self, ClosureError> {
        let calendar_end = start + CALENDAR;
        let closures = resolve(&airspace, &zones, start - CALENDAR_BEFORE, calendar_end)?;
        Ok(ServiceWorld {
            label,
            airspace,
            zones,
            closures,
            params,
            offset,
            booking_horizon,
            calendar_end,
        })
    }

    /// The closures of a zone announced at `announced`: its calendar resolved from
    /// [`CALENDAR_BEFORE`] before the announcement to the end of the service's calendar.
    pub fn announced_closures(
        &self,
        zones: &[Zone],
        announced: Instant,
    ) -> Result<Closures, ClosureError> {
        resolve(
            &self.airspace,
            zones,
            announced - CALENDAR_BEFORE,
            self.calendar_end.max(announced),
        )
    }

    /// What a store must have been written for to be restored here: the airspace, zones and
    /// parameters, as counts and checksums of their canonical files.
    pub fn fingerprint(&self) -> String {
        let airspace = muse_formats::airspace_geojson::write_airspace(&self.airspace);
        let zones = muse_formats::zones::write_ed318(&self.zones);
        let p = &self.params;
        // Logs written without battery swaps keep the description they were written with.
        let swaps = p.battery_swap.map_or(String::new(), |s| {
            format!(
                ", battery swaps {} ms, at most {} legs",
                s.time.0,
                s.max_legs.map_or("any".into(), |k| k.to_string())
            )
        });
        let deadline = p
            .max_trip
            .map_or(String::new(), |m| format!(", trips within {} ms", m.0));
        format!(
            "airspace of {} nodes and {} edges (crc {:08x}), {} zone(s) (crc {:08x}), \
             speed {} mm/s, battery {} ms, node separation {} ms, edges {:?}, ground delay {} ms{}{}",
            self.airspace.node_count(),
            self.airspace.edge_count(),
            crc32fast::hash(airspace.as_bytes()),
            self.zones.len(),
            crc32fast::hash(zones.as_bytes()),
            (p.speed.mps() * 1000.0).round(),
            p.max_flight.0,
            p.node_separation.0,
            p.edge_rule,
            p.max_ground_delay.0,
            swaps,
            deadline,
        )
    }
}

/// The service clock: the system clock, optionally shifted (tests and demonstrations may
/// start the clock at a chosen instant; it then runs at real speed).
#[derive(Clone, Copy, Debug, Default)]
pub struct Clock {
    offset_ms: i64,
}

impl Clock {
    /// The system clock.
    pub fn system() -> Self {
        Clock::default()
    }

    /// A clock that reads `start` now and runs at real speed from there.
    pub fn starting_at(start: Instant) -> Self {
        Clock {
            offset_ms: start.0 - system_ms(),
        }
    }

    /// Now.
    pub fn now(&self) -> Instant {
        Instant(system_ms() + self.offset_ms)
    }
}

fn system_ms() -> i64 {
    let d = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    d.as_millis() as i64
}

/// What the planner task and the handlers share.
#[derive(Debug)]
pub struct State {
    /// What is planned on.
    pub world: ServiceWorld,
    /// Every flight known, for reads.
    pub index: RwLock<FlightIndex>,
    /// Counters and histograms.
    pub metrics: Metrics,
    /// The clock.
    pub clock: Clock,
    /// How long after its end a flight stays in memory (for reads and idempotent retries),
    /// and an event in the history.
    pub retain: Millis,
    /// The zones known from the start and those announced since (written by the planner
    /// task only).
    pub zones: RwLock<ZoneBook>,
    /// The flights' change events (published by the planner task only).
    pub events: Events,
}
