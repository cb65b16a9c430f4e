//! What one run of an announcement-lead sweep measured, and its row of `announce_lead.csv`.

use muse_model::UtcOffset;

use super::case::LeadCase;
use crate::day::DayRun;
use crate::demand::BookingLead;
use crate::experiment::grid::{booking_lead_ms, minutes};
use crate::experiment::report::Column;
use crate::metrics::ReplanSummary;

/// The measurements of one run: one demand (count, repetition, seed) planned in one
/// [`LeadCase`]. The counts are those of [`ReplanSummary`] (a flight hit by several
/// announcements counts once, by its last outcome). Serialized in sweep shards
/// (see [`crate::experiment::ShardFile`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LeadRecord {
    /// How the zones to announce became known.
    #[serde(with = "case_text")]
    pub case: LeadCase,
    /// Requests.
    pub count: usize,
    /// Repetition index.
    pub rep: usize,
    /// Demand seed (the same for every case of a count and repetition).
    pub seed: u64,
    /// How far ahead of departure the requests were booked.
    #[serde(with = "booking_lead_ms")]
    pub booking_lead: BookingLead,
    /// Requests planned when they were booked (first answers).
    pub planned_at_booking: usize,
    /// Requests whose final plan lands at their destination.
    pub delivered: usize,
    /// `delivered / count`: the success rate.
    pub delivery_rate: f64,
    /// Flights affected by an announcement.
    pub affected: usize,
    /// Of those, flights airborne at the announcement that hit them.
    pub airborne_affected: usize,
    /// Final outcome `replanned`.
    pub replanned: usize,
    /// Final outcome `diverted`.
    pub diverted: usize,
    /// Final outcome `cancelled`.
    pub cancelled: usize,
    /// Final outcome `contingency`.
    pub contingency: usize,
    /// Mean over replanned flights of final landing minus first planned landing, seconds;
    /// `None` when no flight was replanned.
    pub mean_extra_delay_s: Option<f64>,
    /// Planner wall time of the run (planning and replanning), milliseconds.
    pub planner_ms: f64,
    /// Search effort of replanning, labels expanded.
    pub replan_expanded: u64,
}

impl LeadRecord {
    /// The record of `run`, planned in `case` from the demand of repetition `rep` and `seed`.
    pub fn of(
        case: LeadCase,
        rep: usize,
        seed: u64,
        booking_lead: BookingLead,
        run: &DayRun,
    ) -> Self {
        let s = ReplanSummary::of(&run.replay, UtcOffset(0));
        LeadRecord {
            case,
            count: run.requests.len(),
            rep,
            seed,
            booking_lead,
            planned_at_booking: run
                .replay
                .outcomes
                .iter()
                .filter(|o| o.result.is_ok())
                .count(),
            delivered: s.delivered,
            delivery_rate: s.delivery_rate,
            affected: s.flights_affected,
            airborne_affected: s.airborne_affected,
            replanned: s.replanned,
            diverted: s.diverted,
            cancelled: s.cancelled,
            contingency: s.contingency,
            mean_extra_delay_s: (s.replanned > 0).then_some(s.extra_delay_s.mean),
            planner_ms: run.replay.planner_wall.as_secs_f64() * 1e3,
            replan_expanded: run.replay.replan_expanded,
        }
    }
}

/// `LeadCase::lead_min` as a cell: the lead in minutes, empty for `known` and `none`.
pub(crate) fn lead_cell(case: LeadCase) -> String {
    case.lead_min().map_or(String::new(), |m| m.to_string())
}

/// The columns of `announce_lead.csv`, one row per run. `case` is `announced`, `known` or
/// `none` (see [`LeadCase`]); `lead_min` is the lead in minutes, empty for `known` and `none`;
/// `mean_extra_delay_s` is empty when no flight was replanned; the last two columns are the
/// booking lead's bounds in minutes.
pub fn columns() -> Vec<Column<'static, LeadRecord>> {
    type R = LeadRecord;
    vec![
        Column::new("case", |r: &R| r.case.kind().to_owned()),
        Column::new("lead_min", |r: &R| lead_cell(r.case)),
        Column::new("count", |r: &R| r.count.to_string()),
        Column::new("rep", |r: &R| r.rep.to_string()),
        Column::new("seed", |r: &R| r.seed.to_string()),
        Column::new("planned_at_booking", |r: &R| {
            r.planned_at_booking.to_string()
        }),
        Column::new("delivered", |r: &R| r.delivered.to_string()),
        Column::new("success_rate", |r: &R| format!("{:.6}", r.delivery_rate)),
        Column::new("affected", |r: &R| r.affected.to_string()),
        Column::new("airborne_affected", |r: &R| r.airborne_affected.to_string()),
        Column::new("replanned", |r: &R| r.replanned.to_string()),
        Column::new("diverted", |r: &R| r.diverted.to_string()),
        Column::new("cancelled", |r: &R| r.cancelled.to_string()),
        Column::new("contingency", |r: &R| r.contingency.to_string()),
        Column::new("mean_extra_delay_s", |r: &R| {
            r.mean_extra_delay_s
                .map_or(String::new(), |x| format!("{x:.3}"))
        }),
        Column::new("planner_ms", |r: &R| format!("{:.3}", r.planner_ms)),
        Column::new("replan_expanded", |r: &R| r.replan_expanded.to_string()),
        Column::new("booking_lead_min_from", |r: &R| minutes(r.booking_lead.min)),
        Column::new("booking_lead_min_to", |r: &R| minutes(r.booking_lead.max)),
    ]
}

/// A [`LeadCase`] in files: `announced:LEAD_MS`, `known` or `none`.
mod case_text {
    use muse_model::Millis;
    use serde::{Deserialize, Deserializer, Serializer, de::Error as _};

    use crate::experiment::lead::case::LeadCase;

    pub fn serialize<S: Serializer>(case: &LeadCase, s: S) -> Result<S::Ok, S::Error> {
        match case {
            LeadCase::Announced { lead } => s.serialize_str(&format!("announced:{}", lead.0)),
            other => s.serialize_str(other.kind()),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<LeadCase, D::Error> {
        let text = String::deserialize(d)?;
        match text.as_str() {
            "known" => Ok(LeadCase::Known),
            "none" => Ok(LeadCase::NoZone),
            other => other
                .strip_prefix("announced:")
                .and_then(|ms| ms.parse().ok())
                .map(|ms| LeadCase::Announced { lead: Millis(ms) })
                .ok_or_else(|| D::Error::custom(format!("case `{other}`"))),
        }
    }
}
