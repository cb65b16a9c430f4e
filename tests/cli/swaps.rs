//! Multi-leg trips (docs/reference.md#multi-leg-trips) end to end: `muse simulate`, `verify`,
//! `sweep` and `serve` with `--battery-swap-s`, on the embedded Singapore default.

use serde_json::{Value, json};

use crate::run::{muse, read_json, said};
use crate::support::{scratch_dir, start};

#[test]
fn simulate_with_swaps_plans_out_of_range_requests_and_verify_checks_the_legs() {
    let dir = scratch_dir("swaps-simulate");
    let out = dir.display().to_string();
    let o = muse(&["simulate", "--count", "600", "--out", &out]);
    assert!(o.status.success(), "{}", said(&o));
    let single = read_json(&dir.join("summary.json"));
    let out_of_range = single["rejected_by_reason"]["out_of_range"]
        .as_u64()
        .unwrap();
    assert!(out_of_range > 250, "{single}");
    assert!(
        single.get("legs").is_none(),
        "no legs section without swaps"
    );

    let o = muse(&[
        "simulate",
        "--count",
        "600",
        "--battery-swap-s",
        "300",
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(said(&o).contains("legs          mean"), "{}", said(&o));
    let s = read_json(&dir.join("summary.json"));
    assert_eq!(s["rejected_by_reason"]["out_of_range"], 0, "{s}");
    let planned = s["planned"].as_u64().unwrap();
    let before = single["planned"].as_u64().unwrap();
    assert!(
        planned >= before + out_of_range / 2,
        "{planned} vs {before} + {out_of_range}"
    );
    assert_eq!(s["parameters"]["battery_swap_s"], 300.0);
    assert!(s["legs"]["swaps"].as_u64().unwrap() > 0, "{s}");
    assert!(s["legs"]["per_trip_max"].as_u64().unwrap() >= 2, "{s}");

    // Every multi-leg line lists its legs, and they chain.
    let plans = std::fs::read_to_string(dir.join("plans.jsonl")).unwrap();
    let mut multi = 0;
    for line in plans.lines() {
        let v: Value = serde_json::from_str(line).unwrap();
        let Some(legs) = v["legs"].as_array() else {
            continue;
        };
        multi += 1;
        assert!(legs.len() >= 2);
        assert_eq!(legs[0]["takeoff"], v["takeoff"]);
        assert_eq!(legs[legs.len() - 1]["landing"], v["landing"]);
        for pair in legs.windows(2) {
            let landed = pair[0]["path"].as_array().unwrap().last().unwrap().clone();
            let next = pair[1]["path"][0].clone();
            assert_eq!(landed["node"], next["node"], "{line}");
        }
    }
    assert!(multi > 100, "{multi} multi-leg plans");
    // flights.geojson draws each leg.
    let flights = read_json(&dir.join("flights.geojson"));
    let with_leg = flights["features"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["properties"]["leg"] == 2)
        .count();
    assert!(with_leg > 100, "{with_leg} second legs drawn");

    let p = dir.join("plans.jsonl").display().to_string();
    let o = muse(&["verify", "--plans", &p, "--battery-swap-s", "300"]);
    assert!(o.status.success(), "{}", said(&o));
    // The summary beside the plans gives the swaps: no option needed.
    let o = muse(&["verify", "--plans", &p]);
    assert!(o.status.success(), "{}", said(&o));
    // Without swaps (the default, with no summary beside the plans) the same plans break the
    // rules, and the verifier says which.
    let alone = dir.join("alone");
    std::fs::create_dir_all(&alone).unwrap();
    std::fs::copy(dir.join("plans.jsonl"), alone.join("plans.jsonl")).unwrap();
    let o = muse(&[
        "verify",
        "--plans",
        &alone.join("plans.jsonl").display().to_string(),
    ]);
    assert!(!o.status.success());
    assert!(said(&o).contains("battery swaps are off"), "{}", said(&o));
    // A longer swap time than the plans kept is caught too.
    let o = muse(&["verify", "--plans", &p, "--battery-swap-s", "301"]);
    assert!(!o.status.success());
    assert!(said(&o).contains("swap"), "{}", said(&o));
}

#[test]
fn a_leg_limit_bounds_every_trip_and_needs_swaps() {
    let dir = scratch_dir("swaps-max-legs");
    let out = dir.display().to_string();
    let o = muse(&[
        "simulate",
        "--count",
        "300",
        "--battery-swap-s",
        "120",
        "--max-legs",
        "2",
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let s = read_json(&dir.join("summary.json"));
    assert_eq!(s["legs"]["per_trip_max"], 2, "{s}");
    assert_eq!(s["parameters"]["max_legs"], 2, "{s}");
    assert!(
        s["rejected_by_reason"]["out_of_range"].as_u64().unwrap() > 0,
        "{s}"
    );
    let p = dir.join("plans.jsonl").display().to_string();
    let o = muse(&[
        "verify",
        "--plans",
        &p,
        "--battery-swap-s",
        "120",
        "--max-legs",
        "1",
    ]);
    assert!(!o.status.success());
    assert!(
        said(&o).contains("more than the K = 1 allowed"),
        "{}",
        said(&o)
    );

    let o = muse(&["simulate", "--max-legs", "2", "--out", &out]);
    assert_eq!(o.status.code(), Some(2), "a usage error: {}", said(&o));
    assert!(said(&o).contains("--battery-swap-s"), "{}", said(&o));
    let o = muse(&["simulate", "--battery-swap-s=-5", "--out", &out]);
    assert!(!o.status.success());
    assert!(said(&o).contains("--battery-swap-s"), "{}", said(&o));
}

#[test]
fn sweep_compares_single_legs_with_swaps_on_the_same_seeds() {
    let dir = scratch_dir("swaps-sweep");
    let out = dir.display().to_string();
    let o = muse(&[
        "sweep",
        "--vary",
        "battery-swap",
        "--swap-min",
        "2,10",
        "--counts",
        "200,400",
        "--reps",
        "2",
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let summary = std::fs::read_to_string(dir.join("sweep_summary.csv")).unwrap();
    assert!(
        summary
            .lines()
            .next()
            .unwrap()
            .contains("legs_per_trip_mean")
    );
    let rows: Vec<&str> = summary.lines().skip(1).collect();
    assert_eq!(rows.len(), 6, "{summary}");
    for name in ["no swaps", "swaps 2 min", "swaps 10 min"] {
        assert!(
            rows.iter().any(|r| r.starts_with(name)),
            "{name}: {summary}"
        );
    }
    let runs = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    // Same seeds for every variant.
    let seeds = |v: &str| -> Vec<String> {
        runs.lines()
            .filter(|l| l.starts_with(v))
            .map(|l| l.split(',').nth(3).unwrap().to_owned())
            .collect()
    };
    assert_eq!(seeds("no swaps"), seeds("swaps 2 min"));
    for plot in [
        "sweep_success.svg",
        "sweep_air_delay.svg",
        "sweep_runtime.svg",
    ] {
        assert!(dir.join(plot).exists(), "{plot}");
    }
    let o = muse(&[
        "sweep",
        "--swap-min",
        "5",
        "--counts",
        "10",
        "--reps",
        "1",
        "--out",
        &out,
    ]);
    assert!(!o.status.success());
    assert!(said(&o).contains("--swap-min applies only with --vary battery-swap"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_service_plans_multi_leg_flights_and_reports_its_swap_time() {
    let data = scratch_dir("swaps-serve");
    let server = start(
        &data,
        &[
            "--battery-swap-s",
            "300",
            "--clock",
            "2026-01-05T08:00:00.000+08:00",
        ],
    );
    let http = reqwest::Client::new();
    let health: Value = http
        .get(format!("{}/healthz", server.base))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(health["parameters"]["battery_swap_s"], 300.0, "{health}");
    // S001 to S077 are at the island's far ends: beyond one battery.
    let body = json!({"id": "far", "origin": "S001", "destination": "S077",
                      "departure": "2026-01-05T09:00:00.000+08:00"});
    let r = http
        .post(format!("{}/v1/flights", server.base))
        .header("content-type", "application/json")
        .body(body.to_string())
        .send()
        .await
        .unwrap();
    assert_eq!(r.status().as_u16(), 201);
    let answer: Value = r.json().await.unwrap();
    let legs = answer["legs"]
        .as_array()
        .expect("a multi-leg plan lists its legs");
    assert!(legs.len() >= 2, "{answer}");
    // A restart on the same data holds the same plan.
    server.kill();
    let server = start(
        &data,
        &[
            "--battery-swap-s",
            "300",
            "--clock",
            "2026-01-05T08:00:00.000+08:00",
        ],
    );
    let again: Value = http
        .get(format!("{}/v1/flights/far", server.base))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(again["legs"], answer["legs"], "{again}");
    server.kill();
}
