//! `muse sweep`: the paper's experiment — request counts × repetitions × scenario variants;
//! with `--vary announce-lead`, the announcement-lead sweep ([`super::sweep_lead`]).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{ArgMatches, Args};
use indicatif::{ProgressBar, ProgressStyle};
use muse_render::{PlotOptions, Point, Series, render_line_plot};
use muse_sim::shard::{Shard, fingerprint};
use muse_sim::stats::MeanCi;
use muse_sim::sweep::{
    RunRecord, SummaryRow, SweepSpec, run_sweep, run_sweep_shard, runs_csv, summarize, summary_csv,
};

use super::common::{FlightArgs, World, WorldArgs, write_atomically};
use super::demand::DemandArgs;
use super::output;
use super::ranges::{self, MAX_COUNTS, MAX_REQUESTS, MAX_SWEEP_DAYS};
use super::study::Study;
use super::sweep_lead::LeadSweep;
use super::sweep_shard::{ShardInfo, run_shard};
use super::sweep_vary::{Vary, parse_swap_times, variants};

/// `muse sweep` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum SweepCommand {
    /// Merge the shards of one sweep (`--shard K/N` runs) into the files of an unsharded run;
    /// refuses shards of different sweeps, a missing shard and a shard given twice.
    Merge(super::sweep_shard::MergeArgs),
}

/// Arguments of `muse sweep`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
// A sweep's request counts are `--counts`: the demand options' `--count` is not one of its own.
#[command(mut_arg("count", |a| a.hide(true)))]
pub struct SweepArgs {
    /// `muse sweep merge DIR...`: merge the shards of one sweep.
    #[command(subcommand)]
    pub(super) command: Option<SweepCommand>,
    /// Run the sweep a study file describes (TOML: its title, and the options of this
    /// command in a `[sweep]` table; see `studies/`). Beside it give only `--shard`, `--out`
    /// (default `out/STUDY`), `--threads` and `--dry-run`.
    #[arg(long, value_name = "FILE")]
    pub(super) study: Option<PathBuf>,
    /// Run only shard `K` of `N` (0-based: runs `K`, `K+N`, … in run order), seeds unchanged,
    /// and write `DIR/shard.json`; `muse sweep merge` joins the shards. For array jobs:
    /// Slurm `--shard $SLURM_ARRAY_TASK_ID/N`, Kubernetes `--shard $JOB_COMPLETION_INDEX/N`.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub(super) shard: Option<String>,
    /// Request counts: `START:END:STEP` or a comma-separated list; each from 1 to 10000000,
    /// at most 1000 counts, and at most 1000000 days (counts × repetitions).
    #[arg(long, default_value = "1000:10000:1000", allow_hyphen_values = true)]
    pub(super) counts: String,
    /// Repetitions per count, each with its own seed, from 1 to 10000.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true, value_parser = ranges::reps)]
    pub(super) reps: usize,
    /// Compare scenarios on the same seeds; repeat to combine (except `announce-lead`).
    #[arg(long, value_enum)]
    pub(super) vary: Vec<Vary>,
    /// `--vary announce-lead`: the leads to compare, minutes between a zone's announcement and
    /// the start of its first active window on the scenario's day, comma-separated, each
    /// from 0 to 43200, at most 100 [default: 0,15,30,60,120].
    #[arg(long, value_name = "MIN,...", allow_hyphen_values = true)]
    pub(super) leads: Option<String>,
    /// `--vary announce-lead`: zone files (ED-318/ED-269) whose zones are announced, each
    /// `lead` before its first window (their own announcement instants are replaced); repeat
    /// for several. Default: the built-in scenario's CBD zone. A base zone (`--zones`) with
    /// the same id is not also known from the start.
    #[arg(long, value_name = "FILE")]
    pub(super) announce_zones: Vec<PathBuf>,
    /// `--vary battery-swap`: the swap times to compare with single legs, minutes,
    /// comma-separated, each from 0 to 1440, at most 100 [default: 2,5,10].
    #[arg(long, value_name = "MIN,...", allow_hyphen_values = true)]
    pub(super) swap_min: Option<String>,
    /// Worker threads, from 1 to 1024 (default: all cores).
    #[arg(long, allow_negative_numbers = true, value_parser = ranges::threads)]
    threads: Option<usize>,
    /// Print what would run — the sweep's identity, its runs and requests, the shard's share,
    /// the command line it stands for — and exit without running.
    #[arg(long)]
    pub(super) dry_run: bool,
    #[command(flatten)]
    pub(super) demand: DemandArgs,
    #[command(flatten)]
    pub(super) world: WorldArgs,
    #[command(flatten)]
    pub(super) flight: FlightArgs,
    /// Output folder, written whole: it replaces an earlier run's folder as a whole, and a
    /// folder holding files muse does not write is refused (docs/reference.md#outputs).
    #[arg(long, value_name = "DIR", default_value = "out/sweep")]
    pub(super) out: PathBuf,
}

/// Parses `START:END:STEP` or `a,b,c`: at most [`MAX_COUNTS`] counts, each from 1 to
/// [`MAX_REQUESTS`] (checked before the list is made).
pub(super) fn parse_counts(text: &str) -> anyhow::Result<Vec<usize>> {
    let bad = || {
        anyhow::anyhow!(
            "--counts `{text}`: expected START:END:STEP or a comma-separated list of counts, \
             each from 1 to {MAX_REQUESTS}, at most {MAX_COUNTS} counts"
        )
    };
    let count = |x: &str| {
        x.trim()
            .parse()
            .ok()
            .filter(|n| (1..=MAX_REQUESTS).contains(n))
            .ok_or_else(bad)
    };
    let counts: Vec<usize> = if let [a, b, s] = text.split(':').collect::<Vec<_>>()[..] {
        let (a, b, s): (usize, usize, usize) = (count(a)?, count(b)?, count(s)?);
        if a > b || (b - a) / s >= MAX_COUNTS {
            return Err(bad());
        }
        (a..=b).step_by(s).collect()
    } else {
        let items: Vec<&str> = text.split(',').collect();
        if items.len() > MAX_COUNTS {
            return Err(bad());
        }
        items
            .into_iter()
            .map(count)
            .collect::<anyhow::Result<_>>()?
    };
    Ok(counts)
}

/// Refuses a sweep of more than [`MAX_SWEEP_DAYS`] days (counts × repetitions).
pub(super) fn check_days(counts: usize, reps: usize) -> anyhow::Result<()> {
    let days = counts.saturating_mul(reps);
    if days > MAX_SWEEP_DAYS {
        anyhow::bail!(
            "--counts and --reps: {counts} counts × {reps} repetitions = {days} days, more than \
             the {MAX_SWEEP_DAYS} a sweep runs"
        );
    }
    Ok(())
}

/// Runs `muse sweep`; `matches` are its own, to tell what was given beside `--study`.
pub fn run(args: &SweepArgs, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    if let Some(SweepCommand::Merge(merge)) = &args.command {
        return super::sweep_shard::merge(merge);
    }
    if matches.value_source("count") == Some(clap::parser::ValueSource::CommandLine) {
        anyhow::bail!(
            "--count: a sweep's request counts are --counts (e.g. 1000:10000:1000 or 3000,6000)"
        );
    }
    let Some(path) = &args.study else {
        return run_sweep_args(args, &std::env::args().skip(1).collect::<Vec<_>>(), None);
    };
    let study = Study::open::<SweepArgs>(path, "sweep", matches)?;
    let extra = how_to_run(args, &study.out(matches, &args.out));
    let sweep: SweepArgs = study.parse("sweep", &extra)?;
    run_sweep_args(&sweep, &study.command_line("sweep", &extra), Some(&study))
}

/// How a study is run, as command-line arguments: `--out`, and `--shard`, `--threads` and
/// `--dry-run` when given.
fn how_to_run(args: &SweepArgs, out: &std::path::Path) -> Vec<String> {
    let mut extra = vec!["--out".to_owned(), out.display().to_string()];
    if let Some(shard) = &args.shard {
        extra.extend(["--shard".to_owned(), shard.clone()]);
    }
    if let Some(n) = args.threads {
        extra.extend(["--threads".to_owned(), n.to_string()]);
    }
    if args.dry_run {
        extra.push("--dry-run".to_owned());
    }
    extra
}

/// Runs the sweep `args` describe; `command_line` (from `sweep` on) is recorded in shard
/// files, `study` is the study it came from, if any.
fn run_sweep_args(
    args: &SweepArgs,
    command_line: &[String],
    study: Option<&Study>,
) -> anyhow::Result<ExitCode> {
    let announce_lead = args.vary.contains(&Vary::AnnounceLead);
    if announce_lead && args.vary.iter().any(|v| *v != Vary::AnnounceLead) {
        anyhow::bail!(
            "--vary announce-lead cannot be combined with other --vary values (it is its own sweep: leads × counts × repetitions)"
        );
    }
    if !announce_lead && (args.leads.is_some() || !args.announce_zones.is_empty()) {
        anyhow::bail!("--leads and --announce-zones apply only with --vary announce-lead");
    }
    if args.swap_min.is_some() && !args.vary.contains(&Vary::BatterySwap) {
        anyhow::bail!("--swap-min applies only with --vary battery-swap");
    }
    if let Some(n) = args.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("--threads")?;
    }
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?;
    if args.dry_run {
        let (id, runs, requests) = if announce_lead {
            let lead = LeadSweep::of(args)?;
            let s = &lead.spec;
            (fingerprint(s), s.runs(), s.total_requests())
        } else {
            let (_, s) = spec_of(args)?;
            (fingerprint(&s), s.runs(), s.total_requests())
        };
        println!("sweep {id}: {runs} runs, {requests} requests");
        if let Some(shard) = shard {
            let mine = (0..runs).filter(|&r| shard.takes(r)).count();
            println!("shard {shard}: {mine} runs");
        }
        let line: Vec<&str> = command_line
            .iter()
            .map(String::as_str)
            .filter(|a| *a != "--dry-run")
            .collect();
        println!("command line: muse {}", line.join(" "));
        return Ok(ExitCode::SUCCESS);
    }
    let out = output::folder("--out", &args.out, &inputs_of(args, study))?;
    let info = |sweep: String, runs: usize, shard: Shard| ShardInfo {
        sweep,
        runs,
        shard,
        command_line,
        study,
        out: &args.out,
    };
    if announce_lead {
        if let Some(shard) = shard {
            let lead = LeadSweep::of(args)?;
            let info = info(fingerprint(&lead.spec), lead.spec.runs(), shard);
            return run_shard(&info, out, |tick| lead.run(shard, tick));
        }
        return super::sweep_lead::run(args, study, out);
    }
    let (world, spec) = spec_of(args)?;
    if let Some(shard) = shard {
        let info = info(fingerprint(&spec), spec.runs(), shard);
        return run_shard(&info, out, |tick| {
            Ok(run_sweep_shard(&world.airspace, &spec, shard, tick)?)
        });
    }
    let booked = args.demand.booking_note();
    println!(
        "sweep: {} variant(s) × {} counts × {} repetitions = {} runs, {} requests{}, {} threads",
        spec.variants.len(),
        spec.counts.len(),
        spec.reps,
        spec.runs(),
        spec.total_requests(),
        booked.as_deref().map_or(String::new(), |b| format!(" {b}")),
        rayon::current_num_threads()
    );
    let bar = runs_bar(spec.runs());
    let started = std::time::Instant::now();
    let records = run_sweep(&world.airspace, &spec, || bar.inc(1))?;
    bar.finish_and_clear();
    write_results(&spec, &records, booked.as_deref(), out.path())?;
    out.commit()?;
    println!(
        "done in {:.1} s wall; wrote {}/{{sweep.csv, sweep_summary.csv, sweep_runtime.svg, sweep_success.svg, sweep_air_delay.svg}}",
        started.elapsed().as_secs_f64(),
        args.out.display()
    );
    print_table(&summarize(&records));
    super::study::report_reproduction(
        study.map(Study::reference).as_ref(),
        &args.out,
        SUMMARY_FILE,
        super::study::sweep_time_column,
    )
}

/// The files a sweep reads: its world, the zones it announces, its study.
pub(super) fn inputs_of(args: &SweepArgs, study: Option<&Study>) -> output::Inputs {
    let inputs = output::Inputs::new()
        .world(&args.world)
        .add_all("--announce-zones", &args.announce_zones);
    match study {
        Some(s) => inputs.add("--study", &s.path),
        None => inputs,
    }
}

/// The summary file, the one a study's published results are compared on.
pub const SUMMARY_FILE: &str = "sweep_summary.csv";

/// The world and the sweep `args` describe.
pub(super) fn spec_of(args: &SweepArgs) -> anyhow::Result<(World, SweepSpec)> {
    let swap_times = parse_swap_times(args.swap_min.as_deref().unwrap_or("2,5,10"))?;
    let base = args.flight.params()?;
    let world = args.world.load()?;
    world.refuse_withdrawn("sweep")?;
    let counts = parse_counts(&args.counts)?;
    check_days(counts.len(), args.reps)?;
    let demand = args.demand.spec(&world, args.flight.range)?;
    let spec = SweepSpec {
        counts,
        reps: args.reps,
        base_seed: demand.seed,
        start: demand.start,
        end: demand.end,
        od: demand.od,
        booking_lead: demand.booking_lead,
        variants: variants(&world, base, &args.vary, &swap_times)?,
    };
    Ok((world, spec))
}

/// Writes a sweep's results into `out`: `sweep.csv`, `sweep_summary.csv` and the plots.
pub(super) fn write_results(
    spec: &SweepSpec,
    records: &[RunRecord],
    booked: Option<&str>,
    out: &std::path::Path,
) -> anyhow::Result<()> {
    let rows = summarize(records);
    write_atomically(&out.join("sweep.csv"), &runs_csv(records))?;
    write_atomically(&out.join(SUMMARY_FILE), &summary_csv(&rows))?;
    write_plots(spec, &rows, booked, out)
}

/// The progress bar of a sweep: one step per run.
pub(super) fn runs_bar(runs: usize) -> ProgressBar {
    let bar = ProgressBar::new(runs as u64).with_message("runs");
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({elapsed}, ETA {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar
}

fn series(
    spec: &SweepSpec,
    rows: &[SummaryRow],
    metric: impl Fn(&SummaryRow) -> MeanCi,
) -> Vec<Series> {
    spec.variants
        .iter()
        .map(|v| Series {
            name: v.name.clone(),
            points: rows
                .iter()
                .filter(|r| r.variant == v.name)
                .map(|r| {
                    let m = metric(r);
                    Point {
                        x: r.count as f64,
                        mean: m.mean,
                        ci_low: m.low(),
                        ci_high: m.high(),
                    }
                })
                .collect(),
        })
        .collect()
}

fn write_plots(
    spec: &SweepSpec,
    rows: &[SummaryRow],
    booked: Option<&str>,
    out: &std::path::Path,
) -> anyhow::Result<()> {
    let foot = format!(
        "{} runs per point (seeds {}…{}{}); bands: 95% confidence interval of the mean.",
        spec.reps,
        spec.base_seed,
        spec.base_seed + (spec.counts.len() * spec.reps) as u64 - 1,
        booked.map_or(String::new(), |b| format!(", requests {b}"))
    );
    let plots = [
        (
            "sweep_runtime.svg",
            "Planner runtime for a day of requests",
            "Planner wall time per day (ms)",
            false,
            series(spec, rows, |r| r.planner_ms),
        ),
        (
            "sweep_success.svg",
            "Share of requests planned",
            "Success rate",
            true,
            series(spec, rows, |r| r.success_rate),
        ),
        (
            "sweep_air_delay.svg",
            "Mean air delay of planned flights",
            "Air delay (s)",
            false,
            series(spec, rows, |r| r.air_delay_s),
        ),
    ];
    for (file, title, y_label, percent, s) in plots {
        let opts = PlotOptions {
            title: title.to_owned(),
            x_label: "Requests per day".to_owned(),
            y_label: y_label.to_owned(),
            y_from_zero: true,
            y_percent: percent,
            footnote: foot.clone(),
            ..PlotOptions::default()
        };
        let svg = render_line_plot(&s, &opts).with_context(|| format!("drawing {file}"))?;
        write_atomically(&out.join(file), &svg)?;
    }
    Ok(())
}

pub(super) fn print_table(rows: &[SummaryRow]) {
    println!(
        "{:<28} {:>7} {:>16} {:>16} {:>16} {:>10}",
        "variant", "count", "success %", "planner ms", "air delay s", "expanded"
    );
    for r in rows {
        let f = |m: MeanCi, scale: f64, prec: usize| {
            format!(
                "{:.prec$} ± {:.prec$}",
                m.mean * scale,
                m.half_width * scale
            )
        };
        println!(
            "{:<28} {:>7} {:>16} {:>16} {:>16} {:>10.2}",
            r.variant,
            r.count,
            f(r.success_rate, 100.0, 1),
            f(r.planner_ms, 1.0, 2),
            f(r.air_delay_s, 1.0, 1),
            r.expanded_per_request.mean
        );
    }
}

#[cfg(test)]
mod tests {
    use super::{check_days, parse_counts};

    #[test]
    fn counts() {
        assert_eq!(
            parse_counts("1000:3000:1000").unwrap(),
            vec![1000, 2000, 3000]
        );
        assert_eq!(parse_counts("5, 10").unwrap(), vec![5, 10]);
        for bad in [
            "",
            "1:2",
            "3:1:1",
            "1:5:0",
            "a,b",
            "0,5",
            "-5",
            "10000001",
            "1:2000000000:1",
            "1:1001:1",
        ] {
            let e = parse_counts(bad).unwrap_err().to_string();
            assert!(
                e.ends_with("each from 1 to 10000000, at most 1000 counts"),
                "{bad}: {e}"
            );
        }
        assert_eq!(parse_counts("1:1000:1").unwrap().len(), 1_000);
        assert_eq!(
            parse_counts(&vec!["5"; 1_001].join(","))
                .unwrap_err()
                .to_string(),
            format!(
                "--counts `{}`: expected START:END:STEP or a comma-separated list of counts, \
                 each from 1 to 10000000, at most 1000 counts",
                vec!["5"; 1_001].join(",")
            )
        );
        assert!(check_days(100, 10_000).is_ok());
        assert_eq!(
            check_days(1_000, 10_000).unwrap_err().to_string(),
            "--counts and --reps: 1000 counts × 10000 repetitions = 10000000 days, more than \
             the 1000000 a sweep runs"
        );
    }
}
