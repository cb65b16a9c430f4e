//! MUSE file formats (SPEC §2, §4, §5, §7).
//!
//! Every reader takes the text of a file together with a name for it (usually its path)
//! and returns either the parsed value or an [`InputError`] that names the file, the line
//! or feature, and the field. Nothing here panics on bad input.
//!
//! - [`airspace_geojson`]: the airspace GeoJSON (nodes as `Point`s, edges as `LineString`s);
//! - [`zones`]: no-fly zones in the ED-318 GeoJSON profile and ED-269 JSON;
//! - [`requests`]: the requests CSV;
//! - [`plans`]: plan output as JSON Lines;
//! - [`flights`]: planned flights as time-stamped GeoJSON lines (QGIS, kepler.gl);
//! - [`flights_csv`]: one row per request, the plans file as a table;
//! - [`stays_csv`]: one row per stay of every flight that flies.

pub mod airspace_geojson;
pub mod error;
pub mod flights;
pub mod flights_csv;
pub mod plans;
pub mod requests;
pub mod stays_csv;
pub mod zones;

pub use error::{InputError, Location};

/// Reads a whole file to a string, mapping I/O failures to an [`InputError`].
pub fn read_to_string(path: &std::path::Path) -> Result<String, InputError> {
    std::fs::read_to_string(path).map_err(|e| {
        InputError::new(
            path.display().to_string(),
            Location::Whole,
            None,
            format!("cannot read: {e}"),
        )
    })
}
