//! `muse view`: one self-contained HTML page that plays a day of deliveries (also written
//! by `muse simulate` as `view.html`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{ArgMatches, Args};
use muse_formats::plans::{OperatorCancellation, PlanItem, PlanRecord};
use muse_model::{Instant, Millis};

use super::common::World;
use super::output::{self, write_atomically};
use super::plans_run::RunArgs;

/// Arguments of `muse view`.
#[derive(Debug, Args)]
#[command(
    mut_arg("plans", |a| a.help(PLANS_HELP)),
    mut_arg("summary", |a| a.help(SUMMARY_HELP))
)]
pub struct ViewArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Output file (`-`: standard output).
    #[arg(long, value_name = "FILE", default_value = "view.html")]
    out: PathBuf,
}

/// The help of `--plans` here.
const PLANS_HELP: &str = "Plans file (JSON Lines, as written by `muse simulate` or `muse plan`)";

/// The help of `--summary` here.
const SUMMARY_HELP: &str = "The day's summary: shown beside the map, and its world drawn (each \
                            option given here overrides its own). Default: `summary.json` \
                            beside the plans file, if there is one";

/// Runs `muse view`.
pub fn run(args: &ViewArgs, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    let files = args.run.files()?;
    let out = output::file("--out", &args.out, &files.inputs())?;
    let run = files.open(matches)?;
    let mut records = Vec::new();
    let mut cancelled = Vec::new();
    for entry in run.entries {
        match entry.item {
            PlanItem::Record(r) => records.push(r),
            PlanItem::CancelledByOperator(c) => cancelled.push(c),
        }
    }
    let summary = match &run.summary {
        Some(s) => {
            let text = std::fs::read_to_string(&s.path)
                .with_context(|| format!("reading {}", s.path.display()))?;
            Some(
                serde_json::from_str(&text)
                    .with_context(|| format!("{}: not a JSON summary", s.path.display()))?,
            )
        }
        None => None,
    };
    let (html, drawn) = view_page(&run.world, &records, &cancelled, summary)?;
    out.write(&html)?;
    output::say(
        out.is_stdout(),
        format_args!(
            "wrote {out} ({:.1} MB): {drawn} flights of {} requests{}; open it in a browser, no network needed",
            html.len() as f64 / 1e6,
            records.len() + cancelled.len(),
            run.summary.map_or(String::new(), |s| format!(
                ", summary from {}",
                s.path.display()
            ))
        ),
    );
    Ok(ExitCode::SUCCESS)
}

/// Writes the page of `records` (and the operators' `cancelled` flights) over `world` to
/// `path`; returns its size in bytes and the flights it draws.
pub fn write_view(
    world: &World,
    records: &[PlanRecord],
    cancelled: &[OperatorCancellation],
    summary: Option<serde_json::Value>,
    path: &Path,
) -> anyhow::Result<(usize, usize)> {
    let (html, drawn) = view_page(world, records, cancelled, summary)?;
    write_atomically(path, &html)?;
    Ok((html.len(), drawn))
}

/// The page of `records` over `world`, and the number of flights it draws.
fn view_page(
    world: &World,
    records: &[PlanRecord],
    cancelled: &[OperatorCancellation],
    summary: Option<serde_json::Value>,
) -> anyhow::Result<(String, usize)> {
    let range = day_range(world, records, cancelled);
    let scene = scene_of(world, records, cancelled, summary, range)?;
    Ok((muse_view::page(&scene), scene.flights.len()))
}

/// The live page of `muse serve` over `world`, its clock starting around `now`.
pub fn live_page(world: &World, now: Instant) -> anyhow::Result<String> {
    let range = (
        now - Millis::from_mins(60),
        now + Millis::from_mins(23 * 60),
    );
    let scene = scene_of(world, &[], &[], None, range)?;
    Ok(muse_view::live_page(&scene))
}

/// The scene of `records` over `world`, showing at least `range`.
fn scene_of(
    world: &World,
    records: &[PlanRecord],
    cancelled: &[OperatorCancellation],
    summary: Option<serde_json::Value>,
    range: (Instant, Instant),
) -> anyhow::Result<muse_view::Scene> {
    let land = super::common::world_land(world);
    let mut input = muse_view::SceneInput::new(&world.airspace, world.day.offset, range);
    input.title.clone_from(&world.title);
    if world.scenario.is_some() {
        muse_scenario::ATTRIBUTION.clone_into(&mut input.attribution);
    }
    input.land = &land;
    input.zones = &world.zones;
    input.flights = records;
    input.cancelled = cancelled;
    input.summary = summary;
    muse_view::scene(&input).context("building the viewer's scene")
}

/// The stretch of time the page shows at least: the requests' departures and the flights,
/// or the scenario's whole day when there are none.
fn day_range(
    world: &World,
    records: &[PlanRecord],
    cancelled: &[OperatorCancellation],
) -> (Instant, Instant) {
    let times = records
        .iter()
        .flat_map(|r| {
            let plan = r.final_plan();
            [
                Some(r.requested_departure),
                plan.map(muse_model::Plan::landing),
            ]
            .into_iter()
            .flatten()
        })
        .chain(cancelled.iter().map(|c| c.requested_departure));
    let (lo, hi) = times.fold(
        (None, None),
        |(lo, hi): (Option<Instant>, Option<Instant>), t| {
            (
                Some(lo.map_or(t, |l| l.min(t))),
                Some(hi.map_or(t, |h| h.max(t))),
            )
        },
    );
    if let (Some(lo), Some(hi)) = (lo, hi) {
        (lo, hi)
    } else {
        let midnight = Instant::at_local(world.day.date, Millis::ZERO, world.day.offset);
        (midnight, midnight + Millis::from_mins(24 * 60))
    }
}
