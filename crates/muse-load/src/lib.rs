//! `muse load`: an HTTP load generator for the MUSE planning service (`muse serve`,
//! docs/reference.md#the-planning-service).
//!
//! A run asks the service what it plans on (`/healthz`, `/v1/airspace`, `/v1/zones`), sends
//! it seeded Singapore demand with departures in the future — open loop at a fixed rate,
//! closed loop with N clients, or paced: N clients that together follow the open-loop
//! schedule of a fixed rate — for a count or a duration — records every request's latency,
//! status and outcome, samples the service's memory gauges about once a second, and at the
//! end fetches every planned flight the service holds and checks them all together with the
//! independent verifier.
//!
//! - [`config`]: what a run does ([`LoadConfig`], [`Mode`], [`Stop`]);
//! - [`server`]: the HTTP client and what the service plans on (the hot `POST /v1/flights`
//!   goes on kept-alive connections of its own, written and read directly);
//! - [`demand`]: the seeded requests (pairs from `muse_sim::demand`);
//! - [`schedule`]: the open-loop schedule (latency from due time: no coordinated omission)
//!   and its precise pacing for paced runs;
//! - [`client`]: the open-loop, closed-loop and paced runners;
//! - [`outcome`]: what became of one request;
//! - [`stats`]: exact percentiles;
//! - [`metrics`]: the service's gauges over time;
//! - [`verify`]: fetching and verifying every planned flight;
//! - [`report`]: the JSON report and the terminal summary;
//! - [`run`](mod@run): a whole run.
//!
//! ```no_run
//! # async fn demo() -> Result<(), muse_load::LoadError> {
//! use muse_load::{LoadConfig, Mode, Stop};
//! let mut config = LoadConfig::new("http://127.0.0.1:8080");
//! config.mode = Mode::Open { rate: 500.0, max_in_flight: 10_000 };
//! config.stop = Stop::Duration(std::time::Duration::from_secs(10));
//! let report = muse_load::run(&config, |_| {}).await?;
//! println!("{}", report.text());
//! // The same schedule served by 16 clients, each with one request in flight at most.
//! config.mode = Mode::Paced { rate: 500.0, clients: 16 };
//! let paced = muse_load::run(&config, |_| {}).await?;
//! println!("{}", paced.text());
//! # Ok(()) }
//! ```
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod client;
pub mod config;
pub mod demand;
pub mod error;
pub mod metrics;
pub mod outcome;
mod post;
pub mod report;
pub mod run;
pub mod schedule;
pub mod server;
pub mod stats;
pub mod verify;

pub use config::{LoadConfig, Mode, Stop};
pub use demand::OdChoice;
pub use error::LoadError;
pub use report::Report;
pub use run::{Event, run};
