//! The world and parameters of a run, for `muse verify` and `muse view`: those `summary.json`
//! recorded beside the plans (or `--summary FILE`), each overridden by the option the command
//! line gives, and said on standard error: which came from where.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::ArgMatches;
use muse_formats::params::Field;
use muse_model::{EdgeRule, FlightParams};
use muse_sim::metrics::ParamsRecord;
use muse_sim::metrics::recorded::{WorldRecord, read_recorded};

use super::common::{EdgeRuleArg, FlightArgs, LayoutArg, World, WorldArgs};
use super::overrides::{Overridable, Summary, given, overridden};

/// What a command reading the plans file `plans` reads, which its outputs must not overwrite:
/// the plans, the world's files and the summary `found` (named `--summary` when `given`, else
/// as the one beside the plans).
pub fn plans_inputs(
    plans: &Path,
    found: Option<&Summary>,
    given: bool,
    world: &WorldArgs,
) -> super::output::Inputs {
    let inputs = super::output::Inputs::new()
        .add("--plans", plans)
        .world(world);
    match found {
        Some(s) if given => inputs.add("--summary", &s.path),
        Some(s) => inputs.add("the summary beside --plans", &s.path),
        None => inputs,
    }
}

/// The world of the run behind the plans file `plans` (whose summary is `found`) at its
/// layers, and its flight parameters when `flight` is given: the summary's, each option the
/// command line gives overriding its own. What was used is said on standard error.
pub fn world_of_run(
    plans: &Path,
    found: Option<&Summary>,
    world: &WorldArgs,
    layers: &super::layers::LayersArgs,
    flight: Option<&FlightArgs>,
    matches: &ArgMatches,
) -> anyhow::Result<(World, Option<FlightParams>)> {
    let mut notes = Vec::new();
    let world_args = world_args(world, matches, found, &mut notes)?;
    let layers = super::layers::recorded_layers(layers, matches, found, &mut notes)?;
    let params = flight
        .map(|f| flight_params(f, matches, found, &mut notes))
        .transpose()?;
    let world = super::layers::layered(load_world(&world_args, found)?, &layers)?;
    for line in said(plans, found, &world, params.as_ref(), &notes) {
        eprintln!("{line}");
    }
    Ok((world, params))
}

/// The summary that goes with `plans`: `given` (which must exist), else the `summary.json`
/// beside the plans file if there is one.
pub fn find(plans: &Path, given: Option<&Path>) -> anyhow::Result<Option<Summary>> {
    let path = if let Some(p) = given {
        p.to_path_buf()
    } else {
        let beside = plans.with_file_name("summary.json");
        if !beside.is_file() {
            return Ok(None);
        }
        beside
    };
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("--summary: cannot read {}", path.display()))?;
    let recorded = read_recorded(&text, &path.display().to_string()).map_err(anyhow::Error::msg)?;
    Ok(Some(Summary { path, recorded }))
}

/// The world arguments to load: the command line's `cli`, where it gives the airspace (or the
/// zones), else the summary's; each override goes into `notes`.
pub fn world_args(
    cli: &WorldArgs,
    matches: &ArgMatches,
    summary: Option<&Summary>,
    notes: &mut Vec<String>,
) -> anyhow::Result<WorldArgs> {
    let Some(s) = summary else {
        return Ok(cli.clone());
    };
    let name = s.path.display();
    let Some(rec) = &s.recorded.world else {
        notes.push(format!(
            "{name} records no world (an older muse wrote it): the airspace and zones from the \
             command line and the defaults"
        ));
        return Ok(cli.clone());
    };
    let mut out = cli.clone();
    let airspace_given = ["scenario", "airspace", "synthetic"]
        .iter()
        .any(|id| given(matches, id));
    let mine = cli.record()?;
    let recorded_airspace = describe_airspace(rec);
    if airspace_given {
        let same = (&mine.scenario, &mine.airspace, &mine.synthetic)
            == (&rec.scenario, &rec.airspace, &rec.synthetic);
        notes.push(if same {
            format!("{} given: as in {name}", given_airspace(cli))
        } else {
            format!(
                "{} given: overrides {name}'s airspace ({recorded_airspace})",
                given_airspace(cli)
            )
        });
    } else {
        apply_airspace(rec, &mut out).with_context(|| format!("{name}: field `world`"))?;
    }
    let recorded_zones = describe_zones(rec.zones.as_deref());
    if cli.zones.is_empty() {
        out.zones = match &rec.zones {
            None => Vec::new(),
            Some(files) if files.is_empty() => vec![PathBuf::from("none")],
            Some(files) => files.iter().map(PathBuf::from).collect(),
        };
    } else {
        let zones: Vec<String> = cli.zones.iter().map(|z| z.display().to_string()).collect();
        let option = format!("--zones {}", zones.join(" --zones "));
        notes.push(if mine.zones == rec.zones {
            format!("{option} given: as in {name}")
        } else {
            format!("{option} given: overrides {name}'s zones ({recorded_zones})")
        });
    }
    Ok(out)
}

/// Sets the airspace of `out` to the one `rec` records.
fn apply_airspace(rec: &WorldRecord, out: &mut WorldArgs) -> anyhow::Result<()> {
    match (&rec.scenario, &rec.airspace, &rec.synthetic) {
        (Some(name), None, None) => out.scenario = Some(name.clone()),
        (None, Some(path), None) => out.airspace = Some(PathBuf::from(path)),
        (None, None, Some(spec)) => {
            out.synthetic = Some(match spec.layout.as_str() {
                "grid" => LayoutArg::Grid,
                "geometric" => LayoutArg::Geometric,
                other => {
                    anyhow::bail!("synthetic.layout `{other}`: expected `grid` or `geometric`")
                }
            });
            out.nodes = Some(spec.nodes);
            out.spacing_m = spec.spacing_m;
            out.station_share = spec.station_share;
            out.synthetic_seed = spec.seed;
        }
        _ => anyhow::bail!("exactly one of `scenario`, `airspace` and `synthetic` must be set"),
    }
    Ok(())
}

/// The airspace the command line names, as its options.
fn given_airspace(cli: &WorldArgs) -> String {
    if let Some(name) = &cli.scenario {
        format!("--scenario {name}")
    } else if let Some(path) = &cli.airspace {
        format!("--airspace {}", path.display())
    } else {
        "--synthetic".to_owned()
    }
}

/// The airspace a summary records, for messages.
fn describe_airspace(rec: &WorldRecord) -> String {
    match (&rec.scenario, &rec.airspace, &rec.synthetic) {
        (Some(name), _, _) => format!("embedded {name}"),
        (_, Some(path), _) => path.clone(),
        (_, _, Some(s)) => format!(
            "synthetic {}, {} nodes, spacing {} m, station share {}, seed {}",
            s.layout, s.nodes, s.spacing_m, s.station_share, s.seed
        ),
        _ => "none".to_owned(),
    }
}

/// The zones a summary records, for messages.
fn describe_zones(zones: Option<&[String]>) -> String {
    match zones {
        None => "the airspace's own".to_owned(),
        Some([]) => "none".to_owned(),
        Some(files) => files.join(", "),
    }
}

/// The flight options and the summary's field each is recorded in, by clap id (the same
/// name).
const FLIGHT_OPTIONS: [&str; 11] = Field::NAMES;

/// The flight parameters: the summary's, each overridden by the option the command line
/// gives (said in `notes`); the command line's and the defaults without a summary.
pub fn flight_params(
    cli: &FlightArgs,
    matches: &ArgMatches,
    summary: Option<&Summary>,
    notes: &mut Vec<String>,
) -> anyhow::Result<FlightParams> {
    let Some(s) = summary else {
        return cli.params();
    };
    let name = s.path.display();
    let recorded = args_of(&s.recorded.parameters);
    // The summary's own values must hold, whatever overrides them.
    recorded.params().map_err(|e| {
        let mut message = e.to_string();
        for id in FLIGHT_OPTIONS {
            message = message.replace(
                &format!("--{}", id.replace('_', "-")),
                &format!("`parameters.{id}`"),
            );
        }
        anyhow::anyhow!("{name}: {message}")
    })?;
    let mut merged = overridden(&recorded, cli, &FLIGHT_OPTIONS, matches, s, notes);
    // A rule given without its headway takes the rule's default, not the summary's headway.
    if given(matches, "edge_rule") && !given(matches, "headway_s") {
        merged.headway_s = None;
    }
    merged.params()
}

/// The flight options a summary's parameters stand for.
fn args_of(p: &ParamsRecord) -> FlightArgs {
    FlightArgs {
        range: super::common::RangeArgs {
            speed_kmh: p.speed_kmh,
            max_flight_min: p.max_flight_min,
        },
        node_separation_s: p.node_separation_s,
        edge_rule: if p.edge_rule == "headway" {
            EdgeRuleArg::Headway
        } else {
            EdgeRuleArg::Exclusive
        },
        headway_s: p.headway_s,
        max_ground_delay_s: p.max_ground_delay_s,
        battery_swap_s: p.battery_swap_s,
        max_legs: p.max_legs,
        max_trip_min: p.max_trip_min,
        separation_m: p.separation_m,
        vertical_separation_m: p.vertical_separation_m,
    }
}

/// The flight options by clap id ([`FLIGHT_OPTIONS`]), `none` for an option left unset.
impl Overridable for FlightArgs {
    fn value(&self, id: &str) -> String {
        let opt = |v: Option<f64>| v.map_or("none".to_owned(), |v| v.to_string());
        match id {
            "speed_kmh" => self.range.speed_kmh.to_string(),
            "max_flight_min" => self.range.max_flight_min.to_string(),
            "node_separation_s" => self.node_separation_s.to_string(),
            "edge_rule" => match self.edge_rule {
                EdgeRuleArg::Exclusive => "exclusive".to_owned(),
                EdgeRuleArg::Headway => "headway".to_owned(),
            },
            "headway_s" => opt(self.headway_s),
            "max_ground_delay_s" => self.max_ground_delay_s.to_string(),
            "battery_swap_s" => opt(self.battery_swap_s),
            "max_legs" => self.max_legs.map_or("none".to_owned(), |k| k.to_string()),
            "max_trip_min" => opt(self.max_trip_min),
            "separation_m" => opt(self.separation_m),
            "vertical_separation_m" => opt(self.vertical_separation_m),
            _ => unreachable!("every id of FLIGHT_OPTIONS is listed"),
        }
    }

    fn set(&mut self, from: &FlightArgs, id: &str) {
        match id {
            "speed_kmh" => self.range.speed_kmh = from.range.speed_kmh,
            "max_flight_min" => self.range.max_flight_min = from.range.max_flight_min,
            "node_separation_s" => self.node_separation_s = from.node_separation_s,
            "edge_rule" => self.edge_rule = from.edge_rule,
            "headway_s" => self.headway_s = from.headway_s,
            "max_ground_delay_s" => self.max_ground_delay_s = from.max_ground_delay_s,
            "battery_swap_s" => self.battery_swap_s = from.battery_swap_s,
            "max_legs" => self.max_legs = from.max_legs,
            "max_trip_min" => self.max_trip_min = from.max_trip_min,
            "separation_m" => self.separation_m = from.separation_m,
            "vertical_separation_m" => self.vertical_separation_m = from.vertical_separation_m,
            _ => unreachable!("every id of FLIGHT_OPTIONS is listed"),
        }
    }
}

/// Loads the world of `args`, saying in an error that it came (in part) from `summary`.
pub fn load_world(args: &WorldArgs, summary: Option<&Summary>) -> anyhow::Result<World> {
    let world = args.load();
    match summary {
        Some(s) if s.recorded.world.is_some() => world.with_context(|| {
            format!(
                "loading the world {} records (--scenario, --airspace, --synthetic and --zones \
                 override it)",
                s.path.display()
            )
        }),
        _ => world,
    }
}

/// Where the world and parameters came from, then the overrides: the lines said on standard
/// error before a command's own output.
pub fn said(
    plans: &Path,
    summary: Option<&Summary>,
    world: &World,
    params: Option<&FlightParams>,
    notes: &[String],
) -> Vec<String> {
    let used = match params {
        Some(p) => format!("{}; {}", describe_world(world), describe_params(p)),
        None => describe_world(world),
    };
    let mut lines = vec![match summary {
        Some(s) => format!("parameters from {}: {used}", s.path.display()),
        None => format!(
            "no summary.json beside {}: the command line and the defaults: {used}",
            plans.display()
        ),
    }];
    lines.extend(notes.iter().map(|n| format!("  {n}")));
    lines
}

/// The airspace and zones loaded, for messages.
fn describe_world(world: &World) -> String {
    let zones = if world.zones.is_empty() {
        "no zones".to_owned()
    } else {
        let ids: Vec<&str> = world.zones.iter().map(|z| z.id.as_str()).collect();
        format!("zones {}", ids.join(", "))
    };
    match describe_layers(&world.airspace) {
        Some(layers) => format!("{}, {layers}, {zones}", world.airspace_source),
        None => format!("{}, {zones}", world.airspace_source),
    }
}

/// The layering of `airspace`, for messages: `4 layers from 60 m, 9.144 m apart, climbing at
/// 5 m/s, heading rule sectors`; `None` when flat.
fn describe_layers(airspace: &muse_model::Airspace) -> Option<String> {
    airspace.layers().map(|l| {
        format!(
            "{} layers from {} m, {} m apart, climbing at {} m/s, heading rule {}",
            l.count,
            l.base.m(),
            l.spacing.m(),
            f64::from(l.climb_mm_per_s) / 1e3,
            l.heading_rule
        )
    })
}

/// Flight parameters, for messages.
fn describe_params(p: &FlightParams) -> String {
    let secs = |m: muse_model::Millis| m.as_secs_f64();
    let mut parts = vec![
        format!("{} km/h", p.speed.kmh()),
        format!("battery {} min", secs(p.max_flight) / 60.0),
        format!("tau {} s", secs(p.node_separation)),
        match p.edge_rule {
            EdgeRule::Exclusive => "exclusive edges".to_owned(),
            EdgeRule::Headway(h) => format!("headway {} s", secs(h)),
        },
    ];
    parts.push(if p.max_ground_delay == muse_model::Millis::ZERO {
        "no ground delay".to_owned()
    } else {
        format!("ground delay up to {} s", secs(p.max_ground_delay))
    });
    parts.push(match p.battery_swap {
        None => "no battery swaps".to_owned(),
        Some(s) => match s.max_legs {
            None => format!("battery swaps {} s", secs(s.time)),
            Some(k) => format!("battery swaps {} s, at most {k} legs", secs(s.time)),
        },
    });
    if let Some(m) = p.max_trip {
        parts.push(format!("deadline {} min", secs(m) / 60.0));
    }
    // Only when on: the description of a day without it is as before the rule.
    if p.separation.is_on() {
        let vertical = p
            .separation
            .vertical
            .map_or(String::new(), |v| format!(" or {v} m vertically"));
        parts.push(format!(
            "metric separation {} m{vertical}",
            p.separation.horizontal
        ));
    }
    parts.join(", ")
}
