//! `muse sweep --shard K/N` and `muse sweep merge`: a sweep run as shards (a cluster's array
//! job), merged back into exactly the files of one machine (see [`muse_sim::shard`]).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{Args, Parser};
use muse_sim::shard::{FORMAT, Shard, ShardFile, ShardRun, fingerprint, merge as merge_shards};
use muse_sim::sweep::{SweepSpec, run_sweep_shard, summarize};

use super::common::write_atomically;
use super::sweep::{SweepArgs, print_table, runs_bar, spec_of, write_results};

/// The file a shard writes into its `--out` folder.
pub const SHARD_FILE: &str = "shard.json";

/// Arguments of `muse sweep merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shards' output folders (or their `shard.json` files), every shard of one sweep once.
    #[arg(required = true, value_name = "DIR")]
    shards: Vec<PathBuf>,
    /// Output folder for the merged `sweep.csv`, `sweep_summary.csv` and plots.
    #[arg(long, value_name = "DIR", default_value = "out/sweep")]
    out: PathBuf,
}

/// Runs shard `shard` of the sweep `spec` and writes `shard.json` into `args.out`
/// atomically: a killed shard leaves no file, and is simply rerun.
pub fn run_shard(args: &SweepArgs, spec: &SweepSpec, shard: Shard) -> anyhow::Result<ExitCode> {
    let world = args.world.load()?;
    let mine = (0..spec.runs()).filter(|&r| shard.takes(r)).count();
    println!(
        "sweep shard {shard}: {mine} of {} runs, {} threads",
        spec.runs(),
        rayon::current_num_threads()
    );
    let bar = runs_bar(mine);
    let started = std::time::Instant::now();
    let runs = run_sweep_shard(&world.airspace, spec, shard, || bar.inc(1))?;
    bar.finish_and_clear();
    let file = ShardFile {
        format: FORMAT.to_owned(),
        sweep: fingerprint(spec),
        shard: shard.index,
        of: shard.of,
        runs: spec.runs(),
        args: std::env::args().skip(1).collect(),
        records: runs
            .into_iter()
            .map(|(run, record)| ShardRun { run, record })
            .collect(),
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let path = args.out.join(SHARD_FILE);
    let text = serde_json::to_string(&file).context("writing the shard")?;
    write_atomically(&path, &text)?;
    println!(
        "done in {:.1} s wall; wrote {} (sweep {}); merge the {} shards with `muse sweep merge DIR...`",
        started.elapsed().as_secs_f64(),
        path.display(),
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

/// Runs `muse sweep merge`.
pub fn merge(args: &MergeArgs) -> anyhow::Result<ExitCode> {
    let mut shards = Vec::with_capacity(args.shards.len());
    for dir in &args.shards {
        let path = if dir.is_dir() {
            dir.join(SHARD_FILE)
        } else {
            dir.clone()
        };
        let name = path.display().to_string();
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!("reading {name} (a shard that did not finish writes none: rerun it)")
        })?;
        shards.push((name.clone(), ShardFile::read(&text, &name)?));
    }
    let records = merge_shards(&shards)?;
    // The sweep itself, from the command line the shards ran: its plots need it, and it must
    // be the sweep the shards say they are.
    let (name, first) = &shards[0];
    let recorded =
        Recorded::try_parse_from(std::iter::once("muse".to_owned()).chain(first.args.clone()))
            .with_context(|| format!("{name}: the recorded command line does not parse"))?;
    let RecordedCommand::Sweep(sweep) = recorded.command;
    let (_, spec) = spec_of(&sweep)
        .with_context(|| format!("{name}: rebuilding the sweep from its command line"))?;
    if fingerprint(&spec) != first.sweep {
        anyhow::bail!(
            "{name}: the sweep rebuilt from its command line ({}) is not the one the shards ran ({}): a file it reads (zones, airspace, requests) has changed, or this is another build of muse",
            fingerprint(&spec),
            first.sweep
        );
    }
    let booked = sweep.demand.booking_note();
    write_results(&spec, &records, booked.as_deref(), &args.out)?;
    println!(
        "merged {} shards, {} runs of sweep {}; wrote {}/{{sweep.csv, sweep_summary.csv, sweep_runtime.svg, sweep_success.svg, sweep_air_delay.svg}}",
        shards.len(),
        records.len(),
        first.sweep,
        args.out.display()
    );
    print_table(&summarize(&records));
    Ok(ExitCode::SUCCESS)
}
