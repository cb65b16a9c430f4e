//! The parameters travel with the plans: `muse verify` and `muse view` check and draw a day
//! with the world and parameters its `summary.json` records (each option given overriding its
//! own, and said), and `muse simulate` writes the tables `flights.csv` and `stays.csv`, whose
//! totals are the summary's.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

/// A folder under the target directory for one test, removed if it exists.
fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn muse_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("muse runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn said(o: &Output) -> String {
    format!("{}{}", stdout(o), stderr(o))
}

/// `muse simulate` of a day with battery swaps into `DIR/out` (the day of the tests below).
fn swap_day(name: &str) -> PathBuf {
    let dir = scratch_dir(name);
    std::fs::create_dir_all(&dir).unwrap();
    let o = muse_in(
        &dir,
        &[
            "simulate",
            "--count",
            "600",
            "--battery-swap-s",
            "300",
            "--max-trip-min",
            "90",
            "--out",
            "out",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    dir
}

#[test]
fn a_swap_day_verifies_with_no_other_option() {
    let dir = swap_day("params-swap-day");
    let o = muse_in(&dir, &["verify", "--plans", "out/plans.jsonl"]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(stdout(&o).starts_with("OK: 600 lines read"), "{}", said(&o));
    let err = stderr(&o);
    assert!(
        err.starts_with(
            "parameters from out/summary.json: embedded singapore-77, zones \
             SG-CBD-DOWNTOWN-CORE; 30 km/h, battery 20 min, tau 5 s, exclusive edges, no ground \
             delay, battery swaps 300 s, deadline 90 min\n"
        ),
        "{err}"
    );
    // The same with the summary named.
    let o = muse_in(
        &dir,
        &[
            "verify",
            "--plans",
            "out/plans.jsonl",
            "--summary",
            "out/summary.json",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
}

#[test]
fn an_override_is_said_and_wins() {
    let dir = swap_day("params-override");
    let o = muse_in(
        &dir,
        &["verify", "--plans", "out/plans.jsonl", "--speed-kmh", "40"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", said(&o));
    let err = stderr(&o);
    assert!(
        err.contains("; 40 km/h, battery 20 min")
            && err.contains("\n  --speed-kmh 40 given: overrides out/summary.json's 30\n"),
        "{err}"
    );
    // An option given with the summary's own value is said too, and changes nothing.
    let o = muse_in(
        &dir,
        &[
            "verify",
            "--plans",
            "out/plans.jsonl",
            "--battery-swap-s",
            "300",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).contains("--battery-swap-s 300 given: as in out/summary.json"),
        "{}",
        stderr(&o)
    );
    // The world too: another zone file than the summary's (none).
    let root = env!("CARGO_MANIFEST_DIR");
    let stadium = format!("{root}/scenarios/singapore-77/stadium_zone.geojson");
    let o = muse_in(
        &dir,
        &["verify", "--plans", "out/plans.jsonl", "--zones", &stadium],
    );
    assert!(
        stderr(&o).contains(&format!(
            "--zones {stadium} given: overrides out/summary.json's zones (the airspace's own)"
        )),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_missing_summary_is_said_and_the_defaults_apply() {
    let dir = swap_day("params-missing");
    let alone = dir.join("alone");
    std::fs::create_dir_all(&alone).unwrap();
    std::fs::copy(dir.join("out/plans.jsonl"), alone.join("plans.jsonl")).unwrap();
    let o = muse_in(&dir, &["verify", "--plans", "alone/plans.jsonl"]);
    // Without the summary the swaps are off: the multi-leg plans break the rules.
    assert_eq!(o.status.code(), Some(1), "{}", said(&o));
    assert!(
        stderr(&o).starts_with(
            "no summary.json beside alone/plans.jsonl: the command line and the defaults: \
             embedded singapore-77, zones SG-CBD-DOWNTOWN-CORE; 30 km/h, battery 20 min, tau 5 \
             s, exclusive edges, no ground delay, no battery swaps\n"
        ),
        "{}",
        stderr(&o)
    );
    assert!(stdout(&o).contains("battery swaps are off"), "{}", said(&o));
    // A summary named but missing is an error (exit 2).
    let o = muse_in(
        &dir,
        &[
            "verify",
            "--plans",
            "alone/plans.jsonl",
            "--summary",
            "alone/summary.json",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains("--summary: cannot read alone/summary.json"),
        "{}",
        stderr(&o)
    );
    // `muse view` says where its world came from, too.
    let o = muse_in(
        &dir,
        &[
            "view",
            "--plans",
            "alone/plans.jsonl",
            "--out",
            "alone/view.html",
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).starts_with("no summary.json beside alone/plans.jsonl: "),
        "{}",
        stderr(&o)
    );
    let o = muse_in(
        &dir,
        &["view", "--plans", "out/plans.jsonl", "--out", "view.html"],
    );
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).starts_with("parameters from out/summary.json: embedded singapore-77"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn violations_give_rfc3339_local_times() {
    let dir = swap_day("params-rfc3339");
    let o = muse_in(
        &dir,
        &[
            "verify",
            "--plans",
            "out/plans.jsonl",
            "--battery-swap-s",
            "301",
            "--max-listed",
            "5",
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", said(&o));
    let out = stdout(&o);
    let listed: Vec<&str> = out.lines().filter(|l| l.starts_with("  ")).collect();
    assert!(!listed.is_empty(), "{out}");
    for line in listed.iter().filter(|l| !l.contains("… and")) {
        assert!(
            line.contains("less than the battery swap time S = 301.000s")
                && line.contains("2026-01-05T"),
            "{line}"
        );
        // Every instant is RFC 3339 in the scenario's offset; none is epoch seconds.
        assert!(!line.contains("1767"), "{line}");
        for word in line.split([' ', ',', '(', ')', '[', ']']) {
            if word.starts_with("2026-") {
                assert!(
                    word.len() == "2026-01-05T08:00:00.000+08:00".len() && word.ends_with("+08:00"),
                    "{word} in {line}"
                );
            }
        }
    }
}

/// The totals of `flights.csv` and `stays.csv` as a Python program computes them, with the
/// csv module and, when it is installed, pandas: a JSON object per reader.
const PYTHON: &str = r#"
import csv, json, sys
from datetime import datetime, timedelta
out = sys.argv[1]
midnight = datetime.fromisoformat("2026-01-05T00:00:00+08:00")
def totals(flights, stays):
    return {
        "rows": len(flights),
        "planned": sum(1 for f in flights if f["status"] == "planned"),
        "rejected": sum(1 for f in flights if f["status"] == "rejected"),
        "out_of_range": sum(1 for f in flights if f["reason"] == "out_of_range"),
        "no_feasible_plan": sum(1 for f in flights if f["reason"] == "no_feasible_plan"),
        "air_delay_s": sum(float(f["air_delay_s"]) for f in flights if f["air_delay_s"] not in ("", None)),
        "ground_delay_s": sum(float(f["ground_delay_s"]) for f in flights if f["ground_delay_s"] not in ("", None)),
        "total_delay_s": sum(float(f["total_delay_s"]) for f in flights if f["total_delay_s"] not in ("", None)),
        "expanded": sum(int(f["expanded"]) for f in flights),
        "swaps": sum(int(f["legs"]) - 1 for f in flights if f["legs"] not in ("", None)),
        "stays": len(stays),
        "hover_s": sum(float(s["hover_s"]) for s in stays),
    }
with open(f"{out}/flights.csv", newline="") as fh:
    flights = list(csv.DictReader(fh))
with open(f"{out}/stays.csv", newline="") as fh:
    stays = list(csv.DictReader(fh))
# Both time columns of every instant say the same.
for f in flights:
    for col in ("requested_departure", "takeoff", "landing"):
        if f[col]:
            t = datetime.fromisoformat(f[col])
            assert abs((t - midnight).total_seconds() - float(f[col + "_day_s"])) < 1e-6, (f, col)
for s in stays:
    for col in ("arrive", "depart"):
        t = datetime.fromisoformat(s[col])
        assert abs((t - midnight).total_seconds() - float(s[col + "_day_s"])) < 1e-6, (s, col)
print(json.dumps({"csv": totals(flights, stays)}))
try:
    import pandas as pd
except ImportError:
    print(json.dumps({"pandas": None}))
    sys.exit(0)
fl = pd.read_csv(f"{out}/flights.csv", keep_default_na=False, na_values=[""])
st = pd.read_csv(f"{out}/stays.csv")
for col in ("takeoff_day_s", "air_delay_s", "total_delay_s"):
    assert fl[col].dtype.kind == "f", (col, fl[col].dtype)
assert pd.to_datetime(fl["requested_departure"]).notna().all()
assert pd.to_datetime(st["arrive"]).notna().all()
records = lambda df: [{k: ("" if pd.isna(v) else v) for k, v in r.items()} for r in df.to_dict("records")]
print(json.dumps({"pandas": totals(records(fl), records(st))}))
"#;

#[test]
fn the_tables_load_in_python_and_add_up_to_the_summary() {
    let dir = swap_day("params-tables");
    let out = dir.join("out");
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let python = Command::new("python3")
        .arg("-c")
        .arg(PYTHON)
        .arg(&out)
        .output();
    let Ok(python) = python else {
        println!("python3 is not installed: the tables were not read with Python");
        return;
    };
    assert!(python.status.success(), "{}", said(&python));
    let mut readers = 0;
    for line in stdout(&python).lines() {
        let v: Value = serde_json::from_str(line).unwrap();
        let (reader, t) = v.as_object().unwrap().iter().next().unwrap();
        if t.is_null() {
            println!(
                "pandas is not installed: flights.csv and stays.csv were read with Python's csv module only; the pandas check was skipped"
            );
            continue;
        }
        readers += 1;
        let n = |k: &str| t[k].as_f64().unwrap();
        let count = |k: &str| t[k].as_u64().unwrap_or_else(|| panic!("{k} in {t}"));
        let s = |path: &[&str]| {
            path.iter()
                .fold(&summary, |v, k| &v[*k])
                .as_f64()
                .unwrap_or_else(|| panic!("{path:?} in {summary}"))
        };
        let whole = |path: &[&str]| {
            path.iter()
                .fold(&summary, |v, k| &v[*k])
                .as_u64()
                .unwrap_or_else(|| panic!("{path:?} in {summary}"))
        };
        assert_eq!(count("rows"), whole(&["requests"]), "{reader}");
        assert_eq!(count("planned"), whole(&["planned"]), "{reader}");
        assert_eq!(count("rejected"), whole(&["rejected"]), "{reader}");
        for reason in ["out_of_range", "no_feasible_plan"] {
            assert_eq!(
                count(reason),
                whole(&["rejected_by_reason", reason]),
                "{reader}"
            );
        }
        let planned = s(&["planned"]);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-3;
        assert!(
            close(n("air_delay_s") / planned, s(&["air_delay_s", "mean"])),
            "{reader}: {t}"
        );
        assert!(
            close(
                n("ground_delay_s") / planned,
                s(&["ground_delay_s", "mean"])
            ),
            "{reader}: {t}"
        );
        // No ground delay: the total delay is the air delay.
        assert!(close(n("total_delay_s"), n("air_delay_s")), "{reader}: {t}");
        assert_eq!(
            count("expanded"),
            whole(&["search", "expanded_total"]),
            "{reader}"
        );
        assert_eq!(count("swaps"), whole(&["legs", "swaps"]), "{reader}");
        assert!(count("swaps") > 0, "a swap day: {t}");
        // Each planned trip has one stay more per leg than it has corridors flown.
        let plans = std::fs::read_to_string(out.join("plans.jsonl")).unwrap();
        let stays: u64 = plans
            .lines()
            .map(|l| serde_json::from_str::<Value>(l).unwrap())
            .filter_map(|v| v["path"].as_array().map(|p| p.len() as u64))
            .sum();
        assert_eq!(count("stays"), stays, "{reader}");
    }
    assert!(readers >= 1, "{}", stdout(&python));
    // Without the tables when asked.
    let o = muse_in(
        &dir,
        &["simulate", "--count", "50", "--no-csv", "--out", "no-csv"],
    );
    assert!(o.status.success(), "{}", said(&o));
    assert!(!dir.join("no-csv/flights.csv").exists());
    assert!(!dir.join("no-csv/stays.csv").exists());
    assert!(dir.join("no-csv/plans.jsonl").exists());
}

#[test]
fn zone_files_travel_as_absolute_paths() {
    // Simulated from the repository with a relative zone file, verified from elsewhere.
    let dir = scratch_dir("params-zones");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("out").display().to_string();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let o = muse_in(
        root,
        &[
            "simulate",
            "--count",
            "2000",
            "--booking-lead-min",
            "0:120",
            "--zones",
            "scenarios/singapore-77/cbd_zone.geojson",
            "--zones",
            "scenarios/singapore-77/stadium_zone.geojson",
            "--out",
            &out,
        ],
    );
    assert!(o.status.success(), "{}", said(&o));
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    let stadium = root
        .join("scenarios/singapore-77/stadium_zone.geojson")
        .canonicalize()
        .unwrap();
    assert_eq!(
        summary["world"]["zones"][1].as_str(),
        Some(stadium.display().to_string().as_str()),
        "{summary}"
    );
    let o = muse_in(&dir, &["verify", "--plans", "out/plans.jsonl"]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stdout(&o).contains("2 zone(s), 1 announced during the day"),
        "{}",
        said(&o)
    );
    assert!(
        stderr(&o).contains("zones SG-CBD-DOWNTOWN-CORE, SG-NATIONAL-STADIUM-EVENT"),
        "{}",
        stderr(&o)
    );
}
