//! End-to-end tests of the `muse` binary: what a user sees for good and bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn muse(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .output()
        .expect("muse runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A fresh folder under the target directory for one test.
fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

#[test]
fn airspace_info_describes_the_default() {
    let o = muse(&["airspace", "info"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("77 (77 stations, 0 waypoints)"), "{out}");
    assert!(out.contains("SG-CBD-DOWNTOWN-CORE"), "{out}");
}

#[test]
fn airspace_build_check_passes_on_the_committed_files() {
    let root = env!("CARGO_MANIFEST_DIR");
    let dir = format!("{root}/scenarios/singapore-77");
    let o = muse(&["airspace", "build", "--check", "--out", &dir]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
}

#[test]
fn airspace_map_writes_an_svg() {
    let dir = scratch_dir("map");
    let out = dir.join("map.svg").display().to_string();
    let o = muse(&["airspace", "map", "--out", &out]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("S077") && svg.contains("Downtown Core"));
}

#[test]
fn bad_airspace_file_is_named_with_feature_and_field() {
    let dir = scratch_dir("bad_airspace");
    let air = write(
        &dir,
        "air.geojson",
        r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.81, 1.3]]}, "properties": {"from": "A", "to": "B"}}]}"#,
    );
    let o = muse(&["airspace", "info", "--airspace", &air]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("air.geojson: feature 1 (`A-B`): field `to`: unknown node id `B`"),
        "{err}"
    );
}

#[test]
fn bad_zone_file_is_named_with_feature_and_field() {
    let dir = scratch_dir("bad_zone");
    let zones = write(
        &dir,
        "z.geojson",
        r#"{"type": "FeatureCollection", "features": [{"type": "Feature",
  "geometry": {"type": "Polygon", "coordinates": [[[103.8, 1.3], [103.81, 1.3], [103.81, 1.31], [103.8, 1.31], [103.8, 1.3]]]},
  "properties": {"identifier": "Z1", "limitedApplicability": [{"schedule": [{"day": ["ANY"], "startTime": "10:00:00", "endTime": "12:00:00"}]}]}}]}"#,
    );
    let o = muse(&["airspace", "info", "--zones", &zones]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("z.geojson: feature 0 (`Z1`)") && err.contains("startTime"),
        "{err}"
    );
    assert!(err.contains("offset"), "{err}");
}

/// Two stations one kilometre apart (two minutes at 30 km/h).
const PAIR: &str = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.81, 1.3]]}, "properties": {"from": "A", "to": "B", "length_m": 1000}}]}"#;

fn plan_line(id: &str, from: &str, to: &str, depart: &str, arrive: &str) -> String {
    format!(
        r#"{{"request":"{id}","status":"planned","reason":null,"origin":"{from}","destination":"{to}","requested_departure":"2026-01-05T{depart}+08:00","takeoff":"2026-01-05T{depart}+08:00","landing":"2026-01-05T{arrive}+08:00","airborne_s":120.0,"free_flow_s":120.0,"air_delay_s":0.0,"ground_delay_s":0.0,"distance_m":1000.0,"path":[{{"node":"{from}","arrive":"2026-01-05T{depart}+08:00","depart":"2026-01-05T{depart}+08:00"}},{{"node":"{to}","arrive":"2026-01-05T{arrive}+08:00","depart":"2026-01-05T{arrive}+08:00"}}]}}"#
    )
}

#[test]
fn verify_names_a_hand_made_conflict() {
    let dir = scratch_dir("verify_conflict");
    let air = write(&dir, "pair.geojson", PAIR);
    // Two drones on the corridor in opposite directions at the same time.
    let plans = format!(
        "{}\n{}\n",
        plan_line("r1", "A", "B", "08:00:00.000", "08:02:00.000"),
        plan_line("r2", "B", "A", "08:00:00.000", "08:02:00.000"),
    );
    let p = write(&dir, "plans.jsonl", &plans);
    let o = muse(&["verify", "--plans", &p, "--airspace", &air]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    let out = stdout(&o);
    assert!(out.contains("FAILED"), "{out}");
    assert!(
        out.contains("r1") && out.contains("r2") && out.contains("A-B"),
        "{out}"
    );
    // Once the first has landed and cleared B by tau = 5 s, the second may go.
    let plans = format!(
        "{}\n{}\n",
        plan_line("r1", "A", "B", "08:00:00.000", "08:02:00.000"),
        plan_line("r2", "B", "A", "08:02:05.000", "08:04:05.000"),
    );
    let p = write(&dir, "plans_ok.jsonl", &plans);
    let o = muse(&["verify", "--plans", &p, "--airspace", &air]);
    assert!(o.status.success(), "{}", stdout(&o));
}

#[test]
fn plan_then_verify_on_the_singapore_default() {
    let dir = scratch_dir("plan_verify");
    let req = dir.join("requests.csv").display().to_string();
    let out = dir.join("out").display().to_string();
    let o = muse(&["demand", "--count", "5000", "--seed", "7", "--out", &req]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = muse(&["plan", "--requests", &req, "--out", &out]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = std::fs::read_to_string(format!("{out}/summary.json")).unwrap();
    assert!(summary.contains("\"requests\": 5000"), "{summary}");
    let o = muse(&["verify", "--plans", &format!("{out}/plans.jsonl")]);
    assert!(o.status.success(), "{}", stdout(&o));
}

#[test]
fn bad_requests_fail_with_line_numbers_and_leave_no_output() {
    let dir = scratch_dir("bad_requests");
    for (body, expected) in [
        (
            "r1,S001,S002,08:00\nr2,S001,S999,08:05\n",
            "line 3: field `destination`: unknown node id `S999`",
        ),
        (
            "r1,S001,S001,08:00\n",
            "line 2: field `destination`: origin and destination are both `S001`",
        ),
        (
            "r1,S001,S002,8am\n",
            "line 2: field `departure`: `8am` is neither",
        ),
    ] {
        let req = write(
            &dir,
            "requests.csv",
            &format!("id,origin,destination,departure\n{body}"),
        );
        let out = dir.join("out");
        let o = muse(&[
            "plan",
            "--requests",
            &req,
            "--out",
            &out.display().to_string(),
        ]);
        assert_eq!(o.status.code(), Some(2));
        let err = stderr(&o);
        assert!(
            err.contains("requests.csv: ") && err.contains(expected),
            "{err}"
        );
        assert!(!out.exists(), "no output folder after a failed run");
    }
}

/// `summary.json` without its wall-clock timing, which is the one part that may differ.
fn summary_without_timing(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v.as_object_mut().unwrap().remove("planner_time");
    v.to_string()
}

#[test]
fn simulate_is_deterministic() {
    let dir = scratch_dir("determinism");
    let (a, b) = (dir.join("a"), dir.join("b"));
    for out in [&a, &b] {
        let o = muse(&[
            "simulate",
            "--count",
            "3000",
            "--seed",
            "11",
            "--max-ground-delay-s",
            "300",
            "--out",
            &out.display().to_string(),
        ]);
        assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
        assert!(stdout(&o).contains("verified      OK"), "{}", stdout(&o));
    }
    for file in ["requests.csv", "plans.jsonl", "flights.geojson", "map.svg"] {
        let (x, y) = (
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
        );
        assert!(
            !x.is_empty() && x == y,
            "{file} differs between two identical runs"
        );
    }
    assert_eq!(
        summary_without_timing(&a.join("summary.json")),
        summary_without_timing(&b.join("summary.json"))
    );
    // A different seed gives different demand.
    let c = dir.join("c");
    let o = muse(&[
        "simulate",
        "--count",
        "3000",
        "--seed",
        "12",
        "--out",
        &c.display().to_string(),
    ]);
    assert!(o.status.success());
    assert_ne!(
        std::fs::read(a.join("requests.csv")).unwrap(),
        std::fs::read(c.join("requests.csv")).unwrap()
    );
}

#[test]
fn sweep_is_deterministic_and_compares_variants() {
    let dir = scratch_dir("sweep");
    let mut tables = Vec::new();
    for name in ["a", "b"] {
        let out = dir.join(name);
        let o = muse(&[
            "sweep",
            "--counts",
            "300,600",
            "--reps",
            "3",
            "--vary",
            "zones",
            "--vary",
            "edge-rule",
            "--vary",
            "ground-delay",
            "--out",
            &out.display().to_string(),
        ]);
        assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
        for file in [
            "sweep_summary.csv",
            "sweep_runtime.svg",
            "sweep_success.svg",
            "sweep_air_delay.svg",
        ] {
            assert!(out.join(file).exists(), "{file}");
        }
        // Drop the timing column (planner_ms) before comparing.
        let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let timing = header.iter().position(|h| *h == "planner_ms").unwrap();
        let rows: Vec<String> = csv
            .lines()
            .map(|l| {
                let mut cells: Vec<&str> = l.split(',').collect();
                cells.remove(timing);
                cells.join(",")
            })
            .collect();
        assert_eq!(
            rows.len(),
            1 + 8 * 2 * 3,
            "8 variants × 2 counts × 3 repetitions"
        );
        tables.push(rows);
    }
    assert_eq!(tables[0], tables[1]);
    let variants: std::collections::BTreeSet<&str> = tables[0][1..]
        .iter()
        .map(|r| r.split(',').next().unwrap())
        .collect();
    assert!(
        variants.contains("CBD zone / exclusive / G_max 0"),
        "{variants:?}"
    );
    assert!(
        variants.contains("no zone / headway 5 s / G_max 10 min"),
        "{variants:?}"
    );
}

#[test]
fn argument_errors_are_clear() {
    for (args, expected) in [
        (vec!["sweep", "--counts", "10:5:1"], "--counts `10:5:1`"),
        (vec!["sweep", "--reps", "0"], "--reps must be at least 1"),
        (
            vec!["sweep", "--vary", "zones", "--zones", "none"],
            "--vary zones needs zones",
        ),
        (
            vec!["simulate", "--from", "20:00", "--to", "08:00"],
            "--to 08:00 must be after --from 20:00",
        ),
        (
            vec!["simulate", "--from", "25:00"],
            "--from `25:00` is not a local time",
        ),
        (
            vec!["simulate", "--max-flight-min=-1"],
            "--max-flight-min -1 must be a number > 0",
        ),
        (
            vec!["simulate", "--speed-kmh", "0"],
            "speed 0 km/h must be a finite number > 0",
        ),
        (
            vec!["plan", "--requests", "x.csv", "--headway-s", "3"],
            "--headway-s applies only with --edge-rule headway",
        ),
        (
            vec!["demand", "--zones", "none", "--zones", "z.json"],
            "`--zones none` cannot be combined",
        ),
    ] {
        let o = muse(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(expected), "{args:?}: {}", stderr(&o));
    }
    // Usage errors come from clap, also with exit code 2.
    let o = muse(&["simulate", "--edge-rule", "sometimes"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("invalid value 'sometimes'"),
        "{}",
        stderr(&o)
    );
}
