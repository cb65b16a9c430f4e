//! Options shared by several commands: which airspace and zones, and flight parameters.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::Args;
use clap::builder::PossibleValuesParser;
use muse_formats::params::ParamsRecord;
use muse_model::{Airspace, Millis, Speed, Zone};
use muse_sim::metrics::WorldRecord;
use muse_sim::world::{AirspaceSpec, WorldError, WorldSpec, ZonesSpec};

use super::ranges;

/// Which airspace and zones to work on.
#[derive(Debug, Args, Clone)]
pub struct WorldArgs {
    /// Built-in scenario: `singapore-77` (the default: 77 k-means-chosen car parks) or
    /// `singapore-all` (all 1,115 HDB multi-storey car parks); both with the CBD zone.
    #[arg(
        long,
        value_name = "NAME",
        value_parser = PossibleValuesParser::new(muse_scenario::SCENARIOS),
        conflicts_with_all = ["airspace", "synthetic"]
    )]
    pub scenario: Option<String>,
    /// Airspace GeoJSON (docs/reference.md#airspace) instead of a built-in scenario.
    #[arg(long, value_name = "FILE", conflicts_with = "synthetic")]
    pub airspace: Option<PathBuf>,
    /// A synthetic airspace instead of a built-in scenario: a `grid` (4-neighbour corridors)
    /// or `geometric` (uniform random points, Delaunay); needs `--nodes`.
    #[arg(long, value_enum, value_name = "LAYOUT", requires = "nodes")]
    pub synthetic: Option<LayoutArg>,
    /// Synthetic airspace: number of nodes, from 2 to 1000000.
    #[arg(long, value_name = "N", requires = "synthetic", allow_negative_numbers = true, value_parser = ranges::nodes)]
    pub nodes: Option<usize>,
    /// Synthetic airspace: grid spacing, or mean nearest-neighbour distance, metres, from 1
    /// to 100000 (the airspace spans at most 2,000 km).
    #[arg(
        long,
        value_name = "M",
        default_value_t = 1_500.0,
        requires = "synthetic",
        allow_negative_numbers = true,
        value_parser = ranges::spacing_m
    )]
    pub spacing_m: f64,
    /// Synthetic airspace: the fraction of nodes that are stations, from 0.001 to 1 (at least
    /// 2 stations).
    #[arg(
        long,
        value_name = "SHARE",
        default_value_t = 0.1,
        requires = "synthetic",
        allow_negative_numbers = true,
        value_parser = ranges::station_share
    )]
    pub station_share: f64,
    /// Synthetic airspace: seed of the points and of the choice of stations, a whole number
    /// from 0 to 18446744073709551615.
    #[arg(
        long,
        value_name = "SEED",
        default_value_t = 1,
        requires = "synthetic",
        allow_negative_numbers = true,
        value_parser = ranges::seed
    )]
    pub synthetic_seed: u64,
    /// No-fly zone file (ED-318 GeoJSON or ED-269 JSON); repeat for several, or `none`.
    /// Default: the scenario's zones (the CBD zone) with a built-in scenario, no zones with
    /// `--airspace` or `--synthetic`.
    #[arg(long, value_name = "FILE|none")]
    pub zones: Vec<PathBuf>,
}

/// The layout of a synthetic airspace on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LayoutArg {
    /// A square grid, 4-neighbour corridors.
    Grid,
    /// Uniform random points joined by Delaunay triangulation and collinear joining.
    Geometric,
}

/// The world a day is planned on ([`muse_sim::world`]): what [`WorldArgs::load`] loads.
pub use muse_sim::world::World;

impl WorldArgs {
    /// The synthetic airspace spec these arguments describe, if any.
    fn synthetic_spec(&self) -> Option<muse_scenario::SyntheticSpec> {
        let layout = match self.synthetic? {
            LayoutArg::Grid => muse_scenario::Layout::Grid,
            LayoutArg::Geometric => muse_scenario::Layout::Geometric,
        };
        Some(muse_scenario::SyntheticSpec {
            layout,
            nodes: self.nodes.unwrap_or(0),
            spacing_m: self.spacing_m,
            station_share: self.station_share,
            seed: self.synthetic_seed,
        })
    }

    /// The airspace these arguments name: `--airspace`, `--synthetic`, or the scenario
    /// (`singapore-77` by default).
    fn airspace_spec(&self) -> AirspaceSpec {
        if let Some(path) = &self.airspace {
            AirspaceSpec::File(path.clone())
        } else if let Some(spec) = self.synthetic_spec() {
            AirspaceSpec::Synthetic(spec)
        } else {
            AirspaceSpec::Scenario(
                self.scenario
                    .clone()
                    .unwrap_or_else(|| muse_scenario::SINGAPORE_77.to_owned()),
            )
        }
    }

    /// Loads the airspace and zones these arguments name, warning of zones that do nothing
    /// on the airspace.
    pub fn load(&self) -> anyhow::Result<World> {
        let spec = WorldSpec {
            airspace: self.airspace_spec(),
            zones: zones_spec(&self.zones)?,
        };
        let world = spec.load().map_err(world_error)?;
        warn_idle_zones(&world, false);
        Ok(world)
    }

    /// What `summary.json` records of these arguments: files as absolute paths, so that a
    /// run can be checked again from another folder.
    pub fn record(&self) -> anyhow::Result<WorldRecord> {
        let spec = WorldSpec {
            airspace: self.airspace_spec(),
            zones: zones_given(&self.zones),
        };
        spec.record().map_err(world_error)
    }
}

/// The zones `--zones` gives: none when it names `none`, the files it names, or (not given)
/// the airspace's own.
fn zones_given(zones: &[PathBuf]) -> ZonesSpec {
    if zones.iter().any(|z| z.as_os_str() == "none") {
        ZonesSpec::None
    } else if zones.is_empty() {
        ZonesSpec::Own
    } else {
        ZonesSpec::Files(zones.to_vec())
    }
}

/// The zones `--zones` gives ([`zones_given`]), `none` alone.
///
/// # Errors
/// `none` with zone files.
pub fn zones_spec(zones: &[PathBuf]) -> anyhow::Result<ZonesSpec> {
    let spec = zones_given(zones);
    if spec == ZonesSpec::None && zones.len() > 1 {
        anyhow::bail!("`--zones none` cannot be combined with zone files");
    }
    Ok(spec)
}

/// A world that cannot be loaded, a synthetic airspace named by its option.
fn world_error(e: WorldError) -> anyhow::Error {
    match e {
        WorldError::Synthetic { layout, source } => {
            anyhow::Error::new(*source).context(format!("--synthetic {layout}"))
        }
        e => e.into(),
    }
}

/// Warns on standard error of every zone that does nothing on the world's airspace
/// ([`World::idle_zone_warnings`]).
pub fn warn_idle_zones(world: &World, heights_only: bool) {
    for warning in world.idle_zone_warnings(heights_only) {
        eprintln!("{warning}");
    }
}

/// Refuses zones with a `withdrawn` instant (a service listing's): `command` plans, and
/// planning replays zone announcements, never withdrawals.
pub fn refuse_withdrawn(world: &World, command: &str) -> anyhow::Result<()> {
    match world.withdrawn_zone() {
        Some(z) => anyhow::bail!(
            "--zones: zone `{}` was withdrawn (`withdrawn`): `muse {command}` cannot plan \
             with a withdrawn zone; leave it out (only `muse verify` and `muse view` read \
             withdrawals)",
            z.id
        ),
        None => Ok(()),
    }
}

/// Cruise speed and battery.
#[derive(Debug, Args, Clone, Copy)]
pub struct RangeArgs {
    /// Cruise speed, km/h, from 1 to 1000.
    #[arg(long, default_value_t = 30.0, value_name = "KMH", allow_negative_numbers = true, value_parser = ranges::speed_kmh)]
    pub speed_kmh: f64,
    /// Maximum airborne time (battery), minutes, from 1 to 1440.
    #[arg(long, default_value_t = 20.0, value_name = "MIN", allow_negative_numbers = true, value_parser = ranges::max_flight_min)]
    pub max_flight_min: f64,
}

impl RangeArgs {
    /// The cruise speed.
    pub fn speed(&self) -> anyhow::Result<Speed> {
        Speed::from_kmh(self.speed_kmh).context("--speed-kmh")
    }

    /// The battery limit `T_max`.
    pub fn t_max(&self) -> anyhow::Result<Millis> {
        Millis::from_secs_f64(self.max_flight_min * 60.0)
            .ok()
            .filter(|m| m.0 > 0)
            .with_context(|| {
                format!(
                    "--max-flight-min {}: must be a number of minutes from 1 to 1440",
                    self.max_flight_min
                )
            })
    }
}

/// Every flight-model parameter of docs/reference.md#flight-model-and-separation (defaults: the
/// paper).
#[derive(Debug, Args, Clone, Copy)]
pub struct FlightArgs {
    #[command(flatten)]
    pub range: RangeArgs,
    /// Node separation `tau`, seconds, from 0 to 3600.
    #[arg(long, default_value_t = 5.0, value_name = "S", allow_negative_numbers = true, value_parser = ranges::separation_s)]
    pub node_separation_s: f64,
    /// Edge rule: `exclusive` (one drone per corridor) or `headway` (same-direction drones
    /// `--headway-s` apart).
    #[arg(long, value_enum, default_value_t = EdgeRuleArg::Exclusive)]
    pub edge_rule: EdgeRuleArg,
    /// Same-direction headway for `--edge-rule headway`, seconds, from 0 to 3600 (default:
    /// `tau`).
    #[arg(long, value_name = "S", allow_negative_numbers = true, value_parser = ranges::separation_s)]
    pub headway_s: Option<f64>,
    /// Maximum ground delay `G_max`, seconds, from 0 to 86400.
    #[arg(long, default_value_t = 0.0, value_name = "S", allow_negative_numbers = true, value_parser = ranges::day_s)]
    pub max_ground_delay_s: f64,
    /// Battery swaps at stations (docs/reference.md#multi-leg-trips): a trip may land at
    /// intermediate stations, stay on the ground at least this many seconds, and take off
    /// again with a full battery; from 0 to 86400. Off by default (the paper: single legs).
    #[arg(long, value_name = "S", allow_negative_numbers = true, value_parser = ranges::day_s)]
    pub battery_swap_s: Option<f64>,
    /// With `--battery-swap-s`: at most this many legs per trip, from 1 to 100 (default: no
    /// bound).
    #[arg(long, value_name = "K", requires = "battery_swap_s", allow_negative_numbers = true, value_parser = ranges::max_legs)]
    pub max_legs: Option<u32>,
    /// A delivery deadline: every trip must land within this many minutes of its requested
    /// departure, or it is rejected (`no_feasible_plan`). Default: none. With battery swaps
    /// the time on the ground between legs is otherwise unbounded. From 1 to 1440.
    #[arg(long, value_name = "MIN", allow_negative_numbers = true, value_parser = ranges::max_trip_min)]
    pub max_trip_min: Option<f64>,
    /// Metric separation `D` (docs/reference.md#metric-separation): at every instant two
    /// flights are both airborne, at least this many metres apart horizontally (or
    /// `--vertical-separation-m` apart vertically); from 0 to 1000. Default 0: off.
    #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = ranges::separation_m)]
    pub separation_m: Option<f64>,
    /// Vertical separation `V` for `--separation-m`, metres, from 0 to 1000 but not 0
    /// (default: the layers' spacing; accepted on a flat airspace, where it changes nothing).
    #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = ranges::separation_m)]
    pub vertical_separation_m: Option<f64>,
}

/// The edge rule on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum EdgeRuleArg {
    /// At most one drone on an edge.
    Exclusive,
    /// Opposite directions exclusive, same direction a headway apart.
    Headway,
}

impl FlightArgs {
    /// The options as a record of parameters in user units (what a summary records).
    pub fn record(&self) -> ParamsRecord {
        ParamsRecord {
            speed_kmh: self.range.speed_kmh,
            max_flight_min: self.range.max_flight_min,
            node_separation_s: self.node_separation_s,
            edge_rule: match self.edge_rule {
                EdgeRuleArg::Exclusive => "exclusive",
                EdgeRuleArg::Headway => "headway",
            }
            .to_owned(),
            headway_s: self.headway_s,
            max_ground_delay_s: self.max_ground_delay_s,
            booking_lead_min: None,
            battery_swap_s: self.battery_swap_s,
            max_legs: self.max_legs,
            max_trip_min: self.max_trip_min,
            separation_m: self.separation_m.filter(|&d| d > 0.0),
            vertical_separation_m: self.vertical_separation_m,
        }
    }

    /// The parameters, validated.
    pub fn params(&self) -> anyhow::Result<muse_model::FlightParams> {
        if matches!(self.edge_rule, EdgeRuleArg::Exclusive) && self.headway_s.is_some() {
            anyhow::bail!("--headway-s applies only with --edge-rule headway");
        }
        self.record()
            .to_params()
            .map_err(|e| anyhow::anyhow!(e.as_option()))
    }
}

/// Stations are labelled on maps with at most this many stations (more would be illegible).
pub const MAX_LABELLED_STATIONS: usize = 150;

/// Singapore's land outline when the world is one of its scenarios; else the outline its
/// airspace file carries, if any.
pub fn world_land(world: &World) -> Vec<geo_types::Polygon<f64>> {
    if world.land {
        muse_scenario::singapore_land().0
    } else {
        world.land_outline.clone()
    }
}

/// The data attribution a map of `world` must carry (empty for a file or synthetic airspace).
pub fn world_attribution(world: &World) -> String {
    if world.scenario.is_some() {
        muse_scenario::ATTRIBUTION.to_owned()
    } else {
        String::new()
    }
}

/// The name `--customers` (`muse demand`, `muse siting`) takes for the embedded customers:
/// every HDB car park (2,257), each of weight 1, as a proxy for where Singapore's residents
/// live.
pub const SINGAPORE_HDB: &str = "singapore-hdb";

/// The file `--customers` names, `None` for the embedded customers ([`SINGAPORE_HDB`]).
pub fn customers_file(arg: &Path) -> Option<&Path> {
    (arg.as_os_str() != SINGAPORE_HDB).then_some(arg)
}

/// The customers `--customers` names: the embedded HDB car parks for [`SINGAPORE_HDB`], else
/// a customers CSV (`id,lon,lat[,weight]`).
///
/// # Errors
/// A file that cannot be read or is refused, named with its line and field.
pub fn read_customers(arg: &Path) -> anyhow::Result<Vec<muse_formats::customers::Customer>> {
    Ok(match customers_file(arg) {
        None => muse_scenario::candidates::residential_customers()?,
        Some(path) => muse_formats::customers::read_customers_file(path)?,
    })
}

/// Each zone as a map draws it on `airspace`: its area, label and the elements it closes.
pub fn zone_layers(
    airspace: &Airspace,
    zones: &[Zone],
) -> anyhow::Result<Vec<muse_render::ZoneLayer>> {
    zones
        .iter()
        .map(|zone| {
            let (closed_nodes, closed_edges) =
                muse_airspace::closures::closed_elements(airspace, zone)
                    .with_context(|| format!("zone `{}`", zone.id))?;
            Ok(muse_render::ZoneLayer {
                label: zone.name.clone(),
                polygons: zone.polygons(),
                closed_nodes,
                closed_edges,
            })
        })
        .collect()
}

/// Draws a world's airspace, land (for the Singapore scenarios) and zones as an SVG map;
/// `edge_load` colours corridors by how busy they were.
pub fn render_world_map(
    world: &World,
    width_px: u32,
    edge_load: Option<(Vec<f64>, String)>,
) -> anyhow::Result<String> {
    use muse_render::{MapInput, MapOptions, render_map};
    let land = world_land(world);
    let zones = zone_layers(&world.airspace, &world.zones)?;
    let mut input = MapInput::new(&world.airspace);
    input.land = &land;
    input.zones = zones;
    let mut opts = MapOptions {
        width_px,
        title: world.title.clone(),
        attribution: world_attribution(world),
        label_stations: world.airspace.stations().count() <= MAX_LABELLED_STATIONS,
        ..MapOptions::default()
    };
    if let Some((load, label)) = edge_load {
        input.edge_load = Some(load);
        opts.load_label = label;
    }
    Ok(render_map(&input, &opts)?)
}
