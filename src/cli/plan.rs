//! `muse plan`: plan a requests file.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::Args;
use muse_formats::plans::PlanRecord;
use muse_formats::requests::{UnservedRequest, read_demand_file};
use muse_model::FlightParams;
use muse_sim::day::DayRun;
use muse_sim::demand::BookingLead;
use muse_sim::metrics::{Provenance, ReplanSummary, Summary};
use muse_sim::outputs::{DayContext, DayFiles, day_outputs};

use super::common::{FlightArgs, World, WorldArgs, refuse_withdrawn};
use super::layers::{LayersArgs, layered};
use super::optimize::{OptimizeArgs, report_lines};
use super::output;
use super::output::write_atomically;

/// Arguments of `muse plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    /// Requests CSV (`id,origin,destination,departure[,submitted]`, and
    /// `origin_customer,destination_customer` for demand from customers, whose unserved
    /// requests are counted apart).
    #[arg(long, value_name = "FILE")]
    requests: PathBuf,
    #[command(flatten)]
    day: DayArgs,
    /// Output folder for `plans.jsonl`, `summary.json`, `flights.csv` and `stays.csv`.
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
    /// Do not write the tables `flights.csv` and `stays.csv`.
    #[arg(long)]
    no_csv: bool,
}

/// What a planned day is planned on and how, as `muse plan` and `muse simulate` take it: the
/// world, its layers, the flight parameters and the planning (first come, first served, or
/// optimised).
#[derive(Debug, Args)]
pub struct DayArgs {
    #[command(flatten)]
    pub world: WorldArgs,
    #[command(flatten)]
    pub layers: LayersArgs,
    #[command(flatten)]
    pub flight: FlightArgs,
    #[command(flatten)]
    pub optimize: OptimizeArgs,
}

impl DayArgs {
    /// The flight parameters and the layered world, refused with a withdrawn zone (`command`
    /// names the command in the message).
    pub fn open(&self, command: &str) -> anyhow::Result<(FlightParams, World)> {
        let params = self.flight.params()?;
        let world = layered(self.world.load()?, &self.layers)?;
        refuse_withdrawn(&world, command)?;
        Ok((params, world))
    }
}

/// Runs `muse plan`.
pub fn run(args: &PlanArgs) -> anyhow::Result<ExitCode> {
    let (params, world) = args.day.open("plan")?;
    let out = output::folder(
        "--out",
        &args.out,
        &output::Inputs::new()
            .add("--requests", &args.requests)
            .world(&args.day.world),
    )?;
    let demand = read_demand_file(&args.requests, &world.airspace, world.day)?;
    let run = args.day.optimize.plan(&world, params, demand.requests)?;
    let provenance = world.provenance(args.requests.display().to_string(), None);
    let tables = !args.no_csv;
    let (summary, _) = write_outputs(
        &world,
        &run,
        demand.rows.is_some().then_some(demand.unserved.as_slice()),
        &params,
        provenance,
        None,
        tables,
        out.path(),
    )?;
    out.commit()?;
    if let Some(r) = &summary.replanning {
        println!("{}", replanning_line(r));
    }
    for line in summary.optimizer.iter().flat_map(report_lines) {
        println!("{}", line.trim_start());
    }
    if let Some(sep) = &summary.separation {
        println!("metric separation: {}", sep.describe());
    }
    let unserved = summary
        .unserved
        .map_or(String::new(), |n| format!(", {n} unserved"));
    println!(
        "planned {} of {} requests ({:.1}%{unserved}) in {:.1} ms ({:.1} µs and {:.1} expanded labels per request); wrote {}",
        summary.planned,
        summary.requests,
        100.0 * summary.success_rate,
        summary.planner_time.total_s * 1e3,
        summary.planner_time.per_request_us,
        summary.search.expanded_per_request,
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// Writes `plans.jsonl` and `summary.json` (and, with `tables`, `flights.csv` and
/// `stays.csv`) for a planned day into `out`; returns the summary and the records written.
/// The `unserved` requests of demand from customers (docs/reference.md#airspace-from-pads; `None`
/// for other demand) follow the planned day's lines, rejected with reason `unserved`, and are
/// counted apart in the summary. `booking_lead` is the lead of generated demand, recorded in the
/// summary's parameters (`None` for requests read from a file).
#[allow(clippy::too_many_arguments)]
pub fn write_outputs(
    world: &World,
    run: &DayRun,
    unserved: Option<&[UnservedRequest]>,
    params: &muse_model::FlightParams,
    provenance: Provenance,
    booking_lead: Option<BookingLead>,
    tables: bool,
    out: &std::path::Path,
) -> anyhow::Result<(Summary, Vec<PlanRecord>)> {
    let outputs = day_outputs(
        run,
        DayContext {
            booking_lead,
            unserved,
            ..DayContext::on(world, params, provenance)?
        },
    );
    let files = DayFiles::of(&outputs, &world.airspace, world.day, tables);
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    for (name, text) in files.iter() {
        write_atomically(&out.join(name), text)?;
    }
    Ok((outputs.summary, outputs.records))
}

/// One line on what zone announcements did, for the terminal.
pub fn replanning_line(r: &ReplanSummary) -> String {
    let zones: Vec<String> = r
        .zones
        .iter()
        .map(|z| format!("{} at {} hit {}", z.zone, z.announced, z.affected))
        .collect();
    format!(
        "{} zone(s) announced ({}); {} flights affected ({} airborne): {} replanned, {} diverted, \
         {} cancelled, {} contingency; extra delay of replanned flights mean {:.1} s, max {:.1} s; \
         {} of the requests delivered to their destination ({:.1}%)",
        r.zones_announced,
        zones.join("; "),
        r.flights_affected,
        r.airborne_affected,
        r.replanned,
        r.diverted,
        r.cancelled,
        r.contingency,
        r.extra_delay_s.mean,
        r.extra_delay_s.max,
        r.delivered,
        100.0 * r.delivery_rate
    )
}
