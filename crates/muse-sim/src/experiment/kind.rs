//! The trait a kind of experiment implements: its cases, how one run goes, what it records,
//! and how its records are summarized and shown.

use muse_model::{Airspace, Request};
use serde::Serialize;
use serde::de::DeserializeOwned;

use super::grid::Grid;
use super::report::{Column, Group, Plot, SummarySpec};
use crate::demand::DemandError;

/// One day of the grid as a run sees it.
#[derive(Clone, Copy, Debug)]
pub struct Day<'a> {
    /// The count's index in [`Grid::counts`].
    pub count_index: usize,
    /// Requests of the day.
    pub count: usize,
    /// Repetition index.
    pub rep: usize,
    /// Demand seed.
    pub seed: u64,
    /// The day's requests, sorted for planning (`(submitted, id)`), generated once and shared
    /// by every case; empty when the kind makes its own demand ([`Kind::shared_demand`]).
    pub requests: &'a [Request],
}

/// What a kind reports while an experiment runs.
#[derive(Clone, Copy, Debug)]
pub enum Progress<'a, R> {
    /// A run is about to start.
    Started {
        /// Its number in the whole experiment.
        run: usize,
        /// Its case's index in [`Kind::cases`].
        case: usize,
        /// Requests of its day.
        count: usize,
    },
    /// A run is done.
    Finished {
        /// Its number in the whole experiment.
        run: usize,
        /// What it measured.
        record: &'a R,
    },
}

/// A kind of experiment: what varies between the runs of one day (its *cases*), how one run
/// goes, what it records, and how the records are summarized and shown.
///
/// An [`Experiment`](super::Experiment) runs every case on every day of its [`Grid`]: run
/// `k · days + d` is case `k` on day `d` (days: count, then repetition). Running, sharding,
/// merging, the CSV files, the printed table and the plots are written once, against this
/// trait; a kind says only what is its own.
pub trait Kind: Sync {
    /// What one run measured: a row of the runs file, an entry of a shard file.
    type Record: Clone + Send + Sync + Serialize + DeserializeOwned;
    /// Why a run fails.
    type Error: std::error::Error + From<DemandError> + Send + Sync + 'static;

    /// Its cases' names, in run order (variants, announcement leads, graphs).
    fn cases(&self) -> Vec<String>;

    /// Everything besides the grid that decides its runs, as a canonical text: the
    /// experiment's identity is a hash of it.
    fn identity(&self) -> String;

    /// The airspace whose stations each day's demand is drawn on, once per day for every
    /// case; `None` when each run makes its own (the benchmark, one process per case).
    fn shared_demand(&self) -> Option<&Airspace>;

    /// Whether runs may go in parallel (on the global `rayon` pool); a kind that measures a
    /// whole process runs them one at a time.
    fn parallel(&self) -> bool {
        true
    }

    /// Runs case `case` on `day` of `grid`.
    fn run(&self, grid: &Grid, case: usize, day: &Day<'_>) -> Result<Self::Record, Self::Error>;

    /// The file of one row per run, e.g. `sweep.csv`.
    fn runs_file(&self) -> &'static str;

    /// The columns of the runs file; `records` are all of them, for columns fitted to the
    /// whole experiment.
    fn columns<'r>(&self, records: &'r [Self::Record]) -> Vec<Column<'r, Self::Record>>;

    /// The summary file: the records grouped by case and count, each metric's mean and 95%
    /// confidence interval; `None` for a kind without one.
    fn summary(&self) -> Option<SummarySpec<Self::Record>>;

    /// Whether a column of the file compared with a study's published one (the summary, or
    /// the runs file without one) is measured on this machine (times, memory) rather than
    /// exact.
    fn measured(&self, column: &str) -> bool;

    /// The table printed when the experiment is done.
    fn table(
        &self,
        grid: &Grid,
        records: &[Self::Record],
        groups: &[Group<Self::Record>],
    ) -> String;

    /// The plots written beside the CSV files.
    fn plots(
        &self,
        grid: &Grid,
        records: &[Self::Record],
        groups: &[Group<Self::Record>],
    ) -> Vec<Plot>;
}
