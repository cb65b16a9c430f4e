//! The `separation` section of a summary: how close the day's flights come in metres
//! (docs/reference.md#metric-separation), as `muse verify` reports it.

use std::collections::BTreeMap;

use muse_model::{Airspace, Instant, Separation, UtcOffset};
use muse_verify::Flight;
use muse_verify::approach::{FARTHEST_M, Positions, REPORTED_M, Report, report};
use serde::Serialize;

/// How close the flights come (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SeparationSummary {
    /// The vertical separation the report was made with, metres.
    pub vertical_m: f64,
    /// The closest approach of any two flights, metres, rounded to the millimetre (`None`:
    /// never two within 5 km of each other).
    pub closest_m: Option<f64>,
    /// The two requests, the instant and the node nearest to the first, when there is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closest: Option<ClosestRecord>,
    /// Pairs of flights closer than 10, 20 and 30 m.
    pub pairs_under_m: BTreeMap<u32, usize>,
    /// With metric separation on, its `D`, metres (`parameters.separation_m`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation_m: Option<f64>,
    /// With metric separation on, the pairs closer than its `D`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pairs_under_separation: Option<usize>,
}

/// Where and when the closest approach is.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClosestRecord {
    /// The two requests' ids.
    pub requests: [String; 2],
    /// The instant, RFC 3339 to the millisecond in the day's offset.
    pub at: String,
    /// The node nearest to the first flight then.
    pub near: String,
}

impl SeparationSummary {
    /// The report on `flights` flown over `airspace`, whose flat nodes are at `plane` (metres),
    /// instants written in `offset`, under the metric separation `rule` (its `V`, and the
    /// pairs closer than its `D` when on).
    #[must_use]
    pub fn of(
        airspace: &Airspace,
        plane: &[[f64; 2]],
        flights: &[Flight<'_>],
        offset: UtcOffset,
        rule: Separation,
    ) -> SeparationSummary {
        let positions = Positions::new(airspace, plane);
        let vertical = rule.vertical_in(airspace).m();
        let mut distances = REPORTED_M.to_vec();
        if rule.is_on() {
            distances.push(rule.horizontal.m());
        }
        let r = report(&positions, flights, &distances, vertical);
        let mut summary = SeparationSummary::from_report(&r, flights, airspace, offset);
        if rule.is_on() {
            summary.separation_m = Some(rule.horizontal.m());
            summary.pairs_under_separation = Some(r.under.get(REPORTED_M.len()).map_or(0, |u| u.1));
        }
        summary
    }

    /// The report in words: `closest approach 2.4 m (r1612 and r2935 at …, near S011); pairs
    /// closer than 10 m: 4, 20 m: 21, 30 m: 45 (vertical separation 9.144 m)`.
    #[must_use]
    pub fn describe(&self) -> String {
        let closest = match (&self.closest_m, &self.closest) {
            (Some(d), Some(c)) => format!(
                "closest approach {d:.1} m ({} and {} at {}, near {})",
                c.requests[0], c.requests[1], c.at, c.near
            ),
            _ => format!("no two flights come within {FARTHEST_M} m of each other"),
        };
        let under: Vec<String> = self
            .pairs_under_m
            .iter()
            .map(|(d, n)| format!("{d} m: {n}"))
            .collect();
        let rule = match (self.separation_m, self.pairs_under_separation) {
            (Some(d), Some(n)) => format!("; closer than D = {d} m, the rule: {n}"),
            _ => String::new(),
        };
        format!(
            "{closest}; pairs closer than {}{rule} (vertical separation {} m)",
            under.join(", "),
            self.vertical_m
        )
    }

    fn from_report(
        r: &Report,
        flights: &[Flight<'_>],
        airspace: &Airspace,
        offset: UtcOffset,
    ) -> SeparationSummary {
        SeparationSummary {
            vertical_m: r.vertical_m,
            closest_m: r
                .closest
                .as_ref()
                .map(|c| (c.distance_m * 1000.0).round() / 1000.0),
            closest: r.closest.as_ref().map(|c| ClosestRecord {
                requests: [
                    flights[c.flights.0].id.to_owned(),
                    flights[c.flights.1].id.to_owned(),
                ],
                at: Instant(c.at_ms.round() as i64).to_rfc3339(offset),
                near: airspace.node(c.near).id.clone(),
            }),
            pairs_under_m: r
                .under
                .iter()
                .take(REPORTED_M.len())
                .map(|&(d, n)| (d as u32, n))
                .collect(),
            separation_m: None,
            pairs_under_separation: None,
        }
    }
}
