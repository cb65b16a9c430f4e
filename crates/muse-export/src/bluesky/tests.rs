use super::*;
use muse_model::{HeadingRule, Millis};

fn stay(n: u32, arrive: i64, depart: i64) -> Stay {
    Stay {
        node: NodeId(n),
        arrive: Instant(arrive),
        depart: Instant(depart),
    }
}

/// 8 a.m. on some day, in milliseconds since the epoch, plus `s` seconds.
fn at(s: f64) -> i64 {
    1_767_571_200_000 + (s * 1000.0).round() as i64
}

fn lines_of<'a>(text: &'a str, callsign: &str) -> Vec<&'a str> {
    text.lines()
        .filter(|l| l.contains(&format!(" {callsign} ")) || l.contains(&format!(" {callsign}:")))
        .collect()
}

#[test]
fn a_flight_is_created_routed_held_and_deleted() {
    let air = Airspace::line(&[1_000.0, 1_000.0]); // A — B — C
    // Take-off 30.5 s after 8:00 at A, B at 150.5 s, hover to 170.5 s, C at 290.5 s.
    let plan = Plan {
        path: vec![
            stay(0, at(30.5), at(30.5)),
            stay(1, at(150.5), at(170.5)),
            stay(2, at(290.5), at(290.5)),
        ],
    };
    let options = Options {
        offset: UtcOffset(8 * 3600),
        ..Options::default()
    };
    let s = scenario(
        &air,
        &[Flight {
            request: "r-1",
            plan: &plan,
        }],
        &options,
    )
    .unwrap();
    assert_eq!(
        (s.flights, s.legs, s.origin),
        (1, 1, Some(Instant(at(0.0))))
    );
    assert!(s.text.contains(
        "# Time origin 00:00:00.00 = 2026-01-05T08:00:00.000+08:00 (2026-01-05 00:00:00 UTC)"
    ));
    assert!(s.text.contains("\n00:00:00.00>DATE 5,1,2026,00:00:00.00\n"));
    let kts = format!("{:.4}", cas_kts(30.0 / 3.6, 60.0));
    let lines = lines_of(&s.text, "R1");
    let (b, c) = (air.node(NodeId(1)).pos, air.node(NodeId(2)).pos);
    assert_eq!(
        lines,
        [
            format!(
                "# flight R1: request r-1, leg 1/1, A -> C, take-off 00:00:30.500, landing \
                 00:04:50.500, destination {:.7} {:.7}",
                air.node(NodeId(2)).pos.lat,
                air.node(NodeId(2)).pos.lon
            )
            .as_str(),
            format!(
                "00:00:30.50>CRE R1 M600 {:.7} {:.7} 90.0 196.850 {kts}",
                air.node(NodeId(0)).pos.lat,
                air.node(NodeId(0)).pos.lon
            )
            .as_str(),
            format!("00:00:30.50>ADDWPT R1 {:.7} {:.7}", b.lat, b.lon).as_str(),
            format!("00:00:30.50>ADDWPT R1 {:.7} {:.7}", c.lat, c.lon).as_str(),
            "00:00:30.50>AT R1 R1002 DO DEL R1",
            // The planned arrivals at B and C, kept by the autopilot's speed.
            "00:00:30.50>RTA R1 R1001 00:02:30.50",
            "00:00:30.50>RTA R1 R1002 00:04:50.50",
            "00:00:30.50>VNAV R1 ON",
            "00:02:30.50>SPD R1 0",
            format!("00:02:50.50>SPD R1 {kts}").as_str(),
            "00:02:50.50>VNAV R1 ON",
        ]
    );
    // Open loop: the same without the required times of arrival.
    let open = Options {
        open_loop: true,
        ..options
    };
    let s = scenario(
        &air,
        &[Flight {
            request: "r-1",
            plan: &plan,
        }],
        &open,
    )
    .unwrap();
    let kept: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| !l.contains(">RTA ") && !l.contains(">VNAV "))
        .collect();
    assert_eq!(lines_of(&s.text, "R1"), kept);
}

#[test]
fn calibrated_airspeed_is_below_true_airspeed_above_sea_level() {
    assert!((cas_kts(10.0, 0.0) - 10.0 / KT_MPS).abs() < 1e-9);
    let ratio = (30.0 / 3.6) / (cas_kts(30.0 / 3.6, 60.0) * KT_MPS);
    // BlueSky's own conversion gives TAS/CAS = 1.00289 at 60 m.
    assert!((ratio - 1.002_89).abs() < 2e-5, "{ratio}");
}

#[test]
fn callsigns_are_unique_and_legs_numbered() {
    let air = Airspace::line(&[1_000.0, 1_000.0]);
    let one = Plan {
        path: vec![stay(0, at(0.0), at(0.0)), stay(1, at(120.0), at(120.0))],
    };
    // A → B, 5 minutes on the ground at B, B → C.
    let two = Plan {
        path: vec![
            stay(0, at(10.0), at(10.0)),
            stay(1, at(130.0), at(130.0)),
            stay(1, at(430.0), at(430.0)),
            stay(2, at(550.0), at(550.0)),
        ],
    };
    let flights = [
        Flight {
            request: "a1",
            plan: &one,
        },
        Flight {
            request: "A1",
            plan: &one,
        },
        Flight {
            request: "x",
            plan: &two,
        },
    ];
    let s = scenario(&air, &flights, &Options::default()).unwrap();
    assert_eq!((s.flights, s.legs), (3, 4));
    let names: Vec<&str> = s
        .text
        .lines()
        .filter_map(|l| l.strip_prefix("# flight "))
        .map(|l| l.split(':').next().unwrap())
        .collect();
    // In order of take-off, then request id: "A1" before "a1".
    assert_eq!(names, ["A1", "A1X2", "XL1", "XL2"]);
    assert!(
        s.text
            .contains("# flight XL2: request x, leg 2/2, B -> C, take-off 00:07:10.000")
    );
    assert!(s.text.contains("00:07:10.00>CRE XL2 M600 "));
    assert!(s.text.contains("00:00:10.00>AT XL1 XL1001 DO DEL XL1\n"));
    // No command holds a leg on the ground: the swap is between a deletion and a creation.
    assert!(!s.text.contains("SPD XL"));
}

#[test]
fn a_change_of_layer_is_a_timed_altitude_command() {
    let layers = Layers {
        count: 2,
        heading_rule: HeadingRule::None,
        ..Layers::default()
    };
    let air = Airspace::line(&[1_000.0, 1_000.0])
        .layered(&layers)
        .unwrap();
    let climb = layers.climb_time().0;
    // A@1, climb at A to A@2, fly to B@2, C@2, descend to C@1 and land.
    let t1 = at(climb as f64 / 1000.0);
    let plan = Plan {
        path: vec![
            stay(0, at(0.0), at(0.0)),
            stay(3, t1, t1),
            stay(4, t1 + 120_000, t1 + 120_000),
            stay(5, t1 + 240_000, t1 + 240_000),
            stay(2, t1 + 240_000 + climb, t1 + 240_000 + climb),
        ],
    };
    let s = scenario(
        &air,
        &[Flight {
            request: "L",
            plan: &plan,
        }],
        &Options::default(),
    )
    .unwrap();
    let upper_kts = format!("{:.4}", cas_kts(30.0 / 3.6, 69.144));
    assert!(s.text.contains(" 196.850 0.0000\n"), "{}", s.text);
    assert!(
        s.text.contains("00:00:00.00>ALT L 226.850 984.3\n"),
        "{}",
        s.text
    );
    assert!(s.text.contains(&format!("00:00:01.83>SPD L {upper_kts}\n")));
    // Two waypoints (B, C), deleted over C: the descent at C is not flown.
    assert!(s.text.contains("AT L L002 DO DEL L\n"));
    assert!(s.text.contains("landing 00:04:01.829,"));
}

#[test]
fn bad_inputs_are_refused() {
    let air = Airspace::line(&[1_000.0]);
    let plan = Plan {
        path: vec![stay(0, 0, 0), stay(1, 120_000, 120_000)],
    };
    let flight = [Flight {
        request: "r",
        plan: &plan,
    }];
    let typed = |t: &str| Options {
        aircraft_type: t.to_owned(),
        ..Options::default()
    };
    for t in ["", "M 600", "M600;DEL", "M600#"] {
        assert_eq!(
            scenario(&air, &flight, &typed(t)),
            Err(BlueskyError::Type(t.to_owned()))
        );
    }
    let slow = Options {
        speed: Speed::from_kmh(1.0).unwrap(),
        ..Options::default()
    };
    assert!(matches!(
        scenario(&air, &flight, &slow),
        Err(BlueskyError::Speed { .. })
    ));
    let empty = Plan::default();
    assert_eq!(
        scenario(
            &air,
            &[Flight {
                request: "e",
                plan: &empty
            }],
            &Options::default()
        ),
        Err(BlueskyError::EmptyPlan("e".to_owned()))
    );
    let outside = Plan {
        path: vec![stay(0, 0, 0), stay(7, 120_000, 120_000)],
    };
    assert_eq!(
        scenario(
            &air,
            &[Flight {
                request: "o",
                plan: &outside
            }],
            &Options::default()
        ),
        Err(BlueskyError::UnknownNode {
            request: "o".to_owned(),
            node: 7
        })
    );
}

#[test]
fn no_flights_write_a_header_only() {
    let s = scenario(&Airspace::line(&[1_000.0]), &[], &Options::default()).unwrap();
    assert_eq!((s.flights, s.legs, s.origin), (0, 0, None));
    assert!(s.text.lines().all(|l| l.starts_with('#')));
}

#[test]
fn clocks_round_to_the_hundredth() {
    assert_eq!(clock(Millis(0)), "00:00:00.00");
    assert_eq!(clock(Millis(1_004)), "00:00:01.00");
    assert_eq!(clock(Millis(1_005)), "00:00:01.01");
    assert_eq!(clock(Millis(90_061_999)), "25:01:02.00");
    assert_eq!(clock_ms(Millis(90_061_999)), "25:01:01.999");
}

#[test]
fn a_sharp_turn_is_flown_over_its_node() {
    let air = Airspace::line(&[1_000.0, 1_000.0]); // A — B — C
    // B → C, back through B (a 180° turn at C), on to A (straight on at B).
    let plan = Plan {
        path: vec![
            stay(1, 0, 0),
            stay(2, 120_000, 120_000),
            stay(1, 240_000, 240_000),
            stay(0, 360_000, 360_000),
        ],
    };
    let s = scenario(
        &air,
        &[Flight {
            request: "u",
            plan: &plan,
        }],
        &Options::default(),
    )
    .unwrap();
    let modes: Vec<&str> = s
        .text
        .lines()
        .filter(|l| l.contains(">ADDWPT U "))
        .map(|l| l.split(' ').nth(2).unwrap())
        .collect();
    let (a, b, c) = (
        air.node(NodeId(0)).pos,
        air.node(NodeId(1)).pos,
        air.node(NodeId(2)).pos,
    );
    let at = |p: LonLat| format!("{:.7}", p.lat);
    assert_eq!(
        modes,
        [
            "FLYOVER",
            at(c).as_str(),
            "FLYBY",
            at(b).as_str(),
            at(a).as_str()
        ]
    );
    assert!(s.text.contains("AT U U003 DO DEL U\n"));
}
