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
fn not_json_and_wrong_top_level() {
    for (text, needle) in [
        ("{\"type\": \"FeatureCollection\", ", "not valid JSON"),
        ("42", "expected an ED-318 FeatureCollection"),
        ("{\"type\": \"FeatureCollection\"}", "no `features` array"),
        ("{\"features\": {}}", "`features` must be an array"),
        ("{\"title\": \"x\"}", "`UASZoneList`"),
    ] {
        let e = err_of(text);
        assert_eq!(e.location, Location::Whole, "{e}");
        assert!(e.message.contains(needle), "{e}");
    }
    assert!(
        read_zones("{\"type\": \"FeatureCollection\", \"features\": []}", "z")
            .unwrap()
            .is_empty()
    );
}

#[test]
fn missing_geometry_and_elements() {
    let e = err_of(&ed318_with(|_, g| *g = Value::Null));
    assert_err(
        &e,
        "geometry",
        "needs a geometry or explicit `nodes` / `edges`",
    );
    assert_eq!(
        e.location,
        Location::Feature {
            index: 0,
            id: Some("Z1".into())
        }
    );
    let e = err_of(&ed318_with(|p, _| {
        p.remove("identifier");
    }));
    assert_err(&e, "identifier", "missing");
}

#[test]
fn explicit_elements_without_geometry() {
    let text = ed318_with(|p, g| {
        *g = Value::Null;
        p.insert("nodes".into(), json!(["S001", "S002"]));
        p.insert("edges".into(), json!(["S001-S003"]));
    });
    let z = &read_zones(&text, "z.json").unwrap()[0];
    assert_eq!(z.area, None);
    assert_eq!(z.node_ids, ["S001", "S002"]);
    assert_eq!(z.edge_ids, ["S001-S003"]);
    let e = err_of(&ed318_with(|p, _| {
        p.insert("nodes".into(), json!(["S001", 7]));
    }));
    assert_err(&e, "nodes[1]", "non-empty id string");
}

#[test]
fn missing_start_time() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["MON"], "startTime": "10:00Z", "endTime": "11:00Z"},
            {"day": ["MON"], "endTime": "12:00:00+08:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[1].startTime",
        "missing",
    );
}

#[test]
fn unparsable_date_time() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"startDateTime": "yesterday"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].startDateTime",
        "`yesterday` is not an RFC 3339 timestamp",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"startDateTime": "2026-01-05T10:00:00"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].startDateTime",
        "with an offset",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{
            "startDateTime": "2026-01-05T10:00:00Z", "endDateTime": "2026-01-05T18:00:00+08:00"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].endDateTime",
        "must be after startDateTime",
    );
}

#[test]
fn unclosed_and_short_rings() {
    let e = err_of(&ed318_with(|_, g| {
        g["coordinates"][0][4] = json!([103.85, 1.27]);
    }));
    assert_err(&e, "geometry.coordinates[0]", "not closed");
    let e = err_of(&ed318_with(|_, g| {
        g["coordinates"] = json!([[[103.84, 1.27], [103.86, 1.27], [103.84, 1.27]]]);
    }));
    assert_err(&e, "geometry.coordinates[0]", "at least 4 positions");
    let e = err_of(&ed318_with(|_, g| g["coordinates"] = json!([])));
    assert_err(&e, "geometry.coordinates", "at least one ring");
}

#[test]
fn bad_coordinates() {
    let e = err_of(&ed318_with(|_, g| {
        g["coordinates"][0][1] = json!(["103.86", 1.27]);
    }));
    assert_err(
        &e,
        "geometry.coordinates[0][1]",
        "coordinate \"103.86\" is not a number",
    );
    let e = err_of(&ed318_with(|_, g| {
        g["coordinates"][0][2] = json!([103.86, 91.0]);
    }));
    assert_err(
        &e,
        "geometry.coordinates[0][2]",
        "latitude 91 is out of range",
    );
    let e = err_of(&ed318_with(|_, g| {
        g["coordinates"][0][2] = json!([203.86, 1.0]);
    }));
    assert_err(
        &e,
        "geometry.coordinates[0][2]",
        "longitude 203.86 is out of range",
    );
    let e = err_of(&ed318_with(|_, g| g["coordinates"][0][2] = json!([103.86])));
    assert_err(
        &e,
        "geometry.coordinates[0][2]",
        "expected a position [longitude, latitude]",
    );
}

#[test]
fn unknown_day() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["MON", "FUNDAY"], "startTime": "10:00Z", "endTime": "11:00Z"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].day[1]",
        "unknown day \"FUNDAY\"",
    );
}

#[test]
fn schedule_without_offset() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startTime": "10:00:00", "endTime": "12:00:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].startTime",
        "`10:00:00` has no UTC offset",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startTime": "10:00:00Z", "endTime": "12:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].endTime",
        "no UTC offset",
    );
}

#[test]
fn bad_circle_radius() {
    for (radius, needle) in [
        (json!(-5), "must be > 0, got -5"),
        (json!(0), "must be > 0, got 0"),
        (json!("big"), "must be a number"),
    ] {
        let e = err_of(&ed318_with(|_, g| {
            *g = json!({"type": "Point", "coordinates": [103.85, 1.28],
                        "extent": {"subType": "Circle", "radius": radius}});
        }));
        assert_err(&e, "geometry.extent.radius", needle);
    }
    let e = err_of(&ed318_with(|_, g| {
        *g = json!({"type": "Point", "coordinates": [103.85, 1.28]});
    }));
    assert_err(&e, "geometry.extent", "needs an extent");
    let e = err_of(&ed318_with(|_, g| {
        *g = json!({"type": "Point", "coordinates": [103.85, 1.28], "extent": {"subType": "Ellipse", "radius": 5}});
    }));
    assert_err(&e, "geometry.extent.subType", "expected \"Circle\"");
    let e = err_of(&ed318_with(|_, g| {
        *g = json!({"type": "Point", "coordinates": [103.85, 1.28],
                    "extent": {"subType": "Circle", "radius": 5, "uom": "furlong"}});
    }));
    assert_err(&e, "geometry.extent.uom", "unknown unit");
}

#[test]
fn unknown_geometry_type() {
    let e = err_of(&ed318_with(|_, g| {
        *g = json!({"type": "LineString", "coordinates": [[0, 0], [1, 1]]});
    }));
    assert_err(
        &e,
        "geometry.type",
        "unsupported geometry type \"LineString\"",
    );
}

#[test]
fn duplicate_identifier() {
    let one = json!({"type": "Feature", "properties": {"identifier": "A", "nodes": ["S1"]}, "geometry": null});
    let text = json!({"type": "FeatureCollection", "features": [one.clone(), one]}).to_string();
    let e = err_of(&text);
    assert_eq!(
        e.location,
        Location::Feature {
            index: 1,
            id: Some("A".into())
        }
    );
    assert_eq!(e.field.as_deref(), Some("identifier"));
    assert!(
        e.message
            .contains("duplicate zone identifier `A` (first used by feature 0)"),
        "{e}"
    );
}

#[test]
fn daylight_events_are_refused() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startEvent": "SR", "endTime": "12:00Z"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].startEvent",
        "not supported",
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
fn permanence_and_periods() {
    let read = |la: Value| {
        read_zones(
            &ed318_with(|p, _| {
                p.insert("limitedApplicability".into(), la);
            }),
            "z",
        )
        .unwrap()
        .remove(0)
    };
    assert!(read(json!([])).is_permanent());
    assert!(read(Value::Null).is_permanent());
    assert!(read(json!([{"permanent": "YES"}])).is_permanent());
    assert!(read(json!([{"startDateTime": "2026-01-05T00:00:00Z"}, {}])).is_permanent());
    let z = read(
        json!({"startDateTime": "2026-01-05T10:00:00+08:00", "endDateTime": "2026-01-05T12:00:00.500Z"}),
    );
    assert_eq!(z.periods.len(), 1);
    assert_eq!(z.periods[0].start, Some(Instant(1_767_578_400_000)));
    assert_eq!(z.periods[0].end, Some(Instant(1_767_614_400_500)));
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"permanent": "MAYBE"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].permanent",
        "expected \"YES\" or \"NO\"",
    );
}

#[test]
fn clock_offsets_and_midnight() {
    let read = |sched: Value| {
        let mut z = read_zones(
            &ed318_with(|p, _| {
                p.insert(
                    "limitedApplicability".into(),
                    json!([{"schedule": [sched]}]),
                );
            }),
            "z",
        )
        .unwrap();
        z.remove(0).periods.remove(0).daily.remove(0)
    };
    let d = read(json!({"day": "sat", "startTime": "22:00Z", "endTime": "24:00Z"}));
    assert_eq!(
        (d.days, d.start, d.end, d.offset),
        (
            vec![Weekday::Sat],
            Millis(79_200_000),
            Millis(86_400_000),
            UtcOffset(0)
        )
    );
    // End stated in another offset: converted to the start's (14:00Z = 22:00+08:00).
    let d = read(
        json!({"day": ["SUN", "MON", "MON"], "startTime": "20:00:00+08:00", "endTime": "14:00:00Z"}),
    );
    assert_eq!(
        (d.days, d.start, d.end),
        (
            vec![Weekday::Mon, Weekday::Sun],
            Millis(72_000_000),
            Millis(79_200_000)
        )
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startTime": "25:00+08:00", "endTime": "12:00+08:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].startTime",
        "not a local clock time",
    );
}

#[test]
fn leap_seconds_are_refused_in_schedules_and_date_times() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startTime": "10:00:00+08:00", "endTime": "23:59:60+08:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].endTime",
        "`23:59:60` is a leap second (second 60): leap seconds are not accepted",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"startDateTime": "2026-06-30T23:59:60Z"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].startDateTime",
        "leap seconds are not accepted",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert("announced".into(), json!("2026-06-30T23:59:60+00:00"));
    }));
    assert_err(&e, "announced", "leap seconds are not accepted");
}

#[test]
fn date_times_of_year_9999_are_read_exactly() {
    let text = ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"startDateTime": "2026-01-05T10:00:00+08:00", "endDateTime": "9999-12-31T23:59:59+08:00"}]),
        );
    });
    let zones = read_zones(&text, "z.json").unwrap();
    assert_eq!(
        zones[0].periods[0].end,
        Some(Instant::parse_rfc3339("9999-12-31T15:59:59Z").unwrap())
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"endDateTime": "+999999999-01-01T00:00:00Z"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].endDateTime",
        "`+999999999-01-01T00:00:00Z` is out of the range MUSE represents",
    );
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
fn ed269_zones() {
    let text = json!({"title": "test", "UASZoneList": [
        {"identifier": "P1", "name": "Port", "type": "COMMON", "restriction": "REQ_AUTHORISATION",
         "applicability": [{"permanent": "YES"}],
         "geometry": [{"uomDimensions": "FT", "lowerLimit": null, "upperLimit": "400",
                       "lowerVerticalReference": "AGL", "upperVerticalReference": "AGL",
                       "horizontalProjection": {"type": "Circle", "center": [103.8, 1.26], "radius": 1000}}]},
        {"identifier": "P2", "restriction": "PROHIBITED",
         "applicability": [{"permanent": "NO", "startDateTime": "2026-01-05T00:00:00+08:00",
                            "dailyPeriod": [{"day": ["MON", "TUE"], "startTime": "08:00:00.00Z", "endTime": "09:00:00.00Z"}]}],
         "geometry": [{"uomDimensions": "M", "lowerLimit": 0, "upperLimit": 120,
                       "horizontalProjection": {"type": "Polygon", "coordinates": [SQUARE]}}]},
    ]})
    .to_string();
    let zones = read_zones(&text, "z").unwrap();
    assert_eq!(zones.len(), 2);
    assert!(zones[0].is_permanent());
    assert_eq!(zones[0].restriction, "REQ_AUTHORISATION");
    let Some(ZoneArea::Circle { centre, radius_m }) = zones[0].area else {
        panic!()
    };
    assert_eq!(centre, LonLat::new(103.8, 1.26));
    assert!((radius_m - 304.8).abs() < 1e-9);
    assert_eq!(
        zones[1].periods[0].daily[0].days,
        [Weekday::Mon, Weekday::Tue]
    );
    assert_eq!(zones[1].periods[0].daily[0].start, Millis(28_800_000));
    // `features` works too, and errors name ED-269 fields.
    let bad = json!({"features": [{"identifier": "P3", "restriction": "PROHIBITED", "applicability": [],
        "geometry": [{"horizontalProjection": {"type": "Circle", "center": [103.8, 1.26], "radius": -1}}]}]})
    .to_string();
    let e = err_of(&bad);
    assert_eq!(
        e.location,
        Location::Feature {
            index: 0,
            id: Some("P3".into())
        }
    );
    assert_eq!(
        e.field.as_deref(),
        Some("geometry[0].horizontalProjection.radius")
    );
    let bad = bad.replace("Circle", "Hexagon");
    assert!(
        err_of(&bad)
            .message
            .contains("unsupported horizontal projection type \"Hexagon\"")
    );
}

#[test]
fn ed269_several_circles_become_several_zones() {
    let circle = |lon: f64| json!({"horizontalProjection": {"type": "Circle", "center": [lon, 1.3], "radius": 50}});
    let text = json!({"features": [{"identifier": "C", "restriction": "PROHIBITED",
        "applicability": [], "nodes": ["S9"], "geometry": [circle(103.8), circle(103.9)]}]})
    .to_string();
    let zones = read_zones(&text, "z").unwrap();
    assert_eq!(
        zones.iter().map(|z| z.id.as_str()).collect::<Vec<_>>(),
        ["C#1", "C#2"]
    );
    assert_eq!(zones[0].node_ids, ["S9"]);
    assert!(zones[1].node_ids.is_empty());
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

#[test]
fn announced_in_ed318_properties_and_ed269_zones() {
    let at = |t: &str| Some(Instant::parse_rfc3339(t).unwrap());
    let text = ed318_with(|props, _| {
        props.insert("announced".into(), json!("2026-01-05T09:30:00+08:00"));
    });
    let zones = read_zones(&text, "z.json").unwrap();
    assert_eq!(zones[0].announced, at("2026-01-05T01:30:00Z"));
    // Absent or null: known from the start.
    assert_eq!(
        read_zones(&ed318_with(|_, _| {}), "z").unwrap()[0].announced,
        None
    );
    let null = ed318_with(|props, _| {
        props.insert("announced".into(), Value::Null);
    });
    assert_eq!(read_zones(&null, "z").unwrap()[0].announced, None);
    // On a circle split into several zones, every part is announced alike.
    let circle = |lon: f64| json!({"horizontalProjection": {"type": "Circle", "center": [lon, 1.3], "radius": 50}});
    let text = json!({"UASZoneList": [{"identifier": "E1", "restriction": "PROHIBITED",
        "announced": "2026-01-05T14:05:00.500+08:00",
        "geometry": [circle(103.8), circle(103.9)]}]})
    .to_string();
    let zones = read_zones(&text, "z").unwrap();
    assert_eq!(zones.len(), 2);
    assert!(
        zones
            .iter()
            .all(|z| z.announced == at("2026-01-05T06:05:00.500Z"))
    );
}

#[test]
fn bad_announced_is_an_error_naming_the_field() {
    for (value, needle) in [
        (
            json!("2026-01-05T09:30:00"),
            "`2026-01-05T09:30:00` is not an RFC 3339 timestamp with an offset",
        ),
        (json!("09:30:00+08:00"), "is not an RFC 3339 timestamp"),
        (json!("soon"), "`soon` is not an RFC 3339 timestamp"),
        (
            json!("2026-01-05T09:30:00.0001+08:00"),
            "sub-millisecond precision",
        ),
        (
            json!(1_767_576_600_000_i64),
            "expected an RFC 3339 date-time string, got 1767576600000",
        ),
        (json!(true), "expected an RFC 3339 date-time string"),
    ] {
        let text = ed318_with(|props, _| {
            props.insert("announced".into(), value.clone());
        });
        assert_err(&err_of(&text), "announced", needle);
        let ed269 = json!({"features": [{"identifier": "E1", "restriction": "PROHIBITED",
            "announced": value, "nodes": ["S001"]}]})
        .to_string();
        let e = err_of(&ed269);
        assert_err(&e, "announced", needle);
        assert_eq!(
            e.location,
            Location::Feature {
                index: 0,
                id: Some("E1".into())
            }
        );
    }
}

#[test]
fn announced_round_trips_through_the_writer() {
    let text = ed318_with(|props, _| {
        props.insert("announced".into(), json!("2026-01-05T01:30:00.125Z"));
    });
    let zones = read_zones(&text, "z").unwrap();
    let written = write_ed318(&zones);
    // Written in the offset of the first daily window (+08:00 here).
    assert!(
        written.contains("\"announced\": \"2026-01-05T09:30:00.125+08:00\""),
        "{written}"
    );
    let back = read_zones(&written, "w").unwrap();
    assert_eq!(back, zones);
    assert_eq!(write_ed318(&back), written);
    // Not announced: nothing written.
    let plain = write_ed318(&read_zones(&ed318_with(|_, _| {}), "z").unwrap());
    assert!(!plain.contains("announced"), "{plain}");
}

mod validation;
