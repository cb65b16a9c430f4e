//! `muse simulate`: a day of deliveries — generate, plan, verify, report.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::Args;
use muse_formats::flights::{FlightFeature, write_flights};
use muse_formats::plans::PlanRecord;
use muse_formats::requests::{Demand, read_demand_file, write_demand, write_requests};
use muse_model::Request;
use muse_sim::day::DayRun;
use muse_sim::demand::{BookingLead, generate};
use muse_sim::metrics::Summary;
use muse_verify::{Flight, verify_known_in};

use super::common::{World, render_world_map};
use super::demand::DemandArgs;
use super::layer_map::render_layer_map;
use super::optimize::report_lines;
use super::output;
use super::output::write_atomically;
use super::plan::{DayArgs, write_outputs};
use super::view::write_view;

/// Arguments of `muse simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    demand: DemandArgs,
    /// Plan this requests file instead of generating demand.
    #[arg(
        long,
        value_name = "FILE",
        conflicts_with_all = ["count", "seed", "from", "to", "od", "booking_lead_min"]
    )]
    requests: Option<PathBuf>,
    #[command(flatten)]
    day: DayArgs,
    /// Output folder, written whole: it replaces an earlier run's folder as a whole, and a
    /// folder holding files muse does not write is refused (docs/reference.md#outputs).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
    /// Do not write the tables `flights.csv` and `stays.csv`.
    #[arg(long)]
    no_csv: bool,
}

/// Runs `muse simulate`; exits 1 if the verifier finds a violation.
pub fn run(args: &SimulateArgs) -> anyhow::Result<ExitCode> {
    let (params, world) = args.day.open("simulate")?;
    let inputs = output::Inputs::new().world(&args.day.world);
    let inputs = match &args.requests {
        Some(path) => inputs.add("--requests", path),
        None => inputs,
    };
    let out = output::folder("--out", &args.out, &inputs)?;
    let (demand, source, seed, booking_lead) = demand_of(args, &world)?;
    let run = args.day.optimize.plan(&world, params, demand.requests)?;

    let flights = run.flights();
    let violations = verify_known_in(
        &world.airspace,
        &run.zones,
        &params,
        &flights,
        world.day.offset,
    );

    let provenance = world.provenance(source.clone(), seed);
    // The requests as read (demand from customers: every row, customer ids kept), by id.
    let from_customers = demand.rows.is_some();
    let requests_csv = if let Some(mut rows) = demand.rows {
        rows.sort_by(|a, b| a.id.cmp(&b.id));
        write_demand(&rows, &world.airspace, world.day.offset)
    } else {
        let mut sorted_by_id: Vec<&Request> = run.requests.iter().collect();
        sorted_by_id.sort_by(|a, b| a.id.cmp(&b.id));
        let owned: Vec<Request> = sorted_by_id.into_iter().cloned().collect();
        write_requests(&owned, &world.airspace, world.day.offset)
    };
    write_atomically(&out.path().join("requests.csv"), &requests_csv)?;
    let tables = !args.no_csv;
    let (summary, records) = write_outputs(
        &world,
        &run,
        from_customers.then_some(demand.unserved.as_slice()),
        &params,
        provenance,
        booking_lead,
        tables,
        out.path(),
    )?;
    write_maps(&world, &run, &flights, &records, &summary, out.path())?;
    out.commit()?;

    print!(
        "{}",
        report(
            &world,
            &summary,
            &source,
            violations.len(),
            tables,
            &args.out
        )
    );
    for v in violations.iter().take(20) {
        println!("  {v}");
    }
    Ok(if violations.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// The day's demand: the requests file's (`--requests`) or generated; with where it came from
/// (for the summary), the seed and the booking lead of generated demand.
fn demand_of(
    args: &SimulateArgs,
    world: &World,
) -> anyhow::Result<(Demand, String, Option<u64>, Option<BookingLead>)> {
    Ok(if let Some(path) = &args.requests {
        (
            read_demand_file(path, &world.airspace, world.day)?,
            path.display().to_string(),
            None,
            None,
        )
    } else {
        let spec = args.demand.spec(world, args.day.flight.range)?;
        let reqs = generate(&world.airspace, &spec)?;
        let od = match args.demand.od {
            super::demand::OdArg::Uniform => "uniform",
            super::demand::OdArg::InRange => "in-range",
        };
        let booked = args
            .demand
            .booking_note()
            .map_or(String::new(), |b| format!(", {b}"));
        let (from, to, day) = (&args.demand.from, &args.demand.to, world.day_note());
        let source = format!(
            "generated: {} requests, {from}–{to}{day}, {od} pairs, seed {}{booked}",
            spec.count, spec.seed
        );
        let demand = Demand {
            requests: reqs,
            ..Demand::default()
        };
        (demand, source, Some(spec.seed), Some(spec.booking_lead))
    })
}

/// Writes the day's drawings into `out`: `flights.geojson`, `map.svg` (corridor load; per
/// layer when layered) and `view.html` (the page that plays the day).
fn write_maps(
    world: &World,
    run: &DayRun,
    flights: &[Flight<'_>],
    records: &[PlanRecord],
    summary: &Summary,
    out: &std::path::Path,
) -> anyhow::Result<()> {
    let features: Vec<FlightFeature<'_>> = run
        .requests
        .iter()
        .zip(&run.replay.outcomes)
        .enumerate()
        .filter_map(|(i, (r, o))| {
            run.replay.final_plan(i).map(|plan| FlightFeature {
                request: &r.id,
                plan,
                requested_departure: r.departure,
                free_flow: o.free_flow,
            })
        })
        .collect();
    write_atomically(
        &out.join("flights.geojson"),
        &write_flights(&features, &world.airspace, world.day.offset),
    )?;
    let svg = if let Some(svg) = render_layer_map(world, flights)? {
        svg
    } else {
        let load = edge_load(world, flights);
        render_world_map(
            world,
            1_800,
            Some((load, "Flights per corridor".to_owned())),
        )?
    };
    write_atomically(&out.join("map.svg"), &svg)?;
    let summary_json =
        serde_json::from_str(&summary.to_json()).context("re-reading the summary")?;
    write_view(
        world,
        records,
        &[],
        Some(summary_json),
        &out.join("view.html"),
    )?;
    Ok(())
}

/// Traversals per edge.
fn edge_load(world: &World, flights: &[Flight<'_>]) -> Vec<f64> {
    let a = &world.airspace;
    let mut load = vec![0.0; a.edge_count()];
    for f in flights {
        for (from, to) in f.plan.hops() {
            if let Some(e) = a.edge_between(from.node, to.node) {
                load[e.index()] += 1.0;
            }
        }
    }
    load
}

/// The short human summary printed at the end.
/// The `rejected` line, and the `unserved` one for demand from customers.
fn rejections(s: &Summary) -> String {
    let reasons: Vec<String> = s
        .rejected_by_reason
        .iter()
        .map(|(k, v)| format!("{k} {v}"))
        .collect();
    let mut o = format!("  rejected      {} ({})\n", s.rejected, reasons.join(", "));
    if let Some(n) = s.unserved {
        let _ = writeln!(
            o,
            "  unserved      {n} (no pad within the last mile of a customer, or both on one pad)"
        );
    }
    o
}

fn report(
    world: &World,
    s: &Summary,
    source: &str,
    violations: usize,
    tables: bool,
    out: &std::path::Path,
) -> String {
    let mut o = String::new();
    let zones = if world.zones.is_empty() {
        "no zones".to_owned()
    } else {
        world
            .zones
            .iter()
            .map(|z| z.id.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(o, "MUSE simulate — {} ({zones})", world.airspace_source);
    let _ = writeln!(o, "  demand        {source}");
    let _ = writeln!(
        o,
        "  planned       {} of {} ({:.1}%)",
        s.planned,
        s.requests,
        100.0 * s.success_rate
    );
    o.push_str(&rejections(s));
    for line in s.optimizer.iter().flat_map(report_lines) {
        let _ = writeln!(o, "{line}");
    }
    let d = |x: muse_sim::metrics::Distribution| {
        format!(
            "mean {:.1} s, median {:.1} s, p95 {:.1} s, max {:.1} s",
            x.mean, x.median, x.p95, x.max
        )
    };
    let _ = writeln!(o, "  air delay     {}", d(s.air_delay_s));
    let _ = writeln!(o, "  ground delay  {}", d(s.ground_delay_s));
    if let Some(l) = &s.legs {
        let _ = writeln!(
            o,
            "  legs          mean {:.2}, max {} per trip; {} trips with swaps, {} swaps in all",
            l.per_trip_mean, l.per_trip_max, l.multi_leg_trips, l.swaps
        );
    }
    if let Some(r) = &s.replanning {
        for z in &r.zones {
            let _ = writeln!(
                o,
                "  announced     {} at {}: {} flights affected",
                z.zone, z.announced, z.affected
            );
        }
        let _ = writeln!(
            o,
            "  replanning    {} affected ({} airborne): {} replanned, {} diverted, {} cancelled, {} contingency",
            r.flights_affected,
            r.airborne_affected,
            r.replanned,
            r.diverted,
            r.cancelled,
            r.contingency
        );
        let _ = writeln!(
            o,
            "  extra delay   {} (replanned flights, final − first landing)",
            d(r.extra_delay_s)
        );
        let _ = writeln!(
            o,
            "  delivered     {} of {} ({:.1}%) to their destination after replanning",
            r.delivered,
            s.requests,
            100.0 * r.delivery_rate
        );
    }
    let _ = writeln!(
        o,
        "  planner       {:.1} ms in all, {:.2} µs and {:.2} expanded labels per request",
        s.planner_time.total_s * 1e3,
        s.planner_time.per_request_us,
        s.search.expanded_per_request
    );
    let verdict = if violations == 0 {
        "OK, every rule holds".to_owned()
    } else {
        format!("FAILED, {violations} violation(s)")
    };
    let _ = writeln!(o, "  verified      {verdict}");
    if let Some(sep) = &s.separation {
        let _ = writeln!(o, "  separation    {}", sep.describe());
    }
    let tables = if tables {
        "flights.csv, stays.csv, "
    } else {
        ""
    };
    let _ = writeln!(
        o,
        "  wrote         {}/{{requests.csv, plans.jsonl, summary.json, {tables}flights.geojson, map.svg, view.html}}",
        out.display()
    );
    o
}
