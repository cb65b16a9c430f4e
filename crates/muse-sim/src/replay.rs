//! A day as it unfolds (docs/reference.md#requests, #zones-announced-during-the-day): requests
//! reach the planner at their submission instants, zones are announced at theirs, and every
//! announcement replans the flights it hits.
//!
//! Events are taken in time order: requests by `(submitted, id)`, each zone at its
//! announcement instant (zones announced at the same instant by id), and an announcement
//! before a request at the same instant. The planner is the online one ([`Live`]) with the
//! clock at each event's instant, so a request is planned against every flight accepted
//! before it and every zone known by then, and an announcement replans exactly as
//! [`muse_planner::Live::announce`] does.

use std::time::{Duration, Instant as WallInstant};

use muse_airspace::announced::KnownZones;
use muse_model::plan::{Change, Fate};
use muse_model::{Instant, Plan, Request};
use muse_planner::ZoneError;
use muse_planner::{FlightId, Live, Outcome, Planner};

/// One zone announcement of a replayed day.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Announcement {
    /// The zone's id.
    pub zone: String,
    /// When it was announced.
    pub at: Instant,
    /// How many accepted flights it affected.
    pub affected: usize,
}

/// What planning a day made of its requests: the first answer to each, what the zones
/// announced during the day did to their flights since (nothing when none is announced), and
/// the time it took. [`replay`] makes one; a day planned against zones all known from the
/// start is [`Replay::unchanged`].
#[derive(Debug)]
pub struct Replay {
    /// The first answer to each request (plan or rejection), as planned at submission, in
    /// planning order (the order of `requests` given).
    pub outcomes: Vec<Outcome>,
    /// What announcements did to each request's flight since, in order (same indexing; all
    /// empty when no zone is announced).
    pub changes: Vec<Vec<Change>>,
    /// What the last of them made of each request's flight, with its plan; `None` if none
    /// changed it (same indexing).
    pub fates: Vec<Option<Fate>>,
    /// The zones announced, in order.
    pub announcements: Vec<Announcement>,
    /// Wall time of the planning loop alone (no I/O, no zone resolution), replanning included.
    pub planner_wall: Duration,
    /// Search effort of replanning, labels expanded (not in the outcomes' counts).
    pub replan_expanded: u64,
}

impl Replay {
    /// A day no zone announcement changed: `outcomes`, planned in `planner_wall`.
    pub fn unchanged(outcomes: Vec<Outcome>, planner_wall: Duration) -> Self {
        let n = outcomes.len();
        Replay {
            outcomes,
            changes: vec![Vec::new(); n],
            fates: vec![None; n],
            announcements: Vec::new(),
            planner_wall,
            replan_expanded: 0,
        }
    }

    /// The last fate of request `i`'s flight, if an announcement changed it.
    pub fn fate(&self, i: usize) -> Option<&Fate> {
        self.fates[i].as_ref()
    }

    /// The final plan of request `i`, if its flight lands somewhere: its first plan, or the
    /// plan the last announcement replanned or diverted it to.
    pub fn final_plan(&self, i: usize) -> Option<&Plan> {
        match self.fate(i) {
            None => self.outcomes[i].result.as_ref().ok(),
            Some(f) => f.plan(),
        }
    }
}

/// Replays `requests` (in planning order, `(submitted, id)`) against `zones`: those known
/// from the start from the beginning, announced ones at their instants. `progress` is called
/// with the number of requests done.
///
/// Errors: two announced zones with the same id.
pub fn replay(
    planner: Planner<'_>,
    zones: &KnownZones,
    requests: &[Request],
    mut progress: impl FnMut(usize),
) -> Result<Replay, ZoneError> {
    let start = requests.first().map_or(Instant(0), |r| r.submitted);
    let start = zones.announced.first().map_or(start, |a| a.at.min(start));
    let mut live = Live::new(planner, &zones.base, start);
    let mut outcomes = Vec::with_capacity(requests.len());
    let mut changes: Vec<Vec<Change>> = Vec::with_capacity(requests.len());
    let mut fates: Vec<Option<Fate>> = Vec::with_capacity(requests.len());
    let mut announcements = Vec::with_capacity(zones.announced.len());
    let mut replan_expanded = 0;
    let mut next_zone = 0;
    let started = WallInstant::now();
    let mut announce_until = |t: Option<Instant>,
                              live: &mut Live<'_>,
                              changes: &mut Vec<Vec<Change>>,
                              fates: &mut Vec<Option<Fate>>|
     -> Result<(), ZoneError> {
        while let Some(a) = zones.announced.get(next_zone) {
            if t.is_some_and(|t| a.at > t) {
                break;
            }
            next_zone += 1;
            live.advance(a.at);
            let affected = live.announce(&a.zone, a.closures.clone())?;
            announcements.push(Announcement {
                zone: a.zone.clone(),
                at: a.at,
                affected: affected.len(),
            });
            for x in affected {
                replan_expanded += x.expanded;
                let i = x.flight.index();
                changes[i].push(x.change(&a.zone, a.at));
                fates[i] = Some(x.fate);
            }
        }
        Ok(())
    };
    for (i, r) in requests.iter().enumerate() {
        announce_until(Some(r.submitted), &mut live, &mut changes, &mut fates)?;
        live.advance(r.submitted);
        outcomes.push(live.book(FlightId::from(i), r));
        changes.push(Vec::new());
        fates.push(None);
        progress(i + 1);
    }
    announce_until(None, &mut live, &mut changes, &mut fates)?;
    Ok(Replay {
        outcomes,
        changes,
        fates,
        announcements,
        planner_wall: started.elapsed(),
        replan_expanded,
    })
}

/// A small day to test replaying on: `A - B`, 1 km (two minutes at 30 km/h); zone `Z` closes
/// B 10:00–10:10 (minutes since the epoch) and is announced at 09:00; 30 minutes of ground
/// delay allowed.
#[cfg(test)]
pub(crate) mod example {
    use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId, Period, Request, Zone};

    /// Minute `m` since the epoch.
    pub fn min(m: i64) -> Instant {
        Instant(m * 60_000)
    }

    /// `A - B`.
    pub fn airspace() -> Airspace {
        Airspace::line(&[1_000.0])
    }

    /// Up to 30 minutes of ground delay.
    pub fn params() -> FlightParams {
        FlightParams {
            max_ground_delay: Millis::from_mins(30),
            ..FlightParams::default()
        }
    }

    /// `Z`: B closed 10:00–10:10, announced at 09:00.
    pub fn zone() -> Zone {
        Zone {
            id: "Z".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: vec![],
            announced: Some(min(540)),
            withdrawn: None,
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
            periods: vec![Period {
                start: Some(min(600)),
                end: Some(min(610)),
                daily: vec![],
            }],
        }
    }

    /// A → B departing at minute `dep`, submitted at minute `sub`.
    pub fn request(id: &str, dep: i64, sub: i64) -> Request {
        Request {
            id: id.into(),
            origin: NodeId(0),
            destination: NodeId(1),
            departure: min(dep),
            submitted: min(sub),
        }
    }

    /// Booked at 08:00 (before the announcement) and at 09:30 (after), both departing 09:59.
    pub fn requests() -> Vec<Request> {
        vec![request("early", 599, 480), request("late", 599, 570)]
    }
}

#[cfg(test)]
mod tests {
    use muse_airspace::announced::KnownZones;
    use muse_model::Instant;
    use muse_planner::Fate;
    use muse_planner::Planner;

    use super::example::{airspace, min, params, requests, zone};
    use super::{Announcement, replay};

    #[test]
    fn an_announcement_replans_the_flights_booked_before_it_only() {
        let a = airspace();
        let known = KnownZones::resolve(&a, &[zone()], Instant(0), min(1440)).unwrap();
        let run = replay(Planner::new(&a, params()), &known, &requests(), |_| {}).unwrap();
        assert_eq!(
            run.announcements,
            [Announcement {
                zone: "Z".to_owned(),
                at: min(540),
                affected: 1
            }]
        );
        assert_eq!(run.outcomes[0].result.as_ref().unwrap().takeoff(), min(599));
        // Replanned to land when B opens again, 10:10.
        let [change] = &run.changes[0][..] else {
            panic!("one change expected: {:?}", run.changes[0]);
        };
        assert_eq!((change.zone.as_str(), change.announced), ("Z", min(540)));
        let Some(Fate::Replanned(plan)) = &run.fates[0] else {
            panic!("replanned expected: {change:?}, {:?}", run.fates[0]);
        };
        assert_eq!(plan.landing(), min(610));
        // The late booking knew the zone: planned around it, never changed, after the other.
        assert!(run.changes[1].is_empty() && run.fates[1].is_none());
        assert_eq!(run.outcomes[1].result.as_ref().unwrap().landing(), min(612));
    }
}
