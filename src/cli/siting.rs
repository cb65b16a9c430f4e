//! `muse siting`: where to add pads (docs/reference.md#airspace-from-pads) — lazy greedy by exact
//! simulation, against greedy maximum coverage and k-means of demand for the same number of pads.

mod report;
mod shards;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant as WallClock;

use anyhow::Context as _;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use muse_airspace::builder::BuildOptions;
use muse_airspace::plane::Plane;
use muse_model::time::parse_clock;
use muse_model::{Instant, Millis, Zone};
use muse_sim::customers::trips::TripSpec;
use muse_sim::demand::BookingLead;
use muse_sim::experiment::Shard;
use muse_siting::baselines::{kmeans_sites, max_coverage};
use muse_siting::greedy::{BATCH, first_round, lazy_greedy_from};
use muse_siting::shard::{FILE, ShardFile};
use muse_siting::{Evaluation, Siting, SitingInput};

use super::common::{FlightArgs, SINGAPORE_HDB, customers_file, read_customers, zones_spec};
use super::output;
use super::ranges;

/// Arguments of `muse siting`.
#[derive(Debug, Args)]
pub struct SitingArgs {
    /// How many pads to add, from 1 to 1000 (at most the number of candidates).
    #[arg(long, default_value_t = 10, allow_negative_numbers = true, value_parser = ranges::add_pads)]
    add: usize,
    /// The pads already there: a pads file (CSV `id,lon,lat[,name]` or GeoJSON points).
    /// Default: Singapore's 77 stations (`singapore-77`).
    #[arg(long, value_name = "FILE", requires_all = ["candidates", "customers"])]
    pads: Option<PathBuf>,
    /// The pads that may be added, a pads file. Default: the 1,038 other HDB multi-storey
    /// car parks (with the default pads only).
    #[arg(long, value_name = "FILE", requires = "pads")]
    candidates: Option<PathBuf>,
    /// Customers CSV (`id,lon,lat[,weight]`), where deliveries start and end, or
    /// `singapore-hdb`: the embedded list of all 2,257 HDB car parks, each of weight 1, as a
    /// proxy for where Singapore's residents live (the customers of the default pads).
    #[arg(long, value_name = "FILE|singapore-hdb", requires = "pads")]
    customers: Option<PathBuf>,
    /// The plane airspaces are built in (with `--pads`): `utm` (default), `EPSG:3414`, a
    /// WGS84 UTM zone `EPSG:326zz`/`EPSG:327zz`, or `stereographic`. The default pads use
    /// SVY21 (EPSG:3414), as the built-in scenarios.
    #[arg(long, value_name = "CRS", requires = "pads")]
    crs: Option<String>,
    /// No-fly zone file (ED-318 GeoJSON or ED-269 JSON; zones known from the start); repeat
    /// for several, or `none`. Default: the CBD zone with the default pads, none with
    /// `--pads`.
    #[arg(long, value_name = "FILE|none")]
    zones: Vec<PathBuf>,
    /// Requests drawn per day, from 1 to 10000000.
    #[arg(long, default_value_t = 5_000, allow_negative_numbers = true, value_parser = ranges::requests)]
    count: usize,
    /// Seeded days every pad set is judged on, from 1 to 1000: seeds `--seed` onwards.
    #[arg(long, default_value_t = 5, allow_negative_numbers = true, value_parser = ranges::siting_days)]
    days: usize,
    /// The first day's seed, a whole number from 0 to 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = ranges::seed)]
    seed: u64,
    /// Start of the departure window, local time (`+08:00`, on the scenario's date).
    #[arg(long, default_value = "08:00", value_name = "HH:MM")]
    from: String,
    /// End of the departure window (exclusive), local time.
    #[arg(long, default_value = "20:00", value_name = "HH:MM")]
    to: String,
    /// The last mile: a customer is served by its nearest pad within this distance, metres
    /// (straight line), from 0 to 100000.
    #[arg(long, default_value_t = 1_000.0, value_name = "M", allow_negative_numbers = true, value_parser = ranges::last_mile_m)]
    last_mile_m: f64,
    /// Seed of the k-means baseline's k-means++ draw, a whole number from 0 to
    /// 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = ranges::seed)]
    kmeans_seed: u64,
    #[command(flatten)]
    flight: FlightArgs,
    /// Evaluate only shard K of N of the greedy's first round (candidates `c` with
    /// `c mod N = K`, counted from 0) and write it to `--out` as `shard.json`, for a cluster:
    /// then `--from-shards` with every shard's folder finishes the greedy.
    #[arg(long, value_name = "K/N", conflicts_with = "from_shards")]
    shard: Option<String>,
    /// Finish the greedy from the first round of these shards (`--shard` folders, every shard
    /// once, made with the same options and input files).
    #[arg(long, value_name = "DIR", num_args = 1..)]
    from_shards: Vec<PathBuf>,
    /// Output folder: `siting.csv` (the greedy's picks), `curve.csv` and `curve.svg`
    /// (delivered requests against pads added, for each method), `airspace.geojson` (the
    /// airspace with the greedy's pads); with `--shard`, `shard.json` alone. The folder is
    /// replaced whole.
    #[arg(long, value_name = "DIR", default_value = "siting")]
    out: PathBuf,
}

/// The problem and where it came from, for messages.
struct Loaded {
    input: SitingInput,
    source: String,
    /// Whether it is Singapore's (its land outline and data attribution go on the map).
    singapore: bool,
}

impl SitingArgs {
    /// The zones: `none`, the files given, or the default.
    fn zones(&self, default: &[Zone]) -> anyhow::Result<Vec<Zone>> {
        Ok(zones_spec(&self.zones)?.read(default)?)
    }

    /// The seeded days.
    fn days(&self, scenario: &muse_scenario::Scenario) -> anyhow::Result<Vec<TripSpec>> {
        let clock = |name: &str, v: &str| -> anyhow::Result<Millis> {
            parse_clock(v).with_context(|| format!("--{name} `{v}` is not a local time HH:MM[:SS]"))
        };
        let start = Instant::at_local(scenario.date, clock("from", &self.from)?, scenario.offset);
        let end = Instant::at_local(scenario.date, clock("to", &self.to)?, scenario.offset);
        if end <= start {
            anyhow::bail!("--to {} must be after --from {}", self.to, self.from);
        }
        (0..self.days as u64)
            .map(|d| {
                let seed = self.seed.checked_add(d).with_context(|| {
                    format!(
                        "--seed {} + {} days passes the largest seed",
                        self.seed, self.days
                    )
                })?;
                Ok(TripSpec {
                    count: self.count,
                    start,
                    end,
                    seed,
                    booking_lead: BookingLead::NONE,
                })
            })
            .collect()
    }

    /// What a shard's first round depends on: the demand, the flight parameters and the
    /// input files (by a digest of their bytes), not `--add` or the baselines' seed.
    fn problem_key(&self) -> anyhow::Result<String> {
        let file = |p: &Option<PathBuf>| -> anyhow::Result<String> {
            p.as_deref()
                .map_or(Ok("default".to_owned()), shards::file_digest)
        };
        let customers = match self.customers.as_deref() {
            Some(arg) if customers_file(arg).is_none() => SINGAPORE_HDB.to_owned(),
            _ => file(&self.customers)?,
        };
        let zones: Vec<String> = self
            .zones
            .iter()
            .map(|z| {
                if z.as_os_str() == "none" {
                    Ok("none".to_owned())
                } else {
                    shards::file_digest(z)
                }
            })
            .collect::<anyhow::Result<_>>()?;
        let flight = serde_json::to_string(&self.flight.record())?;
        Ok(format!(
            "pads {} candidates {} customers {} crs {:?} zones [{}]; {} days of {} from seed {}, \
             {}–{}, last mile {} m; {flight}",
            file(&self.pads)?,
            file(&self.candidates)?,
            customers,
            self.crs,
            zones.join(" "),
            self.days,
            self.count,
            self.seed,
            self.from,
            self.to,
            self.last_mile_m
        ))
    }

    /// Reads or builds the problem.
    fn load(&self) -> anyhow::Result<Loaded> {
        let scenario = muse_scenario::by_name(muse_scenario::SINGAPORE_77)?;
        let days = self.days(scenario)?;
        let params = self.flight.params()?;
        let Some(pads) = &self.pads else {
            return Ok(Loaded {
                input: SitingInput {
                    existing: muse_scenario::station_nodes()?,
                    candidates: muse_scenario::candidates::candidate_pads()?,
                    customers: muse_scenario::candidates::residential_customers()?,
                    last_mile_m: self.last_mile_m,
                    days,
                    params,
                    zones: self.zones(&scenario.zones)?,
                    build: muse_scenario::singapore_build_options(),
                },
                source: "Singapore: the 77 stations, 1,038 candidate car parks, 2,257 HDB car \
                         parks as customers"
                    .to_owned(),
                singapore: true,
            });
        };
        let (Some(candidates), Some(customers)) = (&self.candidates, &self.customers) else {
            anyhow::bail!("--pads needs --candidates FILE and --customers FILE");
        };
        let plane = match &self.crs {
            Some(text) => Plane::parse(text).map_err(|e| anyhow::anyhow!("--crs: {e}"))?,
            None => Plane::Utm,
        };
        let input = SitingInput {
            existing: muse_formats::pads::read_pads_file(pads)?,
            candidates: muse_formats::pads::read_candidate_pads_file(candidates)?,
            customers: read_customers(customers)?,
            last_mile_m: self.last_mile_m,
            days,
            params,
            zones: self.zones(&[])?,
            build: BuildOptions {
                plane,
                ..BuildOptions::default()
            },
        };
        let customers = match customers_file(customers) {
            Some(file) => file.display().to_string(),
            None => format!("{SINGAPORE_HDB} ({} HDB car parks)", input.customers.len()),
        };
        Ok(Loaded {
            source: format!(
                "pads {}, candidates {}, customers {customers}",
                pads.display(),
                candidates.display(),
            ),
            input,
            singapore: false,
        })
    }
}

/// A bar of evaluations, shown once the work has run a second.
struct Evaluations {
    started: WallClock,
    shown: Option<ProgressBar>,
    total: u64,
}

impl Evaluations {
    fn update(&mut self, done: usize, picks: usize, k: usize) {
        let done = done as u64;
        if done > self.total {
            self.total = done + BATCH as u64;
        }
        if self.shown.is_none() && self.started.elapsed().as_secs_f64() > 1.0 {
            let bar = ProgressBar::new(self.total);
            bar.set_style(
                ProgressStyle::with_template(
                    "{msg} [{bar:40}] {pos}/{len} evaluations ({elapsed}, ETA {eta})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            self.shown = Some(bar);
        }
        if let Some(bar) = &self.shown {
            bar.set_length(self.total);
            bar.set_position(done);
            bar.set_message(format!("siting: pick {}/{k}", (picks + 1).min(k)));
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.shown {
            bar.finish_and_clear();
        }
    }
}

/// One method's curve: delivered requests with 0, 1, …, k pads added.
pub struct Curve {
    /// The method's name.
    pub method: &'static str,
    /// For each k from 1: the candidates added, and the evaluation of the set.
    pub steps: Vec<(Vec<usize>, Evaluation)>,
}

/// Runs `muse siting`.
pub fn run(args: &SitingArgs) -> anyhow::Result<ExitCode> {
    let inputs = output::Inputs::new()
        .add_all("--pads", args.pads.as_slice())
        .add_all("--candidates", args.candidates.as_slice())
        .customers(args.customers.as_deref())
        .add_all("--zones", &args.zones)
        .add_all("--from-shards", &args.from_shards);
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()
        .map_err(|e| anyhow::anyhow!("--shard: {e}"))?;
    let files = report::Files::new(&args.out, &inputs)?;
    let loaded = args.load()?;
    let problem = args.problem_key()?;
    let prepared = WallClock::now();
    let singapore = loaded.singapore;
    let siting = Siting::prepare(loaded.input)?;
    let prepare_s = prepared.elapsed().as_secs_f64();
    let k = args.add;
    let count = siting.candidates().len();
    if k > count && shard.is_none() {
        anyhow::bail!("--add {k}: there are only {count} candidate pads");
    }
    eprintln!(
        "MUSE siting — {}; {} days of {} requests, last mile {} m",
        loaded.source, args.days, args.count, args.last_mile_m
    );
    let mut bar = Evaluations {
        started: WallClock::now(),
        shown: None,
        total: (count + k.saturating_sub(1) * BATCH) as u64,
    };
    let started = WallClock::now();
    if let Some(shard) = shard {
        return run_shard(&siting, shard, &problem, files, &mut bar);
    }
    let first = if args.from_shards.is_empty() {
        None
    } else {
        Some(shards::merge(&args.from_shards, &problem, &siting)?)
    };
    let run = lazy_greedy_from(&siting, k, first, |p| bar.update(p.evaluations, p.picks, k))?;
    let greedy_s = started.elapsed().as_secs_f64();
    bar.finish();
    let baselines = WallClock::now();
    let greedy = Curve {
        method: "greedy-simulation",
        steps: run
            .picks
            .iter()
            .enumerate()
            .map(|(i, p)| (run.added()[..=i].to_vec(), p.after.clone()))
            .collect(),
    };
    let coverage_picks = max_coverage(&siting, k);
    let coverage = curve(
        &siting,
        "max-coverage",
        (1..=k).map(|j| coverage_picks[..j].to_vec()),
    )?;
    let kmeans = curve(
        &siting,
        "k-means",
        (1..=k)
            .map(|j| kmeans_sites(&siting, j, args.kmeans_seed))
            .collect::<Result<Vec<_>, _>>()?,
    )?;
    let baselines_s = baselines.elapsed().as_secs_f64();
    let curves = [greedy, coverage, kmeans];
    report::print_picks(&siting, &run);
    report::print_curves(&run.base, &curves);
    // Evaluations made here: the shards' first round was made elsewhere.
    let (here, merged) = if args.from_shards.is_empty() {
        (run.evaluations, String::new())
    } else {
        (
            run.evaluations - (count + 1),
            format!(", {} of them from the shards", count + 1),
        )
    };
    eprintln!(
        "  speed         {} evaluations{merged}; {here} here in {greedy_s:.1} s ({:.1} per \
         second, {} days each; {BATCH} at a time after the first round), baselines {:.1} s, \
         preparing {prepare_s:.2} s",
        run.evaluations,
        here as f64 / greedy_s.max(1e-9),
        siting.day_count(),
        baselines_s
    );
    let map = map_svg(&siting, &run.added(), singapore)?;
    let written = files.describe();
    files.write(&siting, &run, &curves, &map)?;
    eprintln!("  wrote         {written}");
    Ok(ExitCode::SUCCESS)
}

/// `map.svg`: the airspace with the greedy's pads, marked, on the land (Singapore's) with the
/// zones.
fn map_svg(siting: &Siting, added: &[usize], singapore: bool) -> anyhow::Result<String> {
    use muse_render::{MapInput, MapOptions, render_map};
    let airspace = siting.airspace(added)?;
    let land = if singapore {
        muse_scenario::singapore_land().0
    } else {
        Vec::new()
    };
    let zones = super::common::zone_layers(&airspace, &siting.input().zones)?;
    let existing = siting.input().existing.len();
    let mut input = MapInput::new(&airspace);
    input.land = &land;
    input.zones = zones;
    input.marked = (0..added.len())
        .map(|j| muse_model::NodeId((existing + j) as u32))
        .collect();
    input.marked_label = format!("Pads added (greedy by simulation, {})", added.len());
    let opts = MapOptions {
        width_px: 1_600,
        title: format!(
            "MUSE siting: {} pads and {} added by greedy simulation",
            existing,
            added.len()
        ),
        attribution: if singapore {
            muse_scenario::ATTRIBUTION.to_owned()
        } else {
            String::new()
        },
        label_stations: airspace.stations().count() <= super::common::MAX_LABELLED_STATIONS,
        ..MapOptions::default()
    };
    Ok(render_map(&input, &opts)?)
}

/// `--shard K/N`: the first round of shard K alone, into `shard.json`.
fn run_shard(
    siting: &Siting,
    shard: Shard,
    problem: &str,
    files: report::Files,
    bar: &mut Evaluations,
) -> anyhow::Result<ExitCode> {
    let started = WallClock::now();
    bar.total = (siting.candidates().len() / shard.of + 2) as u64;
    let first = first_round(siting, shard, |n| bar.update(n, 0, 1))?;
    bar.finish();
    let took = started.elapsed().as_secs_f64();
    let n = first.evaluations.len() + 1;
    let shown = files.shown().to_owned();
    files.write_shard(&ShardFile::new(problem, shard, siting, &first).to_json())?;
    eprintln!(
        "  shard         {}/{}: {n} evaluations in {took:.1} s ({:.1} per second); wrote \
         {shown}/{}; finish with --from-shards and every shard's folder",
        shard.index,
        shard.of,
        n as f64 / took.max(1e-9),
        FILE
    );
    Ok(ExitCode::SUCCESS)
}

/// Evaluates the sets of a baseline, one per k (in parallel).
fn curve(
    siting: &Siting,
    method: &'static str,
    sets: impl IntoIterator<Item = Vec<usize>>,
) -> anyhow::Result<Curve> {
    use rayon::prelude::*;
    let sets: Vec<Vec<usize>> = sets.into_iter().collect();
    let evaluated: Vec<Evaluation> = sets
        .par_iter()
        .map(|s| siting.evaluate(s))
        .collect::<Result<_, _>>()?;
    Ok(Curve {
        method,
        steps: sets.into_iter().zip(evaluated).collect(),
    })
}
