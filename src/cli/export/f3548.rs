//! `muse export f3548`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{ArgMatches, Args};

/// Arguments of `muse export f3548`.
#[derive(Debug, Args)]
pub struct F3548Args {
    /// Plans file (JSON Lines, as written by `muse plan` or `muse simulate`).
    #[arg(long, value_name = "FILE")]
    plans: PathBuf,
}

/// Runs `muse export f3548`.
pub fn run(args: &F3548Args, _matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    anyhow::bail!("{}: muse export f3548 is being built", args.plans.display())
}
