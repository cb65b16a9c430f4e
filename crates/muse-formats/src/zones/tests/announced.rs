//! Zones announced during the day: `announced` in ED-318 properties and ED-269 zones, read,
//! refused and written back.

use super::*;

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
