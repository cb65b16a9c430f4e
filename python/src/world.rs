//! An airspace with its zones and its day, as the command line loads them: the built-in
//! Singapore default when no airspace is given, the scenario's own zones when no zones are.

use std::path::PathBuf;

use muse_model::{Layers, UtcOffset, Zone};
use muse_sim::metrics::recorded::{LayersRecord, WorldRecord};

use crate::airspace::Airspace;

/// What a day is planned on.
pub struct World {
    /// The airspace, flown at its layers.
    pub airspace: muse_model::Airspace,
    /// The zones.
    pub zones: Vec<Zone>,
    /// The day (the scenario's, or the one an airspace file carries; the Singapore default's
    /// for other airspaces, as on the command line).
    pub date: jiff::civil::Date,
    /// The day's UTC offset.
    pub offset: UtcOffset,
    /// Where the airspace came from.
    pub source: String,
    /// The world as `summary.json` records it.
    pub record: WorldRecord,
}

/// The zones argument: the airspace's own, none, or files.
pub enum Zones {
    /// The scenario's zones (none for other airspaces).
    Own,
    /// These files, in order (none when empty).
    Files(Vec<PathBuf>),
}

/// The world of `airspace` (the Singapore default when `None`) with `zones`, flown at
/// `layers`.
///
/// # Errors
/// A scenario or zone file that cannot be read, or layers the airspace cannot take; the
/// message names the file or option.
pub fn world(airspace: Option<&Airspace>, zones: &Zones, layers: &Layers) -> Result<World, String> {
    let default = muse_scenario::by_name(muse_scenario::SINGAPORE_77).map_err(|e| e.to_string())?;
    let (graph, scenario, file, source, file_day) = match airspace {
        Some(a) => (
            a.graph.clone(),
            a.scenario,
            a.file.clone(),
            a.source.clone(),
            a.day.as_ref().map(|d| d.day),
        ),
        None => (
            default.airspace.clone(),
            Some(default),
            None,
            format!("embedded {}", default.name),
            None,
        ),
    };
    let (zones, zone_files) = match zones {
        Zones::Own => (scenario.map(|s| s.zones.clone()).unwrap_or_default(), None),
        Zones::Files(paths) => {
            let mut all = muse_formats::zones::ZoneFiles::default();
            let mut files = Vec::new();
            for path in paths {
                all.add(path)
                    .map_err(|e| format!("reading zones from {}: {e}", path.display()))?;
                files.push(
                    std::fs::canonicalize(path)
                        .unwrap_or_else(|_| path.clone())
                        .display()
                        .to_string(),
                );
            }
            (all.into_zones(), Some(files))
        }
    };
    let airspace = graph
        .layered(layers)
        .map_err(|e| format!("layers {}: {e}", layers.count))?;
    let day = file_day.unwrap_or_else(|| {
        let s = scenario.unwrap_or(default);
        muse_formats::day::LocalDay {
            date: s.date,
            offset: s.offset,
        }
    });
    Ok(World {
        airspace,
        zones,
        date: day.date,
        offset: day.offset,
        source,
        record: WorldRecord {
            scenario: scenario.map(|s| s.name.clone()),
            airspace: file,
            synthetic: None,
            zones: zone_files,
            layers: layers.is_layered().then(|| LayersRecord::of(layers)),
        },
    })
}
