//! Demand from customers (docs/reference.md#airspace-from-pads): `muse demand --customers` draws
//! requests between customers and maps each to its nearest pad in reach; the file keeps the
//! customer ids; `muse simulate` and `muse plan` count unserved requests apart, in the plans, the
//! summary and the report, and `muse verify` reads them; bad customers files are refused.

use std::path::Path;

use crate::pads::{VIENNA, write};
use crate::run::{muse, said, stderr, stdout};
use crate::siting::customers;
use crate::support::scratch_dir;

/// Builds the Vienna test airspace into `dir`.
fn vienna_airspace(dir: &Path) -> String {
    let pads = write(dir, "pads.csv", VIENNA);
    let air = dir.join("vienna.geojson").display().to_string();
    let o = muse(&["airspace", "build", "--pads", &pads, "--out", &air]);
    assert!(o.status.success(), "{}", said(&o));
    air
}

/// A Vienna airspace and a requests file of demand from customers in `dir`: their paths,
/// the file's text and how many of its requests are unserved.
fn demand_file(dir: &Path) -> (String, String, String, usize) {
    std::fs::create_dir_all(dir).unwrap();
    let air = vienna_airspace(dir);
    let users = write(dir, "customers.csv", &customers());
    let requests = dir.join("requests.csv").display().to_string();
    let o = muse(&[
        "demand",
        "--airspace",
        &air,
        "--customers",
        &users,
        "--last-mile-m",
        "600",
        "--count",
        "500",
        "--out",
        &requests,
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let text = std::fs::read_to_string(&requests).unwrap();
    assert!(
        text.starts_with("id,origin,destination,departure,origin_customer,destination_customer\n"),
        "{text}"
    );
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 500);
    let unserved = rows
        .iter()
        .filter(|r| r[1].is_empty() || r[2].is_empty() || r[1] == r[2])
        .count();
    assert!(unserved > 0 && unserved < 500, "{unserved}");
    assert!(
        said(&o).contains(&format!("{} to fly, {unserved} unserved", 500 - unserved)),
        "{}",
        said(&o)
    );
    // Every customer id is one of the file's.
    assert!(
        rows.iter()
            .all(|r| r[4].starts_with('u') && r[5].starts_with('u'))
    );
    (air, requests, text, unserved)
}

#[test]
fn simulate_counts_unserved_requests_apart_and_keeps_the_file() {
    let dir = scratch_dir("customers-simulate");
    let (air, requests, text, unserved) = demand_file(&dir);
    let out = dir.join("sim");
    let o = muse(&[
        "simulate",
        "--airspace",
        &air,
        "--requests",
        &requests,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stdout(&o).contains(&format!("unserved      {unserved}")),
        "{}",
        said(&o)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["requests"], 500);
    assert_eq!(summary["unserved"], unserved);
    let planned = summary["planned"].as_u64().unwrap() as usize;
    let rejected = summary["rejected"].as_u64().unwrap() as usize;
    assert_eq!(planned + rejected + unserved, 500);
    let plans = std::fs::read_to_string(out.join("plans.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = plans
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 500);
    assert_eq!(
        lines.iter().filter(|l| l["reason"] == "unserved").count(),
        unserved
    );
    assert!(
        lines
            .iter()
            .any(|l| l["reason"] == "unserved" && l["origin"].is_null())
    );
    // The requests file written back is the one read, customer ids and all.
    let mut a: Vec<&str> = text.lines().collect();
    let written = std::fs::read_to_string(out.join("requests.csv")).unwrap();
    let mut b: Vec<&str> = written.lines().collect();
    a.sort_unstable();
    b.sort_unstable();
    assert_eq!(a, b);
}

#[test]
fn plan_and_verify_read_unserved_requests() {
    let dir = scratch_dir("customers-plan");
    let (air, requests, _, unserved) = demand_file(&dir);
    let out = dir.join("plan");
    let o = muse(&[
        "plan",
        "--airspace",
        &air,
        "--requests",
        &requests,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stdout(&o).contains(&format!("{unserved} unserved")),
        "{}",
        said(&o)
    );
    let o = muse(&[
        "verify",
        "--plans",
        out.join("plans.jsonl").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stdout(&o).contains(&format!("{unserved} unserved")),
        "{}",
        said(&o)
    );
    let o = muse(&[
        "view",
        "--plans",
        out.join("plans.jsonl").to_str().unwrap(),
        "--out",
        dir.join("view.html").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
}

#[test]
fn bad_customers_files_and_options_are_refused() {
    let dir = scratch_dir("customers-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let air = vienna_airspace(&dir);
    let out = dir.join("requests.csv");
    for (name, text, message) in [
        (
            "no-lat.csv",
            "id,lon\nu1,16.37\nu2,16.38\n",
            "no-lat.csv: line 1: field `lat`: the header has no `lat` column",
        ),
        (
            "dup.csv",
            "id,lon,lat\nu1,16.37,48.2\nu1,16.38,48.2\n",
            "dup.csv: line 3: field `id`: duplicate customer id `u1` (first on line 2)",
        ),
        (
            "lat.csv",
            "id,lon,lat\nu1,16.37,98.2\nu2,16.38,48.2\n",
            "lat.csv: line 2: field `lat`: 98.2 is outside -90 to 90",
        ),
        (
            "id.csv",
            "id,lon,lat\nu 1,16.37,48.2\nu2,16.38,48.2\n",
            "id.csv: line 2: field `id`: \"u 1\" is not a valid id",
        ),
        (
            "weight.csv",
            "id,lon,lat,weight\nu1,16.37,48.2,inf\nu2,16.38,48.2,1\n",
            "weight.csv: line 2: field `weight`: `inf` is not a weight",
        ),
        (
            "one.csv",
            "id,lon,lat\nu1,16.37,48.2\n",
            "1 customer: a demand needs at least 2",
        ),
    ] {
        let path = write(&dir, name, text);
        let o = muse(&[
            "demand",
            "--airspace",
            &air,
            "--customers",
            &path,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", said(&o));
        assert!(stderr(&o).contains(message), "{name}: {}", said(&o));
        assert!(!out.exists(), "{name}: nothing written");
    }
    let users = write(&dir, "customers.csv", &customers());
    for (args, message) in [
        (&["--od", "in-range"][..], "--od"),
        (&["--last-mile-m", "-1"], "-1"),
    ] {
        let mut all = vec!["demand", "--airspace", &air, "--customers", &users];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--out", out.to_str().unwrap()]);
        let o = muse(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", said(&o));
        assert!(stderr(&o).contains(message), "{args:?}: {}", said(&o));
        assert!(!out.exists());
    }
}

#[test]
fn singapore_hdb_car_parks_are_the_built_in_customers() {
    let o = muse(&[
        "demand",
        "--customers",
        "singapore-hdb",
        "--count",
        "50",
        "--out",
        "-",
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let text = stdout(&o);
    assert!(
        text.starts_with("id,origin,destination,departure,origin_customer,destination_customer\n")
    );
    assert_eq!(text.lines().count(), 51);
    assert!(
        stderr(&o).contains("between 2257 customers"),
        "{}",
        said(&o)
    );
}
