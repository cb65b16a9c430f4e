//! A benchmark as numbers and pictures: `bench.csv` (one row per case, with the growth
//! exponents of its graph and demand level), the printed table and the plots against
//! requests per day, one line per graph.

use std::fmt::Write as _;

use muse_render::{PlotOptions, Point, Series};

use super::fit::{Exponents, PowerFit};
use super::memory::{MIB, mib};
use super::record::{CaseResult, Measured};
use crate::experiment::report::{Align, Column, Plot, TextTable};

/// A count with thousands separators: `1000000` → `1,000,000`.
///
/// ```
/// use muse_sim::experiment::bench::grouped;
/// assert_eq!(grouped(1_234_567), "1,234,567");
/// assert_eq!(grouped(999), "999");
/// ```
pub fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The columns of `bench.csv`, one row per case, with the exponents of its graph and of its
/// demand level fitted to `cases` (all of them).
pub fn columns(cases: &[Measured]) -> Vec<Column<'static, Measured>> {
    type M = Measured;
    let results: Vec<CaseResult> = cases.iter().map(|m| m.result.clone()).collect();
    let exponents = std::rc::Rc::new(Exponents::of(&results));
    let (by_graph, by_level) = (exponents.clone(), exponents);
    let exp =
        |f: Option<PowerFit>| f.map_or_else(|| "n/a".to_owned(), |f| format!("{:.4}", f.exponent));
    vec![
        Column::new("graph", |m: &M| m.result.graph.clone()),
        Column::new("nodes", |m: &M| m.result.nodes.to_string()),
        Column::new("stations", |m: &M| m.result.stations.to_string()),
        Column::new("edges", |m: &M| m.result.edges.to_string()),
        Column::new("zones", |m: &M| m.result.zones.join(" ")),
        Column::new("requests", |m: &M| m.result.requests.to_string()),
        Column::new("od", |m: &M| m.result.od.clone()),
        Column::new("seed", |m: &M| m.result.seed.to_string()),
        Column::new("planned", |m: &M| m.result.planned.to_string()),
        Column::new("out_of_range", |m: &M| m.result.out_of_range.to_string()),
        Column::new("unreachable", |m: &M| m.result.unreachable.to_string()),
        Column::new("no_feasible_plan", |m: &M| {
            m.result.no_feasible_plan.to_string()
        }),
        Column::new("planner_s", |m: &M| format!("{:.6}", m.result.planner_s)),
        Column::new("us_per_request", |m: &M| {
            format!("{:.4}", m.result.us_per_request())
        }),
        Column::new("expanded_per_request", |m: &M| {
            format!("{:.4}", m.result.expanded_per_request())
        }),
        Column::new("peak_rss_mib", |m: &M| mib(m.result.peak_rss_bytes)),
        Column::new("rss_before_planning_mib", |m: &M| {
            mib(m.result.rss_before_planning_bytes)
        }),
        Column::new("demand_s", |m: &M| format!("{:.3}", m.result.demand_s)),
        Column::new("case_wall_s", |m: &M| format!("{:.3}", m.wall_s)),
        Column::new("graph_time_exponent_vs_requests", move |m: &M| {
            exp(by_graph.for_graph(&m.result.graph))
        }),
        Column::new("level_time_per_request_exponent_vs_nodes", move |m: &M| {
            exp(by_level.for_requests(m.result.requests))
        }),
    ]
}

/// Whether a `bench.csv` column is measured on this machine (time, memory, and the growth
/// exponents fitted to the times); the others — graph, demand, outcomes, labels expanded —
/// are exact.
pub fn measured_column(name: &str) -> bool {
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

/// An exponent with two decimals, its R² and points, or why there is none.
fn fit_text(fit: Option<PowerFit>) -> String {
    match fit {
        Some(f) => format!(
            "{:.2} (R² {:.3}, {} points)",
            f.exponent, f.r_squared, f.points
        ),
        None => "n/a (needs two sizes)".to_owned(),
    }
}

/// The table printed at the end of `muse bench`: one row per case, then the exponents.
pub fn table(cases: &[Measured]) -> String {
    let results: Vec<CaseResult> = cases.iter().map(|m| m.result.clone()).collect();
    let exponents = Exponents::of(&results);
    let mut t = TextTable::new(&[
        ("graph", 18, Align::Left),
        ("nodes", 6, Align::Right),
        ("requests", 10, Align::Right),
        ("planned %", 9, Align::Right),
        ("planner s", 9, Align::Right),
        ("µs/request", 10, Align::Right),
        ("expanded/rq", 11, Align::Right),
        ("peak MiB", 10, Align::Right),
        ("demand s", 9, Align::Right),
        ("case s", 8, Align::Right),
    ]);
    for m in cases {
        let r = &m.result;
        let planned = if r.requests == 0 {
            0.0
        } else {
            100.0 * r.planned as f64 / r.requests as f64
        };
        t.row(vec![
            r.graph.clone(),
            grouped(r.nodes),
            grouped(r.requests),
            format!("{planned:.1}"),
            format!("{:.3}", r.planner_s),
            format!("{:.2}", r.us_per_request()),
            format!("{:.2}", r.expanded_per_request()),
            mib(r.peak_rss_bytes),
            format!("{:.2}", r.demand_s),
            format!("{:.1}", m.wall_s),
        ]);
    }
    let mut out = t.to_string();
    let _ = writeln!(
        out,
        "growth exponent of total planner time vs requests (least-squares log-log slope; 1 = linear):"
    );
    for (g, fit) in &exponents.by_graph {
        let _ = writeln!(out, "  {g:<18} {}", fit_text(*fit));
    }
    let _ = writeln!(
        out,
        "growth exponent of planner time per request vs nodes (least-squares log-log slope):"
    );
    for (n, fit) in &exponents.by_requests {
        let level = format!("{} requests", grouped(*n));
        let _ = writeln!(out, "  {level:<18} {}", fit_text(*fit));
    }
    out
}

/// One series per graph of `metric` against requests; cases where it is unknown are left
/// out, and graphs with no known value too.
pub fn series_by_graph(
    cases: &[Measured],
    metric: impl Fn(&CaseResult) -> Option<f64>,
) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    for m in cases {
        let r = &m.result;
        let Some(y) = metric(r) else { continue };
        let p = Point {
            x: r.requests as f64,
            mean: y,
            ci_low: y,
            ci_high: y,
        };
        match out.iter_mut().find(|s| s.name == r.graph) {
            Some(s) => s.points.push(p),
            None => out.push(Series {
                name: r.graph.clone(),
                points: vec![p],
            }),
        }
    }
    out
}

/// The three plots — time per request, labels expanded per request, peak memory — each
/// against requests per day (log scale); a plot with no value (peak memory where it cannot be
/// read) is left out. `foot` says how the demand was made.
pub fn plots(cases: &[Measured], foot: &str) -> Vec<Plot> {
    let foot = format!("{foot}; planner time is the wall time of the planning loop, one thread.");
    let plots: [(&'static str, &str, &str, String, Vec<Series>); 3] = [
        (
            "bench_time_per_request.svg",
            "Planner time per request",
            "Planner wall time per request (µs)",
            foot.clone(),
            series_by_graph(cases, |r| Some(r.us_per_request())),
        ),
        (
            "bench_expanded.svg",
            "Search effort per request",
            "Labels expanded per request",
            foot.clone(),
            series_by_graph(cases, |r| Some(r.expanded_per_request())),
        ),
        (
            "bench_peak_memory.svg",
            "Peak memory of a case",
            "Peak resident memory (MiB)",
            format!(
                "{foot}\nPeak memory: VmHWM of the case's own process (graph, demand, heuristic tables, plans and schedule)."
            ),
            series_by_graph(cases, |r| r.peak_rss_bytes.map(|b| b as f64 / MIB)),
        ),
    ];
    plots
        .into_iter()
        .filter(|p| !p.4.is_empty())
        .map(|(file, title, y_label, footnote, series)| Plot {
            file,
            options: PlotOptions {
                title: title.to_owned(),
                x_label: "Requests per day (log scale)".to_owned(),
                y_label: y_label.to_owned(),
                y_from_zero: true,
                x_log: true,
                footnote,
                ..PlotOptions::default()
            },
            series,
        })
        .collect()
}
