//! `muse export`: a plans file in another tool's language.

mod bluesky;
mod f3548;

use std::process::ExitCode;

use clap::{ArgMatches, Subcommand};

/// The formats `muse export` writes.
#[derive(Debug, Subcommand)]
pub enum ExportCommand {
    /// A BlueSky scenario (`.scn`): each flight created at take-off over its origin, flown
    /// through its nodes, held where it hovers, and landed at its destination.
    Bluesky(bluesky::BlueskyArgs),
    /// ASTM F3548-21 operational intents: one per flight, a 4-D volume per stay and corridor
    /// traversal.
    F3548(f3548::F3548Args),
}

/// Runs `muse export`.
pub fn run(cmd: &ExportCommand, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    match cmd {
        ExportCommand::Bluesky(args) => bluesky::run(args, matches),
        ExportCommand::F3548(args) => f3548::run(args, matches),
    }
}
