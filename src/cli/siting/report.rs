//! What `muse siting` prints and writes: the greedy's picks, the curves of every method, the
//! plot of the curves and the airspace with the greedy's pads.

use std::path::Path;

use muse_formats::CsvWriter;
use muse_render::{PlotOptions, Point, Series, render_line_plot};
use muse_siting::greedy::GreedyRun;
use muse_siting::{Evaluation, Siting};

use super::Curve;
use crate::cli::output::{self, Inputs, OutFolder};

/// The output folder and its files.
pub struct Files {
    folder: OutFolder,
    shown: String,
}

impl Files {
    /// Checks the output folder before any work (it must not hold an input).
    pub fn new(out: &Path, inputs: &Inputs) -> anyhow::Result<Files> {
        Ok(Files {
            folder: output::folder("--out", out, inputs)?,
            shown: out.display().to_string(),
        })
    }

    /// `DIR/{…}`, for the last line.
    pub fn describe(&self) -> String {
        format!(
            "{}/{{siting.csv, curve.csv, curve.svg, map.svg, airspace.geojson}}",
            self.shown
        )
    }

    /// Writes a shard's `shard.json` alone and puts the folder in place.
    pub fn write_shard(self, text: &str) -> anyhow::Result<()> {
        output::write_atomically(&self.folder.path().join(muse_siting::shard::FILE), text)?;
        self.folder.commit()
    }

    /// The folder as given, for messages.
    pub fn shown(&self) -> &str {
        &self.shown
    }

    /// Writes every file and puts the folder in place.
    pub fn write(
        self,
        siting: &Siting,
        run: &GreedyRun,
        curves: &[Curve],
        map: &str,
    ) -> anyhow::Result<()> {
        let k = run.picks.len();
        let dir = self.folder.path();
        output::write_atomically(&dir.join("map.svg"), map)?;
        output::write_atomically(&dir.join("siting.csv"), &picks_csv(siting, run))?;
        output::write_atomically(
            &dir.join("curve.csv"),
            &curves_csv(siting, &run.base, curves),
        )?;
        output::write_atomically(
            &dir.join("curve.svg"),
            &curve_svg(siting, &run.base, curves, k)?,
        )?;
        let airspace = siting.airspace(&run.added())?;
        output::write_atomically(
            &dir.join("airspace.geojson"),
            &muse_formats::airspace_geojson::write_airspace(&airspace),
        )?;
        self.folder.commit()
    }
}

/// `12.3 ± 0.4`.
fn pm(ci: muse_sim::stats::MeanCi) -> String {
    format!("{:.1} ± {:.1}", ci.mean, ci.half_width)
}

/// The greedy's picks, one line each.
pub fn print_picks(siting: &Siting, run: &GreedyRun) {
    eprintln!(
        "  existing      delivered {} of {} served per day",
        pm(run.base.delivered_ci()),
        pm(run.base.served_ci())
    );
    for (i, p) in run.picks.iter().enumerate() {
        let pad = &siting.candidates()[p.candidate];
        eprintln!(
            "  pick {:>3}     {:<8} gain {:>14}  delivered {:>16}  served {:>16}  {}",
            i + 1,
            pad.id,
            pm(p.gain),
            pm(p.after.delivered_ci()),
            pm(p.after.served_ci()),
            pad.name
        );
    }
}

/// Each method's deliveries with all its pads, and what the first method (the greedy) delivers
/// over each other one on the same days (a paired difference).
pub fn print_curves(base: &Evaluation, curves: &[Curve]) {
    let last = |c: &Curve| c.steps.last().map_or(base, |(_, e)| e).clone();
    let first = curves.first().map(last);
    for c in curves {
        let end = last(c);
        let versus = match &first {
            Some(f) if c.method != curves[0].method => {
                format!(
                    "; {} delivers {} more",
                    curves[0].method,
                    pm(f.gain_over(&end))
                )
            }
            _ => String::new(),
        };
        eprintln!(
            "  {:<18} {} pads: delivered {} per day ({:+.1} over the existing pads){versus}",
            c.method,
            c.steps.len(),
            pm(end.delivered_ci()),
            end.mean_delivered() - base.mean_delivered()
        );
    }
}

/// `siting.csv`: the greedy's picks in order.
fn picks_csv(siting: &Siting, run: &GreedyRun) -> String {
    let mut out = CsvWriter::new(&[
        "rank",
        "pad",
        "name",
        "lon",
        "lat",
        "gain_mean",
        "gain_ci95",
        "delivered_mean",
        "delivered_ci95",
        "served_mean",
        "corridors",
        "evaluations",
    ]);
    for (i, p) in run.picks.iter().enumerate() {
        let pad = &siting.candidates()[p.candidate];
        let d = p.after.delivered_ci();
        out.row(&[
            (i + 1).to_string(),
            pad.id.clone(),
            pad.name.clone(),
            pad.pos.lon.to_string(),
            pad.pos.lat.to_string(),
            format!("{:.3}", p.gain.mean),
            format!("{:.3}", p.gain.half_width),
            format!("{:.3}", d.mean),
            format!("{:.3}", d.half_width),
            format!("{:.3}", p.after.served_ci().mean),
            p.after.corridors.to_string(),
            p.evaluations.to_string(),
        ]);
    }
    out.finish()
}

/// `curve.csv`: every method's set at each k, with its deliveries.
fn curves_csv(siting: &Siting, base: &Evaluation, curves: &[Curve]) -> String {
    let mut out = CsvWriter::new(&[
        "method",
        "k",
        "delivered_mean",
        "delivered_ci95",
        "served_mean",
        "served_ci95",
        "corridors",
        "pads",
    ]);
    let mut row = |method: &str, k: usize, e: &Evaluation, pads: &[usize]| {
        let (d, s) = (e.delivered_ci(), e.served_ci());
        let ids: Vec<&str> = pads
            .iter()
            .map(|&c| siting.candidates()[c].id.as_str())
            .collect();
        out.row(&[
            method.to_owned(),
            k.to_string(),
            format!("{:.3}", d.mean),
            format!("{:.3}", d.half_width),
            format!("{:.3}", s.mean),
            format!("{:.3}", s.half_width),
            e.corridors.to_string(),
            ids.join(" "),
        ]);
    };
    for c in curves {
        row(c.method, 0, base, &[]);
        for (k, (pads, e)) in c.steps.iter().enumerate() {
            row(c.method, k + 1, e, pads);
        }
    }
    out.finish()
}

/// `curve.svg`: delivered requests per day against pads added, one line per method.
fn curve_svg(
    siting: &Siting,
    base: &Evaluation,
    curves: &[Curve],
    k: usize,
) -> anyhow::Result<String> {
    let point = |x: usize, e: &Evaluation| {
        let ci = e.delivered_ci();
        Point {
            x: x as f64,
            mean: ci.mean,
            ci_low: ci.low(),
            ci_high: ci.high(),
        }
    };
    let series: Vec<Series> = curves
        .iter()
        .map(|c| Series {
            name: c.method.to_owned(),
            points: std::iter::once(point(0, base))
                .chain(
                    c.steps
                        .iter()
                        .enumerate()
                        .map(|(i, (_, e))| point(i + 1, e)),
                )
                .collect(),
        })
        .collect();
    let input = siting.input();
    let day = &input.days[0];
    let opts = PlotOptions {
        title: format!("Delivered requests per day with up to {k} pads added"),
        x_label: "pads added".into(),
        y_label: "delivered requests per day".into(),
        footnote: format!(
            "{} existing pads, {} candidates, {} customers; {} seeded days of {} requests \
             (seeds {}–{}), last mile {} m; 95% confidence intervals over the days",
            input.existing.len(),
            input.candidates.len(),
            input.customers.len(),
            input.days.len(),
            day.count,
            day.seed,
            input.days[input.days.len() - 1].seed,
            input.last_mile_m
        ),
        ..PlotOptions::default()
    };
    Ok(render_line_plot(&series, &opts)?)
}
