use muse_model::{Airspace, FlightParams, Instant, Millis, Period, Request, UtcOffset, Zone};

use super::*;
use crate::demand::{BookingLead, OdRule};
use crate::experiment::{Experiment, Grid, Kind, Progress, Seeds, Shard, summarize};

fn min(m: i64) -> Instant {
    Instant(m * 60_000)
}

/// `A - B - C - D`, 1 km apart: two minutes per corridor at 30 km/h.
fn line() -> Airspace {
    Airspace::line(&[1_000.0, 1_000.0, 1_000.0])
}

/// Closes station `B` from 10:00 to 10:30 (minutes since the epoch).
fn zone_b() -> Zone {
    Zone {
        id: "ZB".into(),
        name: String::new(),
        restriction: String::new(),
        area: None,
        node_ids: vec!["B".into()],
        edge_ids: vec![],
        announced: None,
        withdrawn: None,
        vertical: muse_model::VerticalLimits::WHOLE_SKY,
        periods: vec![Period {
            start: Some(min(600)),
            end: Some(min(630)),
            daily: vec![],
        }],
    }
}

fn day() -> ScenarioDay {
    ScenarioDay {
        start: min(0),
        end: min(1_440),
        offset: UtcOffset(0),
    }
}

fn request(id: &str, from: u32, to: u32, departure: i64, submitted: i64) -> Request {
    Request {
        submitted: min(submitted),
        ..muse_model::testing::request(id, from, to, departure * 60_000)
    }
}

fn announced(lead_min: i64) -> LeadCase {
    LeadCase::Announced {
        lead: Millis::from_mins(lead_min),
    }
}

#[test]
fn a_longer_lead_never_cancels_more_and_frees_the_corridor_for_others() {
    // No ground delay, 20 minutes of battery: a flight through B that departs between 10:00
    // and 10:30 cannot wait out the zone (it would land after 10:34, over 20 minutes after a
    // take-off before 10:14), so once the zone is known it is rejected, and if it was booked
    // before the announcement it is cancelled.
    // - `y` A→C departs 10:08, booked 08:08: it lands at C at 10:12, where
    // - `z` C→D departs 10:12, booked 08:30: rejected while `y` holds C;
    // - `w` A→B departs 09:40, booked 09:00: lands before the zone, never affected;
    // - `x` A→C departs 10:05, booked 09:05.
    let air = line();
    let world = LeadWorld::new(
        &air,
        FlightParams::default(),
        &[],
        &[zone_b()],
        day(),
        (min(-1_440), min(2_880)),
    )
    .unwrap();
    assert_eq!(
        world.first_windows().collect::<Vec<_>>(),
        [("ZB", min(600))]
    );
    let mut requests = vec![
        request("y", 0, 2, 608, 488),
        request("z", 2, 3, 612, 510),
        request("w", 0, 1, 580, 540),
        request("x", 0, 2, 605, 545),
    ];
    muse_model::request::sort_for_planning(&mut requests);
    let measure = |case| {
        let run = world.run(case, &requests).unwrap();
        let r = LeadRecord::of(case, 0, 1, BookingLead::NONE, &run);
        (r.planned_at_booking, r.affected, r.cancelled, r.delivered)
    };
    // (planned at booking, affected, cancelled, delivered)
    let expected = [
        // Announced at 10:00, 09:45, 09:30: `x` and `y` were booked without it; both cancelled.
        (announced(0), (3, 2, 2, 1)),
        (announced(15), (3, 2, 2, 1)),
        (announced(30), (3, 2, 2, 1)),
        // At 09:00: `x` (booked 09:05) knows it and is rejected; `y` is still cancelled.
        (announced(60), (2, 1, 1, 1)),
        // At 08:00, before every booking: `y` is rejected, so `z` gets C and is delivered.
        (announced(120), (2, 0, 0, 2)),
        (LeadCase::Known, (2, 0, 0, 2)),
        // Without the zone, `y`, `w` and `x` fly and `z` is rejected.
        (LeadCase::NoZone, (3, 0, 0, 3)),
    ];
    for (case, want) in expected {
        assert_eq!(measure(case), want, "{case:?}");
    }
    let cancelled: Vec<usize> = expected[..5].iter().map(|(_, w)| w.2).collect();
    assert!(cancelled.windows(2).all(|w| w[1] <= w[0]), "{cancelled:?}");
}

/// Three leads, known and none × 60 requests × 3 repetitions on [`line`], zone `ZB` announced.
fn small_sweep() -> (Grid, LeadSpec) {
    let grid = Grid {
        counts: vec![60],
        reps: 3,
        seeds: Seeds::PerDay(11),
        start: min(480),
        end: min(720),
        od: OdRule::Uniform,
        booking_lead: BookingLead::new(Millis::ZERO, Millis::from_mins(120)).unwrap(),
        params: FlightParams::default(),
    };
    let spec = LeadSpec {
        leads: vec![
            Millis::ZERO,
            Millis::from_mins(30),
            Millis::from_mins(1_440),
        ],
        base_zones: vec![],
        announce: vec![zone_b()],
        day: day(),
        no_zone_reference: true,
    };
    (grid, spec)
}

/// The records of a whole experiment, in run order.
fn run_all<K: Kind>(exp: &Experiment<K>) -> Vec<K::Record> {
    exp.run(Shard::WHOLE, &|_| {})
        .unwrap()
        .into_iter()
        .map(|(_, r)| r)
        .collect()
}

#[test]
fn every_case_plans_the_same_seeded_demand() {
    let (grid, spec) = small_sweep();
    let air = line();
    let lead = Lead::new(&air, &grid, spec, "booked".into()).unwrap();
    let exp = Experiment { grid, kind: lead };
    let ticks = std::sync::atomic::AtomicUsize::new(0);
    let records: Vec<LeadRecord> = exp
        .run(Shard::WHOLE, &|p| {
            if let Progress::Finished { .. } = p {
                ticks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
        })
        .unwrap()
        .into_iter()
        .map(|(_, r)| r)
        .collect();
    assert_eq!(records.len(), exp.runs());
    assert_eq!(records.len(), 5 * 3);
    assert_eq!(ticks.into_inner(), records.len());
    assert_eq!(
        records.iter().map(|r| r.case).collect::<Vec<_>>()[..4],
        [announced(0), announced(0), announced(0), announced(30)]
    );
    for rep in 0..3 {
        let runs: Vec<&LeadRecord> = records.iter().filter(|r| r.rep == rep).collect();
        assert_eq!(runs.len(), 5);
        assert!(
            runs.iter()
                .all(|r| r.seed == 11 + rep as u64 && r.count == 60)
        );
        // A day's warning is before every booking: the day is planned as if the zone were
        // known from the start.
        let by = |case| *runs.iter().find(|r| r.case == case).unwrap();
        let (long, known) = (by(announced(1_440)), by(LeadCase::Known));
        assert_eq!(
            (long.planned_at_booking, long.delivered, long.affected),
            (known.planned_at_booking, known.delivered, 0)
        );
    }
    // The zone matters: at no warning some booked flights are hit.
    let hit: usize = records
        .iter()
        .filter(|r| r.case == announced(0))
        .map(|r| r.affected)
        .sum();
    assert!(hit > 0);
    let groups = summarize(&records, &summary());
    assert_eq!(groups.len(), 5);
    assert!(groups.iter().all(|g| g.runs == 3));
}

#[test]
fn input_errors_name_the_zone() {
    let air = line();
    let range = (min(-1_440), min(2_880));
    let params = FlightParams::default();
    let later = ScenarioDay {
        start: min(1_440),
        end: min(2_880),
        offset: UtcOffset(0),
    };
    let err = LeadWorld::new(&air, params, &[], &[zone_b()], later, range).unwrap_err();
    assert_eq!(
        err.to_string(),
        "zone `ZB` has no active window starting between 1970-01-02T00:00:00.000+00:00 and \
         1970-01-03T00:00:00.000+00:00, so it has no first window to announce ahead of"
    );
    let err = LeadWorld::new(&air, params, &[], &[zone_b(), zone_b()], day(), range).unwrap_err();
    assert_eq!(err.to_string(), "a zone `ZB` is already announced");
    let err = LeadWorld::new(&air, params, &[zone_b()], &[], day(), range).unwrap_err();
    assert!(matches!(err, LeadError::NothingToAnnounce));
}

#[test]
fn a_negative_lead_is_refused() {
    let (grid, mut spec) = small_sweep();
    spec.leads.push(Millis(-1));
    let err = Lead::new(&line(), &grid, spec, String::new()).unwrap_err();
    assert_eq!(err.to_string(), "lead -0.001 s: a lead must be >= 0");
}

#[test]
fn a_lead_sweep_in_three_shards_merges_into_the_same_runs() {
    use crate::experiment::{ShardFile, merge};
    let (grid, spec) = small_sweep();
    let air = line();
    let exp = Experiment {
        kind: Lead::new(&air, &grid, spec, String::new()).unwrap(),
        grid,
    };
    let untimed = |mut r: LeadRecord| {
        r.planner_ms = 0.0;
        r
    };
    let whole = run_all(&exp);
    let shards: Vec<(String, ShardFile<LeadRecord>)> = (0..3)
        .map(|index| {
            let shard = Shard { index, of: 3 };
            let runs = exp.run(shard, &|_| {}).unwrap();
            let file = ShardFile::new(exp.identity(), shard, exp.runs(), vec![], None, runs);
            // Through the file format and back.
            let text = serde_json::to_string(&file).unwrap();
            (format!("{shard}"), ShardFile::read(&text, "shard").unwrap())
        })
        .collect();
    let merged = merge(&shards).unwrap();
    assert_eq!(merged.len(), exp.runs());
    assert_eq!(
        merged.into_iter().map(untimed).collect::<Vec<_>>(),
        whole.into_iter().map(untimed).collect::<Vec<_>>()
    );
}
