//! MUSE simulation: from requests and plans to the numbers a user reads.
//!
//! - [`demand`]: seeded, reproducible request generation (SPEC §8);
//! - [`day`]: planning a day of requests first come, first served;
//! - [`replay`](mod@replay): a day as it unfolds: requests at their submission instants, zones
//!   announced at theirs, and the flights each announcement replans (SPEC §11);
//! - [`sweep`]: the paper's experiment, counts × repetitions × variants in parallel;
//! - [`shard`]: a sweep cut into shards for a cluster's array job, and merged back exactly;
//! - [`lead`]: the regulator's question, announcement lead × counts × repetitions: how much
//!   warning before a temporary zone becomes active keeps the cost of replanning low;
//! - [`bench`](mod@bench): scaling benchmarks (`muse bench`): case measurements, peak memory, growth
//!   exponents, table and CSV;
//! - [`stats`]: means and 95% confidence intervals;
//! - [`metrics`]: the run summary (`summary.json`, SPEC §7): success rate, rejections by
//!   reason, air and ground delay statistics, planner time and search effort, parameters.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod bench;
pub mod day;
pub mod demand;
pub mod lead;
pub mod metrics;
pub mod replay;
pub mod shard;
pub mod stats;
pub mod sweep;
