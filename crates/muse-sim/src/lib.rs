//! MUSE simulation: from requests and plans to the numbers a user reads.
//!
//! - [`demand`]: seeded, reproducible request generation (docs/reference.md#built-in-scenarios);
//! - [`customers`]: demand from customers: each customer's serving pad
//!   (docs/reference.md#airspace-from-pads);
//! - [`day`]: planning a day of requests first come, first served;
//! - [`replay`](mod@replay): a day as it unfolds: requests at their submission instants, zones
//!   announced at theirs, and the flights each announcement replans
//!   (docs/reference.md#zones-announced-during-the-day);
//! - [`experiment`]: experiments as one abstraction — a grid of seeded days run in every case
//!   of a kind, sharded and merged, written as CSV files, tables and plots, and study files:
//!   the paper's sweep ([`experiment::sweep`]), the announcement-lead sweep
//!   ([`experiment::lead`]) and the scaling benchmark ([`experiment::bench`]);
//! - [`outputs`]: a planned day's records (the lines of `plans.jsonl`), its summary and the
//!   texts of its files (`plans.jsonl`, `summary.json`, `flights.csv`, `stays.csv`);
//! - [`world`]: the world a day is planned on — airspace, zones, day and what a summary
//!   records of them — loaded for every front end, and flown at its layers;
//! - [`stats`]: means and 95% confidence intervals;
//! - [`metrics`]: the run summary (`summary.json`, docs/reference.md#plans): success rate,
//!   rejections by reason, air and ground delay statistics, planner time and search effort,
//!   parameters.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod customers;
pub mod day;
pub mod demand;
pub mod experiment;
pub mod metrics;
pub mod outputs;
pub mod replay;
pub mod stats;
pub mod world;
