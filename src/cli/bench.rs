//! `muse bench`: how planning scales with demand and graph size.
//!
//! Each case (one graph, one demand level) runs in its own process — this executable again,
//! with the hidden `bench-case` subcommand — so that its peak memory is its own. The case
//! process loads the graph, generates the demand, plans the day (only the planning loop is
//! timed), reads its peak resident memory and prints one JSON line; `muse bench` collects the
//! lines, prints a table with the growth exponents and writes `bench.csv` and three plots.

use std::borrow::Cow;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use anyhow::Context as _;
use clap::{Args, ValueEnum as _};
use muse_model::{Airspace, EdgeRule, Instant, Millis, RejectReason, UtcOffset, Zone};
use muse_sim::bench::{
    CaseResult, Exponents, Measured, bench_csv, bench_table, current_rss_bytes, grouped, mib,
    peak_rss_bytes,
};
use muse_sim::day::plan_requests;
use muse_sim::demand::{BookingLead, DemandSpec, OdRule, generate};

use super::common::{FlightArgs, write_atomically};
use super::demand::OdArg;
use super::output;
use super::progress::LazyProgress;
use super::ranges::{self, MAX_REQUESTS};
use super::study::{Study, report_reproduction};

mod plots;
#[cfg(test)]
use plots::series_by_graph;
use plots::write_plots;

/// Synthetic graphs of `--graphs synthetic-N`: geometric layout, this share of stations,
/// this spacing and seed.
const SYNTHETIC_STATION_SHARE: f64 = 0.1;
const SYNTHETIC_SPACING_M: f64 = 1_500.0;
const SYNTHETIC_SEED: u64 = 1;
/// The smallest synthetic graph: 10% of it must give at least two stations.
const SYNTHETIC_MIN_NODES: usize = 20;
/// The largest synthetic graph the generator builds.
const SYNTHETIC_MAX_NODES: usize = muse_scenario::synthetic::MAX_NODES;
/// Bytes in a mebibyte.
const MIB: f64 = 1024.0 * 1024.0;
/// Departure window, local time on the scenario's date.
const FROM_H: i64 = 8;
const TO_H: i64 = 20;

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

/// A graph named on the command line.
#[derive(Clone, Debug, PartialEq, Eq)]
enum GraphName {
    /// A built-in scenario, e.g. `singapore-77`.
    Scenario(String),
    /// `synthetic-N`.
    Synthetic(usize),
}

impl std::fmt::Display for GraphName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GraphName::Scenario(name) => f.write_str(name),
            GraphName::Synthetic(n) => write!(f, "synthetic-{n}"),
        }
    }
}

/// A loaded graph with its zones and the day planned on.
struct Graph {
    airspace: Cow<'static, Airspace>,
    zones: Cow<'static, [Zone]>,
    date: jiff::civil::Date,
    offset: UtcOffset,
}

/// Parses one graph name; built-in scenario names are checked when loading.
fn parse_graph(name: &str) -> anyhow::Result<GraphName> {
    let name = name.trim();
    if let Some(n) = name.strip_prefix("synthetic-") {
        let n: usize = n.replace('_', "").parse().map_err(|_| {
            anyhow::anyhow!("--graphs: `{name}`: expected synthetic-N with N a number of nodes")
        })?;
        if !(SYNTHETIC_MIN_NODES..=SYNTHETIC_MAX_NODES).contains(&n) {
            anyhow::bail!(
                "--graphs: `{name}`: a synthetic graph has {SYNTHETIC_MIN_NODES} to {} nodes",
                grouped(SYNTHETIC_MAX_NODES)
            );
        }
        return Ok(GraphName::Synthetic(n));
    }
    if name.is_empty() {
        anyhow::bail!("--graphs: empty graph name");
    }
    Ok(GraphName::Scenario(name.to_owned()))
}

/// Parses `--graphs`: names separated by commas, each at most once.
fn parse_graphs(text: &str) -> anyhow::Result<Vec<GraphName>> {
    let mut out: Vec<GraphName> = Vec::new();
    for item in text.split(',') {
        let g = parse_graph(item)?;
        if out.contains(&g) {
            anyhow::bail!("--graphs: `{g}` is named twice");
        }
        out.push(g);
    }
    Ok(out)
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

/// Loads a graph: a built-in scenario with its zones, or a synthetic graph without zones
/// (planned on the Singapore default's day).
fn load_graph(name: &GraphName) -> anyhow::Result<Graph> {
    match name {
        GraphName::Scenario(s) => {
            let scenario = muse_scenario::by_name(s).with_context(|| format!("--graphs: `{s}`"))?;
            Ok(Graph {
                airspace: Cow::Borrowed(&scenario.airspace),
                zones: Cow::Borrowed(&scenario.zones),
                date: scenario.date,
                offset: scenario.offset,
            })
        }
        GraphName::Synthetic(n) => {
            use muse_scenario::synthetic::{Layout, SyntheticSpec, synthetic};
            let spec = SyntheticSpec {
                layout: Layout::Geometric,
                nodes: *n,
                spacing_m: SYNTHETIC_SPACING_M,
                station_share: SYNTHETIC_STATION_SHARE,
                seed: SYNTHETIC_SEED,
            };
            let airspace = synthetic(&spec).with_context(|| format!("--graphs: `{name}`"))?;
            let day = muse_scenario::by_name(muse_scenario::SINGAPORE_77)?;
            Ok(Graph {
                airspace: Cow::Owned(airspace),
                zones: Cow::Borrowed(&[]),
                date: day.date,
                offset: day.offset,
            })
        }
    }
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

/// Runs the hidden `muse bench-case`: one case, measured in this process.
pub fn run_case(args: &CaseArgs) -> anyhow::Result<ExitCode> {
    let params = args.flight.params()?;
    let name = parse_graph(&args.graph)?;
    let graph = load_graph(&name)?;
    let at = |h: i64| Instant::at_local(graph.date, Millis::from_mins(h * 60), graph.offset);
    let od = match args.od {
        OdArg::Uniform => OdRule::Uniform,
        OdArg::InRange => OdRule::InRange {
            speed: params.speed,
            max_flight: params.max_flight,
        },
    };
    let spec = DemandSpec {
        count: args.requests,
        start: at(FROM_H),
        end: at(TO_H),
        seed: args.seed,
        od,
        booking_lead: BookingLead::NONE,
    };
    let started = std::time::Instant::now();
    let requests = generate(&graph.airspace, &spec).with_context(|| format!("demand on {name}"))?;
    let demand_s = started.elapsed().as_secs_f64();
    let rss_before_planning_bytes = current_rss_bytes();

    // The bar is checked every 4,096 requests only, to keep it out of the timing.
    let mut progress = LazyProgress::new(args.requests as u64, "planning");
    let run = plan_requests(&graph.airspace, &graph.zones, params, requests, |done| {
        if done % 4_096 == 0 {
            progress.set(done as u64);
        }
    })?;
    progress.finish();

    let mut result = CaseResult {
        graph: name.to_string(),
        nodes: graph.airspace.node_count(),
        stations: graph.airspace.stations().count(),
        edges: graph.airspace.edge_count(),
        zones: graph.zones.iter().map(|z| z.id.clone()).collect(),
        requests: run.requests.len(),
        od: od_name(args.od).to_owned(),
        seed: args.seed,
        planned: 0,
        out_of_range: 0,
        unreachable: 0,
        no_feasible_plan: 0,
        planner_s: run.planner_wall.as_secs_f64(),
        expanded: 0,
        demand_s,
        rss_before_planning_bytes,
        peak_rss_bytes: None,
    };
    for o in &run.outcomes {
        result.expanded += o.expanded;
        match o.result {
            Ok(_) => result.planned += 1,
            Err(RejectReason::OutOfRange) => result.out_of_range += 1,
            Err(RejectReason::Unreachable) => result.unreachable += 1,
            // A day planned in advance has no clock, so it never answers `departure_in_past`.
            Err(RejectReason::NoFeasiblePlan | RejectReason::DepartureInPast) => {
                result.no_feasible_plan += 1;
            }
        }
    }
    // Read while the plans and the schedule are still alive.
    result.peak_rss_bytes = peak_rss_bytes();
    drop(run);
    println!("{}", result.to_json_line());
    Ok(ExitCode::SUCCESS)
}

/// Runs one case in a child process and reads its JSON line.
fn run_child(
    exe: &Path,
    graph: &GraphName,
    requests: usize,
    args: &BenchArgs,
) -> anyhow::Result<CaseResult> {
    let output = Command::new(exe)
        .arg("bench-case")
        .arg(format!("--graph={graph}"))
        .arg(format!("--requests={requests}"))
        .arg(format!("--od={}", od_name(args.od)))
        .arg(format!("--seed={}", args.seed))
        .args(flight_flags(&args.flight))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .output()
        .with_context(|| format!("starting {}", exe.display()))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        anyhow::bail!(
            "case {graph}, {requests} requests failed ({}); its messages are above",
            output.status
        );
    }
    let line = stdout
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .with_context(|| format!("case {graph}, {requests} requests printed nothing"))?;
    CaseResult::from_json_line(line)
        .with_context(|| format!("case {graph}, {requests} requests: reading `{line}`"))
}

/// Runs `muse bench`; `matches` are its own, to tell what was given beside `--study`.
pub fn run(args: &BenchArgs, matches: &clap::ArgMatches) -> anyhow::Result<ExitCode> {
    let Some(path) = &args.study else {
        return run_bench(args, None);
    };
    let study = Study::open::<BenchArgs>(path, "bench", matches)?;
    let out = study.out(matches, &args.out).display().to_string();
    let bench: BenchArgs = study.parse("bench", &["--out".to_owned(), out])?;
    let code = run_bench(&bench, Some(path))?;
    if code != ExitCode::SUCCESS {
        return Ok(code);
    }
    report_reproduction(
        Some(&study.reference()),
        &bench.out,
        "bench.csv",
        measured_column,
    )
}

/// Whether a `bench.csv` column is measured on this machine (time, memory, and the growth
/// exponents fitted to the times); the others — graph, demand, outcomes, labels expanded —
/// are exact.
fn measured_column(name: &str) -> bool {
    !matches!(
        name,
        "graph"
            | "nodes"
            | "stations"
            | "edges"
            | "zones"
            | "requests"
            | "od"
            | "seed"
            | "planned"
            | "out_of_range"
            | "unreachable"
            | "no_feasible_plan"
            | "expanded_per_request"
    )
}

/// Runs the benchmark `args` describe; `study` is the study file it came from, if any.
fn run_bench(args: &BenchArgs, study: Option<&Path>) -> anyhow::Result<ExitCode> {
    let params = args.flight.params()?;
    let levels = parse_requests(&args.requests)?;
    let graphs = parse_graphs(&args.graphs)?;
    let inputs = match study {
        Some(path) => output::Inputs::new().add("--study", path),
        None => output::Inputs::new(),
    };
    let out = output::folder("--out", &args.out, &inputs)?;
    let exe = std::env::current_exe().context("finding the muse executable")?;
    let total = graphs.len() * levels.len();
    println!(
        "muse bench: {} graph(s) × {} demand level(s) = {total} cases, each in its own process",
        graphs.len(),
        levels.len()
    );
    for g in &graphs {
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
    println!(
        "  demand    {} requests a day, seed {}, departures uniform {FROM_H:02}:00–{TO_H:02}:00",
        levels
            .iter()
            .map(|&n| grouped(n))
            .collect::<Vec<_>>()
            .join(" / "),
        args.seed
    );
    println!("  OD rule   {}", od_description(args.od));
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

    let bench_started = std::time::Instant::now();
    let mut cases = Vec::with_capacity(total);
    for g in &graphs {
        for &n in &levels {
            let i = cases.len() + 1;
            println!("[{i}/{total}] {g}, {} requests: running…", grouped(n));
            let _ = std::io::stdout().flush();
            let started = std::time::Instant::now();
            let result = run_child(&exe, g, n, args)?;
            let wall_s = started.elapsed().as_secs_f64();
            println!(
                "[{i}/{total}] {g}, {} requests: done in {wall_s:.1} s — planner {:.3} s, {:.2} µs and {:.2} expanded labels per request, {:.1}% planned, peak {} MiB",
                grouped(n),
                result.planner_s,
                result.us_per_request(),
                result.expanded_per_request(),
                100.0 * result.planned as f64 / result.requests.max(1) as f64,
                mib(result.peak_rss_bytes)
            );
            cases.push(Measured { result, wall_s });
        }
    }
    let wall = bench_started.elapsed();

    let results: Vec<CaseResult> = cases.iter().map(|m| m.result.clone()).collect();
    let exponents = Exponents::of(&results);
    write_atomically(
        &out.path().join("bench.csv"),
        &bench_csv(&cases, &exponents),
    )?;
    let written = write_plots(&cases, args, out.path())?;
    out.commit()?;
    println!();
    print!("{}", bench_table(&cases, &exponents));
    println!(
        "done in {:.1} s wall; wrote {}/{{bench.csv, {}}}",
        wall.as_secs_f64(),
        args.out.display(),
        written.join(", ")
    );
    Ok(ExitCode::SUCCESS)
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
    fn graph_lists() {
        assert_eq!(
            parse_graphs("singapore-77, singapore-all,synthetic-10000").unwrap(),
            vec![
                GraphName::Scenario("singapore-77".into()),
                GraphName::Scenario("singapore-all".into()),
                GraphName::Synthetic(10_000)
            ]
        );
        assert_eq!(GraphName::Synthetic(10_000).to_string(), "synthetic-10000");
        for (bad, message) in [
            ("synthetic-ten", "expected synthetic-N"),
            ("synthetic-", "expected synthetic-N"),
            ("synthetic-5", "a synthetic graph has 20 to 1,000,000 nodes"),
            ("synthetic-2000000", "a synthetic graph has 20"),
            ("singapore-77,,synthetic-100", "empty graph name"),
            ("singapore-77,singapore-77", "`singapore-77` is named twice"),
            (
                "synthetic-100,synthetic-1_00",
                "`synthetic-100` is named twice",
            ),
        ] {
            let err = parse_graphs(bad).unwrap_err().to_string();
            assert!(
                err.contains(message) && err.starts_with("--graphs"),
                "{bad}: {err}"
            );
        }
        // Unknown names are caught when loading, before any case runs.
        let err = load_graph(&parse_graph("atlantis").unwrap()).err().unwrap();
        assert!(format!("{err:#}").contains("`atlantis`"), "{err:#}");
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

    #[test]
    fn series_skip_unknown_values() {
        let case = |graph: &str, requests: usize, peak: Option<u64>| Measured {
            result: CaseResult {
                graph: graph.into(),
                nodes: 10,
                stations: 10,
                edges: 20,
                zones: Vec::new(),
                requests,
                od: "in-range".into(),
                seed: 1,
                planned: requests,
                out_of_range: 0,
                unreachable: 0,
                no_feasible_plan: 0,
                planner_s: 1.0,
                expanded: 2 * requests as u64,
                demand_s: 0.0,
                rss_before_planning_bytes: None,
                peak_rss_bytes: peak,
            },
            wall_s: 1.0,
        };
        let cases = [
            case("a", 100, Some(1 << 20)),
            case("a", 200, None),
            case("b", 100, None),
        ];
        let s = series_by_graph(&cases, |r| r.peak_rss_bytes.map(|b| b as f64));
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].points.len(), 1);
        let s = series_by_graph(&cases, |r| Some(r.expanded_per_request()));
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].points.len(), 2);
        assert!(
            s.iter()
                .flat_map(|s| &s.points)
                .all(|p| (p.mean - 2.0).abs() < 1e-12)
        );
    }
}
