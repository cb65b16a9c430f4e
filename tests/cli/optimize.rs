//! Batch planning (docs/reference.md#batch-planning) end to end: `muse simulate --optimize` and
//! `muse plan --optimize` on the embedded Singapore default, checked by `muse verify`.

use crate::run::{muse, read_json, said};
use crate::support::scratch_dir;

#[test]
fn simulate_optimize_plans_more_than_fcfs_verified_and_repeats_with_plan() {
    let dir = scratch_dir("optimize-simulate");
    let out = dir.join("sim");
    let o = muse(&[
        "simulate",
        "--od",
        "in-range",
        "--count",
        "2000",
        "--optimize",
        "--iterations",
        "3000",
        "--out",
        out.to_str().unwrap(),
    ]);
    let text = said(&o);
    assert!(o.status.success(), "{text}");
    assert!(text.contains("verified      OK"), "{text}");
    assert!(
        text.contains("  fcfs          ") && text.contains("displaced"),
        "{text}"
    );
    let s = read_json(&out.join("summary.json"));
    let opt = &s["optimizer"];
    let (fcfs, best) = (
        opt["fcfs"]["planned"].as_u64().unwrap(),
        opt["optimized"]["planned"].as_u64().unwrap(),
    );
    assert!(best > fcfs, "{opt}");
    assert_eq!(s["planned"].as_u64(), Some(best), "{s}");
    assert_eq!(opt["iterations"].as_u64(), Some(3000), "{opt}");
    let displaced = opt["displaced_requests"].as_array().unwrap();
    assert_eq!(displaced.len() as u64, opt["displaced"].as_u64().unwrap());
    let v = muse(&[
        "verify",
        "--plans",
        out.join("plans.jsonl").to_str().unwrap(),
    ]);
    assert!(v.status.success(), "{}", said(&v));

    // The same requests through `muse plan` with the same budget give the same plans.
    let again = dir.join("plan");
    let p = muse(&[
        "plan",
        "--requests",
        out.join("requests.csv").to_str().unwrap(),
        "--optimize",
        "--iterations",
        "3000",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(p.status.success(), "{}", said(&p));
    assert_eq!(
        std::fs::read(out.join("plans.jsonl")).unwrap(),
        std::fs::read(again.join("plans.jsonl")).unwrap(),
        "muse plan --optimize differs from muse simulate --optimize on the same requests"
    );
}

#[test]
fn optimizer_options_need_optimize_and_are_range_checked() {
    let dir = scratch_dir("optimize-refused");
    let out = dir.join("o");
    let o = muse(&[
        "simulate",
        "--count",
        "10",
        "--iterations",
        "5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(said(&o).contains("--optimize"), "{}", said(&o));
    let o = muse(&[
        "simulate",
        "--count",
        "10",
        "--optimize",
        "--iterations",
        "-1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(said(&o).contains("from 0 to 1000000000"), "{}", said(&o));
    assert!(!out.exists(), "nothing is written on a refused option");
}
