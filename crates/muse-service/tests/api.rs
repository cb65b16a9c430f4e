//! The HTTP API, end to end: a real service on an ephemeral loopback port, a real client.
//!
//! The airspace is small and made for the cases: a line of stations `A — B — C` 1 km apart
//! (120 s per corridor at 30 km/h), a far station `F` 12 km beyond `C` (out of range of `A`
//! with a 20-minute battery), and a separate pair `X — Y` that nothing else reaches.

use std::path::PathBuf;
use std::time::Duration;

use muse_model::{Airspace, Edge, FlightParams, LonLat, Millis, Node, NodeId, NodeKind, UtcOffset};
use muse_service::auth::Tokens;
use muse_service::state::{Clock, ServiceWorld};
use muse_service::{Options, start};
use serde_json::{Value, json};

fn airspace() -> Airspace {
    let node = |id: &str, lon: f64, lat: f64| Node {
        id: id.into(),
        kind: NodeKind::Station,
        name: String::new(),
        pos: LonLat::new(lon, lat),
    };
    let edge = |id: &str, from: u32, to: u32, m: f64| Edge {
        id: id.into(),
        from: NodeId(from),
        to: NodeId(to),
        length_m: m,
    };
    Airspace::new(
        vec![
            node("A", 103.80, 1.30),
            node("B", 103.81, 1.30),
            node("C", 103.82, 1.30),
            node("F", 103.93, 1.30),
            node("X", 103.80, 1.40),
            node("Y", 103.81, 1.40),
        ],
        vec![
            edge("A-B", 0, 1, 1_000.0),
            edge("B-C", 1, 2, 1_000.0),
            edge("C-F", 2, 3, 12_000.0),
            edge("X-Y", 4, 5, 1_000.0),
        ],
    )
    .unwrap()
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("muse-api-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A running service and a client for it.
struct Service {
    base: String,
    client: reqwest::Client,
    data: PathBuf,
}

impl Service {
    async fn start(name: &str, configure: impl FnOnce(&mut Options)) -> Service {
        let data = temp_dir(name);
        let mut options = Options::new(data.clone());
        configure(&mut options);
        let world = ServiceWorld::new(
            "test line".into(),
            airspace(),
            Vec::new(),
            FlightParams::default(),
            UtcOffset::SINGAPORE,
            Millis::from_secs(30 * 86_400),
            options.clock.now(),
        )
        .unwrap();
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let running = start(world, options, listener).await.unwrap();
        let base = format!("http://{}", running.addr);
        tokio::spawn(running.serve());
        Service {
            base,
            client: reqwest::Client::new(),
            data,
        }
    }

    async fn send(
        &self,
        method: reqwest::Method,
        path: &str,
        token: Option<&str>,
        body: Option<String>,
    ) -> (u16, Value) {
        let mut rq = self.client.request(method, format!("{}{path}", self.base));
        if let Some(t) = token {
            rq = rq.bearer_auth(t);
        }
        if let Some(b) = body {
            rq = rq.header("content-type", "application/json").body(b);
        }
        let response = rq.send().await.unwrap();
        let status = response.status().as_u16();
        let text = response.text().await.unwrap();
        let value = serde_json::from_str(&text).unwrap_or(Value::String(text));
        (status, value)
    }

    async fn post(&self, token: Option<&str>, body: &Value) -> (u16, Value) {
        self.send(
            reqwest::Method::POST,
            "/v1/flights",
            token,
            Some(body.to_string()),
        )
        .await
    }

    async fn get(&self, path: &str, token: Option<&str>) -> (u16, Value) {
        self.send(reqwest::Method::GET, path, token, None).await
    }

    async fn delete(&self, path: &str, token: Option<&str>) -> (u16, Value) {
        self.send(reqwest::Method::DELETE, path, token, None).await
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.data);
    }
}

/// `now + secs`, as RFC 3339 in Singapore time.
fn in_secs(secs: i64) -> String {
    (Clock::system().now() + Millis::from_secs(secs)).to_rfc3339(UtcOffset::SINGAPORE)
}

fn flight(id: &str, from: &str, to: &str, departure: &str) -> Value {
    json!({"id": id, "origin": from, "destination": to, "departure": departure})
}

fn error_field(v: &Value) -> Option<&str> {
    v["error"]["field"].as_str()
}

#[tokio::test]
async fn plan_reject_each_reason_and_read_back() {
    let s = Service::start("reasons", |_| {}).await;
    let t = in_secs(600);
    let (code, planned) = s.post(None, &flight("f1", "A", "C", &t)).await;
    assert_eq!(code, 201, "{planned}");
    assert_eq!(planned["status"], "planned");
    assert_eq!(planned["takeoff"], planned["requested_departure"]);
    assert_eq!(planned["airborne_s"], 240.0);
    assert_eq!(planned["path"].as_array().unwrap().len(), 3);

    // Same slot again, no ground delay allowed: the node rule at A forbids it.
    let (code, v) = s.post(None, &flight("f2", "A", "C", &t)).await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("no_feasible_plan")),
        "{v}"
    );
    let (code, v) = s.post(None, &flight("f3", "A", "F", &t)).await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("out_of_range")),
        "{v}"
    );
    let (code, v) = s.post(None, &flight("f4", "A", "Y", &t)).await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("unreachable")),
        "{v}"
    );
    let (code, v) = s.post(None, &flight("f5", "A", "B", &in_secs(-60))).await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("departure_in_past")),
        "{v}"
    );
    assert!(v["path"].is_null());

    let (code, got) = s.get("/v1/flights/f1", None).await;
    assert_eq!((code, &got), (200, &planned));
    let (code, _) = s.get("/v1/flights/nope", None).await;
    assert_eq!(code, 404);
    let (code, list) = s.get("/v1/flights", None).await;
    assert_eq!(code, 200);
    let ids: Vec<&str> = list["flights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["request"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["f1", "f2", "f3", "f4", "f5"]);
    let (_, list) = s.get("/v1/flights?status=planned", None).await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 1);
    // Time window: f1 flies 10 to 14 minutes from now.
    let (_, list) = s
        .get(
            &format!("/v1/flights?status=planned&from={}", enc(&in_secs(900))),
            None,
        )
        .await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 0);
    let (_, list) = s
        .get(
            &format!("/v1/flights?status=planned&to={}", enc(&in_secs(700))),
            None,
        )
        .await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 1);
    // Pages.
    let (_, page) = s.get("/v1/flights?limit=2", None).await;
    assert_eq!(page["flights"].as_array().unwrap().len(), 2);
    let after = page["next_after"].as_u64().unwrap();
    let (_, page) = s
        .get(&format!("/v1/flights?limit=10&after={after}"), None)
        .await;
    assert_eq!(page["flights"].as_array().unwrap().len(), 3);
    assert!(page["next_after"].is_null());
    let (code, v) = s.get("/v1/flights?status=flying", None).await;
    assert_eq!((code, error_field(&v)), (422, Some("status")));
    let (code, _) = s.get("/v1/flights?colour=red", None).await;
    assert_eq!(code, 400);

    // Metrics count each outcome.
    let (_, metrics) = s.get("/metrics", None).await;
    let metrics = metrics.as_str().unwrap().to_owned();
    for line in [
        "muse_flight_requests_total{outcome=\"planned\"} 1",
        "muse_flight_requests_total{outcome=\"rejected\",reason=\"no_feasible_plan\"} 1",
        "muse_flight_requests_total{outcome=\"rejected\",reason=\"departure_in_past\"} 1",
    ] {
        assert!(metrics.contains(line), "{line} not in\n{metrics}");
    }
    assert!(metrics.contains("muse_store_commit_seconds_count"));
}

/// Percent-encodes the `+` of an offset for a query string.
fn enc(t: &str) -> String {
    t.replace('+', "%2B")
}

#[tokio::test]
async fn retries_are_idempotent_and_conflicts_refused() {
    let s = Service::start("idempotent", |_| {}).await;
    let t = in_secs(600);
    let (code, first) = s.post(None, &flight("r1", "A", "B", &t)).await;
    assert_eq!(code, 201);
    let (code, again) = s.post(None, &flight("r1", "A", "B", &t)).await;
    assert_eq!((code, &again), (201, &first));
    // A rejection is repeated as it was, too.
    let (code, rej) = s.post(None, &flight("r2", "A", "F", &t)).await;
    assert_eq!(code, 200);
    assert_eq!(s.post(None, &flight("r2", "A", "F", &t)).await, (200, rej));
    // Same id, other content: a conflict, and nothing changes.
    let (code, v) = s.post(None, &flight("r1", "A", "C", &t)).await;
    assert_eq!((code, error_field(&v)), (409, Some("id")), "{v}");
    let (_, list) = s.get("/v1/flights", None).await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 2);
    // Twenty concurrent copies of one new request: one flight, one answer.
    let t2 = in_secs(1200);
    let mut tasks = Vec::new();
    for _ in 0..20 {
        let client = s.client.clone();
        let url = format!("{}/v1/flights", s.base);
        let body = flight("r3", "B", "C", &t2).to_string();
        tasks.push(tokio::spawn(async move {
            let r = client.post(url).body(body).send().await.unwrap();
            (r.status().as_u16(), r.text().await.unwrap())
        }));
    }
    let mut answers = Vec::new();
    for t in tasks {
        answers.push(t.await.unwrap());
    }
    assert!(answers.iter().all(|a| a == &answers[0]), "{answers:?}");
    assert_eq!(answers[0].0, 201);
}

#[tokio::test]
async fn cancel_before_take_off_frees_the_slot_and_not_after() {
    let s = Service::start("cancel", |_| {}).await;
    let t = in_secs(600);
    assert_eq!(s.post(None, &flight("c1", "A", "B", &t)).await.0, 201);
    assert_eq!(
        s.post(None, &flight("c2", "A", "B", &t)).await.1["reason"],
        "no_feasible_plan"
    );
    let (code, v) = s.delete("/v1/flights/c1", None).await;
    assert_eq!(code, 200, "{v}");
    assert_eq!(v["status"], "cancelled");
    assert!(v["path"].is_null() && v["cancelled_at"].is_string());
    // Cancelling again answers the same; the freed slot can be booked.
    assert_eq!(s.delete("/v1/flights/c1", None).await.0, 200);
    let (code, v) = s.post(None, &flight("c3", "A", "B", &t)).await;
    assert_eq!(
        (code, v["takeoff"].as_str()),
        (201, v["requested_departure"].as_str())
    );
    // A rejected flight has nothing to cancel; an unknown one does not exist.
    assert_eq!(s.delete("/v1/flights/c2", None).await.0, 409);
    assert_eq!(s.delete("/v1/flights/zz", None).await.0, 404);
    // After take-off the flight is committed.
    let soon = Clock::system().now() + Millis(1_500);
    let (code, _) = s
        .post(
            None,
            &flight("c4", "B", "C", &soon.to_rfc3339(UtcOffset::SINGAPORE)),
        )
        .await;
    assert_eq!(code, 201);
    tokio::time::sleep(Duration::from_millis(1_700)).await;
    let (code, v) = s.delete("/v1/flights/c4", None).await;
    assert_eq!(
        (code, v["error"]["code"].as_str()),
        (409, Some("committed")),
        "{v}"
    );
    assert_eq!(s.get("/v1/flights/c4", None).await.1["status"], "planned");
}

const TOKENS: &str = r#"
[[tokens]]
token = "alpha-secret"
operator = "alpha"
role = "operator"

[[tokens]]
token = "bravo-secret"
operator = "bravo"
role = "operator"

[[tokens]]
token = "authority-secret"
operator = "caas"
role = "authority"
"#;

#[tokio::test]
#[allow(clippy::many_single_char_names)]
async fn operators_see_their_own_flights_and_the_authority_all() {
    let s = Service::start("auth", |o| {
        o.tokens = Tokens::parse(TOKENS, "tokens.toml").unwrap();
    })
    .await;
    let (a, b, auth) = (
        Some("alpha-secret"),
        Some("bravo-secret"),
        Some("authority-secret"),
    );
    let t = in_secs(600);
    assert_eq!(s.post(None, &flight("a1", "A", "B", &t)).await.0, 401);
    assert_eq!(
        s.post(Some("wrong-token"), &flight("a1", "A", "B", &t))
            .await
            .0,
        401
    );
    assert_eq!(s.get("/v1/flights", None).await.0, 401);
    let (code, v) = s.post(a, &flight("a1", "A", "B", &t)).await;
    assert_eq!((code, v["operator"].as_str()), (201, Some("alpha")));
    assert_eq!(s.post(b, &flight("b1", "B", "C", &t)).await.0, 201);
    // Another operator's flight does not exist for bravo, not even to cancel or to reuse
    // its id.
    assert_eq!(s.get("/v1/flights/a1", b).await.0, 404);
    assert_eq!(s.delete("/v1/flights/a1", b).await.0, 404);
    assert_eq!(s.post(b, &flight("a1", "A", "B", &t)).await.0, 409);
    let (_, list) = s.get("/v1/flights", b).await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 1);
    assert_eq!(s.get("/v1/flights?operator=alpha", b).await.0, 403);
    // The authority reads every flight.
    assert_eq!(s.get("/v1/flights/a1", auth).await.0, 200);
    let (_, list) = s.get("/v1/flights", auth).await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 2);
    let (_, list) = s.get("/v1/flights?operator=bravo", auth).await;
    assert_eq!(list["flights"][0]["request"], "b1");
    // Health and metrics need no token; the API description neither.
    assert_eq!(s.get("/healthz", None).await.0, 200);
    assert_eq!(s.get("/metrics", None).await.0, 200);
    assert_eq!(s.get("/v1/openapi.json", None).await.0, 200);
    assert_eq!(s.get("/v1/airspace", a).await.0, 200);
    assert_eq!(s.get("/v1/zones", None).await.0, 401);
}

#[tokio::test]
async fn bad_input_is_a_clear_4xx_and_changes_nothing() {
    let s = Service::start("bad", |o| o.max_body = 1024).await;
    let t = in_secs(600);
    let raw = |body: &str| {
        s.send(
            reqwest::Method::POST,
            "/v1/flights",
            None,
            Some(body.to_owned()),
        )
    };
    let cases: Vec<(String, u16, Option<&str>)> = vec![
        ("{".into(), 400, None),
        ("not json".into(), 400, None),
        ("[]".into(), 400, None),
        (r#"{"id": "x"}"#.into(), 400, None),
        (
            json!({"id": "x", "origin": "A", "destination": "B", "departure": t, "extra": 1})
                .to_string(),
            400,
            Some("extra"),
        ),
        (
            json!({"id": 5, "origin": "A", "destination": "B", "departure": t}).to_string(),
            400,
            Some("id"),
        ),
        (flight("x", "Q", "B", &t).to_string(), 422, Some("origin")),
        (
            flight("x", "A", "Q", &t).to_string(),
            422,
            Some("destination"),
        ),
        (
            flight("x", "A", "A", &t).to_string(),
            422,
            Some("destination"),
        ),
        (
            flight("x", "A", "B", "2026-01-05T08:00:00").to_string(),
            422,
            Some("departure"),
        ),
        (
            flight("x", "A", "B", "08:00").to_string(),
            422,
            Some("departure"),
        ),
        (
            flight("x", "A", "B", "2026-13-05T08:00:00Z").to_string(),
            422,
            Some("departure"),
        ),
        (
            flight("x", "A", "B", &in_secs(40 * 86_400)).to_string(),
            422,
            Some("departure"),
        ),
        (flight("", "A", "B", &t).to_string(), 422, Some("id")),
        (flight("a/b", "A", "B", &t).to_string(), 422, Some("id")),
        (
            flight(&"x".repeat(129), "A", "B", &t).to_string(),
            422,
            Some("id"),
        ),
        (format!("{} trailing", flight("x", "A", "B", &t)), 400, None),
    ];
    for (body, code, field) in &cases {
        let (got, v) = raw(body).await;
        assert_eq!(got, *code, "{body}: {v}");
        assert!(
            v["error"]["message"]
                .as_str()
                .is_some_and(|m| !m.is_empty()),
            "{v}"
        );
        if field.is_some() {
            assert_eq!(error_field(&v), *field, "{body}: {v}");
        }
    }
    // Too large a body: 413.
    let big = json!({"id": "x".repeat(2_000), "origin": "A", "destination": "B", "departure": t});
    let (code, v) = raw(&big.to_string()).await;
    assert_eq!(code, 413, "{v}");
    // Nothing was stored or booked.
    let (_, list) = s.get("/v1/flights", None).await;
    assert_eq!(list["flights"].as_array().unwrap().len(), 0);
    let (_, m) = s.get("/metrics", None).await;
    assert!(m.as_str().unwrap().contains(&format!(
        "muse_flight_requests_total{{outcome=\"invalid\"}} {}",
        cases.len() + 1
    )));
    assert_eq!(s.get("/v1/nothing", None).await.0, 404);
}

#[tokio::test]
async fn pages_after_concurrent_requests_list_each_flight_once() {
    let s = Service::start("pages", |_| {}).await;
    let mut tasks = Vec::new();
    for k in 0..64 {
        let client = s.client.clone();
        let url = format!("{}/v1/flights", s.base);
        let (from, to) = if k % 2 == 0 { ("A", "C") } else { ("C", "A") };
        let body = flight(&format!("p{k}"), from, to, &in_secs(600 + 10 * k)).to_string();
        tasks.push(tokio::spawn(async move {
            client
                .post(url)
                .body(body)
                .send()
                .await
                .unwrap()
                .status()
                .as_u16()
        }));
    }
    for t in tasks {
        assert!([200, 201].contains(&t.await.unwrap()));
    }
    let mut seen = Vec::new();
    let mut after: Option<u64> = None;
    loop {
        let path = match after {
            Some(a) => format!("/v1/flights?limit=5&after={a}"),
            None => "/v1/flights?limit=5".to_owned(),
        };
        let (_, page) = s.get(&path, None).await;
        for f in page["flights"].as_array().unwrap() {
            seen.push(f["request"].as_str().unwrap().to_owned());
        }
        match page["next_after"].as_u64() {
            Some(a) => after = Some(a),
            None => break,
        }
    }
    let mut unique = seen.clone();
    unique.sort();
    unique.dedup();
    assert_eq!((seen.len(), unique.len()), (64, 64), "{seen:?}");
}

#[tokio::test]
async fn departures_older_than_the_retention_are_answered_but_not_kept() {
    let s = Service::start("retain", |o| o.retain = Millis::from_secs(3_600)).await;
    let (code, v) = s
        .post(None, &flight("old", "A", "B", &in_secs(-7_200)))
        .await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("departure_in_past"))
    );
    assert_eq!(s.get("/v1/flights/old", None).await.0, 404);
    let (code, v) = s
        .post(None, &flight("recent", "A", "B", &in_secs(-60)))
        .await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("departure_in_past"))
    );
    assert_eq!(s.get("/v1/flights/recent", None).await.0, 200);
}

#[tokio::test]
async fn requests_per_token_are_limited() {
    let s = Service::start("rate", |o| {
        o.rate_limit = 2.0;
        o.burst = 3.0;
    })
    .await;
    let mut codes = Vec::new();
    for _ in 0..5 {
        codes.push(s.get("/v1/flights", None).await.0);
    }
    assert_eq!(codes, [200, 200, 200, 429, 429]);
}

#[tokio::test]
async fn state_survives_a_restart_on_the_same_folder() {
    let data = temp_dir("restart");
    let t = in_secs(600);
    let world = || {
        ServiceWorld::new(
            "test line".into(),
            airspace(),
            Vec::new(),
            FlightParams::default(),
            UtcOffset::SINGAPORE,
            Millis::from_secs(30 * 86_400),
            Clock::system().now(),
        )
        .unwrap()
    };
    let first = {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let running = start(world(), Options::new(data.clone()), listener)
            .await
            .unwrap();
        let base = format!("http://{}", running.addr);
        let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
        let server = tokio::spawn(running.serve_until(async {
            let _ = stop_rx.await;
        }));
        let client = reqwest::Client::new();
        let post = |body: Value| {
            client
                .post(format!("{base}/v1/flights"))
                .body(body.to_string())
                .send()
        };
        let planned: Value = post(flight("k1", "A", "C", &t))
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
        post(flight("k2", "B", "C", &t)).await.unwrap();
        client
            .delete(format!("{base}/v1/flights/k2"))
            .send()
            .await
            .unwrap();
        // A second service on the same folder is refused while this one runs.
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let e = start(world(), Options::new(data.clone()), listener)
            .await
            .unwrap_err()
            .to_string();
        assert!(e.contains("in use by another process"), "{e}");
        let _ = stop_tx.send(());
        server.await.unwrap().unwrap();
        planned
    };
    // The engine thread lets go of the store when its queue closes; wait for the lock.
    let mut running = None;
    for _ in 0..100 {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        match start(world(), Options::new(data.clone()), listener).await {
            Ok(r) => {
                running = Some(r);
                break;
            }
            Err(_) => tokio::time::sleep(Duration::from_millis(20)).await,
        }
    }
    let running = running.expect("restarts once the first service is gone");
    assert_eq!(running.restored.flights, 2);
    assert_eq!(running.restored.cancellations, 1);
    let base = format!("http://{}", running.addr);
    tokio::spawn(running.serve());
    let client = reqwest::Client::new();
    let again: Value = client
        .get(format!("{base}/v1/flights/k1"))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(again, first);
    let k2: Value = client
        .get(format!("{base}/v1/flights/k2"))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(k2["status"], "cancelled");
    // The restored flight still holds its slot: the same request under a new id is refused.
    let v: Value = client
        .post(format!("{base}/v1/flights"))
        .body(flight("k3", "A", "C", &t).to_string())
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(v["reason"], "no_feasible_plan");
    let _ = std::fs::remove_dir_all(&data);
}

/// The router serves every route of `ROUTES` (and the `OpenAPI` test below ties `ROUTES` to
/// the document).
#[tokio::test]
async fn every_listed_route_is_served() {
    let s = Service::start("routes", |_| {}).await;
    for (method, path) in muse_service::api::ROUTES {
        let method = reqwest::Method::from_bytes(method.to_uppercase().as_bytes()).unwrap();
        let path = path.replace("{id}", "some-id");
        let body = (method == reqwest::Method::POST).then(|| "{}".to_owned());
        let (code, v) = s.send(method.clone(), &path, None, body).await;
        let unrouted = code == 405
            || (code == 404
                && v["error"]["message"]
                    .as_str()
                    .is_some_and(|m| m.starts_with("no such route")));
        assert!(!unrouted, "{method} {path}: {code} {v}");
    }
}

#[test]
fn openapi_describes_every_route() {
    let doc: Value = serde_json::from_str(muse_service::api::OPENAPI).unwrap();
    let mut described = Vec::new();
    for (path, item) in doc["paths"].as_object().unwrap() {
        for method in item.as_object().unwrap().keys() {
            described.push((method.clone(), path.clone()));
        }
    }
    described.sort();
    let mut routes: Vec<(String, String)> = muse_service::api::ROUTES
        .iter()
        .map(|(m, p)| ((*m).to_owned(), (*p).to_owned()))
        .collect();
    routes.sort();
    assert_eq!(described, routes);
}
