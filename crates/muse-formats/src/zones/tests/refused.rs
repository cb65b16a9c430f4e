//! Zone files refused: each error names the feature, the field and what is wrong.

use super::*;

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
