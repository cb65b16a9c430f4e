//! Experiments as one abstraction: a [`Grid`] of days (request counts × repetitions, each
//! with its seed, window, demand rule, booking lead and flight parameters) run in every case
//! of a [`Kind`].
//!
//! A kind says what is its own — its cases, how one run goes, its record and columns, its
//! summary, its table and plots — and everything else is written once, here:
//!
//! - [`Experiment`]: a grid and a kind; [`Experiment::run`] runs every case on every day (or
//!   one [`Shard`] of them), days' demand generated once and shared by the cases;
//!   [`Experiment::results`] makes the CSV files (through the `csv` crate), the summary,
//!   the plots and the table;
//! - [`shard`](ShardFile): a run cut into shards for a cluster's array job, and [`merge`]d
//!   back exactly;
//! - [`Study`]: a study file, the options of a run written down in TOML; [`reproduction`]
//!   compares a rerun with the study's published file.
//!
//! The kinds:
//!
//! - [`sweep`]: the paper's experiment, scenario variants made by [`sweep::levers`] (one
//!   file per lever);
//! - [`lead`]: the regulator's question, how much warning before a temporary zone keeps the
//!   cost of announcing it low;
//! - [`bench`](mod@bench): how planning scales, each case in a process of its own.

pub mod bench;
mod engine;
mod grid;
mod kind;
pub mod lead;
mod report;
mod reproduce;
mod shard;
mod study;
pub mod sweep;

pub use engine::{Experiment, Results};
pub use grid::{Grid, Seeds};
pub use kind::{Day, Kind, Progress};
pub use report::{
    Column, Group, Metric, Plot, ReportError, SummarySpec, csv_text, summarize, summary_csv,
};
pub use reproduce::{Reproduction, reproduction};
pub use shard::{FORMAT, Shard, ShardError, ShardFile, ShardRun, StudyRef, fingerprint, merge};
pub use study::{HOW_TO_RUN, OptionShape, Study, StudyError, Takes};

#[cfg(test)]
mod tests;
