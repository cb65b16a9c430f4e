//! The plots of an announcement-lead sweep against the lead: the success rate (with the zones
//! known from the start and never announced as flat references), what the announcement did to
//! booked flights, and the extra delay of the replanned ones.

use muse_model::Millis;
use muse_render::{PlotOptions, Point, Series};

use super::case::LeadCase;
use super::record::LeadRecord;
use super::report::metric::{
    AFFECTED, CANCELLED, CONTINGENCY, DIVERTED, EXTRA_DELAY, REPLANNED, SUCCESS,
};
use crate::experiment::grid::Grid;
use crate::experiment::report::{Group, Plot};
use crate::stats::MeanCi;

type G = Group<LeadRecord>;

/// What values a metric can take: the plotted confidence band is cut to them.
#[derive(Clone, Copy)]
enum Range {
    /// A share, in `[0, 1]`.
    Share,
    /// A count, at least 0.
    Count,
    /// Any value (a delay may be negative).
    Any,
}

/// A summary metric and its range.
type Metric = (&'static str, Range);

/// A plotted mean and its 95% CI, cut to the metric's range.
fn point(x: f64, m: MeanCi, range: Range) -> Point {
    let (lo, hi) = match range {
        Range::Share => (0.0, 1.0),
        Range::Count => (0.0, f64::INFINITY),
        Range::Any => (f64::NEG_INFINITY, f64::INFINITY),
    };
    Point {
        x,
        mean: m.mean,
        ci_low: m.low().max(lo).min(m.mean),
        ci_high: m.high().min(hi).max(m.mean),
    }
}

/// The grid's counts and the sweep's leads, what the series are drawn over.
struct Axes<'a> {
    counts: &'a [usize],
    leads: &'a [Millis],
}

impl Axes<'_> {
    /// `what`, or `what, N requests` when the sweep has several counts.
    fn named(&self, what: &str, count: usize) -> String {
        if self.counts.len() == 1 {
            what.to_owned()
        } else {
            format!("{what}, {count} requests")
        }
    }

    /// One series per count over the leads (groups with `keep` only), named `name(count)`;
    /// counts without such groups are left out.
    fn by_lead(
        &self,
        groups: &[G],
        name: &dyn Fn(usize) -> String,
        (metric, range): Metric,
        keep: fn(&G) -> bool,
    ) -> Vec<Series> {
        self.counts
            .iter()
            .map(|&count| Series {
                name: name(count),
                points: groups
                    .iter()
                    .filter(|g| g.count == count && keep(g))
                    .filter_map(|g| Some(point(g.first.case.lead_min()?, g.metric(metric), range)))
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    }

    /// Per count, a flat series at a reference case's value across the leads.
    fn reference(
        &self,
        groups: &[G],
        case: LeadCase,
        what: &str,
        (metric, range): Metric,
    ) -> Vec<Series> {
        let xs: Vec<f64> = self.leads.iter().map(|l| l.as_secs_f64() / 60.0).collect();
        let (Some(&lo), Some(&hi)) = (xs.first(), xs.last()) else {
            return Vec::new();
        };
        self.counts
            .iter()
            .filter_map(|&count| {
                let g = groups
                    .iter()
                    .find(|g| g.first.case == case && g.count == count)?;
                let m = g.metric(metric);
                Some(Series {
                    name: self.named(what, count),
                    points: vec![point(lo, m, range), point(hi, m, range)],
                })
            })
            .collect()
    }

    /// The success plot: per count, the success rate over the leads, with the `known` and
    /// `none` references.
    fn success(&self, groups: &[G]) -> Vec<Series> {
        let success: Metric = (SUCCESS, Range::Share);
        let mut s = self.by_lead(groups, &|c| self.named("announced", c), success, |_| true);
        s.extend(self.reference(groups, LeadCase::Known, "known from the start", success));
        s.extend(self.reference(groups, LeadCase::NoZone, "never announced", success));
        s
    }

    /// The outcomes plot: with one count, affected, replanned, diverted, cancelled and
    /// contingency flights per run; with several, affected and cancelled per count.
    fn outcomes(&self, groups: &[G]) -> Vec<Series> {
        let all: [(&str, Metric); 5] = [
            ("affected", (AFFECTED, Range::Count)),
            ("replanned", (REPLANNED, Range::Count)),
            ("diverted", (DIVERTED, Range::Count)),
            ("cancelled", (CANCELLED, Range::Count)),
            ("contingency", (CONTINGENCY, Range::Count)),
        ];
        let metrics = if self.counts.len() == 1 {
            &all[..]
        } else {
            &[all[0], all[3]][..]
        };
        metrics
            .iter()
            .flat_map(|&(what, metric)| {
                self.by_lead(groups, &|c| self.named(what, c), metric, |_| true)
            })
            .collect()
    }

    /// The extra-delay plot, per count, over the leads where some run replanned a flight
    /// (all leads, at zero, if none did), and its footnote's last lines.
    fn delay(&self, groups: &[G]) -> (Vec<Series>, &'static str) {
        let extra: Metric = (EXTRA_DELAY, Range::Any);
        let name = |count| format!("{count} requests");
        let delay = self.by_lead(groups, &name, extra, |g| g.metric(EXTRA_DELAY).n > 0);
        if delay.is_empty() {
            return (
                self.by_lead(groups, &name, extra, |_| true),
                "No flight was replanned in any run.",
            );
        }
        (
            delay,
            "Per run, the mean over its replanned flights; a point averages the runs that replanned any\n(leads where none did are left out). Bands: 95% confidence interval of the mean.",
        )
    }
}

/// `announce_lead_success.svg`, `announce_lead_outcomes.svg` and
/// `announce_lead_extra_delay.svg`; `booked` says how requests were booked, `zones` which
/// zones were announced (with their first windows).
pub fn plots(
    grid: &Grid,
    leads: &[Millis],
    groups: &[G],
    booked: &str,
    zones: &[String],
) -> Vec<Plot> {
    let axes = Axes {
        counts: &grid.counts,
        leads,
    };
    let (first, last) = grid.seed_range();
    let foot = format!(
        "{} runs per point (seeds {first}…{last}), requests {booked}.\nAnnounced: {}.",
        grid.reps,
        zones.join(", ")
    );
    let (delay, delay_note) = axes.delay(groups);
    [
        (
            "announce_lead_success.svg",
            "Share of requests delivered, by announcement lead",
            "Success rate (delivered / requests)",
            axes.success(groups),
            "Flat lines: the zone known from the start, and never announced, on the same seeds.\nBands: 95% confidence interval of the mean.",
        ),
        (
            "announce_lead_outcomes.svg",
            "What the announcement did to booked flights",
            "Flights per day",
            axes.outcomes(groups),
            "A flight hit by several announcements counts once, by its final outcome.\nBands: 95% confidence interval of the mean, cut at zero.",
        ),
        (
            "announce_lead_extra_delay.svg",
            "Extra delay of replanned flights",
            "Final minus first planned landing (s)",
            delay,
            delay_note,
        ),
    ]
    .into_iter()
    .map(|(file, title, y_label, series, note)| {
        let percent = file == "announce_lead_success.svg";
        Plot {
            file,
            options: PlotOptions {
                title: title.to_owned(),
                x_label: "Announcement lead before the zone's first window (min)".to_owned(),
                y_label: y_label.to_owned(),
                y_from_zero: !percent,
                y_percent: percent,
                footnote: format!("{foot}\n{note}"),
                ..PlotOptions::default()
            },
            series,
        }
    })
    .collect()
}
