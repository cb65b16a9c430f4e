//! Requests files: the sample fixtures (with and without the `submitted` column), the
//! writer's golden output, header and `submitted` errors, and the write/read round trip.

use std::path::PathBuf;

use muse_formats::Location;
use muse_formats::airspace_geojson::AirspaceFile;
use muse_formats::day::LocalDay;
use muse_formats::requests::{read_requests, read_requests_file, write_requests};
use muse_model::testing::request;
use muse_model::{Airspace, Instant, Millis, Request, UtcOffset};
use proptest::prelude::*;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("testdata/requests")
        .join(name)
}

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap()
}

fn air() -> Airspace {
    AirspaceFile::read(&fixture("air.geojson"))
        .unwrap()
        .airspace
}

const DAY: LocalDay = LocalDay {
    date: jiff::civil::date(2026, 1, 5),
    offset: UtcOffset::SINGAPORE,
};

fn at(text: &str) -> Instant {
    Instant::parse_rfc3339(text).unwrap()
}

#[test]
fn four_column_file_is_written_back_byte_identical() {
    let air = air();
    let reqs = read_requests_file(&fixture("paper.csv"), &air, DAY).unwrap();
    assert_eq!(reqs.len(), 3);
    assert!(reqs.iter().all(|r| r.submitted == r.departure));
    assert_eq!(
        write_requests(&reqs, &air, UtcOffset::SINGAPORE),
        fixture_text("paper.csv"),
        "without bookings ahead the file keeps its four columns"
    );
}

#[test]
fn reads_the_booked_sample() {
    let air = air();
    let reqs = read_requests_file(&fixture("booked.csv"), &air, DAY).unwrap();
    let ids: Vec<&str> = reqs.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(ids, ["r1", "r2", "r3", "r4"]);
    assert_eq!(reqs[0].departure, at("2026-01-05T08:00:00+08:00"));
    assert_eq!(reqs[0].submitted, at("2026-01-05T07:30:00+08:00"));
    // An empty cell: submitted at departure.
    assert_eq!(reqs[1].submitted, reqs[1].departure);
    assert_eq!(reqs[1].departure, at("2026-01-05T08:07:30.250+08:00"));
    // RFC 3339 in another offset, the day before in UTC.
    assert_eq!(
        reqs[2].departure - reqs[2].submitted,
        Millis::from_secs(5 * 3_600 + 45 * 60)
    );
    assert_eq!(reqs[3].submitted, reqs[3].departure);
    assert_eq!(
        (reqs[2].origin, reqs[2].destination),
        (air.node_id("S002").unwrap(), air.node_id("S003").unwrap())
    );
}

#[test]
fn booked_sample_is_written_as_the_golden_file_and_reads_back() {
    let air = air();
    let reqs = read_requests_file(&fixture("booked.csv"), &air, DAY).unwrap();
    let text = write_requests(&reqs, &air, UtcOffset::SINGAPORE);
    assert_eq!(text, fixture_text("booked.expected.csv"));
    let back = read_requests(&text, "out.csv", &air, DAY).unwrap();
    assert_eq!(back, reqs);
    assert_eq!(write_requests(&back, &air, UtcOffset::SINGAPORE), text);
}

#[test]
fn bad_headers_name_file_line_one_and_the_column() {
    let air = air();
    let e = read_requests_file(&fixture("extra_column.csv"), &air, DAY).unwrap_err();
    assert!(e.file.ends_with("extra_column.csv"), "{e}");
    assert_eq!(e.location, Location::Line(1));
    assert_eq!(e.field.as_deref(), Some("priority"));
    assert_eq!(
        e.message,
        "unknown column; the header must be id,origin,destination,departure, optionally \
         followed by submitted, and by origin_customer,destination_customer"
    );
    let e = read_requests_file(&fixture("missing_column.csv"), &air, DAY).unwrap_err();
    assert!(e.file.ends_with("missing_column.csv"), "{e}");
    assert_eq!(e.location, Location::Line(1));
    assert_eq!(e.field.as_deref(), Some("destination"));
    assert!(e.message.starts_with("missing column"), "{e}");
}

#[test]
fn submitted_after_departure_names_file_line_and_field() {
    let e = read_requests_file(&fixture("submitted_after_departure.csv"), &air(), DAY).unwrap_err();
    assert!(e.file.ends_with("submitted_after_departure.csv"), "{e}");
    assert_eq!(e.location, Location::Line(3));
    assert_eq!(e.field.as_deref(), Some("submitted"));
    assert!(
        e.message
            .starts_with("`2026-01-05T08:30:00+08:00` is later than the departure `08:00`"),
        "{e}"
    );
}

fn arb_requests() -> impl Strategy<Value = Vec<Request>> {
    let pairs = [(0, 1), (1, 0), (1, 2), (2, 1), (0, 2), (2, 0)];
    prop::collection::vec(
        (
            prop::sample::select(pairs.to_vec()),
            1_767_571_200_000_i64..1_767_657_600_000,
            prop::option::weighted(0.3, 0_i64..86_400_000),
        ),
        // At least one: a file with no request is refused (requests::tests).
        1..12,
    )
    .prop_map(|rows| {
        rows.into_iter()
            .enumerate()
            .map(|(i, ((o, d), departure, lead))| Request {
                submitted: Instant(departure - lead.unwrap_or(0)),
                ..request(&format!("r{i}"), o, d, departure)
            })
            .collect()
    })
}

proptest! {
    #[test]
    fn written_requests_read_back(reqs in arb_requests()) {
        let air = air();
        let text = write_requests(&reqs, &air, UtcOffset::SINGAPORE);
        let booked = reqs.iter().any(|r| r.submitted != r.departure);
        prop_assert_eq!(text.starts_with("id,origin,destination,departure,submitted\n"), booked);
        let back = read_requests(&text, "gen.csv", &air, DAY)
            .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(back, reqs);
    }
}
