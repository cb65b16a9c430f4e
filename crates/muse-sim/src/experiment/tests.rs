//! The engine with a kind of its own (numbering, shards, progress), and the paper's sweep run
//! whole and in shards.

use std::sync::Mutex;

use muse_model::{Airspace, FlightParams, Instant, Millis};
use serde::{Deserialize, Serialize};

use super::*;
use crate::demand::{BookingLead, DemandError, OdRule};

/// A record of [`Echo`]: which case and day ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Echoed {
    case: String,
    count: usize,
    rep: usize,
    seed: u64,
    requests: usize,
}

/// A kind that plans nothing: each run echoes its case and day.
struct Echo {
    cases: Vec<String>,
    shared: Option<Airspace>,
    parallel: bool,
}

impl Kind for Echo {
    type Record = Echoed;
    type Error = DemandError;

    fn cases(&self) -> Vec<String> {
        self.cases.clone()
    }

    fn identity(&self) -> String {
        format!("{:?}", self.cases)
    }

    fn shared_demand(&self) -> Option<&Airspace> {
        self.shared.as_ref()
    }

    fn parallel(&self) -> bool {
        self.parallel
    }

    fn run(&self, _: &Grid, case: usize, day: &Day<'_>) -> Result<Echoed, DemandError> {
        Ok(Echoed {
            case: self.cases[case].clone(),
            count: day.count,
            rep: day.rep,
            seed: day.seed,
            requests: day.requests.len(),
        })
    }

    fn runs_file(&self) -> &'static str {
        "echo.csv"
    }

    fn columns<'r>(&self, _: &'r [Echoed]) -> Vec<Column<'r, Echoed>> {
        vec![
            Column::new("case", |r: &Echoed| r.case.clone()),
            Column::new("seed", |r: &Echoed| r.seed.to_string()),
        ]
    }

    fn summary(&self) -> Option<SummarySpec<Echoed>> {
        Some(SummarySpec {
            file: "echo_summary.csv",
            group: |r| (r.case.clone(), r.count),
            head: vec![
                Column::new("case", |g: &Group<Echoed>| g.first.case.clone()),
                Column::new("runs", |g: &Group<Echoed>| g.runs.to_string()),
            ],
            metrics: vec![Metric {
                name: "seed",
                value: |r| Some(r.seed as f64),
            }],
        })
    }

    fn measured(&self, _: &str) -> bool {
        false
    }

    fn table(&self, _: &Grid, records: &[Echoed], groups: &[Group<Echoed>]) -> String {
        format!("{} runs, {} groups", records.len(), groups.len())
    }

    fn plots(&self, _: &Grid, _: &[Echoed], _: &[Group<Echoed>]) -> Vec<Plot> {
        Vec::new()
    }
}

fn grid(counts: Vec<usize>, reps: usize, seeds: Seeds) -> Grid {
    Grid {
        counts,
        reps,
        seeds,
        start: Instant(0),
        end: Instant(3_600_000),
        od: OdRule::Uniform,
        booking_lead: BookingLead::NONE,
        params: FlightParams::default(),
    }
}

fn echo(cases: &[&str], shared: Option<Airspace>, parallel: bool) -> Echo {
    Echo {
        cases: cases.iter().map(|&c| c.to_owned()).collect(),
        shared,
        parallel,
    }
}

#[test]
fn runs_are_numbered_case_then_count_then_repetition() {
    let exp = Experiment {
        grid: grid(vec![10, 20], 2, Seeds::PerDay(5)),
        kind: echo(&["a", "b"], None, false),
    };
    assert_eq!((exp.runs(), exp.total_requests()), (8, 120));
    let started = Mutex::new(Vec::new());
    let runs = exp
        .run(Shard::WHOLE, &|p| {
            if let Progress::Started { run, case, count } = p {
                started.lock().unwrap().push((run, case, count));
            }
        })
        .unwrap();
    let seen: Vec<(usize, &str, usize, usize, u64)> = runs
        .iter()
        .map(|(n, r)| (*n, r.case.as_str(), r.count, r.rep, r.seed))
        .collect();
    assert_eq!(
        seen,
        [
            (0, "a", 10, 0, 5),
            (1, "a", 10, 1, 6),
            (2, "a", 20, 0, 7),
            (3, "a", 20, 1, 8),
            (4, "b", 10, 0, 5),
            (5, "b", 10, 1, 6),
            (6, "b", 20, 0, 7),
            (7, "b", 20, 1, 8),
        ]
    );
    // One at a time, in order, when the kind asks for it.
    let started = started.into_inner().unwrap();
    assert_eq!(started.len(), 8);
    assert_eq!(started[5], (5, 1, 10));
    assert!(
        runs.iter().all(|(_, r)| r.requests == 0),
        "no shared demand"
    );

    let shard = exp.run(Shard { index: 1, of: 3 }, &|_| {}).unwrap();
    assert_eq!(shard.iter().map(|(n, _)| *n).collect::<Vec<_>>(), [1, 4, 7]);

    let results = exp
        .results(&runs.into_iter().map(|(_, r)| r).collect::<Vec<_>>())
        .unwrap();
    assert_eq!(results.compared, "echo_summary.csv");
    assert_eq!(results.files[0].1.lines().nth(1), Some("a,5"));
    assert_eq!(
        results.files[1].1,
        "case,runs,seed_mean,seed_ci95_low,seed_ci95_high\n\
         a,2,5.500000,-0.853000,11.853000\na,2,7.500000,1.147000,13.853000\n\
         b,2,5.500000,-0.853000,11.853000\nb,2,7.500000,1.147000,13.853000\n"
    );
    assert_eq!(results.table, "8 runs, 4 groups");
}

#[test]
fn shared_demand_is_the_same_in_every_case_and_one_seed_may_serve_every_day() {
    let exp = Experiment {
        grid: grid(vec![3, 7], 1, Seeds::Same(42)),
        kind: echo(
            &["a", "b", "c"],
            Some(Airspace::line(&[1_000.0, 1_000.0])),
            true,
        ),
    };
    let runs = exp.run(Shard::WHOLE, &|_| {}).unwrap();
    assert_eq!(runs.len(), 6);
    assert!(
        runs.iter()
            .all(|(_, r)| r.seed == 42 && r.requests == r.count)
    );
    assert_eq!(exp.grid.seed_range(), (42, 42));
    let other = Experiment {
        grid: grid(vec![3, 7], 1, Seeds::Same(43)),
        kind: echo(&["a", "b", "c"], None, true),
    };
    assert_ne!(exp.identity(), other.identity());
}

#[test]
fn a_demand_error_stops_the_run() {
    let mut g = grid(vec![5], 1, Seeds::PerDay(1));
    g.end = g.start;
    let exp = Experiment {
        grid: g,
        kind: echo(&["a"], Some(Airspace::line(&[1_000.0])), true),
    };
    assert!(matches!(
        exp.run(Shard::WHOLE, &|_| {}),
        Err(DemandError::EmptyWindow)
    ));
}

/// The paper's sweep on the embedded default: with and without the CBD zone, 2 counts × 3
/// repetitions.
fn paper(s: &muse_scenario::Scenario) -> Experiment<sweep::Sweep<'_>> {
    let at = |h: i64| Instant::at_local(s.date, Millis::from_mins(h * 60), s.offset);
    let grid = Grid {
        counts: vec![40, 120],
        reps: 3,
        seeds: Seeds::PerDay(7),
        start: at(8),
        end: at(20),
        od: OdRule::Uniform,
        booking_lead: BookingLead::NONE,
        params: FlightParams::default(),
    };
    let base = sweep::levers::Base {
        params: grid.params,
        zones: &s.zones,
        zone_label: "zone, \"CBD\"",
    };
    let variants = sweep::levers::variants(&base, &["zones"], &[]).unwrap();
    let airspaces = Box::leak(Box::new(
        sweep::Airspaces::new(&s.airspace, &variants).unwrap(),
    ));
    Experiment {
        kind: sweep::Sweep::new(airspaces, &grid, variants, None).unwrap(),
        grid,
    }
}

/// Without the timing, which no two runs share.
fn untimed(mut r: sweep::RunRecord) -> sweep::RunRecord {
    r.planner_ms = 0.0;
    r
}

#[test]
fn a_sweep_in_three_shards_merges_into_the_same_runs() {
    let s = muse_scenario::singapore_77();
    let exp = paper(&s);
    let whole: Vec<sweep::RunRecord> = exp
        .run(Shard::WHOLE, &|_| {})
        .unwrap()
        .into_iter()
        .map(|(_, r)| r)
        .collect();
    assert_eq!(whole.len(), 12);
    let shards: Vec<(String, ShardFile<sweep::RunRecord>)> = (0..3)
        .map(|index| {
            let shard = Shard { index, of: 3 };
            let runs = exp.run(shard, &|_| {}).unwrap();
            let file = ShardFile::new(exp.identity(), shard, exp.runs(), vec![], None, runs);
            (format!("shard {shard}"), file)
        })
        .collect();
    let merged = merge(&shards).unwrap();
    assert_eq!(
        merged.into_iter().map(untimed).collect::<Vec<_>>(),
        whole.iter().cloned().map(untimed).collect::<Vec<_>>()
    );

    // The files: a quoted variant name, the columns of the reference.
    let results = exp.results(&whole).unwrap();
    let names: Vec<&str> = results.files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "sweep.csv",
            "sweep_summary.csv",
            "sweep_runtime.svg",
            "sweep_success.svg",
            "sweep_air_delay.svg"
        ]
    );
    let runs = &results.files[0].1;
    assert!(
        runs.starts_with("variant,count,rep,seed,planned,out_of_range,unreachable,no_feasible_plan,success_rate,mean_air_delay_s,mean_ground_delay_s,planner_ms,expanded_per_request,legs_per_trip,booking_lead_min_from,booking_lead_min_to\n\"zone, \"\"CBD\"\"\",40,0,7,"),
        "{runs}"
    );
    assert!(runs.lines().nth(7).unwrap().starts_with("no zone,40,0,7,"));
    assert!(
        runs.lines()
            .all(|l| l.ends_with(",0,0") || l.starts_with("variant"))
    );
    assert!(
        results
            .table
            .starts_with("variant                        count")
    );

    let mut other = paper(&s);
    other.grid.reps = 4;
    assert_ne!(exp.identity(), other.identity());
}
