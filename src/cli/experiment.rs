//! Running an experiment from the command line, whatever its kind: `--dry-run`, one
//! `--shard` (written to `shard.json`), or the whole of it (its files written, its table
//! printed, a study's published file compared); and the merge of its shards.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressStyle};
use muse_sim::experiment::{
    Experiment, Kind, Progress, Results, Shard, ShardFile, Study, StudyRef, merge, reproduction,
};

use crate::cli::output::{OutFolder, write_atomically};

/// The file a shard writes into its `--out` folder.
pub const SHARD_FILE: &str = "shard.json";

/// How an experiment is run: what the command line said besides the experiment itself.
pub struct Launch<'a> {
    /// The output folder, as given.
    pub out: &'a Path,
    /// Only this shard, if given.
    pub shard: Option<Shard>,
    /// The command line, from the command's name on (recorded in shard files).
    pub command_line: &'a [String],
    /// The study it came from.
    pub study: Option<&'a Study>,
}

/// Prints what `exp` would run (`--dry-run`): its identity, runs and requests, the shard's
/// share, the command line it stands for.
pub fn dry_run<K: Kind>(exp: &Experiment<K>, how: &Launch<'_>) -> ExitCode {
    let runs = exp.runs();
    println!(
        "sweep {}: {runs} runs, {} requests",
        exp.identity(),
        exp.total_requests()
    );
    if let Some(shard) = how.shard {
        let mine = (0..runs).filter(|&r| shard.takes(r)).count();
        println!("shard {shard}: {mine} runs");
    }
    let line: Vec<&str> = how
        .command_line
        .iter()
        .map(String::as_str)
        .filter(|a| *a != "--dry-run")
        .collect();
    println!("command line: muse {}", line.join(" "));
    ExitCode::SUCCESS
}

/// The progress bar of a run: one step per run.
fn runs_bar(runs: usize) -> ProgressBar {
    let bar = ProgressBar::new(runs as u64).with_message("runs");
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({elapsed}, ETA {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar
}

/// Runs the runs of `shard` with a progress bar.
fn run_with_bar<K: Kind>(
    exp: &Experiment<K>,
    shard: Shard,
    runs: usize,
) -> anyhow::Result<Vec<(usize, K::Record)>> {
    let bar = runs_bar(runs);
    let records = exp.run(shard, &|p| {
        if let Progress::Finished { .. } = p {
            bar.inc(1);
        }
    })?;
    bar.finish_and_clear();
    Ok(records)
}

/// Runs `exp` as `how` says into `out` (`heading`: the lines announcing it): one shard, or
/// the whole of it.
pub fn launch<K: Kind>(
    exp: &Experiment<K>,
    how: &Launch<'_>,
    out: OutFolder,
    heading: &[String],
) -> anyhow::Result<ExitCode> {
    if let Some(shard) = how.shard {
        return run_shard(exp, how, shard, out);
    }
    for line in heading {
        println!("{line}");
    }
    let started = std::time::Instant::now();
    let records: Vec<K::Record> = run_with_bar(exp, Shard::WHOLE, exp.runs())?
        .into_iter()
        .map(|(_, r)| r)
        .collect();
    let results = exp.results(&records)?;
    let names = write_results(&results, out)?;
    println!(
        "done in {:.1} s wall; wrote {}/{{{names}}}",
        started.elapsed().as_secs_f64(),
        how.out.display()
    );
    print!("{}", results.table);
    report(
        how.study.map(Study::reference).as_ref(),
        how.out,
        &results,
        exp,
    )
}

/// Runs one shard and writes `shard.json` into `out` as a whole: a killed shard leaves no
/// file, and is simply rerun.
fn run_shard<K: Kind>(
    exp: &Experiment<K>,
    how: &Launch<'_>,
    shard: Shard,
    out: OutFolder,
) -> anyhow::Result<ExitCode> {
    let runs = exp.runs();
    let mine = (0..runs).filter(|&r| shard.takes(r)).count();
    println!(
        "sweep shard {shard}: {mine} of {runs} runs, {} threads",
        rayon::current_num_threads()
    );
    let started = std::time::Instant::now();
    let records = run_with_bar(exp, shard, mine)?;
    let file = ShardFile::new(
        exp.identity(),
        shard,
        runs,
        how.command_line.to_vec(),
        how.study.map(Study::reference),
        records,
    );
    let text = serde_json::to_string(&file).context("writing the shard")?;
    write_atomically(&out.path().join(SHARD_FILE), &text)?;
    out.commit()?;
    println!(
        "done in {:.1} s wall; wrote {} (sweep {}); merge the {} shards with `muse sweep merge DIR...`",
        started.elapsed().as_secs_f64(),
        how.out.join(SHARD_FILE).display(),
        file.sweep,
        shard.of
    );
    Ok(ExitCode::SUCCESS)
}

/// Writes the files of `results` into `out` and puts it in place; their names, joined.
fn write_results(results: &Results, out: OutFolder) -> anyhow::Result<String> {
    for (name, text) in &results.files {
        write_atomically(&out.path().join(name), text)?;
    }
    out.commit()?;
    let names: Vec<&str> = results.files.iter().map(|(n, _)| n.as_str()).collect();
    Ok(names.join(", "))
}

/// Compares the file a study publishes with the one written into `out`, and says so: exit 0
/// when it is the same (or there is nothing to compare), 1 when it differs.
pub fn report<K: Kind>(
    study: Option<&StudyRef>,
    out: &Path,
    results: &Results,
    exp: &Experiment<K>,
) -> anyhow::Result<ExitCode> {
    let verdict = reproduction(study, out, &results.compared, &|c| exp.kind.measured(c))?;
    if !verdict.ok() {
        eprintln!("error: {verdict}");
        return Ok(ExitCode::from(1));
    }
    let text = verdict.to_string();
    if !text.is_empty() {
        println!("{text}");
    }
    Ok(ExitCode::SUCCESS)
}

/// Merges the shard files `texts` (name, text) of `exp` into `out` (the folder `shown`): the
/// files of one machine, the table, the study's verdict.
pub fn merged<K: Kind>(
    exp: &Experiment<K>,
    texts: &[(String, String)],
    out: OutFolder,
    shown: &Path,
) -> anyhow::Result<ExitCode> {
    let shards: Vec<(String, ShardFile<K::Record>)> = texts
        .iter()
        .map(|(name, text)| Ok((name.clone(), ShardFile::read(text, name)?)))
        .collect::<anyhow::Result<_>>()?;
    let records = merge(&shards)?;
    let (name, first) = &shards[0];
    let rebuilt = exp.identity();
    if rebuilt != first.sweep {
        anyhow::bail!(
            "{name}: the sweep rebuilt from its command line ({rebuilt}) is not the one the shards ran ({}): a file it reads (zones, airspace, requests) has changed, or this is another build of muse",
            first.sweep
        );
    }
    println!(
        "merged {} shards, {} runs of sweep {}{} into {}",
        shards.len(),
        records.len(),
        first.sweep,
        first.study.as_ref().map_or(String::new(), |s| format!(
            " (study {}: {})",
            s.file, s.title
        )),
        shown.display()
    );
    let results = exp.results(&records)?;
    let names = write_results(&results, out)?;
    println!("wrote {}/{{{names}}}", shown.display());
    print!("{}", results.table);
    report(first.study.as_ref(), shown, &results, exp)
}
