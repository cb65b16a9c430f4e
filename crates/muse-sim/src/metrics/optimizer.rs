//! The `optimizer` section of `summary.json` (docs/reference.md#batch-planning): first come, first
//! served beside the optimised schedule, the search's budget and effort, and the displaced
//! requests.

use muse_model::Request;
use muse_optimize::{Objective, Report};
use serde::Serialize;

/// An objective as written: requests planned, total and mean delay in seconds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ObjectiveRecord {
    /// Requests planned.
    pub planned: usize,
    /// Total delay (`landing − departure − free_flow` summed over planned requests), seconds.
    pub total_delay_s: f64,
    /// Mean delay per planned request, seconds (0 when none is planned).
    pub mean_delay_s: f64,
}

impl From<Objective> for ObjectiveRecord {
    fn from(o: Objective) -> Self {
        let total = o.delay.as_secs_f64();
        ObjectiveRecord {
            planned: o.planned,
            total_delay_s: total,
            mean_delay_s: if o.planned == 0 {
                0.0
            } else {
                total / o.planned as f64
            },
        }
    }
}

/// The `optimizer` section.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OptimizerSummary {
    /// First come, first served: where the optimiser started.
    pub fcfs: ObjectiveRecord,
    /// The schedule written: never worse than `fcfs`.
    pub optimized: ObjectiveRecord,
    /// Requests that can fly alone (on the empty schedule, with the zones): an upper bound
    /// on `planned`.
    pub can_fly_alone: usize,
    /// The planning order the search started from (`arrival` is first come, first served).
    pub started_from: &'static str,
    /// Each planning order tried, with the requests it planned and its total delay.
    pub orders: Vec<(&'static str, ObjectiveRecord)>,
    /// Search steps done.
    pub iterations: u64,
    /// Of which improved the objective.
    pub improved: u64,
    /// Whether the time budget stopped the search before its steps were done (the result is
    /// then not reproducible).
    pub stopped_by_time_budget: bool,
    /// Wall time of the whole optimisation (first come, first served included), seconds.
    pub time_s: f64,
    /// Steps per second.
    pub iterations_per_s: f64,
    /// Labels expanded by every search.
    pub expanded: u64,
    /// How many requests first come, first served planned and the optimiser rejects.
    pub displaced: usize,
    /// Their ids, in planning order.
    pub displaced_requests: Vec<String>,
}

impl OptimizerSummary {
    /// The section for `report` on `requests` (in the optimiser's order).
    pub fn of(report: &Report, requests: &[Request]) -> Self {
        OptimizerSummary {
            fcfs: report.fcfs.into(),
            optimized: report.result.into(),
            can_fly_alone: report.alone,
            started_from: report.start,
            orders: report
                .orders
                .iter()
                .map(|(n, o)| (*n, (*o).into()))
                .collect(),
            iterations: report.iterations,
            improved: report.improved,
            stopped_by_time_budget: report.timed_out,
            time_s: report.elapsed.as_secs_f64(),
            iterations_per_s: report.iterations_per_s(),
            expanded: report.expanded,
            displaced: report.displaced.len(),
            displaced_requests: report
                .displaced
                .iter()
                .map(|&i| requests[i].id.clone())
                .collect(),
        }
    }
}
