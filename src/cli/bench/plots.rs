//! The plots of `muse bench`: planner time, search effort and peak memory against requests
//! per day, one series per graph.

use std::path::Path;

use anyhow::Context as _;
use muse_render::{PlotOptions, Point, Series, render_line_plot};

use super::{BenchArgs, CaseResult, FROM_H, MIB, Measured, TO_H, od_name};
use crate::cli::common::write_atomically;

/// One series per graph of `metric` against requests; cases where it is unknown are left
/// out, and graphs with no known value too.
pub(super) fn series_by_graph(
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

/// Writes the three plots into `out`; returns the names of the files written (the memory
/// plot is left out where peak memory could not be read).
pub(super) fn write_plots(
    cases: &[Measured],
    args: &BenchArgs,
    out: &Path,
) -> anyhow::Result<Vec<String>> {
    let foot = format!(
        "One run per point: {} OD pairs, seed {}, departures uniform {FROM_H:02}:00–{TO_H:02}:00; \
         planner time is the wall time of the planning loop, one thread.",
        od_name(args.od),
        args.seed
    );
    let plots: [(&str, &str, &str, String, Vec<Series>); 3] = [
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
    let mut written = Vec::new();
    for (file, title, y_label, footnote, series) in plots {
        if series.is_empty() {
            continue;
        }
        let opts = PlotOptions {
            title: title.to_owned(),
            x_label: "Requests per day (log scale)".to_owned(),
            y_label: y_label.to_owned(),
            y_from_zero: true,
            x_log: true,
            footnote,
            ..PlotOptions::default()
        };
        let svg = render_line_plot(&series, &opts).with_context(|| format!("drawing {file}"))?;
        write_atomically(&out.join(file), &svg)?;
        written.push(file.to_owned());
    }
    Ok(written)
}
