//! What the service plans on and shares between its planner task and its handlers.

use std::sync::RwLock;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use muse_airspace::closures::{ClosureError, Closures, resolve};
use muse_model::{Airspace, FlightParams, Instant, Millis, UtcOffset, Zone};

use crate::events::Events;
use crate::flights::FlightIndex;
use crate::metrics::Metrics;
use crate::store::Reads;
use crate::zones::book::ZoneBook;

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
    /// Their closures, resolved from a day before start to `CALENDAR` (366 days) after it.
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
    pub(crate) fn announced_closures(
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

    /// What a store must have been written for to be restored here, in words: the airspace
    /// and zones (counts and checksums of their canonical files) and every flight parameter
    /// (`("speed", "30 km/h")`). A store written for anything else is refused, naming what
    /// differs.
    pub fn description(&self) -> Vec<(String, String)> {
        let flat = self.airspace.flat();
        let airspace = muse_formats::airspace_geojson::write_airspace(flat);
        let zones = muse_formats::zones::write_ed318(&self.zones);
        let p = &self.params;
        let secs = |m: Millis| format!("{} s", m.as_secs_f64());
        let mins = |m: Millis| format!("{} min", m.as_secs_f64() / 60.0);
        let stations = flat.stations().count();
        let ids: Vec<&str> = self.zones.iter().map(|z| z.id.as_str()).collect();
        let mut rows = vec![
            (
                "airspace",
                format!(
                    "{} stations, {} waypoints and {} corridors (GeoJSON checksum {:08x})",
                    stations,
                    flat.node_count() - stations,
                    flat.edge_count(),
                    crc32fast::hash(airspace.as_bytes()),
                ),
            ),
            (
                "zones",
                if ids.is_empty() {
                    "none".to_owned()
                } else {
                    format!(
                        "{} (ED-318 checksum {:08x})",
                        ids.join(", "),
                        crc32fast::hash(zones.as_bytes())
                    )
                },
            ),
            ("speed", format!("{} km/h", p.speed.kmh())),
            ("battery", mins(p.max_flight)),
            ("node separation", secs(p.node_separation)),
            (
                "edge rule",
                match p.edge_rule {
                    muse_model::EdgeRule::Exclusive => "exclusive".to_owned(),
                    muse_model::EdgeRule::Headway(h) => format!("headway {}", secs(h)),
                },
            ),
            ("ground delay", secs(p.max_ground_delay)),
            (
                "battery swaps",
                p.battery_swap.map_or("off".to_owned(), |s| {
                    format!(
                        "{}, {}",
                        secs(s.time),
                        s.max_legs
                            .map_or("any number of legs".into(), |k| format!("at most {k} legs"))
                    )
                }),
            ),
            (
                "delivery deadline",
                p.max_trip.map_or("none".to_owned(), mins),
            ),
        ];
        // Only with metric separation on is there the row: a store without it keeps its meta.
        if p.separation.is_on() {
            rows.push((
                "metric separation",
                format!(
                    "{} m horizontally or {} m vertically",
                    p.separation.horizontal,
                    p.separation.vertical_in(&self.airspace)
                ),
            ));
        }
        // Only a layered world has the row: a flat store's meta is as before layers.
        if let Some(l) = self.airspace.layers() {
            rows.push((
                "layers",
                format!(
                    "{} from {} m, {} m apart, climbing at {} mm/s ({} ms a link), heading rule {}",
                    l.count,
                    l.base,
                    l.spacing,
                    l.climb_mm_per_s,
                    l.climb_time().0,
                    l.heading_rule
                ),
            ));
        }
        rows.into_iter().map(|(k, v)| (k.to_owned(), v)).collect()
    }

    /// How the earlier versions' log described the world it was written for (to convert such
    /// a log: see `store::legacy`).
    pub fn legacy_fingerprint(&self) -> String {
        let airspace = muse_formats::airspace_geojson::write_airspace(self.airspace.flat());
        let zones = muse_formats::zones::write_ed318(&self.zones);
        let p = &self.params;
        // Logs written without battery swaps kept the description they were written with.
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

pub(crate) fn system_ms() -> i64 {
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
    /// The flights the schedule holds, for reads.
    pub index: RwLock<FlightIndex>,
    /// Reads of every other flight, and of the event history.
    pub reader: Box<dyn Reads>,
    /// Whether the service has loaded its store.
    pub phase: Phase,
    /// Counters and histograms.
    pub metrics: Metrics,
    /// The clock.
    pub clock: Clock,
    /// The zones known from the start and those announced since (written by the planner
    /// task only).
    pub zones: RwLock<ZoneBook>,
    /// The flights' change events (published by the planner task only).
    pub events: Events,
    /// Leader or standby (set by the planner task).
    pub role: crate::role::Role,
    /// This service's address as other services reach it (advertised when it leads).
    pub address: String,
}

/// Where a starting service is: loading its store, or serving.
#[derive(Debug, Default)]
pub struct Phase {
    ready: AtomicBool,
    /// Records of an earlier version's log converted so far.
    imported: AtomicU64,
    /// Flights still ahead loaded so far, and how many there are.
    loaded: AtomicU64,
    to_load: AtomicU64,
}

/// What a starting service has done so far (`GET /healthz` while `starting`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Progress {
    /// Records of an earlier version's log converted so far (0 when there is none).
    pub imported_records: u64,
    /// Flights still ahead put back into the schedule so far.
    pub flights_loaded: u64,
    /// Flights still ahead to put back (0 until counted).
    pub flights_to_load: u64,
}

impl Phase {
    /// Whether the store is loaded and the service answers.
    pub fn is_ready(&self) -> bool {
        self.ready.load(Ordering::Acquire)
    }

    /// Marks the service ready.
    pub fn set_ready(&self) {
        self.ready.store(true, Ordering::Release);
    }

    /// What has been done so far.
    pub fn progress(&self) -> Progress {
        Progress {
            imported_records: self.imported.load(Ordering::Relaxed),
            flights_loaded: self.loaded.load(Ordering::Relaxed),
            flights_to_load: self.to_load.load(Ordering::Relaxed),
        }
    }

    /// Records converted so far.
    pub fn set_imported(&self, n: u64) {
        self.imported.store(n, Ordering::Relaxed);
    }

    /// Flights to load.
    pub fn set_to_load(&self, n: u64) {
        self.to_load.store(n, Ordering::Relaxed);
    }

    /// Flights loaded so far.
    pub fn set_loaded(&self, n: u64) {
        self.loaded.store(n, Ordering::Relaxed);
    }
}
