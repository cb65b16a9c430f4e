//! The land outline an airspace file may carry (`muse airspace build --land`): `Polygon` or
//! `MultiPolygon` features with `"kind": "land"`, drawn on the airspace's maps and in the
//! viewer; not part of the graph ([`crate::airspace_geojson`] skips them).

use std::fmt::Write as _;

use geo_types::{LineString, Polygon};
use serde_json::Value;

use crate::error::{InputError, Location};

/// The `kind` of the land outline's features.
pub(crate) const LAND: &str = "land";

pub(crate) fn land_polygons(geometry: &Value) -> Result<Vec<Polygon<f64>>, (&'static str, String)> {
    crate::exclusions::geometry_polygons(geometry, "the land outline").map_err(|(field, m)| {
        (
            if field == "type" {
                "geometry.type"
            } else {
                "geometry.coordinates"
            },
            m,
        )
    })
}

/// The land outline of an airspace file's JSON document (its features of kind `land`), in
/// file order; none for most files. [`AirspaceFile`](crate::airspace_geojson::AirspaceFile)
/// reads it:
///
/// ```
/// let text = r#"{"type": "FeatureCollection", "features": [
///   {"type": "Feature", "geometry": {"type": "Point", "coordinates": [16.37, 48.2]}, "properties": {"id": "A", "kind": "station"}},
///   {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[16.3, 48.1], [16.5, 48.1], [16.5, 48.3], [16.3, 48.1]]]}, "properties": {"kind": "land"}}]}"#;
/// let file = muse_formats::airspace_geojson::AirspaceFile::parse(text, "a.geojson").unwrap();
/// assert_eq!((file.land.len(), file.airspace.node_count()), (1, 1));
/// ```
pub(crate) fn land_of(root: &Value, file: &str) -> Result<Vec<Polygon<f64>>, InputError> {
    let mut out = Vec::new();
    for (index, feature) in root["features"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        if feature["properties"]["kind"].as_str() != Some(LAND) {
            continue;
        }
        let polygons = land_polygons(&feature["geometry"]).map_err(|(field, m)| {
            InputError::new(file, Location::Feature { index, id: None }, Some(field), m)
        })?;
        out.extend(polygons);
    }
    Ok(out)
}

/// Appends one land feature for `p` (positions rounded to 7 decimals, as the airspace's).
pub(crate) fn write_land_feature(out: &mut String, p: &Polygon<f64>) {
    let ring = |l: &LineString<f64>| {
        let positions: Vec<String> =
            l.0.iter()
                .map(|c| format!("[{}, {}]", round7(c.x), round7(c.y)))
                .collect();
        format!("[{}]", positions.join(", "))
    };
    let rings: Vec<String> = std::iter::once(p.exterior())
        .chain(p.interiors())
        .map(ring)
        .collect();
    let _ = write!(
        out,
        "{{\"type\": \"Feature\", \"geometry\": {{\"type\": \"Polygon\", \"coordinates\": [{}]}}, \
         \"properties\": {{\"kind\": \"{LAND}\"}}}}",
        rings.join(", ")
    );
}

/// `x` rounded to 7 decimals, printed as the shortest text that reads back the same.
fn round7(x: f64) -> String {
    let r = (x * 1e7).round() / 1e7;
    let r = if r == 0.0 { 0.0 } else { r };
    format!("{r:?}")
}
