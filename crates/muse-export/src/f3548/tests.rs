use muse_model::{Airspace, HeadingRule, Instant, Layers, NodeId, Plan, Stay};

use super::*;

fn stay(n: u32, a_ms: i64, d_ms: i64) -> Stay {
    Stay {
        node: NodeId(n),
        arrive: Instant(a_ms),
        depart: Instant(d_ms),
    }
}

fn export(air: &Airspace, plan: &Plan, options: &Options) -> Result<IntentEntry, F3548Error> {
    let flights = [Flight {
        request: "r000001",
        plan,
    }];
    operational_intents(air, &flights, options).map(|mut v| v.remove(0))
}

/// A — B — C along 1.3° N; a flight from A hovering 10 s at B on its way to C.
fn a_to_c() -> (Airspace, Plan) {
    let plan = Plan {
        path: vec![
            stay(0, 1_000, 1_000),
            stay(1, 121_000, 131_000),
            stay(2, 251_000, 251_000),
        ],
    };
    (Airspace::line(&[1_000.0, 1_000.0]), plan)
}

#[test]
fn a_flight_is_its_traversals_and_its_hovers_in_time_order() {
    let (air, plan) = a_to_c();
    let entry = export(&air, &plan, &Options::default()).unwrap();
    assert_eq!(entry.request, "r000001");
    let oi = &entry.operational_intent;
    let r = &oi.reference;
    assert_eq!(r.id, entity_id("muse:f3548:intent:r000001"));
    assert_eq!(
        r.subscription_id,
        entity_id("muse:f3548:subscription:r000001")
    );
    assert_ne!(r.id, r.subscription_id);
    assert_eq!(
        (r.state, r.version, r.uss_availability, r.manager.as_str()),
        ("Accepted", 1, "Unknown", "muse")
    );
    assert_eq!(r.time_start.value, "1970-01-01T00:00:01.000Z");
    assert_eq!(r.time_end.value, "1970-01-01T00:04:11.000Z");
    let v = &oi.details.volumes;
    // A–B, the hover at B, B–C; the take-off and the landing last no time.
    assert_eq!(v.len(), 3);
    let windows: Vec<_> = v
        .iter()
        .map(|v| (v.time_start.value.as_str(), v.time_end.value.as_str()))
        .collect();
    assert_eq!(
        windows,
        [
            ("1970-01-01T00:00:01.000Z", "1970-01-01T00:02:01.000Z"),
            ("1970-01-01T00:02:01.000Z", "1970-01-01T00:02:11.000Z"),
            ("1970-01-01T00:02:11.000Z", "1970-01-01T00:04:11.000Z"),
        ]
    );
    let polygon = v[0].volume.outline_polygon.as_ref().unwrap();
    assert_eq!(polygon.vertices.len(), 2 * CAP_VERTICES);
    assert!(v[0].volume.outline_circle.is_none());
    let circle = v[1].volume.outline_circle.as_ref().unwrap();
    assert_eq!(
        circle.center,
        LatLngPoint {
            lat: 1.3,
            lng: 103.81
        }
    );
    assert_eq!(circle.radius, Radius::metres(10.0));
    for v in v {
        assert_eq!(v.volume.altitude_lower, Altitude::w84_metres(57.0));
        assert_eq!(v.volume.altitude_upper, Altitude::w84_metres(63.0));
    }
    assert!(oi.details.off_nominal_volumes.is_empty());
    assert_eq!(oi.details.priority, 0);
}

#[test]
fn the_corridor_outline_spans_the_corridor_and_its_buffer() {
    let (air, plan) = a_to_c();
    let options = Options {
        buffer_m: 30.0,
        ..Options::default()
    };
    let entry = export(&air, &plan, &options).unwrap();
    let polygon = entry.operational_intent.details.volumes[0]
        .volume
        .outline_polygon
        .clone()
        .unwrap();
    let lats = polygon.vertices.iter().map(|p| p.lat);
    let lngs = polygon.vertices.iter().map(|p| p.lng);
    let (south, north) = lats.fold((90.0f64, -90.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
    let (west, east) = lngs.fold((180.0f64, -180.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
    // The straight sides 30 m north and south of 1.3° N; the ends beyond A and B.
    let metres_per_degree = 110_574.8;
    assert!(((north - 1.3) * metres_per_degree - 30.0).abs() < 0.01);
    assert!(((1.3 - south) * metres_per_degree - 30.0).abs() < 0.01);
    assert!(west < 103.8 && east > 103.81 && east < 103.811);
}

#[test]
fn no_buffer_is_written_as_one_centimetre() {
    let (air, plan) = a_to_c();
    let options = Options {
        buffer_m: 0.0,
        ..Options::default()
    };
    let entry = export(&air, &plan, &options).unwrap();
    let volumes = &entry.operational_intent.details.volumes;
    let circle = volumes[1].volume.outline_circle.as_ref().unwrap();
    assert_eq!(circle.radius, Radius::metres(MIN_OUTLINE_M));
    let polygon = volumes[0].volume.outline_polygon.as_ref().unwrap();
    let mut distinct = polygon.vertices.clone();
    distinct.dedup();
    assert_eq!(distinct.len(), 2 * CAP_VERTICES);
}

#[test]
fn a_climb_spans_both_layers_at_its_node() {
    let layers = Layers {
        count: 2,
        heading_rule: HeadingRule::None,
        ..Layers::default()
    };
    let air = Airspace::line(&[1_000.0]).layered(&layers).unwrap();
    // A@1 (0) → A@2 (2) → B@2 (3) → B@1 (1).
    let plan = Plan {
        path: vec![
            stay(0, 0, 0),
            stay(2, 1_829, 1_829),
            stay(3, 121_829, 121_829),
            stay(1, 123_658, 123_658),
        ],
    };
    let entry = export(&air, &plan, &Options::default()).unwrap();
    let bands: Vec<_> = entry
        .operational_intent
        .details
        .volumes
        .iter()
        .map(|v| {
            (
                v.volume.outline_circle.is_some(),
                v.volume.altitude_lower.value,
                v.volume.altitude_upper.value,
            )
        })
        .collect();
    assert_eq!(
        bands,
        [
            (true, 57.0, 72.144),
            (false, 66.144, 72.144),
            (true, 57.0, 72.144)
        ]
    );
}

#[test]
fn a_battery_swap_leaves_the_time_on_the_ground_out() {
    let air = Airspace::line(&[1_000.0, 1_000.0]);
    // A → B, land; 5 min on the ground; B → C.
    let plan = Plan {
        path: vec![
            stay(0, 0, 0),
            stay(1, 120_000, 120_000),
            stay(1, 420_000, 420_000),
            stay(2, 540_000, 540_000),
        ],
    };
    let entry = export(&air, &plan, &Options::default()).unwrap();
    let v = &entry.operational_intent.details.volumes;
    assert_eq!(v.len(), 2);
    assert_eq!(v[0].time_end.value, "1970-01-01T00:02:00.000Z");
    assert_eq!(v[1].time_start.value, "1970-01-01T00:07:00.000Z");
}

#[test]
fn ids_are_version_4_uuids_that_differ_by_request() {
    let mut seen = std::collections::HashSet::new();
    for i in 0..1_000 {
        let id = entity_id(&format!("muse:f3548:intent:r{i:06}"));
        let groups: Vec<usize> = id.split('-').map(str::len).collect();
        assert_eq!(groups, [8, 4, 4, 4, 12]);
        assert!(id.chars().all(|c| c == '-' || c.is_ascii_hexdigit()));
        assert!(id[14..].starts_with('4') && "89ab".contains(&id[19..20]));
        assert!(seen.insert(id));
    }
}

#[test]
fn options_out_of_range_are_refused() {
    let (air, plan) = a_to_c();
    let with = |f: &dyn Fn(&mut Options)| {
        let mut o = Options::default();
        f(&mut o);
        export(&air, &plan, &o).unwrap_err()
    };
    assert_eq!(with(&|o| o.buffer_m = -0.5), F3548Error::Buffer(-0.5));
    assert_eq!(with(&|o| o.buffer_m = 1_000.5), F3548Error::Buffer(1_000.5));
    assert!(matches!(
        with(&|o| o.buffer_m = f64::NAN),
        F3548Error::Buffer(_)
    ));
    assert_eq!(
        with(&|o| o.vertical_buffer_m = 0.0),
        F3548Error::VerticalBuffer(0.0)
    );
    for url in [
        "uss.example.com",
        "https://uss.example.com/",
        "https://",
        "http://a b",
    ] {
        assert!(matches!(
            with(&|o| o.uss_base_url = url.into()),
            F3548Error::BaseUrl(_)
        ));
    }
    assert_eq!(with(&|o| o.manager = " ".into()), F3548Error::Manager);
}

#[test]
fn plans_that_do_not_fit_are_errors_naming_the_request() {
    let (air, plan) = a_to_c();
    let options = Options::default();
    let twice = [
        Flight {
            request: "r1",
            plan: &plan,
        },
        Flight {
            request: "r1",
            plan: &plan,
        },
    ];
    assert_eq!(
        operational_intents(&air, &twice, &options),
        Err(F3548Error::DuplicateRequest("r1".into()))
    );
    let unknown = Plan {
        path: vec![stay(0, 0, 0), stay(7, 10, 10)],
    };
    let e = export(&air, &unknown, &options).unwrap_err();
    assert!(
        e.to_string()
            .contains("r000001: node #7 is not in the airspace")
    );
    let skip = Plan {
        path: vec![stay(0, 0, 0), stay(2, 10_000, 10_000)],
    };
    let e = export(&air, &skip, &options).unwrap_err();
    assert!(e.to_string().contains("a corridor from A to C"), "{e}");
    let backwards = Plan {
        path: vec![stay(0, 5_000, 5_000), stay(1, 5_000, 5_000)],
    };
    assert!(matches!(
        export(&air, &backwards, &options),
        Err(F3548Error::Backwards { .. })
    ));
    let grounded = Plan {
        path: vec![stay(0, 0, 0)],
    };
    assert_eq!(
        export(&air, &grounded, &options),
        Err(F3548Error::Empty("r000001".into()))
    );
}

#[test]
fn limits_of_the_standard_are_errors() {
    let air = Airspace::line(&[1_000.0]);
    // 626 traversals back and forth: 626 · 16 = 10,016 vertices.
    let path = (0..=626)
        .map(|i| stay(i % 2, i64::from(i) * 120_000, i64::from(i) * 120_000))
        .collect();
    let e = export(&air, &Plan { path }, &Options::default()).unwrap_err();
    assert_eq!(
        e,
        F3548Error::TooManyVertices {
            request: "r000001".into(),
            vertices: 10_016
        }
    );
    // 625 traversals fit.
    let path = (0..=625)
        .map(|i| stay(i % 2, i64::from(i) * 120_000, i64::from(i) * 120_000))
        .collect();
    assert!(export(&air, &Plan { path }, &Options::default()).is_ok());
    let far = Plan {
        path: vec![
            stay(0, 253_402_300_000_000, 253_402_300_000_000),
            stay(1, 253_402_400_000_000, 253_402_400_000_000),
        ],
    };
    assert!(matches!(
        export(&air, &far, &Options::default()),
        Err(F3548Error::Time { .. })
    ));
}

#[test]
fn a_sharing_time_checks_the_horizon() {
    let (air, plan) = a_to_c();
    let at = |ms| Options {
        shared_at: Some(Instant(ms)),
        ..Options::default()
    };
    assert!(export(&air, &plan, &at(0)).is_ok());
    assert!(export(&air, &plan, &at(251_000 - 1)).is_ok());
    let e = export(&air, &plan, &at(251_000)).unwrap_err();
    assert!(e.to_string().contains("ends before it is shared"), "{e}");
    let month = 30 * 86_400_000;
    assert!(export(&air, &plan, &at(1_000 - month)).is_ok());
    let e = export(&air, &plan, &at(1_000 - month - 1)).unwrap_err();
    assert!(e.to_string().contains("30-day planning horizon"), "{e}");
}
