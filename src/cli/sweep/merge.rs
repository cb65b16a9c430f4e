//! `muse sweep merge DIR...`: the shards of one sweep merged back into exactly the files of
//! one machine (see [`muse_sim::experiment::merge`]); the sweep is rebuilt from the command
//! line its first shard recorded, for its plots and to check it is the one the shards ran.

use std::process::ExitCode;

use anyhow::Context as _;
use clap::Parser;

use super::args::{MergeArgs, SweepArgs};
use super::build::paper;
use super::lead::lead;
use super::levers::ANNOUNCE_LEAD;
use crate::cli::common::refuse_withdrawn;
use crate::cli::experiment::{SHARD_FILE, merged};
use crate::cli::output::{self, Inputs};

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

/// The files a sweep reads: its world, the zones it announces.
pub fn inputs_of(args: &SweepArgs) -> Inputs {
    Inputs::new()
        .world(&args.world)
        .add_all("--announce-zones", &args.announce_zones)
}

/// Runs `muse sweep merge`.
pub fn run(args: &MergeArgs) -> anyhow::Result<ExitCode> {
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
    let out = output::folder(
        "--out",
        &args.out,
        &inputs_of(&sweep).add_all("the shard", &files),
    )?;
    let rebuilt = || format!("{name}: rebuilding the sweep from its command line");
    let world = sweep.world.load().with_context(rebuilt)?;
    refuse_withdrawn(&world, "sweep").with_context(rebuilt)?;
    if sweep.vary.iter().any(|v| v == ANNOUNCE_LEAD) {
        let (exp, _) = lead(&sweep, &world).with_context(rebuilt)?;
        merged(&exp, &texts, out, &args.out)
    } else {
        let airspaces = std::sync::OnceLock::new();
        let (exp, _) = paper(&sweep, &world, &airspaces).with_context(rebuilt)?;
        merged(&exp, &texts, out, &args.out)
    }
}
