//! Plans files with multi-leg plans (docs/reference.md#plans, #zones-announced-during-the-day,
//! #multi-leg-trips) and with layers (#layered-airspace): each golden file is what the writer gives
//! for known records, byte for byte, and reads back to the same records.

use std::path::PathBuf;

use muse_formats::airspace_geojson::AirspaceFile;
use muse_formats::plans::{PlanRecord, plan_line, read_plans_file, write_plan_line};
use muse_model::plan::Change;
use muse_model::plan::{Fate, FateKind};
use muse_model::{Airspace, Instant, Millis, Plan, Stay, UtcOffset};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("testdata/plans")
        .join(name)
}

/// `A - B - W - C` (`W` a waypoint), 1 km per edge: 120 s at 30 km/h.
fn air() -> Airspace {
    AirspaceFile::read(&fixture("air.geojson"))
        .unwrap()
        .airspace
}

/// 2026-01-05 08:00 in Singapore, plus `s` seconds.
fn at(s: i64) -> Instant {
    Instant(
        Instant::parse_rfc3339("2026-01-05T08:00:00+08:00")
            .unwrap()
            .0
            + s * 1_000,
    )
}

/// Legs, each `(take-off in seconds after 08:00, nodes)`, 120 s per edge, no hovering.
fn trip(air: &Airspace, legs: &[(i64, &[&str])]) -> Plan {
    let mut path = Vec::new();
    for &(takeoff, nodes) in legs {
        for (i, id) in nodes.iter().enumerate() {
            let t = at(takeoff + 120 * i as i64);
            path.push(Stay {
                node: air.node_id(id).unwrap(),
                arrive: t,
                depart: t,
            });
        }
    }
    Plan { path }
}

fn record(id: &str, from: &str, to: &str, departure: i64, plan: Plan) -> PlanRecord {
    PlanRecord::first(
        id.into(),
        from.into(),
        to.into(),
        at(departure),
        Ok(plan),
        Some(Millis::from_secs(360)),
        7,
    )
}

fn changed(mut rec: PlanRecord, zone: &str, announced: i64, fate: Fate) -> PlanRecord {
    rec.changes.push(Change {
        zone: zone.into(),
        announced: at(announced),
        airborne: matches!(fate, Fate::Diverted(_) | Fate::Contingency(_)),
        outcome: fate.kind(),
    });
    rec.fate = Some(fate);
    rec
}

/// The records of `multi_leg.jsonl`: a two-leg plan (swap at `B` for 5 min), a two-leg plan
/// replanned later, a two-leg plan left in contingency during its second leg, and a
/// single-leg plan (written as before, without `legs`).
fn records(air: &Airspace) -> Vec<PlanRecord> {
    let a_to_c = |t: i64| trip(air, &[(t, &["A", "B"]), (t + 420, &["B", "W", "C"])]);
    let c_to_a = |t: i64| trip(air, &[(t, &["C", "W", "B"]), (t + 540, &["B", "A"])]);
    let stranded = trip(air, &[(1_800, &["A", "B"]), (2_220, &["B", "W"])]);
    vec![
        record("r1", "A", "C", 0, a_to_c(0)),
        changed(
            record("r2", "C", "A", 600, c_to_a(600)),
            "Z1",
            300,
            Fate::Replanned(c_to_a(900)),
        ),
        changed(
            record("r3", "A", "C", 1_800, a_to_c(1_800)),
            "Z2",
            2_280,
            Fate::Contingency(stranded),
        ),
        PlanRecord {
            free_flow: Some(Millis::from_secs(120)),
            ..record("r4", "A", "B", 3_600, trip(air, &[(3_600, &["A", "B"])]))
        },
    ]
}

#[test]
fn multi_leg_golden_file() {
    let air = air();
    let records = records(&air);
    let mut text = String::new();
    for r in &records {
        write_plan_line(&mut text, &air, UtcOffset::SINGAPORE, r);
    }
    let golden = std::fs::read_to_string(fixture("multi_leg.jsonl")).unwrap();
    assert_eq!(text, golden);
    assert_eq!(
        read_plans_file(&fixture("multi_leg.jsonl"), &air).unwrap(),
        records
    );
}

#[test]
fn multi_leg_lines_describe_the_whole_trip() {
    let air = air();
    let records = records(&air);
    let line = plan_line(&air, UtcOffset::SINGAPORE, &records[0]);
    // First take-off to last landing, the 5 minutes on the ground at B included.
    assert_eq!(
        line.takeoff.as_deref(),
        Some("2026-01-05T08:00:00.000+08:00")
    );
    assert_eq!(
        line.landing.as_deref(),
        Some("2026-01-05T08:11:00.000+08:00")
    );
    assert_eq!(line.airborne_s, Some(660.0));
    assert_eq!(line.air_delay_s, Some(300.0));
    assert_eq!(line.distance_m, Some(3_000.0), "the swap flies no edge");
    let nodes = |stays: &[muse_formats::plans::StayLine]| -> Vec<String> {
        stays.iter().map(|s| s.node.clone()).collect()
    };
    assert_eq!(
        nodes(line.path.as_ref().unwrap()),
        ["A", "B", "B", "W", "C"]
    );
    let legs = line.legs.unwrap();
    assert_eq!(legs.len(), 2);
    assert_eq!(nodes(&legs[0].path), ["A", "B"]);
    assert_eq!(nodes(&legs[1].path), ["B", "W", "C"]);
    assert_eq!(
        (legs[1].takeoff.as_str(), legs[1].landing.as_deref()),
        (
            "2026-01-05T08:07:00.000+08:00",
            Some("2026-01-05T08:11:00.000+08:00")
        )
    );

    let replanned = plan_line(&air, UtcOffset::SINGAPORE, &records[1]);
    assert_eq!(replanned.extra_delay_s, Some(300.0));
    assert_eq!(replanned.original.unwrap().legs.map(|l| l.len()), Some(2));

    let stranded = plan_line(&air, UtcOffset::SINGAPORE, &records[2]);
    assert!(stranded.path.is_none() && stranded.legs.is_none());
    let committed = stranded.committed_legs.unwrap();
    assert_eq!(committed.len(), 2);
    assert_eq!(
        committed[1].landing, None,
        "the committed part does not land"
    );

    let single = plan_line(&air, UtcOffset::SINGAPORE, &records[3]);
    assert!(single.legs.is_none());
    assert_eq!(
        FateKind::parse(&stranded.status),
        Some(FateKind::Contingency)
    );
}

/// The airspace of `air.geojson` at two layers under the semicircular rule: eastward at
/// layer 1, westward at layer 2 (docs/reference.md#layered-airspace).
fn layered_air() -> Airspace {
    let layers = muse_model::Layers {
        count: 2,
        heading_rule: muse_model::HeadingRule::Sectors,
        ..muse_model::Layers::default()
    };
    air().layered(&layers).unwrap()
}

/// A trip from `takeoff` (seconds after 08:00) through `(node, layer)` pairs, no hovering:
/// 120 s per corridor, 1.829 s per vertical link.
fn layered_trip(air: &Airspace, takeoff: i64, stays: &[(&str, u32)]) -> Plan {
    let mut t = at(takeoff);
    let mut path: Vec<Stay> = Vec::new();
    for &(id, layer) in stays {
        let node = air.at_layer(air.node_id(id).unwrap(), layer).unwrap();
        if let Some(last) = path.last() {
            let same_place = air.flat_node(last.node) == air.flat_node(node);
            t = Instant(t.0 + if same_place { 1_829 } else { 120_000 });
        }
        path.push(Stay {
            node,
            arrive: t,
            depart: t,
        });
    }
    Plan { path }
}

/// The records of `layered.jsonl`: eastward at layer 1; westward at layer 2 (climbing at `C`,
/// descending at `A`), replanned later; westward left in contingency at `W` of layer 2.
fn layered_records(air: &Airspace) -> Vec<PlanRecord> {
    let east = layered_trip(air, 0, &[("A", 1), ("B", 1), ("W", 1), ("C", 1)]);
    let west = |t: i64| {
        layered_trip(
            air,
            t,
            &[("C", 1), ("C", 2), ("W", 2), ("B", 2), ("A", 2), ("A", 1)],
        )
    };
    let stranded = layered_trip(air, 1_800, &[("C", 1), ("C", 2), ("W", 2)]);
    vec![
        record("r1", "A", "C", 0, east),
        changed(
            record("r2", "C", "A", 600, west(600)),
            "Z1",
            300,
            Fate::Replanned(west(900)),
        ),
        changed(
            record("r3", "C", "A", 1_800, west(1_800)),
            "Z2",
            1_900,
            Fate::Contingency(stranded),
        ),
    ]
}

#[test]
fn layered_golden_file() {
    let air = layered_air();
    let records = layered_records(&air);
    let mut text = String::new();
    for r in &records {
        write_plan_line(&mut text, &air, UtcOffset::SINGAPORE, r);
    }
    let golden = std::fs::read_to_string(fixture("layered.jsonl")).unwrap();
    assert_eq!(text, golden);
    assert_eq!(
        read_plans_file(&fixture("layered.jsonl"), &air).unwrap(),
        records
    );
    // Every stay names a flat node and its layer: the path, the original, the committed part.
    let ids = |stays: &[muse_formats::plans::StayLine]| -> Vec<(String, Option<u32>)> {
        stays.iter().map(|s| (s.node.clone(), s.layer)).collect()
    };
    let replanned = plan_line(&air, UtcOffset::SINGAPORE, &records[1]);
    let west: Vec<(String, Option<u32>)> =
        [("C", 1), ("C", 2), ("W", 2), ("B", 2), ("A", 2), ("A", 1)]
            .iter()
            .map(|&(n, k)| (n.to_owned(), Some(k)))
            .collect();
    assert_eq!(ids(replanned.path.as_ref().unwrap()), west);
    assert_eq!(ids(&replanned.original.unwrap().path), west);
    assert_eq!(
        replanned.distance_m,
        Some(3_000.0),
        "climbs fly no corridor"
    );
    let stranded = plan_line(&air, UtcOffset::SINGAPORE, &records[2]);
    assert_eq!(ids(&stranded.committed.unwrap()), west[..3]);
}

#[test]
fn layered_files_are_refused_where_the_layering_differs() {
    let text = std::fs::read_to_string(fixture("layered.jsonl")).unwrap();
    // On the flat airspace.
    let e = muse_formats::plans::read_plans(&text, "layered.jsonl", &air())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "layered.jsonl: line 1: field `path[0].layer`: layer 1, but the airspace is flat (one \
         layer): a stay gives its layer only in a layered airspace (`--layers` 2 or more)"
    );
    // A flat file on the layered airspace.
    let flat = std::fs::read_to_string(fixture("multi_leg.jsonl")).unwrap();
    let e = muse_formats::plans::read_plans(&flat, "multi_leg.jsonl", &layered_air())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "multi_leg.jsonl: line 1: field `path[0].layer`: missing: the airspace has 2 layers, \
         and every stay gives its layer (1 to 2)"
    );
    // A layer beyond the airspace's, in the original plan of line 2.
    let third = text.replacen(r#"{"node":"W","layer":2"#, r#"{"node":"W","layer":3"#, 2);
    let e = muse_formats::plans::read_plans(&third, "layered.jsonl", &layered_air())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "layered.jsonl: line 2: field `original.path[2].layer`: layer 3 is out of range: give \
         1 to 2"
    );
}
