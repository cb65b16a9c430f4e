//! `muse bench`: how planning scales with demand and graph size.
//!
//! The benchmark is an experiment of its own kind ([`muse_sim::experiment::bench`]): each
//! case (one graph, one demand level) runs in its own process — this executable again, with
//! the hidden `bench-case` subcommand — so that its peak memory is its own. The case process
//! loads the graph, generates the demand, plans the day (only the planning loop is timed),
//! reads its peak resident memory and prints one JSON line; `muse bench` collects the lines,
//! prints a table with the growth exponents and writes `bench.csv` and three plots.

mod graphs;

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{Args, ValueEnum as _};
use muse_model::{EdgeRule, Instant, Millis};
use muse_sim::demand::{BookingLead, DemandSpec, OdRule};
use muse_sim::experiment::bench::{Bench, Graph, WINDOW_HOURS, grouped, measure, mib};
use muse_sim::experiment::{Experiment, Grid, Progress, Seeds, Shard, Study};

use crate::cli::common::FlightArgs;
use crate::cli::demand::OdArg;
use crate::cli::experiment::report;
use crate::cli::output::{self, write_atomically};
use crate::cli::progress::LazyProgress;
use crate::cli::ranges::{self, MAX_REQUESTS};
use crate::cli::study;
use graphs::{GraphName, load_graph, parse_graph, parse_graphs};

/// Arguments of `muse bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Demand levels, requests per day, comma-separated (`10k` and `1M` are read too), each
    /// from 1 to 10000000.
    #[arg(
        long,
        value_name = "N,N,...",
        default_value = "10000,100000,1000000",
        allow_hyphen_values = true
    )]
    requests: String,
    /// Graphs, comma-separated: `singapore-77`, `singapore-all` (every HDB multi-storey car
    /// park a station) or `synthetic-N` (a geometric graph of N nodes, 10% of them
    /// stations, spacing 1,500 m, seed 1).
    #[arg(
        long,
        value_name = "NAME,NAME,...",
        default_value = "singapore-77,singapore-all,synthetic-10000"
    )]
    graphs: String,
    /// Origin–destination rule: `in-range` (only pairs within the battery, so that every
    /// request is searched) or `uniform` (the paper's; pairs out of range are rejected
    /// before any search).
    #[arg(long, value_enum, default_value_t = OdArg::InRange)]
    od: OdArg,
    /// Seed of the demand (the same for every case), a whole number from 0 to
    /// 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = ranges::seed)]
    seed: u64,
    #[command(flatten)]
    flight: FlightArgs,
    /// Run the benchmark a study file describes (TOML: its title, and the options of this
    /// command in a `[bench]` table; see `studies/`). Beside it give only `--out`.
    #[arg(long, value_name = "FILE")]
    study: Option<PathBuf>,
    /// Output folder, written whole: it replaces an earlier run's folder as a whole, and a
    /// folder holding files muse does not write is refused (docs/reference.md#outputs).
    #[arg(long, value_name = "DIR", default_value = "out/bench")]
    out: PathBuf,
}

/// Arguments of the hidden `muse bench-case`: one case of `muse bench`, measured in this
/// process; prints one JSON line.
#[derive(Debug, Args)]
pub struct CaseArgs {
    /// The graph, as in `muse bench --graphs`.
    #[arg(long)]
    graph: String,
    /// Requests, from 1 to 10000000.
    #[arg(long, allow_negative_numbers = true, value_parser = ranges::requests)]
    requests: usize,
    /// Origin–destination rule.
    #[arg(long, value_enum, default_value_t = OdArg::InRange)]
    od: OdArg,
    /// Seed of the demand, a whole number from 0 to 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = ranges::seed)]
    seed: u64,
    #[command(flatten)]
    flight: FlightArgs,
}

/// Parses `--requests`: positive counts separated by commas, each at most once, with
/// optional `_` separators and a `k` (thousand) or `M` (million) suffix; sorted ascending.
fn parse_requests(text: &str) -> anyhow::Result<Vec<usize>> {
    let bad = |item: &str| {
        anyhow::anyhow!(
            "--requests `{text}`: `{}` is not a count of requests from 1 to {MAX_REQUESTS} \
             (e.g. 10000, 10k or 1M)",
            item.trim()
        )
    };
    let mut out = Vec::new();
    for item in text.split(',') {
        let t = item.trim().replace('_', "");
        let (digits, scale) = if let Some(d) = t.strip_suffix(['k', 'K']) {
            (d, 1_000)
        } else if let Some(d) = t.strip_suffix('M') {
            (d, 1_000_000)
        } else {
            (t.as_str(), 1)
        };
        let n = digits
            .parse::<usize>()
            .ok()
            .and_then(|n| n.checked_mul(scale))
            .filter(|n| (1..=MAX_REQUESTS).contains(n))
            .ok_or_else(|| bad(item))?;
        if out.contains(&n) {
            anyhow::bail!("--requests `{text}`: {n} is named twice");
        }
        out.push(n);
    }
    out.sort_unstable();
    Ok(out)
}

fn od_name(od: OdArg) -> &'static str {
    match od {
        OdArg::Uniform => "uniform",
        OdArg::InRange => "in-range",
    }
}

fn od_description(od: OdArg) -> &'static str {
    match od {
        OdArg::Uniform => {
            "uniform over distinct station pairs (the paper's; pairs out of range are rejected before any search)"
        }
        OdArg::InRange => {
            "in-range: uniform over station pairs within the battery, so every request is searched"
        }
    }
}

/// The flight options as `bench-case` arguments.
fn flight_flags(f: &FlightArgs) -> Vec<String> {
    let edge_rule = f
        .edge_rule
        .to_possible_value()
        .map(|v| v.get_name().to_owned())
        .unwrap_or_default();
    let mut out = vec![
        format!("--speed-kmh={}", f.range.speed_kmh),
        format!("--max-flight-min={}", f.range.max_flight_min),
        format!("--node-separation-s={}", f.node_separation_s),
        format!("--edge-rule={edge_rule}"),
        format!("--max-ground-delay-s={}", f.max_ground_delay_s),
    ];
    if let Some(h) = f.headway_s {
        out.push(format!("--headway-s={h}"));
    }
    if let Some(s) = f.battery_swap_s {
        out.push(format!("--battery-swap-s={s}"));
    }
    if let Some(k) = f.max_legs {
        out.push(format!("--max-legs={k}"));
    }
    if let Some(m) = f.max_trip_min {
        out.push(format!("--max-trip-min={m}"));
    }
    out
}

/// The demand of a case of `muse bench` on a graph planned on `date` at `offset`: requests
/// uniform in the benchmark's window, the rule `od`, `seed`.
fn demand_of(
    date: jiff::civil::Date,
    offset: muse_model::UtcOffset,
    requests: usize,
    od: OdRule,
    seed: u64,
) -> DemandSpec {
    let at = |h: i64| Instant::at_local(date, Millis::from_mins(h * 60), offset);
    DemandSpec {
        count: requests,
        start: at(WINDOW_HOURS.0),
        end: at(WINDOW_HOURS.1),
        seed,
        od,
        booking_lead: BookingLead::NONE,
    }
}

/// The origin–destination rule of `od` for flights of `params`.
fn od_rule(od: OdArg, params: &muse_model::FlightParams) -> OdRule {
    match od {
        OdArg::Uniform => OdRule::Uniform,
        OdArg::InRange => OdRule::InRange {
            speed: params.speed,
            max_flight: params.max_flight,
        },
    }
}

/// Runs the hidden `muse bench-case`: one case, measured in this process.
pub fn run_case(args: &CaseArgs) -> anyhow::Result<ExitCode> {
    let params = args.flight.params()?;
    let name = parse_graph(&args.graph)?;
    let graph = load_graph(&name)?;
    let spec = demand_of(
        graph.date,
        graph.offset,
        args.requests,
        od_rule(args.od, &params),
        args.seed,
    );
    // The bar is checked every 4,096 requests only, to keep it out of the timing.
    let mut progress = LazyProgress::new(args.requests as u64, "planning");
    let graph_name = name.to_string();
    let result = measure(
        Graph {
            name: &graph_name,
            airspace: &graph.airspace,
            zones: &graph.zones,
        },
        &spec,
        od_name(args.od),
        params,
        |done| progress.set(done as u64),
    )?;
    progress.finish();
    println!("{}", result.to_json_line());
    Ok(ExitCode::SUCCESS)
}

/// Runs `muse bench`; `matches` are its own, to tell what was given beside `--study`.
pub fn run(args: &BenchArgs, matches: &clap::ArgMatches) -> anyhow::Result<ExitCode> {
    let Some(path) = &args.study else {
        return run_bench(args, None);
    };
    let study = study::open::<BenchArgs>(path, "bench", matches)?;
    let out = study::out(&study, matches, &args.out).display().to_string();
    let bench: BenchArgs = study::parse(&study, "bench", &["--out".to_owned(), out])?;
    run_bench(&bench, Some(&study))
}

/// The benchmark `args` describe, its graphs named and loaded (for the heading).
fn experiment(args: &BenchArgs) -> anyhow::Result<(Experiment<Bench>, Vec<GraphName>)> {
    let params = args.flight.params()?;
    let levels = parse_requests(&args.requests)?;
    let graphs = parse_graphs(&args.graphs)?;
    let day = muse_scenario::by_name(muse_scenario::SINGAPORE_77)?;
    let window = demand_of(
        day.date,
        day.offset,
        0,
        od_rule(args.od, &params),
        args.seed,
    );
    let grid = Grid {
        counts: levels,
        reps: 1,
        seeds: Seeds::Same(args.seed),
        start: window.start,
        end: window.end,
        od: window.od,
        booking_lead: BookingLead::NONE,
        params,
    };
    let kind = Bench {
        graphs: graphs.iter().map(ToString::to_string).collect(),
        exe: std::env::current_exe().context("finding the muse executable")?,
        od: od_name(args.od),
        flags: flight_flags(&args.flight),
    };
    Ok((Experiment { grid, kind }, graphs))
}

/// Prints what the benchmark runs: its graphs, demand, rule and flight parameters.
fn heading(exp: &Experiment<Bench>, graphs: &[GraphName], args: &BenchArgs) -> anyhow::Result<()> {
    let total = exp.runs();
    println!(
        "muse bench: {} graph(s) × {} demand level(s) = {total} cases, each in its own process",
        graphs.len(),
        exp.grid.counts.len()
    );
    for g in graphs {
        let graph = load_graph(g)?;
        let zones: Vec<&str> = graph.zones.iter().map(|z| z.id.as_str()).collect();
        println!(
            "  graph     {g}: {} nodes, {} stations, {} corridors, {}",
            grouped(graph.airspace.node_count()),
            grouped(graph.airspace.stations().count()),
            grouped(graph.airspace.edge_count()),
            if zones.is_empty() {
                "no zones".to_owned()
            } else {
                format!("zones {}", zones.join(", "))
            }
        );
    }
    let (from, to) = WINDOW_HOURS;
    println!(
        "  demand    {} requests a day, seed {}, departures uniform {from:02}:00–{to:02}:00",
        exp.grid
            .counts
            .iter()
            .map(|&n| grouped(n))
            .collect::<Vec<_>>()
            .join(" / "),
        args.seed
    );
    println!("  OD rule   {}", od_description(args.od));
    let params = &exp.grid.params;
    let edges = match params.edge_rule {
        EdgeRule::Exclusive => "exclusive edges".to_owned(),
        EdgeRule::Headway(h) => format!("edge headway {} s", h.as_secs_f64()),
    };
    println!(
        "  flight    {} km/h, battery {} min, node separation {} s, {edges}, ground delay up to {} s",
        args.flight.range.speed_kmh,
        args.flight.range.max_flight_min,
        params.node_separation.as_secs_f64(),
        params.max_ground_delay.as_secs_f64()
    );
    Ok(())
}

/// Runs the benchmark `args` describe; `study` is the study it came from, if any.
fn run_bench(args: &BenchArgs, study: Option<&Study>) -> anyhow::Result<ExitCode> {
    let (exp, graphs) = experiment(args)?;
    let inputs = match study {
        Some(s) => output::Inputs::new().add("--study", &s.path),
        None => output::Inputs::new(),
    };
    let out = output::folder("--out", &args.out, &inputs)?;
    heading(&exp, &graphs, args)?;
    let total = exp.runs();
    let started = std::time::Instant::now();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let runs = exp.run(Shard::WHOLE, &|p| match p {
        Progress::Started { case, count, .. } => {
            let i = done.load(std::sync::atomic::Ordering::Relaxed) + 1;
            println!("[{i}/{total}] {}, {} requests: running…", graphs[case], grouped(count));
            let _ = std::io::stdout().flush();
        }
        Progress::Finished { record: m, .. } => {
            let i = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            let r = &m.result;
            println!(
                "[{i}/{total}] {}, {} requests: done in {:.1} s — planner {:.3} s, {:.2} µs and {:.2} expanded labels per request, {:.1}% planned, peak {} MiB",
                r.graph,
                grouped(r.requests),
                m.wall_s,
                r.planner_s,
                r.us_per_request(),
                r.expanded_per_request(),
                100.0 * r.planned as f64 / r.requests.max(1) as f64,
                mib(r.peak_rss_bytes)
            );
        }
    })?;
    let wall = started.elapsed();
    let cases: Vec<_> = runs.into_iter().map(|(_, m)| m).collect();
    let results = exp.results(&cases)?;
    for (name, text) in &results.files {
        write_atomically(&out.path().join(name), text)?;
    }
    out.commit()?;
    println!();
    print!("{}", results.table);
    let names: Vec<&str> = results.files.iter().map(|(n, _)| n.as_str()).collect();
    println!(
        "done in {:.1} s wall; wrote {}/{{{}}}",
        wall.as_secs_f64(),
        args.out.display(),
        names.join(", ")
    );
    report(
        study.map(Study::reference).as_ref(),
        &args.out,
        &results,
        &exp,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_lists() {
        assert_eq!(
            parse_requests("10000,100000,1000000").unwrap(),
            vec![10_000, 100_000, 1_000_000]
        );
        assert_eq!(
            parse_requests(" 1M, 10k ,100_000").unwrap(),
            vec![10_000, 100_000, 1_000_000]
        );
        assert_eq!(parse_requests("200").unwrap(), vec![200]);
        for (bad, message) in [
            ("", "`` is not a count of requests from 1 to 10000000"),
            ("0", "`0` is not a count of requests from 1 to 10000000"),
            ("10,,20", "`` is not a count of requests from 1 to 10000000"),
            ("-5", "`-5` is not a count of requests from 1 to 10000000"),
            ("ten", "`ten` is not a count of requests from 1 to 10000000"),
            (
                "1.5k",
                "`1.5k` is not a count of requests from 1 to 10000000",
            ),
            (
                "99999999999999999999",
                "is not a count of requests from 1 to 10000000",
            ),
            ("11M", "`11M` is not a count of requests from 1 to 10000000"),
            ("10k,10000", "10000 is named twice"),
        ] {
            let err = parse_requests(bad).unwrap_err().to_string();
            assert!(
                err.contains(message) && err.starts_with("--requests"),
                "{bad}: {err}"
            );
        }
    }

    #[test]
    fn flight_options_reach_the_case_process() {
        use clap::Parser as _;
        #[derive(clap::Parser)]
        struct Wrapper {
            #[command(flatten)]
            flight: FlightArgs,
        }
        let given = Wrapper::parse_from([
            "x",
            "--speed-kmh",
            "42.5",
            "--edge-rule",
            "headway",
            "--headway-s",
            "2.25",
            "--max-ground-delay-s",
            "600",
        ]);
        let flags = flight_flags(&given.flight);
        assert!(
            flags.contains(&"--edge-rule=headway".to_owned()),
            "{flags:?}"
        );
        let again = Wrapper::parse_from(std::iter::once("x".to_owned()).chain(flags));
        assert_eq!(
            again.flight.params().unwrap(),
            given.flight.params().unwrap()
        );
        let default = Wrapper::parse_from(["x"]);
        assert!(
            !flight_flags(&default.flight)
                .iter()
                .any(|f| f.starts_with("--headway-s"))
        );
    }
}
