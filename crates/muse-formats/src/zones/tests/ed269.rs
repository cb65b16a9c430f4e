//! ED-269 zone files.

use super::*;

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
