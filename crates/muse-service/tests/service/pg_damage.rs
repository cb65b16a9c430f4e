//! Damage in the PostgreSQL store: a row changed behind the service's back (its checksum no
//! longer matching its content) or missing is named, never served or planned on: a read that
//! meets it fails naming the row, and a start that loads or checks it is refused. And the
//! promise the store checks at its start: durable commits.

use serde_json::Value;

use crate::api::{Kind, Service, flight, in_secs};
use crate::throwaway_pg::{Throwaway, execute};

#[tokio::test]
async fn a_changed_or_missing_row_is_named_and_never_served() {
    let Some(pg) = Throwaway::shared() else {
        return;
    };
    let store = Kind::Postgres(pg).store("pg-damage");
    let muse_service::StoreAt::Postgres(url) = &store else {
        unreachable!()
    };
    let s = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .unwrap();
    // Held (planned ahead), then rejected (out of range): the rejected one is read from the
    // store, the held one from the schedule.
    let (code, held) = s.post(None, &flight("held", "A", "C", &in_secs(600))).await;
    assert_eq!(code, 201, "{held}");
    let (code, far) = s.post(None, &flight("far", "A", "F", &in_secs(600))).await;
    assert_eq!(code, 200, "{far}");
    let (code, later) = s
        .post(None, &flight("later", "B", "C", &in_secs(900)))
        .await;
    assert_eq!(code, 201, "{later}");
    assert_eq!(s.get("/v1/flights/far", None).await, (200, far.clone()));

    // One character of the rejected flight's row changed: the read fails, naming it.
    execute(
        url,
        "UPDATE flights SET operator = 'someone' WHERE id = 'far'",
    );
    let (code, e) = s.get("/v1/flights/far", None).await;
    let message = e["error"]["message"]
        .as_str()
        .unwrap_or_default()
        .to_owned();
    assert_eq!(code, 500, "{e}");
    assert!(
        message.contains("flights row seq 2 (id \"far\")") && message.contains("checksum"),
        "{message}"
    );
    // And a listing that meets it.
    let (code, e) = s.get("/v1/flights", None).await;
    assert_eq!(code, 500, "{e}");

    // Put back, the row reads as before.
    execute(url, "UPDATE flights SET operator = 'open' WHERE id = 'far'");
    assert_eq!(s.get("/v1/flights/far", None).await, (200, far));

    // A held flight's plan changed while the service is stopped: the start refuses.
    let store = s.stop().await;
    execute(
        url,
        "UPDATE flights SET landing_ms = landing_ms + 1000 WHERE id = 'held'",
    );
    let e = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .err()
        .expect("a start on a damaged store is refused")
        .to_string();
    assert!(
        e.contains("is damaged") && e.contains("flights row seq 1 (id \"held\")"),
        "{e}"
    );
    execute(
        url,
        "UPDATE flights SET landing_ms = landing_ms - 1000 WHERE id = 'held'",
    );

    // An event deleted: the start's check of what was written last finds the gap.
    execute(
        url,
        "DELETE FROM events WHERE id = (SELECT min(id) FROM events)",
    );
    let e = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .err()
        .expect("a start on a store missing a row is refused")
        .to_string();
    assert!(e.contains("is damaged") && e.contains("events row"), "{e}");
}

/// A database set to `synchronous_commit = off` would acknowledge commits a crash of the
/// server loses (those of the last few hundred milliseconds); the service turns it on for its
/// own connection, so every answer survives the server's crash.
#[tokio::test]
async fn answers_survive_a_crash_of_the_server_even_with_synchronous_commit_off() {
    // A cluster of its own: it is crashed.
    let Some(pg) = tokio::task::spawn_blocking(Throwaway::start).await.unwrap() else {
        return;
    };
    execute(
        &pg.url(),
        "ALTER DATABASE muse SET synchronous_commit = off",
    );
    let store = muse_service::StoreAt::Postgres(pg.url());
    let s = Service::open(store.clone(), Vec::new(), |_| {})
        .await
        .unwrap();
    let mut answers = Vec::new();
    for k in 0..60 {
        let (code, v): (u16, Value) = s
            .post(
                None,
                &flight(&format!("k{k}"), "A", "C", &in_secs(600 + 30 * k)),
            )
            .await;
        assert!(code == 200 || code == 201, "{v}");
        answers.push(v);
    }
    // The server crashes straight after the last answer (no checkpoint, no flush).
    let pg = tokio::task::spawn_blocking(move || {
        pg.crash_and_restart();
        pg
    })
    .await
    .unwrap();
    drop(s);
    let s = Service::open(store, Vec::new(), |_| {}).await.unwrap();
    for (k, want) in answers.iter().enumerate() {
        let got = s.get(&format!("/v1/flights/k{k}"), None).await;
        assert_eq!(got, (200, want.clone()), "k{k} after the server's crash");
    }
    drop(s);
    tokio::task::spawn_blocking(move || drop(pg)).await.unwrap();
}

#[tokio::test]
async fn a_server_that_may_lose_commits_is_refused() {
    // A cluster of its own: fsync is the whole server's setting.
    let Some(pg) = tokio::task::spawn_blocking(Throwaway::start).await.unwrap() else {
        return;
    };
    execute(&pg.url(), "ALTER SYSTEM SET fsync = off");
    execute(&pg.url(), "SELECT pg_reload_conf()");
    let e = Service::open(
        muse_service::StoreAt::Postgres(pg.url()),
        Vec::new(),
        |_| {},
    )
    .await
    .err()
    .expect("fsync off is refused")
    .to_string();
    assert!(
        e.contains("cannot keep the store's promises") && e.contains("fsync = off"),
        "{e}"
    );
    tokio::task::spawn_blocking(move || drop(pg)).await.unwrap();
}
