//! `muse export bluesky`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{ArgMatches, Args};

/// Arguments of `muse export bluesky`.
#[derive(Debug, Args)]
pub struct BlueskyArgs {
    /// Plans file (JSON Lines, as written by `muse plan` or `muse simulate`).
    #[arg(long, value_name = "FILE")]
    plans: PathBuf,
}

/// Runs `muse export bluesky`.
pub fn run(args: &BlueskyArgs, _matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    anyhow::bail!(
        "{}: muse export bluesky is being built",
        args.plans.display()
    )
}
