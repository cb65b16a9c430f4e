//! One benchmark case measured in this process: the demand generated (timed apart), the day
//! planned (only the planning loop timed), the outcomes counted, the memory read.

use muse_model::{Airspace, FlightParams, RejectReason, Zone};

use super::memory::{current_rss_bytes, peak_rss_bytes};
use super::record::CaseResult;
use crate::day::{DayError, plan_requests};
use crate::demand::{DemandError, DemandSpec, generate};

/// Why a case could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// The demand could not be generated.
    #[error("demand on {graph}: {source}")]
    Demand {
        /// The graph's name.
        graph: String,
        /// Cause.
        source: DemandError,
    },
    /// The day could not be planned.
    #[error(transparent)]
    Day(#[from] DayError),
}

/// A graph to measure on: its name, airspace and zones.
#[derive(Clone, Copy, Debug)]
pub struct Graph<'a> {
    /// Its name, e.g. `singapore-77` or `synthetic-10000`.
    pub name: &'a str,
    /// The airspace.
    pub airspace: &'a Airspace,
    /// The zones in force.
    pub zones: &'a [Zone],
}

/// Measures one case: the demand `spec` on `graph` (`od` names its rule in the record),
/// planned with `params`; `progress` is told how many requests are planned, every 4,096.
pub fn measure(
    graph: Graph<'_>,
    spec: &DemandSpec,
    od: &str,
    params: FlightParams,
    mut progress: impl FnMut(usize),
) -> Result<CaseResult, MeasureError> {
    let started = std::time::Instant::now();
    let requests = generate(graph.airspace, spec).map_err(|source| MeasureError::Demand {
        graph: graph.name.to_owned(),
        source,
    })?;
    let demand_s = started.elapsed().as_secs_f64();
    let rss_before_planning_bytes = current_rss_bytes();

    // Progress every 4,096 requests only, to keep it out of the timing.
    let run = plan_requests(graph.airspace, graph.zones, params, requests, |done| {
        if done % 4_096 == 0 {
            progress(done);
        }
    })?;

    let mut result = CaseResult {
        graph: graph.name.to_owned(),
        nodes: graph.airspace.node_count(),
        stations: graph.airspace.stations().count(),
        edges: graph.airspace.edge_count(),
        zones: graph.zones.iter().map(|z| z.id.clone()).collect(),
        requests: run.requests.len(),
        od: od.to_owned(),
        seed: spec.seed,
        planned: 0,
        out_of_range: 0,
        unreachable: 0,
        no_feasible_plan: 0,
        planner_s: run.replay.planner_wall.as_secs_f64(),
        expanded: 0,
        demand_s,
        rss_before_planning_bytes,
        peak_rss_bytes: None,
    };
    for o in &run.replay.outcomes {
        result.expanded += o.expanded;
        match o.result {
            Ok(_) => result.planned += 1,
            Err(RejectReason::OutOfRange) => result.out_of_range += 1,
            Err(RejectReason::Unreachable) => result.unreachable += 1,
            // A day planned in advance has no clock, so it never answers `departure_in_past`;
            // the planner never sees an `unserved` request.
            Err(
                RejectReason::NoFeasiblePlan
                | RejectReason::DepartureInPast
                | RejectReason::Unserved,
            ) => {
                result.no_feasible_plan += 1;
            }
        }
    }
    // Read while the plans and the schedule are still alive.
    result.peak_rss_bytes = peak_rss_bytes();
    drop(run);
    Ok(result)
}
