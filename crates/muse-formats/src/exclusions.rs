//! Exclusion polygons for building an airspace from pads (docs/reference.md#airspace-from-pads):
//! areas no corridor may meet, as GeoJSON — a FeatureCollection of `Polygon` or `MultiPolygon`
//! features, one such feature, or a bare geometry. Positions are `[lon, lat]` in WGS84; each ring
//! has at least four positions and ends where it starts; the first ring of a polygon is its
//! outline, the others its holes.
//!
//! ```
//! use muse_formats::exclusions::read_exclusions;
//! let text = r#"{"type": "Polygon", "coordinates": [[[16.3, 48.2], [16.4, 48.2], [16.4, 48.3], [16.3, 48.2]]]}"#;
//! assert_eq!(read_exclusions(text, "lake.geojson").unwrap().len(), 1);
//! let open = r#"{"type": "Polygon", "coordinates": [[[16.3, 48.2], [16.4, 48.2], [16.4, 48.3], [16.3, 48.3]]]}"#;
//! assert_eq!(
//!     read_exclusions(open, "lake.geojson").unwrap_err().to_string(),
//!     "lake.geojson: feature 0: field `coordinates`: ring 0 does not end where it starts"
//! );
//! ```

use std::path::Path;

use geo_types::{Coord, LineString, Polygon};
use serde_json::Value;

use crate::error::{InputError, Location};

/// Reads exclusion polygons from GeoJSON text; `file` names it in errors.
///
/// # Errors
/// Not JSON, not a polygon, a position that is not `[lon, lat]` within WGS84, or a ring
/// that is too short or not closed, naming the feature and field.
pub fn read_exclusions(text: &str, file: &str) -> Result<Vec<Polygon<f64>>, InputError> {
    let v: Value = serde_json::from_str(text)
        .map_err(|e| InputError::new(file, Location::Whole, None, format!("not JSON: {e}")))?;
    let geometries: Vec<&Value> = match v["type"].as_str() {
        Some("FeatureCollection") => v["features"]
            .as_array()
            .ok_or_else(|| InputError::new(file, Location::Whole, Some("features"), "not a list"))?
            .iter()
            .map(|f| &f["geometry"])
            .collect(),
        Some("Feature") => vec![&v["geometry"]],
        _ => vec![&v],
    };
    let mut out = Vec::new();
    for (index, g) in geometries.into_iter().enumerate() {
        let polygons = geometry_polygons(g, "an exclusion").map_err(|(field, m)| {
            InputError::new(file, Location::Feature { index, id: None }, Some(field), m)
        })?;
        out.extend(polygons);
    }
    Ok(out)
}

/// The polygons of a GeoJSON `Polygon` or `MultiPolygon` geometry; else the field to blame
/// and why (`what` names what the geometry is for in the message, e.g. `an exclusion`).
pub(crate) fn geometry_polygons(
    g: &Value,
    what: &str,
) -> Result<Vec<Polygon<f64>>, (&'static str, String)> {
    let coords = &g["coordinates"];
    match g["type"].as_str() {
        Some("Polygon") => Ok(vec![polygon(coords).map_err(|m| ("coordinates", m))?]),
        Some("MultiPolygon") => coords
            .as_array()
            .ok_or_else(|| {
                (
                    "coordinates",
                    "a MultiPolygon's coordinates are a list of polygons".to_owned(),
                )
            })?
            .iter()
            .map(|p| polygon(p).map_err(|m| ("coordinates", m)))
            .collect(),
        other => Err((
            "type",
            format!(
                "{}: {what} is a GeoJSON Polygon or MultiPolygon",
                other.map_or_else(|| "no geometry type".to_owned(), |t| format!("`{t}`"))
            ),
        )),
    }
}

/// Reads an exclusions file.
///
/// # Errors
/// An unreadable file, or as [`read_exclusions`].
pub fn read_exclusions_file(path: &Path) -> Result<Vec<Polygon<f64>>, InputError> {
    read_exclusions(&crate::read_to_string(path)?, &path.display().to_string())
}

/// The polygons of several exclusion files, in order, each knowing the file and place it came
/// from, to name it when a pad lies in it.
#[derive(Clone, Debug, Default)]
pub struct Exclusions {
    /// Every polygon of every file, in order.
    pub polygons: Vec<Polygon<f64>>,
    /// Each polygon's file and its index there (counted from 0).
    origin: Vec<(String, usize)>,
}

impl Exclusions {
    /// Reads the exclusion files `paths`, in order.
    ///
    /// # Errors
    /// The first file that cannot be read, as [`read_exclusions_file`] says.
    pub fn read_files(paths: &[impl AsRef<Path>]) -> Result<Self, InputError> {
        let mut all = Exclusions::default();
        for path in paths {
            let path = path.as_ref();
            let polygons = read_exclusions_file(path)?;
            let file = path.display().to_string();
            all.origin
                .extend((0..polygons.len()).map(|k| (file.clone(), k)));
            all.polygons.extend(polygons);
        }
        Ok(all)
    }

    /// Why pad `id` of the pads file `pads` cannot be: it lies in polygon `polygon` of these.
    pub fn pad_inside(&self, pads: &str, id: &str, polygon: usize) -> String {
        let (file, k) = &self.origin[polygon];
        format!("{pads}: pad `{id}` lies in polygon {k} (counted from 0) of the exclusions {file}")
    }
}

/// A polygon from its GeoJSON rings.
fn polygon(rings: &Value) -> Result<Polygon<f64>, String> {
    let rings = rings
        .as_array()
        .filter(|r| !r.is_empty())
        .ok_or("a Polygon's coordinates are a list of rings")?;
    let mut lines = rings.iter().enumerate().map(|(k, ring)| {
        let positions = ring
            .as_array()
            .ok_or_else(|| format!("ring {k} is not a list of positions"))?;
        let coords = positions
            .iter()
            .map(|p| {
                let (lon, lat) = (p[0].as_f64(), p[1].as_f64());
                match (lon, lat) {
                    (Some(x), Some(y))
                        if (-180.0..=180.0).contains(&x) && (-90.0..=90.0).contains(&y) =>
                    {
                        Ok(Coord { x, y })
                    }
                    _ => Err(format!(
                        "ring {k}: {p} is not a [lon, lat] position in WGS84"
                    )),
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        if coords.len() < 4 {
            return Err(format!(
                "ring {k} has {} positions; a ring needs at least 4",
                coords.len()
            ));
        }
        if coords.first() != coords.last() {
            return Err(format!("ring {k} does not end where it starts"));
        }
        Ok(LineString(coords))
    });
    let outline = lines.next().expect("at least one ring")?;
    let holes = lines.collect::<Result<Vec<_>, _>>()?;
    Ok(Polygon::new(outline, holes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collections_features_and_multipolygons() {
        let square = "[[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]";
        let text = format!(
            r#"{{"type": "FeatureCollection", "features": [
              {{"type": "Feature", "properties": {{}}, "geometry": {{"type": "Polygon", "coordinates": {square}}}}},
              {{"type": "Feature", "properties": {{}}, "geometry": {{"type": "MultiPolygon", "coordinates": [{square}, {square}]}}}}]}}"#
        );
        assert_eq!(read_exclusions(&text, "x").unwrap().len(), 3);
        let feature = format!(
            r#"{{"type": "Feature", "geometry": {{"type": "Polygon", "coordinates": {square}}}}}"#
        );
        assert_eq!(read_exclusions(&feature, "x").unwrap().len(), 1);
    }

    #[test]
    fn bad_exclusions_are_named() {
        let cases = [
            (
                "[",
                "x: not JSON: EOF while parsing a list at line 1 column 1",
            ),
            (
                r#"{"type": "Point", "coordinates": [0, 0]}"#,
                "x: feature 0: field `type`: `Point`: an exclusion is a GeoJSON Polygon or MultiPolygon",
            ),
            (
                r#"{"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [0, 0]]]}"#,
                "x: feature 0: field `coordinates`: ring 0 has 3 positions; a ring needs at least 4",
            ),
            (
                r#"{"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 95], [0, 0]]]}"#,
                "x: feature 0: field `coordinates`: ring 0: [1,95] is not a [lon, lat] position in WGS84",
            ),
            (
                r#"{"type": "Polygon", "coordinates": []}"#,
                "x: feature 0: field `coordinates`: a Polygon's coordinates are a list of rings",
            ),
            (
                r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": null}]}"#,
                "x: feature 0: field `type`: no geometry type: an exclusion is a GeoJSON Polygon or MultiPolygon",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(
                read_exclusions(text, "x").unwrap_err().to_string(),
                want,
                "{text}"
            );
        }
    }
}
