//! Zone files: the sample fixtures, the ED-318 writer's round trip, and no panics on any input.

use std::path::PathBuf;

use geo_types::{Coord, LineString, MultiPolygon, Polygon};
use muse_formats::Location;
use muse_formats::zones::{normalize, read_zones, read_zones_file, write_ed318};
use muse_model::{
    DailyWindow, Instant, LonLat, Metres, Millis, Period, UtcOffset, VerticalLimit, VerticalLimits,
    VerticalReference, Weekday, Zone, ZoneArea,
};
use proptest::prelude::*;
use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("testdata/zones")
        .join(name)
}

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap()
}

#[test]
fn reads_the_ed318_sample() {
    let zones = read_zones_file(&fixture("ed318_sample.geojson")).unwrap();
    let ids: Vec<&str> = zones.iter().map(|z| z.id.as_str()).collect();
    assert_eq!(ids, ["SGCBD", "SGHELI", "SGEVT", "PAPER-NFZ"]);

    let cbd = &zones[0];
    assert_eq!(cbd.name, "Downtown Core (simplified)");
    assert_eq!(cbd.restriction, "PROHIBITED");
    assert!(
        matches!(&cbd.area, Some(ZoneArea::Polygons(mp)) if mp.0.len() == 1 && mp.0[0].exterior().0.len() == 9)
    );
    assert_eq!(cbd.vertical.to_string(), "0–120 m AGL");
    let daily = &cbd.periods[0].daily[0];
    assert_eq!(daily.days, Weekday::ALL);
    assert_eq!(
        (daily.start, daily.end, daily.offset),
        (Millis(36_000_000), Millis(43_200_000), UtcOffset::SINGAPORE)
    );

    assert!(zones[1].is_permanent());
    assert_eq!(zones[1].restriction, "REQ_AUTHORIZATION");
    assert_eq!(
        zones[1].area,
        Some(ZoneArea::Circle {
            centre: LonLat::new(103.87, 1.3),
            radius_m: 500.0
        })
    );
    // 400 ft AMSL, exactly.
    assert_eq!(
        zones[1].vertical.upper,
        Some(VerticalLimit {
            height: Metres::from_um(121_920_000),
            reference: VerticalReference::Amsl
        })
    );

    let evt = &zones[2];
    assert!(evt.vertical.is_whole_sky());
    assert_eq!(evt.periods.len(), 2);
    assert_eq!(evt.periods[0].daily[0].days, [Weekday::Sat, Weekday::Sun]);
    assert_eq!(
        evt.periods[1].start,
        Some(Instant::parse_rfc3339("2026-02-01T17:00:00+08:00").unwrap())
    );
    let Some(ZoneArea::Polygons(mp)) = &evt.area else {
        panic!("expected polygons")
    };
    assert_eq!((mp.0.len(), mp.0[1].interiors().len()), (2, 1));

    let paper = &zones[3];
    assert_eq!(
        (
            paper.area.as_ref(),
            paper.node_ids.len(),
            paper.edge_ids.len()
        ),
        (None, 2, 1)
    );
}

#[test]
fn reads_the_ed269_sample() {
    let zones = read_zones_file(&fixture("ed269_sample.json")).unwrap();
    assert_eq!(zones.len(), 2);
    assert!(zones[0].is_permanent());
    let Some(ZoneArea::Circle { radius_m, .. }) = zones[0].area else {
        panic!("expected a circle")
    };
    assert!(
        (radius_m - 500.0).abs() < 0.001,
        "1640.42 ft is 500 m, got {radius_m}"
    );
    assert_eq!(zones[0].vertical.to_string(), "0 m AGL – 121.92 m AMSL");
    assert_eq!(zones[1].vertical.to_string(), "up to 120 m AGL");
    let p = &zones[1].periods[0];
    assert_eq!(
        p.daily[0].days,
        [
            Weekday::Mon,
            Weekday::Tue,
            Weekday::Wed,
            Weekday::Thu,
            Weekday::Fri
        ]
    );
    assert_eq!(
        p.end,
        Some(Instant::parse_rfc3339("2026-12-31T23:59:59Z").unwrap())
    );
}

#[test]
fn missing_file_names_the_path() {
    let e = read_zones_file(&fixture("no_such_file.json")).unwrap_err();
    assert!(e.file.ends_with("no_such_file.json"));
    assert_eq!(e.location, Location::Whole);
}

#[test]
fn fixtures_round_trip_and_output_is_stable() {
    for name in [
        "ed318_sample.geojson",
        "ed269_sample.json",
        "ed318_announced.geojson",
        "ed269_announced.json",
    ] {
        let zones = read_zones(&fixture_text(name), name).unwrap();
        let text = write_ed318(&zones);
        assert_eq!(read_zones(&text, "out").unwrap(), zones, "{name}");
        let again = write_ed318(&read_zones(&text, "out").unwrap());
        assert_eq!(
            again, text,
            "{name}: writing what was read back changes nothing"
        );
    }
}

#[test]
fn reads_announced_zones_in_both_formats() {
    let at = |t: &str| Some(Instant::parse_rfc3339(t).unwrap());
    let zones = read_zones_file(&fixture("ed318_announced.geojson")).unwrap();
    let announced: Vec<(&str, Option<Instant>)> =
        zones.iter().map(|z| (z.id.as_str(), z.announced)).collect();
    assert_eq!(
        announced,
        [
            ("SGFIRE", at("2026-01-05T09:40:00+08:00")),
            ("SGVIP", at("2026-01-05T10:00:00.250+08:00")),
            ("SGKNOWN", None),
        ]
    );
    assert_eq!(zones[1].edge_ids, ["S001-S002"]);
    let zones = read_zones_file(&fixture("ed269_announced.json")).unwrap();
    assert_eq!(zones.len(), 1);
    assert_eq!(zones[0].id, "E001");
    assert_eq!(zones[0].announced, at("2026-01-05T06:05:00Z"));
    assert_eq!(zones[0].periods[0].start, at("2026-01-05T14:15:00+08:00"));
}

#[test]
fn announced_is_written_and_read_back() {
    let zones = read_zones_file(&fixture("ed318_announced.geojson")).unwrap();
    let text = write_ed318(&zones);
    // In the offset of the zone's first daily window, else UTC; an unannounced zone has none.
    assert!(
        text.contains("\"announced\": \"2026-01-05T01:40:00.000+00:00\""),
        "{text}"
    );
    assert!(
        text.contains("\"announced\": \"2026-01-05T10:00:00.250+08:00\""),
        "{text}"
    );
    assert_eq!(text.matches("\"announced\"").count(), 2, "{text}");
    let back = read_zones(&text, "out.geojson").unwrap();
    assert_eq!(back, zones);
    assert_eq!(write_ed318(&back), text);
    // ED-269 in, ED-318 out: the announcement survives the change of format.
    let ed269 = read_zones_file(&fixture("ed269_announced.json")).unwrap();
    let text = write_ed318(&ed269);
    assert_eq!(read_zones(&text, "out.geojson").unwrap(), ed269);

    let mut cbd = cbd_zone();
    cbd.announced = Some(Instant::parse_rfc3339("2026-01-05T09:15:30.125+08:00").unwrap());
    let text = write_ed318(std::slice::from_ref(&cbd));
    assert!(
        text.contains("\"announced\": \"2026-01-05T09:15:30.125+08:00\""),
        "{text}"
    );
    let back = read_zones(&text, "cbd.geojson").unwrap();
    assert_eq!(back[0].announced, cbd.announced);
    assert_eq!(back, vec![normalize(&cbd)]);
}

/// The Singapore CBD zone as the scenario builder makes it: a polygon with full-precision
/// coordinates, every day 10:00–12:00 +08:00.
fn cbd_zone() -> Zone {
    let ring: Vec<Coord<f64>> = [
        (103.843_216_712_345_6, 1.285_120_298_765_4),
        (103.848_021_123_456_7, 1.278_011_456_789_1),
        (103.864_937_7, 1.274_159_8),
        (103.866_452_011_11, 1.283_885_4),
        (103.854_087_6, 1.301_126_7),
        (103.843_216_712_345_6, 1.285_120_298_765_4),
    ]
    .into_iter()
    .map(|(x, y)| Coord { x, y })
    .collect();
    Zone {
        id: "CBD".into(),
        name: "Downtown Core".into(),
        restriction: "PROHIBITED".into(),
        area: Some(ZoneArea::Polygons(MultiPolygon(vec![Polygon::new(
            LineString(ring),
            vec![],
        )]))),
        node_ids: vec![],
        edge_ids: vec![],
        announced: None,
        withdrawn: None,
        vertical: VerticalLimits::WHOLE_SKY,
        periods: vec![Period {
            start: None,
            end: None,
            daily: vec![DailyWindow {
                days: Weekday::ALL.to_vec(),
                start: Millis::from_secs(10 * 3_600),
                end: Millis::from_secs(12 * 3_600),
                offset: UtcOffset::SINGAPORE,
            }],
        }],
    }
}

#[test]
fn cbd_round_trips() {
    let cbd = cbd_zone();
    let text = write_ed318(std::slice::from_ref(&cbd));
    assert!(text.contains("\"day\": [\"ANY\"]"), "{text}");
    assert!(text.contains("\"startTime\": \"10:00:00+08:00\""), "{text}");
    assert!(text.contains("\"endTime\": \"12:00:00+08:00\""), "{text}");
    assert!(
        text.contains("[103.8432167, 1.2851203]"),
        "rounded to 7 decimals: {text}"
    );
    let back = read_zones(&text, "cbd.geojson").unwrap();
    assert_eq!(back, vec![normalize(&cbd)]);
    // Everything but the coordinates is exact; the coordinates move by less than 1 cm.
    let (Some(ZoneArea::Polygons(a)), Some(ZoneArea::Polygons(b))) = (&cbd.area, &back[0].area)
    else {
        panic!("expected polygons")
    };
    for (p, q) in a.0[0].exterior().0.iter().zip(&b.0[0].exterior().0) {
        let d = LonLat::new(p.x, p.y).geodesic_distance_m(LonLat::new(q.x, q.y));
        assert!(d < 0.01, "moved {d} m");
    }
    assert_eq!(back[0].periods, cbd.periods);
    assert_eq!(write_ed318(&back), text);
}

/// An ED-318 feature around (103.8, 1.3) whose `properties` hold `props` (JSON members) and
/// whose geometry holds `geometry_extra`.
fn ed318_with(props: &str, geometry_extra: &str) -> String {
    format!(
        r#"{{"type": "FeatureCollection", "features": [{{"type": "Feature",
  "properties": {{"identifier": "Z", "type": "PROHIBITED"{props}}},
  "geometry": {{"type": "Polygon", "coordinates": [[[103.79, 1.29], [103.81, 1.29],
    [103.81, 1.31], [103.79, 1.31], [103.79, 1.29]]]{geometry_extra}}}}}]}}"#
    )
}

#[test]
fn ed318_properties_limits_read_as_ed269_reads_them() {
    // ED-269's names in an ED-318 feature's properties: the band ED-269 gives a volume with
    // the same members, whatever the unit, or metres without one.
    let ed269 = |members: &str| {
        let text = format!(
            r#"{{"UASZoneList": [{{"identifier": "Z", "geometry": [{{{members},
  "horizontalProjection": {{"type": "Circle", "center": [103.8, 1.3], "radius": 100}}}}]}}]}}"#
        );
        read_zones(&text, "ed269.json").unwrap()[0].vertical
    };
    for members in [
        r#""uomDimensions": "FT", "lowerLimit": 100, "lowerVerticalReference": "AMSL", "upperLimit": 400, "upperVerticalReference": "AGL""#,
        r#""lowerLimit": 30, "upperLimit": "120""#,
        r#""upperLimit": 60"#,
        r#""uomDimensions": "m", "lowerLimit": 45.5"#,
    ] {
        let text = ed318_with(&format!(", {members}"), "");
        let zones = read_zones(&text, "z.geojson").unwrap();
        assert_eq!(zones.len(), 1);
        assert!(!zones[0].vertical.is_whole_sky(), "{members}");
        assert_eq!(zones[0].vertical, ed269(members), "{members}");
    }
    let text = ed318_with(r#", "uomDimensions": "FT", "upperLimit": 400"#, "");
    assert_eq!(
        read_zones(&text, "z.geojson").unwrap()[0]
            .vertical
            .to_string(),
        "up to 121.92 m AGL"
    );
    // The same limits on the geometry's `layer` too: one band, said twice, accepted.
    let text = ed318_with(
        r#", "lowerLimit": 30, "upperLimit": 120"#,
        r#", "layer": {"lower": 30, "upper": 120, "uom": "m"}"#,
    );
    assert_eq!(
        read_zones(&text, "z.geojson").unwrap()[0]
            .vertical
            .to_string(),
        "30–120 m AGL"
    );
    // A zone with explicit nodes only takes them as its band (as `properties.layer`).
    let text = r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": null,
      "properties": {"identifier": "N", "nodes": ["S001"], "upperLimit": 90}}]}"#;
    assert_eq!(
        read_zones(text, "n.geojson").unwrap()[0]
            .vertical
            .to_string(),
        "up to 90 m AGL"
    );
    // Written back, the band is the geometry's `layer`, read back the same.
    let zones = read_zones(&ed318_with(r#", "lowerLimit": 30"#, ""), "z.geojson").unwrap();
    assert_eq!(
        read_zones(&write_ed318(&zones), "w.geojson").unwrap(),
        zones
    );
}

#[test]
fn ed318_properties_limits_that_contradict_or_are_bad_are_refused() {
    let refused = |text: &str| read_zones(text, "z.geojson").unwrap_err();
    let feature = Location::Feature {
        index: 0,
        id: Some("Z".into()),
    };
    // A bad height, unit or reference: the ED-269 reader's own message, on the property.
    let e = refused(&ed318_with(r#", "upperLimit": -5"#, ""));
    assert_eq!(
        (&e.location, e.field.as_deref()),
        (&feature, Some("upperLimit"))
    );
    assert!(e.message.contains("must be ≥ 0"), "{e}");
    let e = refused(&ed318_with(
        r#", "uomDimensions": "FL", "upperLimit": 5"#,
        "",
    ));
    assert_eq!(e.field.as_deref(), Some("uomDimensions"), "{e}");
    let e = refused(&ed318_with(r#", "lowerLimit": 90, "upperLimit": 60"#, ""));
    assert_eq!(e.field.as_deref(), Some("lowerLimit"), "{e}");
    let e = refused(&ed318_with(
        r#", "upperLimit": 60, "upperVerticalReference": "STD""#,
        "",
    ));
    assert_eq!(e.field.as_deref(), Some("upperVerticalReference"), "{e}");
    // The geometry's `layer` and the properties' limits disagree: which is meant?
    let e = refused(&ed318_with(
        r#", "upperLimit": 120"#,
        r#", "layer": {"upper": 60, "uom": "m"}"#,
    ));
    assert_eq!(
        (&e.location, e.field.as_deref()),
        (&feature, Some("geometry.layer"))
    );
    assert!(
        e.message.contains("up to 60 m AGL") && e.message.contains("up to 120 m AGL"),
        "{e}"
    );
    // So do `properties.layer` and the limits of a zone without geometry.
    let text = r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": null,
      "properties": {"identifier": "N", "nodes": ["S001"], "upperLimit": 90,
        "layer": {"upper": 80, "uom": "m"}}}]}"#;
    let e = refused(text);
    assert_eq!(e.field.as_deref(), Some("layer"), "{e}");
    // A member of a collection with a band of its own, other than the properties' one.
    let text = r#"{"type": "FeatureCollection", "features": [{"type": "Feature",
      "properties": {"identifier": "Z", "lowerLimit": 0, "upperLimit": 60},
      "geometry": {"type": "GeometryCollection", "geometries": [
        {"type": "Point", "coordinates": [103.8, 1.3], "extent": {"subType": "Circle", "radius": 50}},
        {"type": "Point", "coordinates": [103.9, 1.3], "extent": {"subType": "Circle", "radius": 50},
         "layer": {"lower": 60, "upper": 120, "uom": "m"}}]}}]}"#;
    let e = refused(text);
    assert_eq!(
        e.field.as_deref(),
        Some("geometry.geometries[1].layer"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// Property tests.
// ---------------------------------------------------------------------------------------------

fn arb_coord() -> impl Strategy<Value = Coord<f64>> {
    (-180.0..=180.0_f64, -90.0..=90.0_f64).prop_map(|(x, y)| Coord { x, y })
}

fn arb_polygon() -> impl Strategy<Value = Polygon<f64>> {
    (
        prop::collection::vec(arb_coord(), 3..8),
        prop::option::of(prop::collection::vec(arb_coord(), 3..5)),
    )
        .prop_map(|(ext, hole)| {
            Polygon::new(LineString(ext), hole.map(LineString).into_iter().collect())
        })
}

fn arb_area() -> impl Strategy<Value = ZoneArea> {
    prop_oneof![
        prop::collection::vec(arb_polygon(), 1..3)
            .prop_map(|p| ZoneArea::Polygons(MultiPolygon(p))),
        (arb_coord(), 1e-3..1e6_f64).prop_map(|(c, r)| ZoneArea::Circle {
            centre: LonLat::new(c.x, c.y),
            radius_m: r
        }),
    ]
}

fn arb_daily() -> impl Strategy<Value = DailyWindow> {
    (
        prop::sample::subsequence(Weekday::ALL.to_vec(), 1..=7),
        0..86_400_000_i64,
        0..=86_400_000_i64,
        -18 * 60..=18 * 60_i32,
    )
        // A window may end the next day (written with `overnight`), not when it starts.
        .prop_filter("ends when it starts", |(_, start, end, _)| start != end)
        .prop_map(|(days, start, end, minutes)| DailyWindow {
            days,
            start: Millis(start),
            end: Millis(end),
            offset: UtcOffset(minutes * 60),
        })
}

fn arb_period() -> impl Strategy<Value = Period> {
    // 2000-01-01 .. 2100-01-01.
    let t = 946_684_800_000..4_102_444_800_000_i64;
    (
        prop::option::of(t.clone()),
        prop::option::of(1..10_000_000_000_i64),
        prop::collection::vec(arb_daily(), 0..3),
    )
        .prop_map(|(start, len, daily)| Period {
            start: start.map(Instant),
            end: len.map(|l| Instant(start.unwrap_or(946_684_800_000) + l)),
            daily,
        })
}

fn arb_limit() -> impl Strategy<Value = VerticalLimit> {
    (
        0..10_000_000_000_i64,
        prop::sample::select(vec![
            VerticalReference::Agl,
            VerticalReference::Amsl,
            VerticalReference::Wgs84,
        ]),
    )
        .prop_map(|(um, reference)| VerticalLimit {
            height: Metres::from_um(um),
            reference,
        })
}

fn arb_band() -> impl Strategy<Value = VerticalLimits> {
    (prop::option::of(arb_limit()), prop::option::of(arb_limit())).prop_map(|(a, b)| {
        // The lower limit may not be above the upper one.
        let (lower, upper) = match (a, b) {
            (Some(a), Some(b)) if a.height > b.height => (Some(b), Some(a)),
            other => other,
        };
        VerticalLimits { lower, upper }
    })
}

fn arb_zone() -> impl Strategy<Value = Zone> {
    (
        "[A-Za-z0-9_ -]{1,8}",
        "\\PC{0,12}",
        prop::sample::select(vec![
            "PROHIBITED",
            "REQ_AUTHORIZATION",
            "CONDITIONAL",
            "NO_RESTRICTION",
            "USPACE",
        ]),
        prop::option::of(arb_area()),
        prop::collection::vec("[A-Z0-9-]{1,6}", 0..3),
        prop::collection::vec("[A-Z0-9-]{1,9}", 0..3),
        prop::collection::vec(arb_period(), 0..3),
        prop::option::of(946_684_800_000..4_102_444_800_000_i64),
        arb_band(),
    )
        .prop_map(
            |(
                id,
                name,
                restriction,
                area,
                mut node_ids,
                edge_ids,
                periods,
                announced,
                vertical,
            )| {
                if area.is_none() && edge_ids.is_empty() && node_ids.is_empty() {
                    node_ids.push("S001".into());
                }
                Zone {
                    id,
                    name,
                    restriction: restriction.into(),
                    area,
                    node_ids,
                    edge_ids,
                    announced: announced.map(Instant),
                    withdrawn: None,
                    vertical,
                    periods,
                }
            },
        )
}

/// A node of a JSON document, in pre-order, replaced by `with`.
fn replace_nth(v: &mut Value, n: &mut usize, with: &Value) -> bool {
    if *n == 0 {
        *v = with.clone();
        return true;
    }
    *n -= 1;
    match v {
        Value::Array(items) => items.iter_mut().any(|c| replace_nth(c, n, with)),
        Value::Object(map) => map.values_mut().any(|c| replace_nth(c, n, with)),
        _ => false,
    }
}

fn count_nodes(v: &Value) -> usize {
    1 + match v {
        Value::Array(items) => items.iter().map(count_nodes).sum(),
        Value::Object(map) => map.values().map(count_nodes).sum(),
        _ => 0,
    }
}

fn arb_json() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(Value::from),
        prop::num::f64::NORMAL.prop_map(Value::from),
        prop::sample::select(vec![-1.0, 0.0, 91.0, 181.0, 1e308, 24.0]).prop_map(Value::from),
        prop::sample::select(vec![
            "Polygon",
            "MultiPolygon",
            "Point",
            "Circle",
            "GeometryCollection",
            "Feature",
            "FeatureCollection",
            "ANY",
            "MON",
            "YES",
            "NO",
            "FT",
            "24:00+08:00",
            "10:00",
            "10:00:00Z",
            "2026-01-05T10:00:00+08:00",
            "yesterday",
            "",
            "S001",
        ])
        .prop_map(Value::from),
        "[ -~]{0,10}".prop_map(Value::from),
    ];
    leaf.prop_recursive(3, 24, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(Value::Array),
            prop::collection::vec(
                (
                    prop::sample::select(vec![
                        "type",
                        "coordinates",
                        "extent",
                        "radius",
                        "subType",
                        "uom",
                        "properties",
                        "identifier",
                        "geometry",
                        "limitedApplicability",
                        "applicability",
                        "schedule",
                        "day",
                        "startTime",
                        "endTime",
                        "startDateTime",
                        "endDateTime",
                        "nodes",
                        "edges",
                        "horizontalProjection",
                        "center",
                        "uomDimensions",
                        "geometries",
                        "permanent",
                        "name",
                        "layer",
                        "upper",
                        "lowerLimit",
                        "upperVerticalReference",
                    ]),
                    inner,
                ),
                0..4,
            )
            .prop_map(|kv| Value::Object(kv.into_iter().map(|(k, v)| (k.to_owned(), v)).collect())),
        ]
    })
}

proptest! {

    #[test]
    fn written_zones_read_back_normalized(zones in prop::collection::vec(arb_zone(), 0..4)) {
        // Identifiers must be unique within a file.
        let zones: Vec<Zone> = zones
            .into_iter()
            .enumerate()
            .map(|(i, mut z)| { z.id = format!("{}{i}", z.id); z })
            .collect();
        let text = write_ed318(&zones);
        let back = read_zones(&text, "gen").map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        let expected: Vec<Zone> = zones.iter().map(normalize).collect();
        prop_assert_eq!(&back, &expected);
        prop_assert_eq!(write_ed318(&back), text);
    }

    #[test]
    fn mutated_files_never_panic(
        which in 0..2usize,
        edits in prop::collection::vec((any::<usize>(), arb_json()), 1..4),
    ) {
        let name = ["ed318_sample.geojson", "ed269_sample.json"][which];
        let mut doc: Value = serde_json::from_str(&fixture_text(name)).unwrap();
        for (at, with) in edits {
            let mut n = at % count_nodes(&doc);
            replace_nth(&mut doc, &mut n, &with);
        }
        let _ = read_zones(&doc.to_string(), name);
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}", cut in any::<usize>()) {
        let _ = read_zones(&text, "any");
        let sample = fixture_text("ed318_sample.geojson");
        let mut end = cut % (sample.len() + 1);
        while !sample.is_char_boundary(end) { end -= 1; }
        let _ = read_zones(&sample[..end], "cut");
    }
}
