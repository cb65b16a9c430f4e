//! Upgrading: a data folder written by the earlier version (the append-only log `muse.log`)
//! is converted into the store once, at start, with every flight, cancellation, zone and
//! event kept — the id the earlier version stored twice included — and the log kept beside it.

use std::io::Write as _;

use muse_model::{Airspace, FlightParams, Instant, Millis, UtcOffset};
use muse_service::{Clock, Options, ServiceWorld, start};
use serde_json::{Value, json};

/// `A — B — C`, 1 km apart.
fn airspace() -> Airspace {
    Airspace::line(&[1_000.0, 1_000.0])
}

/// The world of these tests, its zone calendar resolved around `now`.
fn world(now: Instant) -> ServiceWorld {
    ServiceWorld::new(
        "import test".into(),
        airspace(),
        Vec::new(),
        FlightParams::default(),
        UtcOffset::SINGAPORE,
        Millis::from_secs(30 * 86_400),
        now,
    )
    .unwrap()
}

/// One record of the earlier version's log: `len | crc | JSON`.
fn record(out: &mut Vec<u8>, value: &Value) {
    let payload = value.to_string().into_bytes();
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
}

/// The earlier version's record of an answer.
fn flight(seq: u64, id: &str, stays: &[(&str, i64)], reason: Option<&str>, at: i64) -> Value {
    let path: Option<Vec<Value>> =
        (reason.is_none()).then(|| stays.iter().map(|(n, t)| json!([n, t, t])).collect());
    json!({"kind": "flight", "seq": seq, "id": id, "operator": "open",
           "origin": stays[0].0, "destination": stays[stays.len() - 1].0,
           "departure": stays[0].1, "answered": at, "path": path, "reason": reason,
           "free_flow": 120_000 * (stays.len() as i64 - 1), "expanded": 3})
}

/// The earlier version's log of a short day: three answers, a cancellation, a zone that
/// cancels a flight, an id stored a second time, a withdrawal, and a torn tail of 20 bytes.
fn legacy_log(fingerprint: &str, now: Instant) -> Vec<u8> {
    let t = |s: i64| now.0 + s * 1_000;
    let mut log = b"MUSE-LOG-V1\n\0\0\0\0".to_vec();
    record(&mut log, &json!({"kind": "header", "world": fingerprint}));
    record(
        &mut log,
        &flight(
            1,
            "r1",
            &[("A", t(600)), ("B", t(720)), ("C", t(840))],
            None,
            t(0),
        ),
    );
    record(
        &mut log,
        &flight(2, "r2", &[("B", t(1_200)), ("C", t(1_320))], None, t(1)),
    );
    record(
        &mut log,
        &flight(
            3,
            "r3",
            &[("A", t(600)), ("B", t(720))],
            Some("no_feasible_plan"),
            t(2),
        ),
    );
    record(
        &mut log,
        &json!({"kind": "cancel", "id": "r2", "at": t(10)}),
    );
    let feature = json!({"type": "Feature", "properties": {"identifier": "Z", "nodes": ["C"]},
                         "geometry": null})
    .to_string();
    record(
        &mut log,
        &json!({"kind": "zone", "id": "Z", "feature": feature, "announced": t(20),
                "outcomes": [{"seq": 1, "airborne": false, "outcome": "cancelled"}]}),
    );
    // The earlier version stored an id re-sent after its retention a second time.
    record(
        &mut log,
        &flight(4, "r1", &[("A", t(1_800)), ("B", t(1_920))], None, t(25)),
    );
    record(
        &mut log,
        &json!({"kind": "withdraw", "id": "Z", "at": t(30)}),
    );
    let whole = log.len();
    // A crash tore the last group: half a record, never acknowledged.
    record(
        &mut log,
        &flight(5, "r5", &[("B", t(3_000)), ("C", t(3_120))], None, t(40)),
    );
    log.truncate(whole + 20);
    log
}

#[tokio::test]
#[allow(clippy::too_many_lines)] // One story, told in order.
async fn a_log_of_the_earlier_version_is_converted_once_with_everything_kept() {
    let data = std::env::temp_dir().join(format!("muse-import-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    std::fs::create_dir_all(&data).unwrap();
    let now = Instant(
        ((std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_millis() as i64)
            / 1_000)
            * 1_000,
    );
    let clock = Clock::starting_at(now);
    let t = |s: i64| now.0 + s * 1_000;
    let log = legacy_log(&world(now).legacy_fingerprint(), now);
    std::fs::File::create(data.join("muse.log"))
        .unwrap()
        .write_all(&log)
        .unwrap();

    let mut options = Options::new(data.clone());
    options.clock = clock;
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let running = start(world(now), options, listener).await.unwrap();
    let report = running
        .restored
        .import
        .clone()
        .expect("the log was converted");
    assert_eq!(
        (
            report.records,
            report.flights,
            report.cancellations,
            report.zones,
            report.withdrawn,
            report.events,
            report.torn_bytes
        ),
        (8, 4, 1, 1, 1, 5, 20)
    );
    assert_eq!(report.renamed, [("r1".to_owned(), "r1#2".to_owned())]);
    assert_eq!(report.log, data.join("muse.log.imported"));
    assert!(!data.join("muse.log").exists() && data.join("muse.db").exists());
    // Still ahead: r1#2 only (r1 was cancelled by the zone, r2 by its operator).
    assert_eq!((running.restored.held, running.restored.flights), (1, 4));
    let base = format!("http://{}", running.addr);
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(running.serve_until(async {
        let _ = stopped.await;
    }));
    let http = reqwest::Client::new();
    let get = |path: String| {
        let http = http.clone();
        let base = base.clone();
        async move {
            let r = http.get(format!("{base}{path}")).send().await.unwrap();
            (r.status().as_u16(), r.json::<Value>().await.unwrap())
        }
    };
    let (_, r1) = get("/v1/flights/r1".into()).await;
    assert_eq!(
        (r1["status"].as_str(), r1["reason"].as_str()),
        (Some("cancelled"), Some("zone_announced"))
    );
    let (code, second) = get("/v1/flights/r1%232".into()).await;
    assert_eq!(
        (code, second["status"].as_str()),
        (200, Some("planned")),
        "{second}"
    );
    assert_eq!(get("/v1/flights/r2".into()).await.1["status"], "cancelled");
    assert_eq!(get("/v1/flights/r3".into()).await.1["status"], "rejected");
    assert_eq!(get("/v1/flights/r5".into()).await.0, 404);
    let (_, zones) = get("/v1/zones".into()).await;
    assert!(zones.to_string().contains("\"withdrawn\""), "{zones}");
    // The converted schedule holds r1#2: the same take-off at A is taken.
    let (code, v) = {
        let r = http
            .post(format!("{base}/v1/flights"))
            .header("content-type", "application/json")
            .body(
                json!({"id": "again", "origin": "A", "destination": "B",
                       "departure": Instant(t(1_800)).to_rfc3339(UtcOffset::SINGAPORE)})
                .to_string(),
            )
            .send()
            .await
            .unwrap();
        (r.status().as_u16(), r.json::<Value>().await.unwrap())
    };
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("no_feasible_plan")),
        "{v}"
    );
    let _ = stop.send(());
    server.await.unwrap().unwrap();

    // Event ids as the earlier version numbered them, in the store for anyone to query.
    let db = rusqlite::Connection::open(data.join("muse.db")).unwrap();
    let events: Vec<(i64, String, String)> = db
        .prepare(
            "SELECT e.id, e.kind, f.id FROM events e JOIN flights f ON f.seq = e.flight_seq \
             ORDER BY e.id",
        )
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let events: Vec<(i64, &str, &str)> = events
        .iter()
        .map(|(i, k, f)| (*i, k.as_str(), f.as_str()))
        .collect();
    assert_eq!(
        events,
        [
            (1, "planned", "r1"),
            (2, "planned", "r2"),
            (3, "cancelled", "r2"),
            (4, "cancelled", "r1"),
            (5, "planned", "r1#2"),
        ]
    );
    drop(db);
    std::fs::remove_dir_all(&data).unwrap();
}

/// A long conversion (or load) does not leave the service silent: it listens at once,
/// `/healthz` answers `starting` with how far it got, every other route `503` `starting`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_service_says_it_is_starting_while_it_converts() {
    const FLIGHTS: u64 = 60_000;
    let data = std::env::temp_dir().join(format!("muse-import-long-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    std::fs::create_dir_all(&data).unwrap();
    let now = Instant(1_767_571_200_000);
    let mut log = b"MUSE-LOG-V1\n\0\0\0\0".to_vec();
    record(
        &mut log,
        &json!({"kind": "header", "world": world(now).legacy_fingerprint()}),
    );
    for seq in 1..=FLIGHTS {
        let at = now.0 - 86_400_000 + seq as i64;
        record(
            &mut log,
            &flight(
                seq,
                &format!("f{seq}"),
                &[("A", at), ("B", at + 120_000)],
                Some("no_feasible_plan"),
                at,
            ),
        );
    }
    std::fs::write(data.join("muse.log"), &log).unwrap();
    let mut options = Options::new(data.clone());
    options.clock = Clock::starting_at(now);
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let launched = muse_service::launch(world(now), options, listener)
        .await
        .unwrap();
    let base = format!("http://{}", launched.addr);
    let http = reqwest::Client::new();
    let health = http.get(format!("{base}/healthz")).send().await.unwrap();
    assert_eq!(health.status().as_u16(), 503);
    let health: Value = health.json().await.unwrap();
    assert_eq!(health["status"], "starting", "{health}");
    assert!(health["progress"]["imported_records"].is_u64(), "{health}");
    let refused = http.get(format!("{base}/v1/flights")).send().await.unwrap();
    assert_eq!(refused.status().as_u16(), 503);
    assert_eq!(refused.headers()["retry-after"], "1");
    let refused: Value = refused.json().await.unwrap();
    assert_eq!(refused["error"]["code"], "starting");
    let running = launched.ready().await.unwrap();
    assert_eq!(running.restored.flights, FLIGHTS);
    let health: Value = http
        .get(format!("{base}/healthz"))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(
        (health["status"].as_str(), health["flights"].as_u64()),
        (Some("ok"), Some(FLIGHTS))
    );
    drop(running);
    let _ = std::fs::remove_dir_all(&data);
}
