//! The paper's sweep as numbers and pictures: `sweep_summary.csv`, the printed table and the
//! three plots (runtime, success rate, air delay against requests per day).

use muse_render::{PlotOptions, Point, Series};

use super::record::RunRecord;
use crate::experiment::grid::Grid;
use crate::experiment::report::{
    Align, Column, Group, Metric, Plot, SummarySpec, TextTable, plus_minus,
};

/// The summary file.
pub const SUMMARY_FILE: &str = "sweep_summary.csv";

const SUCCESS: &str = "success_rate";
const PLANNER_MS: &str = "planner_ms";
const AIR_DELAY: &str = "air_delay_s";
const EXPANDED: &str = "expanded_per_request";

/// `sweep_summary.csv`: per variant and count, the runs, then the mean and 95% CI of the
/// success rate, planner time, air and ground delay, labels expanded per request, rejections
/// for lack of a feasible plan and legs per trip.
pub fn summary() -> SummarySpec<RunRecord> {
    SummarySpec {
        file: SUMMARY_FILE,
        group: |r| (r.variant.clone(), r.count),
        head: vec![
            Column::new("variant", |g: &Group<RunRecord>| g.first.variant.clone()),
            Column::new("count", |g: &Group<RunRecord>| g.count.to_string()),
            Column::new("runs", |g: &Group<RunRecord>| g.runs.to_string()),
        ],
        metrics: vec![
            Metric {
                name: SUCCESS,
                value: |r| Some(r.success_rate),
            },
            Metric {
                name: PLANNER_MS,
                value: |r| Some(r.planner_ms),
            },
            Metric {
                name: AIR_DELAY,
                value: |r| Some(r.mean_air_delay_s),
            },
            Metric {
                name: "ground_delay_s",
                value: |r| Some(r.mean_ground_delay_s),
            },
            Metric {
                name: EXPANDED,
                value: |r| Some(r.expanded_per_request),
            },
            Metric {
                name: "no_feasible_plan",
                value: |r| Some(r.no_feasible_plan as f64),
            },
            Metric {
                name: "legs_per_trip",
                value: |r| Some(r.legs_per_trip),
            },
        ],
    }
}

/// The metrics a sweep that compares separations adds to `sweep_summary.csv`: the closest
/// approach and the pairs closer than 30 m.
pub fn approach_metrics() -> Vec<Metric<RunRecord>> {
    vec![
        Metric {
            name: "closest_m",
            value: |r| r.approach.and_then(|a| a.closest_m),
        },
        Metric {
            name: "pairs_under_30m",
            value: |r| r.approach.map(|a| a.pairs_under_30m as f64),
        },
    ]
}

/// The metrics a sweep with layered variants adds to `sweep_summary.csv`: the share of
/// airborne time spent climbing or descending, and vertical links crossed per flight (none for
/// a flat variant).
pub fn layer_metrics() -> Vec<Metric<RunRecord>> {
    vec![
        Metric {
            name: "climb_share",
            value: |r| r.layer_use.map(|u| u.climb_share),
        },
        Metric {
            name: "vertical_crossings_per_flight",
            value: |r| r.layer_use.map(|u| u.crossings_per_flight),
        },
        Metric {
            name: "busiest_vertical_link_crossings",
            value: |r| r.layer_use.map(|u| u.busiest_link_crossings as f64),
        },
    ]
}

/// The table printed at the end: per variant and count, success rate, planner time and air
/// delay (mean ± half-width of the 95% CI), labels expanded per request; when `layered`, the
/// share of airborne time spent climbing or descending too.
pub fn table(groups: &[Group<RunRecord>], layered: bool, approach: bool) -> String {
    let mut columns = vec![
        ("variant", 28, Align::Left),
        ("count", 7, Align::Right),
        ("success %", 16, Align::Right),
        ("planner ms", 16, Align::Right),
        ("air delay s", 16, Align::Right),
        ("expanded", 10, Align::Right),
    ];
    if layered {
        columns.push(("climbing %", 12, Align::Right));
    }
    if approach {
        columns.push(("closest m", 10, Align::Right));
        columns.push(("pairs < 30 m", 14, Align::Right));
    }
    let mut t = TextTable::new(&columns);
    for g in groups {
        let mut row = vec![
            g.first.variant.clone(),
            g.count.to_string(),
            plus_minus(g.metric(SUCCESS), 100.0, 1),
            plus_minus(g.metric(PLANNER_MS), 1.0, 2),
            plus_minus(g.metric(AIR_DELAY), 1.0, 1),
            format!("{:.2}", g.metric(EXPANDED).mean),
        ];
        if layered {
            let climb = g.metric("climb_share");
            row.push(if climb.n > 0 {
                format!("{:.2}", climb.mean * 100.0)
            } else {
                "–".to_owned()
            });
        }
        if approach {
            let closest = g.metric("closest_m");
            row.push(if closest.n > 0 {
                format!("{:.1}", closest.mean)
            } else {
                "–".to_owned()
            });
            row.push(format!("{:.1}", g.metric("pairs_under_30m").mean));
        }
        t.row(row);
    }
    t.to_string()
}

/// One series per variant (`variants`, in order) of `metric` against requests per day.
fn series(variants: &[String], groups: &[Group<RunRecord>], metric: &str) -> Vec<Series> {
    variants
        .iter()
        .map(|v| Series {
            name: v.clone(),
            points: groups
                .iter()
                .filter(|g| g.first.variant == *v)
                .map(|g| {
                    let m = g.metric(metric);
                    Point {
                        x: g.count as f64,
                        mean: m.mean,
                        ci_low: m.low(),
                        ci_high: m.high(),
                    }
                })
                .collect(),
        })
        .collect()
}

/// `sweep_runtime.svg`, `sweep_success.svg` and `sweep_air_delay.svg`: each metric against
/// requests per day, one line per variant with its 95% band; `booked` says how requests were
/// booked, if ahead of departure.
pub fn plots(
    grid: &Grid,
    variants: &[String],
    groups: &[Group<RunRecord>],
    booked: Option<&str>,
) -> Vec<Plot> {
    let (first, last) = grid.seed_range();
    let foot = format!(
        "{} runs per point (seeds {first}…{last}{}); bands: 95% confidence interval of the mean.",
        grid.reps,
        booked.map_or(String::new(), |b| format!(", requests {b}"))
    );
    [
        (
            "sweep_runtime.svg",
            "Planner runtime for a day of requests",
            "Planner wall time per day (ms)",
            false,
            PLANNER_MS,
        ),
        (
            "sweep_success.svg",
            "Share of requests planned",
            "Success rate",
            true,
            SUCCESS,
        ),
        (
            "sweep_air_delay.svg",
            "Mean air delay of planned flights",
            "Air delay (s)",
            false,
            AIR_DELAY,
        ),
    ]
    .into_iter()
    .map(|(file, title, y_label, percent, metric)| Plot {
        file,
        options: PlotOptions {
            title: title.to_owned(),
            x_label: "Requests per day".to_owned(),
            y_label: y_label.to_owned(),
            y_from_zero: true,
            y_percent: percent,
            footnote: foot.clone(),
            ..PlotOptions::default()
        },
        series: series(variants, groups, metric),
    })
    .collect()
}
