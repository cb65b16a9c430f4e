//! Run metrics and the `summary.json` document (docs/reference.md#plans).

use std::collections::BTreeMap;

use muse_model::{FlightParams, Millis, Plan, RejectReason};
use serde::Serialize;

use crate::demand::BookingLead;

mod distribution;
mod optimizer;
mod params;
pub mod recorded;
pub mod replanning;
mod separation;

pub use distribution::Distribution;
pub use muse_formats::params::{BookingLeadRecord, ParamsRecord};
pub use optimizer::{ObjectiveRecord, OptimizerSummary};
pub use recorded::WorldRecord;
pub use replanning::ReplanSummary;
pub use separation::{ClosestRecord, SeparationSummary};

/// The legs of planned trips (docs/reference.md#multi-leg-trips), when battery swaps are on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LegsRecord {
    /// Mean legs per planned trip.
    pub per_trip_mean: f64,
    /// Most legs of one planned trip.
    pub per_trip_max: usize,
    /// Planned trips with more than one leg.
    pub multi_leg_trips: usize,
    /// Battery swaps made in all (legs − 1, summed over planned trips).
    pub swaps: usize,
}

/// Planner wall time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Timing {
    /// Total planner wall time, seconds.
    pub total_s: f64,
    /// Per request, microseconds.
    pub per_request_us: f64,
}

/// Search effort.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Effort {
    /// Labels expanded in all.
    pub expanded_total: u64,
    /// Mean labels expanded per request.
    pub expanded_per_request: f64,
    /// Most labels expanded for one request.
    pub expanded_max: u64,
}

/// What produced a run: scenario, inputs and seed.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Provenance {
    /// Airspace source (file or embedded scenario).
    pub airspace: String,
    /// Zone ids in force.
    pub zones: Vec<String>,
    /// Requests source (file, or generated).
    pub requests: String,
    /// Seed of generated demand, if any.
    pub seed: Option<u64>,
}

/// The `summary.json` of a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Requests planned (accepted or rejected).
    pub requests: usize,
    /// Accepted.
    pub planned: usize,
    /// Rejected, in all.
    pub rejected: usize,
    /// Rejected, by reason (every reason listed, zero included).
    pub rejected_by_reason: BTreeMap<&'static str, usize>,
    /// Demand from customers (docs/reference.md#airspace-from-pads): requests never planned because
    /// a customer has no pad in reach or both share one, counted apart from the planner's
    /// rejections (in `requests`, not in `rejected`); absent for other demand.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unserved: Option<usize>,
    /// `planned / requests` (1 for an empty run).
    pub success_rate: f64,
    /// Air delay (airborne − free-flow) of planned requests, seconds.
    pub air_delay_s: Distribution,
    /// Ground delay (take-off − requested departure) of planned requests, seconds.
    pub ground_delay_s: Distribution,
    /// Planner wall time.
    pub planner_time: Timing,
    /// Search effort.
    pub search: Effort,
    /// Legs per trip and swaps made (only with battery swaps on).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub legs: Option<LegsRecord>,
    /// Parameters.
    pub parameters: ParamsRecord,
    /// Inputs and seed.
    pub provenance: Provenance,
    /// The world planned on, so that the run can be checked again with it
    /// ([`recorded::read_recorded`]); absent when not recorded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub world: Option<WorldRecord>,
    /// Zones announced during the day and what became of the flights they hit (only when
    /// some zone was announced). `planned`, `rejected` and the delays above are the first
    /// answers, as given at submission.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replanning: Option<ReplanSummary>,
    /// The day planned as one batch (docs/reference.md#batch-planning): first come, first served
    /// beside the optimised schedule (only with `--optimize`). `planned`, `rejected` and the delays
    /// above are the optimised schedule's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimizer: Option<OptimizerSummary>,
    /// How close the flights come in metres (docs/reference.md#metric-separation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<SeparationSummary>,
}

/// One planned-or-rejected request, as the metrics see it.
#[derive(Clone, Copy, Debug)]
pub struct RunItem<'a> {
    /// Requested departure.
    pub departure: muse_model::Instant,
    /// The plan or the rejection.
    pub result: &'a Result<Plan, RejectReason>,
    /// Free-flow time, where defined.
    pub free_flow: Option<Millis>,
    /// Labels expanded.
    pub expanded: u64,
}

impl Summary {
    /// Computes the summary of a run.
    pub fn compute<'a>(
        items: impl IntoIterator<Item = RunItem<'a>>,
        params: &FlightParams,
        planner_wall: std::time::Duration,
        provenance: Provenance,
    ) -> Summary {
        let mut rejected_by_reason: BTreeMap<&'static str, usize> = RejectReason::PLANNING
            .iter()
            .map(|r| (r.as_str(), 0))
            .collect();
        let (mut air, mut ground) = (Vec::new(), Vec::new());
        let mut legs = LegsRecord::default();
        let mut requests = 0;
        let mut effort = Effort::default();
        for item in items {
            requests += 1;
            effort.expanded_total += item.expanded;
            effort.expanded_max = effort.expanded_max.max(item.expanded);
            match item.result {
                Ok(plan) => {
                    if let Some(ff) = item.free_flow {
                        air.push(plan.airborne() - ff);
                    }
                    ground.push(plan.takeoff() - item.departure);
                    let n = plan.leg_count();
                    legs.per_trip_max = legs.per_trip_max.max(n);
                    legs.swaps += n.saturating_sub(1);
                    legs.multi_leg_trips += usize::from(n > 1);
                }
                Err(r) => *rejected_by_reason.entry(r.as_str()).or_default() += 1,
            }
        }
        let planned = ground.len();
        effort.expanded_per_request = if requests == 0 {
            0.0
        } else {
            effort.expanded_total as f64 / requests as f64
        };
        let total_s = planner_wall.as_secs_f64();
        if planned > 0 {
            legs.per_trip_mean = (planned + legs.swaps) as f64 / planned as f64;
        }
        Summary {
            requests,
            planned,
            rejected: requests - planned,
            rejected_by_reason,
            unserved: None,
            success_rate: if requests == 0 {
                1.0
            } else {
                planned as f64 / requests as f64
            },
            air_delay_s: Distribution::of(&air),
            ground_delay_s: Distribution::of(&ground),
            planner_time: Timing {
                total_s,
                per_request_us: if requests == 0 {
                    0.0
                } else {
                    total_s * 1e6 / requests as f64
                },
            },
            search: effort,
            legs: params.battery_swap.is_some().then_some(legs),
            parameters: params.into(),
            provenance,
            world: None,
            replanning: None,
            optimizer: None,
            separation: None,
        }
    }

    /// Records the booking lead of generated demand in the parameters.
    ///
    /// ```
    /// use muse_model::{FlightParams, Millis};
    /// use muse_sim::demand::BookingLead;
    /// use muse_sim::metrics::{Provenance, Summary};
    /// let s = Summary::compute([], &FlightParams::default(), Default::default(), Provenance::default());
    /// assert!(!s.to_json().contains("booking_lead_min"));
    /// let lead = BookingLead::new(Millis::ZERO, Millis::from_mins(120)).unwrap();
    /// let s = s.with_booking_lead(lead);
    /// assert!(s.to_json().contains("\"booking_lead_min\": {\n      \"from\": 0.0,\n      \"to\": 120.0\n    }"));
    /// ```
    #[must_use]
    pub fn with_booking_lead(mut self, lead: BookingLead) -> Summary {
        self.parameters.booking_lead_min = Some(lead.into());
        self
    }

    /// Counts `n` unserved requests of demand from customers apart
    /// (docs/reference.md#airspace-from-pads): they join the requests, not the rejections, and the
    /// success rate is over all requests.
    ///
    /// ```
    /// use muse_model::FlightParams;
    /// use muse_sim::metrics::{Provenance, Summary};
    /// let s = Summary::compute([], &FlightParams::default(), Default::default(), Provenance::default());
    /// let s = s.with_unserved(4);
    /// assert_eq!((s.requests, s.rejected, s.unserved, s.success_rate), (4, 0, Some(4), 0.0));
    /// ```
    #[must_use]
    pub fn with_unserved(mut self, n: usize) -> Summary {
        self.requests += n;
        self.unserved = Some(n);
        self.success_rate = if self.requests == 0 {
            1.0
        } else {
            self.planned as f64 / self.requests as f64
        };
        self
    }

    /// Records the world planned on (`world`).
    #[must_use]
    pub fn with_world(mut self, world: WorldRecord) -> Summary {
        self.world = Some(world);
        self
    }

    /// Adds the `replanning` section.
    #[must_use]
    pub fn with_replanning(mut self, replanning: ReplanSummary) -> Summary {
        self.replanning = Some(replanning);
        self
    }

    /// Adds the `optimizer` section.
    #[must_use]
    pub fn with_optimizer(mut self, optimizer: OptimizerSummary) -> Summary {
        self.optimizer = Some(optimizer);
        self
    }

    /// Adds the `separation` section.
    #[must_use]
    pub fn with_separation(mut self, separation: SeparationSummary) -> Summary {
        self.separation = Some(separation);
        self
    }

    /// The summary as pretty JSON with a trailing newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use super::*;
    use muse_model::Instant;

    #[test]
    fn hand_checked_summary() {
        let plan = |takeoff: i64, landing: i64| {
            muse_model::testing::plan(&[(0, takeoff, takeoff), (1, landing, landing)])
        };
        let results = [
            Ok(plan(0, 100_000)),    // air delay 10 s, ground 0
            Ok(plan(5_000, 95_000)), // air delay 0 s, ground 5 s
            Err(RejectReason::NoFeasiblePlan),
            Err(RejectReason::OutOfRange),
        ];
        let items = results.iter().map(|r| RunItem {
            departure: Instant(0),
            result: r,
            free_flow: Some(Millis(90_000)),
            expanded: 4,
        });
        let s = Summary::compute(
            items,
            &FlightParams::default(),
            std::time::Duration::from_millis(2),
            Provenance::default(),
        );
        assert_eq!((s.requests, s.planned, s.rejected), (4, 2, 2));
        assert_eq!(s.success_rate, 0.5);
        assert_eq!(s.rejected_by_reason["no_feasible_plan"], 1);
        assert_eq!(s.rejected_by_reason["out_of_range"], 1);
        assert_eq!(s.rejected_by_reason["unreachable"], 0);
        assert_eq!(
            s.air_delay_s,
            Distribution {
                mean: 5.0,
                median: 0.0,
                p95: 10.0,
                max: 10.0
            }
        );
        assert_eq!(s.ground_delay_s.mean, 2.5);
        assert_eq!(s.search.expanded_per_request, 4.0);
        assert_eq!(s.planner_time.per_request_us, 500.0);
        assert_eq!(s.parameters.edge_rule, "exclusive");
        assert!(s.to_json().contains("\"success_rate\": 0.5"));
    }
}
