//! Several services on one PostgreSQL store (docs/service.md#several-services-on-one-postgresql):
//! the first leads, the next stands by, following what the leader commits, sending writes on
//! to it, and taking over when it stops, with the same answers for retried ids and the
//! schedule as the leader left it. A leader whose lead was taken commits nothing more.

use std::time::Duration;

use serde_json::Value;

use crate::api::{Kind, Service, flight, ids, in_secs};
use crate::throwaway_pg::{Throwaway, execute};

/// `/healthz` of `s`, once `ready` holds of it (within 10 s).
async fn health_once(s: &Service, ready: impl Fn(&Value) -> bool) -> Value {
    for _ in 0..200 {
        let (code, h) = s.get("/healthz", None).await;
        if code == 200 && ready(&h) {
            return h;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    panic!(
        "{} never got there: {}",
        s.base,
        s.get("/healthz", None).await.1
    );
}

/// The flight as read, without what reads add over time (nothing here: flights are read
/// whole), for comparing answers across services.
async fn flight_at(s: &Service, id: &str) -> (u16, Value) {
    s.get(&format!("/v1/flights/{id}"), None).await
}

#[tokio::test]
#[allow(clippy::many_single_char_names)] // a leads, b stands by, k1..k5 are flights.
async fn a_standby_follows_forwards_and_takes_over_with_the_same_answers() {
    let Some(pg) = Throwaway::shared() else {
        return;
    };
    let store = Kind::Postgres(pg).store("standby");
    let a = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .unwrap();
    let b = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .unwrap();
    let h = health_once(&a, |_| true).await;
    assert_eq!(
        (h["role"].as_str(), h["takeovers"].as_u64()),
        (Some("leader"), Some(0)),
        "{h}"
    );
    let h = health_once(&b, |_| true).await;
    assert_eq!(h["role"], "standby", "{h}");
    assert_eq!(h["leader"].as_str(), Some(a.base.as_str()), "{h}");

    // A write through the standby is the leader's.
    let t = in_secs(600);
    let (code, k1) = b.post(None, &flight("k1", "A", "C", &t)).await;
    assert_eq!(code, 201, "{k1}");
    assert_eq!(flight_at(&a, "k1").await, (200, k1.clone()));
    // The standby follows: it reads the flight as the leader answered it, and its schedule
    // holds it (the same slot under a new id is refused, decided by the leader).
    health_once(&b, |h| h["behind"]["events"] == 0 && h["flights_held"] == 1).await;
    assert_eq!(flight_at(&b, "k1").await, (200, k1.clone()));
    let (code, k2) = a.post(None, &flight("k2", "B", "C", &in_secs(900))).await;
    assert_eq!(code, 201, "{k2}");
    let (code, k3) = a.post(None, &flight("k3", "X", "Y", &in_secs(900))).await;
    assert_eq!(code, 201, "{k3}");
    let (code, cancelled) = b.delete("/v1/flights/k3", None).await;
    assert_eq!(code, 200, "{cancelled}");

    // The leader stops: the standby takes over, and answers every retried id as it was
    // first answered.
    let _ = a.stop().await;
    let h = health_once(&b, |h| h["role"] == "leader").await;
    assert_eq!(h["takeovers"], 1, "{h}");
    let (code, again) = b.post(None, &flight("k1", "A", "C", &t)).await;
    assert_eq!((code, &again), (201, &k1), "a retry after the take-over");
    assert_eq!(flight_at(&b, "k2").await, (200, k2));
    assert_eq!(flight_at(&b, "k3").await, (200, cancelled));
    // Its schedule is the leader's: k1's slot is taken, k3's is free again.
    let (code, v) = b.post(None, &flight("k4", "A", "C", &t)).await;
    assert_eq!(
        (code, v["reason"].as_str()),
        (200, Some("no_feasible_plan")),
        "{v}"
    );
    let (code, v) = b.post(None, &flight("k5", "X", "Y", &in_secs(900))).await;
    assert_eq!(code, 201, "{v}");
    let (_, list) = b.get("/v1/flights", None).await;
    assert_eq!(ids(&list), ["k1", "k2", "k3", "k4", "k5"], "{list}");
    let _ = b.stop().await;
}

#[tokio::test]
async fn a_leader_whose_lead_was_taken_commits_nothing_more() {
    let Some(pg) = Throwaway::shared() else {
        return;
    };
    let store = Kind::Postgres(pg).store("fenced");
    let muse_service::StoreAt::Postgres(url) = &store else {
        unreachable!()
    };
    let a = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .unwrap();
    let (code, k1) = a.post(None, &flight("k1", "A", "C", &in_secs(600))).await;
    assert_eq!(code, 201, "{k1}");
    // Another service takes the lead in the store (as a standby does once the leader's
    // session has ended; here the old leader's session lives on).
    execute(
        url,
        "UPDATE lease SET term = term + 1, holder = 'elsewhere'",
    );
    let (code, e) = a.post(None, &flight("k2", "B", "C", &in_secs(600))).await;
    let message = e["error"]["message"].as_str().unwrap_or_default();
    assert_eq!(code, 500, "{e}");
    assert!(
        message.contains("another service took the lead"),
        "{message}"
    );
    drop(a);
    // Nothing of it was stored: a new leader knows k1 and not k2.
    let b = Service::open(store, Vec::new(), |_| {}).await.unwrap();
    assert_eq!(flight_at(&b, "k1").await, (200, k1));
    assert_eq!(flight_at(&b, "k2").await.0, 404);
}
