//! The arguments of `muse sweep` and `muse sweep merge`.

use std::path::PathBuf;

use clap::Args;

use super::levers::{LeverArgs, vary_values};
use crate::cli::common::{FlightArgs, WorldArgs};
use crate::cli::demand::DemandArgs;
use crate::cli::ranges;

/// `muse sweep` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum SweepCommand {
    /// Merge the shards of one sweep (`--shard K/N` runs) into the files of an unsharded run;
    /// refuses shards of different sweeps, a missing shard and a shard given twice.
    Merge(MergeArgs),
}

/// Arguments of `muse sweep`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
// A sweep's request counts are `--counts`: the demand options' `--count` is not one of its own.
#[command(mut_arg("count", |a| a.hide(true)))]
pub struct SweepArgs {
    /// `muse sweep merge DIR...`: merge the shards of one sweep.
    #[command(subcommand)]
    pub command: Option<SweepCommand>,
    /// Run the sweep a study file describes (TOML: its title, and the options of this
    /// command in a `[sweep]` table; see `studies/`). Beside it give only `--shard`, `--out`
    /// (default `out/STUDY`), `--threads` and `--dry-run`.
    #[arg(long, value_name = "FILE")]
    pub study: Option<PathBuf>,
    /// Run only shard `K` of `N` (0-based: runs `K`, `K+N`, … in run order), seeds unchanged,
    /// and write `DIR/shard.json`; `muse sweep merge` joins the shards. For array jobs:
    /// Slurm `--shard $SLURM_ARRAY_TASK_ID/N`, Kubernetes `--shard $JOB_COMPLETION_INDEX/N`.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Request counts: `START:END:STEP` or a comma-separated list; each from 1 to 10000000,
    /// at most 1000 counts, and at most 1000000 days (counts × repetitions).
    #[arg(long, default_value = "1000:10000:1000", allow_hyphen_values = true)]
    pub counts: String,
    /// Repetitions per count, each with its own seed, from 1 to 10000.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true, value_parser = ranges::reps)]
    pub reps: usize,
    /// Compare scenarios on the same seeds; repeat to combine (except `announce-lead`).
    #[arg(long, value_parser = vary_values())]
    pub vary: Vec<String>,
    /// `--vary announce-lead`: the leads to compare, minutes between a zone's announcement and
    /// the start of its first active window on the scenario's day, comma-separated, each
    /// from 0 to 43200, at most 100 [default: 0,15,30,60,120].
    #[arg(long, value_name = "MIN,...", allow_hyphen_values = true)]
    pub leads: Option<String>,
    /// `--vary announce-lead`: zone files (ED-318/ED-269) whose zones are announced, each
    /// `lead` before its first window (their own announcement instants are replaced); repeat
    /// for several. Default: the built-in scenario's CBD zone. A base zone (`--zones`) with
    /// the same id is not also known from the start.
    #[arg(long, value_name = "FILE")]
    pub announce_zones: Vec<PathBuf>,
    /// The levers' own options (`--swap-min`, …).
    #[command(flatten)]
    pub levers: LeverArgs,
    /// Worker threads, from 1 to 1024 (default: all cores).
    #[arg(long, allow_negative_numbers = true, value_parser = ranges::threads)]
    pub threads: Option<usize>,
    /// Print what would run — the sweep's identity, its runs and requests, the shard's share,
    /// the command line it stands for — and exit without running.
    #[arg(long)]
    pub dry_run: bool,
    #[command(flatten)]
    pub demand: DemandArgs,
    #[command(flatten)]
    pub world: WorldArgs,
    #[command(flatten)]
    pub flight: FlightArgs,
    /// Output folder, written whole: it replaces an earlier run's folder as a whole, and a
    /// folder holding files muse does not write is refused (docs/reference.md#outputs).
    #[arg(long, value_name = "DIR", default_value = "out/sweep")]
    pub out: PathBuf,
}

/// Arguments of `muse sweep merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shards' output folders (or their `shard.json` files), every shard of one sweep once.
    #[arg(required = true, value_name = "DIR")]
    pub shards: Vec<PathBuf>,
    /// Output folder for the merged `sweep.csv`, `sweep_summary.csv` and plots (with
    /// `--vary announce-lead`: `announce_lead.csv`, its summary and plots).
    #[arg(long, value_name = "DIR", default_value = "out/sweep")]
    pub out: PathBuf,
}
