//! The regulator's question (issue 9): how much warning before a temporary no-fly zone
//! becomes active keeps the cost of announcing it low?
//!
//! An announcement-lead sweep plans the same demand once per lead `L`: each zone to announce
//! is announced (SPEC §11) at the start of its first active window on the day minus `L`, and
//! the day is [replayed](crate::replay). Run `i` of count index `c` uses the demand seed
//! `base_seed + c · reps + i` for every lead, so the differences between leads are the lead's
//! effect, not sampling noise. Two reference cases run on the same seeds: the zones known
//! from the start ([`LeadCase::Known`], the limit of a long lead) and, optionally, never
//! announced at all ([`LeadCase::NoZone`]). Zones known from the start (`base` zones) apply
//! in every case.
//!
//! - [`LeadWorld`]: the zones resolved once, and one planned day per case;
//! - [`LeadRecord`]: what one run measured (success rate, affected, replanned, diverted,
//!   cancelled, contingency, extra delay, …);
//! - [`summarize`], [`runs_csv`], [`summary_csv`]: means with 95% confidence intervals and
//!   the CSV files.

mod record;
mod report;
mod world;

use muse_airspace::closures::ClosureError;
use muse_model::{Airspace, FlightParams, Instant, Millis, Zone};
use muse_planner::ZoneError;
use rayon::prelude::*;

pub use record::LeadRecord;
pub use report::{LeadSummaryRow, RUNS_CSV_HEADER, runs_csv, summarize, summary_csv};
pub use world::{Day, LeadWorld, first_window_start};

use crate::demand::{BookingLead, DemandError, DemandSpec, OdRule};
use crate::shard::{Shard, ShardDays};

/// How the zones to announce become known in one run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LeadCase {
    /// Announced `lead` before the start of the zone's first active window.
    Announced {
        /// Warning between announcement and the first window's start (at least zero).
        lead: Millis,
    },
    /// Known from the start, like a base zone: the reference a long lead tends to.
    Known,
    /// Never announced: the day without the zones (base zones still apply).
    NoZone,
}

impl LeadCase {
    /// `announced`, `known` or `none`, as in the CSV files.
    pub fn kind(self) -> &'static str {
        match self {
            LeadCase::Announced { .. } => "announced",
            LeadCase::Known => "known",
            LeadCase::NoZone => "none",
        }
    }

    /// The lead in minutes, if the zones are announced.
    ///
    /// ```
    /// use muse_model::Millis;
    /// use muse_sim::lead::LeadCase;
    /// assert_eq!(LeadCase::Announced { lead: Millis::from_secs(90) }.lead_min(), Some(1.5));
    /// assert_eq!(LeadCase::Known.lead_min(), None);
    /// ```
    pub fn lead_min(self) -> Option<f64> {
        match self {
            LeadCase::Announced { lead } => Some(lead.as_secs_f64() / 60.0),
            LeadCase::Known | LeadCase::NoZone => None,
        }
    }

    /// A short label for tables and legends: the lead in minutes, `known` or `none`.
    ///
    /// ```
    /// use muse_model::Millis;
    /// use muse_sim::lead::LeadCase;
    /// assert_eq!(LeadCase::Announced { lead: Millis::from_mins(15) }.label(), "15");
    /// assert_eq!(LeadCase::NoZone.label(), "none");
    /// ```
    pub fn label(self) -> String {
        self.lead_min()
            .map_or_else(|| self.kind().to_owned(), |m| m.to_string())
    }
}

/// Errors of an announcement-lead sweep.
#[derive(Debug, thiserror::Error)]
pub enum LeadError {
    /// No zone to announce was given.
    #[error("no zone to announce")]
    NothingToAnnounce,
    /// A zone to announce has no active window beginning on the day.
    #[error(
        "zone `{zone}` has no active window starting between {from} and {to}, so it has no first window to announce ahead of"
    )]
    NoWindow {
        /// The zone's id.
        zone: String,
        /// The day's start, RFC 3339.
        from: String,
        /// The day's end, RFC 3339.
        to: String,
    },
    /// A lead is negative.
    #[error("lead {0}: a lead must be >= 0")]
    NegativeLead(Millis),
    /// A zone could not be resolved against the airspace.
    #[error(transparent)]
    Zones(#[from] ClosureError),
    /// Two zones to announce share an id.
    #[error(transparent)]
    Announced(#[from] ZoneError),
    /// Demand could not be generated.
    #[error(transparent)]
    Demand(#[from] DemandError),
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct LeadSweepSpec {
    /// Leads, in the order runs are reported.
    pub leads: Vec<Millis>,
    /// Request counts.
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
    /// Flight parameters.
    pub params: FlightParams,
    /// Zones known from the start in every case.
    pub base_zones: Vec<Zone>,
    /// Zones to announce (their own announcement instants are replaced).
    pub announce: Vec<Zone>,
    /// The day on which each zone's first window is looked for.
    pub day: Day,
    /// Whether to run the [`LeadCase::NoZone`] reference too.
    pub no_zone_reference: bool,
}

impl LeadSweepSpec {
    /// The demand seed of repetition `rep` of count index `count_index`, shared by every case.
    ///
    /// Seeds follow [`crate::sweep::SweepSpec::seed`]: `base_seed + count_index · reps + rep`.
    pub fn seed(&self, count_index: usize, rep: usize) -> u64 {
        self.base_seed + (count_index * self.reps + rep) as u64
    }

    /// The cases run: each lead, then [`LeadCase::Known`], then [`LeadCase::NoZone`] if asked.
    pub fn cases(&self) -> Vec<LeadCase> {
        let mut cases: Vec<LeadCase> = self
            .leads
            .iter()
            .map(|&lead| LeadCase::Announced { lead })
            .collect();
        cases.push(LeadCase::Known);
        if self.no_zone_reference {
            cases.push(LeadCase::NoZone);
        }
        cases
    }

    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.cases().len() * self.counts.len() * self.reps
    }

    /// Total requests planned.
    pub fn total_requests(&self) -> usize {
        self.cases().len() * self.counts.iter().sum::<usize>() * self.reps
    }

    /// The range zone closures are resolved over: from a day before the earliest possible
    /// submission to a day after the latest possible landing (as [`crate::sweep`] does).
    pub fn closure_range(&self) -> (Instant, Instant) {
        let day = Millis::from_secs(86_400);
        (
            self.start - self.booking_lead.max - day,
            self.end + self.params.trip_span() + day,
        )
    }

    /// Checks the leads and prepares the sweep's world on `airspace` (see [`LeadWorld::new`]).
    pub fn world<'a>(&self, airspace: &'a Airspace) -> Result<LeadWorld<'a>, LeadError> {
        if let Some(&lead) = self.leads.iter().find(|l| **l < Millis::ZERO) {
            return Err(LeadError::NegativeLead(lead));
        }
        LeadWorld::new(
            airspace,
            self.params,
            &self.base_zones,
            &self.announce,
            self.day,
            self.closure_range(),
        )
    }
}

/// Runs the sweep on the global `rayon` pool in `world` (from [`LeadSweepSpec::world`]):
/// every (case, count, repetition), one record each, ordered by case, then count, then
/// repetition. `tick` is called once per finished run.
///
/// ```
/// use muse_model::{Airspace, FlightParams, Instant, Millis, Period, UtcOffset, Zone};
/// use muse_sim::demand::{BookingLead, OdRule};
/// use muse_sim::lead::{Day, LeadCase, LeadSweepSpec, run_lead_sweep};
/// let min = |m: i64| Instant(m * 60_000);
/// let air = Airspace::line(&[1_000.0, 1_000.0]);
/// let zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: String::new(), area: None,
///     node_ids: vec!["B".into()], edge_ids: vec![], announced: None, withdrawn: None,
///     periods: vec![Period { start: Some(min(600)), end: Some(min(630)), daily: vec![] }],
/// };
/// let spec = LeadSweepSpec {
///     leads: vec![Millis::ZERO, Millis::from_mins(60)], counts: vec![20], reps: 2,
///     base_seed: 1, start: min(480), end: min(720), od: OdRule::Uniform,
///     booking_lead: BookingLead::new(Millis::ZERO, Millis::from_mins(120)).unwrap(),
///     params: FlightParams::default(), base_zones: vec![], announce: vec![zone],
///     day: Day { start: min(0), end: min(1_440), offset: UtcOffset(0) },
///     no_zone_reference: false,
/// };
/// let world = spec.world(&air).unwrap();
/// let records = run_lead_sweep(&world, &spec, || {}).unwrap();
/// assert_eq!(records.len(), 3 * 2); // (0 min, 60 min, known) × 2 repetitions
/// assert_eq!(records[5].case, LeadCase::Known);
/// assert_eq!(records[1].seed, records[5].seed); // same demand in every case
/// ```
pub fn run_lead_sweep(
    world: &LeadWorld<'_>,
    spec: &LeadSweepSpec,
    tick: impl Fn() + Sync,
) -> Result<Vec<LeadRecord>, LeadError> {
    let runs = run_lead_sweep_shard(world, spec, Shard::WHOLE, tick)?;
    Ok(runs.into_iter().map(|(_, r)| r).collect())
}

/// Runs the runs of `shard` (see [`crate::shard`]; run `k · jobs + j` is case `k` on the
/// `j`-th (count, repetition)) with their run numbers, in run order.
pub fn run_lead_sweep_shard(
    world: &LeadWorld<'_>,
    spec: &LeadSweepSpec,
    shard: Shard,
    tick: impl Fn() + Sync,
) -> Result<Vec<(usize, LeadRecord)>, LeadError> {
    let cases = spec.cases();
    let share = ShardDays::new(
        world.airspace(),
        shard,
        cases.len(),
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
    share
        .runs
        .par_iter()
        .map(|&(run_number, k, d)| {
            let (c, r) = share.days[d];
            let run = world.run(cases[k], &share.demands[d])?;
            let rec = LeadRecord::of(cases[k], r, spec.seed(c, r), spec.booking_lead, &run);
            tick();
            Ok((run_number, rec))
        })
        .collect()
}

#[cfg(test)]
mod tests;
