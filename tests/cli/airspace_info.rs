//! `muse airspace info` on zones with vertical limits: each zone's heights as read from
//! ED-318 and ED-269 files, and what it closes (the same as without limits: MUSE flies one
//! cruise altitude until layers exist).

use std::path::Path;

use crate::run::{muse, said, stdout};
use crate::support::scratch_dir;

/// Three stations on a line, A–B–C, one kilometre apart.
const LINE: &str = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8089, 1.3]}, "properties": {"id": "B", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8178, 1.3]}, "properties": {"id": "C", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.8089, 1.3]]}, "properties": {"from": "A", "to": "B", "length_m": 1000}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8089, 1.3], [103.8178, 1.3]]}, "properties": {"from": "B", "to": "C", "length_m": 1000}}]}"#;

/// ED-318: a zone around A from the ground to 60 m; a "wedding cake" around B (60–120 m) and
/// C (up to 400 ft AMSL); a zone around C with no limits.
const ED318: &str = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"identifier": "LOW", "name": "Low", "type": "PROHIBITED"},
   "geometry": {"type": "Polygon", "coordinates": [[[103.799, 1.299], [103.801, 1.299], [103.801, 1.301], [103.799, 1.301], [103.799, 1.299]]],
     "layer": {"upper": 60, "upperReference": "AGL", "lower": 0, "lowerReference": "AGL", "uom": "m"}}},
  {"type": "Feature", "properties": {"identifier": "CAKE", "name": "Cake", "type": "PROHIBITED"},
   "geometry": {"type": "GeometryCollection", "geometries": [
     {"type": "Point", "coordinates": [103.8089, 1.3], "extent": {"subType": "Circle", "radius": 50},
      "layer": {"upper": 120, "upperReference": "AGL", "lower": 60, "lowerReference": "AGL", "uom": "m"}},
     {"type": "Point", "coordinates": [103.8178, 1.3], "extent": {"subType": "Circle", "radius": 50},
      "layer": {"upper": 400, "upperReference": "AMSL", "uom": "ft"}}]}},
  {"type": "Feature", "properties": {"identifier": "ALL", "name": "All", "type": "PROHIBITED"},
   "geometry": {"type": "Point", "coordinates": [103.8178, 1.3], "extent": {"subType": "Circle", "radius": 50}}}]}"#;

/// ED-269: a heliport around B from the ground to 400 ft.
const ED269: &str = r#"{"UASZoneList": [
  {"identifier": "HELI", "name": "Heliport", "restriction": "REQ_AUTHORISATION",
   "applicability": [{"permanent": "YES"}],
   "geometry": [{"uomDimensions": "FT", "lowerLimit": 0, "lowerVerticalReference": "AGL",
     "upperLimit": 400, "upperVerticalReference": "AGL",
     "horizontalProjection": {"type": "Circle", "center": [103.8089, 1.3], "radius": 164}}]}]}"#;

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// What `muse airspace info` says of the zones: its lines from the first zone on.
fn zone_lines(args: &[&str]) -> String {
    let all: Vec<&str> = ["airspace", "info"]
        .into_iter()
        .chain(args.iter().copied())
        .collect();
    let o = muse(&all);
    assert!(o.status.success(), "{}", said(&o));
    let out = stdout(&o);
    let at = out.find("\nzone ").expect("a zone is listed") + 1;
    out[at..].to_owned()
}

#[test]
fn airspace_info_shows_each_zones_heights() {
    let dir = scratch_dir("airspace_info_heights");
    std::fs::create_dir_all(&dir).unwrap();
    let air = write(&dir, "line.geojson", LINE);
    let ed318 = write(&dir, "zones.geojson", ED318);
    let ed269 = write(&dir, "heli.json", ED269);
    let got = zone_lines(&["--airspace", &air, "--zones", &ed318, "--zones", &ed269]);
    let want = "\
zone          LOW — Low (permanent)
  heights     0–60 m AGL
  closes      1 nodes: A
  closes      1 edges: A-B
zone          CAKE#1 — Cake (permanent)
  heights     60–120 m AGL
  closes      1 nodes: B
  closes      2 edges: A-B, B-C
zone          CAKE#2 — Cake (permanent)
  heights     up to 121.92 m AMSL
  closes      1 nodes: C
  closes      1 edges: B-C
zone          ALL — All (permanent)
  heights     whole sky
  closes      1 nodes: C
  closes      1 edges: B-C
zone          HELI — Heliport (permanent)
  heights     0–121.92 m AGL
  closes      1 nodes: B
  closes      2 edges: A-B, B-C
";
    assert_eq!(got, want);

    // What a zone closes does not depend on its heights (one cruise altitude): the same
    // file without its limits closes the same elements.
    let flat = write(
        &dir,
        "flat.geojson",
        &ED318.replace(r#""layer""#, r#""layer_ignored""#),
    );
    let without = zone_lines(&["--airspace", &air, "--zones", &flat]);
    let closes = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with("  closes"))
            .map(str::to_owned)
            .collect()
    };
    let mut with = closes(&got);
    with.truncate(with.len() - 2); // HELI's, from the other file.
    assert_eq!(closes(&without), with, "{without}");
}
