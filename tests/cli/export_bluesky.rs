//! `muse export bluesky`: plans files written as BlueSky scenarios, compared with the golden
//! files of `crates/muse-export/testdata/bluesky` (every status of a real `muse serve` session,
//! multi-leg trips, a layered day); bad inputs refused with exit code 2 and a message naming
//! what is wrong; an input never replaced by the output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn muse(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("muse runs")
}

fn said(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A folder under the target directory for one test, emptied.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("export_bluesky_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A file of `crates/muse-formats/testdata`, as an absolute path.
fn testdata(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates/muse-formats/testdata")
        .join(name)
        .display()
        .to_string()
}

/// Exports with `args` into `DIR/out.scn` and compares it with the golden file `name`.
fn golden(name: &str, args: &[&str]) {
    let dir = scratch(name);
    let mut all = vec!["export", "bluesky", "--out", "out.scn"];
    all.extend_from_slice(args);
    let o = muse(&dir, &all);
    assert!(o.status.success(), "{}", said(&o));
    let written = std::fs::read_to_string(dir.join("out.scn")).unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates/muse-export/testdata/bluesky")
        .join(name);
    let expected = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        written,
        expected,
        "{name} differs from its golden file {}",
        path.display()
    );
}

/// Runs `args` in `dir` and checks that it is refused with exit code 2, saying `message`.
fn refused(dir: &Path, args: &[&str], message: &str) {
    let o = muse(dir, args);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {}", said(&o));
    assert!(said(&o).contains(message), "{args:?}: {}", said(&o));
}

#[test]
fn every_status_of_a_service_session() {
    // Three flights land: a1 (diverted to B), e1 (replanned: it hovers at its origin, then at
    // B) and a3; k1, left in contingency, lands nowhere, and the rejected and cancelled
    // requests write nothing.
    golden(
        "service.scn",
        &[
            "--plans",
            &testdata("service/flights.jsonl"),
            "--airspace",
            &testdata("service/line.geojson"),
        ],
    );
}

#[test]
fn multi_leg_trips_are_one_aircraft_a_leg() {
    golden(
        "multi_leg.scn",
        &[
            "--plans",
            &testdata("plans/multi_leg.jsonl"),
            "--airspace",
            &testdata("plans/air.geojson"),
        ],
    );
}

#[test]
fn a_layered_day_climbs_at_its_nodes() {
    golden(
        "layered.scn",
        &[
            "--plans",
            &testdata("plans/layered.jsonl"),
            "--airspace",
            &testdata("plans/air.geojson"),
            "--layers",
            "2",
            "--heading-rule",
            "sectors",
        ],
    );
}

#[test]
fn the_type_and_speed_are_written_and_standard_output_works() {
    let dir = scratch("stdout");
    let plans = testdata("plans/multi_leg.jsonl");
    let air = testdata("plans/air.geojson");
    let o = muse(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            &plans,
            "--airspace",
            &air,
            "--type",
            "Amzn",
            "--speed-kmh",
            "54",
            "--out",
            "-",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("# BlueSky scenario"), "{text}");
    assert!(text.contains(">CRE R1L1 Amzn "), "{text}");
    assert!(text.contains("# Cruise 54 km/h true airspeed"), "{text}");
    // The one-line result goes to standard error when the scenario takes standard output.
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("wrote standard output: 3 flights (5 BlueSky aircraft)"),
        "{err}"
    );
    assert!(std::fs::read_dir(&dir).unwrap().next().is_none());
}

#[test]
fn bad_inputs_are_refused() {
    let dir = scratch("bad");
    let air = testdata("plans/air.geojson");
    let plans = testdata("plans/multi_leg.jsonl");
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            "missing.jsonl",
            "--airspace",
            &air,
            "--out",
            "x.scn",
        ],
        "missing.jsonl",
    );
    std::fs::write(
        dir.join("bad.jsonl"),
        "{\"request\": \"r1\", \"status\": \"planned\", \"surprise\": 1}\n",
    )
    .unwrap();
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            "bad.jsonl",
            "--airspace",
            &air,
            "--out",
            "x.scn",
        ],
        "bad.jsonl: line 1: field `surprise`",
    );
    // A plan through a node the airspace does not have.
    let text = std::fs::read_to_string(&plans)
        .unwrap()
        .replace("\"node\":\"B\"", "\"node\":\"NOWHERE\"");
    std::fs::write(dir.join("unknown.jsonl"), text).unwrap();
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            "unknown.jsonl",
            "--airspace",
            &air,
            "--out",
            "x.scn",
        ],
        "NOWHERE",
    );
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            &plans,
            "--airspace",
            &air,
            "--type",
            "M600;DEL",
            "--out",
            "x.scn",
        ],
        "--type: aircraft type `M600;DEL`",
    );
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            &plans,
            "--airspace",
            &air,
            "--speed-kmh",
            "-3",
            "--out",
            "x.scn",
        ],
        "--speed-kmh",
    );
    assert!(!dir.join("x.scn").exists());
}

#[test]
fn an_input_is_never_replaced() {
    let dir = scratch("clobber");
    let o = muse(
        &dir,
        &[
            "simulate", "--count", "20", "--from", "08:00", "--to", "08:10", "--out", "day",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    let plans = std::fs::read_to_string(dir.join("day/plans.jsonl")).unwrap();
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            "day/plans.jsonl",
            "--out",
            "day/plans.jsonl",
        ],
        "--out day/plans.jsonl is the input --plans day/plans.jsonl",
    );
    refused(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            "day/plans.jsonl",
            "--out",
            "day/summary.json",
        ],
        "--out day/summary.json is the input the summary beside --plans",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("day/plans.jsonl")).unwrap(),
        plans
    );
    // The summary beside the plans gives the world and speed: one flight a planned line.
    let o = muse(
        &dir,
        &[
            "export",
            "bluesky",
            "--plans",
            "day/plans.jsonl",
            "--out",
            "day.scn",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        said(&o).contains("parameters from day/summary.json"),
        "{}",
        said(&o)
    );
    let planned = plans.matches("\"status\":\"planned\"").count();
    let scn = std::fs::read_to_string(dir.join("day.scn")).unwrap();
    assert_eq!(scn.matches(">CRE ").count(), planned);
    assert_eq!(scn.matches(" DO DEL ").count(), planned);
}
