//! `muse verify`: check a plans file against the rules, independently of the planner.

use std::fmt::Write as _;
use std::process::ExitCode;

use clap::{ArgMatches, Args};
use muse_formats::plans::{PlanEntry, PlanItem};
use muse_model::RejectReason;
use muse_sim::metrics::SeparationSummary;
use muse_verify::recorded::{Recorded, zones_for};
use muse_verify::verify_known_in;

use super::common::FlightArgs;
use super::plans_run::RunArgs;

/// Arguments of `muse verify`.
#[derive(Debug, Args)]
#[command(
    mut_arg("plans", |a| a.help(PLANS_HELP)),
    mut_arg("summary", |a| a.help(SUMMARY_HELP))
)]
pub struct VerifyArgs {
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    flight: FlightArgs,
    /// Print at most this many violations (all are counted), from 0 to 1000000.
    #[arg(long, default_value_t = 50, allow_negative_numbers = true, value_parser = super::ranges::max_listed)]
    max_listed: usize,
}

/// The help of `--plans` here.
const PLANS_HELP: &str = "Plans file (JSON Lines, as written by `muse plan`, or a `muse serve` \
                          listing saved one flight a line)";

/// The help of `--summary` here.
const SUMMARY_HELP: &str = "The run's summary, whose world and parameters to check with (each \
                            option given here overrides its own). Default: `summary.json` \
                            beside the plans file, if there is one";

/// The statuses a plans file's lines may have, in the order the summary counts them.
const STATUSES: [&str; 6] = [
    "planned",
    "replanned",
    "diverted",
    "contingency",
    "cancelled",
    "rejected",
];

/// Runs `muse verify`: exit 0 if every flight that flies satisfies
/// docs/reference.md#flight-model-and-separation and #no-fly-zones (and
/// #zones-announced-during-the-day, #multi-leg-trips), 1 otherwise. Every line of the plans file is
/// read: those of `muse plan` and `muse simulate`, and those of a service listing saved one flight
/// a line (flights cancelled by their operator and rejected requests are read and counted, and fly
/// nothing).
pub fn run(args: &VerifyArgs, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    let (run, params) = args.run.files()?.open_with_flight(&args.flight, matches)?;
    let (world, entries) = (&run.world, &run.entries);
    let a = &world.airspace;
    let records = entries.iter().filter_map(|e| e.record().cloned()).collect();
    let recorded =
        Recorded::new(records, a).map_err(|e| anyhow::anyhow!("{}: {e}", run.plans.display()))?;
    let flights = recorded.flights();
    let zones = zones_for(a, &world.zones, &flights)?;
    let violations = verify_known_in(a, &zones, &params, &flights, world.day.offset);
    let read = lines_read(entries);
    let separation = SeparationSummary::of(
        a,
        &world.plane_positions()?,
        &flights,
        world.day.offset,
        params.separation,
    );
    let mut report = String::new();
    let code = if violations.is_empty() {
        let changed = entries.iter().filter(|e| !e.changes().is_empty()).count();
        let announced = if zones.announced.is_empty() {
            String::new()
        } else {
            format!(
                ", {} announced during the day; {changed} flights changed by announcements",
                zones.announced.len()
            )
        };
        let layers = a.layers().map_or(String::new(), |l| {
            format!("; {} layers, heading rule {}", l.count, l.heading_rule)
        });
        let _ = writeln!(
            report,
            "OK: {read}; {} flights checked, every rule holds ({}{layers}; {} zone(s){announced})",
            flights.len(),
            params.edge_rule.name(),
            world.zones.len()
        );
        ExitCode::SUCCESS
    } else {
        let _ = writeln!(
            report,
            "FAILED: {} violation(s) among the {} flights checked ({read})",
            violations.len(),
            flights.len()
        );
        for v in violations.iter().take(args.max_listed) {
            let _ = writeln!(report, "  {v}");
        }
        if violations.len() > args.max_listed {
            let _ = writeln!(
                report,
                "  … and {} more",
                violations.len() - args.max_listed
            );
        }
        ExitCode::FAILURE
    };
    let _ = writeln!(report, "metric separation: {}", separation.describe());
    print_report(&report)?;
    Ok(code)
}

/// Prints the report on standard output. A reader that stops early (`muse verify … | head`)
/// closes the pipe: the rest is dropped quietly, and the exit code still says what was found.
fn print_report(report: &str) -> anyhow::Result<()> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(report.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("writing the report to standard output"))
        }
        _ => Ok(()),
    }
}

/// `N lines read (P planned, …, Z cancelled by a zone, K cancelled by their operator, R
/// rejected)`: the lines of a plans file by status, statuses with none left out.
fn lines_read(entries: &[PlanEntry]) -> String {
    let by_operator = |e: &PlanEntry| matches!(e.item, PlanItem::CancelledByOperator(_));
    let parts: Vec<String> = STATUSES
        .iter()
        .flat_map(|&status| {
            let of = |e: &&PlanEntry| e.status() == status;
            if status == "cancelled" {
                vec![
                    (
                        "cancelled by a zone",
                        entries
                            .iter()
                            .filter(of)
                            .filter(|e| !by_operator(e))
                            .count(),
                    ),
                    (
                        "cancelled by their operator",
                        entries.iter().filter(of).filter(|e| by_operator(e)).count(),
                    ),
                ]
            } else if status == "rejected" {
                let unserved = |e: &&PlanEntry| {
                    e.record()
                        .is_some_and(|r| r.result == Err(RejectReason::Unserved))
                };
                vec![
                    (
                        "rejected",
                        entries.iter().filter(of).filter(|e| !unserved(e)).count(),
                    ),
                    (
                        "unserved",
                        entries.iter().filter(of).filter(unserved).count(),
                    ),
                ]
            } else {
                vec![(status, entries.iter().filter(of).count())]
            }
        })
        .filter(|(_, n)| *n > 0)
        .map(|(s, n)| format!("{n} {s}"))
        .collect();
    let lines = entries.len();
    let noun = if lines == 1 { "line" } else { "lines" };
    if parts.is_empty() {
        format!("{lines} {noun} read")
    } else {
        format!("{lines} {noun} read ({})", parts.join(", "))
    }
}
