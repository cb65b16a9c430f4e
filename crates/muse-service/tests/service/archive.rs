//! Retention without forgetting (docs/service.md#retention-without-forgetting), on both
//! stores: a service archiving after one day, its clock moved through a week of traffic (a
//! restart a day later each time, each start running a pass). The hot tables hold one day's
//! flights at each start; every archived id answers, read or retried, as first answered; the
//! files hold every archived flight, row for row; and the keys run on without reuse.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Duration;

use muse_model::{Instant, Millis, UtcOffset};
use muse_service::{Clock, StoreAt};
use serde_json::Value;

use crate::api::{Kind, Service, flight, ids, temp_dir};

/// Flights answered each day.
const PER_DAY: usize = 40;
/// Days of traffic.
const DAYS: i64 = 7;

/// The flights of the hot tables, by id (a listing reads nothing archived).
async fn hot(s: &Service) -> BTreeMap<String, Value> {
    let (code, list) = s.get("/v1/flights?limit=100000", None).await;
    assert_eq!(code, 200, "{list}");
    list["flights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["request"].as_str().unwrap().to_owned(), f.clone()))
        .collect()
}

/// A service on `store` with its clock at `start`, archiving after a day into `dir`.
async fn archiving(store: &StoreAt, start: Instant, dir: &Path) -> Service {
    let dir = dir.to_path_buf();
    Service::open(store.clone(), Vec::new(), move |o| {
        o.clock = Clock::starting_at(start);
        o.archive_after_days = Some(1);
        o.archive_dir = Some(dir);
    })
    .await
    .unwrap()
}

/// The number of rows of the gzip-compressed CSV file at `path`, its header aside.
fn rows_in(path: &Path) -> usize {
    use std::io::Read as _;
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    csv::Reader::from_reader(text.as_bytes()).records().count()
}

#[allow(clippy::too_many_lines)] // One week, told in order.
async fn a_week_of_traffic(kind: Kind) {
    let store = kind.store("archive-week");
    let dir = temp_dir(&format!("archive-week-files-{}", kind.name()));
    std::fs::create_dir_all(&dir).unwrap();
    // 06:00 in Singapore on a Monday; each day's flights leave between 06:10 and 16:00.
    let monday = Instant::parse_rfc3339("2026-03-02T06:00:00+08:00").unwrap();
    let mut answered: BTreeMap<String, (u16, Value)> = BTreeMap::new();
    let mut by_day: Vec<Vec<String>> = Vec::new();
    let legs = [("A", "C"), ("C", "A"), ("A", "B"), ("B", "C"), ("X", "Y")];
    for day in 0..DAYS {
        let start = monday + Millis::from_secs(day * 86_400);
        let s = archiving(&store, start, &dir).await;
        // The pass at the start leaves exactly yesterday's flights hot (those of the days
        // before it landed more than a whole day ago).
        let want: std::collections::BTreeSet<&String> = by_day
            .last()
            .map(|d| d.iter().collect())
            .unwrap_or_default();
        let mut left = hot(&s).await;
        for _ in 0..200 {
            if left.len() == want.len() {
                break;
            }
            tokio::time::sleep(Duration::from_millis(25)).await;
            left = hot(&s).await;
        }
        assert_eq!(
            left.keys().collect::<std::collections::BTreeSet<_>>(),
            want,
            "day {day}: the hot tables hold yesterday's flights only"
        );
        // Every id answered before reads, and is retried, as first answered.
        for (id, (_, first)) in &answered {
            assert_eq!(
                s.get(&format!("/v1/flights/{id}"), None).await,
                (200, first.clone()),
                "day {day}: {id}"
            );
        }
        for (id, (code, first)) in answered.iter().step_by(7) {
            let body = serde_json::json!({
                "id": id,
                "origin": first["origin"],
                "destination": first["destination"],
                "departure": first["requested_departure"],
            });
            assert_eq!(
                s.post(None, &body).await,
                (*code, first.clone()),
                "retry of {id}"
            );
        }
        let mut today = Vec::new();
        for k in 0..PER_DAY {
            let (from, to) = legs[k % legs.len()];
            let at =
                (start + Millis::from_secs(600 + 881 * k as i64)).to_rfc3339(UtcOffset::SINGAPORE);
            let id = format!("d{day}-{k}");
            let (code, v) = s.post(None, &flight(&id, from, to, &at)).await;
            assert!(code == 200 || code == 201, "{v}");
            answered.insert(id.clone(), (code, v));
            today.push(id);
        }
        by_day.push(today);
        let _ = s.stop().await;
    }
    // The files: one pair per archived day, holding each of its flights.
    for (day, ids) in by_day.iter().enumerate().take(DAYS as usize - 2) {
        let date = (monday + Millis::from_secs(day as i64 * 86_400))
            .local_date(UtcOffset::SINGAPORE)
            .to_string();
        let flights = dir.join(format!("flights-{date}.csv.gz"));
        assert_eq!(rows_in(&flights), ids.len(), "{}", flights.display());
        assert!(dir.join(format!("events-{date}.csv.gz")).exists());
    }
    // A new flight after a week takes a new number: the keys of archived flights are not
    // given again.
    let start = monday + Millis::from_secs(DAYS * 86_400);
    let s = archiving(&store, start, &dir).await;
    let at = (start + Millis::from_secs(600)).to_rfc3339(UtcOffset::SINGAPORE);
    let (code, v) = s.post(None, &flight("last", "A", "C", &at)).await;
    assert_eq!(code, 201, "{v}");
    let (_, list) = s
        .get(&format!("/v1/flights?after={}", answered.len()), None)
        .await;
    assert_eq!(ids(&list), ["last"], "{list}");
    let _ = s.stop().await;
    let restarted = Service::open(store, Vec::new(), |_| {}).await.unwrap();
    assert_eq!(
        restarted.get("/v1/flights/last", None).await,
        (200, v),
        "the last flight reads back after a restart that checks the last keys"
    );
    // A listener resuming from before the archived events is told where they are.
    let mut stream = reqwest::Client::new()
        .get(format!("{}/v1/events", restarted.base))
        .header("last-event-id", "0")
        .send()
        .await
        .unwrap();
    let first = stream.chunk().await.unwrap().unwrap();
    let first = String::from_utf8_lossy(&first);
    assert!(
        first.starts_with(": events after 0 up to") && first.contains("events-DAY.csv.gz"),
        "{first}"
    );
    drop(stream);
    drop(restarted);
    let _ = std::fs::remove_dir_all(&dir);
}

crate::api::on_both_stores!(a_week_of_traffic);
