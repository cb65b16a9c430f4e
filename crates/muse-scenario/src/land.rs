//! Singapore's land: the 55 URA Master Plan 2019 planning areas (no sea), and the Downtown
//! Core polygon, parsed from the embedded `GeoJSON` files.
//!
//! The planning areas tile the land, coast and islands included, so "inside the land
//! outline" means "inside (or on the boundary of) some planning area"; their union is not
//! computed.

use std::sync::LazyLock;

use geo_types::{Coord, LineString, MultiPolygon, Polygon};
use serde_json::Value;

use crate::ScenarioError;
use crate::data::{
    DOWNTOWN_CORE_GEOJSON, DOWNTOWN_CORE_GEOJSON_NAME, PLANNING_AREAS_GEOJSON,
    PLANNING_AREAS_GEOJSON_NAME,
};

/// One URA Master Plan 2019 planning area.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanningArea {
    /// `PLN_AREA_N`, e.g. `DOWNTOWN CORE`.
    pub name: String,
    /// `PLN_AREA_C`, e.g. `DT`.
    pub code: String,
    /// `REGION_N`, e.g. `CENTRAL REGION`.
    pub region: String,
    /// The area, WGS84 degrees (`x` = longitude, `y` = latitude; the file's z is dropped).
    pub area: MultiPolygon<f64>,
}

static PLANNING_AREAS: LazyLock<Vec<PlanningArea>> = LazyLock::new(|| {
    parse_planning_areas(PLANNING_AREAS_GEOJSON, PLANNING_AREAS_GEOJSON_NAME)
        .expect("the embedded planning-area file is valid (checked by the tests)")
});

/// The 55 planning areas, in file order. Parsed once, on first use.
///
/// ```
/// let areas = muse_scenario::planning_areas();
/// assert_eq!(areas.len(), 55);
/// assert!(areas.iter().any(|a| a.name == "DOWNTOWN CORE" && a.code == "DT"));
/// ```
pub fn planning_areas() -> &'static [PlanningArea] {
    &PLANNING_AREAS
}

/// Singapore's land as one multipolygon: every polygon of every planning area (they tile
/// the land without overlapping, so a point is on land iff some polygon contains it or has
/// it on its boundary).
///
/// ```
/// use geo_types::MultiPolygon;
/// let land: MultiPolygon<f64> = muse_scenario::singapore_land();
/// assert!(land.0.len() >= 55);
/// ```
pub fn singapore_land() -> MultiPolygon<f64> {
    MultiPolygon(
        planning_areas()
            .iter()
            .flat_map(|a| a.area.0.iter().cloned())
            .collect(),
    )
}

/// The Downtown Core polygon from the embedded `ura_mp2019_downtown_core.geojson` (z
/// dropped): the area of the CBD no-fly zone.
pub fn downtown_core() -> Result<MultiPolygon<f64>, ScenarioError> {
    let file = DOWNTOWN_CORE_GEOJSON_NAME;
    let features = features(DOWNTOWN_CORE_GEOJSON, file)?;
    let [feature] = features.as_slice() else {
        return Err(geo_err(
            file,
            format!("expected 1 feature, found {}", features.len()),
        ));
    };
    let name = feature
        .pointer("/properties/PLN_AREA_N")
        .and_then(Value::as_str);
    if name != Some("DOWNTOWN CORE") {
        return Err(geo_err(
            file,
            format!("the feature is {name:?}, not DOWNTOWN CORE"),
        ));
    }
    geometry(feature.get("geometry").unwrap_or(&Value::Null))
        .map_err(|m| geo_err(file, format!("feature 0: {m}")))
}

/// Parses the MP2019 planning-area `GeoJSON`: a `FeatureCollection` whose features carry an
/// HTML `Description` table with `PLN_AREA_N`, `PLN_AREA_C` and `REGION_N`.
pub fn parse_planning_areas(text: &str, file: &str) -> Result<Vec<PlanningArea>, ScenarioError> {
    features(text, file)?
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let desc = f
                .pointer("/properties/Description")
                .and_then(Value::as_str)
                .unwrap_or("");
            let field = |key: &str| {
                html_field(desc, key).ok_or_else(|| {
                    geo_err(file, format!("feature {i}: no `{key}` in the Description"))
                })
            };
            Ok(PlanningArea {
                name: field("PLN_AREA_N")?,
                code: field("PLN_AREA_C")?,
                region: field("REGION_N")?,
                area: geometry(f.get("geometry").unwrap_or(&Value::Null))
                    .map_err(|m| geo_err(file, format!("feature {i}: {m}")))?,
            })
        })
        .collect()
}

fn geo_err(file: &str, message: String) -> ScenarioError {
    ScenarioError::Geo {
        file: file.to_owned(),
        message,
    }
}

fn features(text: &str, file: &str) -> Result<Vec<Value>, ScenarioError> {
    let mut root: Value =
        serde_json::from_str(text).map_err(|e| geo_err(file, format!("not JSON: {e}")))?;
    match root.get_mut("features").map(Value::take) {
        Some(Value::Array(list)) => Ok(list),
        _ => Err(geo_err(file, "not a GeoJSON FeatureCollection".into())),
    }
}

/// The value of `<th>KEY</th> <td>VALUE</td>` in an HTML attribute table.
fn html_field(html: &str, key: &str) -> Option<String> {
    let start = html.find(&format!("<th>{key}</th>"))?;
    let rest = &html[start..];
    let open = rest.find("<td>")? + "<td>".len();
    let close = rest[open..].find("</td>")? + open;
    Some(rest[open..close].trim().to_owned())
}

/// A `GeoJSON` `Polygon` or `MultiPolygon` geometry as a multipolygon (extra coordinates such
/// as z are ignored).
fn geometry(g: &Value) -> Result<MultiPolygon<f64>, String> {
    let coords = g
        .get("coordinates")
        .ok_or("the geometry has no coordinates")?;
    match g.get("type").and_then(Value::as_str) {
        Some("Polygon") => Ok(MultiPolygon(vec![polygon(coords)?])),
        Some("MultiPolygon") => Ok(MultiPolygon(
            coords
                .as_array()
                .ok_or("MultiPolygon coordinates are not an array")?
                .iter()
                .map(polygon)
                .collect::<Result<_, _>>()?,
        )),
        other => Err(format!("unsupported geometry type {other:?}")),
    }
}

fn polygon(rings: &Value) -> Result<Polygon<f64>, String> {
    let rings = rings.as_array().ok_or("polygon rings are not an array")?;
    let mut rings = rings.iter().map(ring);
    let exterior = rings.next().ok_or("a polygon without rings")??;
    let interiors = rings.collect::<Result<Vec<_>, _>>()?;
    Ok(Polygon::new(exterior, interiors))
}

fn ring(positions: &Value) -> Result<LineString<f64>, String> {
    let positions = positions.as_array().ok_or("a ring is not an array")?;
    if positions.len() < 4 {
        return Err(format!(
            "a ring has {} positions; at least 4 are needed",
            positions.len()
        ));
    }
    positions
        .iter()
        .map(|p| {
            let xy = p
                .as_array()
                .filter(|a| a.len() >= 2)
                .ok_or("a position is not [x, y, …]")?;
            match (xy[0].as_f64(), xy[1].as_f64()) {
                (Some(x), Some(y)) => Ok(Coord { x, y }),
                _ => Err("a coordinate is not a number".to_owned()),
            }
        })
        .collect::<Result<Vec<_>, String>>()
        .map(LineString::new)
}

/// The largest coordinate difference between corresponding vertices of two multipolygons,
/// or `None` if they differ in structure (polygon, ring or vertex counts).
#[cfg(test)]
pub(crate) fn max_vertex_gap(a: &MultiPolygon<f64>, b: &MultiPolygon<f64>) -> Option<f64> {
    let rings = |p: &Polygon<f64>| -> Vec<LineString<f64>> {
        std::iter::once(p.exterior().clone())
            .chain(p.interiors().iter().cloned())
            .collect()
    };
    if a.0.len() != b.0.len() {
        return None;
    }
    let mut gap = 0.0_f64;
    for (p, q) in a.0.iter().zip(&b.0) {
        let (rp, rq) = (rings(p), rings(q));
        if rp.len() != rq.len() {
            return None;
        }
        for (r, t) in rp.iter().zip(&rq) {
            if r.0.len() != t.0.len() {
                return None;
            }
            for (u, v) in r.0.iter().zip(&t.0) {
                gap = gap.max((u.x - v.x).abs()).max((u.y - v.y).abs());
            }
        }
    }
    Some(gap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planning_areas_parse() {
        let areas = planning_areas();
        assert_eq!(areas.len(), 55);
        let mut names: Vec<&str> = areas.iter().map(|a| a.name.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), 55, "names are unique");
        assert!(areas.iter().all(|a| !a.area.0.is_empty()));
    }

    #[test]
    fn downtown_core_is_the_planning_area() {
        let dt = downtown_core().unwrap();
        assert_eq!(dt.0.len(), 1);
        assert_eq!(dt.0[0].exterior().0.len(), 638);
        let from_areas = planning_areas()
            .iter()
            .find(|a| a.name == "DOWNTOWN CORE")
            .unwrap();
        // The derived file keeps the geometry unchanged. (Its numbers are written with fewer
        // digits, and serde_json's default float parser may differ from correct rounding by
        // an ulp on long inputs, hence a tolerance of 1e-12° ≈ 0.1 µm.)
        let gap = max_vertex_gap(&from_areas.area, &dt).expect("same structure");
        assert!(gap < 1e-12, "{gap}");
    }

    #[test]
    fn html_fields() {
        let d = "<tr> <th>PLN_AREA_N</th> <td>BEDOK</td> </tr><tr> <th>PLN_AREA_C</th> <td>BD</td>";
        assert_eq!(html_field(d, "PLN_AREA_C").as_deref(), Some("BD"));
        assert_eq!(html_field(d, "REGION_N"), None);
    }

    #[test]
    fn bad_geometry() {
        let text = r#"{"type":"FeatureCollection","features":[{"type":"Feature","properties":{},"geometry":{"type":"Point","coordinates":[1,2]}}]}"#;
        let err = parse_planning_areas(text, "pa.geojson").unwrap_err();
        assert!(
            err.to_string()
                .starts_with("pa.geojson: feature 0: no `PLN_AREA_N`"),
            "{err}"
        );
        assert!(geometry(&serde_json::json!({"type":"Point","coordinates":[1,2]})).is_err());
        assert!(polygon(&serde_json::json!([[[0, 0], [1, 0], [0, 0]]])).is_err());
    }
}
