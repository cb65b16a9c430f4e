//! MUSE file formats (docs/reference.md#airspace, #no-fly-zones, #requests, #plans,
//! #airspace-from-pads).
//!
//! Every reader takes the text of a file together with a name for it (usually its path)
//! and returns either the parsed value or an [`InputError`] that names the file, the line
//! or feature, and the field. Nothing here panics on bad input.
//!
//! - [`airspace_geojson`]: the airspace GeoJSON (nodes as `Point`s, edges as `LineString`s);
//! - [`day`]: the day an airspace is planned on (its date and UTC offset), which a file may carry;
//! - [`zones`]: no-fly zones in the ED-318 GeoJSON profile and ED-269 JSON;
//! - [`pads`]: the pads an airspace is built from (CSV or GeoJSON points,
//!   docs/reference.md#airspace-from-pads);
//! - [`exclusions`]: polygons no corridor of an airspace built from pads may meet;
//! - [`land`]: the land outline an airspace file may carry, for its maps;
//! - [`customers`]: customers, the points demand is drawn between
//!   (docs/reference.md#airspace-from-pads);
//! - [`requests`]: the requests CSV;
//! - [`plans`]: plan output as JSON Lines;
//! - [`flights`]: planned flights as time-stamped GeoJSON lines (QGIS, kepler.gl);
//! - [`flights_csv`]: one row per request, the plans file as a table;
//! - [`stays_csv`]: one row per stay of every flight that flies;
//! - [`params`]: the flight parameters in user units (summaries, `/healthz`, options);
//! - [`layer_params`]: the layering in user units (options, the Python package's keywords);
//! - [`ranges`]: the accepted range of each of them, of the layering's, and of every other
//!   numeric option (one table: the command line, the Python package and the service).
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod airspace_geojson;
pub mod customers;
pub mod day;
pub mod error;
pub mod exclusions;
mod fields;
pub mod flights;
pub mod flights_csv;
pub mod land;
pub mod layer_params;
pub mod pads;
pub mod params;
pub mod plans;
pub mod ranges;
pub mod requests;
pub mod stays_csv;
mod table;

pub use table::CsvWriter;
pub mod zones;

pub use error::{InputError, Location};

/// Reads a whole file to a string, mapping I/O failures to an [`InputError`]. A file that is
/// not UTF-8 is an error naming the line (and the byte in it) of the first bad byte.
pub fn read_to_string(path: &std::path::Path) -> Result<String, InputError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        InputError::new(
            file.as_str(),
            Location::Whole,
            None,
            format!("cannot read: {e}"),
        )
    })?;
    String::from_utf8(bytes).map_err(|e| not_utf8(&file, e.as_bytes(), e.utf8_error()))
}

/// The error for text that is not UTF-8: the line of the first bad byte, the byte's place in
/// the line (1-based) and its value.
///
/// ```
/// let bytes = b"id,origin\nr\xe9,A\n";
/// let e = std::str::from_utf8(bytes).unwrap_err();
/// assert_eq!(
///     muse_formats::not_utf8("r.csv", bytes, e).to_string(),
///     "r.csv: line 2: byte 2 of the line, 0xE9, is not UTF-8: save the file as UTF-8"
/// );
/// ```
pub fn not_utf8(file: &str, bytes: &[u8], e: std::str::Utf8Error) -> InputError {
    let at = e.valid_up_to();
    let before = &bytes[..at];
    let line = before.split(|&b| b == b'\n').count();
    let column = at
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1)
        + 1;
    let byte = bytes.get(at).copied().unwrap_or_default();
    InputError::new(
        file,
        Location::Line(line),
        None,
        format!("byte {column} of the line, 0x{byte:02X}, is not UTF-8: save the file as UTF-8"),
    )
}
