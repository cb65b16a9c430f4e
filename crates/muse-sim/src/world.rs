//! The world a day is planned on: an airspace (a built-in scenario, an airspace file or a
//! synthetic airspace), its zones, the day (date and UTC offset) and what a summary records
//! of them — loaded here for every front end. The command line turns its options into a
//! [`WorldSpec`], the Python package its keywords; both then [`load`](WorldSpec::load) it and
//! fly it at its layers ([`World::layered`]).
//!
//! ```
//! use muse_sim::world::{AirspaceSpec, WorldSpec, ZonesSpec};
//! let spec = WorldSpec { airspace: AirspaceSpec::default(), zones: ZonesSpec::None };
//! let world = spec.load().unwrap();
//! assert_eq!(world.airspace_source, "embedded singapore-77");
//! assert!(world.zones.is_empty());
//! assert_eq!(world.record.scenario.as_deref(), Some("singapore-77"));
//! assert_eq!(world.record.zones, Some(Vec::new()));
//! ```

use std::path::{Path, PathBuf};

use muse_formats::InputError;
use muse_formats::airspace_geojson::AirspaceFile;
use muse_formats::day::{FileDay, LocalDay};
use muse_model::{Airspace, AirspaceError, Layers, Zone};
use muse_scenario::{Layout, Scenario, ScenarioError, SyntheticSpec};

use crate::metrics::Provenance;
use crate::metrics::recorded::{LayersRecord, SyntheticRecord, WorldRecord};

/// Which airspace: a built-in scenario by name, an airspace GeoJSON file, or a synthetic
/// airspace.
#[derive(Clone, Debug, PartialEq)]
pub enum AirspaceSpec {
    /// A built-in scenario (`singapore-77`, `singapore-all`).
    Scenario(String),
    /// An airspace GeoJSON file (with the land outline and the day it may carry).
    File(PathBuf),
    /// A synthetic airspace.
    Synthetic(SyntheticSpec),
}

impl Default for AirspaceSpec {
    /// The default scenario, `singapore-77`.
    fn default() -> Self {
        AirspaceSpec::Scenario(muse_scenario::SINGAPORE_77.to_owned())
    }
}

/// Which zones: the airspace's own (a built-in scenario's; none for other airspaces), none,
/// or those of files.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum ZonesSpec {
    /// The airspace's own.
    #[default]
    Own,
    /// No zones.
    None,
    /// The zones of these files (ED-318 GeoJSON or ED-269 JSON), in order.
    Files(Vec<PathBuf>),
}

/// An airspace and its zones, to be loaded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WorldSpec {
    /// The airspace.
    pub airspace: AirspaceSpec,
    /// The zones.
    pub zones: ZonesSpec,
}

/// Why a world cannot be loaded; the message names the scenario, file or airspace at fault.
#[derive(Debug, thiserror::Error)]
pub enum WorldError {
    /// An unknown scenario (or one whose embedded data cannot be read).
    #[error(transparent)]
    Scenario(Box<ScenarioError>),
    /// An airspace file that cannot be read or is refused.
    #[error(transparent)]
    AirspaceFile(Box<InputError>),
    /// A synthetic airspace that cannot be built.
    #[error("synthetic {layout} airspace")]
    Synthetic {
        /// Its layout.
        layout: Layout,
        /// Why.
        source: Box<ScenarioError>,
    },
    /// A zone file that cannot be read or is refused.
    #[error("reading zones from {}: {error}", path.display())]
    ZoneFile {
        /// The file.
        path: PathBuf,
        /// Why.
        error: Box<InputError>,
    },
    /// A file whose absolute path cannot be known (for the summary's record).
    #[error("the absolute path of {}: {error}", path.display())]
    AbsolutePath {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
}

impl From<ScenarioError> for WorldError {
    fn from(e: ScenarioError) -> Self {
        WorldError::Scenario(Box::new(e))
    }
}

/// An airspace and where it came from: a world without its zones.
#[derive(Clone, Debug)]
pub struct LoadedAirspace {
    /// The airspace (flat).
    pub airspace: Airspace,
    /// Where it came from, for messages and the summary's provenance.
    pub source: String,
    /// A one-line description for map titles.
    pub title: String,
    /// The built-in scenario, if the airspace is one.
    pub scenario: Option<&'static Scenario>,
    /// The land outline an airspace file carries, drawn on maps; empty otherwise.
    pub land_outline: Vec<geo_types::Polygon<f64>>,
    /// The day an airspace file carries, if it carries one.
    pub file_day: Option<FileDay>,
    /// What a summary records of the airspace (its zones and layers left `None`).
    pub record: WorldRecord,
}

impl LoadedAirspace {
    /// An airspace built in memory (from pads, say), named `source`, planned on `day` (the
    /// default's when `None`); a summary records no scenario, file or synthetic airspace for
    /// it.
    ///
    /// ```
    /// use muse_sim::world::LoadedAirspace;
    /// let built = LoadedAirspace::built(muse_model::Airspace::line(&[1_000.0]), "two pads".into(), None);
    /// assert_eq!((built.source.as_str(), built.record.scenario), ("two pads", None));
    /// ```
    pub fn built(airspace: Airspace, source: String, day: Option<FileDay>) -> Self {
        LoadedAirspace {
            airspace,
            title: format!("MUSE airspace: {source}"),
            source,
            scenario: None,
            land_outline: Vec::new(),
            file_day: day,
            record: WorldRecord::default(),
        }
    }
}

/// An airspace with its zones and the day they are planned on.
#[derive(Clone, Debug)]
pub struct World {
    /// Where the airspace came from, for messages.
    pub airspace_source: String,
    /// The airspace (layered, once [`World::layered`]).
    pub airspace: Airspace,
    /// The zones.
    pub zones: Vec<Zone>,
    /// The built-in scenario, if the airspace is one (not a file or a synthetic airspace).
    pub scenario: Option<&'static Scenario>,
    /// Whether Singapore's land outline applies (drawn on maps, with the data attribution).
    pub land: bool,
    /// The land outline an airspace file carries (`muse airspace build --land`), drawn on
    /// maps; empty otherwise.
    pub land_outline: Vec<geo_types::Polygon<f64>>,
    /// A one-line description for map titles.
    pub title: String,
    /// The day planned on, its date and UTC offset: the scenario's, the one the airspace file
    /// carries, or the default's.
    pub day: LocalDay,
    /// The day an airspace file carries (with its time zone's name, if it gives one), which
    /// `day` is then; `None` for a scenario, a synthetic airspace or a file without one.
    pub file_day: Option<FileDay>,
    /// Where the airspace and zones came from, as `summary.json` records it.
    pub record: WorldRecord,
}

impl AirspaceSpec {
    /// Loads the airspace.
    ///
    /// # Errors
    /// An unknown scenario, a file that cannot be read or is refused, a synthetic airspace
    /// that cannot be built.
    pub fn load(&self) -> Result<LoadedAirspace, WorldError> {
        Ok(match self {
            AirspaceSpec::File(path) => {
                let file =
                    AirspaceFile::read(path).map_err(|e| WorldError::AirspaceFile(Box::new(e)))?;
                LoadedAirspace {
                    airspace: file.airspace,
                    source: path.display().to_string(),
                    title: format!("MUSE airspace: {}", path.display()),
                    scenario: None,
                    land_outline: file.land,
                    file_day: file.day,
                    record: self.record()?,
                }
            }
            AirspaceSpec::Synthetic(spec) => {
                let airspace =
                    muse_scenario::synthetic(spec).map_err(|e| WorldError::Synthetic {
                        layout: spec.layout,
                        source: Box::new(e),
                    })?;
                LoadedAirspace {
                    airspace,
                    source: spec.to_string(),
                    title: format!(
                        "MUSE airspace: synthetic {}, {} nodes ({} stations)",
                        spec.layout,
                        spec.nodes,
                        spec.station_count()
                    ),
                    scenario: None,
                    land_outline: Vec::new(),
                    file_day: None,
                    record: self.record()?,
                }
            }
            AirspaceSpec::Scenario(name) => {
                let s = muse_scenario::by_name(name)?;
                LoadedAirspace {
                    airspace: s.airspace.clone(),
                    source: format!("embedded {}", s.name),
                    title: format!("MUSE airspace: {}", s.title),
                    scenario: Some(s),
                    land_outline: Vec::new(),
                    file_day: None,
                    record: self.record()?,
                }
            }
        })
    }

    /// What `summary.json` records of the airspace (its zones and layers left `None`): a file
    /// as an absolute path, so that a run can be checked again from another folder.
    ///
    /// # Errors
    /// A file whose absolute path cannot be known.
    pub fn record(&self) -> Result<WorldRecord, WorldError> {
        Ok(match self {
            AirspaceSpec::Scenario(name) => WorldRecord {
                scenario: Some(name.clone()),
                ..WorldRecord::default()
            },
            AirspaceSpec::File(path) => WorldRecord {
                airspace: Some(absolute(path)?),
                ..WorldRecord::default()
            },
            AirspaceSpec::Synthetic(s) => WorldRecord {
                synthetic: Some(SyntheticRecord {
                    layout: s.layout.to_string(),
                    nodes: s.nodes,
                    spacing_m: s.spacing_m,
                    station_share: s.station_share,
                    seed: s.seed,
                }),
                ..WorldRecord::default()
            },
        })
    }
}

impl ZonesSpec {
    /// The zones: `own` (the airspace's), none, or those the files give.
    ///
    /// # Errors
    /// A zone file that cannot be read or is refused, named.
    pub fn read(&self, own: &[Zone]) -> Result<Vec<Zone>, WorldError> {
        Ok(match self {
            ZonesSpec::Own => own.to_vec(),
            ZonesSpec::None => Vec::new(),
            ZonesSpec::Files(paths) => {
                let mut all = muse_formats::zones::ZoneFiles::default();
                for path in paths {
                    all.add(path).map_err(|e| WorldError::ZoneFile {
                        path: path.clone(),
                        error: Box::new(e),
                    })?;
                }
                all.into_zones()
            }
        })
    }

    /// What `summary.json` records of the zones: `None` for the airspace's own, else the
    /// files as absolute paths (none for no zones).
    ///
    /// # Errors
    /// A file whose absolute path cannot be known.
    pub fn record(&self) -> Result<Option<Vec<String>>, WorldError> {
        Ok(match self {
            ZonesSpec::Own => None,
            ZonesSpec::None => Some(Vec::new()),
            ZonesSpec::Files(paths) => Some(
                paths
                    .iter()
                    .map(|p| absolute(p))
                    .collect::<Result<_, _>>()?,
            ),
        })
    }
}

impl WorldSpec {
    /// Loads the airspace and the zones.
    ///
    /// # Errors
    /// As [`AirspaceSpec::load`] and [`ZonesSpec::read`].
    pub fn load(&self) -> Result<World, WorldError> {
        World::new(self.airspace.load()?, &self.zones)
    }

    /// What `summary.json` records of the world (its layers left `None`), without loading
    /// it.
    ///
    /// # Errors
    /// A file whose absolute path cannot be known.
    pub fn record(&self) -> Result<WorldRecord, WorldError> {
        Ok(WorldRecord {
            zones: self.zones.record()?,
            ..self.airspace.record()?
        })
    }
}

/// The absolute path of `path` as a summary records it.
fn absolute(path: &Path) -> Result<String, WorldError> {
    std::fs::canonicalize(path)
        .or_else(|_| std::path::absolute(path))
        .map(|p| p.display().to_string())
        .map_err(|error| WorldError::AbsolutePath {
            path: path.to_owned(),
            error,
        })
}

impl World {
    /// The local metric plane the airspace is measured in (docs/reference.md#metric-separation):
    /// for a built-in scenario the plane it is built in (SVY21), else the UTM zone of the
    /// nodes' centroid (the default plane of docs/reference.md#airspace-from-pads).
    #[must_use]
    pub fn plane(&self) -> muse_airspace::plane::Plane {
        if self.scenario.is_some() {
            muse_scenario::singapore_build_options().plane
        } else {
            muse_airspace::plane::Plane::default()
        }
    }

    /// The positions of the airspace's flat nodes in [`World::plane`], metres east and north.
    ///
    /// # Errors
    /// A node the plane cannot take (see [`muse_airspace::plane::Plane::project`]).
    pub fn plane_positions(&self) -> Result<Vec<[f64; 2]>, muse_airspace::plane::PlaneError> {
        Ok(self
            .plane()
            .project(self.airspace.flat().nodes())?
            .into_iter()
            .map(|p| [p.x, p.y])
            .collect())
    }

    /// The world of `airspace` with `zones`, on the day the airspace carries: a scenario's,
    /// an airspace file's, or the default scenario's for other airspaces.
    ///
    /// # Errors
    /// As [`ZonesSpec::read`].
    pub fn new(airspace: LoadedAirspace, zones: &ZonesSpec) -> Result<World, WorldError> {
        let LoadedAirspace {
            airspace,
            source,
            title,
            scenario,
            land_outline,
            file_day,
            mut record,
        } = airspace;
        let own = scenario.map_or(&[][..], |s| s.zones.as_slice());
        let zone_list = zones.read(own)?;
        record.zones = zones.record()?;
        let day = if let Some(f) = &file_day {
            f.day
        } else {
            let s = match scenario {
                Some(s) => s,
                None => muse_scenario::by_name(muse_scenario::SINGAPORE_77)?,
            };
            LocalDay {
                date: s.date,
                offset: s.offset,
            }
        };
        let mut world = World {
            airspace_source: source,
            airspace,
            zones: zone_list,
            scenario,
            land: scenario.is_some_and(|s| s.land),
            land_outline,
            title,
            day,
            file_day,
            record,
        };
        // The plane metric separation is planned and reported in
        // (docs/reference.md#metric-separation). A plane that cannot take the nodes is named by
        // the report that needs it ([`World::plane_positions`]); until then the airspace keeps
        // its tangent plane.
        // (One position per flat node, each finite: `with_plane` takes them.)
        if let Ok(placed) = world
            .plane_positions()
            .map(|plane| world.airspace.clone().with_plane(plane))
        {
            world.airspace = placed.expect("one finite position per flat node");
        }
        Ok(world)
    }

    /// The world flown at `layers` (unchanged with one layer); `summary.json` records them.
    ///
    /// # Errors
    /// A layer copy's id (`ID@k`) already taken in the airspace.
    pub fn layered(mut self, layers: &Layers) -> Result<World, AirspaceError> {
        if layers.is_layered() {
            self.airspace = self.airspace.layered(layers)?;
            self.record.layers = Some(LayersRecord::of(layers));
        }
        Ok(self)
    }

    /// The day an airspace file carries, for the summary's demand line: ` on 2026-01-05 at
    /// +01:00 (Europe/Vienna)`; empty on the default day and a scenario's.
    pub fn day_note(&self) -> String {
        self.file_day.as_ref().map_or(String::new(), |d| {
            let zone = d
                .time_zone
                .as_ref()
                .map(|z| format!(" ({z})"))
                .unwrap_or_default();
            format!(" on {} at {}{zone}", d.day.date, d.day.offset)
        })
    }

    /// What a summary's provenance says of a day planned on this world: the airspace, the
    /// zones' ids, `requests` (where the requests came from) and the `seed` of generated
    /// demand.
    pub fn provenance(&self, requests: String, seed: Option<u64>) -> Provenance {
        Provenance {
            airspace: self.airspace_source.clone(),
            zones: self.zones.iter().map(|z| z.id.clone()).collect(),
            requests,
            seed,
        }
    }

    /// The first zone with a `withdrawn` instant (a service listing's), which a day cannot be
    /// planned with: planning replays zone announcements, never withdrawals.
    pub fn withdrawn_zone(&self) -> Option<&Zone> {
        self.zones.iter().find(|z| z.withdrawn.is_some())
    }

    /// A warning for every zone that does nothing on the airspace ([`idle`]): one that closes
    /// nothing, or is announced after its last window ended. With `heights_only` (the
    /// airspace just layered, the rest said already) only of a zone whose heights hold no
    /// layer. A zone the airspace cannot resolve (an unknown id) is left to the error its
    /// resolution gives.
    ///
    /// [`idle`]: muse_airspace::closures::idle::idle
    pub fn idle_zone_warnings(&self, heights_only: bool) -> Vec<String> {
        use muse_airspace::closures::idle::{Idle, idle};
        let mut warnings = Vec::new();
        for zone in &self.zones {
            let id = &zone.id;
            match idle(&self.airspace, zone) {
                Ok(Some(Idle::ClosesNothingAtItsHeights)) => {
                    let layers = self.airspace.layers().map_or_else(String::new, |l| {
                        format!(
                            " (the layers fly from {} m to {} m)",
                            l.altitude(1),
                            l.altitude(l.count)
                        )
                    });
                    warnings.push(format!(
                        "warning: zone `{id}` closes nothing on the airspace at its heights \
                         ({}): it covers stations or corridors, but no layer{layers} nor climb \
                         between layers lies in its band",
                        zone.vertical
                    ));
                }
                Ok(Some(Idle::ClosesNothing)) if !heights_only => warnings.push(format!(
                    "warning: zone `{id}` closes nothing on the airspace ({}): its area covers \
                     no station, waypoint or corridor, and it lists none",
                    self.airspace_source
                )),
                Ok(Some(Idle::AnnouncedAfterItsWindows { announced, ended })) if !heights_only => {
                    warnings.push(format!(
                        "warning: zone `{id}` is announced at {}, when its last window has \
                         already ended ({}): it closes nothing",
                        announced.to_rfc3339(self.day.offset),
                        ended.to_rfc3339(self.day.offset)
                    ));
                }
                _ => {}
            }
        }
        warnings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> AirspaceSpec {
        AirspaceSpec::Synthetic(SyntheticSpec {
            layout: Layout::Grid,
            nodes: 9,
            spacing_m: 1_000.0,
            station_share: 0.5,
            seed: 1,
        })
    }

    #[test]
    fn a_synthetic_world_is_planned_on_the_default_day_and_recorded() {
        let world = WorldSpec {
            airspace: grid(),
            zones: ZonesSpec::Own,
        }
        .load()
        .unwrap();
        let default = muse_scenario::by_name(muse_scenario::SINGAPORE_77).unwrap();
        assert_eq!(
            (world.day.date, world.day.offset),
            (default.date, default.offset)
        );
        assert!(world.zones.is_empty() && world.scenario.is_none() && !world.land);
        let record = world.record.synthetic.as_ref().unwrap();
        assert_eq!((record.layout.as_str(), record.nodes), ("grid", 9));
        assert_eq!(world.record.zones, None);
        assert_eq!(world.day_note(), "");
        let layered = world
            .layered(&Layers {
                count: 2,
                ..Layers::default()
            })
            .unwrap();
        assert_eq!(layered.airspace.node_count(), 18);
        assert_eq!(layered.record.layers.map(|l| l.count), Some(2));
    }

    #[test]
    fn errors_name_what_is_at_fault() {
        let missing = PathBuf::from("/no/such/zones.geojson");
        let spec = WorldSpec {
            airspace: grid(),
            zones: ZonesSpec::Files(vec![missing]),
        };
        let e = spec.load().unwrap_err().to_string();
        assert!(
            e.starts_with("reading zones from /no/such/zones.geojson: /no/such/zones.geojson: "),
            "{e}"
        );
        let e = AirspaceSpec::Scenario("paris".into()).load().unwrap_err();
        assert!(e.to_string().starts_with("unknown scenario `paris`"), "{e}");
        let e = AirspaceSpec::Synthetic(SyntheticSpec {
            layout: Layout::Grid,
            nodes: 1,
            spacing_m: 1_000.0,
            station_share: 0.5,
            seed: 1,
        })
        .load()
        .unwrap_err();
        assert!(matches!(e, WorldError::Synthetic { .. }), "{e}");
    }
}
