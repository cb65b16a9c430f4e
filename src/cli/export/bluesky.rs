//! `muse export bluesky`: a plans file as a BlueSky scenario (docs/reference.md, "BlueSky
//! scenarios").

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{ArgMatches, Args};
use muse_export::bluesky::{Flight, Options, scenario};
use muse_formats::plans::read_plan_entries_file;

use super::super::common::{FlightArgs, WorldArgs};
use super::super::layers::LayersArgs;
use super::super::{output, recorded};

/// Arguments of `muse export bluesky`.
#[derive(Debug, Args)]
pub struct BlueskyArgs {
    /// Plans file (JSON Lines, as written by `muse plan` or `muse simulate`).
    #[arg(long, value_name = "FILE")]
    plans: PathBuf,
    /// The run's summary, whose world and cruise speed to write with (each option given here
    /// overrides its own). Default: `summary.json` beside the plans file, if there is one.
    #[arg(long, value_name = "FILE")]
    summary: Option<PathBuf>,
    // Boxed: the world's options are large, and `muse export`'s formats share one enum.
    #[command(flatten)]
    world: Box<WorldArgs>,
    #[command(flatten)]
    layers: Box<LayersArgs>,
    #[command(flatten)]
    flight: Box<FlightArgs>,
    /// BlueSky aircraft type of every flight: an OpenAP rotorcraft such as `M600` (DJI Matrice
    /// 600), `Amzn` or `Mavic`.
    #[arg(long = "type", value_name = "TYPE", default_value = "M600")]
    aircraft_type: String,
    /// Output scenario file (`-`: standard output).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
}

/// Runs `muse export bluesky`: every flight that flies (planned, replanned or diverted: its
/// final plan) becomes BlueSky commands; rejected, unserved and cancelled requests write
/// nothing.
pub fn run(args: &BlueskyArgs, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    let found = recorded::find(&args.plans, args.summary.as_deref())?;
    let inputs = recorded::plans_inputs(
        &args.plans,
        found.as_ref(),
        args.summary.is_some(),
        &args.world,
    );
    let out = output::file("--out", &args.out, &inputs)?;
    let (world, params) = recorded::world_of_run(
        &args.plans,
        found.as_ref(),
        &args.world,
        &args.layers,
        Some(&args.flight),
        matches,
    )?;
    let params = params.expect("the flight parameters were asked for");
    let entries = read_plan_entries_file(&args.plans, &world.airspace)?;
    let records: Vec<_> = entries.iter().filter_map(|e| e.record()).collect();
    let flights: Vec<Flight<'_>> = records
        .iter()
        .filter_map(|r| {
            r.final_plan().map(|plan| Flight {
                request: &r.request,
                plan,
            })
        })
        .collect();
    let options = Options {
        aircraft_type: args.aircraft_type.clone(),
        speed: params.speed,
        offset: world.offset,
    };
    let written = scenario(&world.airspace, &flights, &options).map_err(|e| {
        if matches!(e, muse_export::bluesky::BlueskyError::Type(_)) {
            anyhow::anyhow!("--type: {e}")
        } else {
            anyhow::anyhow!("{}: {e}", args.plans.display())
        }
    })?;
    out.write(&written.text)?;
    let origin = written.origin.map_or(String::new(), |o| {
        format!(", time origin {}", o.to_rfc3339(world.offset))
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
