//! An announcement-lead sweep as numbers: `announce_lead_summary.csv` (means with 95%
//! confidence intervals per case and count) and the printed table.

use super::case::LeadCase;
use super::record::{LeadRecord, lead_cell};
use crate::experiment::report::{Align, Column, Group, Metric, SummarySpec, TextTable, plus_minus};

/// The summary file.
pub const SUMMARY_FILE: &str = "announce_lead_summary.csv";

/// The metrics of the summary: the success rate, the flights affected and their fates, the
/// extra delay of the replanned flights, the planner time.
pub(crate) mod metric {
    pub const SUCCESS: &str = "success_rate";
    pub const AFFECTED: &str = "affected";
    pub const REPLANNED: &str = "replanned";
    pub const DIVERTED: &str = "diverted";
    pub const CANCELLED: &str = "cancelled";
    pub const CONTINGENCY: &str = "contingency";
    pub const EXTRA_DELAY: &str = "extra_delay_s";
}

use metric::{AFFECTED, CANCELLED, CONTINGENCY, DIVERTED, EXTRA_DELAY, REPLANNED, SUCCESS};

/// A case as the summary groups it: `announced:LEAD_MS`, `known` or `none`.
fn case_key(case: LeadCase) -> String {
    match case {
        LeadCase::Announced { lead } => format!("announced:{}", lead.0),
        other => other.kind().to_owned(),
    }
}

/// `announce_lead_summary.csv`: per case and count, the number of runs, the number of runs
/// with a replanned flight (those `extra_delay_s` averages over), then the mean and 95% CI
/// (`_mean`, `_ci95_low`, `_ci95_high`) of each metric.
///
/// ```
/// use muse_model::Millis;
/// use muse_sim::demand::BookingLead;
/// use muse_sim::experiment::lead::{LeadCase, LeadRecord, summary};
/// use muse_sim::experiment::summarize;
/// let run = |case, rep, cancelled| LeadRecord {
///     case, count: 10, rep, seed: rep as u64, booking_lead: BookingLead::NONE,
///     planned_at_booking: 10, delivered: 10 - cancelled, delivery_rate: (10 - cancelled) as f64 / 10.0,
///     affected: cancelled, airborne_affected: 0, replanned: 0, diverted: 0, cancelled,
///     contingency: 0, mean_extra_delay_s: None, planner_ms: 1.0, replan_expanded: 0,
/// };
/// let lead = LeadCase::Announced { lead: Millis::from_mins(30) };
/// let groups = summarize(&[run(lead, 0, 2), run(lead, 1, 4), run(LeadCase::Known, 0, 0)], &summary());
/// assert_eq!(groups.len(), 2);
/// assert_eq!((groups[0].runs, groups[0].metric("cancelled").mean), (2, 3.0));
/// assert_eq!(groups[0].metric("success_rate").mean, 0.7);
/// assert_eq!(groups[0].metric("extra_delay_s").n, 0);
/// ```
pub fn summary() -> SummarySpec<LeadRecord> {
    type G = Group<LeadRecord>;
    SummarySpec {
        file: SUMMARY_FILE,
        group: |r| (case_key(r.case), r.count),
        head: vec![
            Column::new("case", |g: &G| g.first.case.kind().to_owned()),
            Column::new("lead_min", |g: &G| lead_cell(g.first.case)),
            Column::new("count", |g: &G| g.count.to_string()),
            Column::new("runs", |g: &G| g.runs.to_string()),
            Column::new("runs_with_replanned", |g: &G| {
                g.metric(EXTRA_DELAY).n.to_string()
            }),
        ],
        metrics: vec![
            Metric {
                name: SUCCESS,
                value: |r| Some(r.delivery_rate),
            },
            Metric {
                name: "planned_at_booking",
                value: |r| Some(r.planned_at_booking as f64),
            },
            Metric {
                name: AFFECTED,
                value: |r| Some(r.affected as f64),
            },
            Metric {
                name: "airborne_affected",
                value: |r| Some(r.airborne_affected as f64),
            },
            Metric {
                name: REPLANNED,
                value: |r| Some(r.replanned as f64),
            },
            Metric {
                name: DIVERTED,
                value: |r| Some(r.diverted as f64),
            },
            Metric {
                name: CANCELLED,
                value: |r| Some(r.cancelled as f64),
            },
            Metric {
                name: CONTINGENCY,
                value: |r| Some(r.contingency as f64),
            },
            Metric {
                name: EXTRA_DELAY,
                value: |r| r.mean_extra_delay_s,
            },
            Metric {
                name: "planner_ms",
                value: |r| Some(r.planner_ms),
            },
        ],
    }
}

/// Means per run; `±` is the half-width of the 95% confidence interval.
pub fn table(groups: &[Group<LeadRecord>]) -> String {
    let mut t = TextTable::new(&[
        ("lead min", 8, Align::Right),
        ("count", 7, Align::Right),
        ("success %", 15, Align::Right),
        ("affected", 9, Align::Right),
        ("replanned", 9, Align::Right),
        ("diverted", 9, Align::Right),
        ("cancelled", 9, Align::Right),
        ("contingency", 11, Align::Right),
        ("extra delay s", 15, Align::Right),
    ]);
    for g in groups {
        let extra = g.metric(EXTRA_DELAY);
        let mean = |name| format!("{:.2}", g.metric(name).mean);
        t.row(vec![
            g.first.case.label(),
            g.count.to_string(),
            plus_minus(g.metric(SUCCESS), 100.0, 2),
            mean(AFFECTED),
            mean(REPLANNED),
            mean(DIVERTED),
            mean(CANCELLED),
            mean(CONTINGENCY),
            if extra.n == 0 {
                "-".to_owned()
            } else {
                plus_minus(extra, 1.0, 1)
            },
        ]);
    }
    format!(
        "means per run (± 95% CI); extra delay: of replanned flights, over the runs that \
         replanned any\n{t}"
    )
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use muse_model::Millis;

    use super::*;
    use crate::demand::BookingLead;
    use crate::experiment::lead::record::columns;
    use crate::experiment::report::{csv_text, summarize, summary_csv};

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
        let csv = csv_text("announce_lead.csv", &columns(), &records).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "case,lead_min,count,rep,seed,planned_at_booking,delivered,success_rate,affected,airborne_affected,replanned,diverted,cancelled,contingency,mean_extra_delay_s,planner_ms,replan_expanded,booking_lead_min_from,booking_lead_min_to"
        );
        assert_eq!(
            lines[1],
            "announced,15,4,0,7,4,3,0.750000,2,1,1,0,1,0,60.000,1.500,9,0,120"
        );
        assert_eq!(
            lines[2],
            "announced,15,4,1,8,4,3,0.750000,2,1,0,0,1,0,,1.500,9,0,120"
        );
        assert!(lines[3].starts_with("known,,4,0,7,"), "{}", lines[3]);

        let spec = summary();
        let groups = summarize(&records, &spec);
        assert_eq!((groups[0].runs, groups[0].metric(EXTRA_DELAY).n), (2, 1));
        assert_eq!(groups[0].metric(EXTRA_DELAY).mean, 60.0);
        let summary = summary_csv(&spec, &groups).unwrap();
        let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
        assert_eq!(header.len(), 5 + 3 * spec.metrics.len());
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
        let table = table(&groups);
        assert!(table.contains("known       4"), "{table}");
    }
}
