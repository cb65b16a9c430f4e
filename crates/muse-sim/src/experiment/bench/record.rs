//! What one benchmark case measured: written by the case process as one JSON line, and read
//! back by the parent with the wall time of the whole process.

use serde::{Deserialize, Serialize};

/// The measurements of one case, written by the case process as one JSON line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    /// Graph name, e.g. `singapore-77` or `synthetic-10000`.
    pub graph: String,
    /// Nodes of the graph.
    pub nodes: usize,
    /// Stations of the graph.
    pub stations: usize,
    /// Edges (corridors) of the graph.
    pub edges: usize,
    /// Ids of the zones in force.
    pub zones: Vec<String>,
    /// Requests planned.
    pub requests: usize,
    /// Origin–destination rule: `uniform` or `in-range`.
    pub od: String,
    /// Demand seed.
    pub seed: u64,
    /// Accepted plans.
    pub planned: usize,
    /// Rejected: out of range.
    pub out_of_range: usize,
    /// Rejected: unreachable.
    pub unreachable: usize,
    /// Rejected: no feasible plan.
    pub no_feasible_plan: usize,
    /// Wall time of the planning loop alone, seconds.
    pub planner_s: f64,
    /// Labels expanded, summed over the requests.
    pub expanded: u64,
    /// Wall time of demand generation, seconds (not part of `planner_s`).
    pub demand_s: f64,
    /// Resident memory just before planning (graph and demand loaded), bytes.
    pub rss_before_planning_bytes: Option<u64>,
    /// Peak resident memory of the case process (`VmHWM`), bytes.
    pub peak_rss_bytes: Option<u64>,
}

impl CaseResult {
    /// Requests rejected, for any reason.
    pub fn rejected(&self) -> usize {
        self.out_of_range + self.unreachable + self.no_feasible_plan
    }

    /// Planner wall time per request, microseconds (0 without requests).
    pub fn us_per_request(&self) -> f64 {
        if self.requests == 0 {
            0.0
        } else {
            self.planner_s * 1e6 / self.requests as f64
        }
    }

    /// Labels expanded per request (0 without requests).
    pub fn expanded_per_request(&self) -> f64 {
        if self.requests == 0 {
            0.0
        } else {
            self.expanded as f64 / self.requests as f64
        }
    }

    /// One line of JSON, without a line break.
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(self).expect("a case result serialises")
    }

    /// Reads a line written by [`CaseResult::to_json_line`].
    pub fn from_json_line(line: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(line.trim())
    }
}

/// A case as seen by the parent: what the case process measured and how long it ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Measured {
    /// The case process's measurements.
    pub result: CaseResult,
    /// Wall time of the whole case process (loading, demand, planning), seconds.
    pub wall_s: f64,
}
