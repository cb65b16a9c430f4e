//! Vertical limits (docs/reference.md#layered-airspace): ED-318's geometry `layer` and ED-269's
//! volume limits, read, refused, and written back.

use muse_model::{Metres, VerticalLimit, VerticalLimits, VerticalReference};

use super::*;

fn m(x: f64) -> Metres {
    Metres::from_m(x).unwrap()
}

fn limit(height: Metres, reference: VerticalReference) -> VerticalLimit {
    VerticalLimit { height, reference }
}

/// The zones of the ED-318 test zone whose geometry carries `layer`.
fn ed318_layer(layer: &Value) -> Result<Vec<Zone>, InputError> {
    let text = ed318_with(|_, g| {
        g.as_object_mut()
            .unwrap()
            .insert("layer".into(), layer.clone());
    });
    read_zones(&text, "z.json")
}

fn ed318_band(layer: &Value) -> VerticalLimits {
    let zones = ed318_layer(layer).unwrap();
    assert_eq!(zones.len(), 1);
    zones[0].vertical
}

/// One ED-269 zone with one polygon volume patched by `edit`.
fn ed269_with(edit: impl FnOnce(&mut Map<String, Value>)) -> String {
    let mut volume = json!({"horizontalProjection": {"type": "Polygon", "coordinates": [SQUARE]}});
    edit(volume.as_object_mut().unwrap());
    json!({"UASZoneList": [{"identifier": "Z1", "restriction": "PROHIBITED",
        "applicability": [{"permanent": "YES"}], "geometry": [volume]}]})
    .to_string()
}

fn ed269_band(limits: &Value) -> VerticalLimits {
    let text = ed269_with(|v| v.extend(limits.as_object().unwrap().clone()));
    let zones = read_zones(&text, "z.json").unwrap();
    assert_eq!(zones.len(), 1);
    zones[0].vertical
}

fn ed269_err(limits: &Value) -> InputError {
    err_of(&ed269_with(|v| {
        v.extend(limits.as_object().unwrap().clone());
    }))
}

#[test]
fn ed318_heights_in_metres() {
    let band = ed318_band(&json!({"upper": 120, "upperReference": "AGL", "lower": 0,
                                  "lowerReference": "AGL", "uom": "m"}));
    assert_eq!(band, VerticalLimits::agl(Some(m(0.0)), Some(m(120.0))));
    assert_eq!(band.to_string(), "0–120 m AGL");
    // Without a unit, metres; decimals kept to the micrometre.
    let band = ed318_band(&json!({"upper": 60.000_001, "lower": 12.5}));
    assert_eq!(band.upper.unwrap().height.um(), 60_000_001);
    assert_eq!(band.lower.unwrap().height, m(12.5));
}

#[test]
fn ed318_heights_in_feet() {
    for uom in ["ft", "FT", "Ft"] {
        let band = ed318_band(
            &json!({"upper": 400, "upperReference": "AMSL", "lower": 100,
                                      "lowerReference": "AGL", "uom": uom}),
        );
        // 1 ft = 0.3048 m exactly.
        assert_eq!(
            band.upper,
            Some(limit(Metres::from_um(121_920_000), VerticalReference::Amsl))
        );
        assert_eq!(
            band.lower,
            Some(limit(Metres::from_um(30_480_000), VerticalReference::Agl))
        );
        assert_eq!(band.to_string(), "30.48 m AGL – 121.92 m AMSL");
    }
    // A numeric string is read as a number.
    let band = ed318_band(&json!({"upper": "400", "uom": "FT"}));
    assert_eq!(band.upper.unwrap().height, m(121.92));
}

#[test]
fn ed318_one_side_missing_is_open() {
    let band = ed318_band(&json!({"upper": 60, "upperReference": "AGL", "uom": "m"}));
    assert_eq!(band, VerticalLimits::agl(None, Some(m(60.0))));
    assert!(band.contains(m(0.0)) && !band.contains(m(60.5)));
    let band = ed318_band(
        &json!({"upper": null, "lower": 30, "lowerReference": "WGS84",
                                  "upperReference": "WGS84"}),
    );
    assert_eq!(band.upper, None);
    assert_eq!(band.lower, Some(limit(m(30.0), VerticalReference::Wgs84)));
    assert_eq!(band.to_string(), "from 30 m WGS84 up");
}

#[test]
fn ed318_no_limits_is_the_whole_sky() {
    let zones = read_zones(&ed318_with(|_, _| {}), "z.json").unwrap();
    assert!(zones[0].vertical.is_whole_sky());
    assert!(ed318_band(&Value::Null).is_whole_sky());
    assert!(ed318_band(&json!({"uom": "ft"})).is_whole_sky());
}

#[test]
fn ed318_references_in_any_case_and_aeronautical_spellings() {
    for (text, reference) in [
        ("agl", VerticalReference::Agl),
        ("SFC", VerticalReference::Agl),
        ("GND", VerticalReference::Agl),
        ("amsl", VerticalReference::Amsl),
        ("MSL", VerticalReference::Amsl),
        ("WGS84", VerticalReference::Wgs84),
        ("W84", VerticalReference::Wgs84),
    ] {
        let band = ed318_band(&json!({"upper": 50, "upperReference": text}));
        assert_eq!(band.upper, Some(limit(m(50.0), reference)), "{text}");
    }
    // A height without a reference is above ground level.
    let band = ed318_band(&json!({"lower": 5}));
    assert_eq!(band.lower, Some(limit(m(5.0), VerticalReference::Agl)));
}

#[test]
fn ed318_geometries_at_different_heights_become_one_zone_each() {
    // ED-318's "inverted wedding cake": two volumes of one zone, each with its own layer.
    let square_at = |lower: f64, upper: f64| {
        json!({"type": "Polygon", "coordinates": [SQUARE],
               "layer": {"upper": upper, "upperReference": "AGL", "lower": lower,
                         "lowerReference": "AGL", "uom": "m"}})
    };
    let text = ed318_with(|_, g| {
        *g = json!({"type": "GeometryCollection", "geometries": [
            square_at(50.0, 150.0), square_at(0.0, 50.0), square_at(50.0, 150.0)]});
    });
    let zones = read_zones(&text, "z").unwrap();
    let got: Vec<(&str, String, usize)> = zones
        .iter()
        .map(|z| {
            let Some(ZoneArea::Polygons(mp)) = &z.area else {
                panic!("expected polygons")
            };
            (z.id.as_str(), z.vertical.to_string(), mp.0.len())
        })
        .collect();
    assert_eq!(
        got,
        [
            ("Z1#1", "50–150 m AGL".to_owned(), 2),
            ("Z1#2", "0–50 m AGL".to_owned(), 1)
        ]
    );
    // One band for all: one zone, as without limits.
    let text = ed318_with(|_, g| {
        *g = json!({"type": "GeometryCollection", "geometries": [
            square_at(0.0, 50.0), square_at(0.0, 50.0)]});
    });
    let zones = read_zones(&text, "z").unwrap();
    assert_eq!(zones.len(), 1);
    assert_eq!(zones[0].id, "Z1");
}

#[test]
fn ed318_a_collection_layer_is_the_band_of_members_without_one() {
    let text = ed318_with(|_, g| {
        *g = json!({"type": "GeometryCollection",
            "layer": {"upper": 90},
            "geometries": [
                {"type": "Polygon", "coordinates": [SQUARE]},
                {"type": "Point", "coordinates": [103.9, 1.3], "extent": {"subType": "Circle", "radius": 100},
                 "layer": {"upper": 30}}]});
    });
    let zones = read_zones(&text, "z").unwrap();
    let bands: Vec<String> = zones.iter().map(|z| z.vertical.to_string()).collect();
    assert_eq!(bands, ["up to 90 m AGL", "up to 30 m AGL"]);
}

#[test]
fn ed318_a_zone_without_geometry_has_its_band_in_its_properties() {
    let text = ed318_with(|p, g| {
        *g = Value::Null;
        p.insert("nodes".into(), json!(["S001"]));
        p.insert(
            "layer".into(),
            json!({"upper": 60, "upperReference": "AMSL"}),
        );
    });
    let z = &read_zones(&text, "z.json").unwrap()[0];
    assert_eq!(
        z.vertical.upper,
        Some(limit(m(60.0), VerticalReference::Amsl))
    );
    // With a geometry, the band belongs on the geometry.
    let e = err_of(&ed318_with(|p, _| {
        p.insert("layer".into(), json!({"upper": 60}));
    }));
    assert_err(&e, "layer", "on the geometry (`geometry.layer`");
}

#[test]
fn ed318_refusals_name_the_field() {
    let cases = [
        (
            json!({"upper": "high"}),
            "geometry.layer.upper",
            "must be a number ≥ 0",
        ),
        (
            json!({"upper": true}),
            "geometry.layer.upper",
            "must be a number",
        ),
        (
            json!({"lower": -5, "upper": 60}),
            "geometry.layer.lower",
            "must be ≥ 0, got -5",
        ),
        (
            json!({"upper": 60, "uom": "km"}),
            "geometry.layer.uom",
            "unknown unit \"km\": expected M (metres) or FT (feet)",
        ),
        (
            json!({"upper": 60, "uom": "NM"}),
            "geometry.layer.uom",
            "unknown unit \"NM\"",
        ),
        (
            json!({"upper": 60, "upperReference": "STD"}),
            "geometry.layer.upperReference",
            "unknown vertical reference \"STD\": expected AGL, AMSL or WGS84",
        ),
        (
            json!({"lowerReference": 7}),
            "geometry.layer.lowerReference",
            "unknown vertical reference 7",
        ),
        (
            json!({"lower": 120, "upper": 60}),
            "geometry.layer.lower",
            "the lower limit (120 m) is above the upper limit (60 m)",
        ),
        (
            json!({"lower": 400, "upper": 120, "uom": "ft"}),
            "geometry.layer.lower",
            "(121.92 m) is above the upper limit (36.576 m)",
        ),
        (json!({"upper": 1e12}), "geometry.layer.upper", "too large"),
        (
            json!({"uom": "m", "uomDimensions": "m"}),
            "geometry.layer.uomDimensions",
            "both `uom` and `uomDimensions`",
        ),
        (json!([60]), "geometry.layer", "a layer"),
    ];
    for (layer, field, needle) in cases {
        let e = ed318_layer(&layer).expect_err(&layer.to_string());
        assert_err(&e, field, needle);
        assert_eq!(
            e.location,
            Location::Feature {
                index: 0,
                id: Some("Z1".into())
            }
        );
    }
    // Inside a collection, the member is named.
    let text = ed318_with(|_, g| {
        *g = json!({"type": "GeometryCollection", "geometries": [
            {"type": "Polygon", "coordinates": [SQUARE]},
            {"type": "Polygon", "coordinates": [SQUARE], "layer": {"upper": -1}}]});
    });
    assert_err(
        &err_of(&text),
        "geometry.geometries[1].layer.upper",
        "must be ≥ 0",
    );
    // The whole message names the file, the feature and the field.
    let e = ed318_layer(&json!({"upper": "high"})).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("z.json: feature 0 (`Z1`): field `geometry.layer.upper`: "),
        "{e}"
    );
}

#[test]
fn ed269_heights_in_metres() {
    let band = ed269_band(
        &json!({"uomDimensions": "M", "lowerLimit": 0, "upperLimit": 120,
        "lowerVerticalReference": "AGL", "upperVerticalReference": "AMSL"}),
    );
    assert_eq!(band.lower, Some(limit(m(0.0), VerticalReference::Agl)));
    assert_eq!(band.upper, Some(limit(m(120.0), VerticalReference::Amsl)));
    // Without `uomDimensions`, metres.
    let band = ed269_band(&json!({"upperLimit": 60}));
    assert_eq!(band, VerticalLimits::agl(None, Some(m(60.0))));
}

#[test]
fn ed269_heights_in_feet() {
    for uom in ["FT", "ft"] {
        let band = ed269_band(
            &json!({"uomDimensions": uom, "lowerLimit": "100", "upperLimit": 400,
            "lowerVerticalReference": "AGL", "upperVerticalReference": "AGL"}),
        );
        assert_eq!(
            band,
            VerticalLimits::agl(
                Some(Metres::from_um(30_480_000)),
                Some(Metres::from_um(121_920_000))
            )
        );
    }
}

#[test]
fn ed269_one_side_missing_is_open() {
    let band = ed269_band(
        &json!({"uomDimensions": "M", "lowerLimit": null, "upperLimit": 120,
        "lowerVerticalReference": "AGL", "upperVerticalReference": "AGL"}),
    );
    assert_eq!(band, VerticalLimits::agl(None, Some(m(120.0))));
    let band = ed269_band(&json!({"lowerLimit": 30, "lowerVerticalReference": "SFC"}));
    assert_eq!(band, VerticalLimits::agl(Some(m(30.0)), None));
}

#[test]
fn ed269_no_limits_is_the_whole_sky() {
    assert!(ed269_band(&json!({})).is_whole_sky());
    assert!(ed269_band(&json!({"uomDimensions": "FT", "lowerLimit": null})).is_whole_sky());
    // A circle's radius in NM is fine in a volume without heights.
    let text =
        json!({"features": [{"identifier": "C", "restriction": "PROHIBITED", "applicability": [],
        "geometry": [{"uomDimensions": "NM", "horizontalProjection":
            {"type": "Circle", "center": [103.8, 1.3], "radius": 1}}]}]})
        .to_string();
    let z = &read_zones(&text, "z").unwrap()[0];
    assert!(z.vertical.is_whole_sky());
    assert!(matches!(z.area, Some(ZoneArea::Circle { radius_m, .. }) if radius_m == 1_852.0));
}

#[test]
fn ed269_volumes_at_different_heights_become_one_zone_each() {
    let volume = |upper: i64| {
        json!({"uomDimensions": "M", "upperLimit": upper,
               "horizontalProjection": {"type": "Polygon", "coordinates": [SQUARE]}})
    };
    let text = json!({"UASZoneList": [{"identifier": "W", "restriction": "PROHIBITED",
        "applicability": [], "geometry": [volume(50), volume(150)]}]})
    .to_string();
    let zones = read_zones(&text, "z").unwrap();
    let got: Vec<(&str, String)> = zones
        .iter()
        .map(|z| (z.id.as_str(), z.vertical.to_string()))
        .collect();
    assert_eq!(
        got,
        [
            ("W#1", "up to 50 m AGL".to_owned()),
            ("W#2", "up to 150 m AGL".to_owned())
        ]
    );
}

#[test]
fn ed269_refusals_name_the_field() {
    let cases = [
        (
            json!({"upperLimit": "400ft"}),
            "geometry[0].upperLimit",
            "must be a number ≥ 0",
        ),
        (
            json!({"lowerLimit": -1}),
            "geometry[0].lowerLimit",
            "must be ≥ 0, got -1",
        ),
        (
            json!({"uomDimensions": "KM", "upperLimit": 1}),
            "geometry[0].uomDimensions",
            "unknown unit \"KM\": expected M (metres) or FT (feet)",
        ),
        (
            json!({"uomDimensions": "NM", "upperLimit": 1}),
            "geometry[0].uomDimensions",
            "heights in NM are not supported",
        ),
        (
            json!({"upperLimit": 1, "upperVerticalReference": "FL"}),
            "geometry[0].upperVerticalReference",
            "unknown vertical reference \"FL\"",
        ),
        (
            json!({"lowerVerticalReference": "ground"}),
            "geometry[0].lowerVerticalReference",
            "unknown vertical reference \"ground\"",
        ),
        (
            json!({"uomDimensions": "FT", "lowerLimit": 500, "upperLimit": 400}),
            "geometry[0].lowerLimit",
            "the lower limit (152.4 m) is above the upper limit (121.92 m)",
        ),
    ];
    for (limits, field, needle) in cases {
        let e = ed269_err(&limits);
        assert_err(&e, field, needle);
        assert!(
            e.to_string()
                .starts_with(&format!("z.json: feature 0 (`Z1`): field `{field}`: ")),
            "{e}"
        );
    }
}

#[test]
fn bands_are_written_and_read_back() {
    let band = |lower: Option<VerticalLimit>, upper: Option<VerticalLimit>| VerticalLimits {
        lower,
        upper,
    };
    let zone = |id: &str, area: Option<ZoneArea>, vertical: VerticalLimits| Zone {
        id: id.into(),
        name: String::new(),
        restriction: "PROHIBITED".into(),
        area,
        node_ids: vec!["S001".into()],
        edge_ids: vec![],
        periods: vec![],
        announced: None,
        withdrawn: None,
        vertical,
    };
    let polygon = || {
        let ring: Vec<(f64, f64)> = SQUARE.iter().map(|p| (p[0], p[1])).collect();
        Some(ZoneArea::Polygons(
            geo_types::Polygon::new(ring.into(), vec![]).into(),
        ))
    };
    let circle = Some(ZoneArea::Circle {
        centre: LonLat::new(103.9, 1.3),
        radius_m: 150.0,
    });
    let zones = vec![
        zone(
            "A",
            polygon(),
            VerticalLimits::agl(Some(m(0.0)), Some(m(121.92))),
        ),
        zone(
            "B",
            circle,
            band(None, Some(limit(m(60.000_001), VerticalReference::Amsl))),
        ),
        zone(
            "C",
            None,
            band(Some(limit(m(30.48), VerticalReference::Wgs84)), None),
        ),
        zone("D", polygon(), VerticalLimits::WHOLE_SKY),
    ];
    let text = write_ed318(&zones);
    assert!(
        text.contains(
            "\"layer\": {\n          \"upper\": 121.92,\n          \"upperReference\": \"AGL\",\n          \
             \"lower\": 0.0,\n          \"lowerReference\": \"AGL\",\n          \"uom\": \"m\"\n        }"
        ),
        "{text}"
    );
    assert_eq!(text.matches("\"layer\"").count(), 3, "{text}");
    assert_eq!(read_zones(&text, "z").unwrap(), zones);
    assert_eq!(write_ed318(&read_zones(&text, "z").unwrap()), text);
}
