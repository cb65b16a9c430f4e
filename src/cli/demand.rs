//! `muse demand`: generate a seeded requests file (SPEC §8).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::Args;
use muse_formats::requests::write_requests;
use muse_model::Instant;
use muse_model::time::parse_clock;
use muse_sim::demand::{DemandSpec, OdRule, generate};

use super::common::{RangeArgs, World, WorldArgs, write_atomically};

/// Origin–destination rule on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OdArg {
    /// Uniform over distinct station pairs (the paper).
    Uniform,
    /// Only pairs whose free-flow time fits the battery.
    InRange,
}

/// Demand options shared by `muse demand` and `muse simulate`.
#[derive(Debug, Args, Clone)]
pub struct DemandArgs {
    /// Number of requests.
    #[arg(long, default_value_t = 5_000)]
    pub count: usize,
    /// Seed of the generator.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Start of the departure window, local time on the scenario's date.
    #[arg(long, default_value = "08:00", value_name = "HH:MM")]
    pub from: String,
    /// End of the departure window (exclusive), local time.
    #[arg(long, default_value = "20:00", value_name = "HH:MM")]
    pub to: String,
    /// Origin–destination rule.
    #[arg(long, value_enum, default_value_t = OdArg::Uniform)]
    pub od: OdArg,
}

impl DemandArgs {
    /// The generation spec for a world.
    pub fn spec(&self, world: &World, range: RangeArgs) -> anyhow::Result<DemandSpec> {
        let clock = |name: &str, v: &str| {
            parse_clock(v).with_context(|| format!("--{name} `{v}` is not a local time HH:MM[:SS]"))
        };
        let start = Instant::at_local(world.date, clock("from", &self.from)?, world.offset);
        let end = Instant::at_local(world.date, clock("to", &self.to)?, world.offset);
        if end <= start {
            anyhow::bail!("--to {} must be after --from {}", self.to, self.from);
        }
        let od = match self.od {
            OdArg::Uniform => OdRule::Uniform,
            OdArg::InRange => OdRule::InRange {
                speed: range.speed()?,
                max_flight: range.t_max()?,
            },
        };
        Ok(DemandSpec {
            count: self.count,
            start,
            end,
            seed: self.seed,
            od,
        })
    }
}

/// Arguments of `muse demand`.
#[derive(Debug, Args)]
pub struct DemandCmd {
    #[command(flatten)]
    demand: DemandArgs,
    #[command(flatten)]
    world: WorldArgs,
    #[command(flatten)]
    range: RangeArgs,
    /// Output CSV.
    #[arg(long, value_name = "FILE", default_value = "requests.csv")]
    out: PathBuf,
}

/// Runs `muse demand`.
pub fn run(args: &DemandCmd) -> anyhow::Result<ExitCode> {
    let world = args.world.load()?;
    let spec = args.demand.spec(&world, args.range)?;
    let requests = generate(&world.airspace, &spec)?;
    write_atomically(
        &args.out,
        &write_requests(&requests, &world.airspace, world.offset),
    )?;
    println!(
        "wrote {} requests (seed {}) to {}",
        requests.len(),
        spec.seed,
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
