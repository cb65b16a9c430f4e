//! Scaling benchmarks (`muse bench`) as a [`Kind`](crate::experiment::Kind): graphs × demand
//! levels, one run each, every run a process of its own so that its peak memory is its own.
//!
//! - [`Bench`]: the kind; a case process measures with [`measure`] and prints one JSON line
//!   ([`CaseResult::to_json_line`]), which the parent reads back ([`Measured`]);
//! - [`fit_power_law`], [`Exponents`]: growth summarised by least-squares slopes on log–log
//!   axes — per graph, total planner time against requests (1 means linear in demand); per
//!   demand level, time per request against the number of nodes;
//! - [`peak_rss_bytes`]: peak memory from `/proc/self/status`;
//! - `bench.csv`, the table and the plots.

mod fit;
mod kind;
mod measure;
mod memory;
mod record;
mod report;

pub use fit::{Exponents, PowerFit, fit_power_law};
pub use kind::{Bench, BenchError, WINDOW_HOURS};
pub use measure::{Graph, MeasureError, measure};
pub use memory::{MIB, current_rss_bytes, mib, peak_rss_bytes, status_kib_field};
pub use record::{CaseResult, Measured};
pub use report::{columns, grouped, series_by_graph, table};

#[cfg(test)]
mod tests;
