//! The world of an announcement-lead sweep, prepared once: the zones known from the start, the
//! zones to announce with the first instant each becomes active, and one planned day per
//! [`LeadCase`].

use muse_airspace::announced::{Announced, KnownZones};
use muse_airspace::closures::{ClosureError, Closures, resolve, zone_windows};
use muse_model::{Airspace, FlightParams, Instant, Millis, Request, UtcOffset, Zone};
use muse_planner::Planner;
use muse_planner::ZoneError;

use super::case::{LeadCase, LeadError};
use crate::day::{DayRun, plan_sorted};
use crate::replay::replay;

/// The start of the first window of `zone` that begins in `[from, to)`: when the zone first
/// becomes active on a day. `None` when no window begins in that range (a permanent zone, a
/// zone on other days, or one already active at `from` and not closing again before `to`).
///
/// ```
/// use muse_model::{Instant, Period, Zone};
/// use muse_sim::experiment::lead::first_window_start;
/// let min = |m: i64| Instant(m * 60_000);
/// let zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: String::new(), area: None,
///     node_ids: vec![], edge_ids: vec![], announced: None, withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
///     periods: vec![
///         Period { start: Some(min(900)), end: Some(min(960)), daily: vec![] },
///         Period { start: Some(min(600)), end: Some(min(720)), daily: vec![] },
///     ],
/// };
/// assert_eq!(first_window_start(&zone, min(0), min(1440)).unwrap(), Some(min(600)));
/// // A window already running at the start of the range does not begin in it.
/// assert_eq!(first_window_start(&zone, min(660), min(1440)).unwrap(), Some(min(900)));
/// assert_eq!(first_window_start(&zone, min(1000), min(1440)).unwrap(), None);
/// ```
pub fn first_window_start(
    zone: &Zone,
    from: Instant,
    to: Instant,
) -> Result<Option<Instant>, ClosureError> {
    // One millisecond earlier, so that a window running at `from` starts before it (windows
    // are clipped to the range) and is told apart from one that begins exactly at `from`.
    let windows = zone_windows(zone, from - Millis(1), to)?;
    Ok(windows.iter().map(|w| w.start).find(|&s| s >= from))
}

/// One zone to announce, resolved.
#[derive(Clone, Debug)]
struct ToAnnounce {
    id: String,
    first_window: Instant,
    closures: Closures,
}

/// An airspace, its flight parameters and zones, prepared for planning the same demand under
/// every [`LeadCase`]: the zone closures are resolved once, the announcement instants are
/// derived per case.
#[derive(Debug)]
pub struct LeadWorld<'a> {
    airspace: &'a Airspace,
    params: FlightParams,
    /// The zones known from the start.
    base: Closures,
    /// The base zones and the zones to announce, all known from the start.
    known: Closures,
    announce: Vec<ToAnnounce>,
    /// A planner shared by the runs that need no replay.
    planner: Planner<'a>,
}

/// The day whose first active windows set the announcement instants: `[start, end)`, and the
/// offset its instants are written in (messages only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScenarioDay {
    /// Its first instant (local midnight).
    pub start: Instant,
    /// The first instant after it.
    pub end: Instant,
    /// Its UTC offset.
    pub offset: UtcOffset,
}

impl ScenarioDay {
    /// `t` as a clock time `HH:MM` of the day (` +1d` past its end, ` -1d` before it).
    ///
    /// ```
    /// use muse_model::{Instant, UtcOffset};
    /// use muse_sim::experiment::lead::ScenarioDay;
    /// let day = ScenarioDay { start: Instant(0), end: Instant(86_400_000), offset: UtcOffset(0) };
    /// assert_eq!(day.clock(Instant(600 * 60_000)), "10:00");
    /// assert_eq!(day.clock(Instant(-30 * 60_000)), "23:30 -1d");
    /// ```
    pub fn clock(self, t: Instant) -> String {
        let mins = (t - self.start).0.div_euclid(60_000);
        let (d, m) = (mins.div_euclid(1_440), mins.rem_euclid(1_440));
        let extra = if d == 0 {
            String::new()
        } else {
            format!(" {d:+}d")
        };
        format!("{:02}:{:02}{extra}", m / 60, m % 60)
    }
}

impl<'a> LeadWorld<'a> {
    /// Prepares `airspace` with `base` zones (known from the start; their own announcement
    /// instants are ignored) and `announce` zones (announced at their first window's start
    /// on `day` minus the lead), closures resolved over `[from, to)`.
    ///
    /// Errors: no zone to announce, two zones to announce with the same id, a zone to announce
    /// with no window beginning on `day`, a zone that cannot be resolved.
    pub fn new(
        airspace: &'a Airspace,
        params: FlightParams,
        base: &[Zone],
        announce: &[Zone],
        day: ScenarioDay,
        (from, to): (Instant, Instant),
    ) -> Result<Self, LeadError> {
        if announce.is_empty() {
            return Err(LeadError::NothingToAnnounce);
        }
        let unannounced = |z: &Zone| Zone {
            announced: None,
            withdrawn: None,
            ..z.clone()
        };
        let base: Vec<Zone> = base.iter().map(unannounced).collect();
        let mut prepared: Vec<ToAnnounce> = Vec::with_capacity(announce.len());
        for zone in announce {
            if prepared.iter().any(|p| p.id == zone.id) {
                return Err(ZoneError::Taken(zone.id.clone()).into());
            }
            let zone = unannounced(zone);
            let first_window = first_window_start(&zone, day.start, day.end)?.ok_or_else(|| {
                LeadError::NoWindow {
                    zone: zone.id.clone(),
                    from: day.start.to_rfc3339(day.offset),
                    to: day.end.to_rfc3339(day.offset),
                }
            })?;
            prepared.push(ToAnnounce {
                id: zone.id.clone(),
                first_window,
                closures: resolve(airspace, std::slice::from_ref(&zone), from, to)?,
            });
        }
        let resolved_base = resolve(airspace, &base, from, to)?;
        let mut known = resolved_base.clone();
        for p in &prepared {
            known.add(&p.closures);
        }
        Ok(LeadWorld {
            airspace,
            params,
            base: resolved_base,
            known,
            announce: prepared,
            planner: Planner::new(airspace, params),
        })
    }

    /// The airspace.
    pub fn airspace(&self) -> &'a Airspace {
        self.airspace
    }

    /// The zones to announce and the start of each one's first window on the day, in the
    /// order given.
    pub fn first_windows(&self) -> impl Iterator<Item = (&str, Instant)> + '_ {
        self.announce
            .iter()
            .map(|a| (a.id.as_str(), a.first_window))
    }

    /// The zones planned against in `case`: for a lead, the base zones from the start and each
    /// zone to announce at its first window's start minus the lead (in order of announcement,
    /// then id); for [`LeadCase::Known`], all of them from the start; for
    /// [`LeadCase::NoZone`], the base zones alone.
    pub fn zones(&self, case: LeadCase) -> KnownZones {
        match case {
            LeadCase::Announced { lead } => {
                let mut announced: Vec<Announced> = self
                    .announce
                    .iter()
                    .map(|a| Announced {
                        zone: a.id.clone(),
                        at: a.first_window - lead,
                        withdrawn: None,
                        closures: a.closures.clone(),
                    })
                    .collect();
                announced.sort_by(|a, b| a.at.cmp(&b.at).then_with(|| a.zone.cmp(&b.zone)));
                KnownZones {
                    base: self.base.clone(),
                    announced,
                }
            }
            LeadCase::Known => KnownZones {
                base: self.known.clone(),
                announced: Vec::new(),
            },
            LeadCase::NoZone => KnownZones {
                base: self.base.clone(),
                announced: Vec::new(),
            },
        }
    }

    /// Plans `requests` (in planning order `(submitted, id)`) in `case`: replayed with the
    /// announcements of a lead (docs/reference.md#zones-announced-during-the-day), or planned first
    /// come, first served against zones all known from the start.
    pub fn run(&self, case: LeadCase, requests: &[Request]) -> Result<DayRun, LeadError> {
        let zones = self.zones(case);
        if zones.announced.is_empty() {
            let (outcomes, planner_wall) =
                plan_sorted(&self.planner, &zones.base, requests, |_| {});
            return Ok(DayRun::unchanged(
                requests.to_vec(),
                outcomes,
                planner_wall,
                zones,
            ));
        }
        let planner = Planner::new(self.airspace, self.params);
        let run = replay(planner, &zones, requests, |_| {})?;
        Ok(DayRun::replayed(requests.to_vec(), run, zones))
    }
}
