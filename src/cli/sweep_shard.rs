//! `muse sweep --shard K/N` and `muse sweep merge`: a sweep run as shards (a cluster's array
//! job), merged back into exactly the files of one machine (see [`muse_sim::shard`]). Both
//! kinds of sweep shard: variants × counts × repetitions, and `--vary announce-lead`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{Args, Parser};
use muse_sim::lead::LeadRecord;
use muse_sim::shard::{Shard, ShardFile, StudyRef, fingerprint, merge as merge_shards};
use muse_sim::sweep::{RunRecord, summarize};
use serde::Serialize;

use super::common::write_atomically;
use super::output::{self, OutFolder};
use super::study::{Study, report_reproduction, sweep_time_column};
use super::sweep::{SUMMARY_FILE, SweepArgs, print_table, runs_bar, spec_of, write_results};
use super::sweep_lead::{self, LeadSweep};
use super::sweep_vary::Vary;

/// The file a shard writes into its `--out` folder.
pub const SHARD_FILE: &str = "shard.json";

/// Arguments of `muse sweep merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shards' output folders (or their `shard.json` files), every shard of one sweep once.
    #[arg(required = true, value_name = "DIR")]
    shards: Vec<PathBuf>,
    /// Output folder for the merged `sweep.csv`, `sweep_summary.csv` and plots (with
    /// `--vary announce-lead`: `announce_lead.csv`, its summary and plots).
    #[arg(long, value_name = "DIR", default_value = "out/sweep")]
    out: PathBuf,
}

/// Where a shard comes from and how it is cut: what its file records beside its runs.
pub struct ShardInfo<'a> {
    /// The sweep's [`fingerprint`].
    pub sweep: String,
    /// Runs in the whole sweep.
    pub runs: usize,
    /// Which shard.
    pub shard: Shard,
    /// The command line, from `sweep` on.
    pub command_line: &'a [String],
    /// The study it came from.
    pub study: Option<&'a Study>,
    /// The output folder, as given.
    pub out: &'a Path,
}

/// Runs the shard `info` says with `go` (which calls its tick once per finished run) and
/// writes `shard.json` into the output folder `out` as a whole: a killed shard leaves no
/// file, and is simply rerun.
pub fn run_shard<R: Serialize>(
    info: &ShardInfo<'_>,
    out: OutFolder,
    go: impl FnOnce(&(dyn Fn() + Sync)) -> anyhow::Result<Vec<(usize, R)>>,
) -> anyhow::Result<ExitCode> {
    let shard = info.shard;
    let mine = (0..info.runs).filter(|&r| shard.takes(r)).count();
    println!(
        "sweep shard {shard}: {mine} of {} runs, {} threads",
        info.runs,
        rayon::current_num_threads()
    );
    let bar = runs_bar(mine);
    let started = std::time::Instant::now();
    let runs = go(&|| bar.inc(1))?;
    bar.finish_and_clear();
    let file = ShardFile::new(
        info.sweep.clone(),
        shard,
        info.runs,
        info.command_line.to_vec(),
        info.study.map(Study::reference),
        runs,
    );
    let text = serde_json::to_string(&file).context("writing the shard")?;
    write_atomically(&out.path().join(SHARD_FILE), &text)?;
    out.commit()?;
    println!(
        "done in {:.1} s wall; wrote {} (sweep {}); merge the {} shards with `muse sweep merge DIR...`",
        started.elapsed().as_secs_f64(),
        info.out.join(SHARD_FILE).display(),
        file.sweep,
        shard.of
    );
    Ok(ExitCode::SUCCESS)
}

/// The command line a shard was run with, read back.
#[derive(Debug, Parser)]
#[command(name = "muse")]
struct Recorded {
    #[command(subcommand)]
    command: RecordedCommand,
}

#[derive(Debug, clap::Subcommand)]
enum RecordedCommand {
    Sweep(SweepArgs),
}

/// What every shard file holds beside its runs, read before its kind of record is known.
#[derive(serde::Deserialize)]
struct Head {
    args: Vec<String>,
}

/// Reads the shards of `args` as records `R`.
fn read_shards<R: for<'de> serde::Deserialize<'de>>(
    texts: &[(String, String)],
) -> anyhow::Result<Vec<(String, ShardFile<R>)>> {
    texts
        .iter()
        .map(|(name, text)| Ok((name.clone(), ShardFile::read(text, name)?)))
        .collect()
}

/// Runs `muse sweep merge`.
pub fn merge(args: &MergeArgs) -> anyhow::Result<ExitCode> {
    let mut texts = Vec::with_capacity(args.shards.len());
    let mut files = Vec::with_capacity(args.shards.len());
    for dir in &args.shards {
        let path = if dir.is_dir() {
            dir.join(SHARD_FILE)
        } else {
            dir.clone()
        };
        files.push(path.clone());
        let name = path.display().to_string();
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!("reading {name} (a shard that did not finish writes none: rerun it)")
        })?;
        texts.push((name, text));
    }
    // The sweep itself, from the command line the first shard ran: its plots need it, and it
    // must be the sweep the shards say they are.
    let (name, text) = &texts[0];
    let head: Head = serde_json::from_str(text)
        .map_err(|e| anyhow::anyhow!("{name}: not a MUSE sweep shard ({e})"))?;
    let recorded =
        Recorded::try_parse_from(std::iter::once("muse".to_owned()).chain(head.args.clone()))
            .with_context(|| format!("{name}: the recorded command line does not parse"))?;
    let RecordedCommand::Sweep(sweep) = recorded.command;
    let inputs = super::sweep::inputs_of(&sweep, None).add_all("the shard", &files);
    let out = output::folder("--out", &args.out, &inputs)?;
    let rebuilt = |what: &str| format!("{name}: rebuilding the {what} from its command line");
    if sweep.vary.contains(&Vary::AnnounceLead) {
        let shards = read_shards::<LeadRecord>(&texts)?;
        let records = merge_shards(&shards)?;
        let lead = LeadSweep::of(&sweep).with_context(|| rebuilt("sweep"))?;
        check_fingerprint(name, &fingerprint(&lead.spec), &shards[0].1)?;
        announce(&shards, records.len(), &args.out);
        lead.write_results(&records, out, &args.out)?;
        report_reproduction(
            shards[0].1.study.as_ref(),
            &args.out,
            sweep_lead::SUMMARY_FILE,
            sweep_time_column,
        )
    } else {
        let shards = read_shards::<RunRecord>(&texts)?;
        let records = merge_shards(&shards)?;
        let (_, spec) = spec_of(&sweep).with_context(|| rebuilt("sweep"))?;
        check_fingerprint(name, &fingerprint(&spec), &shards[0].1)?;
        announce(&shards, records.len(), &args.out);
        let booked = sweep.demand.booking_note();
        write_results(&spec, &records, booked.as_deref(), out.path())?;
        out.commit()?;
        println!(
            "wrote {}/{{sweep.csv, sweep_summary.csv, sweep_runtime.svg, sweep_success.svg, sweep_air_delay.svg}}",
            args.out.display()
        );
        print_table(&summarize(&records));
        report_reproduction(
            shards[0].1.study.as_ref(),
            &args.out,
            SUMMARY_FILE,
            sweep_time_column,
        )
    }
}

/// Refuses shards whose sweep is not the one rebuilt from their command line.
fn check_fingerprint<R>(name: &str, rebuilt: &str, first: &ShardFile<R>) -> anyhow::Result<()> {
    if rebuilt != first.sweep {
        anyhow::bail!(
            "{name}: the sweep rebuilt from its command line ({rebuilt}) is not the one the shards ran ({}): a file it reads (zones, airspace, requests) has changed, or this is another build of muse",
            first.sweep
        );
    }
    Ok(())
}

/// Prints what is merged.
fn announce<R>(shards: &[(String, ShardFile<R>)], runs: usize, out: &Path) {
    let first = &shards[0].1;
    println!(
        "merged {} shards, {runs} runs of sweep {}{} into {}",
        shards.len(),
        first.sweep,
        first.study.as_ref().map_or(String::new(), |s| format!(
            " (study {}: {})",
            s.file, s.title
        )),
        out.display()
    );
}

impl Study {
    /// How the shards of a study name it.
    pub fn reference(&self) -> StudyRef {
        StudyRef {
            file: self.path.display().to_string(),
            title: self.title.clone(),
            results: self.results.as_ref().map(|r| r.display().to_string()),
        }
    }
}
