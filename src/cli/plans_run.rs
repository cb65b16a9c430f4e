//! The run behind a plans file, as `muse view`, `muse verify`, `muse export bluesky` and
//! `muse export f3548` open it: the plans, the summary beside them (or `--summary FILE`), and
//! the world, layers and flight parameters the summary records, each overridden by the option
//! the command line gives ([`super::recorded`]).
//!
//! A command finds the run's files first ([`RunArgs::files`]), so that its outputs are
//! checked against them before anything is loaded, then opens it ([`RunFiles::open`]): the
//! world loaded and said on standard error, the plans read on its airspace.

use std::path::PathBuf;

use clap::{ArgMatches, Args};
use muse_formats::plans::{PlanEntry, read_plan_entries_file};
use muse_model::{FlightParams, Plan};

use super::common::{FlightArgs, World, WorldArgs};
use super::layers::LayersArgs;
use super::output::Inputs;
use super::overrides::Summary;
use super::recorded;

/// `--plans`, `--summary`, and the world and layer options that override the summary's: the
/// options of every command that reads a plans file. A command may word the help of
/// `--plans` and `--summary` for itself (`#[command(mut_arg("summary", |a| a.help(…)))]`).
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Plans file (JSON Lines, as written by `muse plan` or `muse simulate`).
    #[arg(long, value_name = "FILE")]
    pub plans: PathBuf,
    /// The day's summary, whose world the plans were made on (each option given here
    /// overrides its own). Default: `summary.json` beside the plans file, if there is one.
    #[arg(long, value_name = "FILE")]
    pub summary: Option<PathBuf>,
    #[command(flatten)]
    pub world: WorldArgs,
    #[command(flatten)]
    pub layers: LayersArgs,
}

/// The files of a run: its plans file and the summary found with it, nothing loaded yet.
pub struct RunFiles<'a> {
    args: &'a RunArgs,
    summary: Option<Summary>,
}

/// A run opened: what a command reading a plans file starts from.
pub struct Run {
    /// The plans file, as given.
    pub plans: PathBuf,
    /// The summary read with it, if any.
    pub summary: Option<Summary>,
    /// Its world, at its layers.
    pub world: World,
    /// The plans file's lines, read on the world's airspace.
    pub entries: Vec<PlanEntry>,
}

impl RunArgs {
    /// The run's files: the plans and the summary that goes with them (`--summary`, which must
    /// exist, else the `summary.json` beside the plans file if there is one).
    pub fn files(&self) -> anyhow::Result<RunFiles<'_>> {
        Ok(RunFiles {
            args: self,
            summary: recorded::find(&self.plans, self.summary.as_deref())?,
        })
    }
}

impl Run {
    /// The flights that fly, in the plans file's order: each request's final plan (planned,
    /// replanned or diverted), with its id; rejected, unserved and cancelled requests fly
    /// nothing.
    pub fn flown(&self) -> impl Iterator<Item = (&str, &Plan)> {
        self.entries
            .iter()
            .filter_map(PlanEntry::record)
            .filter_map(|r| r.final_plan().map(|plan| (r.request.as_str(), plan)))
    }
}

impl RunFiles<'_> {
    /// What opening the run reads, which the command's outputs must not overwrite.
    pub fn inputs(&self) -> Inputs {
        recorded::plans_inputs(
            &self.args.plans,
            self.summary.as_ref(),
            self.args.summary.is_some(),
            &self.args.world,
        )
    }

    /// Opens the run: its world at its layers (said on standard error, with the options that
    /// override the summary's), and the plans read on its airspace.
    pub fn open(self, matches: &ArgMatches) -> anyhow::Result<Run> {
        self.open_as(None, matches).map(|(run, _)| run)
    }

    /// [`RunFiles::open`], with the run's flight parameters: the summary's, each overridden
    /// by the option `flight` gives.
    pub fn open_with_flight(
        self,
        flight: &FlightArgs,
        matches: &ArgMatches,
    ) -> anyhow::Result<(Run, FlightParams)> {
        self.open_as(Some(flight), matches).map(|(run, params)| {
            let params = params.expect("the flight parameters were asked for");
            (run, params)
        })
    }

    fn open_as(
        self,
        flight: Option<&FlightArgs>,
        matches: &ArgMatches,
    ) -> anyhow::Result<(Run, Option<FlightParams>)> {
        let args = self.args;
        let (world, params) = recorded::world_of_run(
            &args.plans,
            self.summary.as_ref(),
            &args.world,
            &args.layers,
            flight,
            matches,
        )?;
        let entries = read_plan_entries_file(&args.plans, &world.airspace)?;
        let run = Run {
            plans: args.plans.clone(),
            summary: self.summary,
            world,
            entries,
        };
        Ok((run, params))
    }
}
