//! The HTTP API, end to end: a real service on an ephemeral loopback port, a real client.
//!
//! The airspace is small and made for the cases: a line of stations `A — B — C` 1 km apart
//! (120 s per corridor at 30 km/h), a far station `F` 12 km beyond `C` (out of range of `A`
//! with a 20-minute battery), and a separate pair `X — Y` that nothing else reaches.
//!
//! No test here draws random numbers: every case is fixed.

use std::path::{Path, PathBuf};
use std::time::Duration;

use muse_model::testing::{joined, station};
use muse_model::{Airspace, FlightParams, Millis, UtcOffset, Zone};
use muse_service::{Clock, Options, ServiceWorld, StoreAt, Tokens, start};
use serde_json::{Value, json};

use crate::throwaway_pg::Throwaway;

fn airspace() -> Airspace {
    joined(
        vec![
            station("A", 103.80, 1.30),
            station("B", 103.81, 1.30),
            station("C", 103.82, 1.30),
            station("F", 103.93, 1.30),
            station("X", 103.80, 1.40),
            station("Y", 103.81, 1.40),
        ],
        &[
            ("A", "B", 1_000.0),
            ("B", "C", 1_000.0),
            ("C", "F", 12_000.0),
            ("X", "Y", 1_000.0),
        ],
    )
}

pub(crate) fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("muse-api-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Which store a test's service runs on: each test of the suite runs on both (see
/// [`on_both_stores`]).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    /// A data folder (SQLite), under the system's temporary folder.
    Folder,
    /// A fresh database on the throwaway PostgreSQL the test process shares.
    Postgres(&'static Throwaway),
}

impl Kind {
    /// `sqlite` or `postgres`, for the names of a test's own folders.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Kind::Folder => "sqlite",
            Kind::Postgres(_) => "postgres",
        }
    }

    /// A new, empty store named after `name`.
    pub(crate) fn store(self, name: &str) -> StoreAt {
        match self {
            Kind::Folder => StoreAt::Folder(temp_dir(name)),
            Kind::Postgres(pg) => StoreAt::Postgres(pg.database(name)),
        }
    }
}

/// Runs each named test (an `async fn` taking a [`Kind`]) twice, as `NAME::sqlite` on a data
/// folder and `NAME::postgres` on a PostgreSQL database (skipped, saying so, where PostgreSQL
/// is not installed, except under CI).
macro_rules! on_both_stores {
    ($($name:ident),* $(,)?) => {$(
        mod $name {
            #[tokio::test]
            async fn sqlite() {
                super::$name(super::Kind::Folder).await;
            }
            #[tokio::test]
            async fn postgres() {
                if let Some(pg) = crate::throwaway_pg::Throwaway::shared() {
                    super::$name(super::Kind::Postgres(pg)).await;
                }
            }
        }
    )*};
}
pub(crate) use on_both_stores;

/// A running service and a client for it.
pub(crate) struct Service {
    pub(crate) base: String,
    client: reqwest::Client,
    /// Where its store is.
    pub(crate) store: StoreAt,
    /// The zones known from the start.
    zones: Vec<Zone>,
    /// Stops the server cleanly.
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    server: Option<tokio::task::JoinHandle<Result<(), muse_service::ServeError>>>,
}

impl Service {
    async fn start(kind: Kind, name: &str, configure: impl FnOnce(&mut Options)) -> Service {
        Service::start_with(kind, name, Vec::new(), configure).await
    }

    /// A service whose world has `zones` known from the start.
    async fn start_with(
        kind: Kind,
        name: &str,
        zones: Vec<Zone>,
        configure: impl FnOnce(&mut Options),
    ) -> Service {
        Service::open(kind.store(name), zones, configure)
            .await
            .unwrap()
    }

    /// A service on the store `at` (a data folder, or a database).
    pub(crate) async fn open(
        at: impl Into<StoreAt>,
        zones: Vec<Zone>,
        configure: impl FnOnce(&mut Options),
    ) -> Result<Service, muse_service::ServeError> {
        let store: StoreAt = at.into();
        let mut options = Options::new(store.clone());
        configure(&mut options);
        let world = ServiceWorld::new(
            "test line".into(),
            airspace(),
            zones.clone(),
            FlightParams::default(),
            UtcOffset::SINGAPORE,
            Millis::from_secs(30 * 86_400),
            options.clock.now(),
        )
        .unwrap();
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let running = start(world, options, listener).await?;
        let base = format!("http://{}", running.addr);
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let server = tokio::spawn(running.serve_until(async {
            let _ = stopped.await;
        }));
        Ok(Service {
            base,
            client: reqwest::Client::new(),
            store,
            zones,
            stop: Some(stop),
            server: Some(server),
        })
    }

    /// Stops the service cleanly (open event streams end) and starts it again on the same
    /// folder.
    async fn restart(mut self, configure: impl Fn(&mut Options)) -> Service {
        let _ = self.stop.take().unwrap().send(());
        tokio::time::timeout(Duration::from_secs(10), self.server.take().unwrap())
            .await
            .expect("a clean stop, event streams included")
            .unwrap()
            .unwrap();
        let store = std::mem::replace(&mut self.store, StoreAt::Folder(PathBuf::new()));
        let zones = std::mem::take(&mut self.zones);
        // The planner thread lets go of the store when its queue closes; wait for the lock.
        for _ in 0..100 {
            match Service::open(store.clone(), zones.clone(), &configure).await {
                Ok(s) => return s,
                Err(_) => tokio::time::sleep(Duration::from_millis(20)).await,
            }
        }
        panic!("the service restarts once the first one is gone");
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

    pub(crate) async fn post(&self, token: Option<&str>, body: &Value) -> (u16, Value) {
        self.send(
            reqwest::Method::POST,
            "/v1/flights",
            token,
            Some(body.to_string()),
        )
        .await
    }

    pub(crate) async fn get(&self, path: &str, token: Option<&str>) -> (u16, Value) {
        self.send(reqwest::Method::GET, path, token, None).await
    }

    pub(crate) async fn delete(&self, path: &str, token: Option<&str>) -> (u16, Value) {
        self.send(reqwest::Method::DELETE, path, token, None).await
    }
}

impl Service {
    /// Stops it cleanly and waits until it has let go of its store; where the store is.
    pub(crate) async fn stop(mut self) -> StoreAt {
        let _ = self.stop.take().unwrap().send(());
        tokio::time::timeout(Duration::from_secs(10), self.server.take().unwrap())
            .await
            .expect("a clean stop")
            .unwrap()
            .unwrap();
        std::mem::replace(&mut self.store, StoreAt::Folder(PathBuf::new()))
    }

    /// Its data folder (a test of the SQLite store only).
    pub(crate) fn folder(&self) -> &Path {
        match &self.store {
            StoreAt::Folder(dir) => dir,
            StoreAt::Postgres(url) => panic!("a service on {url} has no data folder"),
        }
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        if let StoreAt::Folder(dir) = &self.store
            && !dir.as_os_str().is_empty()
        {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// `now + secs`, as RFC 3339 in Singapore time.
pub(crate) fn in_secs(secs: i64) -> String {
    (Clock::system().now() + Millis::from_secs(secs)).to_rfc3339(UtcOffset::SINGAPORE)
}

pub(crate) fn flight(id: &str, from: &str, to: &str, departure: &str) -> Value {
    json!({"id": id, "origin": from, "destination": to, "departure": departure})
}

/// The ids of a listing's flights, in its order.
pub(crate) fn ids(list: &Value) -> Vec<&str> {
    list["flights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["request"].as_str().unwrap())
        .collect()
}

fn error_field(v: &Value) -> Option<&str> {
    v["error"]["field"].as_str()
}

async fn plan_reject_each_reason_and_read_back(kind: Kind) {
    let s = Service::start(kind, "reasons", |_| {}).await;
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
    assert_eq!(ids(&list), ["f1", "f2", "f3", "f4", "f5"]);
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

async fn retries_are_idempotent_and_conflicts_refused(kind: Kind) {
    let s = Service::start(kind, "idempotent", |_| {}).await;
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
            let r = client
                .post(url)
                .header("content-type", "application/json")
                .body(body)
                .send()
                .await
                .unwrap();
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

async fn cancel_before_take_off_frees_the_slot_and_not_after(kind: Kind) {
    let s = Service::start(kind, "cancel", |_| {}).await;
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
token = "alpha-secret-0001"
operator = "alpha"
role = "operator"

[[tokens]]
token = "bravo-secret-0002"
operator = "bravo"
role = "operator"

[[tokens]]
token = "authority-secret-0003"
operator = "caas"
role = "authority"
"#;

#[allow(clippy::many_single_char_names)]
async fn operators_see_their_own_flights_and_the_authority_all(kind: Kind) {
    let s = Service::start(kind, "auth", |o| {
        o.tokens = Tokens::parse(TOKENS, "tokens.toml").unwrap();
    })
    .await;
    let (a, b, auth) = (
        Some("alpha-secret-0001"),
        Some("bravo-secret-0002"),
        Some("authority-secret-0003"),
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

async fn bad_input_is_a_clear_4xx_and_changes_nothing(kind: Kind) {
    let s = Service::start(kind, "bad", |o| o.max_body = 1024).await;
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

async fn pages_after_concurrent_requests_list_each_flight_once(kind: Kind) {
    let s = Service::start(kind, "pages", |_| {}).await;
    let mut tasks = Vec::new();
    for k in 0..64 {
        let client = s.client.clone();
        let url = format!("{}/v1/flights", s.base);
        let (from, to) = if k % 2 == 0 { ("A", "C") } else { ("C", "A") };
        let body = flight(&format!("p{k}"), from, to, &in_secs(600 + 10 * k)).to_string();
        tasks.push(tokio::spawn(async move {
            client
                .post(url)
                .header("content-type", "application/json")
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

/// Ids are forever (docs/reference.md#the-planning-service): a departure in the past, however old,
/// is answered and stored, and its id names that answer from then on.
async fn departures_in_the_past_are_answered_and_kept(kind: Kind) {
    let s = Service::start(kind, "past", |_| {}).await;
    let (code, v) = s
        .post(None, &flight("old", "A", "B", &in_secs(-30 * 86_400)))
        .await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("departure_in_past"))
    );
    let (code, again) = s.get("/v1/flights/old", None).await;
    assert_eq!((code, &again), (200, &v));
    // The same id with a departure ahead is a conflict, not a second flight.
    let (code, v) = s.post(None, &flight("old", "A", "B", &in_secs(600))).await;
    assert_eq!((code, error_field(&v)), (409, Some("id")));
}

async fn requests_per_token_are_limited(kind: Kind) {
    let s = Service::start(kind, "rate", |o| {
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

async fn state_survives_a_restart_on_the_same_store(kind: Kind) {
    let data = kind.store("restart");
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
        let post = |body: Value| client.post(format!("{base}/v1/flights")).json(&body).send();
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
        // A second service on the same folder is refused while this one runs; on the same
        // database it stands by (see `standby.rs`).
        if let StoreAt::Folder(_) = &data {
            let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
            let e = start(world(), Options::new(data.clone()), listener)
                .await
                .unwrap_err()
                .to_string();
            assert!(e.contains("in use by another process"), "{e}");
        }
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
    // The cancelled flight holds nothing: only k1 is put back into the schedule.
    assert_eq!(running.restored.held, 1);
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
        .json(&flight("k3", "A", "C", &t))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(v["reason"], "no_feasible_plan");
    if let StoreAt::Folder(dir) = &data {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// The router serves every route of `ROUTES` (and the `OpenAPI` test below ties `ROUTES` to
/// the document).
async fn every_listed_route_is_served(kind: Kind) {
    let s = Service::start(kind, "routes", |_| {}).await;
    for (method, path) in muse_service::ROUTES {
        let method = reqwest::Method::from_bytes(method.to_uppercase().as_bytes()).unwrap();
        let path = path.replace("{id}", "some-id");
        if path == "/v1/events" {
            // An event stream never ends: its head is enough.
            let stream = EventStream::open(&s, None, None).await;
            drop(stream);
            continue;
        }
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
    let doc: Value = serde_json::from_str(muse_service::OPENAPI).unwrap();
    let mut described = Vec::new();
    for (path, item) in doc["paths"].as_object().unwrap() {
        for method in item.as_object().unwrap().keys() {
            described.push((method.clone(), path.clone()));
        }
    }
    described.sort();
    let mut routes: Vec<(String, String)> = muse_service::ROUTES
        .iter()
        .map(|(m, p)| ((*m).to_owned(), (*p).to_owned()))
        .collect();
    routes.sort();
    assert_eq!(described, routes);
}

// ---------------------------------------------------------------------------------------------
// Zones announced during the day (docs/reference.md#zones-announced-during-the-day) and the event
// stream.
// ---------------------------------------------------------------------------------------------

/// `now + ms`, as RFC 3339 in Singapore time.
fn in_ms(ms: i64) -> String {
    (Clock::system().now() + Millis(ms)).to_rfc3339(UtcOffset::SINGAPORE)
}

/// An ED-318 feature closing `nodes` from `from` to `to`.
fn zone_feature(id: &str, nodes: &[&str], from: &str, to: &str) -> Value {
    json!({
        "type": "Feature",
        "properties": {
            "identifier": id,
            "name": [{"text": format!("test zone {id}"), "lang": "en"}],
            "type": "PROHIBITED",
            "nodes": nodes,
            "limitedApplicability": [{"startDateTime": from, "endDateTime": to}],
        },
        "geometry": null,
    })
}

/// A zone known from the start: `F` closed for a day in 2000 (it closes nothing now).
fn base_zone() -> Zone {
    let text = zone_feature(
        "BASE",
        &["F"],
        "2000-01-01T00:00:00+08:00",
        "2000-01-02T00:00:00+08:00",
    )
    .to_string();
    muse_formats::zones::read_zones(&text, "base")
        .unwrap()
        .remove(0)
}

impl Service {
    async fn post_zone(&self, token: Option<&str>, body: &Value) -> (u16, Value) {
        self.send(
            reqwest::Method::POST,
            "/v1/zones",
            token,
            Some(body.to_string()),
        )
        .await
    }
}

/// Checks every flight the service holds as it finally stands (first plan, or replanned,
/// diverted, committed), with the zones as `GET /v1/zones` lists them, against
/// docs/reference.md#flight-model-and-separation, #no-fly-zones and
/// docs/reference.md#zones-announced-during-the-day (an announced zone binds only what begins after
/// its announcement and before its withdrawal). Returns how many flights fly.
async fn verify_everything(s: &Service, token: Option<&str>) -> usize {
    let air = airspace();
    let (code, list) = s.get("/v1/flights", token).await;
    assert_eq!(code, 200);
    let mut text = String::new();
    for f in list["flights"].as_array().unwrap() {
        // Rejected and operator-cancelled flights do not fly.
        if f["status"] != "rejected" && f["reason"] != "cancelled_by_operator" {
            text.push_str(&f.to_string());
            text.push('\n');
        }
    }
    let records = muse_formats::plans::read_plans(&text, "GET /v1/flights", &air).unwrap();
    let recorded = muse_verify::recorded::Recorded::new(records, &air).unwrap();
    let flights = recorded.flights();
    let (code, zones) = s.get("/v1/zones", token).await;
    assert_eq!(code, 200);
    let read = muse_formats::zones::read_zones(&zones.to_string(), "GET /v1/zones").unwrap();
    let now = Clock::system().now();
    let day = Millis::from_secs(86_400);
    let mut known =
        muse_airspace::announced::KnownZones::resolve(&air, &read, now - day, now + day).unwrap();
    for f in zones["features"].as_array().unwrap() {
        if let Some(w) = f["properties"]["withdrawn"].as_str() {
            let id = f["properties"]["identifier"].as_str().unwrap();
            let a = known.announced.iter_mut().find(|a| a.zone == id).unwrap();
            a.withdrawn = Some(muse_model::Instant::parse_rfc3339(w).unwrap());
        }
    }
    let violations = muse_verify::verify_known(&air, &known, &FlightParams::default(), &flights);
    assert!(violations.is_empty(), "{violations:#?}");
    flights.len()
}

/// `(flight, outcome, airborne)` of an announcement's answer.
fn outcomes(answer: &Value) -> Vec<(String, String, bool)> {
    answer["affected"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            (
                a["flight"].as_str().unwrap().to_owned(),
                a["outcome"].as_str().unwrap().to_owned(),
                a["airborne"].as_bool().unwrap(),
            )
        })
        .collect()
}

/// `GET /v1/closures` lists what each zone closes, as the planner works it out: a zone known
/// from the start by its node ids, then one announced with an area over the corridor `A-B`
/// (neither end inside); a withdrawn zone stays listed.
async fn closures_list_what_each_zone_closes(kind: Kind) {
    let s = Service::start_with(kind, "closures", vec![base_zone()], |_| {}).await;
    let ring = json!([[
        [103.804, 1.299],
        [103.806, 1.299],
        [103.806, 1.301],
        [103.804, 1.301],
        [103.804, 1.299]
    ]]);
    let mut zone = zone_feature("ZAB", &[], &in_secs(-60), &in_secs(600));
    zone["properties"].as_object_mut().unwrap().remove("nodes");
    zone["geometry"] = json!({"type": "Polygon", "coordinates": ring});
    let (code, v) = s.post_zone(None, &zone).await;
    assert_eq!(code, 201, "{v}");
    let expected = json!({"zones": [
        {"zone": "BASE", "nodes": ["F"], "corridors": []},
        {"zone": "ZAB", "nodes": [], "corridors": [{"id": "A-B", "from": "A", "to": "B"}]},
    ]});
    assert_eq!(s.get("/v1/closures", None).await, (200, expected.clone()));
    let (code, v) = s.delete("/v1/zones/ZAB", None).await;
    assert_eq!(code, 200, "{v}");
    assert_eq!(s.get("/v1/closures", None).await, (200, expected));
}

#[allow(clippy::too_many_lines, clippy::many_single_char_names)] // One story, told in order.
async fn an_announced_zone_replans_what_it_hits_and_everything_still_verifies(kind: Kind) {
    let s = Service::start_with(kind, "zones", vec![base_zone()], |o| {
        o.tokens = Tokens::parse(TOKENS, "tokens.toml").unwrap();
    })
    .await;
    let (a, b, auth) = (
        Some("alpha-secret-0001"),
        Some("bravo-secret-0002"),
        Some("authority-secret-0003"),
    );
    // Two flights take off in 1.5 s; the others are ahead.
    let soon = in_ms(1_500);
    for (token, id, from, to, at) in [
        (a, "a1", "A", "C", soon.clone()),
        (b, "k1", "X", "Y", soon.clone()),
        (a, "a2", "A", "C", in_secs(600)),
        (b, "b1", "B", "C", in_secs(1_500)),
        (b, "b2", "X", "Y", in_secs(600)),
        (a, "a3", "B", "A", in_secs(1_200)),
    ] {
        let (code, v) = s.post(token, &flight(id, from, to, &at)).await;
        assert_eq!(code, 201, "{id}: {v}");
    }
    tokio::time::sleep(Duration::from_secs(2)).await;
    let (_, before) = s.get("/v1/flights", auth).await;

    // C closed for the next 40 minutes.
    let zc = zone_feature("ZC", &["C"], &in_secs(-60), &in_secs(2_400));
    let (code, v) = s.post_zone(a, &zc).await;
    assert_eq!(
        (code, v["error"]["code"].as_str()),
        (403, Some("forbidden"))
    );
    let mut announced = zc.clone();
    announced["properties"]["announced"] = json!(in_secs(0));
    let bad = [
        (announced, Some("properties.announced")),
        (
            zone_feature("ZQ", &["Q"], &in_secs(0), &in_secs(60)),
            Some("nodes"),
        ),
        (
            json!({"type": "Feature", "properties": {"identifier": "ZN", "nodes": "C"}}),
            Some("nodes"),
        ),
        (
            json!({"type": "FeatureCollection", "features": [zc, zc]}),
            Some("features"),
        ),
        (json!({"type": "Point"}), Some("type")),
        (json!("not a zone"), Some("type")),
    ];
    for (body, field) in &bad {
        let (code, v) = s.post_zone(auth, body).await;
        assert_eq!((code, error_field(&v)), (422, *field), "{body}: {v}");
    }
    let (code, v) = s
        .send(reqwest::Method::POST, "/v1/zones", auth, Some("{".into()))
        .await;
    assert_eq!(code, 422, "{v}");
    // Nothing changed yet.
    assert_eq!(s.get("/v1/flights", auth).await.1, before);

    let (code, answer) = s.post_zone(auth, &zc).await;
    assert_eq!(code, 201, "{answer}");
    assert_eq!(answer["zone"], "ZC");
    // In take-off order: a1 is in A-B and cannot wait 40 minutes for C: it lands at B; a2
    // could not hover that long either; b1 can (it now lands when C opens again).
    assert_eq!(
        outcomes(&answer),
        [
            ("a1".into(), "diverted".into(), true),
            ("a2".into(), "cancelled".into(), false),
            ("b1".into(), "replanned".into(), false),
        ]
    );
    for affected in answer["affected"].as_array().unwrap() {
        let id = affected["flight"].as_str().unwrap();
        let (code, got) = s.get(&format!("/v1/flights/{id}"), auth).await;
        assert_eq!((code, &got), (200, &affected["plan"]), "{id}");
        assert_eq!(got["changes"][0]["zone"], "ZC");
        assert_eq!(got["changes"][0]["announced"], answer["announced"]);
    }
    let a1 = &answer["affected"][0]["plan"];
    assert_eq!(
        (a1["status"].as_str(), a1["diverted_to"].as_str()),
        (Some("diverted"), Some("B"))
    );
    assert_eq!(answer["affected"][1]["plan"]["reason"], "zone_announced");
    assert!(
        answer["affected"][2]["plan"]["extra_delay_s"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    // An id is never reused, a base zone's neither.
    for id in ["ZC", "BASE"] {
        let mut again = zc.clone();
        again["properties"]["identifier"] = json!(id);
        let (code, v) = s.post_zone(auth, &again).await;
        assert_eq!((code, error_field(&v)), (409, Some("identifier")), "{v}");
    }

    // Y closed too (sent as a collection of one): k1, in X-Y, is committed to arriving there.
    let zy = zone_feature("ZY", &["Y"], &in_secs(-60), &in_secs(2_400));
    let (code, answer) = s
        .post_zone(
            auth,
            &json!({"type": "FeatureCollection", "features": [zy]}),
        )
        .await;
    assert_eq!(code, 201, "{answer}");
    assert_eq!(
        outcomes(&answer),
        [
            ("k1".into(), "contingency".into(), true),
            ("b2".into(), "cancelled".into(), false),
        ]
    );
    let k1 = &answer["affected"][0]["plan"];
    assert!(k1["path"].is_null() && k1["landing"].is_null());
    assert_eq!(k1["committed"].as_array().unwrap().len(), 2);

    // Listings know the new statuses; an operator sees only its own.
    let count = |v: &Value| v["flights"].as_array().unwrap().len();
    for (status, n) in [
        ("diverted", 1),
        ("cancelled", 2),
        ("replanned", 1),
        ("contingency", 1),
        ("planned", 1),
    ] {
        let (code, v) = s.get(&format!("/v1/flights?status={status}"), auth).await;
        assert_eq!((code, count(&v)), (200, n), "{status}: {v}");
    }
    assert_eq!(count(&s.get("/v1/flights?status=cancelled", a).await.1), 1);
    assert_eq!(s.get("/v1/flights/b1", a).await.0, 404);
    assert_eq!(verify_everything(&s, auth).await, 4);

    // Withdrawing: the authority only; base zones and unknown ids are refused; it replans
    // nothing, and is idempotent.
    let (_, before) = s.get("/v1/flights", auth).await;
    assert_eq!(s.delete("/v1/zones/ZC", a).await.0, 403);
    let (code, v) = s.delete("/v1/zones/BASE", auth).await;
    assert_eq!(
        (code, v["error"]["code"].as_str()),
        (409, Some("known_from_start")),
        "{v}"
    );
    assert!(
        v["error"]["message"]
            .as_str()
            .unwrap()
            .contains("known from the start, cannot be withdrawn")
    );
    assert_eq!(s.delete("/v1/zones/NOPE", auth).await.0, 404);
    let (code, w) = s.delete("/v1/zones/ZC", auth).await;
    assert_eq!(code, 200, "{w}");
    assert_eq!(
        (w["zone"].as_str(), w["affected"].as_u64()),
        (Some("ZC"), Some(3))
    );
    assert!(w["withdrawn"].is_string());
    assert_eq!(s.delete("/v1/zones/ZC", auth).await, (200, w));
    assert_eq!(s.get("/v1/flights", auth).await.1, before);
    let (_, zones) = s.get("/v1/zones", a).await;
    let listed: Vec<(&str, bool, bool)> = zones["features"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let p = &f["properties"];
            (
                p["identifier"].as_str().unwrap(),
                p["announced"].is_string(),
                p["withdrawn"].is_string(),
            )
        })
        .collect();
    assert_eq!(
        listed,
        [
            ("BASE", false, false),
            ("ZC", true, true),
            ("ZY", true, false)
        ]
    );
    // C is open again: a new flight lands there on time.
    let (code, v) = s.post(a, &flight("a4", "A", "C", &in_secs(700))).await;
    assert_eq!(
        (
            code,
            v["ground_delay_s"].as_f64(),
            v["air_delay_s"].as_f64()
        ),
        (201, Some(0.0), Some(0.0)),
        "{v}"
    );

    // A replanned flight can be cancelled by its operator before its new take-off.
    let (code, v) = s.delete("/v1/flights/b1", b).await;
    assert_eq!(
        (code, v["status"].as_str(), v["reason"].as_str()),
        (200, Some("cancelled"), Some("cancelled_by_operator")),
        "{v}"
    );
    assert!(v["path"].is_null() && v["changes"][0]["outcome"] == "replanned");
    // A flight a zone cancelled is cancelled already; a contingency took off.
    assert_eq!(
        s.delete("/v1/flights/a2", a).await.1["reason"],
        "zone_announced"
    );
    assert_eq!(s.delete("/v1/flights/k1", b).await.0, 409);
    assert_eq!(verify_everything(&s, auth).await, 4);

    // A restart replays the log without planning: the same flights, zones and events (ids
    // included). An open event stream does not hold up the stop.
    let mut stream = EventStream::open(&s, auth, Some("0")).await;
    // 7 bookings, 5 zone outcomes, 1 cancellation.
    let events = stream.take(13).await;
    assert_eq!(events.last().unwrap().0, 13);
    let (_, flights) = s.get("/v1/flights", auth).await;
    let (_, zones) = s.get("/v1/zones", auth).await;
    let s = s
        .restart(|o| o.tokens = Tokens::parse(TOKENS, "tokens.toml").unwrap())
        .await;
    assert_eq!(s.get("/v1/flights", auth).await.1, flights);
    assert_eq!(s.get("/v1/zones", auth).await.1, zones);
    assert_eq!(
        EventStream::open(&s, auth, Some("0")).await.take(13).await,
        events
    );
    // The zones are back in the schedule: Y is still closed, C open again.
    let (code, v) = s.post(b, &flight("b3", "X", "Y", &in_secs(700))).await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("no_feasible_plan")),
        "{v}"
    );
    assert_eq!(
        s.post(a, &flight("a5", "B", "C", &in_secs(900))).await.0,
        201
    );
    assert_eq!(
        s.post_zone(auth, &zone_feature("ZC", &["A"], &in_secs(0), &in_secs(60)))
            .await
            .0,
        409
    );
    assert_eq!(s.delete("/v1/zones/ZY", auth).await.0, 200);
    assert_eq!(verify_everything(&s, auth).await, 5);
}

/// A client of `GET /v1/events`.
struct EventStream {
    response: reqwest::Response,
    buffer: String,
}

/// One server-sent event: id, type, data.
type Received = (u64, String, Value);

impl EventStream {
    async fn open(s: &Service, token: Option<&str>, last: Option<&str>) -> EventStream {
        let mut rq = s.client.get(format!("{}/v1/events", s.base));
        if let Some(t) = token {
            rq = rq.bearer_auth(t);
        }
        if let Some(id) = last {
            rq = rq.header("last-event-id", id);
        }
        let response = rq.send().await.unwrap();
        assert_eq!(response.status().as_u16(), 200);
        assert_eq!(
            response.headers()["content-type"].to_str().unwrap(),
            "text/event-stream"
        );
        EventStream {
            response,
            buffer: String::new(),
        }
    }

    /// The next event (comments skipped); fails after 10 s without one.
    async fn next(&mut self) -> Received {
        loop {
            if let Some(end) = self.buffer.find("\n\n") {
                let frame: String = self.buffer.drain(..end + 2).collect();
                let (mut id, mut kind, mut data) = (None, None, None);
                for line in frame.lines() {
                    if let Some(v) = line.strip_prefix("id: ").or(line.strip_prefix("id:")) {
                        id = Some(v.parse::<u64>().unwrap());
                    } else if let Some(v) =
                        line.strip_prefix("event: ").or(line.strip_prefix("event:"))
                    {
                        kind = Some(v.to_owned());
                    } else if let Some(v) =
                        line.strip_prefix("data: ").or(line.strip_prefix("data:"))
                    {
                        data = Some(serde_json::from_str::<Value>(v).unwrap());
                    }
                }
                match (id, kind, data) {
                    (Some(id), Some(kind), Some(data)) => return (id, kind, data),
                    (None, None, None) => continue, // a comment (keep-alive)
                    other => panic!("incomplete event {other:?} in {frame:?}"),
                }
            }
            let chunk = tokio::time::timeout(Duration::from_secs(10), self.response.chunk())
                .await
                .expect("an event within 10 s")
                .unwrap()
                .expect("the stream goes on");
            self.buffer.push_str(std::str::from_utf8(&chunk).unwrap());
        }
    }

    /// The next `n` events.
    async fn take(&mut self, n: usize) -> Vec<Received> {
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            out.push(self.next().await);
        }
        out
    }
}

/// `(id, type, flight)` of events.
fn summary(events: &[Received]) -> Vec<(u64, &str, &str)> {
    events
        .iter()
        .map(|(id, kind, data)| (*id, kind.as_str(), data["flight"].as_str().unwrap()))
        .collect()
}

/// Checks the data of alpha's (`mine`) and bravo's (`theirs`) events of the event test:
/// who, what, why, and the flight as `GET /v1/flights/{id}` shows it.
async fn check_event_data(s: &Service, mine: &[Received], theirs: &[Received]) {
    let (a, b) = (Some("alpha-secret-0001"), Some("bravo-secret-0002"));
    for (_, kind, data) in mine.iter().chain(theirs) {
        assert_eq!(data["status"].as_str(), Some(kind.as_str()), "{data}");
        assert_eq!(data["plan"]["status"], data["status"]);
        assert_eq!(
            data["operator"],
            if data["flight"] == "e2" {
                "bravo"
            } else {
                "alpha"
            }
        );
    }
    assert_eq!(mine[2].2["plan"]["reason"], "cancelled_by_operator");
    assert!(mine[2].2.get("zone").is_none());
    assert_eq!(
        (mine[3].2["zone"].as_str(), theirs[1].2["zone"].as_str()),
        (Some("ZB"), Some("ZB"))
    );
    assert_eq!(theirs[1].2["plan"]["reason"], "zone_announced");
    assert_eq!(mine[3].2["plan"], s.get("/v1/flights/e1", a).await.1);
    assert_eq!(theirs[1].2["plan"], s.get("/v1/flights/e2", b).await.1);
}

async fn event_streams_show_each_operator_its_own_flights_and_resume_exactly(kind: Kind) {
    let s = Service::start(kind, "events", |o| {
        o.tokens = Tokens::parse(TOKENS, "tokens.toml").unwrap();
    })
    .await;
    let (a, b, auth) = (
        Some("alpha-secret-0001"),
        Some("bravo-secret-0002"),
        Some("authority-secret-0003"),
    );
    // Alpha listens live from now; bravo and the authority from the start of the history.
    let mut alpha = EventStream::open(&s, a, None).await;
    let mut bravo = EventStream::open(&s, b, Some("0")).await;
    let mut all = EventStream::open(&s, auth, Some("0")).await;
    assert_eq!(
        s.post(a, &flight("e1", "A", "B", &in_secs(600))).await.0,
        201
    );
    assert_eq!(
        s.post(b, &flight("e2", "B", "C", &in_secs(600))).await.0,
        201
    );
    assert_eq!(
        s.post(a, &flight("e3", "A", "C", &in_secs(1_200))).await.0,
        201
    );
    assert_eq!(s.delete("/v1/flights/e3", a).await.0, 200);
    // A rejection is no event.
    assert_eq!(
        s.post(a, &flight("e4", "A", "F", &in_secs(600))).await.0,
        200
    );
    // B closed for 20 minutes: e1 waits for it in the air, e2 cannot leave it.
    let zone = zone_feature("ZB", &["B"], &in_secs(-60), &in_secs(1_200));
    let (code, answer) = s.post_zone(auth, &zone).await;
    assert_eq!(code, 201, "{answer}");
    assert_eq!(
        outcomes(&answer),
        [
            ("e1".into(), "replanned".into(), false),
            ("e2".into(), "cancelled".into(), false),
        ]
    );

    let mine = alpha.take(4).await;
    assert_eq!(
        summary(&mine),
        [
            (1, "planned", "e1"),
            (3, "planned", "e3"),
            (4, "cancelled", "e3"),
            (5, "replanned", "e1")
        ]
    );
    let theirs = bravo.take(2).await;
    assert_eq!(
        summary(&theirs),
        [(2, "planned", "e2"), (6, "cancelled", "e2")]
    );
    let every = all.take(6).await;
    assert_eq!(
        every.iter().map(|e| e.0).collect::<Vec<_>>(),
        [1, 2, 3, 4, 5, 6]
    );
    check_event_data(&s, &mine, &theirs).await;

    // Resuming after event 3: exactly alpha's events 4 and 5 again, then live ones.
    let mut resumed = EventStream::open(&s, a, Some("3")).await;
    let again = resumed.take(2).await;
    assert_eq!(again, mine[2..]);
    assert_eq!(
        s.post(b, &flight("e7", "X", "Y", &in_secs(600))).await.0,
        201
    );
    assert_eq!(
        s.post(a, &flight("e8", "A", "B", &in_secs(2_400))).await.0,
        201
    );
    assert_eq!(summary(&[resumed.next().await]), [(8, "planned", "e8")]);
    assert_eq!(summary(&[alpha.next().await]), [(8, "planned", "e8")]);
    assert_eq!(summary(&[bravo.next().await]), [(7, "planned", "e7")]);
    assert_eq!(
        summary(&all.take(2).await),
        [(7, "planned", "e7"), (8, "planned", "e8")]
    );
    // A bad Last-Event-ID is refused.
    let r = s
        .client
        .get(format!("{}/v1/events", s.base))
        .bearer_auth("alpha-secret-0001")
        .header("last-event-id", "x")
        .send()
        .await
        .unwrap();
    assert_eq!(r.status().as_u16(), 422);
    assert_eq!(s.get("/v1/events", None).await.0, 401);
}

async fn a_listener_that_falls_behind_reads_the_history_and_misses_nothing(kind: Kind) {
    // One live event of slack: a zone's outcomes, published in one burst, overrun it.
    let s = Service::start(kind, "lag", |o| o.event_buffer = 1).await;
    let mut stream = EventStream::open(&s, None, Some("0")).await;
    for k in 0..8 {
        let (code, v) = s
            .post(
                None,
                &flight(&format!("l{k}"), "X", "Y", &in_secs(600 + 300 * k)),
            )
            .await;
        assert_eq!(code, 201, "{v}");
    }
    // Y closed for more than an hour: no flight can hover that long.
    let zone = zone_feature("ZL", &["Y"], &in_secs(-60), &in_secs(4_000));
    let (code, answer) = s.post_zone(None, &zone).await;
    assert_eq!(
        (code, answer["affected"].as_array().map(Vec::len)),
        (201, Some(8)),
        "{answer}"
    );
    let events = stream.take(16).await;
    let got: Vec<(u64, &str, &str)> = summary(&events);
    let mut want = Vec::new();
    let ids: Vec<String> = (0..8).map(|k| format!("l{k}")).collect();
    for (k, id) in ids.iter().enumerate() {
        want.push((k as u64 + 1, "planned", id.as_str()));
    }
    for (k, id) in ids.iter().enumerate() {
        want.push((k as u64 + 9, "cancelled", id.as_str()));
    }
    assert_eq!(got, want);
    let (_, metrics) = s.get("/metrics", None).await;
    let metrics = metrics.as_str().unwrap();
    assert!(
        metrics.contains("muse_zones_total{change=\"announced\"} 1"),
        "{metrics}"
    );
    let lags = metrics
        .lines()
        .find_map(|l| l.strip_prefix("muse_event_lags_total "))
        .unwrap();
    println!("the listener fell behind {lags} time(s)");
}

/// `r1` A → C at `t` and `r2` B → C a minute later, sent in that order within the batch
/// window: first come, first served, `r1` holds B-C from `t + 2 min` and `r2` (no ground
/// delay) finds no plan; as one batch, `r2` flies first and `r1` hovers a minute at B.
async fn requests_arriving_together_are_planned_as_one_batch(kind: Kind) {
    for (window_ms, both) in [(0_u64, false), (1_000, true)] {
        let service = Service::start(kind, &format!("batch-{window_ms}"), |o| {
            o.batch_window = Duration::from_millis(window_ms);
        })
        .await;
        // One instant for both: two readings of the clock would put them a millisecond or
        // more further apart than the minute the test is about.
        let now = Clock::system().now();
        let at = |secs: i64| (now + Millis::from_secs(secs)).to_rfc3339(UtcOffset::SINGAPORE);
        let (at_a, at_b) = (at(600), at(660));
        let r1 = flight("r1", "A", "C", &at_a);
        let first = service.post(None, &r1);
        let second = async {
            tokio::time::sleep(Duration::from_millis(50)).await;
            service.post(None, &flight("r2", "B", "C", &at_b)).await
        };
        let ((c1, v1), (c2, v2)) = tokio::join!(first, second);
        assert_eq!(c1, 201, "window {window_ms} ms: {v1}");
        if both {
            assert_eq!(c2, 201, "window {window_ms} ms: {v2}");
            assert_eq!(v1["air_delay_s"], 60.0, "{v1}");
            assert_eq!(v2["air_delay_s"], 0.0, "{v2}");
        } else {
            assert_eq!(
                (c2, v2["reason"].as_str()),
                (200, Some("no_feasible_plan")),
                "{v2}"
            );
        }
        // Answered and numbered in order of arrival; a retry inside a batch is a retry.
        let (list_code, list) = service.get("/v1/flights", None).await;
        assert_eq!(list_code, 200);
        let ids: Vec<&str> = list["flights"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["request"].as_str().unwrap())
            .collect();
        assert_eq!(ids, ["r1", "r2"], "window {window_ms} ms");
        let body = flight("r3", "X", "Y", &in_secs(900));
        let ((code_a, once), (code_b, twice)) =
            tokio::join!(service.post(None, &body), service.post(None, &body));
        assert_eq!((code_a, code_b), (201, 201), "{once} {twice}");
        assert_eq!(once, twice);
        let other = flight("r3", "Y", "X", &in_secs(900));
        let ((code_c, _), (code_d, refused)) =
            tokio::join!(service.post(None, &body), service.post(None, &other));
        assert_eq!((code_c, code_d), (201, 409), "{refused}");
        assert_eq!(
            verify_everything(&service, None).await,
            if both { 3 } else { 2 }
        );
    }
}

on_both_stores!(
    plan_reject_each_reason_and_read_back,
    retries_are_idempotent_and_conflicts_refused,
    cancel_before_take_off_frees_the_slot_and_not_after,
    operators_see_their_own_flights_and_the_authority_all,
    bad_input_is_a_clear_4xx_and_changes_nothing,
    pages_after_concurrent_requests_list_each_flight_once,
    departures_in_the_past_are_answered_and_kept,
    requests_per_token_are_limited,
    state_survives_a_restart_on_the_same_store,
    every_listed_route_is_served,
    closures_list_what_each_zone_closes,
    an_announced_zone_replans_what_it_hits_and_everything_still_verifies,
    event_streams_show_each_operator_its_own_flights_and_resume_exactly,
    a_listener_that_falls_behind_reads_the_history_and_misses_nothing,
    requests_arriving_together_are_planned_as_one_batch,
);
