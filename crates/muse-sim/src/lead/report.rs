//! An announcement-lead sweep as numbers: means with 95% confidence intervals per case and
//! count, and the two CSV files (`announce_lead.csv`, `announce_lead_summary.csv`).

use std::fmt::Write as _;

use super::{LeadCase, LeadRecord};
use crate::stats::MeanCi;

/// Mean and 95% CI of each run metric over the repetitions of one (case, count).
#[derive(Clone, Debug, PartialEq)]
pub struct LeadSummaryRow {
    /// How the zones to announce became known.
    pub case: LeadCase,
    /// Requests per run.
    pub count: usize,
    /// Runs summarized.
    pub runs: usize,
    /// Success rate: the share of requests delivered (final plan lands at the destination).
    pub success_rate: MeanCi,
    /// Requests planned when booked.
    pub planned_at_booking: MeanCi,
    /// Flights affected by an announcement.
    pub affected: MeanCi,
    /// Flights airborne at the announcement that affected them.
    pub airborne_affected: MeanCi,
    /// Flights replanned.
    pub replanned: MeanCi,
    /// Flights diverted.
    pub diverted: MeanCi,
    /// Flights cancelled.
    pub cancelled: MeanCi,
    /// Flights in contingency.
    pub contingency: MeanCi,
    /// Mean extra delay of the replanned flights of a run, seconds, over the runs that
    /// replanned any (its `n` says how many).
    pub extra_delay_s: MeanCi,
    /// Planner wall time per run, milliseconds.
    pub planner_ms: MeanCi,
}

/// Groups runs by (case, count), in the order cases and counts first appear.
///
/// ```
/// use muse_model::Millis;
/// use muse_sim::demand::BookingLead;
/// use muse_sim::lead::{LeadCase, LeadRecord, summarize};
/// let run = |case, rep, cancelled| LeadRecord {
///     case, count: 10, rep, seed: rep as u64, booking_lead: BookingLead::NONE,
///     planned_at_booking: 10, delivered: 10 - cancelled, delivery_rate: (10 - cancelled) as f64 / 10.0,
///     affected: cancelled, airborne_affected: 0, replanned: 0, diverted: 0, cancelled,
///     contingency: 0, mean_extra_delay_s: None, planner_ms: 1.0, replan_expanded: 0,
/// };
/// let lead = LeadCase::Announced { lead: Millis::from_mins(30) };
/// let rows = summarize(&[run(lead, 0, 2), run(lead, 1, 4), run(LeadCase::Known, 0, 0)]);
/// assert_eq!(rows.len(), 2);
/// assert_eq!((rows[0].runs, rows[0].cancelled.mean, rows[0].success_rate.mean), (2, 3.0, 0.7));
/// assert_eq!(rows[0].extra_delay_s.n, 0);
/// ```
pub fn summarize(records: &[LeadRecord]) -> Vec<LeadSummaryRow> {
    let mut keys: Vec<(LeadCase, usize)> = Vec::new();
    for r in records {
        if !keys.contains(&(r.case, r.count)) {
            keys.push((r.case, r.count));
        }
    }
    keys.into_iter()
        .map(|(case, count)| {
            let runs: Vec<&LeadRecord> = records
                .iter()
                .filter(|r| r.case == case && r.count == count)
                .collect();
            let ci = |f: fn(&LeadRecord) -> f64| {
                MeanCi::of(&runs.iter().map(|r| f(r)).collect::<Vec<_>>())
            };
            let extra: Vec<f64> = runs.iter().filter_map(|r| r.mean_extra_delay_s).collect();
            LeadSummaryRow {
                case,
                count,
                runs: runs.len(),
                success_rate: ci(|r| r.delivery_rate),
                planned_at_booking: ci(|r| r.planned_at_booking as f64),
                affected: ci(|r| r.affected as f64),
                airborne_affected: ci(|r| r.airborne_affected as f64),
                replanned: ci(|r| r.replanned as f64),
                diverted: ci(|r| r.diverted as f64),
                cancelled: ci(|r| r.cancelled as f64),
                contingency: ci(|r| r.contingency as f64),
                extra_delay_s: MeanCi::of(&extra),
                planner_ms: ci(|r| r.planner_ms),
            }
        })
        .collect()
}

/// The header of [`runs_csv`].
pub const RUNS_CSV_HEADER: &str = "case,lead_min,count,rep,seed,planned_at_booking,delivered,success_rate,affected,airborne_affected,replanned,diverted,cancelled,contingency,mean_extra_delay_s,planner_ms,replan_expanded,booking_lead_min_from,booking_lead_min_to";

/// `announce_lead.csv`: one row per run. `case` is `announced`, `known` or `none` (see
/// [`LeadCase`]); `lead_min` is the lead in minutes, empty for `known` and `none`;
/// `mean_extra_delay_s` is empty when no flight was replanned; the last two columns are the
/// booking lead's bounds in minutes.
pub fn runs_csv(records: &[LeadRecord]) -> String {
    let mut out = format!("{RUNS_CSV_HEADER}\n");
    for r in records {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{:.6},{},{},{},{},{},{},{},{:.3},{},{},{}",
            r.case.kind(),
            lead_cell(r.case),
            r.count,
            r.rep,
            r.seed,
            r.planned_at_booking,
            r.delivered,
            r.delivery_rate,
            r.affected,
            r.airborne_affected,
            r.replanned,
            r.diverted,
            r.cancelled,
            r.contingency,
            r.mean_extra_delay_s
                .map_or(String::new(), |x| format!("{x:.3}")),
            r.planner_ms,
            r.replan_expanded,
            r.booking_lead.min.as_secs_f64() / 60.0,
            r.booking_lead.max.as_secs_f64() / 60.0
        );
    }
    out
}

/// The metrics of [`summary_csv`], in column order.
const SUMMARY_METRICS: [&str; 10] = [
    "success_rate",
    "planned_at_booking",
    "affected",
    "airborne_affected",
    "replanned",
    "diverted",
    "cancelled",
    "contingency",
    "extra_delay_s",
    "planner_ms",
];

/// `announce_lead_summary.csv`: per case and count, the number of runs, the number of runs
/// with a replanned flight (those `extra_delay_s` averages over), then the mean and 95% CI
/// (`_mean`, `_ci95_low`, `_ci95_high`) of each metric.
pub fn summary_csv(rows: &[LeadSummaryRow]) -> String {
    let mut out = String::from("case,lead_min,count,runs,runs_with_replanned");
    for m in SUMMARY_METRICS {
        let _ = write!(out, ",{m}_mean,{m}_ci95_low,{m}_ci95_high");
    }
    out.push('\n');
    for r in rows {
        let _ = write!(
            out,
            "{},{},{},{},{}",
            r.case.kind(),
            lead_cell(r.case),
            r.count,
            r.runs,
            r.extra_delay_s.n
        );
        for m in [
            r.success_rate,
            r.planned_at_booking,
            r.affected,
            r.airborne_affected,
            r.replanned,
            r.diverted,
            r.cancelled,
            r.contingency,
            r.extra_delay_s,
            r.planner_ms,
        ] {
            let _ = write!(out, ",{:.6},{:.6},{:.6}", m.mean, m.low(), m.high());
        }
        out.push('\n');
    }
    out
}

fn lead_cell(case: LeadCase) -> String {
    case.lead_min().map_or(String::new(), |m| m.to_string())
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use muse_model::Millis;

    use super::*;
    use crate::demand::BookingLead;

    fn record(case: LeadCase, rep: usize, extra: Option<f64>) -> LeadRecord {
        LeadRecord {
            case,
            count: 4,
            rep,
            seed: 7 + rep as u64,
            booking_lead: BookingLead::new(Millis::ZERO, Millis::from_mins(120)).unwrap(),
            planned_at_booking: 4,
            delivered: 3,
            delivery_rate: 0.75,
            affected: 2,
            airborne_affected: 1,
            replanned: usize::from(extra.is_some()),
            diverted: 0,
            cancelled: 1,
            contingency: 0,
            mean_extra_delay_s: extra,
            planner_ms: 1.5,
            replan_expanded: 9,
        }
    }

    #[test]
    fn csv_rows_and_extra_delay_over_runs_that_replanned() {
        let lead = LeadCase::Announced {
            lead: Millis::from_mins(15),
        };
        let records = [
            record(lead, 0, Some(60.0)),
            record(lead, 1, None),
            record(LeadCase::Known, 0, None),
        ];
        let csv = runs_csv(&records);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0], RUNS_CSV_HEADER);
        assert_eq!(
            lines[1],
            "announced,15,4,0,7,4,3,0.750000,2,1,1,0,1,0,60.000,1.500,9,0,120"
        );
        assert_eq!(
            lines[2],
            "announced,15,4,1,8,4,3,0.750000,2,1,0,0,1,0,,1.500,9,0,120"
        );
        assert!(lines[3].starts_with("known,,4,0,7,"), "{}", lines[3]);

        let rows = summarize(&records);
        assert_eq!((rows[0].runs, rows[0].extra_delay_s.n), (2, 1));
        assert_eq!(rows[0].extra_delay_s.mean, 60.0);
        let summary = summary_csv(&rows);
        let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
        assert_eq!(header.len(), 5 + 3 * SUMMARY_METRICS.len());
        assert_eq!(
            header[5..8],
            [
                "success_rate_mean",
                "success_rate_ci95_low",
                "success_rate_ci95_high"
            ]
        );
        assert!(
            summary
                .lines()
                .nth(1)
                .unwrap()
                .starts_with("announced,15,4,2,1,0.750000,")
        );
        assert!(summary.lines().nth(2).unwrap().starts_with("known,,4,1,0,"));
    }
}
