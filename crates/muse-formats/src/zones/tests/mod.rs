//! The zone readers and writer: what they read (here), what they refuse (`refused`,
//! `validation`), time (`time`), ED-269 (`ed269`), announced zones (`announced`) and vertical
//! limits (`vertical`).

use muse_model::{DailyWindow, Instant, LonLat, Millis, Period, UtcOffset, Weekday};
use serde_json::json;

use super::*;

const SQUARE: [[f64; 2]; 5] = [
    [103.84, 1.27],
    [103.86, 1.27],
    [103.86, 1.29],
    [103.84, 1.29],
    [103.84, 1.27],
];

fn daily_cbd() -> Value {
    json!([{"schedule": [{"day": ["ANY"], "startTime": "10:00:00+08:00", "endTime": "12:00:00+08:00"}]}])
}

/// A one-feature ED-318 collection whose properties and geometry are patched by `edit`.
fn ed318_with(edit: impl FnOnce(&mut Map<String, Value>, &mut Value)) -> String {
    let mut props = json!({"identifier": "Z1", "name": "Zone one", "type": "PROHIBITED",
                           "limitedApplicability": daily_cbd()});
    let mut geometry = json!({"type": "Polygon", "coordinates": [SQUARE]});
    edit(props.as_object_mut().unwrap(), &mut geometry);
    json!({"type": "FeatureCollection",
           "features": [{"type": "Feature", "properties": props, "geometry": geometry}]})
    .to_string()
}

fn err_of(text: &str) -> InputError {
    read_zones(text, "z.json").expect_err("the input is invalid")
}

/// Asserts the error points at feature 0 (`Z1`), the given field, and says `needle`.
fn assert_err(e: &InputError, field: &str, needle: &str) {
    assert_eq!(e.file, "z.json");
    assert!(
        matches!(&e.location, Location::Feature { index: 0, .. }),
        "{e}"
    );
    assert_eq!(e.field.as_deref(), Some(field), "{e}");
    assert!(
        e.message.contains(needle),
        "`{}` does not contain `{needle}`",
        e.message
    );
}

mod announced;
mod ed269;
mod refused;
mod time;
mod vertical;

#[test]
fn reads_the_cbd_zone() {
    let zones = read_zones(&ed318_with(|_, _| {}), "z.json").unwrap();
    assert_eq!(zones.len(), 1);
    let z = &zones[0];
    assert_eq!(
        (z.id.as_str(), z.name.as_str(), z.restriction.as_str()),
        ("Z1", "Zone one", "PROHIBITED")
    );
    let Some(ZoneArea::Polygons(mp)) = &z.area else {
        panic!("expected polygons")
    };
    assert_eq!(mp.0.len(), 1);
    assert_eq!(mp.0[0].exterior().0.len(), 5);
    assert_eq!(
        z.periods,
        vec![Period {
            start: None,
            end: None,
            daily: vec![DailyWindow {
                days: Weekday::ALL.to_vec(),
                start: Millis::from_secs(36_000),
                end: Millis::from_secs(43_200),
                offset: UtcOffset::SINGAPORE,
            }],
        }]
    );
}

#[test]
fn circles_in_every_accepted_place_and_unit() {
    let point = json!({"type": "Point", "coordinates": [103.85, 1.28]});
    let circle = |z: &Zone| match z.area {
        Some(ZoneArea::Circle { centre, radius_m }) => (centre, radius_m),
        _ => panic!("expected a circle"),
    };
    // On the geometry, with a unit.
    let text = ed318_with(|_, g| {
        *g = json!({"type": "Point", "coordinates": [103.85, 1.28],
                    "extent": {"subType": "Circle", "radius": 1000, "uom": "ft"}});
    });
    let (centre, r) = circle(&read_zones(&text, "z").unwrap()[0]);
    assert_eq!(centre, LonLat::new(103.85, 1.28));
    assert!((r - 304.8).abs() < 1e-9);
    // In the properties.
    let text = ed318_with(|p, g| {
        *g = point.clone();
        p.insert(
            "extent".into(),
            json!({"subType": "Circle", "radius": "250"}),
        );
    });
    assert_eq!(circle(&read_zones(&text, "z").unwrap()[0]).1, 250.0);
    // On the feature.
    let text = json!({"type": "FeatureCollection", "features": [{
        "type": "Feature", "properties": {"identifier": "C"}, "geometry": point,
        "extent": {"subType": "Circle", "radius": 1, "uomDimensions": "NM"}}]})
    .to_string();
    assert_eq!(circle(&read_zones(&text, "z").unwrap()[0]).1, 1_852.0);
}

#[test]
fn names_restrictions_and_ids() {
    let text = json!({"type": "FeatureCollection", "features": [{
        "type": "Feature", "id": "F7",
        "properties": {"name": [{"lang": "en-GB", "text": "Marina"}], "restriction": "REQ_AUTHORISATION", "type": "COMMON",
                       "nodes": ["S1"]},
        "geometry": null}]})
    .to_string();
    let z = &read_zones(&text, "z").unwrap()[0];
    assert_eq!(
        (z.id.as_str(), z.name.as_str(), z.restriction.as_str()),
        ("F7", "Marina", "REQ_AUTHORISATION")
    );
    assert!(z.is_permanent());
}

#[test]
fn collections_split_into_one_zone_per_area() {
    let text = ed318_with(|_, g| {
        *g = json!({"type": "GeometryCollection", "geometries": [
            {"type": "Polygon", "coordinates": [SQUARE]},
            {"type": "Point", "coordinates": [103.9, 1.3], "extent": {"subType": "Circle", "radius": 100}},
            {"type": "MultiPolygon", "coordinates": [[SQUARE]]}]});
    });
    let zones = read_zones(&text, "z").unwrap();
    assert_eq!(
        zones.iter().map(|z| z.id.as_str()).collect::<Vec<_>>(),
        ["Z1#1", "Z1#2"]
    );
    assert!(matches!(&zones[0].area, Some(ZoneArea::Polygons(mp)) if mp.0.len() == 2));
}

#[test]
fn write_is_deterministic_and_round_trips() {
    let zones = read_zones(&ed318_with(|_, _| {}), "z").unwrap();
    let a = write_ed318(&zones);
    assert_eq!(a, write_ed318(&zones));
    assert!(a.ends_with("}\n"));
    assert!(a.contains("\n  \"features\": [\n"), "2-space indent:\n{a}");
    assert!(a.contains("[103.84, 1.27]"), "{a}");
    assert_eq!(read_zones(&a, "z").unwrap(), zones);
}

mod validation;
