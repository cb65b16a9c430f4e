//! The service under `kill -9`: concurrent clients plan and cancel while the `muse serve`
//! process is killed with SIGKILL at random moments and restarted on the same `--data`.
//!
//! After every restart: every acknowledged flight (and every acknowledged cancellation) is
//! there and unchanged; every request left unanswered by the kill, retried with its id, gets
//! one consistent answer; and at the end the recovered set of planned flights passes the
//! verifier. Bounded: a fixed number of kill cycles, each a fraction of a second of load.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use muse_airspace::closures::resolve;
use muse_model::{FlightParams, Millis, Request, UtcOffset};
use rand::{RngExt as _, SeedableRng as _};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use crate::support::{StoreArg, start_on};

const CYCLES: usize = 12;
/// Concurrent clients during each cycle.
const CLIENTS: usize = 8;
const SEED: u64 = 0x6b11_1009;

/// What the clients learnt, shared between them.
#[derive(Default)]
struct Ledger {
    /// Acknowledged state of each flight: the last answer received about it.
    acked: BTreeMap<String, Value>,
    /// Requests sent whose answer never came (the server died), with their bodies.
    unanswered: BTreeMap<String, Value>,
    /// Planned flights whose cancellation was sent but never answered: either state is right.
    cancel_unanswered: BTreeSet<String>,
}

pub(crate) fn rfc3339_in(ms: i64) -> String {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_millis() as i64;
    muse_model::Instant(now + ms).to_rfc3339(UtcOffset::SINGAPORE)
}

/// One client: plans requests one after another and cancels some of its planned flights,
/// until the server stops answering.
async fn client(
    base: String,
    cycle: usize,
    k: usize,
    stations: Arc<Vec<String>>,
    ledger: Arc<Mutex<Ledger>>,
) {
    let http = reqwest::Client::new();
    let mut rng = ChaCha8Rng::seed_from_u64(SEED ^ ((cycle as u64) << 16) ^ k as u64);
    for n in 0.. {
        let id = format!("c{cycle}-k{k}-n{n}");
        let o = rng.random_range(0..stations.len());
        let mut d = rng.random_range(0..stations.len() - 1);
        if d >= o {
            d += 1;
        }
        // Departures 5 minutes to 3 hours ahead: nothing takes off during the test.
        let body = json!({
            "id": id,
            "origin": stations[o],
            "destination": stations[d],
            "departure": rfc3339_in(rng.random_range(300_000..10_800_000)),
        });
        ledger
            .lock()
            .unwrap()
            .unanswered
            .insert(id.clone(), body.clone());
        let Ok(response) = http
            .post(format!("{base}/v1/flights"))
            .header("content-type", "application/json")
            .body(body.to_string())
            .send()
            .await
        else {
            return;
        };
        let code = response.status().as_u16();
        let Ok(answer) = response.json::<Value>().await else {
            return;
        };
        assert!(code == 201 || code == 200, "{code}: {answer}");
        {
            let mut l = ledger.lock().unwrap();
            l.unanswered.remove(&id);
            l.acked.insert(id.clone(), answer.clone());
        }
        if code == 201 && rng.random_range(0..5) == 0 {
            ledger.lock().unwrap().cancel_unanswered.insert(id.clone());
            let Ok(response) = http.delete(format!("{base}/v1/flights/{id}")).send().await else {
                return;
            };
            let code = response.status().as_u16();
            let Ok(answer) = response.json::<Value>().await else {
                return;
            };
            assert_eq!(code, 200, "{answer}");
            assert_eq!(answer["status"], "cancelled");
            let mut l = ledger.lock().unwrap();
            l.cancel_unanswered.remove(&id);
            l.acked.insert(id, answer);
        }
    }
}

/// The station ids of the Singapore default the binary serves.
pub(crate) fn stations() -> Arc<Vec<String>> {
    let scenario = muse_scenario::by_name("singapore-77").unwrap();
    Arc::new(
        scenario
            .airspace
            .stations()
            .map(|s| scenario.airspace.node(s).id.clone())
            .collect(),
    )
}

pub(crate) async fn get(http: &reqwest::Client, url: String) -> (u16, Value) {
    let r = http.get(url).send().await.expect("server answers");
    let code = r.status().as_u16();
    (code, r.json().await.expect("JSON"))
}

/// Every flight the server holds, by id, read page by page.
pub(crate) async fn all_flights(http: &reqwest::Client, base: &str) -> BTreeMap<String, Value> {
    let mut out = BTreeMap::new();
    let mut after: Option<u64> = None;
    loop {
        let url = match after {
            Some(a) => format!("{base}/v1/flights?limit=5000&after={a}"),
            None => format!("{base}/v1/flights?limit=5000"),
        };
        let (code, page) = get(http, url).await;
        assert_eq!(code, 200, "{page}");
        for f in page["flights"].as_array().unwrap() {
            let id = f["request"].as_str().unwrap().to_owned();
            assert!(
                out.insert(id.clone(), f.clone()).is_none(),
                "{id} listed twice"
            );
        }
        match page["next_after"].as_u64() {
            Some(a) => after = Some(a),
            None => return out,
        }
    }
}

/// Checks, on a freshly restarted server, that every acknowledged state is there unchanged
/// and that retrying each unanswered request gives one consistent answer (which becomes
/// acknowledged).
async fn check_restart(base: &str, ledger: &Mutex<Ledger>) {
    let http = reqwest::Client::new();
    let (acked, unanswered, cancels) = {
        let l = ledger.lock().unwrap();
        (
            l.acked.clone(),
            l.unanswered.clone(),
            l.cancel_unanswered.clone(),
        )
    };
    let held = all_flights(&http, base).await;
    for (id, want) in &acked {
        let got = held
            .get(id)
            .unwrap_or_else(|| panic!("acknowledged flight {id} lost"));
        if cancels.contains(id) && got["status"] == "cancelled" {
            // The unanswered cancellation was durable before the kill: now it is known.
            let mut l = ledger.lock().unwrap();
            l.cancel_unanswered.remove(id);
            l.acked.insert(id.clone(), got.clone());
            continue;
        }
        assert_eq!(got, want, "acknowledged flight {id} changed");
    }
    for (id, body) in &unanswered {
        let post = || {
            http.post(format!("{base}/v1/flights"))
                .header("content-type", "application/json")
                .body(body.to_string())
                .send()
        };
        let first = post().await.expect("answers");
        let (c1, a1): (u16, Value) = (first.status().as_u16(), first.json().await.unwrap());
        let second = post().await.expect("answers");
        let (c2, a2): (u16, Value) = (second.status().as_u16(), second.json().await.unwrap());
        assert!(c1 == 201 || c1 == 200, "retry of {id}: {c1} {a1}");
        assert_eq!(
            (c1, &a1),
            (c2, &a2),
            "retry of {id} answered twice differently"
        );
        let (_, stored) = get(&http, format!("{base}/v1/flights/{id}")).await;
        assert_eq!(stored, a1, "retry of {id}: stored differs from the answer");
        let mut l = ledger.lock().unwrap();
        l.unanswered.remove(id);
        l.acked.insert(id.clone(), a1);
    }
}

/// Runs the verifier on every planned flight the server holds.
pub(crate) async fn verify_all(base: &str) -> usize {
    let http = reqwest::Client::new();
    let (_, list) = get(&http, format!("{base}/v1/flights?status=planned")).await;
    let mut text = String::new();
    for f in list["flights"].as_array().unwrap() {
        text.push_str(&f.to_string());
        text.push('\n');
    }
    let scenario = muse_scenario::by_name("singapore-77").unwrap();
    let airspace = &scenario.airspace;
    let records = muse_formats::plans::read_plans(&text, "GET /v1/flights", airspace).unwrap();
    let requests: Vec<Request> = records
        .iter()
        .map(|r| Request {
            id: r.request.clone(),
            origin: airspace.node_id(&r.origin).unwrap(),
            destination: airspace.node_id(&r.destination).unwrap(),
            departure: r.requested_departure,
            submitted: r.requested_departure,
        })
        .collect();
    let flights: Vec<muse_verify::Flight<'_>> = records
        .iter()
        .zip(&requests)
        .map(|(r, q)| muse_verify::Flight::new(&r.request, q, r.result.as_ref().expect("planned")))
        .collect();
    let day = Millis::from_secs(86_400);
    let from = requests.iter().map(|r| r.departure).min().unwrap() - day;
    let to = requests.iter().map(|r| r.departure).max().unwrap() + day;
    let closures = resolve(airspace, &scenario.zones, from, to).unwrap();
    let violations = muse_verify::verify(airspace, &closures, &FlightParams::default(), &flights);
    assert!(violations.is_empty(), "{violations:?}");
    flights.len()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn acknowledged_flights_survive_sigkill() {
    survive_sigkill(false).await;
}

/// The same on a PostgreSQL store: each SIGKILL ends the service's session, and the
/// restarted process takes the lead at once.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn acknowledged_flights_survive_sigkill_on_postgres() {
    survive_sigkill(true).await;
}

async fn survive_sigkill(postgres: bool) {
    println!("seed {SEED:#x}");
    let Some(data) = StoreArg::fresh("serve-crash", postgres) else {
        return;
    };
    let stations = stations();
    let ledger = Arc::new(Mutex::new(Ledger::default()));
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    for cycle in 0..CYCLES {
        let server = start_on(&data, &[]);
        check_restart(&server.base, &ledger).await;
        let tasks: Vec<_> = (0..CLIENTS)
            .map(|k| {
                tokio::spawn(client(
                    server.base.clone(),
                    cycle,
                    k,
                    Arc::clone(&stations),
                    Arc::clone(&ledger),
                ))
            })
            .collect();
        tokio::time::sleep(Duration::from_millis(rng.random_range(100..800))).await;
        server.kill();
        for t in tasks {
            t.await.expect("client task");
        }
        let l = ledger.lock().unwrap();
        println!(
            "cycle {cycle}: {} acknowledged so far, {} unanswered at the kill",
            l.acked.len(),
            l.unanswered.len()
        );
    }
    let server = start_on(&data, &[]);
    check_restart(&server.base, &ledger).await;
    let planned = verify_all(&server.base).await;
    let acked = ledger.lock().unwrap().acked.len();
    println!(
        "{acked} flights acknowledged over {CYCLES} kills; {planned} planned flights verified"
    );
    assert!(
        acked > 1_000 && planned > 100,
        "too little load: {acked} {planned}"
    );
    server.kill();
    data.remove();
}
