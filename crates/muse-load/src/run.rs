//! A whole run: ask the service what it plans on, load it while sampling its gauges, then
//! fetch and verify every planned flight.

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Duration;

use crate::client::{Live, LoadRun, run_load};
use crate::config::{LoadConfig, Stop};
use crate::demand::{Demand, default_prefix};
use crate::error::LoadError;
use crate::metrics::{MetricPoint, parse_gauges};
use crate::outcome::Outcome;
use crate::report::{Report, ServerSummary};
use crate::server::{Server, ServerWorld, system_now};
use crate::verify::{Verification, check, fetch_planned};

/// How often progress is reported during the load.
pub const PROGRESS_EVERY: Duration = Duration::from_millis(200);

/// How often `/metrics` is sampled during the load.
pub const SAMPLE_EVERY: Duration = Duration::from_secs(1);

/// What a run is doing, for progress displays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// The load is running.
    Load {
        /// Since the load started.
        elapsed: Duration,
        /// Requests sent.
        sent: u64,
        /// Requests finished.
        completed: u64,
        /// Requests planned.
        planned: u64,
        /// Requests that ended in an error.
        errors: u64,
        /// When it stops.
        stop: Stop,
    },
    /// The load is over; fetching planned flights (this many so far).
    Fetching {
        /// Flights fetched.
        flights: usize,
    },
    /// Verifying this many flights.
    Verifying {
        /// Flights to check.
        flights: usize,
    },
}

/// One sample of the gauges, `t_s` seconds after `origin`; `None` if `/metrics` did not
/// answer (a busy service may be slow to).
async fn sample(server: &Server, origin: tokio::time::Instant) -> Option<MetricPoint> {
    let text = server.get_text("/metrics").await.ok()?;
    Some(MetricPoint {
        t_s: origin.elapsed().as_secs_f64(),
        values: parse_gauges(&text),
    })
}

/// Fetches every planned flight the service holds and verifies them together; checks that
/// every flight of this run answered `planned` is listed, when the run was shorter than the
/// service's retention (after it, ended flights leave the service's memory by design).
async fn verify_run(
    server: &Server,
    world: &ServerWorld,
    prefix: &str,
    load_run: &LoadRun,
    ran_for: Duration,
    on_event: &mut impl FnMut(&Event),
) -> Result<Verification, LoadError> {
    on_event(&Event::Fetching { flights: 0 });
    let plans = fetch_planned(server, |flights| {
        on_event(&Event::Fetching { flights });
    })
    .await?;
    on_event(&Event::Verifying {
        flights: plans.lines().count(),
    });
    let complete = world.retain.is_none_or(|r| ran_for < r);
    let acknowledged: Vec<u64> = if complete {
        load_run
            .samples
            .iter()
            .filter(|s| s.outcome == Outcome::Planned)
            .map(|s| s.index)
            .collect()
    } else {
        Vec::new()
    };
    let mut v = check(world, &plans, prefix, &acknowledged)?;
    v.completeness_checked = complete;
    Ok(v)
}

/// Runs `config` against its service, reporting progress to `on_event`.
///
/// An unreachable service, a refused token or an answer that cannot be understood before the
/// load starts is an error; failures during the load are counted in the report.
pub async fn run(
    config: &LoadConfig,
    mut on_event: impl FnMut(&Event),
) -> Result<Report, LoadError> {
    config.check()?;
    let server = Arc::new(Server::new(
        &config.url,
        config.token.as_deref(),
        config.timeout,
    )?);
    let world = server.world().await?;
    let prefix = config
        .id_prefix
        .clone()
        .unwrap_or_else(|| default_prefix(config.seed, system_now().0));
    let demand = Demand::new(
        &world.airspace,
        &world.params,
        config.od,
        config.seed,
        config.lead,
        &prefix,
        world.offset,
    )?;
    let summary = ServerSummary {
        airspace: world.label.clone(),
        stations: world.airspace.stations().count(),
        od_pairs: demand.pair_count(),
        parameters: world.parameters.clone(),
        clock_skew_ms: world.skew.0,
        flights_before: world.flights_before,
    };

    let origin = tokio::time::Instant::now();
    let mut series: Vec<MetricPoint> = sample(&server, origin).await.into_iter().collect();
    let started = (system_now() + world.skew).to_rfc3339(world.offset);
    let live = Arc::new(Live::default());
    let mut load = tokio::spawn(run_load(
        Arc::clone(&server),
        demand,
        world.skew,
        config.mode,
        config.stop,
        Arc::clone(&live),
    ));
    let load_start = tokio::time::Instant::now();
    let mut ticks = tokio::time::interval(PROGRESS_EVERY);
    ticks.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let mut last_sample = tokio::time::Instant::now();
    let finished = loop {
        tokio::select! {
            result = &mut load => break result,
            _ = ticks.tick() => {
                on_event(&Event::Load {
                    elapsed: load_start.elapsed(),
                    sent: live.sent.load(Ordering::Relaxed),
                    completed: live.completed.load(Ordering::Relaxed),
                    planned: live.planned.load(Ordering::Relaxed),
                    errors: live.errors.load(Ordering::Relaxed),
                    stop: config.stop,
                });
                if last_sample.elapsed() >= SAMPLE_EVERY {
                    last_sample = tokio::time::Instant::now();
                    series.extend(sample(&server, origin).await);
                }
            }
        }
    };
    let load_run =
        finished.map_err(|e| LoadError::Config(format!("the load task failed: {e}")))??;
    series.extend(sample(&server, origin).await);

    let verification = if config.verify {
        let ran_for = origin.elapsed();
        Some(verify_run(&server, &world, &prefix, &load_run, ran_for, &mut on_event).await?)
    } else {
        None
    };
    Ok(Report::new(
        started,
        config.summary(&prefix),
        summary,
        &load_run,
        live.sent.load(Ordering::Relaxed),
        series,
        verification,
    ))
}
