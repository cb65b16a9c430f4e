//! The benchmark as a [`Kind`]: its cases are graphs, its counts demand levels, one run each;
//! every run is a process of its own (`muse bench-case`), one at a time, so that its peak
//! memory is its own.

use std::path::PathBuf;
use std::process::{Command, Stdio};

use muse_model::Airspace;

use super::record::{CaseResult, Measured};
use super::report::{columns, measured_column, plots, table};
use crate::demand::DemandError;
use crate::experiment::grid::Grid;
use crate::experiment::kind::{Day, Kind};
use crate::experiment::report::{Column, Group, Plot, SummarySpec};

/// The benchmark's departure window: 08:00 to 20:00, local time on the graph's day.
pub const WINDOW_HOURS: (i64, i64) = (8, 20);

/// Why a case failed.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The case process could not be started.
    #[error("starting {exe}: {source}")]
    Start {
        /// The executable.
        exe: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The case process failed (its messages went to standard error).
    #[error("case {graph}, {requests} requests failed ({status}); its messages are above")]
    Failed {
        /// The graph.
        graph: String,
        /// Its demand level.
        requests: usize,
        /// How it ended.
        status: std::process::ExitStatus,
    },
    /// The case process printed no measurements.
    #[error("case {graph}, {requests} requests printed nothing")]
    Silent {
        /// The graph.
        graph: String,
        /// Its demand level.
        requests: usize,
    },
    /// The case process printed something else than its measurements.
    #[error("case {graph}, {requests} requests: reading `{line}`: {source}")]
    Unreadable {
        /// The graph.
        graph: String,
        /// Its demand level.
        requests: usize,
        /// What it printed last.
        line: String,
        /// Cause.
        source: serde_json::Error,
    },
    /// Demand could not be generated.
    #[error(transparent)]
    Demand(#[from] DemandError),
}

/// How planning scales: each graph at each demand level of the grid, measured in a process of
/// its own.
#[derive(Clone, Debug)]
pub struct Bench {
    /// The graphs, by name (`singapore-77`, `synthetic-10000`, …).
    pub graphs: Vec<String>,
    /// The program that measures a case: run as `EXE bench-case --graph=G --requests=N
    /// --od=OD --seed=S FLAGS…`, it prints one JSON line ([`CaseResult::to_json_line`]).
    pub exe: PathBuf,
    /// The origin–destination rule's name: `uniform` or `in-range`.
    pub od: &'static str,
    /// The flight options, as `bench-case` reads them (`--speed-kmh=30`, …).
    pub flags: Vec<String>,
}

impl Bench {
    /// Runs the case process of `graph` at `requests` with `seed`; returns what it measured.
    fn child(&self, graph: &str, requests: usize, seed: u64) -> Result<CaseResult, BenchError> {
        let output = Command::new(&self.exe)
            .arg("bench-case")
            .arg(format!("--graph={graph}"))
            .arg(format!("--requests={requests}"))
            .arg(format!("--od={}", self.od))
            .arg(format!("--seed={seed}"))
            .args(&self.flags)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .output()
            .map_err(|source| BenchError::Start {
                exe: self.exe.display().to_string(),
                source,
            })?;
        let case = || (graph.to_owned(), requests);
        if !output.status.success() {
            let (graph, requests) = case();
            return Err(BenchError::Failed {
                graph,
                requests,
                status: output.status,
            });
        }
        let stdout = String::from_utf8_lossy(&output.stdout);
        let Some(line) = stdout.lines().rev().find(|l| !l.trim().is_empty()) else {
            let (graph, requests) = case();
            return Err(BenchError::Silent { graph, requests });
        };
        CaseResult::from_json_line(line).map_err(|source| {
            let (graph, requests) = case();
            BenchError::Unreadable {
                graph,
                requests,
                line: line.to_owned(),
                source,
            }
        })
    }
}

impl Kind for Bench {
    type Record = Measured;
    type Error = BenchError;

    fn cases(&self) -> Vec<String> {
        self.graphs.clone()
    }

    fn identity(&self) -> String {
        format!("{:?} {} {:?}", self.graphs, self.od, self.flags)
    }

    fn shared_demand(&self) -> Option<&Airspace> {
        None
    }

    fn parallel(&self) -> bool {
        false
    }

    fn run(&self, _: &Grid, case: usize, day: &Day<'_>) -> Result<Measured, BenchError> {
        let started = std::time::Instant::now();
        let result = self.child(&self.graphs[case], day.count, day.seed)?;
        Ok(Measured {
            result,
            wall_s: started.elapsed().as_secs_f64(),
        })
    }

    fn runs_file(&self) -> &'static str {
        "bench.csv"
    }

    fn columns<'r>(&self, records: &'r [Measured]) -> Vec<Column<'r, Measured>> {
        columns(records)
    }

    fn summary(&self) -> Option<SummarySpec<Measured>> {
        None
    }

    fn measured(&self, column: &str) -> bool {
        measured_column(column)
    }

    fn table(&self, _: &Grid, records: &[Measured], _: &[Group<Measured>]) -> String {
        table(records)
    }

    fn plots(&self, grid: &Grid, records: &[Measured], _: &[Group<Measured>]) -> Vec<Plot> {
        let (from, to) = WINDOW_HOURS;
        let foot = format!(
            "One run per point: {} OD pairs, seed {}, departures uniform {from:02}:00–{to:02}:00",
            self.od,
            grid.seed(0, 0)
        );
        plots(records, &foot)
    }
}
