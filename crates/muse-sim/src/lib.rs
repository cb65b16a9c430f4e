//! MUSE simulation: from requests and plans to the numbers a user reads.
//!
//! - [`demand`]: seeded, reproducible request generation (SPEC §8);
//! - [`day`]: planning a day of requests first come, first served;
//! - [`metrics`]: the run summary (`summary.json`, SPEC §7): success rate, rejections by
//!   reason, air and ground delay statistics, planner time and search effort, parameters.

pub mod day;
pub mod demand;
pub mod metrics;
