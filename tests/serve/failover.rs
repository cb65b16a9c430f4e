//! Three `muse serve` processes on one PostgreSQL store (docs/service.md#several-services-on-
//! one-postgresql), 16 clients sending requests to any of them, and the leader killed with
//! SIGKILL again and again ([`KILLS`] times), each time started again (it comes back as a
//! standby).
//!
//! A client sends each request to an instance drawn at random, and when no answer comes (the
//! instance died, or answered `503` while the lead moved) sends it again, with the same id, to
//! another, until one answers. Checked: every id is answered the same way every time it is
//! answered (before and after take-overs); at the end every acknowledged flight reads, at
//! every instance, as first answered (none lost or changed); and the planned flights pass the
//! verifier (no two violate §3). Bounded: a fixed number of kills, each after a fraction of a
//! second of load, and every wait has a deadline.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use rand::{RngExt as _, SeedableRng as _};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use crate::crash::{all_flights, get, rfc3339_in, stations, verify_all};
use crate::support::throwaway_pg::Throwaway;
use crate::support::{Server, start_with};

/// Times the leader is killed.
const KILLS: usize = 8;
/// Services on the store.
const INSTANCES: usize = 3;
/// Concurrent clients.
const CLIENTS: usize = 16;
const SEED: u64 = 0x40_fa11;

/// The instances: each slot's base URL while its process runs.
type Bases = Arc<Mutex<Vec<Option<String>>>>;

/// Every answer given, by id: the first, to which every later one must be equal.
#[derive(Default)]
struct Answers {
    first: BTreeMap<String, Value>,
    /// Answers that repeated an earlier one (retries after a lost answer).
    repeated: usize,
    /// Sends that got no answer (a dead instance, or `503` while the lead moved).
    unanswered: usize,
}

/// Sends `body` to instances drawn at random until one answers (`200` or `201`); checks the
/// answer against the first one given for its id. `None` once `stop` is set first.
async fn answer(
    http: &reqwest::Client,
    bases: &Bases,
    body: &Value,
    rng: &mut ChaCha8Rng,
    answers: &Mutex<Answers>,
    stop: &AtomicBool,
) -> Option<Value> {
    let id = body["id"].as_str().unwrap().to_owned();
    let deadline = Instant::now() + Duration::from_mins(1);
    loop {
        assert!(Instant::now() < deadline, "{id}: no answer for 60 s");
        let alive: Vec<String> = bases.lock().unwrap().iter().flatten().cloned().collect();
        if alive.is_empty() {
            tokio::time::sleep(Duration::from_millis(20)).await;
            continue;
        }
        let base = &alive[rng.random_range(0..alive.len())];
        let sent = http
            .post(format!("{base}/v1/flights"))
            .header("content-type", "application/json")
            .body(body.to_string())
            .send()
            .await;
        let got = match sent {
            Ok(r) if r.status() == 200 || r.status() == 201 => r.json::<Value>().await.ok(),
            Ok(r) => {
                let code = r.status().as_u16();
                let text = r.text().await.unwrap_or_default();
                assert!(code == 503, "{id} at {base}: {code} {text}");
                None
            }
            Err(_) => None,
        };
        let Some(got) = got else {
            answers.lock().unwrap().unanswered += 1;
            if stop.load(Ordering::Relaxed) {
                return None;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
            continue;
        };
        let mut a = answers.lock().unwrap();
        match a.first.get(&id) {
            Some(first) => {
                assert_eq!(&got, first, "{id} answered otherwise than first");
                a.repeated += 1;
            }
            None => {
                a.first.insert(id, got.clone());
            }
        }
        return Some(got);
    }
}

/// One client: requests one after another (some of them sent twice, as a client that lost
/// its answer would), until `stop`.
async fn client(
    k: usize,
    bases: Bases,
    stations: Arc<Vec<String>>,
    answers: Arc<Mutex<Answers>>,
    stop: Arc<AtomicBool>,
) {
    let http = reqwest::Client::builder()
        .timeout(Duration::from_secs(10))
        .build()
        .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(SEED ^ k as u64);
    for n in 0.. {
        if stop.load(Ordering::Relaxed) {
            return;
        }
        let o = rng.random_range(0..stations.len());
        let mut d = rng.random_range(0..stations.len() - 1);
        if d >= o {
            d += 1;
        }
        // Departures 5 minutes to 3 hours ahead: nothing takes off during the test.
        let body = json!({
            "id": format!("k{k}-n{n}"),
            "origin": stations[o],
            "destination": stations[d],
            "departure": rfc3339_in(rng.random_range(300_000..10_800_000)),
        });
        if answer(&http, &bases, &body, &mut rng, &answers, &stop)
            .await
            .is_some()
            && rng.random_range(0..8) == 0
        {
            answer(&http, &bases, &body, &mut rng, &answers, &stop).await;
        }
    }
}

/// `/healthz` of `base`, if it answers.
async fn health(http: &reqwest::Client, base: &str) -> Option<Value> {
    let r = http.get(format!("{base}/healthz")).send().await.ok()?;
    r.json().await.ok()
}

/// The slot of the instance that leads, once one does (within 30 s).
async fn leader(http: &reqwest::Client, bases: &Bases) -> usize {
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let alive: Vec<(usize, String)> = bases
            .lock()
            .unwrap()
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.clone().map(|b| (i, b)))
            .collect();
        for (i, base) in alive {
            if health(http, &base)
                .await
                .is_some_and(|h| h["role"] == "leader")
            {
                return i;
            }
        }
        assert!(Instant::now() < deadline, "no leader for 30 s");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_leader_killed_again_and_again_loses_and_changes_nothing() {
    let Some(pg) = tokio::task::spawn_blocking(Throwaway::start).await.unwrap() else {
        return;
    };
    println!("seed {SEED:#x}");
    let url = pg.url();
    let args = ["--store", url.as_str()];
    let stations = stations();
    // The first to start leads; the others stand by.
    let mut servers: Vec<Option<Server>> = Vec::new();
    for _ in 0..INSTANCES {
        servers.push(Some(start_with(&args)));
    }
    let bases: Bases = Arc::new(Mutex::new(
        servers
            .iter()
            .map(|s| s.as_ref().map(|s| s.base.clone()))
            .collect(),
    ));
    let http = reqwest::Client::new();
    assert_eq!(leader(&http, &bases).await, 0, "the first to start leads");
    let answers = Arc::new(Mutex::new(Answers::default()));
    let stop = Arc::new(AtomicBool::new(false));
    let clients: Vec<_> = (0..CLIENTS)
        .map(|k| {
            tokio::spawn(client(
                k,
                Arc::clone(&bases),
                Arc::clone(&stations),
                Arc::clone(&answers),
                Arc::clone(&stop),
            ))
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let mut takeovers = Vec::new();
    for kill in 0..KILLS {
        tokio::time::sleep(Duration::from_millis(rng.random_range(300..900))).await;
        let slot = leader(&http, &bases).await;
        bases.lock().unwrap()[slot] = None;
        let killed = Instant::now();
        servers[slot].take().unwrap().kill();
        let next = leader(&http, &bases).await;
        takeovers.push(killed.elapsed());
        let served = answers.lock().unwrap().first.len();
        println!(
            "kill {kill}: instance {slot} killed, instance {next} leads after {:.0} ms; {served} \
             ids answered so far",
            killed.elapsed().as_secs_f64() * 1e3
        );
        // The killed instance comes back, as a standby.
        let back = start_with(&args);
        bases.lock().unwrap()[slot] = Some(back.base.clone());
        servers[slot] = Some(back);
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    stop.store(true, Ordering::Relaxed);
    for c in clients {
        c.await.expect("a client");
    }
    check_at_the_end(&http, &bases, &answers, &takeovers).await;
    for s in servers.into_iter().flatten() {
        s.kill();
    }
    tokio::task::spawn_blocking(move || drop(pg)).await.unwrap();
}

/// Every acknowledged flight reads, at every instance, as first answered; the planned flights
/// pass the verifier.
async fn check_at_the_end(
    http: &reqwest::Client,
    bases: &Bases,
    answers: &Mutex<Answers>,
    takeovers: &[Duration],
) {
    let (first, repeated, unanswered) = {
        let a = answers.lock().unwrap();
        (a.first.clone(), a.repeated, a.unanswered)
    };
    let alive: Vec<String> = bases.lock().unwrap().iter().flatten().cloned().collect();
    let slot = leader(http, bases).await;
    let lead = bases.lock().unwrap()[slot]
        .clone()
        .expect("the leader runs");
    let stored = all_flights(http, &lead).await;
    for (id, want) in &first {
        let got = stored
            .get(id)
            .unwrap_or_else(|| panic!("acknowledged flight {id} lost"));
        assert_eq!(got, want, "acknowledged flight {id} changed");
    }
    for base in &alive {
        for id in first.keys().step_by(97) {
            let (code, got) = get(http, format!("{base}/v1/flights/{id}")).await;
            assert_eq!((code, &got), (200, &first[id]), "{id} at {base}");
        }
    }
    let planned = verify_all(&lead).await;
    println!(
        "{} ids answered ({repeated} answers repeated, {unanswered} sends unanswered) over \
         {KILLS} kills of the leader; {planned} planned flights verified; take-overs {takeovers:?}",
        first.len(),
    );
    assert!(
        first.len() > 500 && planned > 100,
        "too little load: {} {planned}",
        first.len()
    );
}
