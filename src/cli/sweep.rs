//! `muse sweep`: the paper's experiment — request counts × repetitions × scenario variants
//! (the levers of `--vary`); with `--vary announce-lead`, the announcement-lead sweep; from a
//! study file, sharded, or merged from shards (`muse sweep merge`).

mod args;
mod build;
mod lead;
mod levers;
mod merge;

use std::process::ExitCode;

use anyhow::Context as _;
use clap::ArgMatches;
use muse_sim::experiment::{Shard, Study};

pub use args::{SweepArgs, SweepCommand};
use build::paper;
use lead::lead;
use levers::{ANNOUNCE_LEAD, check_given};
use merge::inputs_of;

use crate::cli::common::refuse_withdrawn;
use crate::cli::experiment::{Launch, dry_run, launch};
use crate::cli::{output, study};

/// Runs `muse sweep`; `matches` are its own, to tell what was given beside `--study`.
pub fn run(args: &SweepArgs, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    if let Some(SweepCommand::Merge(m)) = &args.command {
        return merge::run(m);
    }
    if matches.value_source("count") == Some(clap::parser::ValueSource::CommandLine) {
        anyhow::bail!(
            "--count: a sweep's request counts are --counts (e.g. 1000:10000:1000 or 3000,6000)"
        );
    }
    let Some(path) = &args.study else {
        return run_args(args, &std::env::args().skip(1).collect::<Vec<_>>(), None);
    };
    let study = study::open::<SweepArgs>(path, "sweep", matches)?;
    let extra = how_to_run(args, &study::out(&study, matches, &args.out));
    let sweep: SweepArgs = study::parse(&study, "sweep", &extra)?;
    run_args(&sweep, &study.command_line("sweep", &extra), Some(&study))
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
fn run_args(
    args: &SweepArgs,
    command_line: &[String],
    study: Option<&Study>,
) -> anyhow::Result<ExitCode> {
    let announce_lead = args.vary.iter().any(|v| v == ANNOUNCE_LEAD);
    if announce_lead && args.vary.iter().any(|v| v != ANNOUNCE_LEAD) {
        anyhow::bail!(
            "--vary announce-lead cannot be combined with other --vary values (it is its own sweep: leads × counts × repetitions)"
        );
    }
    if !announce_lead && (args.leads.is_some() || !args.announce_zones.is_empty()) {
        anyhow::bail!("--leads and --announce-zones apply only with --vary announce-lead");
    }
    check_given(&args.levers, &args.vary)?;
    if let Some(n) = args.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("--threads")?;
    }
    let how = Launch {
        out: &args.out,
        shard: args.shard.as_deref().map(Shard::parse).transpose()?,
        command_line,
        study,
    };
    let world = args.world.load()?;
    refuse_withdrawn(&world, "sweep")?;
    let inputs = match study {
        Some(s) => inputs_of(args).add("--study", &s.path),
        None => inputs_of(args),
    };
    if announce_lead {
        let (exp, heading) = lead(args, &world)?;
        if args.dry_run {
            return Ok(dry_run(&exp, &how));
        }
        let out = output::folder("--out", &args.out, &inputs)?;
        launch(&exp, &how, out, &heading)
    } else {
        let airspaces = std::sync::OnceLock::new();
        let (exp, heading) = paper(args, &world, &airspaces)?;
        if args.dry_run {
            return Ok(dry_run(&exp, &how));
        }
        let out = output::folder("--out", &args.out, &inputs)?;
        launch(&exp, &how, out, &[heading])
    }
}
