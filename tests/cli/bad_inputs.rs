//! Bad input, as a user gives it: every case is refused with exit code 2 and a message that
//! names what is wrong — the file, the line or feature and the field, or the option — and
//! what is accepted, before anything is written (no output that looks whole is left behind)
//! and before sizes that cannot fit in memory are allocated.

use std::path::{Path, PathBuf};

use crate::run::{muse, stderr};

/// A fresh folder under the target directory for one test.
fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("bad_inputs_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> String {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.display().to_string()
}

/// Runs `args`, asserts exit code 2 and that stderr says every one of `needles`; returns
/// stderr.
fn refused(args: &[&str], needles: &[&str]) -> String {
    let o = muse(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: `{needle}` not in: {err}");
    }
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    err
}

/// Asserts that nothing that looks like a whole output is at `out`: no folder, or no file.
fn nothing_written(out: &Path) {
    if out.is_dir() {
        let files: Vec<_> = std::fs::read_dir(out).unwrap().flatten().collect();
        assert!(files.is_empty(), "{} holds {files:?}", out.display());
    } else {
        assert!(!out.exists(), "{} was written", out.display());
    }
}

/// A requests file every test can plan on the default airspace.
const REQUESTS: &str = "id,origin,destination,departure\nr1,S012,S040,08:15\n";

#[test]
fn request_counts_beyond_what_memory_holds_are_refused_before_allocating() {
    let dir = scratch_dir("counts");
    let out = dir.join("out");
    let o = out.display().to_string();
    let started = std::time::Instant::now();
    refused(
        &["simulate", "--count", "2000000000", "--out", &o],
        &[
            "invalid value '2000000000' for '--count <COUNT>'",
            "must be a whole number of requests from 1 to 10000000",
        ],
    );
    assert!(started.elapsed().as_secs() < 5, "refused before allocating");
    nothing_written(&out);
    let csv = dir.join("r.csv");
    let c = csv.display().to_string();
    refused(
        &["demand", "--count", "10000001", "--out", &c],
        &["'--count <COUNT>'", "from 1 to 10000000"],
    );
    nothing_written(&csv);
    refused(
        &["sweep", "--counts", "1:2000000000:1", "--out", &o],
        &[
            "--counts `1:2000000000:1`",
            "each from 1 to 10000000, at most 1000 counts",
        ],
    );
    refused(
        &[
            "sweep", "--counts", "1:200:1", "--reps", "10000", "--out", &o,
        ],
        &[
            "--counts and --reps: 200 counts × 10000 repetitions = 2000000 days, more than the 1000000 a sweep runs",
        ],
    );
    refused(
        &["sweep", "--reps", "100000", "--out", &o],
        &["'--reps <REPS>'", "from 1 to 10000"],
    );
    nothing_written(&out);
    refused(
        &["bench", "--requests", "11M", "--out", &o],
        &["--requests `11M`", "from 1 to 10000000"],
    );
    nothing_written(&out);
    let report = dir.join("load.json");
    let r = report.display().to_string();
    for (option, value, range) in [
        ("--clients", "1000000000", "from 1 to 100000"),
        ("--count", "0", "from 1 to 10000000"),
        ("--max-in-flight", "0", "from 1 to 1000000"),
    ] {
        let rate = ["--rate", "10"];
        let mut args = vec!["load", "--out", &r, option, value];
        if option == "--max-in-flight" {
            args.extend(rate);
        }
        refused(&args, &[&format!("for '{option} <N>'"), range]);
    }
    nothing_written(&report);
}

/// Two stations 3.86 km apart and a corridor between them with `props`, its LineString from
/// `ends`.
fn corridor(props: &str, ends: [f64; 2]) -> String {
    format!(
        r#"{{"type": "FeatureCollection", "features": [
  {{"type": "Feature", "geometry": {{"type": "Point", "coordinates": [103.8, 1.3]}}, "properties": {{"id": "A", "kind": "station"}}}},
  {{"type": "Feature", "geometry": {{"type": "Point", "coordinates": [103.8347, 1.3]}}, "properties": {{"id": "B", "kind": "station"}}}},
  {{"type": "Feature", "geometry": {{"type": "LineString", "coordinates": [[{}, 1.3], [{}, 1.3]]}}, "properties": {{"from": "A", "to": "B"{props}}}}}]}}"#,
        ends[0], ends[1]
    )
}

#[test]
fn corridor_lengths_and_ends_must_fit_their_nodes() {
    let dir = scratch_dir("corridors");
    let out = dir.join("out");
    let o = out.display().to_string();
    let ends = [103.8, 103.8347];
    for length in ["1", "1e300"] {
        let air = write(
            &dir,
            "air.geojson",
            corridor(&format!(r#", "length_m": {length}"#), ends),
        );
        refused(
            &["simulate", "--airspace", &air, "--count", "10", "--out", &o],
            &[
                &format!(
                    "{air}: feature 2 (`A-B`): field `length_m`: {length} m is not a possible length"
                ),
                "`A` and `B` are 3861.799 m apart (geodesic), so the corridor's length must be \
                 from 3857.937 to 38617.987 m",
                "at least that distance, less 1 m or 0.1 % if more; at most 10 times it",
            ],
        );
        nothing_written(&out);
    }
    // The LineString's positions are its nodes'.
    let air = write(&dir, "ends.geojson", corridor("", [103.8, 103.9]));
    refused(
        &["airspace", "info", "--airspace", &air],
        &[
            &format!("{air}: feature 2 (`A-B`): field `geometry.coordinates[1]`: [103.9, 1.3] is"),
            "from node `B` ([103.8347, 1.3])",
            "within 1 m",
        ],
    );
    // The same corridor with a length it can have is read.
    let air = write(&dir, "ok.geojson", corridor(r#", "length_m": 4000"#, ends));
    let ok = muse(&["airspace", "info", "--airspace", &air]);
    assert!(ok.status.success(), "{}", stderr(&ok));
}

/// A zone file of one ED-318 zone whose `type` and schedule entry are given.
fn zone(zone_type: &str, entry: &str) -> String {
    format!(
        r#"{{"type": "FeatureCollection", "features": [{{"type": "Feature",
  "properties": {{"identifier": "Z1", "type": "{zone_type}",
    "limitedApplicability": [{{"schedule": [{entry}]}}]}},
  "geometry": {{"type": "Polygon", "coordinates": [[[103.84, 1.27], [103.87, 1.27], [103.87, 1.30], [103.84, 1.30], [103.84, 1.27]]]}}}}]}}"#
    )
}

#[test]
fn zone_files_refuse_backwards_windows_unknown_types_and_no_zones() {
    let dir = scratch_dir("zones");
    let requests = write(&dir, "r.csv", REQUESTS);
    let out = dir.join("out");
    let o = out.display().to_string();
    let plan = |zones: &str, needles: &[&str]| {
        refused(
            &[
                "plan",
                "--requests",
                &requests,
                "--zones",
                zones,
                "--out",
                &o,
            ],
            needles,
        );
        nothing_written(&out);
    };
    // 10:00 to 09:00 would close the zone 23 hours a day.
    let backwards = write(
        &dir,
        "backwards.geojson",
        zone(
            "PROHIBITED",
            r#"{"day": ["ANY"], "startTime": "10:00:00+08:00", "endTime": "09:00:00+08:00"}"#,
        ),
    );
    plan(
        &backwards,
        &[
            &format!(
                "{backwards}: feature 0 (`Z1`): field \
                 `limitedApplicability[0].schedule[0].endTime`: the window ends (09:00) before \
                 it starts (10:00)"
            ),
            "close 23 h a day",
            "add \"overnight\": true to this schedule entry; otherwise give an endTime after the \
             startTime, up to 24:00",
        ],
    );
    // Said explicitly, an overnight window is read.
    let overnight = write(
        &dir,
        "overnight.geojson",
        zone(
            "PROHIBITED",
            r#"{"day": ["ANY"], "startTime": "22:00+08:00", "endTime": "06:00+08:00", "overnight": true}"#,
        ),
    );
    let ok = muse(&["airspace", "info", "--zones", &overnight]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    // An unknown type.
    let typo = write(
        &dir,
        "typo.geojson",
        zone(
            "PROHIBTED",
            r#"{"day": ["ANY"], "startTime": "10:00+08:00", "endTime": "12:00+08:00"}"#,
        ),
    );
    plan(
        &typo,
        &[&format!(
            "{typo}: feature 0 (`Z1`): field `type`: unknown zone type \"PROHIBTED\": expected \
             one of PROHIBITED, REQ_AUTHORISATION, REQ_AUTHORIZATION, CONDITIONAL, \
             NO_RESTRICTION, USPACE"
        )],
    );
    // No zone at all.
    let empty = write(
        &dir,
        "empty.geojson",
        r#"{"type": "FeatureCollection", "features": []}"#,
    );
    plan(
        &empty,
        &[&format!(
            "{empty}: the file holds no zone (no features): give a file with at least one zone, \
             or `--zones none` for none"
        )],
    );
}

#[test]
fn zero_counts_deadlines_and_horizons_are_refused() {
    let dir = scratch_dir("zeros");
    let out = dir.join("out");
    let o = out.display().to_string();
    refused(
        &["simulate", "--count", "0", "--out", &o],
        &[
            "invalid value '0' for '--count <COUNT>'",
            "from 1 to 10000000",
        ],
    );
    nothing_written(&out);
    let requests = write(&dir, "r.csv", REQUESTS);
    refused(
        &[
            "plan",
            "--requests",
            &requests,
            "--max-trip-min",
            "0",
            "--out",
            &o,
        ],
        &[
            "invalid value '0' for '--max-trip-min <MIN>'",
            "must be a number of minutes from 1 to 1440",
        ],
    );
    nothing_written(&out);
    let data = dir.join("data");
    let d = data.display().to_string();
    refused(
        &["serve", "--booking-horizon-days", "0", "--data", &d],
        &[
            "invalid value '0' for '--booking-horizon-days <DAYS>'",
            "must be a whole number of days from 1 to 3650",
        ],
    );
    nothing_written(&data);
}

#[test]
fn request_ids_follow_the_services_rule() {
    let dir = scratch_dir("ids");
    let out = dir.join("out");
    let o = out.display().to_string();
    for (id, shown) in [
        ("\"a,b\"", r#""a,b""#),
        ("\"say \"\"hi\"\"\"", r#""say \"hi\"""#),
        ("café", r#""café""#),
    ] {
        let requests = write(&dir, "r.csv", format!("{REQUESTS}{id},S040,S012,09:00\n"));
        refused(
            &["plan", "--requests", &requests, "--out", &o],
            &[&format!(
                "{requests}: line 3: field `id`: {shown} is not a valid id: an id is 1 to 128 \
                 characters among the ASCII letters and digits and `._~:-` (the service's rule \
                 too)"
            )],
        );
        nothing_written(&out);
    }
}

#[test]
fn messages_say_what_is_accepted() {
    let dir = scratch_dir("messages");
    let out = dir.join("out");
    let o = out.display().to_string();
    // A range, not "a number > 0".
    refused(
        &["simulate", "--max-flight-min", "1e12", "--out", &o],
        &[
            "invalid value '1e12' for '--max-flight-min <MIN>'",
            "must be a number of minutes from 1 to 1440",
        ],
    );
    // A negative number is the option's value, refused for its range, not "unexpected
    // argument '-3'".
    let err = refused(
        &["simulate", "--speed-kmh", "-30", "--out", &o],
        &[
            "invalid value '-30' for '--speed-kmh <KMH>'",
            "must be a speed in km/h from 1 to 1000",
        ],
    );
    assert!(!err.contains("unexpected argument"), "{err}");
    nothing_written(&out);
    // A requests file that is not UTF-8 names the line.
    let latin1 = write(
        &dir,
        "latin1.csv",
        b"id,origin,destination,departure\nr1,S012,S040,08:15\nr\xe9,S040,S012,09:00\n",
    );
    refused(
        &["plan", "--requests", &latin1, "--out", &o],
        &[&format!(
            "{latin1}: line 3: byte 2 of the line, 0xE9, is not UTF-8: save the file as UTF-8"
        )],
    );
    nothing_written(&out);
    // A missing tokens file is named once, with the reason once.
    let data = dir.join("data");
    let d = data.display().to_string();
    let tokens = dir.join("no-tokens.toml").display().to_string();
    let err = refused(&["serve", "--tokens", &tokens, "--data", &d], &[]);
    assert_eq!(
        err.trim_end(),
        format!("error: {tokens}: cannot read: No such file or directory (os error 2)")
    );
    nothing_written(&data);
}

#[test]
fn every_numeric_option_refuses_nan_infinity_negatives_and_states_its_range() {
    let dir = scratch_dir("numbers");
    let out = dir.join("out");
    let o = out.display().to_string();
    for (args, range) in [
        (
            vec!["simulate", "--node-separation-s", "NaN"],
            "from 0 to 3600",
        ),
        (
            vec!["simulate", "--max-ground-delay-s", "inf"],
            "from 0 to 86400",
        ),
        (
            vec!["simulate", "--battery-swap-s", "-1"],
            "from 0 to 86400",
        ),
        (
            vec!["simulate", "--battery-swap-s", "300", "--max-legs", "0"],
            "from 1 to 100",
        ),
        (
            vec!["simulate", "--synthetic", "grid", "--nodes", "-9"],
            "from 2 to 1000000",
        ),
        (
            vec![
                "simulate",
                "--synthetic",
                "grid",
                "--nodes",
                "9",
                "--spacing-m",
                "-1",
            ],
            "from 1 to 100000",
        ),
        (
            vec!["simulate", "--seed", "-1"],
            "from 0 to 18446744073709551615",
        ),
        (
            vec!["simulate", "--booking-lead-min", "0:1e9"],
            "from 0 to 43200",
        ),
        (vec!["serve", "--rate-limit", "-1"], "from 0 to 1000000"),
        (vec!["serve", "--idle-timeout-s", "-5"], "from 0.1 to 86400"),
        (vec!["load", "--timeout", "0"], "from 0.1 to 86400"),
        (vec!["load", "--lead-min", "-1:5"], "from 0 to 43200"),
        (
            vec!["verify", "--plans", "p.jsonl", "--max-listed", "-1"],
            "from 0 to 1000000",
        ),
        (vec!["airspace", "map", "--width", "0"], "from 100 to 20000"),
        (vec!["sweep", "--threads", "0"], "from 1 to 1024"),
    ] {
        let mut all = args.clone();
        if !matches!(args[0], "serve" | "load" | "verify" | "airspace") {
            all.extend(["--out", &o]);
        }
        let err = refused(&all, &["invalid value", range]);
        assert!(!err.contains("unexpected argument"), "{all:?}: {err}");
    }
    // Options whose value is a list or a pair read a leading `-` as their value too.
    for (args, message) in [
        (
            vec!["sweep", "--shard", "-1/3"],
            "shard `-1/3`: expected K/N with 0 <= K < N",
        ),
        (
            vec!["sweep", "--counts", "-5,10"],
            "each from 1 to 10000000",
        ),
        (
            vec!["bench", "--requests", "-5"],
            "`-5` is not a count of requests from 1 to 10000000",
        ),
    ] {
        let mut all = args.clone();
        all.extend(["--out", &o]);
        let err = refused(&all, &[message]);
        assert!(!err.contains("unexpected argument"), "{all:?}: {err}");
    }
    nothing_written(&out);
    // The ranges are in --help too.
    let help = muse(&["simulate", "--help"]);
    let text = String::from_utf8_lossy(&help.stdout);
    for range in [
        "from 1 to 1440",
        "from 1 to 1000",
        "from 1 to 10000000",
        "from 0 to 3600",
    ] {
        assert!(
            text.contains(range),
            "`{range}` in simulate --help:\n{text}"
        );
    }
}

#[test]
fn layer_options_out_of_range_are_refused() {
    let dir = scratch_dir("layers");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let run = |extra: &[&str], needles: &[&str]| {
        let mut args = vec!["simulate", "--count", "10", "--out", out];
        args.extend_from_slice(extra);
        refused(&args, needles);
        nothing_written(Path::new(out));
    };
    run(&["--layers", "0"], &["--layers", "from 1 to 64"]);
    run(&["--layers", "65"], &["--layers", "from 1 to 64"]);
    run(
        &["--layer-spacing-m", "0"],
        &["--layer-spacing-m", "from 0.001 to 1000"],
    );
    run(
        &["--climb-mps", "-5"],
        &["--climb-mps", "from 0.001 to 100"],
    );
    run(
        &["--layers", "2", "--climb-mps", "5.0004"],
        &["--climb-mps 5.0004", "whole millimetres per second"],
    );
    run(
        &["--heading-rule", "north"],
        &["--heading-rule", "none", "sectors"],
    );
}

/// Simulates a small day into `dir/day`; its plans file's lines.
fn simulated_plans(dir: &Path) -> Vec<String> {
    let day = dir.join("day");
    let o = muse(&[
        "simulate",
        "--count",
        "40",
        "--seed",
        "3",
        "--out",
        day.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    std::fs::read_to_string(day.join("plans.jsonl"))
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect()
}

/// A plans file has one line per request: a request id on a second line is refused as a
/// duplicate (both lines and the id named), never read as a flight in conflict with itself.
#[test]
fn a_request_id_twice_in_a_plans_file_is_refused() {
    let dir = scratch_dir("duplicate_ids");
    let lines = simulated_plans(&dir);
    let first = lines
        .iter()
        .position(|l| l.contains(r#""status":"planned""#))
        .expect("a planned line");
    let id = serde_json::from_str::<serde_json::Value>(&lines[first]).unwrap()["request"]
        .as_str()
        .unwrap()
        .to_owned();
    let mut twice = lines.clone();
    twice.push(lines[first].clone());
    let dup = write(&dir, "dup.jsonl", twice.join("\n") + "\n");
    let expected = format!(
        "dup.jsonl: line {}: field `request`: duplicate request id `{id}` (first on line {})",
        twice.len(),
        first + 1
    );
    let err = refused(&["verify", "--plans", &dup], &[&expected]);
    assert!(!err.contains("violat"), "{err}");
    let html = dir.join("view.html");
    refused(
        &["view", "--plans", &dup, "--out", html.to_str().unwrap()],
        &[&expected],
    );
    nothing_written(&html);
}

/// Timestamps of the years 0000–9999 are read, and MUSE plans those of the years 1000–8999
/// (UTC): a departure or booking outside them is refused naming the file, the line, the field
/// and the time as written, with or without zones; the first and last instants plan.
#[test]
fn departures_outside_the_planned_years_are_named() {
    let dir = scratch_dir("planned_years");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let rule = "outside the years MUSE plans: from 1000-01-01T00:00:00Z up to \
                9000-01-01T00:00:00Z (the years 1000 to 8999, UTC)";
    for (name, row, field, time) in [
        (
            "late.csv",
            "r1,S012,S040,9999-12-31T23:59:59+00:00",
            "departure",
            "9999-12-31T23:59:59+00:00",
        ),
        (
            "early.csv",
            "r1,S012,S040,0500-06-01T10:00:00+08:00",
            "departure",
            "0500-06-01T10:00:00+08:00",
        ),
        (
            "edge.csv",
            "r1,S012,S040,9000-01-01T00:00:00Z",
            "departure",
            "9000-01-01T00:00:00Z",
        ),
        (
            "booked.csv",
            "r1,S012,S040,2026-01-05T08:00:00+08:00,0999-12-31T23:59:59.999Z",
            "submitted",
            "0999-12-31T23:59:59.999Z",
        ),
    ] {
        let header = if field == "submitted" {
            "id,origin,destination,departure,submitted"
        } else {
            "id,origin,destination,departure"
        };
        let r = write(&dir, name, format!("{header}\n{row}\n"));
        let expected = format!("{name}: line 2: field `{field}`: `{time}` is {rule}");
        for zones in [&[][..], &["--zones", "none"][..]] {
            let mut args = vec!["plan", "--requests", &r, "--out", o];
            args.extend_from_slice(zones);
            let err = refused(&args, &[&expected]);
            assert!(!err.contains(" ms"), "{err}");
            nothing_written(&out);
        }
        refused(&["simulate", "--requests", &r, "--out", o], &[&expected]);
        nothing_written(&out);
    }
    // The first and the last instants planned, with the scenario's zones.
    for (name, departure) in [
        ("first.csv", "1000-01-01T00:00:00Z"),
        ("last.csv", "8999-12-31T23:59:59.999Z"),
    ] {
        let r = write(
            &dir,
            name,
            format!("id,origin,destination,departure\nr1,S012,S040,{departure}\n"),
        );
        let run = muse(&["plan", "--requests", &r, "--out", o]);
        assert_eq!(run.status.code(), Some(0), "{departure}: {}", stderr(&run));
        let plans = std::fs::read_to_string(out.join("plans.jsonl")).unwrap();
        assert!(plans.contains(r#""status":"planned""#), "{plans}");
    }
}

/// `muse serve --data` that is a file is refused once, naming the option, before serving.
#[test]
fn a_service_data_folder_that_is_a_file_is_refused_naming_data() {
    let dir = scratch_dir("serve_data_file");
    let file = write(&dir, "store", "not a folder\n");
    let err = refused(
        &["serve", "--listen", "127.0.0.1:0", "--data", &file],
        &[&format!("--data {file} is a regular file")],
    );
    assert_eq!(err.matches("os error").count(), 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        "not a folder\n",
        "left alone"
    );
}

/// A plans file cut short (a copy stopped mid-line) names its last line as cut short, not a
/// field `?` at "line 1 column N"; a line that is not JSON gives its column in the line.
#[test]
fn a_plans_line_cut_short_is_named_as_such() {
    let dir = scratch_dir("plans_cut_short");
    let text = simulated_plans(&dir).join("\n") + "\n";
    let cut = &text[..5000];
    assert!(!cut.ends_with('\n'));
    let last = cut.matches('\n').count() + 1;
    let file = write(&dir, "t.jsonl", cut);
    let err = refused(
        &["verify", "--plans", &file],
        &[&format!(
            "t.jsonl: line {last}: the line is cut short: it ends before its JSON object does"
        )],
    );
    assert!(
        !err.contains("`?`") && !err.contains("line 1 column"),
        "{err}"
    );
    let broken = text.replacen(r#","status":"#, r#";"status":"#, 1);
    let file = write(&dir, "b.jsonl", broken);
    let err = refused(
        &["verify", "--plans", &file],
        &["b.jsonl: line 1: not JSON: expected `,` or `}` at column "],
    );
    assert!(
        !err.contains("`?`") && !err.contains("line 1 column"),
        "{err}"
    );
}

/// A requests file with no request, and a plans file with no line, are refused naming the
/// file: never `planned 0 of 0 requests (100.0%)` nor a verification of nothing said OK.
#[test]
fn empty_requests_and_plans_files_are_refused() {
    let dir = scratch_dir("empty_inputs");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    for (name, text) in [
        ("header.csv", "id,origin,destination,departure\n"),
        (
            "customers.csv",
            "id,origin,destination,departure,origin_customer,destination_customer\n\n",
        ),
    ] {
        let r = write(&dir, name, text);
        let expected = format!("{name}: no requests: the file has its header and no row");
        refused(&["plan", "--requests", &r, "--out", o], &[&expected]);
        nothing_written(&out);
        refused(&["simulate", "--requests", &r, "--out", o], &[&expected]);
        nothing_written(&out);
    }
    for (name, text) in [("empty.jsonl", ""), ("blank.jsonl", "\n  \n\n")] {
        let plans = write(&dir, name, text);
        let expected = format!("{name}: no plans: the file has no line");
        let err = refused(&["verify", "--plans", &plans], &[&expected]);
        assert!(!err.contains("OK"), "{err}");
        let html = dir.join("view.html");
        refused(
            &["view", "--plans", &plans, "--out", html.to_str().unwrap()],
            &[&expected],
        );
        nothing_written(&html);
    }
}
