//! End-to-end tests of the `muse` binary: what a user sees for good and bad input.

use std::path::{Path, PathBuf};

use crate::run::{muse, stderr, stdout};

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
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8089, 1.3]}, "properties": {"id": "B", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.8089, 1.3]]}, "properties": {"from": "A", "to": "B", "length_m": 1000}}]}"#;

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

/// A file of `crates/muse-formats/testdata/service`: a real `muse serve` session's listing
/// saved one flight a line, its airspace and its zones (the folder's README tells the session).
fn service_testdata(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates/muse-formats/testdata/service")
        .join(name)
        .display()
        .to_string()
}

#[test]
fn verify_reads_every_line_of_a_service_listing() {
    let dir = scratch_dir("verify_service_listing");
    let (air, zones) = (
        service_testdata("line.geojson"),
        service_testdata("zones.geojson"),
    );
    let verify = |plans: &str| {
        muse(&[
            "verify",
            "--plans",
            plans,
            "--airspace",
            &air,
            "--zones",
            &zones,
        ])
    };
    let o = verify(&service_testdata("flights.jsonl"));
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert_eq!(
        stdout(&o),
        "OK: 10 lines read (1 planned, 1 replanned, 1 diverted, 1 contingency, 2 cancelled by a \
         zone, 2 cancelled by their operator, 2 rejected); 4 flights checked, every rule holds \
         (exclusive; 2 zone(s), 2 announced during the day; 6 flights changed by announcements)\n\
         metric separation: no two flights come within 5000 m of each other; pairs closer than \
         10 m: 0, 20 m: 0, 30 m: 0 (vertical separation 9.144 m)\n"
    );

    let listing = std::fs::read_to_string(service_testdata("flights.jsonl")).unwrap();
    let edited = |request: &str, edit: &dyn Fn(&mut serde_json::Map<String, serde_json::Value>)| {
        let mut text = String::new();
        for l in listing.lines() {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            if v["request"] == request {
                edit(v.as_object_mut().unwrap());
            }
            text.push_str(&v.to_string());
            text.push('\n');
        }
        write(&dir, &format!("{request}.jsonl"), &text)
    };
    // The final plan is what is checked: e1 keeping its original plan breaks ZC.
    let kept = edited("e1", &|f| {
        let original = f["original"]["path"].clone();
        f.insert("path".into(), original);
        f.insert("status".into(), "planned".into());
        for field in ["original", "changes", "extra_delay_s"] {
            f.remove(field);
        }
    });
    let o = verify(&kept);
    assert_eq!(o.status.code(), Some(1), "{}{}", stdout(&o), stderr(&o));
    let out = stdout(&o);
    assert!(
        out.starts_with("FAILED: ")
            && out.contains("among the 4 flights checked (10 lines read")
            && out.contains("ZC")
            && out.contains("e1"),
        "{out}"
    );

    // Malformed lines are named: file, line and field.
    for (request, edit, expected) in [
        (
            "c1",
            &(|f: &mut serde_json::Map<String, serde_json::Value>| {
                f.insert("path".into(), serde_json::json!([]));
            }) as &dyn Fn(&mut serde_json::Map<String, serde_json::Value>),
            "c1.jsonl: line 8: field `path`: a flight cancelled by its operator flies nothing",
        ),
        (
            "a3",
            &|f| {
                f.insert("pilot".into(), "Ann".into());
            },
            "a3.jsonl: line 7: field `pilot`: not a plan record: unknown field `pilot`",
        ),
        (
            "a3",
            &|f| {
                f.insert("cancelled_at".into(), f["requested_departure"].clone());
            },
            "a3.jsonl: line 7: field `cancelled_at`: only a flight cancelled by its operator",
        ),
        (
            "b1",
            &|f| {
                f.insert("cancelled_at".into(), "2026-11-25T23:59:60+08:00".into());
            },
            "b1.jsonl: line 4: field `cancelled_at`: `2026-11-25T23:59:60+08:00` is a leap second",
        ),
    ] {
        let o = verify(&edited(request, edit));
        assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
        assert!(stderr(&o).contains(expected), "{}", stderr(&o));
    }
}

/// `muse view` of a service listing: the flights drawn, and every request that did not fly
/// (rejected, cancelled by a zone or by its operator) listed in the page with its reason.
#[test]
fn view_lists_every_request_that_did_not_fly_with_its_reason() {
    let dir = scratch_dir("view_service_listing");
    let out = dir.join("view.html").display().to_string();
    let listing = service_testdata("flights.jsonl");
    let o = muse(&[
        "view",
        "--plans",
        &listing,
        "--airspace",
        &service_testdata("line.geojson"),
        "--zones",
        &service_testdata("zones.geojson"),
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o).contains(": 4 flights of 10 requests"),
        "{}",
        stdout(&o)
    );
    let html = std::fs::read_to_string(&out).unwrap();
    let json = html
        .split_once(r#"<script type="application/json" id="muse-scene">"#)
        .and_then(|(_, rest)| rest.split_once("</script>"))
        .expect("the scene in the page")
        .0;
    let scene: serde_json::Value = serde_json::from_str(json).unwrap();
    let reasons = scene["reasons"].as_array().unwrap();
    let mut shown: Vec<(String, String, String, Option<String>)> = scene["unflown"]
        .as_array()
        .unwrap()
        .iter()
        .map(|u| {
            let why = &reasons[usize::try_from(u[4].as_u64().unwrap()).unwrap()];
            (
                u[0].as_str().unwrap().to_owned(),
                why["status"].as_str().unwrap().to_owned(),
                why["reason"].as_str().unwrap().to_owned(),
                why["zone"].as_str().map(str::to_owned),
            )
        })
        .collect();
    shown.sort();
    let mut expected = Vec::new();
    for l in std::fs::read_to_string(&listing).unwrap().lines() {
        let v: serde_json::Value = serde_json::from_str(l).unwrap();
        let status = v["status"].as_str().unwrap();
        if status == "rejected" || status == "cancelled" {
            let reason = v["reason"].as_str().unwrap().to_owned();
            let zone = (reason == "zone_announced")
                .then(|| v["changes"].as_array().unwrap().last().unwrap()["zone"].clone())
                .map(|z| z.as_str().unwrap().to_owned());
            expected.push((
                v["request"].as_str().unwrap().to_owned(),
                status.to_owned(),
                reason,
                zone,
            ));
        }
    }
    expected.sort();
    assert_eq!(expected.len(), 6);
    assert_eq!(shown, expected);
    assert_eq!(scene["flights"].as_array().unwrap().len(), 4);
}

#[test]
fn times_are_read_exactly_and_leap_seconds_refused() {
    let dir = scratch_dir("times_exact");
    let requests = |name: &str, departure: &str| {
        write(
            &dir,
            name,
            &format!("id,origin,destination,departure\nr1,S063,S066,{departure}\n"),
        )
    };
    let out = dir.join("out").display().to_string();
    for (departure, expected) in [
        (
            "2026-06-30T23:59:60+08:00",
            "leap.csv: line 2: field `departure`: `2026-06-30T23:59:60+08:00` is a leap second \
             (second 60): leap seconds are not accepted",
        ),
        (
            "23:59:60",
            "leap.csv: line 2: field `departure`: `23:59:60` is a leap second",
        ),
        (
            "+1000000-01-01T00:00:00Z",
            "leap.csv: line 2: field `departure`: `+1000000-01-01T00:00:00Z` is out of the range \
             MUSE represents",
        ),
    ] {
        let r = requests("leap.csv", departure);
        let o = muse(&["plan", "--requests", &r, "--out", &out]);
        assert_eq!(o.status.code(), Some(2), "{departure}: {}", stdout(&o));
        assert!(stderr(&o).contains(expected), "{}", stderr(&o));
    }
    // Year 9999 is read (no "not RFC 3339"); what stops it is the years MUSE plans
    // (tests/cli/bad_inputs.rs, departures_outside_the_planned_years_are_named).
    let r = requests("far.csv", "9999-12-31T23:59:59+08:00");
    let o = muse(&["plan", "--requests", &r, "--out", &out]);
    assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
    assert!(
        stderr(&o).contains("outside the years MUSE plans") && !stderr(&o).contains("RFC 3339"),
        "{}",
        stderr(&o)
    );
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

/// `muse verify` says how close the flights come in metres (docs/reference.md#metric-separation):
/// the default day, flown exactly as planned, has 45 pairs closer than 30 m, the closest 2.4 m
/// apart where two corridors meet at 6.6°.
#[test]
fn verify_reports_how_close_the_default_day_comes() {
    let dir = scratch_dir("verify_approach");
    let out = dir.join("out").display().to_string();
    let o = muse(&["simulate", "--out", &out, "--no-csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = muse(&["verify", "--plans", &format!("{out}/plans.jsonl")]);
    assert!(o.status.success(), "{}", stdout(&o));
    let said = stdout(&o);
    assert!(
        said.contains("metric separation: closest approach 2.4 m (r1612 and r2935 at 2026-01-05T13:44:22.382+08:00, near S011)")
            && said.contains("pairs closer than 10 m: 4, 20 m: 21, 30 m: 45"),
        "{said}"
    );
}

/// `--separation-m 30` (docs/reference.md#metric-separation): the default day planned with the
/// rule keeps every pair 30 m apart, and says so; its summary records the rule, which `muse
/// verify` then checks; today's plans checked with the rule break it 45 times.
#[test]
fn the_default_day_keeps_thirty_metres_with_the_rule() {
    let dir = scratch_dir("separation_30");
    let out = dir.join("out").display().to_string();
    let o = muse(&[
        "simulate",
        "--out",
        &out,
        "--no-csv",
        "--separation-m",
        "30",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let said = stdout(&o);
    assert!(
        said.contains("verified      OK")
            && said.contains("pairs closer than 10 m: 0, 20 m: 0, 30 m: 0"),
        "{said}"
    );
    let summary = std::fs::read_to_string(format!("{out}/summary.json")).unwrap();
    assert!(summary.contains("\"separation_m\": 30.0"), "{summary}");
    let o = muse(&["verify", "--plans", &format!("{out}/plans.jsonl")]);
    assert!(o.status.success(), "{}", stdout(&o));

    let plain = dir.join("plain").display().to_string();
    let o = muse(&["simulate", "--out", &plain, "--no-csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let plans = format!("{plain}/plans.jsonl");
    let o = muse(&[
        "verify",
        "--plans",
        &plans,
        "--separation-m",
        "30",
        "--max-listed",
        "100",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    let said = stdout(&o);
    assert!(
        said.contains("FAILED: 45 violation(s)")
            && said.contains(
                "separation rule violated by r1612, r2935 at `S011`: 2.428 m apart horizontally \
                 at 2026-01-05T13:44:22.382+08:00 (at least 30 m, or 9.144 m vertically)"
            ),
        "{said}"
    );
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

/// The `(id, origin, destination, departure)` rows of a requests CSV and its `submitted`
/// instants (the departure where the file has no such column).
fn read_requests_csv(path: &Path) -> (String, Vec<[String; 4]>, Vec<muse_model::Instant>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_owned();
    let (mut rows, mut submitted) = (Vec::new(), Vec::new());
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let at = |t: &str| muse_model::Instant::parse_rfc3339(t).unwrap();
        submitted.push(at(cells.get(4).copied().unwrap_or(cells[3])));
        rows.push([0, 1, 2, 3].map(|i| cells[i].to_owned()));
    }
    (header, rows, submitted)
}

#[test]
fn simulate_books_ahead_records_the_lead_and_verifies() {
    let dir = scratch_dir("booking_lead");
    let path = |name: &str| dir.join(name).display().to_string();
    let simulate = |out: &str, lead: Option<&str>| {
        let mut args = vec![
            "simulate", "--count", "3000", "--seed", "5", "--od", "in-range", "--out", out,
        ];
        if let Some(lead) = lead {
            args.extend(["--booking-lead-min", lead]);
        }
        let o = muse(&args);
        assert!(o.status.success(), "{args:?}: {}{}", stdout(&o), stderr(&o));
        stdout(&o)
    };
    let text = simulate(&path("booked"), Some("0:120"));
    assert!(text.contains("seed 5, booked 0–120 min ahead"), "{text}");
    assert!(text.contains("verified      OK"), "{text}");

    // summary.json records the lead among the parameters.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("booked/summary.json")).unwrap())
            .unwrap();
    assert_eq!(
        summary["parameters"]["booking_lead_min"],
        serde_json::json!({"from": 0.0, "to": 120.0}),
        "{summary}"
    );

    // requests.csv has the submitted column, every lead within 0–120 minutes.
    let (header, rows, submitted) = read_requests_csv(&dir.join("booked/requests.csv"));
    assert_eq!(header, "id,origin,destination,departure,submitted");
    let leads: Vec<i64> = rows
        .iter()
        .zip(&submitted)
        .map(|(r, s)| (muse_model::Instant::parse_rfc3339(&r[3]).unwrap() - *s).0)
        .collect();
    assert!(leads.iter().all(|l| (0..=7_200_000).contains(l)));
    assert!(leads.iter().any(|l| *l > 3_600_000));

    // The plans are in submission order, and the independent verifier accepts them.
    let plans = std::fs::read_to_string(dir.join("booked/plans.jsonl")).unwrap();
    let by_id: std::collections::HashMap<&str, muse_model::Instant> = rows
        .iter()
        .map(|r| r[0].as_str())
        .zip(submitted.iter().copied())
        .collect();
    let order: Vec<muse_model::Instant> = plans
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            by_id[v["request"].as_str().unwrap()]
        })
        .collect();
    assert_eq!(order.len(), 3000);
    assert!(
        order.windows(2).all(|w| w[0] <= w[1]),
        "planned by submission"
    );
    let o = muse(&["verify", "--plans", &path("booked/plans.jsonl")]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));

    // `muse plan` on the written requests reads the column back and plans the same day.
    let o = muse(&[
        "plan",
        "--requests",
        &path("booked/requests.csv"),
        "--out",
        &path("replanned"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(dir.join("replanned/plans.jsonl")).unwrap(),
        plans
    );

    // Same seed without a lead: the same departures and pairs, no submitted column; an
    // explicit lead of 0 is byte for byte the default.
    simulate(&path("paper"), None);
    simulate(&path("zero"), Some("0"));
    let (paper_header, paper_rows, paper_submitted) =
        read_requests_csv(&dir.join("paper/requests.csv"));
    assert_eq!(paper_header, "id,origin,destination,departure");
    assert_eq!(paper_rows, rows);
    assert_ne!(paper_submitted, submitted);
    for file in ["requests.csv", "plans.jsonl"] {
        assert_eq!(
            std::fs::read(dir.join("paper").join(file)).unwrap(),
            std::fs::read(dir.join("zero").join(file)).unwrap(),
            "{file}"
        );
    }
    // Booking ahead changes who gets the contested slots.
    let planned = |text: &str| -> std::collections::BTreeSet<String> {
        text.lines()
            .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
            .filter(|v| v["status"] == "planned")
            .map(|v| v["request"].as_str().unwrap().to_owned())
            .collect()
    };
    let paper_plans = std::fs::read_to_string(dir.join("paper/plans.jsonl")).unwrap();
    assert_ne!(planned(&paper_plans), planned(&plans));
}

#[test]
fn simulate_replays_an_announced_zone_and_verify_applies_it() {
    let dir = scratch_dir("announced");
    let root = env!("CARGO_MANIFEST_DIR");
    let cbd = format!("{root}/scenarios/singapore-77/cbd_zone.geojson");
    let stadium = format!("{root}/scenarios/singapore-77/stadium_zone.geojson");
    let out = dir.join("sim").display().to_string();
    let zones = ["--zones", cbd.as_str(), "--zones", stadium.as_str()];
    let mut args = vec![
        "simulate",
        "--count",
        "10000",
        "--od",
        "in-range",
        "--booking-lead-min",
        "0:120",
        "--out",
        &out,
    ];
    args.extend(zones);
    let o = muse(&args);
    let text = stdout(&o);
    assert!(o.status.success(), "{text}{}", stderr(&o));
    assert!(
        text.contains("announced     SG-NATIONAL-STADIUM-EVENT at 2026-01-05T14:00:00.000+08:00"),
        "{text}"
    );
    assert!(text.contains("verified      OK"), "{text}");

    // plans.jsonl: every changed flight has its original plan and its outcome; the summary
    // counts them.
    let plans = std::fs::read_to_string(dir.join("sim/plans.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = plans
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let changed: Vec<&serde_json::Value> =
        lines.iter().filter(|l| l["original"].is_object()).collect();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sim/summary.json")).unwrap())
            .unwrap();
    let r = &summary["replanning"];
    assert_eq!(r["zones_announced"], 1, "{summary}");
    assert_eq!(r["flights_affected"], changed.len(), "{summary}");
    assert!(
        !changed.is_empty(),
        "the stadium zone hits some of 10,000 flights booked ahead"
    );
    for status in ["replanned", "diverted", "cancelled", "contingency"] {
        let n = changed.iter().filter(|l| l["status"] == status).count();
        assert_eq!(r[status], n, "{status}: {summary}");
    }
    for l in &changed {
        assert_eq!(l["changes"][0]["zone"], "SG-NATIONAL-STADIUM-EVENT", "{l}");
        if l["status"] == "cancelled" {
            assert_eq!(l["reason"], "zone_announced", "{l}");
            assert!(l.get("path").is_none(), "{l}");
        }
    }

    // `muse plan` on the same requests gives the same plans.
    let requests = dir.join("sim/requests.csv").display().to_string();
    let planned = dir.join("plan").display().to_string();
    let mut args = vec!["plan", "--requests", &requests, "--out", &planned];
    args.extend(zones);
    let o = muse(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let without_effort = |text: &str| {
        text.lines()
            .map(|l| {
                let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
                v.as_object_mut().unwrap().remove("expanded");
                v
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(
        without_effort(&std::fs::read_to_string(dir.join("plan/plans.jsonl")).unwrap()),
        without_effort(&plans)
    );

    // `muse verify` knows the announcement: the final plans pass...
    let plans_path = dir.join("sim/plans.jsonl").display().to_string();
    let mut args = vec!["verify", "--plans", &plans_path];
    args.extend(zones);
    let o = muse(&args);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o).contains("1 announced during the day"),
        "{}",
        stdout(&o)
    );

    // ...but a flight that kept its original plan breaks the zone.
    assert_original_plan_breaks_the_zone(&dir, &plans, changed[0], &zones);
}

/// Replaces the line of `first` (a flight an announcement changed) in `plans` by one that keeps
/// its original plan, and checks that `muse verify` with `zones` names the violation.
fn assert_original_plan_breaks_the_zone(
    dir: &Path,
    plans: &str,
    first: &serde_json::Value,
    zones: &[&str],
) {
    let mut kept = first.clone();
    let kept_obj = kept.as_object_mut().unwrap();
    kept_obj.insert("status".into(), "planned".into());
    kept_obj.insert("reason".into(), serde_json::Value::Null);
    kept_obj.insert("path".into(), first["original"]["path"].clone());
    for field in [
        "original",
        "changes",
        "committed",
        "diverted_to",
        "extra_delay_s",
    ] {
        kept_obj.remove(field);
    }
    let id = first["request"].as_str().unwrap();
    let tampered: String = plans
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            if v["request"] == id {
                format!("{kept}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let bad = write(dir, "tampered.jsonl", &tampered);
    let mut args = vec!["verify", "--plans", &bad];
    args.extend(zones);
    let o = muse(&args);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    assert!(
        stdout(&o).contains("SG-NATIONAL-STADIUM-EVENT") && stdout(&o).contains(id),
        "{}",
        stdout(&o)
    );
}

#[test]
fn demand_and_sweep_take_the_booking_lead() {
    let dir = scratch_dir("booking_lead_demand");
    let path = |name: &str| dir.join(name).display().to_string();
    let o = muse(&[
        "demand",
        "--count",
        "50",
        "--booking-lead-min",
        "30",
        "--out",
        &path("r.csv"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("(seed 1, booked 30 min ahead)"),
        "{}",
        stdout(&o)
    );
    let (header, rows, submitted) = read_requests_csv(&dir.join("r.csv"));
    assert_eq!(header, "id,origin,destination,departure,submitted");
    for (r, s) in rows.iter().zip(&submitted) {
        let dep = muse_model::Instant::parse_rfc3339(&r[3]).unwrap();
        assert_eq!((dep - *s).0, 30 * 60_000);
    }
    let o = muse(&["demand", "--count", "50", "--out", &path("paper.csv")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, paper_rows, _) = read_requests_csv(&dir.join("paper.csv"));
    assert_eq!(header, "id,origin,destination,departure");
    assert_eq!(paper_rows, rows);

    let o = muse(&[
        "sweep",
        "--counts",
        "200",
        "--reps",
        "2",
        "--booking-lead-min",
        "10:60",
        "--out",
        &path("sweep"),
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o).contains("400 requests booked 10–60 min ahead"),
        "{}",
        stdout(&o)
    );
    let csv = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .ends_with(",booking_lead_min_from,booking_lead_min_to")
    );
    assert!(lines.all(|l| l.ends_with(",10,60")), "{csv}");
    let svg = std::fs::read_to_string(dir.join("sweep/sweep_success.svg")).unwrap();
    assert!(svg.contains("requests booked 10–60 min ahead"), "footnote");
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
fn sweep_varies_tau_on_the_same_seeds() {
    let dir = scratch_dir("sweep_tau");
    let out = dir.join("tau");
    let o = muse(&[
        "sweep",
        "--vary",
        "tau",
        "--tau-s",
        "0.5,120",
        "--counts",
        "400",
        "--reps",
        "2",
        "--od",
        "in-range",
        "--zones",
        "none",
        "--from",
        "09:00",
        "--to",
        "11:00",
        "--seed",
        "3",
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0][..5], ["variant", "count", "rep", "seed", "planned"]);
    let runs: Vec<(&str, &str, usize)> = rows[1..]
        .iter()
        .map(|r| (r[0], r[3], r[4].parse().unwrap()))
        .collect();
    assert_eq!(
        runs.iter().map(|r| (r.0, r.1)).collect::<Vec<_>>(),
        [
            ("tau 0.5 s", "3"),
            ("tau 0.5 s", "4"),
            ("tau 120 s", "3"),
            ("tau 120 s", "4")
        ]
    );
    // Two minutes between stays at a node refuse flights that half a second lets fly.
    assert!(runs[2].2 < runs[0].2 && runs[3].2 < runs[1].2, "{runs:?}");
    let summary = std::fs::read_to_string(out.join("sweep_summary.csv")).unwrap();
    assert!(summary.contains("\ntau 120 s,400,2,"), "{summary}");

    for (args, message) in [
        (vec!["--tau-s", "3"], "--tau-s applies only with --vary tau"),
        (
            vec!["--vary", "tau", "--tau-s", "5,4000"],
            "--tau-s `5,4000`: expected at most 100 comma-separated seconds, each from 0 to 3600",
        ),
    ] {
        let mut all = vec!["sweep", "--counts", "10", "--reps", "1"];
        all.extend(args);
        let o = muse(&[&all[..], &["--out", &dir.join("x").display().to_string()]].concat());
        assert_eq!(o.status.code(), Some(2), "{all:?}");
        assert!(stderr(&o).contains(message), "{all:?}: {}", stderr(&o));
    }
}

/// The exact header of `announce_lead.csv`.
const ANNOUNCE_LEAD_HEADER: &str = "case,lead_min,count,rep,seed,planned_at_booking,delivered,success_rate,affected,airborne_affected,replanned,diverted,cancelled,contingency,mean_extra_delay_s,planner_ms,replan_expanded,booking_lead_min_from,booking_lead_min_to";

#[test]
fn sweep_announce_lead_writes_runs_summary_and_plots() {
    let dir = scratch_dir("announce_lead");
    let out = dir.join("out");
    let o = muse(&[
        "sweep",
        "--vary",
        "announce-lead",
        "--counts",
        "300",
        "--reps",
        "2",
        "--leads",
        "60,0",
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    let text = stdout(&o);
    for expected in [
        "SG-CBD-DOWNTOWN-CORE (first window 10:00) announced 0, 60 min ahead",
        "4 cases × 1 counts × 2 repetitions = 8 runs, 2400 requests booked 0–120 min ahead (this sweep's default)",
        "lead min",
        "   known     300",
    ] {
        assert!(text.contains(expected), "{expected}: {text}");
    }
    let csv = std::fs::read_to_string(out.join("announce_lead.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), ANNOUNCE_LEAD_HEADER);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Leads sorted, then the references; the same two seeds in every case.
    let keys: Vec<(&str, &str, &str, &str)> =
        rows.iter().map(|r| (r[0], r[1], r[3], r[4])).collect();
    assert_eq!(
        keys,
        [
            ("announced", "0", "0", "1"),
            ("announced", "0", "1", "2"),
            ("announced", "60", "0", "1"),
            ("announced", "60", "1", "2"),
            ("known", "", "0", "1"),
            ("known", "", "1", "2"),
            ("none", "", "0", "1"),
            ("none", "", "1", "2"),
        ]
    );
    for r in &rows {
        assert_eq!(r.len(), 19, "{r:?}");
        assert_eq!((r[2], r[17], r[18]), ("300", "0", "120"), "{r:?}");
        let rate: f64 = r[7].parse().unwrap();
        let delivered: f64 = r[6].parse().unwrap();
        assert!((rate - delivered / 300.0).abs() < 1e-6, "{r:?}");
    }
    let summary = std::fs::read_to_string(out.join("announce_lead_summary.csv")).unwrap();
    assert!(summary.starts_with(
        "case,lead_min,count,runs,runs_with_replanned,success_rate_mean,success_rate_ci95_low,success_rate_ci95_high,planned_at_booking_mean,"
    ));
    assert_eq!(summary.lines().count(), 1 + 4);
    assert!(summary.lines().nth(3).unwrap().starts_with("known,,300,2,"));
    for file in [
        "announce_lead_success.svg",
        "announce_lead_outcomes.svg",
        "announce_lead_extra_delay.svg",
    ] {
        let svg = std::fs::read_to_string(out.join(file)).unwrap();
        assert!(svg.starts_with("<svg"), "{file}");
        assert!(svg.contains("Announcement lead"), "{file}");
    }
    let success = std::fs::read_to_string(out.join("announce_lead_success.svg")).unwrap();
    assert!(success.contains("known from the start"));
}

#[test]
fn sweep_announce_lead_zones_and_errors() {
    let dir = scratch_dir("announce_lead_zones");
    let stadium = format!(
        "{}/scenarios/singapore-77/stadium_zone.geojson",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = muse(&[
        "sweep",
        "--vary",
        "announce-lead",
        "--counts",
        "100",
        "--reps",
        "1",
        "--leads",
        "30",
        "--booking-lead-min",
        "0:60",
        "--announce-zones",
        &stadium,
        "--out",
        &dir.join("out").display().to_string(),
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o)
            .contains("SG-NATIONAL-STADIUM-EVENT (first window 15:00) announced 30 min ahead"),
        "{}",
        stdout(&o)
    );
    assert!(
        stdout(&o).contains("300 requests booked 0–60 min ahead,"),
        "{}",
        stdout(&o)
    );

    let text = std::fs::read_to_string(&stadium).unwrap();
    let tomorrow = write(
        &dir,
        "z.geojson",
        &text.replace("2026-01-05T1", "2026-01-06T1"),
    );
    for (args, expected) in [
        (
            vec!["--vary", "announce-lead", "--vary", "zones"],
            "--vary announce-lead cannot be combined with other --vary values",
        ),
        (
            vec!["--leads", "0,30"],
            "--leads and --announce-zones apply only with --vary announce-lead",
        ),
        (
            vec!["--vary", "announce-lead", "--leads", "0,-5"],
            "--leads `0,-5`: -5 minutes: a lead must be a number of minutes from 0 to 43200",
        ),
        (
            vec![
                "--vary",
                "announce-lead",
                "--synthetic",
                "grid",
                "--nodes",
                "16",
            ],
            "--vary announce-lead needs a zone to announce",
        ),
        (
            vec!["--vary", "announce-lead", "--announce-zones", &tomorrow],
            "on the scenario's day 2026-01-05: zone `SG-NATIONAL-STADIUM-EVENT` has no active window starting between 2026-01-05T00:00:00.000+08:00 and 2026-01-06T00:00:00.000+08:00",
        ),
    ] {
        let mut all = vec!["sweep", "--counts", "10", "--reps", "1"];
        all.extend(args);
        let o = muse(&all);
        assert_eq!(o.status.code(), Some(2), "{all:?}");
        assert!(stderr(&o).contains(expected), "{all:?}: {}", stderr(&o));
    }
}

#[test]
fn argument_errors_are_clear() {
    for (args, expected) in [
        (vec!["sweep", "--counts", "10:5:1"], "--counts `10:5:1`"),
        (
            vec!["sweep", "--reps", "0"],
            "invalid value '0' for '--reps <REPS>': must be a whole number of repetitions from 1 to 10000",
        ),
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
            vec!["demand", "--to", "23:59:60"],
            "--to: `23:59:60` is a leap second (second 60): leap seconds are not accepted",
        ),
        (
            vec!["serve", "--clock", "2026-06-30T23:59:60+08:00"],
            "--clock 2026-06-30T23:59:60+08:00: `2026-06-30T23:59:60+08:00` is a leap second",
        ),
        (
            vec!["simulate", "--max-flight-min=-1"],
            "invalid value '-1' for '--max-flight-min <MIN>': must be a number of minutes from 1 to 1440",
        ),
        (
            vec!["simulate", "--speed-kmh", "0"],
            "invalid value '0' for '--speed-kmh <KMH>': must be a speed in km/h from 1 to 1000",
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
    // The booking lead is checked by clap, for every command that generates demand.
    for (cmd, lead, expected) in [
        (
            "simulate",
            "120:30",
            "invalid value '120:30' for '--booking-lead-min <A[:B]>': the lower bound 120 must not exceed the upper bound 30",
        ),
        (
            "demand",
            "-5",
            "invalid value '-5' for '--booking-lead-min <A[:B]>': -5 minutes: a booking lead must be a number of minutes from 0 to 43200",
        ),
        (
            "sweep",
            "soon",
            "invalid value 'soon' for '--booking-lead-min <A[:B]>': `soon` is not a number of minutes",
        ),
    ] {
        let arg = format!("--booking-lead-min={lead}");
        let o = muse(&[cmd, &arg]);
        assert_eq!(o.status.code(), Some(2), "{cmd} {arg}");
        assert!(stderr(&o).contains(expected), "{cmd} {arg}: {}", stderr(&o));
    }
    let o = muse(&["simulate", "--requests", "r.csv", "--booking-lead-min", "5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("cannot be used with '--booking-lead-min <A[:B]>'"),
        "{}",
        stderr(&o)
    );
    // Usage errors come from clap, also with exit code 2.
    let o = muse(&["simulate", "--edge-rule", "sometimes"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("invalid value 'sometimes'"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bench_writes_a_table_a_csv_and_plots() {
    let dir = scratch_dir("bench");
    let out = dir.display().to_string();
    let o = muse(&[
        "bench",
        "--requests",
        "200,400",
        "--graphs",
        "singapore-77",
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    let text = stdout(&o);
    for expected in [
        "1 graph(s) × 2 demand level(s) = 2 cases",
        "OD rule   in-range",
        "[1/2] singapore-77, 200 requests: running",
        "[2/2] singapore-77, 400 requests: done in",
        "growth exponent of total planner time vs requests",
        "bench.csv",
    ] {
        assert!(text.contains(expected), "`{expected}` in\n{text}");
    }
    let csv = std::fs::read_to_string(dir.join("bench.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3, "{csv}");
    let col = |name: &str| rows[0].iter().position(|c| *c == name).expect(name);
    for (row, requests) in rows[1..].iter().zip(["200", "400"]) {
        assert_eq!(row.len(), rows[0].len(), "{csv}");
        assert_eq!(row[col("graph")], "singapore-77");
        assert_eq!(row[col("nodes")], "77");
        assert_eq!(row[col("requests")], requests);
        assert_eq!(row[col("od")], "in-range");
        assert!(row[col("planned")].parse::<usize>().unwrap() > 0, "{csv}");
        assert!(row[col("planner_s")].parse::<f64>().unwrap() > 0.0, "{csv}");
        assert!(
            row[col("expanded_per_request")].parse::<f64>().unwrap() >= 1.0,
            "{csv}"
        );
        // Two demand levels give an exponent against requests; one graph none against nodes.
        assert!(
            row[col("graph_time_exponent_vs_requests")]
                .parse::<f64>()
                .is_ok(),
            "{csv}"
        );
        assert_eq!(row[col("level_time_per_request_exponent_vs_nodes")], "n/a");
        if cfg!(target_os = "linux") {
            assert!(
                row[col("peak_rss_mib")].parse::<f64>().unwrap() > 1.0,
                "{csv}"
            );
        }
    }
    let mut plots = vec!["bench_time_per_request.svg", "bench_expanded.svg"];
    if cfg!(target_os = "linux") {
        plots.push("bench_peak_memory.svg");
    }
    for plot in plots {
        let svg = std::fs::read_to_string(dir.join(plot)).expect(plot);
        assert!(
            svg.starts_with("<svg") && svg.contains("log scale"),
            "{plot}"
        );
    }
}

#[test]
fn bench_argument_errors_are_clear() {
    let dir = scratch_dir("bench_errors");
    let out = dir.join("never").display().to_string();
    for (args, expected) in [
        (
            vec!["--requests", "0"],
            "--requests `0`: `0` is not a count of requests from 1 to 10000000",
        ),
        (vec!["--requests", "10k,10000"], "10000 is named twice"),
        (vec!["--graphs", "atlantis"], "--graphs: `atlantis`"),
        (
            vec!["--graphs", "synthetic-5"],
            "a synthetic graph has 20 to",
        ),
        (vec!["--graphs", "singapore-77,singapore-77"], "named twice"),
        (
            vec!["--max-flight-min=-1"],
            "invalid value '-1' for '--max-flight-min <MIN>': must be a number of minutes from 1 to 1440",
        ),
    ] {
        let all: Vec<&str> = ["bench", "--out", &out]
            .into_iter()
            .chain(args.clone())
            .collect();
        let o = muse(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{args:?}: {}", stderr(&o));
    }
    assert!(
        !dir.join("never").exists(),
        "no output folder for bad arguments"
    );
    let o = muse(&["bench", "--od", "sometimes"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("invalid value 'sometimes'"));
    // The per-case subcommand is there but not advertised.
    let help = stdout(&muse(&["--help"]));
    assert!(
        help.contains("bench") && !help.contains("bench-case"),
        "{help}"
    );
}

#[test]
fn scenario_singapore_all_info_map_and_simulate() {
    let o = muse(&["airspace", "info", "--scenario", "singapore-all"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("embedded singapore-all"), "{out}");
    assert!(out.contains("1115 (1115 stations, 0 waypoints)"), "{out}");
    assert!(out.contains("edges         3302"), "{out}");
    assert!(out.contains("SG-CBD-DOWNTOWN-CORE"), "{out}");
    // Naming the default explicitly is the same as not naming it.
    let named = muse(&["airspace", "info", "--scenario", "singapore-77"]);
    assert_eq!(stdout(&named), stdout(&muse(&["airspace", "info"])));

    let dir = scratch_dir("singapore_all");
    let map = dir.join("map.svg").display().to_string();
    let o = muse(&[
        "airspace",
        "map",
        "--scenario",
        "singapore-all",
        "--out",
        &map,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(&map).unwrap();
    assert!(svg.contains("1115 HDB multi-storey car parks") && svg.contains("Downtown Core"));
    assert!(
        !svg.contains(">ACM<"),
        "no station labels with 1,115 stations"
    );

    let out = dir.join("sim").display().to_string();
    let o = muse(&[
        "simulate",
        "--scenario",
        "singapore-all",
        "--count",
        "500",
        "--out",
        &out,
    ]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("embedded singapore-all (SG-CBD-DOWNTOWN-CORE)"),
        "{text}"
    );
    assert!(text.contains("verified      OK"), "{text}");
    // Request files name the car parks by number.
    let requests = std::fs::read_to_string(dir.join("sim/requests.csv")).unwrap();
    let plan = muse(&[
        "plan",
        "--scenario",
        "singapore-all",
        "--requests",
        &dir.join("sim/requests.csv").display().to_string(),
        "--out",
        &dir.join("plan").display().to_string(),
    ]);
    assert!(plan.status.success(), "{}", stderr(&plan));
    let on_default = muse(&[
        "plan",
        "--requests",
        &dir.join("sim/requests.csv").display().to_string(),
        "--out",
        &dir.join("plan77").display().to_string(),
    ]);
    assert_eq!(on_default.status.code(), Some(2), "{requests}");
}

#[test]
fn unknown_scenario_and_conflicting_sources_are_usage_errors() {
    let o = muse(&["airspace", "info", "--scenario", "atlantis"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("invalid value 'atlantis' for '--scenario <NAME>'")
            && err.contains("singapore-77")
            && err.contains("singapore-all"),
        "{err}"
    );
    let dir = scratch_dir("scenario_conflicts");
    let air = write(&dir, "air.geojson", "{}");
    for (args, expected) in [
        (
            vec!["--scenario", "singapore-all", "--airspace", &air],
            "'--scenario <NAME>' cannot be used with '--airspace <FILE>'",
        ),
        (
            vec![
                "--scenario",
                "singapore-77",
                "--synthetic",
                "grid",
                "--nodes",
                "9",
            ],
            "cannot be used with",
        ),
        (
            vec!["--airspace", &air, "--synthetic", "grid", "--nodes", "9"],
            "cannot be used with",
        ),
        (vec!["--synthetic", "grid"], "--nodes <N>"),
        (vec!["--nodes", "9"], "--synthetic <LAYOUT>"),
        (
            vec!["--synthetic", "hexagons", "--nodes", "9"],
            "invalid value 'hexagons'",
        ),
        (
            vec!["--synthetic", "grid", "--nodes", "1"],
            "invalid value '1' for '--nodes <N>': must be a whole number of nodes from 2 to 1000000",
        ),
        (
            vec![
                "--synthetic",
                "geometric",
                "--nodes",
                "50",
                "--spacing-m",
                "0",
            ],
            "invalid value '0' for '--spacing-m <M>': must be a number of metres from 1 to 100000",
        ),
        (
            vec![
                "--synthetic",
                "grid",
                "--nodes",
                "50",
                "--station-share",
                "1.5",
            ],
            "invalid value '1.5' for '--station-share <SHARE>': must be a share from 0.001 to 1",
        ),
    ] {
        let all: Vec<&str> = ["airspace", "info"].into_iter().chain(args).collect();
        let o = muse(&all);
        assert_eq!(o.status.code(), Some(2), "{all:?}");
        assert!(stderr(&o).contains(expected), "{all:?}: {}", stderr(&o));
    }
}

#[test]
fn synthetic_airspaces_work_with_every_command() {
    let o = muse(&["airspace", "info", "--synthetic", "grid", "--nodes", "100"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("synthetic grid, 100 nodes, spacing 1500 m, 10 stations, seed 1"),
        "{out}"
    );
    assert!(out.contains("100 (10 stations, 90 waypoints)"), "{out}");
    assert!(out.contains("edges         180\n"), "{out}");
    assert!(
        out.contains("min 1.50 km, median 1.50 km, max 1.50 km"),
        "{out}"
    );
    assert!(out.contains("zones         none"), "{out}");

    let args = [
        "--synthetic",
        "geometric",
        "--nodes",
        "300",
        "--spacing-m",
        "800",
        "--station-share",
        "0.2",
        "--synthetic-seed",
        "7",
    ];
    let run = |cmd: &[&str]| {
        let all: Vec<&str> = cmd.iter().copied().chain(args).collect();
        let o = muse(&all);
        assert!(o.status.success(), "{all:?}: {}{}", stdout(&o), stderr(&o));
        stdout(&o)
    };
    let info = run(&["airspace", "info"]);
    assert!(info.contains("300 (60 stations, 240 waypoints)"), "{info}");
    assert_eq!(info, run(&["airspace", "info"]), "deterministic");

    let dir = scratch_dir("synthetic");
    let path = |name: &str| dir.join(name).display().to_string();
    run(&["airspace", "map", "--out", &path("map.svg")]);
    let svg = std::fs::read_to_string(dir.join("map.svg")).unwrap();
    assert!(svg.contains("synthetic geometric, 300 nodes (60 stations)"));
    run(&["demand", "--count", "400", "--out", &path("requests.csv")]);
    run(&[
        "plan",
        "--requests",
        &path("requests.csv"),
        "--out",
        &path("plan"),
    ]);
    run(&["verify", "--plans", &path("plan/plans.jsonl")]);
    let sim = run(&["simulate", "--count", "400", "--out", &path("sim")]);
    assert!(
        sim.contains("(no zones)") && sim.contains("verified      OK"),
        "{sim}"
    );
    run(&[
        "sweep",
        "--counts",
        "100,200",
        "--reps",
        "2",
        "--out",
        &path("sweep"),
    ]);
    // A zone file still applies to a synthetic airspace.
    let zones = write(
        &dir,
        "zone.geojson",
        r#"{"type": "FeatureCollection", "features": [{"type": "Feature",
  "geometry": {"type": "Polygon", "coordinates": [[[103.80, 1.33], [103.84, 1.33], [103.84, 1.37], [103.80, 1.37], [103.80, 1.33]]]},
  "properties": {"identifier": "BOX", "type": "PROHIBITED"}}]}"#,
    );
    let info = run(&["airspace", "info", "--zones", &zones]);
    assert!(info.contains("zone          BOX"), "{info}");
}
