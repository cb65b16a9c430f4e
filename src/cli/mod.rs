//! Argument parsing and dispatch.

mod airspace;
mod common;
mod plan;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// MUSE: exact collision-free planning and simulation of drone deliveries on a structured
/// airspace. With no files given, commands use the embedded Singapore default (77 HDB car-park
/// rooftop stations, the Downtown Core no-fly zone 10:00–12:00).
#[derive(Debug, Parser)]
#[command(name = "muse", version, about, long_about = None, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Build, inspect and draw airspaces.
    #[command(subcommand)]
    Airspace(airspace::AirspaceCommand),
    /// Plan a requests file: exact earliest-landing plans, first come first served.
    Plan(plan::PlanArgs),
}

/// Parses the command line and runs it. Input errors come back as `Err` (exit 2).
pub fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Airspace(cmd) => airspace::run(cmd),
        Command::Plan(args) => plan::run(&args),
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        super::Cli::command().debug_assert();
    }
}
