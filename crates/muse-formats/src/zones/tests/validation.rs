//! What the zone readers refuse: overnight windows not said, unknown types, files with no
//! zone, and `withdrawn` checked and written back.

use super::*;

/// A zone whose one daily window is `entry`.
fn with_window(entry: &Value) -> String {
    ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{ "schedule": [entry] }]),
        );
    })
}

#[test]
fn overnight_windows_must_say_so() {
    let field = "limitedApplicability[0].schedule[0].endTime";
    // 10:00 to 09:00 would close the zone 23 h a day: refused, saying how to mean it.
    let e = err_of(&with_window(
        &json!({"day": ["ANY"], "startTime": "10:00+08:00", "endTime": "09:00+08:00"}),
    ));
    assert_err(
        &e,
        field,
        "the window ends (09:00) before it starts (10:00), times in the startTime's offset: it \
         would run past midnight and close 23 h a day. If it is meant to end the next day, add \
         \"overnight\": true to this schedule entry",
    );
    // An end in another offset is compared once converted: 00:30Z is 08:30+08:00.
    let e = err_of(&with_window(
        &json!({"day": ["ANY"], "startTime": "22:00:30+08:00", "endTime": "00:30Z"}),
    ));
    assert_err(
        &e,
        field,
        "ends (08:30) before it starts (22:00:30), times in the startTime's offset: it would \
         run past midnight and close 10 h 29 min a day",
    );
    // Said explicitly, it is read as before: Saturday 18:00 to Sunday 02:00.
    let z = read_zones(
        &with_window(&json!({"day": ["SAT"], "startTime": "18:00+08:00",
                            "endTime": "02:00+08:00", "overnight": true})),
        "z.json",
    )
    .unwrap();
    let d = &z[0].periods[0].daily[0];
    assert_eq!(
        (d.start, d.end),
        (Millis::from_mins(1_080), Millis::from_mins(120))
    );
    // ... and written back with it.
    let text = write_ed318(&z);
    assert!(text.contains("\"overnight\": true"), "{text}");
    assert_eq!(read_zones(&text, "again").unwrap(), z);
    // `overnight` on a window that ends the day it starts, or not a boolean.
    assert_err(
        &err_of(&with_window(&json!({"day": ["ANY"], "startTime": "10:00Z",
                                    "endTime": "12:00Z", "overnight": true}))),
        "limitedApplicability[0].schedule[0].overnight",
        "the window 10:00–12:00 ends the day it starts",
    );
    assert_err(
        &err_of(&with_window(&json!({"day": ["ANY"], "startTime": "22:00Z",
                                    "endTime": "02:00Z", "overnight": "yes"}))),
        "limitedApplicability[0].schedule[0].overnight",
        "expected true or false, got \"yes\"",
    );
    // An end equal to the start is neither empty nor a whole day: refused.
    for overnight in [false, true] {
        assert_err(
            &err_of(&with_window(&json!({"day": ["ANY"], "startTime": "10:00Z",
                                        "endTime": "10:00Z", "overnight": overnight}))),
            field,
            "the window ends (10:00) when it starts: give a later endTime (for a whole day, \
             startTime 00:00 and endTime 24:00)",
        );
    }
    // A window to midnight is written 24:00, or 00:00 with `overnight`.
    for (end, overnight) in [("24:00Z", false), ("00:00Z", true)] {
        let z = read_zones(
            &with_window(
                &json!({"day": ["ANY"], "startTime": "22:00Z", "endTime": end,
                                "overnight": overnight}),
            ),
            "z.json",
        );
        assert!(z.is_ok(), "{end}: {z:?}");
    }
}

#[test]
fn unknown_zone_types_are_refused() {
    for (key, value) in [
        ("type", "PROHIBTED"),
        ("restriction", "prohibited"),
        ("type", "COMMON"),
    ] {
        let e = err_of(&ed318_with(|p, _| {
            p.remove("type");
            p.insert(key.into(), json!(value));
        }));
        assert_err(
            &e,
            key,
            &format!(
                "unknown zone type \"{value}\": expected one of PROHIBITED, REQ_AUTHORISATION, \
                 REQ_AUTHORIZATION, CONDITIONAL, NO_RESTRICTION, USPACE"
            ),
        );
    }
    for ok in ZONE_TYPES {
        let z = read_zones(
            &ed318_with(|p, _| {
                p.insert("type".into(), json!(ok));
            }),
            "z.json",
        )
        .unwrap();
        assert_eq!(z[0].restriction, ok);
    }
    // ED-318 `restriction` beside ED-269's `type: COMMON`: the restriction is the zone type.
    let z = read_zones(
        &ed318_with(|p, _| {
            p.insert("type".into(), json!("COMMON"));
            p.insert("restriction".into(), json!("CONDITIONAL"));
        }),
        "z.json",
    )
    .unwrap();
    assert_eq!(z[0].restriction, "CONDITIONAL");
}

#[test]
fn a_zone_file_without_zones_is_refused() {
    let dir = std::env::temp_dir().join(format!("muse-zones-empty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, text) in [
        (
            "empty.geojson",
            r#"{"type": "FeatureCollection", "features": []}"#,
        ),
        ("empty.json", r#"{"UASZoneList": []}"#),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let e = read_zones_file(&path).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "{}: the file holds no zone (no features): give a file with at least one zone, \
                 or `--zones none` for none",
                path.display()
            )
        );
        // The text itself (a service's empty listing, say) reads as no zones.
        assert_eq!(read_zones(text, name).unwrap(), vec![]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn withdrawn_is_read_checked_and_written_back() {
    let at = |t: &str| Some(Instant::parse_rfc3339(t).unwrap());
    // As `GET /v1/zones` lists a withdrawn zone: announced, then withdrawn
    // (docs/reference.md#zones-announced-during-the-day).
    let text = ed318_with(|props, _| {
        props.insert("announced".into(), json!("2026-01-05T14:00:00.000+08:00"));
        props.insert("withdrawn".into(), json!("2026-01-05T15:30:00.250+08:00"));
    });
    let zones = read_zones(&text, "z.json").unwrap();
    assert_eq!(zones[0].withdrawn, at("2026-01-05T07:30:00.250Z"));
    let written = write_ed318(&zones);
    assert!(
        written.contains(
            "\"announced\": \"2026-01-05T14:00:00.000+08:00\",\n        \"withdrawn\": \
             \"2026-01-05T15:30:00.250+08:00\""
        ),
        "{written}"
    );
    assert_eq!(read_zones(&written, "w").unwrap(), zones);
    // Absent or null: not withdrawn; ED-269 zones read it too.
    let null = ed318_with(|props, _| {
        props.insert("announced".into(), json!("2026-01-05T14:00:00+08:00"));
        props.insert("withdrawn".into(), Value::Null);
    });
    assert_eq!(read_zones(&null, "z").unwrap()[0].withdrawn, None);
    let ed269 = json!({"UASZoneList": [{"identifier": "E1", "nodes": ["S001"],
        "announced": "2026-01-05T14:00:00+08:00", "withdrawn": "2026-01-05T14:00:00+08:00"}]})
    .to_string();
    assert_eq!(
        read_zones(&ed269, "z").unwrap()[0].withdrawn,
        at("2026-01-05T06:00:00Z")
    );
    // Withdrawn without an announcement, before it, or not a date-time: errors on the field.
    for (announced, withdrawn, needle) in [
        (
            Value::Null,
            json!("2026-01-05T14:00:00+08:00"),
            "a zone known from the start cannot be withdrawn",
        ),
        (
            json!("2026-01-05T14:00:00+08:00"),
            json!("2026-01-05T13:59:59.999+08:00"),
            "withdrawn at 2026-01-05T05:59:59.999+00:00 before it was announced \
             (2026-01-05T06:00:00.000+00:00)",
        ),
        (
            json!("2026-01-05T14:00:00+08:00"),
            json!("15:00"),
            "`15:00` is not an RFC 3339 timestamp",
        ),
    ] {
        let text = ed318_with(|props, _| {
            props.insert("announced".into(), announced.clone());
            props.insert("withdrawn".into(), withdrawn.clone());
        });
        assert_err(&err_of(&text), "withdrawn", needle);
    }
}
