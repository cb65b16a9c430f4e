//! The paper's experiment as a parameter sweep: request counts × repetitions × scenario
//! variants, run in parallel, each run from its own recorded seed.
//!
//! Run `i` of count index `c` uses seed `base_seed + c · reps + i`: every run of a sweep has
//! a distinct seed, and every variant is run on the same seeds, so differences between
//! variants are the policy's effect, not sampling noise. Every run's demand is booked ahead by
//! the sweep's [`BookingLead`] (none by default: the paper).

use std::fmt::Write as _;

use muse_airspace::closures::{ClosureError, Closures, resolve};
use muse_model::{Airspace, FlightParams, Instant, Millis, Zone};
use muse_planner::Planner;
use rayon::prelude::*;

use crate::day::plan_sorted;
use crate::demand::{BookingLead, DemandError, DemandSpec, OdRule};
use crate::shard::{Shard, ShardDays};
use crate::stats::MeanCi;

/// One scenario variant of a sweep.
#[derive(Clone, Debug)]
pub struct Variant {
    /// Name shown in files and legends, e.g. `CBD zone` or `no zone`.
    pub name: String,
    /// Zones in force.
    pub zones: Vec<Zone>,
    /// Flight parameters.
    pub params: FlightParams,
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepSpec {
    /// Request counts, e.g. 1,000 … 10,000.
    pub counts: Vec<usize>,
    /// Repetitions per count.
    pub reps: usize,
    /// First seed.
    pub base_seed: u64,
    /// Departure window start.
    pub start: Instant,
    /// Departure window end (exclusive).
    pub end: Instant,
    /// Origin–destination rule.
    pub od: OdRule,
    /// How far ahead of departure requests are booked.
    pub booking_lead: BookingLead,
    /// Variants (at least one).
    pub variants: Vec<Variant>,
}

impl SweepSpec {
    /// The seed of repetition `rep` of count index `count_index`.
    pub fn seed(&self, count_index: usize, rep: usize) -> u64 {
        self.base_seed + (count_index * self.reps + rep) as u64
    }

    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.variants.len() * self.counts.len() * self.reps
    }

    /// Total requests planned.
    pub fn total_requests(&self) -> usize {
        self.variants.len() * self.counts.iter().sum::<usize>() * self.reps
    }
}

/// Errors of a sweep.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A variant's zones could not be resolved.
    #[error("variant `{variant}`: {source}")]
    Zones {
        /// Variant name.
        variant: String,
        /// Cause.
        source: ClosureError,
    },
    /// Demand could not be generated.
    #[error(transparent)]
    Demand(#[from] DemandError),
}

/// The measurements of one run (serialized in sweep shards, [`crate::shard`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunRecord {
    /// Variant name.
    pub variant: String,
    /// Requests.
    pub count: usize,
    /// Repetition index.
    pub rep: usize,
    /// Demand seed.
    pub seed: u64,
    /// How far ahead of departure the run's requests were booked.
    #[serde(with = "lead_ms")]
    pub booking_lead: BookingLead,
    /// Accepted.
    pub planned: usize,
    /// Rejected: out of range.
    pub out_of_range: usize,
    /// Rejected: unreachable.
    pub unreachable: usize,
    /// Rejected: no feasible plan.
    pub no_feasible_plan: usize,
    /// `planned / count`.
    pub success_rate: f64,
    /// Mean air delay of planned requests, seconds.
    pub mean_air_delay_s: f64,
    /// Mean ground delay of planned requests, seconds.
    pub mean_ground_delay_s: f64,
    /// Planner wall time of the run, milliseconds.
    pub planner_ms: f64,
    /// Labels expanded per request.
    pub expanded_per_request: f64,
    /// Mean legs per planned trip (1 without battery swaps).
    pub legs_per_trip: f64,
}

/// A booking lead in files: `[min, max]` in milliseconds.
pub(crate) mod lead_ms {
    use muse_model::Millis;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use crate::demand::BookingLead;

    pub fn serialize<S: Serializer>(lead: &BookingLead, s: S) -> Result<S::Ok, S::Error> {
        [lead.min.0, lead.max.0].serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<BookingLead, D::Error> {
        let [min, max] = <[i64; 2]>::deserialize(d)?;
        Ok(BookingLead {
            min: Millis(min),
            max: Millis(max),
        })
    }
}

/// Runs the sweep on the global `rayon` pool; `tick` is called once per finished run. The
/// records come in run order: variant, then count, then repetition.
pub fn run_sweep(
    airspace: &Airspace,
    spec: &SweepSpec,
    tick: impl Fn() + Sync,
) -> Result<Vec<RunRecord>, SweepError> {
    let runs = run_sweep_shard(airspace, spec, Shard::WHOLE, tick)?;
    Ok(runs.into_iter().map(|(_, r)| r).collect())
}

/// Runs the runs of `shard` (see [`crate::shard`]) with their run numbers, in run order.
pub fn run_sweep_shard(
    airspace: &Airspace,
    spec: &SweepSpec,
    shard: Shard,
    tick: impl Fn() + Sync,
) -> Result<Vec<(usize, RunRecord)>, SweepError> {
    let day = Millis::from_secs(86_400);
    // From a day before the earliest possible submission (see `day::closure_range`).
    let from = spec.start - spec.booking_lead.max - day;
    let mut prepared = Vec::with_capacity(spec.variants.len());
    for v in &spec.variants {
        let to = spec.end + v.params.trip_span() + day;
        let closures =
            resolve(airspace, &v.zones, from, to).map_err(|source| SweepError::Zones {
                variant: v.name.clone(),
                source,
            })?;
        prepared.push((v, Planner::new(airspace, v.params), closures));
    }
    let share = ShardDays::new(
        airspace,
        shard,
        prepared.len(),
        spec.counts.len(),
        spec.reps,
        |c, r| DemandSpec {
            count: spec.counts[c],
            start: spec.start,
            end: spec.end,
            seed: spec.seed(c, r),
            od: spec.od,
            booking_lead: spec.booking_lead,
        },
    )?;
    let records = share
        .runs
        .par_iter()
        .map(|&(run, v, d)| {
            let (variant, planner, closures) = &prepared[v];
            let (c, r) = share.days[d];
            let (seed, lead) = (spec.seed(c, r), spec.booking_lead);
            let rec = run_one(variant, planner, closures, &share.demands[d], seed, lead, r);
            tick();
            (run, rec)
        })
        .collect();
    Ok(records)
}

fn run_one(
    variant: &Variant,
    planner: &Planner<'_>,
    closures: &Closures,
    requests: &[muse_model::Request],
    seed: u64,
    booking_lead: BookingLead,
    rep: usize,
) -> RunRecord {
    let (outcomes, wall) = plan_sorted(planner, closures, requests, |_| {});
    let mut rec = RunRecord {
        variant: variant.name.clone(),
        count: requests.len(),
        rep,
        seed,
        booking_lead,
        planned: 0,
        out_of_range: 0,
        unreachable: 0,
        no_feasible_plan: 0,
        success_rate: 0.0,
        mean_air_delay_s: 0.0,
        mean_ground_delay_s: 0.0,
        planner_ms: wall.as_secs_f64() * 1e3,
        expanded_per_request: 0.0,
        legs_per_trip: 0.0,
    };
    let (mut air, mut ground, mut expanded, mut legs) = (0i64, 0i64, 0u64, 0usize);
    for (req, o) in requests.iter().zip(&outcomes) {
        expanded += o.expanded;
        match &o.result {
            Ok(plan) => {
                rec.planned += 1;
                air += (plan.airborne() - o.free_flow.unwrap_or(plan.airborne())).0;
                ground += (plan.takeoff() - req.departure).0;
                legs += plan.leg_count();
            }
            Err(muse_model::RejectReason::OutOfRange) => rec.out_of_range += 1,
            Err(muse_model::RejectReason::Unreachable) => rec.unreachable += 1,
            // A day planned in advance has no clock, so it never answers `departure_in_past`.
            Err(
                muse_model::RejectReason::NoFeasiblePlan
                | muse_model::RejectReason::DepartureInPast,
            ) => rec.no_feasible_plan += 1,
        }
    }
    let n = requests.len().max(1) as f64;
    let planned = rec.planned.max(1) as f64;
    rec.success_rate = rec.planned as f64 / n;
    rec.mean_air_delay_s = air as f64 / 1e3 / planned;
    rec.mean_ground_delay_s = ground as f64 / 1e3 / planned;
    rec.expanded_per_request = expanded as f64 / n;
    rec.legs_per_trip = legs as f64 / planned;
    rec
}

/// Mean and 95% CI of a run metric per (variant, count).
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryRow {
    /// Variant name.
    pub variant: String,
    /// Requests.
    pub count: usize,
    /// Success rate.
    pub success_rate: MeanCi,
    /// Planner wall time, ms.
    pub planner_ms: MeanCi,
    /// Mean air delay, s.
    pub air_delay_s: MeanCi,
    /// Mean ground delay, s.
    pub ground_delay_s: MeanCi,
    /// Labels expanded per request.
    pub expanded_per_request: MeanCi,
    /// Rejections for lack of a feasible plan, per run.
    pub no_feasible_plan: MeanCi,
    /// Legs per planned trip.
    pub legs_per_trip: MeanCi,
}

/// Groups runs by (variant, count) in the order variants and counts first appear.
pub fn summarize(records: &[RunRecord]) -> Vec<SummaryRow> {
    let mut keys: Vec<(String, usize)> = Vec::new();
    for r in records {
        let k = (r.variant.clone(), r.count);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .map(|(variant, count)| {
            let runs: Vec<&RunRecord> = records
                .iter()
                .filter(|r| r.variant == variant && r.count == count)
                .collect();
            let ci = |f: fn(&RunRecord) -> f64| {
                MeanCi::of(&runs.iter().map(|r| f(r)).collect::<Vec<_>>())
            };
            SummaryRow {
                success_rate: ci(|r| r.success_rate),
                planner_ms: ci(|r| r.planner_ms),
                air_delay_s: ci(|r| r.mean_air_delay_s),
                ground_delay_s: ci(|r| r.mean_ground_delay_s),
                expanded_per_request: ci(|r| r.expanded_per_request),
                no_feasible_plan: ci(|r| r.no_feasible_plan as f64),
                legs_per_trip: ci(|r| r.legs_per_trip),
                variant,
                count,
            }
        })
        .collect()
}

/// `sweep.csv`: one row per run; the last two columns are the run's booking lead (uniform in
/// `[from, to]` minutes; `0,0` for requests submitted at departure).
pub fn runs_csv(records: &[RunRecord]) -> String {
    let mut out = String::from(
        "variant,count,rep,seed,planned,out_of_range,unreachable,no_feasible_plan,success_rate,mean_air_delay_s,mean_ground_delay_s,planner_ms,expanded_per_request,legs_per_trip,booking_lead_min_from,booking_lead_min_to\n",
    );
    for r in records {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{:.6},{:.3},{:.3},{:.3},{:.3},{:.4},{},{}",
            csv_text(&r.variant),
            r.count,
            r.rep,
            r.seed,
            r.planned,
            r.out_of_range,
            r.unreachable,
            r.no_feasible_plan,
            r.success_rate,
            r.mean_air_delay_s,
            r.mean_ground_delay_s,
            r.planner_ms,
            r.expanded_per_request,
            r.legs_per_trip,
            r.booking_lead.min.as_secs_f64() / 60.0,
            r.booking_lead.max.as_secs_f64() / 60.0
        );
    }
    out
}

/// `sweep_summary.csv`: mean and 95% CI per (variant, count).
pub fn summary_csv(rows: &[SummaryRow]) -> String {
    let mut out = String::from("variant,count,runs");
    for m in [
        "success_rate",
        "planner_ms",
        "air_delay_s",
        "ground_delay_s",
        "expanded_per_request",
        "no_feasible_plan",
        "legs_per_trip",
    ] {
        let _ = write!(out, ",{m}_mean,{m}_ci95_low,{m}_ci95_high");
    }
    out.push('\n');
    for r in rows {
        let _ = write!(
            out,
            "{},{},{}",
            csv_text(&r.variant),
            r.count,
            r.success_rate.n
        );
        for m in [
            r.success_rate,
            r.planner_ms,
            r.air_delay_s,
            r.ground_delay_s,
            r.expanded_per_request,
            r.no_feasible_plan,
            r.legs_per_trip,
        ] {
            let _ = write!(out, ",{:.6},{:.6},{:.6}", m.mean, m.low(), m.high());
        }
        out.push('\n');
    }
    out
}

/// A CSV field, quoted when it needs to be.
pub(crate) fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}
