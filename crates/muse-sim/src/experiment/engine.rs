//! An experiment: a [`Grid`] and a [`Kind`], run whole or as one shard, and its records made
//! into files and a table.

use muse_model::Request;
use muse_model::request::sort_for_planning;
use rayon::prelude::*;

use super::grid::Grid;
use super::kind::{Day, Kind, Progress};
use super::report::{ReportError, csv_text, summarize, summary_csv};
use super::shard::{Shard, fingerprint};
use crate::demand::{DemandError, generate};

/// Every case of a kind on every day of a grid.
#[derive(Debug)]
pub struct Experiment<K> {
    /// Counts × repetitions and their demand.
    pub grid: Grid,
    /// What varies between the runs of a day.
    pub kind: K,
}

/// An experiment's files and printed table, made from its records.
#[derive(Clone, Debug, PartialEq)]
pub struct Results {
    /// Each file's name and text, in the order written: the runs file, the summary file (if
    /// the kind has one), the plots.
    pub files: Vec<(String, String)>,
    /// The table to print.
    pub table: String,
    /// The file compared with a study's published one: the summary file, or the runs file
    /// for a kind without one.
    pub compared: String,
}

impl<K: Kind> Experiment<K> {
    /// Number of runs: cases × counts × repetitions.
    pub fn runs(&self) -> usize {
        self.kind.cases().len() * self.grid.counts.len() * self.grid.reps
    }

    /// Total requests planned over every run.
    pub fn total_requests(&self) -> usize {
        self.kind.cases().len() * self.grid.requests_per_case()
    }

    /// The experiment's identity (see [`fingerprint`]): the same for the same runs.
    pub fn identity(&self) -> String {
        fingerprint(&(&self.grid, self.kind.identity()))
    }

    /// Runs the runs of `shard` ([`Shard::WHOLE`] for all), with their run numbers, in run
    /// order; `progress` hears of each run's start and end.
    pub fn run(
        &self,
        shard: Shard,
        progress: &(dyn Fn(Progress<'_, K::Record>) + Sync),
    ) -> Result<Vec<(usize, K::Record)>, K::Error> {
        let grid = &self.grid;
        let days = grid.days();
        let runs: Vec<(usize, usize, usize)> = (0..self.kind.cases().len())
            .flat_map(|k| (0..days.len()).map(move |d| (k, d)))
            .enumerate()
            .filter(|&(run, _)| shard.takes(run))
            .map(|(run, (k, d))| (run, k, d))
            .collect();
        let demands = self.demands(&days, &runs)?;
        let one = |&(run, case, d): &(usize, usize, usize)| {
            let (c, rep) = days[d];
            let day = Day {
                count_index: c,
                count: grid.counts[c],
                rep,
                seed: grid.seed(c, rep),
                requests: &demands[d],
            };
            progress(Progress::Started {
                run,
                case,
                count: day.count,
            });
            let record = self.kind.run(grid, case, &day)?;
            progress(Progress::Finished {
                run,
                record: &record,
            });
            Ok((run, record))
        };
        if self.kind.parallel() {
            runs.par_iter().map(one).collect()
        } else {
            runs.iter().map(one).collect()
        }
    }

    /// Each day's requests, sorted for planning, when the kind shares them — generated once,
    /// in parallel, and only for the days `runs` need (empty for the others).
    fn demands(
        &self,
        days: &[(usize, usize)],
        runs: &[(usize, usize, usize)],
    ) -> Result<Vec<Vec<Request>>, DemandError> {
        let Some(airspace) = self.kind.shared_demand() else {
            return Ok(vec![Vec::new(); days.len()]);
        };
        let mut needed = vec![false; days.len()];
        for &(_, _, d) in runs {
            needed[d] = true;
        }
        days.par_iter()
            .zip(&needed)
            .map(|(&(c, r), &needed)| {
                if !needed {
                    return Ok(Vec::new());
                }
                let mut requests = generate(airspace, &self.grid.demand(c, r))?;
                sort_for_planning(&mut requests);
                Ok(requests)
            })
            .collect()
    }

    /// The files and table of `records` (the whole experiment, in run order).
    pub fn results(&self, records: &[K::Record]) -> Result<Results, ReportError> {
        let runs_file = self.kind.runs_file();
        let mut files = vec![(
            runs_file.to_owned(),
            csv_text(runs_file, &self.kind.columns(records), records)?,
        )];
        let mut compared = runs_file.to_owned();
        let groups = match self.kind.summary() {
            Some(spec) => {
                let groups = summarize(records, &spec);
                files.push((spec.file.to_owned(), summary_csv(&spec, &groups)?));
                spec.file.clone_into(&mut compared);
                groups
            }
            None => Vec::new(),
        };
        for plot in self.kind.plots(&self.grid, records, &groups) {
            let svg =
                muse_render::render_line_plot(&plot.series, &plot.options).map_err(|source| {
                    ReportError::Plot {
                        file: plot.file.to_owned(),
                        source,
                    }
                })?;
            files.push((plot.file.to_owned(), svg));
        }
        Ok(Results {
            files,
            table: self.kind.table(&self.grid, records, &groups),
            compared,
        })
    }
}
