//! The day an airspace file carries: built from real pads in Vienna (`examples/vienna-pads.csv`,
//! Wiener Linien stops) with `--time-zone Europe/Vienna`, a simulated day's requests, plans and
//! tables are in Vienna's clock (`+01:00` in January, `+02:00` in July), its verification and
//! export keep the day; without a time zone the default's (`+08:00`) is said on standard error;
//! a day that cannot be made is refused before any work.

use std::path::{Path, PathBuf};

use crate::run::{muse, said, stderr};
use crate::support::scratch_dir;

/// The real Vienna pads shipped with the examples.
fn vienna_pads() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples/vienna-pads.csv")
        .display()
        .to_string()
}

fn build(out: &Path, extra: &[&str]) -> std::process::Output {
    let pads = vienna_pads();
    let mut args = vec!["airspace", "build", "--pads", &pads, "--out"];
    args.push(out.to_str().unwrap());
    args.extend_from_slice(extra);
    muse(&args)
}

/// The departures of a requests file, as written.
fn departures(requests: &Path) -> Vec<String> {
    std::fs::read_to_string(requests)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().to_owned())
        .collect()
}

#[test]
fn a_vienna_day_is_planned_and_written_in_vienna_time() {
    let dir = scratch_dir("airspace-day-vienna");
    std::fs::create_dir_all(&dir).unwrap();
    let air = dir.join("vienna.geojson");
    let built = build(&air, &["--time-zone", "Europe/Vienna"]);
    assert!(built.status.success(), "{}", said(&built));
    assert!(
        stderr(&built).contains("its day: 2026-01-05 at +01:00 (Europe/Vienna)"),
        "{}",
        said(&built)
    );
    let text = std::fs::read_to_string(&air).unwrap();
    assert!(text.starts_with(
        "{\"type\": \"FeatureCollection\", \"date\": \"2026-01-05\", \"utc_offset\": \"+01:00\", \
         \"time_zone\": \"Europe/Vienna\", \"features\": [\n"
    ));

    let out = dir.join("out");
    let sim = muse(&[
        "simulate",
        "--airspace",
        air.to_str().unwrap(),
        "--count",
        "300",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(sim.status.success(), "{}", said(&sim));
    assert!(
        said(&sim).contains(
            "generated: 300 requests, 08:00–20:00 on 2026-01-05 at +01:00 (Europe/Vienna),"
        ),
        "{}",
        said(&sim)
    );
    // Generated departures lie in 08:00–20:00 of Vienna's clock, written at Vienna's offset.
    let deps = departures(&out.join("requests.csv"));
    assert_eq!(deps.len(), 300);
    for d in &deps {
        assert!(d.starts_with("2026-01-05T") && d.ends_with("+01:00"), "{d}");
        let hour: u32 = d[11..13].parse().unwrap();
        assert!((8..20).contains(&hour), "{d}");
    }
    let plans = std::fs::read_to_string(out.join("plans.jsonl")).unwrap();
    assert!(plans.contains("\"takeoff\":\"2026-01-05T"));
    assert!(
        !plans.contains("+08:00"),
        "a Singapore time in a Vienna day"
    );
    let flights = std::fs::read_to_string(out.join("flights.csv")).unwrap();
    assert!(flights.contains("+01:00") && !flights.contains("+08:00"));

    // Verified again from the file, the day is the file's; exported, the file keeps it.
    let verified = muse(&[
        "verify",
        "--plans",
        out.join("plans.jsonl").to_str().unwrap(),
    ]);
    assert!(verified.status.success(), "{}", said(&verified));
    let again = dir.join("again.geojson");
    let exported = muse(&[
        "airspace",
        "export",
        "--airspace",
        air.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(exported.status.success(), "{}", said(&exported));
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);

    // Bare clock times in a requests file are Vienna's too.
    let reqs = dir.join("requests.csv");
    let (a, b) = {
        let pads = std::fs::read_to_string(vienna_pads()).unwrap();
        let ids: Vec<String> = pads
            .lines()
            .skip(1)
            .take(2)
            .map(|l| l.split(',').next().unwrap().to_owned())
            .collect();
        (ids[0].clone(), ids[1].clone())
    };
    std::fs::write(
        &reqs,
        format!("id,origin,destination,departure\nr1,{a},{b},09:30\n"),
    )
    .unwrap();
    let planned = dir.join("planned");
    let plan = muse(&[
        "plan",
        "--airspace",
        air.to_str().unwrap(),
        "--requests",
        reqs.to_str().unwrap(),
        "--out",
        planned.to_str().unwrap(),
    ]);
    assert!(plan.status.success(), "{}", said(&plan));
    let line = std::fs::read_to_string(planned.join("plans.jsonl")).unwrap();
    assert!(
        line.contains("\"requested_departure\":\"2026-01-05T09:30:00.000+01:00\""),
        "{line}"
    );
}

#[test]
fn a_summer_date_takes_the_zones_summer_offset_and_a_fixed_offset_is_kept() {
    let dir = scratch_dir("airspace-day-summer");
    std::fs::create_dir_all(&dir).unwrap();
    let air = dir.join("summer.geojson");
    let built = build(
        &air,
        &["--time-zone", "Europe/Vienna", "--date", "2026-07-06"],
    );
    assert!(built.status.success(), "{}", said(&built));
    let text = std::fs::read_to_string(&air).unwrap();
    assert!(text.contains("\"date\": \"2026-07-06\", \"utc_offset\": \"+02:00\""));
    let fixed = dir.join("fixed.geojson");
    let built = build(&fixed, &["--utc-offset", "-05:00"]);
    assert!(built.status.success(), "{}", said(&built));
    let text = std::fs::read_to_string(&fixed).unwrap();
    assert!(text.contains("\"date\": \"2026-01-05\", \"utc_offset\": \"-05:00\", \"features\""));
}

#[test]
fn without_a_time_zone_the_default_day_is_said_and_bad_days_are_refused_before_work() {
    let dir = scratch_dir("airspace-day-refused");
    std::fs::create_dir_all(&dir).unwrap();
    let air = dir.join("plain.geojson");
    let built = build(&air, &[]);
    assert!(built.status.success(), "{}", said(&built));
    assert!(
        stderr(&built).contains("note: no --time-zone: its day is the default scenario's"),
        "{}",
        said(&built)
    );
    assert!(
        std::fs::read_to_string(&air)
            .unwrap()
            .starts_with("{\"type\": \"FeatureCollection\", \"features\": [\n")
    );

    for (extra, message) in [
        (
            &["--time-zone", "Europe/Wien"][..],
            "--time-zone: `Europe/Wien` is not a time zone of the IANA database",
        ),
        (
            &["--date", "2026-07-01"][..],
            "--date: a date needs a time zone or a UTC offset",
        ),
        (
            &["--utc-offset", "+1"][..],
            "--utc-offset: `+1` is not a UTC offset",
        ),
        (
            &["--time-zone", "Europe/Vienna", "--date", "5.7.2026"][..],
            "--date: `5.7.2026` is not a date such as 2026-01-05",
        ),
    ] {
        let out = dir.join("refused.geojson");
        let o = build(&out, extra);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", said(&o));
        assert!(stderr(&o).contains(message), "{extra:?}: {}", said(&o));
        assert!(!out.exists(), "{extra:?}: an output after a refusal");
    }
}
