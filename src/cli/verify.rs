//! `muse verify`: check a plans file against the rules, independently of the planner.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use muse_airspace::announced::KnownZones;
use muse_formats::plans::read_plans_file;
use muse_model::{Millis, Request};
use muse_verify::{Flight, verify_known};

use super::common::{FlightArgs, WorldArgs};

/// Arguments of `muse verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Plans file (JSON Lines, as written by `muse plan`).
    #[arg(long, value_name = "FILE")]
    plans: PathBuf,
    #[command(flatten)]
    world: WorldArgs,
    #[command(flatten)]
    flight: FlightArgs,
    /// Print at most this many violations (all are counted).
    #[arg(long, default_value_t = 50)]
    max_listed: usize,
}

/// Runs `muse verify`: exit 0 if every planned flight satisfies SPEC §3–§4, 1 otherwise.
pub fn run(args: &VerifyArgs) -> anyhow::Result<ExitCode> {
    let params = args.flight.params()?;
    let world = args.world.load()?;
    let a = &world.airspace;
    let records = read_plans_file(&args.plans, a)?;
    let file = args.plans.display().to_string();
    let mut requests = Vec::with_capacity(records.len());
    for (i, r) in records.iter().enumerate() {
        let station = |id: &str, field: &str| {
            a.node_id(id).ok_or_else(|| {
                anyhow::anyhow!(
                    "{file}: line {}: field `{field}`: unknown node id `{id}`",
                    i + 1
                )
            })
        };
        requests.push(Request {
            id: r.request.clone(),
            origin: station(&r.origin, "origin")?,
            destination: station(&r.destination, "destination")?,
            departure: r.requested_departure,
            submitted: r.requested_departure,
        });
    }
    let flights: Vec<Flight<'_>> = records
        .iter()
        .zip(&requests)
        .filter_map(|(r, q)| Flight::last(&r.request, q, r.result.as_ref().ok(), r.fate.as_ref()))
        .collect();
    let day = Millis::from_secs(86_400);
    let from = flights
        .iter()
        .map(|f| f.plan.takeoff())
        .min()
        .unwrap_or_default()
        - day;
    let to = flights
        .iter()
        .map(|f| f.plan.landing())
        .max()
        .unwrap_or_default()
        + day;
    let from = world
        .zones
        .iter()
        .filter_map(|z| z.announced)
        .min()
        .map_or(from, |n| n.min(from));
    let zones = KnownZones::resolve(a, &world.zones, from, to)?;
    let violations = verify_known(a, &zones, &params, &flights);
    if violations.is_empty() {
        let changed = records.iter().filter(|r| r.fate.is_some()).count();
        let announced = if zones.announced.is_empty() {
            String::new()
        } else {
            format!(
                ", {} announced during the day; {changed} flights changed by announcements",
                zones.announced.len()
            )
        };
        println!(
            "OK: {} flights of {} requests satisfy every rule ({}; {} zone(s){announced})",
            flights.len(),
            records.len(),
            params.edge_rule.name(),
            world.zones.len()
        );
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "FAILED: {} violation(s) among {} planned flights",
        violations.len(),
        flights.len()
    );
    for v in violations.iter().take(args.max_listed) {
        println!("  {v}");
    }
    if violations.len() > args.max_listed {
        println!("  … and {} more", violations.len() - args.max_listed);
    }
    Ok(ExitCode::FAILURE)
}
