//! `muse airspace info` on zones with vertical limits: each zone's heights as read from
//! ED-318 and ED-269 files, and what it closes: on the flat airspace the same as without
//! limits (one cruise altitude); with `--layers`, the layers of its band and the vertical
//! links across it (docs/reference.md#layered-airspace).

use std::path::Path;

use crate::run::{muse, said, stderr, stdout};
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

/// ED-318: around B from 65 m to 75 m (layer 2, 69.144 m, and the climbs on either side of
/// it); around C from 70 m to 75 m (between layers 2 and 3: the climb only); A listed by id
/// from 78 m up (layer 3, and the climb to it).
const BANDS: &str = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"identifier": "MID", "name": "Mid"},
   "geometry": {"type": "Point", "coordinates": [103.8089, 1.3], "extent": {"subType": "Circle", "radius": 50},
     "layer": {"lower": 65, "upper": 75, "uom": "m"}}},
  {"type": "Feature", "properties": {"identifier": "THIN", "name": "Thin"},
   "geometry": {"type": "Point", "coordinates": [103.8178, 1.3], "extent": {"subType": "Circle", "radius": 50},
     "layer": {"lower": 70, "upper": 75, "uom": "m"}}},
  {"type": "Feature", "properties": {"identifier": "TOP", "name": "Top", "nodes": ["A"],
     "layer": {"lower": 78, "uom": "m"}}, "geometry": null}]}"#;

#[test]
fn airspace_info_with_layers_shows_what_each_zone_closes_per_layer() {
    let dir = scratch_dir("airspace_info_layers");
    std::fs::create_dir_all(&dir).unwrap();
    let air = write(&dir, "line.geojson", LINE);
    let bands = write(&dir, "bands.geojson", BANDS);
    let ed318 = write(&dir, "zones.geojson", ED318);
    let o = muse(&[
        "airspace",
        "info",
        "--airspace",
        &air,
        "--zones",
        &bands,
        "--layers",
        "3",
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let out = stdout(&o);
    for line in [
        "layers        3 at 60, 69.144, 78.288 m (9.144 m apart); vertical links climbed in \
         1.829 s at 5 m/s\n",
        "heading rule  none (every direction at every layer)\n",
        "layered graph 9 nodes, 12 edges: 6 corridors (0 one-way; 0 copies absent), 6 vertical \
         links\n",
    ] {
        assert!(out.contains(line), "no {line:?} in\n{out}");
    }
    let at = out.find("\nzone ").expect("a zone is listed") + 1;
    let want = "\
zone          MID — Mid (permanent)
  heights     65–75 m AGL
  covers      1 nodes: B
  covers      2 edges: A-B, B-C
  closes      layer 1: none; layer 2: 1 nodes, 2 corridors; layer 3: none; vertical links: 2
zone          THIN — Thin (permanent)
  heights     70–75 m AGL
  covers      1 nodes: C
  covers      1 edges: B-C
  closes      layer 1: none; layer 2: none; layer 3: none; vertical links: 1
zone          TOP — Top (permanent)
  heights     from 78 m AGL up
  covers      1 nodes: A
  covers      0 edges: none
  closes      layer 1: none; layer 2: none; layer 3: 1 nodes, 0 corridors; vertical links: 1
";
    assert_eq!(&out[at..], want);

    // A zone without limits closes every layer; LOW (0–60 m) layer 1 and the climb from it.
    let got = zone_lines(&["--airspace", &air, "--zones", &ed318, "--layers", "3"]);
    assert!(
        got.contains(
            "zone          ALL — All (permanent)\n  heights     whole sky\n  covers      1 nodes: C\n  \
             covers      1 edges: B-C\n  closes      layer 1: 1 nodes, 1 corridors; layer 2: 1 \
             nodes, 1 corridors; layer 3: 1 nodes, 1 corridors; vertical links: 2\n"
        ),
        "{got}"
    );
    assert!(
        got.contains(
            "  heights     0–60 m AGL\n  covers      1 nodes: A\n  covers      1 edges: A-B\n  \
             closes      layer 1: 1 nodes, 1 corridors; layer 2: none; layer 3: none; vertical \
             links: 1\n"
        ),
        "{got}"
    );
}

#[test]
fn airspace_info_with_layers_follows_the_heading_rule_and_the_flat_ids() {
    let dir = scratch_dir("airspace_info_layers_rules");
    std::fs::create_dir_all(&dir).unwrap();
    let air = write(&dir, "line.geojson", LINE);
    let bands = write(&dir, "bands.geojson", BANDS);
    // Under quadrantal sectors the eastward line is flown at layer 1 only, westward at 3: a
    // zone closes the copies there are.
    let got = zone_lines(&[
        "--airspace",
        &air,
        "--zones",
        &bands,
        "--layers",
        "4",
        "--heading-rule",
        "sectors",
    ]);
    assert!(
        got.contains("  closes      layer 1: none; layer 2: 1 nodes, 0 corridors; layer 3: none; layer 4: none; vertical links: 2\n"),
        "{got}"
    );

    // With one layer nothing changes: the flat listing, heights aside.
    assert_eq!(
        zone_lines(&["--airspace", &air, "--zones", &bands, "--layers", "1"]),
        zone_lines(&["--airspace", &air, "--zones", &bands])
    );

    // A zone names the flat airspace's ids, not a copy's.
    let copy = write(
        &dir,
        "copy.geojson",
        &BANDS.replace(r#""nodes": ["A"]"#, r#""nodes": ["A@3"]"#),
    );
    let o = muse(&[
        "airspace",
        "info",
        "--airspace",
        &air,
        "--zones",
        &copy,
        "--layers",
        "3",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains("zone `TOP` closes node `A@3`, which is not in the airspace"),
        "{}",
        said(&o)
    );
}

/// ED-318 features whose properties give ED-269's `lowerLimit` / `upperLimit`: around A up to
/// 200 ft (60.96 m: layer 1 and the climb from it), around B from 65 to 75 m (layer 2 and the
/// climbs on either side), as `BANDS`' `MID`.
const PROPERTIES_LIMITS: &str = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"identifier": "LOWP", "name": "Low", "uomDimensions": "FT", "upperLimit": 200},
   "geometry": {"type": "Point", "coordinates": [103.8, 1.3], "extent": {"subType": "Circle", "radius": 50}}},
  {"type": "Feature", "properties": {"identifier": "MIDP", "name": "Mid", "lowerLimit": 65, "upperLimit": 75,
     "lowerVerticalReference": "AGL", "upperVerticalReference": "AGL"},
   "geometry": {"type": "Point", "coordinates": [103.8089, 1.3], "extent": {"subType": "Circle", "radius": 50}}}]}"#;

#[test]
fn airspace_info_with_layers_honours_limits_given_in_ed318_properties() {
    let dir = scratch_dir("airspace_info_properties_limits");
    std::fs::create_dir_all(&dir).unwrap();
    let air = write(&dir, "line.geojson", LINE);
    let zones = write(&dir, "props.geojson", PROPERTIES_LIMITS);
    let got = zone_lines(&["--airspace", &air, "--zones", &zones, "--layers", "3"]);
    let want = "\
zone          LOWP — Low (permanent)
  heights     up to 60.96 m AGL
  covers      1 nodes: A
  covers      1 edges: A-B
  closes      layer 1: 1 nodes, 1 corridors; layer 2: none; layer 3: none; vertical links: 1
zone          MIDP — Mid (permanent)
  heights     65–75 m AGL
  covers      1 nodes: B
  covers      2 edges: A-B, B-C
  closes      layer 1: none; layer 2: 1 nodes, 2 corridors; layer 3: none; vertical links: 2
";
    assert_eq!(got, want);

    // Said again, differently, on the geometry: refused, naming the feature and the field.
    let twice = write(
        &dir,
        "twice.geojson",
        &PROPERTIES_LIMITS.replace(
            r#""radius": 50}}},"#,
            r#""radius": 50}, "layer": {"upper": 120, "uom": "m"}}},"#,
        ),
    );
    let o = muse(&["airspace", "info", "--airspace", &air, "--zones", &twice]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains("twice.geojson: feature 0 (`LOWP`): field `geometry.layer`: the layer (up to 120 m AGL) contradicts"),
        "{}",
        said(&o)
    );
}

/// `muse airspace info --separation-m 30` lists the sharpest corners of the default airspace
/// and the gap each needs (docs/reference.md#metric-separation): `S011`, where two corridors
/// leave 6.58° apart, needs 62.7 s between a departure and an arrival at 30 km/h; a value out
/// of range is refused naming the option.
#[test]
fn info_lists_the_sharpest_corners_and_their_gaps() {
    let o = muse(&["airspace", "info", "--separation-m", "30"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("corners       1011 (two corridors at a node, in EPSG:3414)")
            && out.contains("  S011       S011-S018 / S011-S020    6.58°      62.7 s")
            && out.contains("a uniform tau of 62.7 s keeps 30 m at every corner"),
        "{out}"
    );
    let o = muse(&["airspace", "info", "--separation-m", "-5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--separation-m"), "{}", stderr(&o));
}
