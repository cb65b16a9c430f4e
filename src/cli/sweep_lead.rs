//! `muse sweep --vary announce-lead`: the regulator's question (issue 9) — how much warning
//! before a temporary no-fly zone becomes active keeps the cost of announcing it low? Leads ×
//! counts × repetitions, each day replayed (SPEC §11) on the same seeds for every lead, with
//! the zone known from the start and never announced as references.

use std::process::ExitCode;

use anyhow::Context as _;
use muse_model::{Instant, Millis, Zone};
use muse_render::{PlotOptions, Point, Series, render_line_plot};
use muse_sim::demand::BookingLead;
use muse_sim::lead::{
    Day, LeadCase, LeadRecord, LeadSummaryRow, LeadSweepSpec, run_lead_sweep_shard, runs_csv,
    summarize, summary_csv,
};
use muse_sim::shard::Shard;
use muse_sim::stats::MeanCi;

use super::common::{World, write_atomically};
use super::demand::BookingLeadArg;
use super::output::OutFolder;
use super::ranges::{MAX_LEAD_MIN, MAX_LIST};
use super::study::Study;
use super::sweep::{SweepArgs, check_days, parse_counts, runs_bar};

/// The leads compared unless `--leads` is given, minutes.
const DEFAULT_LEADS: &str = "0,15,30,60,120";

/// Bookings made up to two hours ahead, unless `--booking-lead-min` is given.
const DEFAULT_BOOKING_MIN: f64 = 120.0;

/// The summary file, the one a study's published results are compared on.
pub const SUMMARY_FILE: &str = "announce_lead_summary.csv";

/// The files written, in the output folder.
const FILES: [&str; 5] = [
    "announce_lead.csv",
    "announce_lead_summary.csv",
    "announce_lead_success.svg",
    "announce_lead_outcomes.svg",
    "announce_lead_extra_delay.svg",
];

/// Parses `--leads`: at most [`MAX_LIST`] comma-separated minutes from 0 to
/// [`MAX_LEAD_MIN`], sorted, duplicates dropped.
fn parse_leads(text: &str) -> anyhow::Result<Vec<Millis>> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() > MAX_LIST {
        anyhow::bail!(
            "--leads: {} leads, more than the {MAX_LIST} a sweep compares",
            parts.len()
        );
    }
    let mut leads = Vec::new();
    for part in parts {
        let m: f64 = part.trim().parse().map_err(|_| {
            anyhow::anyhow!(
                "--leads `{text}`: `{}` is not a number of minutes from 0 to {MAX_LEAD_MIN}; \
                 expected e.g. 0,15,30,60,120",
                part.trim()
            )
        })?;
        if !(0.0..=MAX_LEAD_MIN).contains(&m) {
            anyhow::bail!(
                "--leads `{text}`: {m} minutes: a lead must be a number of minutes from 0 to \
                 {MAX_LEAD_MIN}"
            );
        }
        leads.push(Millis::from_secs_f64(m * 60.0)?);
    }
    leads.sort_unstable();
    leads.dedup();
    Ok(leads)
}

/// The base zones (known from the start) and the zones to announce: every zone of the
/// `--announce-zones` files, or the built-in scenario's CBD zone; a base zone with the id of
/// a zone to announce is dropped from the base.
fn split_zones(
    world: &World,
    files: &[std::path::PathBuf],
) -> anyhow::Result<(Vec<Zone>, Vec<Zone>)> {
    let mut announce = Vec::new();
    for path in files {
        announce.extend(
            muse_formats::zones::read_zones_file(path)
                .with_context(|| format!("reading zones to announce from {}", path.display()))?,
        );
    }
    if files.is_empty() {
        let cbd = world
            .scenario
            .and_then(|s| s.zones.iter().find(|z| z.id == muse_scenario::CBD_ZONE_ID));
        let Some(cbd) = cbd else {
            anyhow::bail!(
                "--vary announce-lead needs a zone to announce: a built-in scenario's CBD zone (the default) or --announce-zones FILE"
            );
        };
        announce.push(cbd.clone());
    }
    if announce.is_empty() {
        anyhow::bail!("--announce-zones: the files hold no zone");
    }
    if let Some(z) = announce.iter().find(|z| z.withdrawn.is_some()) {
        anyhow::bail!(
            "--announce-zones: zone `{}` was withdrawn (`withdrawn`): a sweep announces zones, \
             it never withdraws them; leave the withdrawal out",
            z.id
        );
    }
    let base = world
        .zones
        .iter()
        .filter(|z| !announce.iter().any(|a| a.id == z.id))
        .cloned()
        .collect();
    Ok((base, announce))
}

/// The sweep the arguments describe, and the booking note for messages.
fn spec(args: &SweepArgs, world: &World) -> anyhow::Result<(LeadSweepSpec, String)> {
    let counts = parse_counts(&args.counts)?;
    check_days(counts.len(), args.reps)?;
    let leads = parse_leads(args.leads.as_deref().unwrap_or(DEFAULT_LEADS))?;
    let (base_zones, announce) = split_zones(world, &args.announce_zones)?;
    let mut demand = args.demand.clone();
    let default_booking = demand.booking_lead_min.is_none();
    if default_booking {
        let max = Millis::from_secs_f64(DEFAULT_BOOKING_MIN * 60.0)?;
        demand.booking_lead_min = Some(BookingLeadArg {
            from_min: 0.0,
            to_min: DEFAULT_BOOKING_MIN,
            lead: BookingLead::new(Millis::ZERO, max)?,
        });
    }
    let booked = match (demand.booking_note(), default_booking) {
        (None, _) => "booked at departure".to_owned(),
        (Some(b), false) => b,
        (Some(b), true) => format!("{b} (this sweep's default)"),
    };
    let d = demand.spec(world, args.flight.range)?;
    let day_start = Instant::at_local(world.date, Millis::ZERO, world.offset);
    let spec = LeadSweepSpec {
        leads,
        counts,
        reps: args.reps,
        base_seed: d.seed,
        start: d.start,
        end: d.end,
        od: d.od,
        booking_lead: d.booking_lead,
        params: args.flight.params()?,
        base_zones,
        announce,
        day: Day {
            start: day_start,
            end: day_start + Millis::from_secs(86_400),
            offset: world.offset,
        },
        no_zone_reference: true,
    };
    Ok((spec, booked))
}

/// An announcement-lead sweep ready to run: its world, spec and the descriptions its
/// messages and plots use.
pub struct LeadSweep {
    /// The world it runs on.
    pub world: World,
    /// What it runs.
    pub spec: LeadSweepSpec,
    /// How requests are booked, for messages.
    pub booked: String,
    /// The zones announced, with their first windows, for messages.
    pub zones: Vec<String>,
}

impl LeadSweep {
    /// The sweep `args` describe.
    pub fn of(args: &SweepArgs) -> anyhow::Result<LeadSweep> {
        let world = args.world.load()?;
        world.refuse_withdrawn("sweep")?;
        let (spec, booked) = spec(args, &world)?;
        let lead_world = spec
            .world(&world.airspace)
            .with_context(|| format!("on the scenario's day {}", world.date))?;
        let zones = lead_world
            .first_windows()
            .map(|(id, t)| format!("{id} (first window {})", clock(spec.day, t)))
            .collect();
        Ok(LeadSweep {
            world,
            spec,
            booked,
            zones,
        })
    }

    /// Runs the runs of `shard`, with their run numbers; `tick` once per finished run.
    pub fn run(
        &self,
        shard: Shard,
        tick: &(dyn Fn() + Sync),
    ) -> anyhow::Result<Vec<(usize, LeadRecord)>> {
        let lead_world = self.spec.world(&self.world.airspace)?;
        Ok(run_lead_sweep_shard(&lead_world, &self.spec, shard, tick)?)
    }

    /// Writes the CSV files and plots of `records` (the whole sweep, in run order) into `out`
    /// (the folder `shown`) and prints the table.
    pub fn write_results(
        &self,
        records: &[LeadRecord],
        out: OutFolder,
        shown: &std::path::Path,
    ) -> anyhow::Result<()> {
        let rows = summarize(records);
        write_atomically(&out.path().join(FILES[0]), &runs_csv(records))?;
        write_atomically(&out.path().join(SUMMARY_FILE), &summary_csv(&rows))?;
        let foot = footnote(&self.spec, &self.booked, &self.zones);
        write_plots(&self.spec, &rows, &foot, out.path())?;
        out.commit()?;
        println!("wrote {}/{{{}}}", shown.display(), FILES.join(", "));
        print_table(&rows);
        Ok(())
    }
}

/// Runs `muse sweep --vary announce-lead` (threads already set up).
pub fn run(args: &SweepArgs, study: Option<&Study>, out: OutFolder) -> anyhow::Result<ExitCode> {
    let sweep = LeadSweep::of(args)?;
    let spec = &sweep.spec;
    let leads: Vec<String> = spec
        .cases()
        .iter()
        .filter_map(|c| c.lead_min())
        .map(|m| m.to_string())
        .collect();
    println!(
        "sweep --vary announce-lead: {} announced {} min ahead, plus known from the start and never announced",
        sweep.zones.join(", "),
        leads.join(", "),
    );
    println!(
        "{} cases × {} counts × {} repetitions = {} runs, {} requests {}, {} threads",
        spec.cases().len(),
        spec.counts.len(),
        spec.reps,
        spec.runs(),
        spec.total_requests(),
        sweep.booked,
        rayon::current_num_threads()
    );
    let bar = runs_bar(spec.runs());
    let started = std::time::Instant::now();
    let records: Vec<LeadRecord> = sweep
        .run(Shard::WHOLE, &|| bar.inc(1))?
        .into_iter()
        .map(|(_, r)| r)
        .collect();
    bar.finish_and_clear();
    println!("done in {:.1} s wall", started.elapsed().as_secs_f64());
    sweep.write_results(&records, out, &args.out)?;
    super::study::report_reproduction(
        study.map(Study::reference).as_ref(),
        &args.out,
        SUMMARY_FILE,
        super::study::sweep_time_column,
    )
}

/// `t` as a local clock time `HH:MM` of `day` (`+1d` past its end).
fn clock(day: Day, t: Instant) -> String {
    let mins = (t - day.start).0.div_euclid(60_000);
    let (d, m) = (mins.div_euclid(1_440), mins.rem_euclid(1_440));
    let extra = if d == 0 {
        String::new()
    } else {
        format!(" {d:+}d")
    };
    format!("{:02}:{:02}{extra}", m / 60, m % 60)
}

/// The first lines of every plot's footnote: runs, seeds, bookings and zones.
fn footnote(spec: &LeadSweepSpec, booked: &str, zones: &[String]) -> String {
    format!(
        "{} runs per point (seeds {}…{}), requests {booked}.\nAnnounced: {}.",
        spec.reps,
        spec.base_seed,
        spec.base_seed + (spec.counts.len() * spec.reps) as u64 - 1,
        zones.join(", ")
    )
}

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
type Metric = (fn(&LeadSummaryRow) -> MeanCi, Range);

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

/// `what`, or `what, N requests` when the sweep has several counts.
fn named(spec: &LeadSweepSpec, what: &str, count: usize) -> String {
    if spec.counts.len() == 1 {
        what.to_owned()
    } else {
        format!("{what}, {count} requests")
    }
}

/// One series per count over the leads (rows with `keep` only), named `name(count)`; counts
/// without such rows are left out.
fn by_lead(
    spec: &LeadSweepSpec,
    rows: &[LeadSummaryRow],
    name: &dyn Fn(usize) -> String,
    (metric, range): Metric,
    keep: fn(&LeadSummaryRow) -> bool,
) -> Vec<Series> {
    spec.counts
        .iter()
        .map(|&count| Series {
            name: name(count),
            points: rows
                .iter()
                .filter(|r| r.count == count && keep(r))
                .filter_map(|r| Some(point(r.case.lead_min()?, metric(r), range)))
                .collect(),
        })
        .filter(|s| !s.points.is_empty())
        .collect()
}

/// Per count, a flat series at a reference case's value across the leads.
fn reference(
    spec: &LeadSweepSpec,
    rows: &[LeadSummaryRow],
    case: LeadCase,
    what: &str,
    (metric, range): Metric,
) -> Vec<Series> {
    let xs: Vec<f64> = spec.leads.iter().map(|l| l.as_secs_f64() / 60.0).collect();
    let (lo, hi) = (xs[0], xs[xs.len() - 1]);
    spec.counts
        .iter()
        .filter_map(|&count| {
            let m = metric(rows.iter().find(|r| r.case == case && r.count == count)?);
            Some(Series {
                name: named(spec, what, count),
                points: vec![point(lo, m, range), point(hi, m, range)],
            })
        })
        .collect()
}

/// The success plot: per count, the success rate over the leads, with the `known` and
/// `none` references.
fn success_series(spec: &LeadSweepSpec, rows: &[LeadSummaryRow]) -> Vec<Series> {
    let success: Metric = (|r| r.success_rate, Range::Share);
    let mut s = by_lead(
        spec,
        rows,
        &|c| named(spec, "announced", c),
        success,
        |_| true,
    );
    s.extend(reference(
        spec,
        rows,
        LeadCase::Known,
        "known from the start",
        success,
    ));
    s.extend(reference(
        spec,
        rows,
        LeadCase::NoZone,
        "never announced",
        success,
    ));
    s
}

/// The outcomes plot: with one count, affected, replanned, diverted, cancelled and
/// contingency flights per run; with several, affected and cancelled per count.
fn outcome_series(spec: &LeadSweepSpec, rows: &[LeadSummaryRow]) -> Vec<Series> {
    let all: [(&str, Metric); 5] = [
        ("affected", (|r| r.affected, Range::Count)),
        ("replanned", (|r| r.replanned, Range::Count)),
        ("diverted", (|r| r.diverted, Range::Count)),
        ("cancelled", (|r| r.cancelled, Range::Count)),
        ("contingency", (|r| r.contingency, Range::Count)),
    ];
    let metrics = if spec.counts.len() == 1 {
        &all[..]
    } else {
        &[all[0], all[3]][..]
    };
    metrics
        .iter()
        .flat_map(|&(what, metric)| {
            by_lead(spec, rows, &|c| named(spec, what, c), metric, |_| true)
        })
        .collect()
}

/// The extra-delay plot, per count, over the leads where some run replanned a flight (all
/// leads, at zero, if none did), and its footnote's last lines.
fn delay_series(spec: &LeadSweepSpec, rows: &[LeadSummaryRow]) -> (Vec<Series>, &'static str) {
    let extra: Metric = (|r| r.extra_delay_s, Range::Any);
    let name = |count| format!("{count} requests");
    let delay = by_lead(spec, rows, &name, extra, |r| r.extra_delay_s.n > 0);
    if delay.is_empty() {
        return (
            by_lead(spec, rows, &name, extra, |_| true),
            "No flight was replanned in any run.",
        );
    }
    (
        delay,
        "Per run, the mean over its replanned flights; a point averages the runs that replanned any\n(leads where none did are left out). Bands: 95% confidence interval of the mean.",
    )
}

fn write_plots(
    spec: &LeadSweepSpec,
    rows: &[LeadSummaryRow],
    foot: &str,
    out: &std::path::Path,
) -> anyhow::Result<()> {
    let (delay, delay_note) = delay_series(spec, rows);
    let plots = [
        (
            FILES[2],
            "Share of requests delivered, by announcement lead",
            "Success rate (delivered / requests)",
            success_series(spec, rows),
            "Flat lines: the zone known from the start, and never announced, on the same seeds.\nBands: 95% confidence interval of the mean.",
        ),
        (
            FILES[3],
            "What the announcement did to booked flights",
            "Flights per day",
            outcome_series(spec, rows),
            "A flight hit by several announcements counts once, by its final outcome.\nBands: 95% confidence interval of the mean, cut at zero.",
        ),
        (
            FILES[4],
            "Extra delay of replanned flights",
            "Final minus first planned landing (s)",
            delay,
            delay_note,
        ),
    ];
    for (file, title, y_label, series, note) in plots {
        let percent = file == FILES[2];
        let opts = PlotOptions {
            title: title.to_owned(),
            x_label: "Announcement lead before the zone's first window (min)".to_owned(),
            y_label: y_label.to_owned(),
            y_from_zero: !percent,
            y_percent: percent,
            footnote: format!("{foot}\n{note}"),
            ..PlotOptions::default()
        };
        let svg = render_line_plot(&series, &opts).with_context(|| format!("drawing {file}"))?;
        write_atomically(&out.join(file), &svg)?;
    }
    Ok(())
}

/// Prints means per run; `±` is the half-width of the 95% confidence interval.
fn print_table(rows: &[LeadSummaryRow]) {
    println!(
        "means per run (± 95% CI); extra delay: of replanned flights, over the runs that replanned any"
    );
    println!(
        "{:>8} {:>7} {:>15} {:>9} {:>9} {:>9} {:>9} {:>11} {:>15}",
        "lead min",
        "count",
        "success %",
        "affected",
        "replanned",
        "diverted",
        "cancelled",
        "contingency",
        "extra delay s"
    );
    for r in rows {
        let ci = |m: MeanCi, scale: f64, prec: usize| {
            format!(
                "{:.prec$} ± {:.prec$}",
                m.mean * scale,
                m.half_width * scale
            )
        };
        let extra = if r.extra_delay_s.n == 0 {
            "-".to_owned()
        } else {
            ci(r.extra_delay_s, 1.0, 1)
        };
        println!(
            "{:>8} {:>7} {:>15} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>11.2} {:>15}",
            r.case.label(),
            r.count,
            ci(r.success_rate, 100.0, 2),
            r.affected.mean,
            r.replanned.mean,
            r.diverted.mean,
            r.cancelled.mean,
            r.contingency.mean,
            extra
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leads() {
        assert_eq!(
            parse_leads("60, 0,15,0").unwrap(),
            [0, 15, 60].map(Millis::from_mins)
        );
        assert_eq!(parse_leads("0.5").unwrap(), [Millis::from_secs(30)]);
        for (bad, message) in [
            ("", "`` is not a number of minutes"),
            ("10,soon", "`soon` is not a number of minutes"),
            (
                "-5",
                "-5 minutes: a lead must be a number of minutes from 0 to 43200",
            ),
            ("inf", "a lead must be a number of minutes from 0 to 43200"),
        ] {
            let e = parse_leads(bad).unwrap_err().to_string();
            assert!(e.contains(message), "{bad}: {e}");
        }
    }

    #[test]
    fn clock_times_of_the_day() {
        let day = Day {
            start: Instant(0),
            end: Instant(86_400_000),
            offset: muse_model::UtcOffset(0),
        };
        assert_eq!(clock(day, Instant(600 * 60_000)), "10:00");
        assert_eq!(clock(day, Instant(-30 * 60_000)), "23:30 -1d");
    }
}
