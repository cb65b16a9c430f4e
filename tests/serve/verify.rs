//! What a user of `muse serve` checks with `muse verify`: the service's flights saved as JSON
//! Lines (`curl -s localhost:8080/v1/flights | jq -c '.flights[]' > p.jsonl`), every status
//! included, and the answers to departures the service must read exactly (year 9999) or
//! refuse for what they are (a leap second).
//!
//! The airspace is `crates/muse-formats/testdata/service/line.geojson`: `A — B — C` 1 km apart,
//! `F` out of range beyond `C`, and a separate pair `X — Y`. The session is the one that
//! folder's README describes: two flights take off 1.5 s after booking, zones closing `C` and
//! `Y` are announced 2 s after it, a flight is cancelled by its operator before any zone and
//! another after a zone replanned it.

use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant as WallInstant};

use muse_model::{Instant, Millis, UtcOffset};
use serde_json::{Value, json};

use crate::support::{scratch_dir, start};

fn testdata(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("crates/muse-formats/testdata/service")
        .join(name)
        .display()
        .to_string()
}

async fn send(
    http: &reqwest::Client,
    method: reqwest::Method,
    url: String,
    body: Option<Value>,
) -> (u16, Value) {
    let mut r = http.request(method, url);
    if let Some(b) = body {
        r = r
            .header("content-type", "application/json")
            .body(b.to_string());
    }
    let r = r.send().await.expect("the service answers");
    let code = r.status().as_u16();
    (code, r.json().await.expect("JSON"))
}

/// An ED-318 feature closing `node` from a minute ago to 40 minutes ahead.
fn zone(id: &str, node: &str, now: Instant) -> Value {
    let at = |s: i64| (now + Millis::from_secs(s)).to_rfc3339(UtcOffset::SINGAPORE);
    json!({
        "type": "Feature",
        "properties": {
            "identifier": id,
            "name": [{"text": format!("test zone {id}"), "lang": "en"}],
            "type": "PROHIBITED",
            "nodes": [node],
            "limitedApplicability": [{"startDateTime": at(-60), "endDateTime": at(2_400)}],
        },
        "geometry": null,
    })
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[allow(clippy::too_many_lines)] // One session, told in order.
async fn a_saved_listing_of_every_status_passes_muse_verify() {
    let data = scratch_dir("serve-verify");
    let server = start(&data, &["--airspace", &testdata("line.geojson")]);
    let base = server.base.clone();
    let http = reqwest::Client::new();
    let (_, health) = send(&http, reqwest::Method::GET, format!("{base}/healthz"), None).await;
    let now = Instant::parse_rfc3339(health["now"].as_str().unwrap()).unwrap();
    let booking = WallInstant::now();

    // Year 9999 is a valid timestamp, far beyond the booking horizon; a leap second is
    // refused as one. Neither is "not RFC 3339".
    let post = |id: &str, from: &str, to: &str, departure: String| {
        send(
            &http,
            reqwest::Method::POST,
            format!("{base}/v1/flights"),
            Some(json!({"id": id, "origin": from, "destination": to, "departure": departure})),
        )
    };
    for (departure, needle) in [
        ("9999-12-31T23:59:59Z", "bookings open 30 days ahead"),
        ("9999-12-31T23:59:59+08:00", "bookings open 30 days ahead"),
        ("2026-06-30T23:59:60+00:00", "leap seconds are not accepted"),
        (
            "+1000000-01-01T00:00:00Z",
            "out of the range MUSE represents",
        ),
    ] {
        let (code, v) = post("x", "A", "B", departure.to_owned()).await;
        let message = v["error"]["message"].as_str().unwrap_or_default();
        assert_eq!(
            (code, v["error"]["field"].as_str()),
            (422, Some("departure"))
        );
        assert!(
            message.contains(needle) && !message.contains("not an RFC 3339"),
            "{departure}: {v}"
        );
    }

    let at = |s: f64| (now + Millis((s * 1_000.0) as i64)).to_rfc3339(UtcOffset::SINGAPORE);
    for (id, from, to, after_s, code) in [
        ("a1", "A", "C", 1.5, 201),
        ("k1", "X", "Y", 1.5, 201),
        ("a2", "A", "C", 600.0, 201),
        ("b1", "B", "C", 1_500.0, 201),
        ("e1", "A", "C", 1_800.0, 201),
        ("b2", "X", "Y", 600.0, 201),
        ("a3", "B", "A", 1_200.0, 201),
        ("c1", "A", "B", 900.0, 201),
        ("r1", "A", "F", 300.0, 200),
        ("r2", "B", "A", -60.0, 200),
    ] {
        let (got, v) = post(id, from, to, at(after_s)).await;
        assert_eq!(got, code, "{id}: {v}");
    }
    let cancel = |id: &str| {
        send(
            &http,
            reqwest::Method::DELETE,
            format!("{base}/v1/flights/{id}"),
            None,
        )
    };
    assert_eq!(cancel("c1").await.0, 200);
    tokio::time::sleep(Duration::from_secs(2).saturating_sub(booking.elapsed())).await;
    for (id, node) in [("ZC", "C"), ("ZY", "Y")] {
        let (code, v) = send(
            &http,
            reqwest::Method::POST,
            format!("{base}/v1/zones"),
            Some(zone(id, node, now)),
        )
        .await;
        assert_eq!(code, 201, "{v}");
    }
    let (code, v) = cancel("b1").await;
    assert_eq!(
        (
            code,
            v["reason"].as_str(),
            v["changes"][0]["outcome"].as_str()
        ),
        (200, Some("cancelled_by_operator"), Some("replanned")),
        "{v}"
    );

    // What the user saves: one flight a line, as `jq -c '.flights[]'` writes them.
    let (_, list) = send(
        &http,
        reqwest::Method::GET,
        format!("{base}/v1/flights"),
        None,
    )
    .await;
    let (_, zones) = send(
        &http,
        reqwest::Method::GET,
        format!("{base}/v1/zones"),
        None,
    )
    .await;
    server.kill();
    std::fs::create_dir_all(&data).unwrap();
    let flights = list["flights"].as_array().unwrap();
    let mut lines = String::new();
    for f in flights {
        lines.push_str(&f.to_string());
        lines.push('\n');
    }
    let statuses: Vec<(&str, Option<&str>)> = flights
        .iter()
        .map(|f| (f["status"].as_str().unwrap(), f["reason"].as_str()))
        .collect();
    assert_eq!(
        statuses,
        [
            ("diverted", None),
            ("contingency", None),
            ("cancelled", Some("zone_announced")),
            ("cancelled", Some("cancelled_by_operator")),
            ("replanned", None),
            ("cancelled", Some("zone_announced")),
            ("planned", None),
            ("cancelled", Some("cancelled_by_operator")),
            ("rejected", Some("out_of_range")),
            ("rejected", Some("departure_in_past")),
        ],
        "{lines}"
    );
    assert!(flights.iter().all(|f| f["operator"] == "open"));
    let plans = data.join("p.jsonl");
    let zones_file = data.join("zones.geojson");
    std::fs::write(&plans, &lines).unwrap();
    std::fs::write(&zones_file, zones.to_string()).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(["verify", "--airspace", &testdata("line.geojson"), "--plans"])
        .arg(&plans)
        .arg("--zones")
        .arg(&zones_file)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        out.starts_with(
            "OK: 10 lines read (1 planned, 1 replanned, 1 diverted, 1 contingency, 2 cancelled \
             by a zone, 2 cancelled by their operator, 2 rejected); 4 flights checked, every \
             rule holds (exclusive; 2 zone(s), 2 announced during the day; 6 flights changed by \
             announcements)"
        ),
        "{out}"
    );
    let _ = std::fs::remove_dir_all(&data);
}

/// `GET /v1/zones` lists a withdrawn zone with its `withdrawn` instant, and `muse verify`
/// honours it: a flight the service planned through the zone after its withdrawal passes.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_withdrawn_zone_binds_nothing_after_its_withdrawal() {
    let data = scratch_dir("serve-verify-withdrawn");
    let server = start(&data, &["--airspace", &testdata("line.geojson")]);
    let base = server.base.clone();
    let http = reqwest::Client::new();
    let (_, health) = send(&http, reqwest::Method::GET, format!("{base}/healthz"), None).await;
    let now = Instant::parse_rfc3339(health["now"].as_str().unwrap()).unwrap();
    let (code, v) = send(
        &http,
        reqwest::Method::POST,
        format!("{base}/v1/zones"),
        Some(zone("ZB", "B", now)),
    )
    .await;
    assert_eq!(code, 201, "{v}");
    let (code, v) = send(
        &http,
        reqwest::Method::DELETE,
        format!("{base}/v1/zones/ZB"),
        None,
    )
    .await;
    assert_eq!(code, 200, "{v}");
    // A to C flies over B, whose closure (to 40 minutes ahead) no longer binds.
    let departure = (now + Millis::from_secs(600)).to_rfc3339(UtcOffset::SINGAPORE);
    let (code, v) = send(
        &http,
        reqwest::Method::POST,
        format!("{base}/v1/flights"),
        Some(json!({"id": "w1", "origin": "A", "destination": "C", "departure": departure})),
    )
    .await;
    assert_eq!((code, v["status"].as_str()), (201, Some("planned")), "{v}");
    assert!(
        v["path"]
            .as_array()
            .unwrap()
            .iter()
            .any(|s| s["node"] == "B"),
        "{v}"
    );
    let (_, list) = send(
        &http,
        reqwest::Method::GET,
        format!("{base}/v1/flights"),
        None,
    )
    .await;
    let (_, zones) = send(
        &http,
        reqwest::Method::GET,
        format!("{base}/v1/zones"),
        None,
    )
    .await;
    server.kill();
    let feature = &zones["features"][0]["properties"];
    assert!(feature["withdrawn"].is_string(), "{zones}");
    std::fs::create_dir_all(&data).unwrap();
    let (plans, zones_file) = (data.join("p.jsonl"), data.join("zones.geojson"));
    let mut lines = String::new();
    for f in list["flights"].as_array().unwrap() {
        lines.push_str(&f.to_string());
        lines.push('\n');
    }
    std::fs::write(&plans, lines).unwrap();
    std::fs::write(&zones_file, zones.to_string()).unwrap();
    let verify = |zones: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_muse"))
            .args(["verify", "--airspace", &testdata("line.geojson"), "--plans"])
            .arg(&plans)
            .arg("--zones")
            .arg(zones)
            .output()
            .unwrap()
    };
    let o = verify(&zones_file);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && out.contains("1 announced during the day"),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_planning_refuses(&zones_file, &data.join("sim"));
    // The same zone never withdrawn binds the flight: it is reported.
    let mut kept = zones.clone();
    kept["features"][0]["properties"]
        .as_object_mut()
        .unwrap()
        .remove("withdrawn");
    let kept_file = data.join("kept.geojson");
    std::fs::write(&kept_file, kept.to_string()).unwrap();
    let o = verify(&kept_file);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(out.contains("zone `ZB`") && out.contains("w1"), "{out}");
    let _ = std::fs::remove_dir_all(&data);
}

/// Planning commands replay announcements, never withdrawals: `muse simulate` refuses a zone
/// listing with a withdrawn zone (exit 2, nothing written into `out`).
fn assert_planning_refuses(zones_file: &std::path::Path, out: &std::path::Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args([
            "simulate",
            "--count",
            "5",
            "--airspace",
            &testdata("line.geojson"),
        ])
        .arg("--zones")
        .arg(zones_file)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("zone `ZB` was withdrawn (`withdrawn`): `muse simulate` cannot plan"),
        "{err}"
    );
    assert!(!out.exists());
}
