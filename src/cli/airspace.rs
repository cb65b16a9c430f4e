//! `muse airspace build | info | export | map`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Subcommand;
use muse_airspace::closures::closed_elements;
use muse_airspace::conflicts::{Movement, Relation};
use muse_airspace::corners::{corners, gap_s};
use muse_airspace::stats::airspace_stats;
use muse_model::{
    Airspace, EdgeId, EdgeKind, FlightParams, HeadingRule, Layers, Metres, Millis, NodeId, Period,
    Separation, Speed, Zone,
};

use super::common::{RangeArgs, WorldArgs};
use super::layers::{LayersArgs, layered};
use super::output;

mod build;

/// The airspace subcommands.
#[derive(Debug, Subcommand)]
pub enum AirspaceCommand {
    /// Build an airspace from a pads file (`--pads`: any place,
    /// docs/reference.md#airspace-from-pads), or regenerate the embedded Singapore files from the
    /// source data in `data/`.
    Build {
        /// Pads file: a CSV with the columns `id,lon,lat` (and optionally `name`), or GeoJSON
        /// points; the airspace is written to `--out`.
        #[arg(long, value_name = "FILE")]
        pads: Option<PathBuf>,
        /// The plane the triangulation is worked out in (with `--pads`): `utm` (the UTM zone
        /// of the pads' centroid, the default), `EPSG:3414` (SVY21, as the built-in Singapore
        /// scenarios), a WGS84 UTM zone `EPSG:326zz` or `EPSG:327zz`, or `stereographic`.
        #[arg(long, value_name = "CRS", requires = "pads")]
        crs: Option<String>,
        /// Exclusion polygons, GeoJSON (with `--pads`; repeatable): no corridor meets them,
        /// and a pad inside one is an error.
        #[arg(long, value_name = "FILE", requires = "pads")]
        exclude: Vec<PathBuf>,
        /// The map's land outline (with `--pads`): Polygon or MultiPolygon GeoJSON, carried in
        /// the airspace file (features of kind `land`) and drawn on its maps and in the
        /// viewer; it does not change the corridors.
        #[arg(long, value_name = "FILE", requires = "pads")]
        land: Option<PathBuf>,
        /// Drop corridors longer than this (with `--pads`), metres, from 1 to 1000000.
        #[arg(long, value_name = "M", requires = "pads", allow_negative_numbers = true, value_parser = super::ranges::max_corridor_m)]
        max_corridor_m: Option<f64>,
        /// The pads' time zone (with `--pads`), an IANA name such as `Europe/Vienna`: the file
        /// then carries the day its airspace is planned on, `--date` at this zone's offset at
        /// noon, so that local clock times in requests and every output's times are the
        /// place's own. Without it (or `--utc-offset`) the day is the default's (2026-01-05,
        /// +08:00, Singapore's).
        #[arg(
            long,
            value_name = "NAME",
            requires = "pads",
            conflicts_with = "utc_offset"
        )]
        time_zone: Option<String>,
        /// The pads' day at a fixed UTC offset (with `--pads`) instead of a time zone, e.g.
        /// `+01:00` or `-05:00`.
        #[arg(
            long,
            value_name = "±HH:MM",
            requires = "pads",
            allow_hyphen_values = true
        )]
        utc_offset: Option<String>,
        /// The date of the pads' day (with `--time-zone` or `--utc-offset`), YYYY-MM-DD, years
        /// 1001 to 8999; default 2026-01-05 (a Monday), the default scenario's.
        #[arg(long, value_name = "YYYY-MM-DD", requires = "pads")]
        date: Option<String>,
        /// Output: with `--pads`, the airspace GeoJSON file (`-`: standard output; an existing
        /// file is replaced atomically, never an input); without, the folder of the Singapore
        /// files (default `scenarios/singapore-77`), whose two files are replaced, each
        /// atomically, its other files left alone.
        #[arg(long, value_name = "PATH")]
        out: Option<PathBuf>,
        /// Do not write: compare with the files in the output folder and fail if they differ
        /// (the Singapore files only).
        #[arg(long, conflicts_with = "pads")]
        check: bool,
    },
    /// Print graph statistics and, for each zone, its heights and what it closes (with
    /// `--layers`: the layering, and what each zone closes at each layer).
    Info {
        #[command(flatten)]
        world: WorldArgs,
        #[command(flatten)]
        layers: LayersArgs,
        #[command(flatten)]
        range: RangeArgs,
        /// Also list the sharpest corners (two corridors at a node, in the airspace's plane)
        /// and the gap in time a departure and an arrival there need to stay this many metres
        /// apart at `--speed-kmh` (docs/reference.md#metric-separation), from 0 to 1000.
        #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = super::ranges::separation_m)]
        separation_m: Option<f64>,
    },
    /// Write the airspace as a GeoJSON file (docs/reference.md#airspace; any scenario, e.g.
    /// `singapore-all`, for use by other tools), and optionally its zones as ED-318 GeoJSON.
    Export {
        #[command(flatten)]
        world: WorldArgs,
        /// Output airspace GeoJSON file (`-`: standard output).
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
        /// Also write the zones (ED-318 GeoJSON) to this file (`-`: standard output).
        #[arg(long, value_name = "FILE")]
        zones_out: Option<PathBuf>,
    },
    /// Draw the airspace, the land and the zones as an SVG map (the paper's Fig. 1).
    Map {
        #[command(flatten)]
        world: WorldArgs,
        /// Output SVG file (`-`: standard output).
        #[arg(long, value_name = "FILE", default_value = "map.svg")]
        out: PathBuf,
        /// Width of the drawing, pixels, from 100 to 20000.
        #[arg(long, default_value_t = 1800, allow_negative_numbers = true, value_parser = super::ranges::width_px)]
        width: u32,
    },
}

/// Runs an airspace subcommand.
pub fn run(cmd: AirspaceCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        AirspaceCommand::Build {
            pads: Some(pads),
            crs,
            exclude,
            max_corridor_m,
            out,
            land,
            time_zone,
            utc_offset,
            date,
            check: _,
        } => build::from_pads(
            &pads,
            crs.as_deref(),
            &exclude,
            land.as_deref(),
            build::pads_day(time_zone.as_deref(), utc_offset.as_deref(), date.as_deref())?.as_ref(),
            max_corridor_m,
            out.as_deref(),
        ),
        AirspaceCommand::Build { out, check, .. } => build::singapore(
            out.as_deref()
                .unwrap_or_else(|| Path::new("scenarios/singapore-77")),
            check,
        ),
        AirspaceCommand::Info {
            world,
            layers,
            range,
            separation_m,
        } => info(&world, &layers, range, separation_m),
        AirspaceCommand::Export {
            world,
            out,
            zones_out,
        } => export(&world, &out, zones_out.as_deref()),
        AirspaceCommand::Map { world, out, width } => map(&world, &out, width),
    }
}

fn info(
    world: &WorldArgs,
    layers: &LayersArgs,
    range: RangeArgs,
    separation_m: Option<f64>,
) -> anyhow::Result<ExitCode> {
    let world = layered(world.load()?, layers)?;
    let (speed, t_max) = (range.speed()?, range.t_max()?);
    // The graph's statistics are the flat airspace's; the layering follows them.
    let a = world.airspace.flat();
    let s = airspace_stats(a, speed, t_max);
    let km = |m: Option<f64>| m.map_or_else(|| "-".to_owned(), |m| format!("{:.2} km", m / 1000.0));
    let mins = |t: Millis| t.as_secs_f64() / 60.0;
    let mut o = String::new();
    let _ = writeln!(o, "airspace      {}", world.airspace_source);
    let _ = writeln!(
        o,
        "nodes         {} ({} stations, {} waypoints)",
        s.nodes,
        s.stations,
        s.nodes - s.stations
    );
    let _ = writeln!(
        o,
        "edges         {}{}",
        s.edges,
        if s.connected { "" } else { "  (NOT connected)" }
    );
    let _ = writeln!(
        o,
        "edge length   min {}, median {}, max {}, total {}",
        km(s.min_edge_m),
        km(s.median_edge_m),
        km(s.max_edge_m),
        km(Some(s.total_edge_m))
    );
    let _ = writeln!(
        o,
        "diameter      {:.1} min of flight at {} km/h (between stations: {:.1} min)",
        mins(s.diameter),
        speed.kmh(),
        mins(s.station_diameter)
    );
    let _ = writeln!(
        o,
        "in range      {} of {} ordered station pairs ({:.1}%) have a free-flow time within the {:.0}-min battery",
        s.station_pairs_within_t_max,
        s.station_pairs,
        100.0 * s.share_within_t_max,
        mins(t_max)
    );
    let layered = &world.airspace;
    if let Some(layers) = layered.layers() {
        layering(&mut o, layered, layers, speed, t_max);
    }
    if let Some(d) = separation_m {
        let plane = world.plane_positions()?;
        separation(&mut o, a, &plane, d, speed, world.plane());
        relation(&mut o, layered, d, speed)?;
    }
    if world.zones.is_empty() {
        let _ = writeln!(o, "zones         none");
    }
    for zone in &world.zones {
        // On the flat graph, heights aside: what its area and ids cover (an error names the
        // zone).
        let (nodes, edges) = closed_elements(a, zone)?;
        let _ = writeln!(
            o,
            "zone          {} — {} ({})",
            zone.id,
            zone.name,
            describe_periods(zone)
        );
        let _ = writeln!(o, "  heights     {}", zone.vertical);
        let node_ids: Vec<&str> = nodes.iter().map(|&n| a.node(n).id.as_str()).collect();
        let edge_ids: Vec<&str> = edges.iter().map(|&e| a.edge(e).id.as_str()).collect();
        // Flat, a zone closes what it covers whatever its heights; layered, the copies at the
        // layers of its band (and the vertical links across it).
        let verb = if layered.layers().is_some() {
            "covers"
        } else {
            "closes"
        };
        let _ = writeln!(
            o,
            "  {verb}      {} nodes: {}",
            nodes.len(),
            list_or_none(&node_ids)
        );
        let _ = writeln!(
            o,
            "  {verb}      {} edges: {}",
            edges.len(),
            list_or_none(&edge_ids)
        );
        if let Some(layers) = layered.layers() {
            let (nodes, edges) = closed_elements(layered, zone)?;
            let _ = writeln!(
                o,
                "  closes      {}",
                by_layer(layered, layers, &nodes, &edges)
            );
        }
    }
    print!("{o}");
    Ok(ExitCode::SUCCESS)
}

/// How many of the sharpest corners `muse airspace info --separation-m` lists.
const CORNERS_LISTED: usize = 10;

/// The lines of `muse airspace info --separation-m D` (docs/reference.md#metric-separation): the
/// sharpest corners of the flat airspace `a` (its nodes at `plane`, in `plane_name`), the gap
/// in time each needs to keep `d` metres at `speed`, and the uniform `tau` that keeps them all.
fn separation(
    o: &mut String,
    a: &Airspace,
    plane: &[[f64; 2]],
    d: f64,
    speed: Speed,
    plane_name: muse_airspace::plane::Plane,
) {
    let all = corners(a, plane);
    let v = speed.mps();
    let _ = writeln!(
        o,
        "corners       {} (two corridors at a node, in {plane_name}); the sharpest, and the gap a \
         departure and an arrival there need to stay {d} m apart at {} km/h:",
        all.len(),
        speed.kmh()
    );
    for c in all.iter().take(CORNERS_LISTED) {
        let _ = writeln!(
            o,
            "  {:<10} {} / {}  {:>6.2}°  {:>8.1} s",
            a.node(c.node).id,
            a.edge(c.edges.0).id,
            a.edge(c.edges.1).id,
            c.angle_deg,
            gap_s(c.angle_deg, d, v)
        );
    }
    if let Some(sharpest) = all.first() {
        let _ = writeln!(
            o,
            "  a uniform tau of {:.1} s keeps {d} m at every corner",
            gap_s(sharpest.angle_deg, d, v)
        );
    }
}

/// The line of `muse airspace info --separation-m D` on the conflict relation the planner keeps
/// `D` with (at `speed`, the other parameters the paper's): how many barriers, on how many of
/// the movements, the most on one, and how long it takes to work out.
fn relation(o: &mut String, a: &Airspace, d: f64, speed: Speed) -> anyhow::Result<()> {
    let params = FlightParams {
        speed,
        separation: Separation::horizontal(Metres::from_m(d)?),
        ..FlightParams::default()
    };
    let started = std::time::Instant::now();
    let relation = Relation::new(a, &params);
    let took = started.elapsed();
    let movements = a.node_count() + 2 * a.edge_count();
    let targets: Vec<(Movement, usize)> = relation.targets().map(|(m, l)| (m, l.len())).collect();
    let busiest = targets
        .iter()
        .max_by_key(|&&(m, n)| (n, std::cmp::Reverse(format!("{m:?}"))));
    let name = |m: Movement| match m {
        Movement::Stay(v) => format!("stays at {}", a.node(v).id),
        Movement::Traversal(e, forward) => {
            let edge = a.edge(e);
            let (from, to) = if forward {
                (edge.from, edge.to)
            } else {
                (edge.to, edge.from)
            };
            format!("{} from {} to {}", edge.id, a.node(from).id, a.node(to).id)
        }
    };
    let _ = writeln!(
        o,
        "  planning    {} barriers between movements beyond tau {} s and the edge rule, on {} of \
         {movements} movements (the most, {}: {}); worked out in {:.2} s",
        relation.len(),
        params.node_separation.as_secs_f64(),
        targets.len(),
        busiest.map_or(0, |b| b.1),
        busiest.map_or("none".to_owned(), |b| name(b.0)),
        took.as_secs_f64()
    );
    Ok(())
}

/// The lines of `muse airspace info` on the layering of a layered airspace `a`.
fn layering(o: &mut String, a: &Airspace, layers: &Layers, speed: Speed, t_max: Millis) {
    let altitudes: Vec<String> = (1..=layers.count)
        .map(|k| layers.altitude(k).to_string())
        .collect();
    let _ = writeln!(
        o,
        "layers        {} at {} m ({} m apart); vertical links climbed in {:.3} s at {} m/s",
        layers.count,
        altitudes.join(", "),
        layers.spacing,
        layers.climb_time().as_secs_f64(),
        Metres::from_mm(i64::from(layers.climb_mm_per_s)),
    );
    let rule = match layers.heading_rule {
        HeadingRule::None => "none (every direction at every layer)".to_owned(),
        HeadingRule::Sectors => {
            let width = 360.0 / f64::from(layers.count);
            let sectors: Vec<String> = (1..=layers.count)
                .map(|k| {
                    let (low, high) = (f64::from(k - 1) * width, f64::from(k) * width);
                    format!("{k}: {}–{}°", trim(low), trim(high))
                })
                .collect();
            format!(
                "sectors (initial bearings by layer, upper bound excluded: {})",
                sectors.join(", ")
            )
        }
    };
    let _ = writeln!(o, "heading rule  {rule}");
    let (mut corridors, mut one_way, mut vertical) = (0, 0, 0);
    for e in 0..a.edge_count() {
        match a.edge_kind(EdgeId(u32::try_from(e).unwrap_or(u32::MAX))) {
            EdgeKind::Corridor { one_way: one, .. } => {
                corridors += 1;
                one_way += usize::from(one);
            }
            EdgeKind::Vertical { .. } => vertical += 1,
        }
    }
    let absent = a.flat().edge_count() * layers.count as usize - corridors;
    let _ = writeln!(
        o,
        "layered graph {} nodes, {} edges: {corridors} corridors ({one_way} one-way; {absent} \
         copies absent), {vertical} vertical links",
        a.node_count(),
        a.edge_count()
    );
    let s = airspace_stats(a, speed, t_max);
    let _ = writeln!(
        o,
        "in range      {} of {} ordered station pairs ({:.1}%) on the layers (climbs and heading \
         rule included)",
        s.station_pairs_within_t_max,
        s.station_pairs,
        100.0 * s.share_within_t_max,
    );
}

/// A number of degrees without a needless fraction: `90`, `22.5`.
fn trim(degrees: f64) -> String {
    let text = format!("{degrees:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// What a zone closes on a layered airspace, by layer: `layer 1: 3 nodes, 5 corridors; layer
/// 2: none; vertical links: 3`.
fn by_layer(a: &Airspace, layers: &Layers, nodes: &[NodeId], edges: &[EdgeId]) -> String {
    let count = layers.count as usize;
    let (mut at_nodes, mut at_corridors, mut vertical) = (vec![0; count], vec![0; count], 0);
    for &n in nodes {
        at_nodes[a.node_layer(n) as usize - 1] += 1;
    }
    for &e in edges {
        match a.edge_kind(e) {
            EdgeKind::Corridor { layer, .. } => at_corridors[layer as usize - 1] += 1,
            EdgeKind::Vertical { .. } => vertical += 1,
        }
    }
    let mut parts: Vec<String> = (0..count)
        .map(|i| match (at_nodes[i], at_corridors[i]) {
            (0, 0) => format!("layer {}: none", i + 1),
            (n, c) => format!("layer {}: {n} nodes, {c} corridors", i + 1),
        })
        .collect();
    parts.push(format!("vertical links: {vertical}"));
    parts.join("; ")
}

fn list_or_none(ids: &[&str]) -> String {
    if ids.is_empty() {
        "none".to_owned()
    } else {
        ids.join(", ")
    }
}

/// A one-line human description of when a zone applies.
fn describe_periods(zone: &Zone) -> String {
    if zone.is_permanent() {
        return "permanent".to_owned();
    }
    let clock = |t: Millis| format!("{:02}:{:02}", t.0 / 3_600_000, (t.0 / 60_000) % 60);
    let describe = |p: &Period| {
        let mut parts = Vec::new();
        if let Some(start) = p.start {
            parts.push(format!(
                "from {}",
                start.to_rfc3339(muse_model::UtcOffset(0))
            ));
        }
        if let Some(end) = p.end {
            parts.push(format!(
                "until {}",
                end.to_rfc3339(muse_model::UtcOffset(0))
            ));
        }
        for w in &p.daily {
            let days = if w.days.len() == 7 {
                "daily".to_owned()
            } else {
                w.days
                    .iter()
                    .map(|d| d.as_str())
                    .collect::<Vec<_>>()
                    .join("/")
            };
            parts.push(format!(
                "{days} {}–{} {}",
                clock(w.start),
                clock(w.end),
                w.offset
            ));
        }
        parts.join(" ")
    };
    zone.periods
        .iter()
        .map(describe)
        .collect::<Vec<_>>()
        .join("; ")
}

fn export(world: &WorldArgs, out: &Path, zones_out: Option<&Path>) -> anyhow::Result<ExitCode> {
    let inputs = output::Inputs::new().world(world);
    let out = output::file("--out", out, &inputs)?;
    let zones_out = zones_out
        .map(|path| output::file("--zones-out", path, &inputs))
        .transpose()?;
    output::distinct(
        &[Some(&out), zones_out.as_ref()]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>(),
    )?;
    let stdout_taken =
        out.is_stdout() || zones_out.as_ref().is_some_and(output::FileOut::is_stdout);
    let world = world.load()?;
    if zones_out.is_some() && world.zones.is_empty() {
        // A zone file holding no zone is refused when read: do not write one.
        anyhow::bail!(
            "--zones-out: there are no zones to write (no zones are in force: give --zones FILE, \
             or a built-in scenario)"
        );
    }
    let text = muse_formats::airspace_geojson::write_airspace_file(
        &world.airspace,
        &world.land_outline,
        world.file_day.as_ref(),
    );
    let zones = zones_out
        .as_ref()
        .map(|_| muse_formats::zones::write_ed318(&world.zones));
    out.write(&text)?;
    if let (Some(path), Some(zones)) = (&zones_out, &zones) {
        path.write(zones)?;
    }
    output::say(
        stdout_taken,
        format_args!(
            "wrote {out} ({} nodes, {} edges, {} bytes)",
            world.airspace.node_count(),
            world.airspace.edge_count(),
            text.len()
        ),
    );
    if let Some(path) = &zones_out {
        output::say(
            stdout_taken,
            format_args!("wrote {path} ({} zone(s))", world.zones.len()),
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn map(world: &WorldArgs, out: &Path, width: u32) -> anyhow::Result<ExitCode> {
    let out = output::file("--out", out, &output::Inputs::new().world(world))?;
    let world = world.load()?;
    let svg = super::common::render_world_map(&world, width, None)?;
    out.write(&svg)?;
    output::say(out.is_stdout(), format_args!("wrote {out}"));
    Ok(ExitCode::SUCCESS)
}
