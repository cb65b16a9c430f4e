//! `flights.csv` and `stays.csv` against golden files: every status of a real `muse serve`
//! session (`testdata/service`, its README tells it; the flights cancelled by their operator
//! are no plans record and have no row) and the multi-leg trips of `testdata/plans`.

use muse_formats::airspace_geojson::read_airspace;
use muse_formats::flights_csv::{FLIGHTS_COLUMNS, write_flights_csv};
use muse_formats::plans::{PlanRecord, read_plans};
use muse_formats::stays_csv::{STAYS_COLUMNS, write_stays_csv};
use muse_model::{Airspace, Instant, UtcOffset};

/// The records of a plans file of `testdata` and its airspace.
fn records(air: &str, plans: &str) -> (Airspace, Vec<PlanRecord>) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/testdata/");
    let read = |name: &str| std::fs::read_to_string(format!("{root}{name}")).unwrap();
    let airspace = read_airspace(&read(air), air).unwrap();
    let records = read_plans(&read(plans), plans, &airspace).unwrap();
    (airspace, records)
}

/// Local midnight of `date` in Singapore.
fn midnight(date: &str) -> Instant {
    Instant::parse_rfc3339(&format!("{date}T00:00:00+08:00")).unwrap()
}

/// Compares `text` with the golden file `testdata/tables/NAME`.
fn golden(name: &str, text: &str) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/testdata/tables/").to_owned() + name;
    let expected = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, expected, "{name} differs from its golden file");
}

#[test]
fn every_status_of_a_service_session() {
    let (air, records) = records("service/line.geojson", "service/flights.jsonl");
    let day = midnight("2026-11-25");
    let flights = write_flights_csv(&records, &air, UtcOffset::SINGAPORE, day);
    golden("service_flights.csv", &flights);
    let stays = write_stays_csv(&records, &air, UtcOffset::SINGAPORE, day);
    golden("service_stays.csv", &stays);
    // One row per record, every row as wide as the header.
    assert_eq!(flights.lines().count(), records.len() + 1);
    assert_eq!(flights.lines().next().unwrap(), FLIGHTS_COLUMNS.join(","));
    assert_eq!(stays.lines().next().unwrap(), STAYS_COLUMNS.join(","));
    for line in flights.lines() {
        assert_eq!(line.split(',').count(), FLIGHTS_COLUMNS.len(), "{line}");
    }
    for line in stays.lines() {
        assert_eq!(line.split(',').count(), STAYS_COLUMNS.len(), "{line}");
    }
}

#[test]
fn multi_leg_trips() {
    let (air, records) = records("plans/air.geojson", "plans/multi_leg.jsonl");
    let day = midnight("2026-01-05");
    golden(
        "multi_leg_flights.csv",
        &write_flights_csv(&records, &air, UtcOffset::SINGAPORE, day),
    );
    golden(
        "multi_leg_stays.csv",
        &write_stays_csv(&records, &air, UtcOffset::SINGAPORE, day),
    );
}

#[test]
fn a_cell_with_a_comma_or_a_quote_is_quoted() {
    let (air, mut records) = records("plans/air.geojson", "plans/multi_leg.jsonl");
    records.truncate(1);
    records[0].request = "r,1 \"x\"".into();
    let day = midnight("2026-01-05");
    let flights = write_flights_csv(&records, &air, UtcOffset::SINGAPORE, day);
    assert!(
        flights
            .lines()
            .nth(1)
            .unwrap()
            .starts_with("\"r,1 \"\"x\"\"\",planned,"),
        "{flights}"
    );
    let stays = write_stays_csv(&records, &air, UtcOffset::SINGAPORE, day);
    assert!(
        stays
            .lines()
            .nth(1)
            .unwrap()
            .starts_with("\"r,1 \"\"x\"\"\",1,1,A,"),
        "{stays}"
    );
}
