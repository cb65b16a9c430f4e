//! `muse export bluesky`: a plans file as a BlueSky scenario (docs/reference.md, "BlueSky
//! scenarios").

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{ArgMatches, Args};
use muse_export::bluesky::{Flight, Options, scenario};

use super::super::common::FlightArgs;
use super::super::output;
use super::super::plans_run::RunArgs;

/// Arguments of `muse export bluesky`.
#[derive(Debug, Args)]
#[command(mut_arg("summary", |a| a.help(SUMMARY_HELP)))]
pub struct BlueskyArgs {
    // Boxed: the run's and flight options are large, and `muse export`'s formats share one
    // enum.
    #[command(flatten)]
    run: Box<RunArgs>,
    #[command(flatten)]
    flight: Box<FlightArgs>,
    /// BlueSky aircraft type of every flight: an OpenAP rotorcraft such as `M600` (DJI Matrice
    /// 600), `Amzn` or `Mavic`.
    #[arg(long = "type", value_name = "TYPE", default_value = "M600")]
    aircraft_type: String,
    /// Fly every corridor at cruise speed, open loop, without the required times of arrival
    /// at the waypoints that keep the planned times (docs/reference.md, "BlueSky scenarios").
    #[arg(long)]
    open_loop: bool,
    /// Output scenario file (`-`: standard output).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
}

/// The help of `--summary` here.
const SUMMARY_HELP: &str = "The run's summary, whose world and cruise speed to write with (each \
                            option given here overrides its own). Default: `summary.json` \
                            beside the plans file, if there is one";

/// Runs `muse export bluesky`: every flight that flies (planned, replanned or diverted: its
/// final plan) becomes BlueSky commands; rejected, unserved and cancelled requests write
/// nothing.
pub fn run(args: &BlueskyArgs, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    let files = args.run.files()?;
    let out = output::file("--out", &args.out, &files.inputs())?;
    let (run, params) = files.open_with_flight(&args.flight, matches)?;
    let (world, entries) = (&run.world, &run.entries);
    let flights: Vec<Flight<'_>> = run
        .flown()
        .map(|(request, plan)| Flight { request, plan })
        .collect();
    let options = Options {
        aircraft_type: args.aircraft_type.clone(),
        speed: params.speed,
        offset: world.day.offset,
        open_loop: args.open_loop,
    };
    let written = scenario(&world.airspace, &flights, &options).map_err(|e| {
        if matches!(e, muse_export::bluesky::BlueskyError::Type(_)) {
            anyhow::anyhow!("--type: {e}")
        } else {
            anyhow::anyhow!("{}: {e}", run.plans.display())
        }
    })?;
    out.write(&written.text)?;
    let origin = written.origin.map_or(String::new(), |o| {
        format!(", time origin {}", o.to_rfc3339(world.day.offset))
    });
    output::say(
        out.is_stdout(),
        format_args!(
            "wrote {out}: {} flights ({} BlueSky aircraft) of {} lines read, type {}{origin}",
            written.flights,
            written.legs,
            entries.len(),
            args.aircraft_type
        ),
    );
    Ok(ExitCode::SUCCESS)
}
