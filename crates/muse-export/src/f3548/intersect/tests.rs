use muse_model::{Airspace, HeadingRule, Instant, Layers, NodeId, Plan, Stay};

use super::*;
use crate::f3548::{
    Circle, F3548Error, Flight, LatLngPoint, Options, Radius, Time, Volume3D, operational_intents,
};

fn stay(n: u32, a_s: i64, d_s: i64) -> Stay {
    Stay {
        node: NodeId(n),
        arrive: Instant(a_s * 1_000),
        depart: Instant(d_s * 1_000),
    }
}

fn plan(stays: &[Stay]) -> Plan {
    Plan {
        path: stays.to_vec(),
    }
}

/// The intents of `plans` over `air` at buffer `b` (vertical buffer `v`).
fn intents(air: &Airspace, plans: &[Plan], b: f64, v: f64) -> Vec<OperationalIntent> {
    let names: Vec<String> = (0..plans.len()).map(|i| format!("r{i}")).collect();
    let flights: Vec<Flight<'_>> = plans
        .iter()
        .zip(&names)
        .map(|(plan, request)| Flight { request, plan })
        .collect();
    let options = Options {
        buffer_m: b,
        vertical_buffer_m: v,
        ..Options::default()
    };
    operational_intents(air, &flights, &options)
        .unwrap()
        .into_iter()
        .map(|e| e.operational_intent)
        .collect()
}

fn count(air: &Airspace, plans: &[Plan], b: f64) -> u64 {
    intersecting_pairs(&intents(air, plans, b, 3.0))
        .unwrap()
        .intersecting
}

/// A — B — C, 0.01° of longitude apart (1,112.9 m) along 1.3° N.
fn line() -> Airspace {
    Airspace::line(&[1_000.0, 1_000.0])
}

#[test]
fn a_landing_and_a_take_off_tau_apart_at_a_node_never_meet() {
    // One lands at B at 120 s; the other takes off there 5 s later, towards C.
    let first = plan(&[stay(0, 0, 0), stay(1, 120, 120)]);
    let second = plan(&[stay(1, 125, 125), stay(2, 245, 245)]);
    for b in [0.0, 10.0, 30.0, 1_000.0] {
        assert_eq!(
            count(&line(), &[first.clone(), second.clone()], b),
            0,
            "B = {b}"
        );
    }
}

#[test]
fn a_take_off_tau_before_a_landing_at_the_same_node_always_meets() {
    // The second leaves B towards C 5 s before the first reaches B from A: both corridors'
    // volumes hold B during [115 s, 120 s), whatever the buffer (the node rule holds, the
    // volumes do not see it: each covers its whole corridor for its whole traversal).
    let first = plan(&[stay(0, 0, 0), stay(1, 120, 120)]);
    let second = plan(&[stay(1, 115, 115), stay(2, 235, 235)]);
    for b in [0.0, 10.0, 30.0] {
        assert_eq!(
            count(&line(), &[first.clone(), second.clone()], b),
            1,
            "B = {b}"
        );
    }
}

#[test]
fn a_hover_and_a_corridor_a_node_apart_meet_once_twice_the_buffer_spans_the_gap() {
    // The first hovers at A during [0, 60 s), then flies to B; the second flies B → C during
    // [0, 60 s). A is 1,112.9 m from B: the hover's circle (radius B) and the corridor's
    // outline (reaching B beyond its end) meet when 2·B ≥ 1,112.9 m. The first's corridor
    // A–B starts as the second's B–C ends, at 60 s: back to back, no overlap.
    let first = plan(&[stay(0, 0, 60), stay(1, 180, 180)]);
    let second = plan(&[stay(1, 0, 0), stay(2, 60, 60)]);
    let plans = [first, second];
    for (b, expected) in [(0.0, 0), (30.0, 0), (556.0, 0), (557.0, 1), (1_000.0, 1)] {
        assert_eq!(count(&line(), &plans, b), expected, "B = {b}");
    }
}

#[test]
fn the_same_corridor_back_to_back_does_not_meet_but_overlapping_does() {
    let first = plan(&[stay(0, 0, 0), stay(1, 120, 120)]);
    let next = plan(&[stay(0, 120, 120), stay(1, 240, 240)]);
    let early = plan(&[stay(0, 119, 119), stay(1, 239, 239)]);
    assert_eq!(count(&line(), &[first.clone(), next], 10.0), 0);
    assert_eq!(count(&line(), &[first, early], 10.0), 1);
}

#[test]
fn parallel_corridors_meet_only_when_the_buffers_span_their_distance() {
    // Two corridors 0.001° of latitude (110.6 m) apart, flown at the same time.
    let node = |id: &str, lon: f64, lat: f64| muse_model::Node {
        id: id.into(),
        kind: muse_model::NodeKind::Station,
        name: String::new(),
        pos: muse_model::LonLat::new(lon, lat),
    };
    let edge = |id: &str, from, to| muse_model::Edge {
        id: id.into(),
        from: NodeId(from),
        to: NodeId(to),
        length_m: 1_000.0,
    };
    let air = Airspace::new(
        vec![
            node("A", 103.80, 1.300),
            node("B", 103.81, 1.300),
            node("C", 103.80, 1.301),
            node("D", 103.81, 1.301),
        ],
        vec![edge("A-B", 0, 1), edge("C-D", 2, 3)],
    )
    .unwrap();
    let plans = [
        plan(&[stay(0, 0, 0), stay(1, 120, 120)]),
        plan(&[stay(3, 0, 0), stay(2, 120, 120)]),
    ];
    let gap = 0.001 * 110_574.8; // metres per degree of latitude at 1.3° N
    assert_eq!(count(&air, &plans, gap / 2.0 - 0.5), 0);
    assert_eq!(count(&air, &plans, gap / 2.0 + 0.5), 1);
}

#[test]
fn layers_apart_do_not_meet_unless_the_vertical_buffers_overlap() {
    let layers = Layers {
        count: 2,
        heading_rule: HeadingRule::None,
        ..Layers::default()
    };
    // A — B — C at two layers: X@1 is node 0, 1, 2 and X@2 is 3, 4, 5.
    let air = line().layered(&layers).unwrap();
    // B@1 → C@1, while the other climbs at A and flies A@2 → B@2: their corridors share
    // B, and the climb at A is far from B–C.
    let low = plan(&[stay(1, 0, 0), stay(2, 120, 120)]);
    let high = plan(&[stay(0, 0, 0), stay(3, 2, 2), stay(4, 122, 122)]);
    let plans = [low, high];
    let with = |v| {
        intersecting_pairs(&intents(&air, &plans, 10.0, v))
            .unwrap()
            .intersecting
    };
    // Layers 9.144 m apart: bands ± v meet once 2·v ≥ 9.144 m.
    assert_eq!(with(3.0), 0);
    assert_eq!(with(4.5), 0);
    assert_eq!(with(4.6), 1);
    // Climbing at B while the other leaves B: the climb spans both layers.
    let climb = plan(&[stay(1, 60, 60), stay(4, 62, 62), stay(5, 182, 182)]);
    let plans = [plans[0].clone(), climb];
    assert_eq!(
        intersecting_pairs(&intents(&air, &plans, 10.0, 3.0))
            .unwrap()
            .intersecting,
        1
    );
}

#[test]
fn counts_pairs_not_volumes() {
    // Three flights over one corridor at once: three pairs, each counted once although
    // their hovers meet too.
    let p = plan(&[stay(0, 0, 30), stay(1, 150, 150)]);
    let plans = [p.clone(), p.clone(), p];
    let pairs = intersecting_pairs(&intents(&line(), &plans, 10.0, 3.0)).unwrap();
    assert_eq!(
        pairs,
        Pairs {
            intersecting: 3,
            pairs: 3,
            intents: 3,
            volumes: 6
        }
    );
    assert_eq!(intersecting_pairs(&[]).unwrap().pairs, 0);
}

#[test]
fn malformed_volumes_are_errors() {
    let p = plan(&[stay(0, 0, 30), stay(1, 150, 150)]);
    let base = intents(&line(), &[p], 10.0, 3.0);
    let edit = |f: &dyn Fn(&mut Volume4D)| {
        let mut oi = base.clone();
        f(&mut oi[0].details.volumes[1]);
        intersecting_pairs(&oi).unwrap_err()
    };
    assert!(matches!(
        edit(&|v| v.time_end = Time::rfc3339("noon".into())),
        IntersectError::Time {
            intent: 0,
            volume: 1,
            ..
        }
    ));
    assert!(matches!(
        edit(&|v| v.time_end = v.time_start.clone()),
        IntersectError::Backwards { .. }
    ));
    assert!(matches!(
        edit(&|v| v.volume.outline_polygon = None),
        IntersectError::Outline { .. }
    ));
    let circle = Circle {
        center: LatLngPoint {
            lat: 1.3,
            lng: 103.8,
        },
        radius: Radius::metres(0.0),
    };
    assert!(matches!(
        edit(&|v| {
            v.volume = Volume3D {
                outline_circle: Some(circle.clone()),
                outline_polygon: None,
                ..v.volume.clone()
            };
        }),
        IntersectError::Outline { .. }
    ));
    // The builder's own errors stay the builder's.
    let options = Options {
        buffer_m: -1.0,
        ..Options::default()
    };
    assert_eq!(
        operational_intents(&line(), &[], &options),
        Err(F3548Error::Buffer(-1.0))
    );
}
