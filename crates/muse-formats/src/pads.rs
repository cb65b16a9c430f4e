//! Pads files (docs/reference.md#airspace-from-pads): the stations an airspace is built from, as a
//! CSV (`id,lon,lat` and an optional `name`, any order, other columns ignored) or as GeoJSON points
//! (a FeatureCollection of `Point` features with an `id` property, or the feature's `id`, and an
//! optional `name`).
//!
//! Each pad becomes a station [`Node`] in the file's order. Refused, naming the line (or
//! feature) and field: a missing or empty id, an id that is not 1 to 64 of the ASCII letters
//! and digits and `_.~:` (a corridor's id joins two pad ids with `-`), the same id twice, a
//! position that is not a number or is outside WGS84 (longitude −180 to 180, latitude −90 to
//! 90), and two pads at one position; and a file with fewer than three pads.
//!
//! ```
//! use muse_formats::pads::read_pads;
//! let csv = "id,lon,lat,name\nP1,16.37,48.21,Stephansplatz\nP2,16.40,48.20,\nP3,16.35,48.19,\n";
//! let pads = read_pads(csv, "pads.csv").unwrap();
//! assert_eq!(pads.len(), 3);
//! assert_eq!((pads[0].id.as_str(), pads[0].name.as_str()), ("P1", "Stephansplatz"));
//! let e = read_pads("id,lon,lat\nP1,16.37,48.21\nP1,16.40,48.20\nP3,16.35,48.19\n", "p.csv");
//! assert_eq!(e.unwrap_err().to_string(), "p.csv: line 3: field `id`: duplicate pad id `P1` (first on line 2)");
//! ```

use std::collections::HashMap;
use std::path::Path;

use muse_model::{LonLat, Node, NodeKind};
use serde_json::Value;

use crate::error::{InputError, Location};
use crate::table::{Table, number};

/// The fewest pads an airspace is built from (a triangle).
pub const MIN_PADS: usize = 3;

/// The longest pad id, characters.
pub const MAX_ID_LEN: usize = 64;

/// Whether `id` is a valid pad id: 1 to [`MAX_ID_LEN`] of the ASCII letters and digits and
/// `_.~:`.
pub fn valid_pad_id(id: &str) -> bool {
    (1..=MAX_ID_LEN).contains(&id.len())
        && id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.' | b'~' | b':'))
}

/// One pad as read, with where it was.
struct Pad {
    id: String,
    name: String,
    lon: f64,
    lat: f64,
    at: Location,
}

/// Reads a pads file's text (CSV, or GeoJSON when it starts with `{`); `file` names it in
/// errors.
///
/// # Errors
/// The first bad line or feature, or too few pads (see the [module documentation](self)).
pub fn read_pads(text: &str, file: &str) -> Result<Vec<Node>, InputError> {
    read_at_least(text, file, MIN_PADS, "an airspace needs")
}

/// Reads a file of candidate pads (`muse siting --candidates`): as [`read_pads`], but one pad
/// is enough.
///
/// # Errors
/// The first bad line or feature, or no pad at all.
pub fn read_candidate_pads(text: &str, file: &str) -> Result<Vec<Node>, InputError> {
    read_at_least(text, file, 1, "siting needs")
}

/// Reads a candidate pads file.
///
/// # Errors
/// An unreadable file, or as [`read_candidate_pads`].
pub fn read_candidate_pads_file(path: &Path) -> Result<Vec<Node>, InputError> {
    read_candidate_pads(&crate::read_to_string(path)?, &path.display().to_string())
}

fn read_at_least(text: &str, file: &str, min: usize, needs: &str) -> Result<Vec<Node>, InputError> {
    let pads = if text.trim_start().starts_with('{') {
        geojson_pads(text, file)?
    } else {
        csv_pads(text, file)?
    };
    check(&pads, file, min, needs)?;
    Ok(pads
        .into_iter()
        .map(|p| Node {
            id: p.id,
            kind: NodeKind::Station,
            name: p.name,
            pos: LonLat::new(p.lon, p.lat),
        })
        .collect())
}

/// Reads a pads file.
///
/// # Errors
/// An unreadable file, or as [`read_pads`].
pub fn read_pads_file(path: &Path) -> Result<Vec<Node>, InputError> {
    read_pads(&crate::read_to_string(path)?, &path.display().to_string())
}

fn csv_pads(text: &str, file: &str) -> Result<Vec<Pad>, InputError> {
    let mut table = Table::new(text, file)?;
    let [id, lon, lat] = table.required(
        ["id", "lon", "lat"],
        "a pads CSV has the columns id, lon, lat and optionally name",
    )?;
    let name = table.column("name");
    let mut out = Vec::new();
    for row in table.rows() {
        let (record, line) = row?;
        let at = Location::Line(line);
        let get = |i: usize| record.get(i).unwrap_or("");
        let coordinate = |i: usize, field: &str| {
            number(get(i)).map_err(|m| InputError::new(file, at.clone(), Some(field), m))
        };
        out.push(Pad {
            id: get(id).to_owned(),
            name: name.map_or("", get).to_owned(),
            lon: coordinate(lon, "lon")?,
            lat: coordinate(lat, "lat")?,
            at,
        });
    }
    Ok(out)
}

fn geojson_pads(text: &str, file: &str) -> Result<Vec<Pad>, InputError> {
    let whole = |m: String| InputError::new(file, Location::Whole, None, m);
    let v: Value = serde_json::from_str(text).map_err(|e| whole(format!("not JSON: {e}")))?;
    let (Some("FeatureCollection"), Some(features)) =
        (v["type"].as_str(), v["features"].as_array())
    else {
        return Err(whole(
            "not a GeoJSON FeatureCollection with `features`".into(),
        ));
    };
    features
        .iter()
        .enumerate()
        .map(|(index, f)| {
            let id = f["properties"]["id"]
                .as_str()
                .or_else(|| f["id"].as_str())
                .unwrap_or("")
                .to_owned();
            let at = Location::Feature {
                index,
                id: (!id.is_empty()).then(|| id.clone()),
            };
            let err = |field: &str, m: String| InputError::new(file, at.clone(), Some(field), m);
            let geometry = &f["geometry"];
            if geometry["type"].as_str() != Some("Point") {
                return Err(err("geometry", "a pad is a GeoJSON `Point`".into()));
            }
            let coords = geometry["coordinates"]
                .as_array()
                .ok_or_else(|| err("coordinates", "a Point's coordinates are [lon, lat]".into()))?;
            let coord = |k: usize, field: &str| {
                coords
                    .get(k)
                    .and_then(Value::as_f64)
                    .ok_or_else(|| err(field, "a Point's coordinates are [lon, lat]".into()))
            };
            Ok(Pad {
                name: f["properties"]["name"].as_str().unwrap_or("").to_owned(),
                lon: coord(0, "lon")?,
                lat: coord(1, "lat")?,
                id,
                at,
            })
        })
        .collect()
}

/// The rules every pad must keep, whatever the file's form.
fn check(pads: &[Pad], file: &str, min: usize, needs: &str) -> Result<(), InputError> {
    let mut ids: HashMap<&str, &Location> = HashMap::with_capacity(pads.len());
    let mut positions: HashMap<(u64, u64), &Pad> = HashMap::with_capacity(pads.len());
    for p in pads {
        let err = |field: &str, m: String| InputError::new(file, p.at.clone(), Some(field), m);
        if p.id.is_empty() {
            return Err(err("id", "missing".into()));
        }
        if !valid_pad_id(&p.id) {
            return Err(err(
                "id",
                format!(
                    "{:?} is not a valid pad id: 1 to {MAX_ID_LEN} of the ASCII letters and \
                     digits and `_.~:` (a corridor's id joins two pad ids with `-`)",
                    p.id
                ),
            ));
        }
        if let Some(first) = ids.insert(&p.id, &p.at) {
            return Err(err(
                "id",
                format!("duplicate pad id `{}` (first {})", p.id, where_(first)),
            ));
        }
        if !(-180.0..=180.0).contains(&p.lon) {
            return Err(err("lon", format!("{} is outside −180 to 180", p.lon)));
        }
        if !(-90.0..=90.0).contains(&p.lat) {
            return Err(err("lat", format!("{} is outside −90 to 90", p.lat)));
        }
        // −0.0 and 0.0 are one position.
        let key = ((p.lon + 0.0).to_bits(), (p.lat + 0.0).to_bits());
        if let Some(other) = positions.insert(key, p) {
            return Err(err(
                "lon",
                format!(
                    "pad `{}` is at the position of pad `{}` ({}): two pads cannot share a position",
                    p.id,
                    other.id,
                    where_(&other.at)
                ),
            ));
        }
    }
    if pads.len() < min {
        return Err(InputError::new(
            file,
            Location::Whole,
            None,
            format!(
                "{} pad{}: {needs} at least {min}",
                pads.len(),
                if pads.len() == 1 { "" } else { "s" }
            ),
        ));
    }
    Ok(())
}

/// `on line 3` or `feature 2 (`P1`)`.
fn where_(at: &Location) -> String {
    match at {
        Location::Line(n) => format!("on line {n}"),
        Location::Feature { index, .. } => format!("feature {index}"),
        Location::Whole => "in the file".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        read_pads(text, "p").unwrap_err().to_string()
    }

    #[test]
    fn csv_columns_in_any_order_and_extra_columns_ignored() {
        let pads = read_pads(
            "lat,note,id,lon\n48.2,x,A,16.3\n48.3,y,B,16.4\n48.25,z,C,16.5\n",
            "p",
        )
        .unwrap();
        let ids: Vec<&str> = pads.iter().map(|n| n.id.as_str()).collect();
        assert_eq!(ids, ["A", "B", "C"]);
        assert_eq!((pads[1].pos.lon, pads[1].pos.lat), (16.4, 48.3));
        assert!(
            pads.iter()
                .all(|n| n.kind == NodeKind::Station && n.name.is_empty())
        );
    }

    #[test]
    fn geojson_points_with_ids_in_properties_or_on_the_feature() {
        let text = r#"{"type": "FeatureCollection", "features": [
          {"type": "Feature", "properties": {"id": "A", "name": "Alpha"}, "geometry": {"type": "Point", "coordinates": [16.3, 48.2]}},
          {"type": "Feature", "id": "B", "properties": {}, "geometry": {"type": "Point", "coordinates": [16.4, 48.3]}},
          {"type": "Feature", "id": "C", "geometry": {"type": "Point", "coordinates": [16.5, 48.25, 180.0]}}]}"#;
        let pads = read_pads(text, "p").unwrap();
        assert_eq!(pads[0].name, "Alpha");
        assert_eq!(pads[2].id, "C");
        assert_eq!(
            err(&text.replace(
                "\"Point\", \"coordinates\": [16.4, 48.3]",
                "\"LineString\", \"coordinates\": [[16.4, 48.3], [1, 2]]"
            )),
            "p: feature 1 (`B`): field `geometry`: a pad is a GeoJSON `Point`"
        );
        assert_eq!(
            err("{\"type\": \"Feature\"}"),
            "p: not a GeoJSON FeatureCollection with `features`"
        );
    }

    #[test]
    fn every_bad_pad_is_named_by_line_and_field() {
        let ok = "id,lon,lat\nA,16.3,48.2\nB,16.4,48.3\nC,16.5,48.25\n";
        assert!(read_pads(ok, "p").is_ok());
        let cases = [
            (
                "id,lon\nA,16.3\n",
                "p: line 1: field `lat`: the header has no `lat` column: a pads CSV has the columns id, lon, lat and optionally name",
            ),
            (
                "id,lon,lat\n,16.3,48.2\nB,16.4,48.3\nC,16.5,48.25\n",
                "p: line 2: field `id`: missing",
            ),
            (
                "id,lon,lat\nA-1,16.3,48.2\nB,16.4,48.3\nC,16.5,48.25\n",
                "p: line 2: field `id`: \"A-1\" is not a valid pad id: 1 to 64 of the ASCII letters and digits and `_.~:` (a corridor's id joins two pad ids with `-`)",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,east,48.3\nC,16.5,48.25\n",
                "p: line 3: field `lon`: `east` is not a number",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,16.4,\nC,16.5,48.25\n",
                "p: line 3: field `lat`: missing",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,196.4,48.3\nC,16.5,48.25\n",
                "p: line 3: field `lon`: 196.4 is outside −180 to 180",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,16.4,-91\nC,16.5,48.25\n",
                "p: line 3: field `lat`: -91 is outside −90 to 90",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,16.4,NaN\nC,16.5,48.25\n",
                "p: line 3: field `lat`: `NaN` is not a number",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,16.4,48.3\nA,16.5,48.25\n",
                "p: line 4: field `id`: duplicate pad id `A` (first on line 2)",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,16.4,48.3\nC,16.30,48.20\n",
                "p: line 4: field `lon`: pad `C` is at the position of pad `A` (on line 2): two pads cannot share a position",
            ),
            (
                "id,lon,lat\nA,16.3,48.2\nB,16.4,48.3\n",
                "p: 2 pads: an airspace needs at least 3",
            ),
            ("id,lon,lat\n", "p: 0 pads: an airspace needs at least 3"),
            (
                "id,lon,lat\nA,16.3,48.2,extra\n",
                "p: line 2: malformed CSV record: CSV error: record 1 (line: 2, byte: 11): found record with 4 fields, but the previous record has 3 fields",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(err(text), want, "{text}");
        }
    }
}
