//! Argument parsing and dispatch.

mod airspace;
mod bench;
mod common;
mod demand;
mod experiment;
mod export;
mod layer_map;
mod layers;
mod load;
mod optimize;
mod output;
mod overrides;
mod plan;
mod plans_run;
mod progress;
mod ranges;
mod recorded;
mod serve;
mod simulate;
mod siting;
mod study;
mod sweep;
mod verify;
mod view;

use std::process::ExitCode;

use clap::{CommandFactory as _, FromArgMatches as _, Parser, Subcommand};

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
    /// How planning scales: planner time, search effort and peak memory per request for
    /// growing demand and graph size, with fitted growth exponents, a table and plots.
    Bench(bench::BenchArgs),
    /// One case of `muse bench`, measured in its own process (prints one JSON line).
    #[command(hide = true)]
    BenchCase(bench::CaseArgs),
    /// Write a plans file in another tool's language: a BlueSky scenario, or ASTM F3548-21
    /// operational intents.
    #[command(subcommand)]
    Export(export::ExportCommand),
    /// Generate a seeded requests file (uniform departures in a window, random station pairs).
    Demand(demand::DemandCmd),
    /// Load a running `muse serve` over HTTP (open loop, paced clients or closed loop), report throughput and
    /// latency, then verify every planned flight.
    Load(load::LoadArgs),
    /// Plan a requests file: exact earliest-landing plans, first come first served.
    Plan(plan::PlanArgs),
    /// The planning service: a live schedule behind a JSON API, durable across crashes
    /// (docs/reference.md#the-planning-service).
    Serve(serve::ServeArgs),
    /// Simulate a day: generate demand, plan it, verify it, write files and a summary.
    Simulate(simulate::SimulateArgs),
    /// Where to add pads: lazy greedy by exact simulation of seeded days on the rebuilt
    /// airspace, against maximum coverage and k-means for the same number of pads.
    Siting(siting::SitingArgs),
    /// The paper's experiment: request counts × repetitions × scenario variants, with plots;
    /// `--vary announce-lead`: how much warning before a temporary zone keeps its cost low.
    Sweep(Box<sweep::SweepArgs>),
    /// Check a plans file (or a `muse serve` listing saved one flight a line) against every
    /// rule, independently of the planner (exit 1 on a violation).
    Verify(verify::VerifyArgs),
    /// Write one self-contained HTML page that plays a plans file's day on a map (no network
    /// needed to open it).
    View(view::ViewArgs),
}

/// Parses the command line and runs it. Input errors come back as `Err` (exit 2).
pub fn run() -> anyhow::Result<ExitCode> {
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    // A command's own matches: what was given on the command line (`--study` refuses more).
    let own = |name: &str| {
        matches
            .subcommand_matches(name)
            .cloned()
            .unwrap_or_default()
    };
    let ran = match cli.command {
        Command::Airspace(cmd) => airspace::run(cmd),
        Command::Bench(args) => bench::run(&args, &own("bench")),
        Command::BenchCase(args) => bench::run_case(&args),
        Command::Demand(args) => demand::run(&args),
        Command::Export(cmd) => {
            let name = match cmd {
                export::ExportCommand::Bluesky(_) => "bluesky",
                export::ExportCommand::F3548(_) => "f3548",
            };
            let own = own("export");
            let own = own.subcommand_matches(name).cloned().unwrap_or_default();
            export::run(&cmd, &own)
        }
        Command::Siting(args) => siting::run(&args),
        Command::Load(args) => load::run(&args),
        Command::Plan(args) => plan::run(&args),
        Command::Serve(args) => serve::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Sweep(args) => sweep::run(&args, &own("sweep")),
        Command::Verify(args) => verify::run(&args, &own("verify")),
        Command::View(args) => view::run(&args, &own("view")),
    };
    if ran.is_err() {
        // An interruption under way ends the process with its own code and message.
        output::hold_if_interrupted();
    }
    ran
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        super::Cli::command().debug_assert();
    }
}
