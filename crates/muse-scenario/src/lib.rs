//! Built-in scenarios of MUSE, built from open data embedded in the crate, and synthetic
//! airspaces:
//!
//! - `singapore-77`, the default (docs/reference.md#built-in-scenarios): 77 HDB car parks chosen by
//!   seeded k-means, the CBD no-fly zone; parsed from committed files ([`singapore_77`]); with it,
//!   an announced event zone around the National Stadium ([`stadium_zone`]);
//! - `singapore-all`: all 1,115 HDB multi-storey car parks, the same zone; built at run time
//!   ([`singapore_all()`]);
//! - [`synthetic`](mod@synthetic): grid or random geometric airspaces of any size, for
//!   scaling studies.
//!
//! [`SCENARIOS`] lists the built-in names and [`by_name`] returns one.
//!
//! # Source data
//!
//! The crate embeds three files of the repository's top-level `data/` folder (provenance,
//! checksums and licence in `data/SOURCES.md`):
//!
//! - `hdb_carpark_information.csv`: HDB car parks with SVY21 (EPSG:3414) coordinates;
//! - `ura_mp2019_planning_area_no_sea.geojson`: the 55 URA Master Plan 2019 planning areas;
//! - `ura_mp2019_downtown_core.geojson`: the Downtown Core planning area alone.
//!
//! [`ATTRIBUTION`]: *Contains information from HDB Carpark Information and Master Plan 2019
//! Planning Area Boundary (No Sea) accessed from data.gov.sg, which is made available under
//! the terms of the Singapore Open Data Licence version 1.0.*
//!
//! # Station selection rule
//!
//! The 77 stations are HDB multi-storey car parks (rooftop pads), chosen so that they spread
//! over the inhabited island the way the car parks do:
//!
//! 1. **Candidates:** the 1,115 rows with `car_park_type` = `MULTI-STOREY CAR PARK`, in file
//!    order (by car park number), at their SVY21 coordinates in metres.
//! 2. **Seeded k-means, k = 77:** k-means++ initialisation driven by a `ChaCha8Rng` seeded
//!    with [`KMEANS_SEED`] = 77 (uniform numbers made from the raw `u64` stream), then Lloyd
//!    iterations until no car park changes cluster (11 iterations here).
//! 3. **Snap to real car parks:** for each centre in k-means++ pick order, the nearest car
//!    park not already taken.
//! 4. **Numbering:** north to south (SVY21 northing descending), `S001` … `S077`. A station
//!    is named `"{car_park_no} {address}"` (e.g. `ACM BLK 98A ALJUNIED CRESCENT`); its
//!    position is the SVY21 position converted to WGS84 by `muse-model` and rounded to 7
//!    decimals (about 1 cm), so that the written file is the source of truth.
//!
//! The details are in [`stations`].
//!
//! # Edges
//!
//! [`muse_airspace::builder::build_airspace`] with [`singapore_build_options`]: the Delaunay
//! triangulation of the stations in SVY21 (EPSG:3414, the grid the car parks are published
//! in; 214 edges, as in the stereographic plane MUSE built in before
//! docs/reference.md#airspace-from-pads), then the paper's "join collinear nodes" with a tolerance
//! of **15°**: edge A–C is dropped when a station B with edges A–B and B–C makes an angle ABC ≥
//! 165° (the detour is then at most 0.9 % longer). Edges are considered longest first and dropped
//! only while A–B and B–C remain, which keeps the graph connected. No maximum edge length. Lengths
//! are geodesic on WGS84, rounded to the millimetre. The result has 211 edges from 0.59 to 9.44 km
//! (median 2.1 km): the step removes the 14.5 km hull edge `S050-S077` along the south-western
//! coast (angle 169.2° at `S062`), so every edge can be flown within the 20-minute battery limit at
//! 30 km/h.
//!
//! # No-fly zone
//!
//! [`cbd_zone`]: the Downtown Core polygon (z dropped; 638 vertices, stored to 7 decimals ≈
//! 1 cm), closed daily 10:00–12:00 `+08:00` on all seven days, restriction `PROHIBITED`,
//! id `SG-CBD-DOWNTOWN-CORE`, name "Downtown Core (CBD) no-fly zone 10:00–12:00". No
//! station lies in it (none of the 1,115 candidates does); edges crossing it close with it.
//!
//! [`stadium_zone`]: a zone announced during the day
//! (docs/reference.md#zones-announced-during-the-day), offered alongside the scenario and not one
//! of its zones: a circle of radius 1.5 km around the National Stadium, Singapore Sports Hub (lat
//! 1.300694, lon 103.874222, from the stadium's Wikipedia infobox; see `data/SOURCES.md`, "Points
//! of interest"), restriction `PROHIBITED`, id [`STADIUM_ZONE_ID`] = `SG-NATIONAL-STADIUM-EVENT`,
//! closed on the scenario's day from 15:00 to 18:00 `+08:00` and announced at 14:00 `+08:00`: the
//! paper's "sports events" case. It closes no station (the nearest, `S069`, is about 1,510 m from
//! the centre) and 4 corridors: `S066-S069`, `S069-S070`, `S069-S076` and `S071-S076` (the last two
//! also cross the CBD zone). Its file, `scenarios/singapore-77/stadium_zone.geojson`, is
//! hand-written, not generated ([`STADIUM_ZONE_GEOJSON`]).
//!
//! # Land
//!
//! [`planning_areas`] / [`singapore_land`]: the 55 planning areas; a point is on land when
//! some planning area contains it (boundary included). The union is not computed.
//!
//! # `singapore-all`
//!
//! Every one of the 1,115 multi-storey car parks is a station (the rule is in
//! [`singapore_all`](mod@singapore_all)): id the car-park number (`ACM`), name the address,
//! position as for `singapore-77` (SVY21 → WGS84, 7 decimals); nodes sorted by car-park
//! number. If several car parks shared a position, the one with the lowest car-park number
//! would be kept and the others dropped and listed; in the embedded data none share one
//! (the closest two, `BJ15` and `BJ16`, are 18 m apart), so **0 are dropped**
//! ([`SINGAPORE_ALL_DROPPED`], checked by a test). Edges: [`build_airspace`] with
//! [`singapore_build_options`], as above (7 of the corridors differ from the stereographic
//! plane's, where four car parks are nearly on one circle): 3,302 corridors from 18 m to 9.50 km, median 0.33 km. Zone, date and
//! offset: those of `singapore-77`; the CBD zone closes no station and 7 corridors. It is
//! built from the embedded data on first use (about 6 ms in release) and cached, rather
//! than committed.
//!
//! [`build_airspace`]: muse_airspace::builder::build_airspace
//!
//! # Files
//!
//! [`build_singapore_77`] produces `scenarios/singapore-77/airspace.geojson` and
//! `scenarios/singapore-77/cbd_zone.geojson` (written by `muse airspace build`). The
//! committed files are embedded ([`AIRSPACE_GEOJSON`], [`CBD_ZONE_GEOJSON`]) and parsed by
//! [`singapore_77`] (Monday 2026-01-05, `+08:00`); a test checks that rebuilding them from
//! the source data gives the same bytes. Building takes a few milliseconds. After a
//! deliberate change of the rule, regenerate them with `muse airspace build` or
//! `cargo test -p muse-scenario -- --ignored write_files`. The announced zone's file,
//! `scenarios/singapore-77/stadium_zone.geojson`, is hand-written and embedded as
//! [`STADIUM_ZONE_GEOJSON`]; nothing regenerates it.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod candidates;
pub mod carparks;
pub mod land;
pub mod singapore;
pub mod singapore_all;
pub mod stations;
pub mod synthetic;

pub use land::{PlanningArea, planning_areas, singapore_land};
pub use singapore::{
    BuiltFiles, CBD_ZONE_ID, CBD_ZONE_NAME, KMEANS_SEED, SINGAPORE_77, STADIUM_ZONE_ID,
    STATION_COUNT, Scenario, build_singapore_77, build_singapore_77_airspace, cbd_zone,
    singapore_77, singapore_build_options, stadium_zone, station_nodes,
};
pub use singapore_all::{
    AllStations, DroppedCarPark, SINGAPORE_ALL, SINGAPORE_ALL_DROPPED, all_stations,
    build_singapore_all, build_singapore_all_airspace, singapore_all,
};
pub use synthetic::{Layout, SyntheticSpec, synthetic};

use muse_airspace::builder::BuildError;
use muse_formats::InputError;
use muse_model::coords::CoordError;

/// The attribution required by the Singapore Open Data Licence v1.0 for the embedded data.
pub const ATTRIBUTION: &str = "Contains information from HDB Carpark Information and Master \
    Plan 2019 Planning Area Boundary (No Sea) accessed from data.gov.sg, which is made \
    available under the terms of the Singapore Open Data Licence version 1.0.";

/// The committed `scenarios/singapore-77/airspace.geojson`, embedded.
pub const AIRSPACE_GEOJSON: &str = include_str!("../../../scenarios/singapore-77/airspace.geojson");

/// The committed `scenarios/singapore-77/cbd_zone.geojson` (ED-318), embedded.
pub const CBD_ZONE_GEOJSON: &str = include_str!("../../../scenarios/singapore-77/cbd_zone.geojson");

/// The committed `scenarios/singapore-77/stadium_zone.geojson` (ED-318), embedded: the
/// announced National Stadium event zone ([`stadium_zone`]). Hand-written, not generated.
pub const STADIUM_ZONE_GEOJSON: &str =
    include_str!("../../../scenarios/singapore-77/stadium_zone.geojson");

/// The embedded source data (copies of the repository's `data/` files) and their names.
pub mod data {
    /// `data/hdb_carpark_information.csv`: HDB Carpark Information (data.gov.sg).
    pub const HDB_CARPARK_CSV: &str = include_str!("../../../data/hdb_carpark_information.csv");
    /// The name used for [`HDB_CARPARK_CSV`] in messages.
    pub const HDB_CARPARK_CSV_NAME: &str = "data/hdb_carpark_information.csv";
    /// `data/ura_mp2019_planning_area_no_sea.geojson`: URA MP2019 planning areas (no sea).
    pub const PLANNING_AREAS_GEOJSON: &str =
        include_str!("../../../data/ura_mp2019_planning_area_no_sea.geojson");
    /// The name used for [`PLANNING_AREAS_GEOJSON`] in messages.
    pub const PLANNING_AREAS_GEOJSON_NAME: &str = "data/ura_mp2019_planning_area_no_sea.geojson";
    /// `data/ura_mp2019_downtown_core.geojson`: the Downtown Core planning area.
    pub const DOWNTOWN_CORE_GEOJSON: &str =
        include_str!("../../../data/ura_mp2019_downtown_core.geojson");
    /// The name used for [`DOWNTOWN_CORE_GEOJSON`] in messages.
    pub const DOWNTOWN_CORE_GEOJSON_NAME: &str = "data/ura_mp2019_downtown_core.geojson";
}

/// The names of the built-in scenarios, the default first.
pub const SCENARIOS: [&str; 2] = [SINGAPORE_77, SINGAPORE_ALL];

/// The built-in scenario called `name` (one of [`SCENARIOS`]). `singapore-77` is parsed
/// from the embedded files, `singapore-all` built from the embedded data, each once per
/// process.
///
/// ```
/// let s = muse_scenario::by_name("singapore-all").unwrap();
/// assert_eq!(s.airspace.stations().count(), 1_115);
/// let err = muse_scenario::by_name("paris").unwrap_err();
/// assert_eq!(
///     err.to_string(),
///     "unknown scenario `paris`; the built-in scenarios are singapore-77, singapore-all"
/// );
/// ```
pub fn by_name(name: &str) -> Result<&'static Scenario, ScenarioError> {
    match name {
        SINGAPORE_77 => Ok(&singapore::SINGAPORE_77_SCENARIO),
        SINGAPORE_ALL => singapore_all(),
        _ => Err(ScenarioError::UnknownScenario {
            name: name.to_owned(),
        }),
    }
}

/// Why a scenario could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScenarioError {
    /// A row of a CSV source file is malformed.
    #[error("{file}: line {line}: {message}")]
    Data {
        /// The file.
        file: String,
        /// 1-based line (the header is line 1).
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// A `GeoJSON` source file is malformed.
    #[error("{file}: {message}")]
    Geo {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// Fewer distinct candidates than stations wanted.
    #[error("{wanted} stations wanted but only {available} distinct candidate car parks")]
    TooFewCandidates {
        /// Stations wanted.
        wanted: usize,
        /// Distinct candidate positions.
        available: usize,
    },
    /// A coordinate conversion failed.
    #[error(transparent)]
    Coord(#[from] CoordError),
    /// The airspace builder failed.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A generated file could not be read back.
    #[error(transparent)]
    Input(#[from] InputError),
    /// No built-in scenario has this name.
    #[error(
        "unknown scenario `{name}`; the built-in scenarios are {}",
        SCENARIOS.join(", ")
    )]
    UnknownScenario {
        /// The name asked for.
        name: String,
    },
    /// A synthetic airspace spec is out of range.
    #[error("invalid synthetic airspace: {0}")]
    BadSpec(String),
}
