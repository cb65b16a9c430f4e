//! The options of batch planning (docs/reference.md#batch-planning) shared by `muse plan` and `muse
//! simulate`.

use std::time::Duration;

use clap::Args;
use muse_model::{FlightParams, Request};
use muse_optimize::Options;
use muse_sim::day::{DayRun, Planning, plan_requests_by};
use muse_sim::metrics::OptimizerSummary;

use super::common::World;
use super::progress::LazyProgress;
use super::ranges;

/// `--optimize` and its budget.
#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// Plan the requests as one batch, better than first come, first served: most requests
    /// planned, then least total delay (docs/reference.md#batch-planning). Starts from first come,
    /// first served and never returns a worse schedule.
    #[arg(long)]
    optimize: bool,
    /// With --optimize: steps of large-neighbourhood search, from 0 to 1000000000 (the
    /// reproducible budget: the same steps and seed give the same plans on every machine).
    #[arg(
        long,
        value_name = "N",
        default_value_t = Options::default().iterations,
        requires = "optimize",
        allow_negative_numbers = true,
        value_parser = ranges::iterations
    )]
    iterations: u64,
    /// With --optimize: stop the search after this many seconds of wall time, from 0.001 to
    /// 86400 (the result then depends on the machine's speed; not reproducible).
    #[arg(
        long,
        value_name = "S",
        requires = "optimize",
        allow_negative_numbers = true,
        value_parser = ranges::time_budget_s
    )]
    time_budget_s: Option<f64>,
    /// With --optimize: seed of the optimiser's random choices, a whole number from 0 to
    /// 18446744073709551615.
    #[arg(
        long,
        value_name = "SEED",
        default_value_t = Options::default().seed,
        requires = "optimize",
        allow_negative_numbers = true,
        value_parser = ranges::seed
    )]
    optimize_seed: u64,
    /// With --optimize: random planning orders tried before the search, from 0 to 10000.
    #[arg(
        long,
        value_name = "N",
        default_value_t = Options::default().restarts,
        requires = "optimize",
        allow_negative_numbers = true,
        value_parser = ranges::restarts
    )]
    restarts: u32,
    /// With --optimize: the most flights one search step takes out of the schedule, from 1
    /// to 1000.
    #[arg(
        long,
        value_name = "N",
        default_value_t = Options::default().neighbourhood,
        requires = "optimize",
        allow_negative_numbers = true,
        value_parser = ranges::neighbourhood
    )]
    neighbourhood: usize,
    /// With --optimize: simulated annealing, the chance at the first step that a step making
    /// the schedule worse is kept anyway (falling to 0 at the last), from 0 to 1; 0 keeps only
    /// steps that leave it no worse. The best schedule seen is written either way.
    #[arg(
        long,
        value_name = "P",
        default_value_t = Options::default().anneal,
        requires = "optimize",
        allow_negative_numbers = true,
        value_parser = ranges::anneal
    )]
    anneal: f64,
}

impl OptimizeArgs {
    /// How the day is to be planned.
    pub fn planning(&self) -> Planning {
        if !self.optimize {
            return Planning::FirstComeFirstServed;
        }
        Planning::Optimized(Options {
            iterations: self.iterations,
            time_budget: self.time_budget_s.map(Duration::from_secs_f64),
            seed: self.optimize_seed,
            restarts: self.restarts,
            neighbourhood: self.neighbourhood,
            anneal: self.anneal,
        })
    }

    /// Plans `requests` on `world` with `params`, first come, first served or as one batch,
    /// with a progress bar over the requests, or over the optimiser's steps.
    pub fn plan(
        &self,
        world: &World,
        params: FlightParams,
        requests: Vec<Request>,
    ) -> anyhow::Result<DayRun> {
        let mut progress = if self.optimize {
            LazyProgress::new(self.iterations, "optimising")
        } else {
            LazyProgress::new(requests.len() as u64, "planning")
        };
        let run = plan_requests_by(
            &world.airspace,
            &world.zones,
            params,
            requests,
            self.planning(),
            |done| progress.set(done as u64),
        )?;
        progress.finish();
        Ok(run)
    }
}

/// The lines `muse plan` and `muse simulate` print about the optimiser.
pub fn report_lines(r: &OptimizerSummary) -> Vec<String> {
    vec![
        format!(
            "  fcfs          {} planned, total delay {:.1} s (mean {:.1} s)",
            r.fcfs.planned, r.fcfs.total_delay_s, r.fcfs.mean_delay_s
        ),
        format!(
            "  optimised     {} planned, total delay {:.1} s (mean {:.1} s); {} displaced; \
             {} can fly alone",
            r.optimized.planned,
            r.optimized.total_delay_s,
            r.optimized.mean_delay_s,
            r.displaced,
            r.can_fly_alone
        ),
        format!(
            "  optimiser     {} steps ({} improved{}) from the {} order, {:.2} s, {:.0} \
             steps/s, {} labels",
            r.iterations,
            r.improved,
            if r.stopped_by_time_budget {
                ", stopped by the time budget"
            } else {
                ""
            },
            r.started_from,
            r.time_s,
            r.iterations_per_s,
            r.expanded
        ),
    ]
}
