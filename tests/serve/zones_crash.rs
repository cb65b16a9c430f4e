//! A zone announced on a running `muse serve`, then `kill -9` right after its answer.
//!
//! Flights are booked on the embedded Singapore default (some take off within seconds, near
//! the National Stadium; the others are spread over the next two hours), the stadium zone
//! is announced while they fly (the service clock starts at 15:10 on the zone's day, inside
//! its 15:00–18:00 window), and the process is killed with SIGKILL as soon as the `201`
//! arrives — never a clean shutdown. After a restart on the same `--data`:
//!
//! - every flight reads exactly as last acknowledged: the announcement's answer for the
//!   flights it changed, the booking's answer for the others;
//! - the event stream replays the same events with the same ids (what a listener received
//!   before the kill is a prefix of it, and it ends with the announcement's outcomes);
//! - the zone is known (listed with its instant, its id refused again), a replanned flight
//!   can still be cancelled before its new take-off, and every final plan passes the
//!   verifier with the zone (docs/reference.md#zones-announced-during-the-day exemptions).

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant as WallInstant};

use muse_model::{FlightParams, Instant, LonLat, Millis, UtcOffset};
use rand::{RngExt as _, SeedableRng as _};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use crate::support::{StoreArg, start_on};

const SEED: u64 = 0x2011_0e09;
/// The service clock at the first start: inside the stadium zone's window.
const CLOCK: &str = "2026-01-05T15:10:00.000+08:00";
/// Flights taking off within seconds (airborne at the announcement), and flights ahead.
const SOON: usize = SOON_PAIRS.len();
/// Flights that take off within seconds: routes whose later corridors the zone closes (e.g.
/// `S063 — S066 — S069`: `S066-S069` is closed).
const SOON_PAIRS: [(&str, &str); 8] = [
    ("S063", "S069"),
    ("S074", "S069"),
    ("S055", "S069"),
    ("S053", "S066"),
    ("S057", "S070"),
    ("S059", "S070"),
    ("S064", "S066"),
    ("S042", "S069"),
];
const AHEAD: usize = 160;

/// One server-sent event: id, type, data.
type Received = (u64, String, Value);

/// Reads events from a `GET /v1/events` response into `into` until the stream ends (the
/// server dies) or `want` events have come.
async fn listen(mut response: reqwest::Response, into: Arc<Mutex<Vec<Received>>>, want: usize) {
    let mut buffer = String::new();
    loop {
        while let Some(end) = buffer.find("\n\n") {
            let frame: String = buffer.drain(..end + 2).collect();
            let (mut id, mut kind, mut data) = (None, None, None);
            for line in frame.lines() {
                if let Some(v) = line.strip_prefix("id:") {
                    id = Some(v.trim().parse::<u64>().unwrap());
                } else if let Some(v) = line.strip_prefix("event:") {
                    kind = Some(v.trim().to_owned());
                } else if let Some(v) = line.strip_prefix("data:") {
                    data = Some(serde_json::from_str::<Value>(v.trim()).unwrap());
                }
            }
            if let (Some(id), Some(kind), Some(data)) = (id, kind, data) {
                let mut events = into.lock().unwrap();
                events.push((id, kind, data));
                if events.len() == want {
                    return;
                }
            }
        }
        let chunk = tokio::time::timeout(Duration::from_secs(20), response.chunk())
            .await
            .expect("an event within 20 s");
        match chunk {
            Ok(Some(chunk)) => buffer.push_str(std::str::from_utf8(&chunk).unwrap()),
            // The server is gone.
            Ok(None) | Err(_) => return,
        }
    }
}

async fn open_events(http: &reqwest::Client, base: &str) -> reqwest::Response {
    let r = http
        .get(format!("{base}/v1/events"))
        .header("last-event-id", "0")
        .send()
        .await
        .expect("the event stream opens");
    assert_eq!(r.status().as_u16(), 200);
    r
}

/// The stadium zone's ED-318 feature, without its `announced` (the service sets it).
fn stadium_feature() -> Value {
    let collection: Value = serde_json::from_str(muse_scenario::STADIUM_ZONE_GEOJSON).unwrap();
    let mut feature = collection["features"][0].clone();
    feature["properties"]
        .as_object_mut()
        .unwrap()
        .remove("announced")
        .expect("the scenario's zone carries `announced`");
    feature
}

/// Books the flights: `SOON_PAIRS` across the stadium area taking off 2 to 4 s from now,
/// `AHEAD` over the next two hours to or from stations near it. Returns the planned answers.
async fn book(http: &reqwest::Client, base: &str) -> BTreeMap<String, Value> {
    let scenario = muse_scenario::by_name("singapore-77").unwrap();
    let airspace = &scenario.airspace;
    let stadium = LonLat::new(103.874_222, 1.300_694);
    let all: Vec<(String, f64)> = airspace
        .stations()
        .map(|s| {
            let n = airspace.node(s);
            (n.id.clone(), n.pos.geodesic_distance_m(stadium))
        })
        .collect();
    let within =
        |m: f64| -> Vec<&String> { all.iter().filter(|s| s.1 < m).map(|s| &s.0).collect() };
    let (near, around) = (within(3_500.0), within(6_000.0));
    let clock = service_now(http, base).await;
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let mut planned = BTreeMap::new();
    for k in 0..SOON + AHEAD {
        let pick =
            |rng: &mut ChaCha8Rng, from: &[&String]| from[rng.random_range(0..from.len())].clone();
        let (mut origin, mut destination, departure) = if let Some((o, d)) = SOON_PAIRS.get(k) {
            let departure = clock + Millis(2_000 + 2_000 * k as i64 / SOON as i64);
            ((*o).to_owned(), (*d).to_owned(), departure)
        } else {
            let departure = clock + Millis(rng.random_range(60_000..7_200_000));
            (pick(&mut rng, &near), pick(&mut rng, &around), departure)
        };
        while destination == origin {
            destination = pick(&mut rng, &around);
        }
        if k >= SOON && rng.random_range(0..2) == 0 {
            std::mem::swap(&mut origin, &mut destination);
        }
        let id = format!("z{k:03}");
        let body = json!({
            "id": id,
            "origin": origin,
            "destination": destination,
            "departure": departure.to_rfc3339(UtcOffset::SINGAPORE),
        });
        let r = http
            .post(format!("{base}/v1/flights"))
            .header("content-type", "application/json")
            .body(body.to_string())
            .send()
            .await
            .unwrap();
        let code = r.status().as_u16();
        let answer: Value = r.json().await.unwrap();
        assert!(code == 200 || code == 201, "{code}: {answer}");
        if code == 201 {
            planned.insert(id, answer);
        }
    }
    planned
}

/// The service clock's now.
async fn service_now(http: &reqwest::Client, base: &str) -> Instant {
    let health: Value = http
        .get(format!("{base}/healthz"))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    Instant::parse_rfc3339(health["now"].as_str().unwrap()).unwrap()
}

/// Every flight the server holds, by id.
async fn all_flights(http: &reqwest::Client, base: &str) -> BTreeMap<String, Value> {
    let list: Value = http
        .get(format!("{base}/v1/flights?limit=100000"))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert!(list["next_after"].is_null());
    list["flights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["request"].as_str().unwrap().to_owned(), f.clone()))
        .collect()
}

/// Runs the verifier on every flight as it finally stands, with the zones listed.
fn verify(flights: &BTreeMap<String, Value>, zones: &str) -> usize {
    let scenario = muse_scenario::by_name("singapore-77").unwrap();
    let airspace = &scenario.airspace;
    let mut text = String::new();
    for f in flights.values() {
        if f["status"] != "rejected" && f["reason"] != "cancelled_by_operator" {
            text.push_str(&f.to_string());
            text.push('\n');
        }
    }
    let records = muse_formats::plans::read_plans(&text, "GET /v1/flights", airspace).unwrap();
    let recorded = muse_verify::recorded::Recorded::new(records, airspace).unwrap();
    let checked = recorded.flights();
    let zones = muse_formats::zones::read_zones(zones, "GET /v1/zones").unwrap();
    let clock = Instant::parse_rfc3339(CLOCK).unwrap();
    let day = Millis::from_secs(86_400);
    let known =
        muse_airspace::announced::KnownZones::resolve(airspace, &zones, clock - day, clock + day)
            .unwrap();
    assert_eq!(known.announced.len(), 1);
    let violations =
        muse_verify::verify_known(airspace, &known, &FlightParams::default(), &checked);
    assert!(violations.is_empty(), "{violations:#?}");
    checked.len()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_announcement_survives_sigkill_right_after_its_answer() {
    announcement_survives_sigkill(false).await;
}

/// The same on a PostgreSQL store.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_announcement_survives_sigkill_right_after_its_answer_on_postgres() {
    announcement_survives_sigkill(true).await;
}

#[allow(clippy::too_many_lines)] // One story, told in order.
async fn announcement_survives_sigkill(postgres: bool) {
    println!("seed {SEED:#x}");
    let Some(data) = StoreArg::fresh("serve-zones-crash", postgres) else {
        return;
    };
    let started = WallInstant::now();
    let server = start_on(&data, &["--clock", CLOCK]);
    let http = reqwest::Client::new();
    // A listener from the start of the history, reading until the kill.
    let before = Arc::new(Mutex::new(Vec::new()));
    let listener = tokio::spawn(listen(
        open_events(&http, &server.base).await,
        Arc::clone(&before),
        usize::MAX,
    ));
    let booking = WallInstant::now();
    let planned = book(&http, &server.base).await;
    // Let the first flights take off (they leave 2 to 4 s after the booking began).
    tokio::time::sleep(Duration::from_millis(4_500).saturating_sub(booking.elapsed())).await;
    let r = http
        .post(format!("{}/v1/zones", server.base))
        .header("content-type", "application/geo+json")
        .body(stadium_feature().to_string())
        .send()
        .await
        .unwrap();
    let code = r.status().as_u16();
    let answer: Value = r.json().await.unwrap();
    server.kill();
    assert_eq!(code, 201, "{answer}");
    listener.await.unwrap();
    let affected = answer["affected"].as_array().unwrap();
    let mut kinds: BTreeMap<(&str, bool), usize> = BTreeMap::new();
    for a in affected {
        *kinds
            .entry((
                a["outcome"].as_str().unwrap(),
                a["airborne"].as_bool().unwrap(),
            ))
            .or_default() += 1;
    }
    println!(
        "{} planned, {} affected by the stadium zone: {kinds:?}",
        planned.len(),
        affected.len()
    );
    assert!(
        affected.len() >= 5 && kinds.keys().any(|(_, airborne)| *airborne),
        "too few flights affected: {answer}"
    );

    // Restart, the clock where it was.
    let clock =
        Instant::parse_rfc3339(CLOCK).unwrap() + Millis(started.elapsed().as_millis() as i64);
    let server = start_on(&data, &["--clock", &clock.to_rfc3339(UtcOffset::SINGAPORE)]);
    let held = all_flights(&http, &server.base).await;
    let mut want = planned.clone();
    for a in affected {
        want.insert(a["flight"].as_str().unwrap().to_owned(), a["plan"].clone());
    }
    for (id, answer) in &want {
        assert_eq!(held.get(id), Some(answer), "flight {id} after the restart");
    }

    // The same events, with the same ids: the bookings', then the announcement's outcomes.
    let total = planned.len() + affected.len();
    let after = Arc::new(Mutex::new(Vec::new()));
    tokio::time::timeout(
        Duration::from_secs(30),
        listen(
            open_events(&http, &server.base).await,
            Arc::clone(&after),
            total,
        ),
    )
    .await
    .expect("every event replayed");
    let after = after.lock().unwrap().clone();
    let before = before.lock().unwrap().clone();
    println!(
        "{} events before the kill, {} after the restart",
        before.len(),
        after.len()
    );
    assert_eq!(
        after.iter().map(|e| e.0).collect::<Vec<_>>(),
        (1..=total as u64).collect::<Vec<_>>()
    );
    assert!(before.len() >= planned.len());
    assert_eq!(before[..], after[..before.len()]);
    for ((_, kind, data), a) in after[planned.len()..].iter().zip(affected) {
        assert_eq!(data["flight"], a["flight"]);
        assert_eq!(data["zone"], "SG-NATIONAL-STADIUM-EVENT");
        assert_eq!(data["plan"], a["plan"]);
        assert_eq!(kind, a["outcome"].as_str().unwrap());
    }

    // The zone is known: listed, its id refused again.
    let zones = http
        .get(format!("{}/v1/zones", server.base))
        .send()
        .await
        .unwrap()
        .text()
        .await
        .unwrap();
    assert!(zones.contains("SG-NATIONAL-STADIUM-EVENT"), "{zones}");
    let again = http
        .post(format!("{}/v1/zones", server.base))
        .header("content-type", "application/geo+json")
        .body(stadium_feature().to_string())
        .send()
        .await
        .unwrap();
    assert_eq!(again.status().as_u16(), 409);
    // A replanned flight can still be cancelled before its new take-off.
    let replanned = affected.iter().find(|a| {
        a["outcome"] == "replanned"
            && Instant::parse_rfc3339(a["plan"]["takeoff"].as_str().unwrap()).unwrap()
                > clock + Millis::from_secs(60)
    });
    if let Some(a) = replanned {
        let id = a["flight"].as_str().unwrap();
        let r = http
            .delete(format!("{}/v1/flights/{id}", server.base))
            .send()
            .await
            .unwrap();
        assert_eq!(r.status().as_u16(), 200, "cancelling {id}");
    }
    let flying = verify(&all_flights(&http, &server.base).await, &zones);
    println!("{flying} flights verified with the zone");
    server.kill();
    data.remove();
}
