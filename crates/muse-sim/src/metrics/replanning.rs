//! What zone announcements did to a day (docs/reference.md#zones-announced-during-the-day), as
//! `summary.json` reports it.

use muse_model::plan::Fate;
use muse_model::{Millis, Plan, UtcOffset};
use serde::Serialize;

use super::distribution::Distribution;
use crate::replay::Replay;

/// One announced zone, as reported.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct ZoneAnnounced {
    /// The zone's id.
    pub zone: String,
    /// When it was announced, RFC 3339.
    pub announced: String,
    /// Flights it affected.
    pub affected: usize,
}

/// The `replanning` section of `summary.json`: the zones announced during the day and what
/// became of the flights they hit.
///
/// A flight hit by several announcements counts once, by its last outcome. `delivered` counts
/// the requests whose final plan lands at their destination (planned and never changed, or
/// replanned); `extra_delay_s` is, over replanned flights, final landing minus the landing
/// first planned.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplanSummary {
    /// Zones announced.
    pub zones_announced: usize,
    /// Each announcement, in order.
    pub zones: Vec<ZoneAnnounced>,
    /// Flights affected by at least one announcement.
    pub flights_affected: usize,
    /// Of those, flights airborne at an announcement that hit them.
    pub airborne_affected: usize,
    /// Final outcome `replanned`.
    pub replanned: usize,
    /// Final outcome `diverted`.
    pub diverted: usize,
    /// Final outcome `cancelled` (reason `zone_announced`).
    pub cancelled: usize,
    /// Final outcome `contingency`.
    pub contingency: usize,
    /// Requests whose final plan lands at their destination.
    pub delivered: usize,
    /// `delivered / requests` (1 for an empty run).
    pub delivery_rate: f64,
    /// Replanned flights: final landing minus first planned landing, seconds.
    pub extra_delay_s: Distribution,
    /// Search effort of replanning, labels expanded.
    pub replan_expanded: u64,
}

impl ReplanSummary {
    /// The section for the day `run` planned, instants written in `offset`.
    pub fn of(run: &Replay, offset: UtcOffset) -> Self {
        let mut s = ReplanSummary {
            zones_announced: run.announcements.len(),
            zones: run
                .announcements
                .iter()
                .map(|a| ZoneAnnounced {
                    zone: a.zone.clone(),
                    announced: a.at.to_rfc3339(offset),
                    affected: a.affected,
                })
                .collect(),
            flights_affected: 0,
            airborne_affected: 0,
            replanned: 0,
            diverted: 0,
            cancelled: 0,
            contingency: 0,
            delivered: 0,
            delivery_rate: 1.0,
            extra_delay_s: Distribution::default(),
            replan_expanded: run.replan_expanded,
        };
        let mut extra: Vec<Millis> = Vec::new();
        for (i, (outcome, changes)) in run.outcomes.iter().zip(&run.changes).enumerate() {
            if changes.is_empty() {
                s.delivered += usize::from(outcome.result.is_ok());
                continue;
            }
            s.flights_affected += 1;
            s.airborne_affected += usize::from(changes.iter().any(|c| c.airborne));
            match run.fate(i) {
                Some(Fate::Replanned(p)) => {
                    s.replanned += 1;
                    s.delivered += 1;
                    if let Ok(first) = &outcome.result {
                        extra.push(p.landing() - Plan::landing(first));
                    }
                }
                Some(Fate::Diverted(_)) => s.diverted += 1,
                Some(Fate::Cancelled) => s.cancelled += 1,
                Some(Fate::Contingency(_)) | None => s.contingency += 1,
            }
        }
        if !run.outcomes.is_empty() {
            s.delivery_rate = s.delivered as f64 / run.outcomes.len() as f64;
        }
        s.extra_delay_s = Distribution::of(&extra);
        s
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use muse_airspace::announced::KnownZones;

    use super::*;
    use crate::day::plan_requests;
    use crate::replay::example::{airspace, params, requests, zone};

    #[test]
    fn counts_one_replanned_flight_and_its_extra_delay() {
        // The flight booked at 08:00 to land at 10:01 is replanned to land at 10:10, when B
        // opens again (nine minutes late); the one booked at 09:30 plans around the zone.
        let run = plan_requests(&airspace(), &[zone()], params(), requests(), |_| {}).unwrap();
        assert_ne!(run.zones, KnownZones::default());
        let s = ReplanSummary::of(&run.replay, UtcOffset::SINGAPORE);
        assert_eq!(s.zones_announced, 1);
        assert_eq!(s.zones[0].announced, "1970-01-01T17:00:00.000+08:00");
        assert_eq!((s.flights_affected, s.airborne_affected), (1, 0));
        assert_eq!(
            (s.replanned, s.diverted, s.cancelled, s.contingency),
            (1, 0, 0, 0)
        );
        assert_eq!((s.delivered, s.delivery_rate), (2, 1.0));
        assert_eq!(s.extra_delay_s.max, 540.0);
    }
}
