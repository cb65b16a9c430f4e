//! `muse load` against a real service: the embedded Singapore default served in-process on
//! an ephemeral loopback port, a closed-loop, an open-loop and a paced run, each verified
//! together with everything planned before it.

use std::path::PathBuf;
use std::time::Duration;

use muse_load::{Event, LoadConfig, LoadError, Mode, OdChoice, Stop};
use muse_model::{FlightParams, Millis};
use muse_service::{Clock, Options, ServiceWorld, start};

/// A fresh data folder for this test process.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("muse-load-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Starts the service on the embedded `singapore-77` (with the CBD zone); returns its URL.
async fn serve(data: PathBuf) -> String {
    let scenario = muse_scenario::by_name("singapore-77").unwrap();
    let world = ServiceWorld::new(
        "embedded singapore-77".into(),
        scenario.airspace.clone(),
        scenario.zones.clone(),
        FlightParams::default(),
        scenario.offset,
        Millis::from_secs(30 * 86_400),
        Clock::system().now(),
    )
    .unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let running = start(world, Options::new(data), listener).await.unwrap();
    let url = format!("http://{}", running.addr);
    tokio::spawn(running.serve());
    url
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn closed_open_and_paced_runs_add_up_and_verify() {
    let data = temp_dir("runs");
    let url = serve(data.clone()).await;

    // Closed loop: 300 requests from 8 clients, pairs within range so that many are planned.
    let mut closed = LoadConfig::new(url.clone());
    closed.mode = Mode::Closed { clients: 8 };
    closed.stop = Stop::Count(300);
    closed.od = OdChoice::InRange;
    closed.lead = (Millis::from_mins(1), Millis::from_mins(120));
    closed.id_prefix = Some("closed".into());
    let mut events = Vec::new();
    let r = muse_load::run(&closed, |e| events.push(*e)).await.unwrap();
    let c = &r.counts;
    assert_eq!(c.sent, 300);
    assert_eq!(c.answered, 300);
    assert_eq!(c.errors, 0, "{:?}", c.errors_by_kind);
    assert_eq!(c.planned + c.rejected, 300);
    assert_eq!(c.rejected_by_reason.values().sum::<u64>(), c.rejected);
    assert!(c.planned > 100, "in-range demand is mostly planned: {c:?}");
    assert_eq!(c.http_status.get("201"), Some(&c.planned));
    assert_eq!(r.latency_ms.count, 300);
    assert!(
        r.latency_ms.p50_ms <= r.latency_ms.p99_ms && r.latency_ms.p99_ms <= r.latency_ms.max_ms
    );
    assert!(r.open_loop.is_none());
    assert_eq!(r.server.flights_before, 0);
    assert_eq!(r.server.stations, 77);
    let v = r.verification.as_ref().unwrap();
    assert!(v.ok(), "{:?}", v.first_violations);
    assert_eq!(
        (v.flights as u64, v.this_run as u64),
        (c.planned, c.planned)
    );
    // The service refreshes its gauges at most every 100 ms, after planning: a short run may
    // see them unchanged, but they are there.
    assert!(r.gauges.extents.contains_key("muse_schedule_reservations"));
    assert!(
        r.gauges.series.len() >= 2,
        "one sample before the load, one after"
    );
    assert!(matches!(events.last(), Some(Event::Verifying { .. })));
    assert!(
        events
            .iter()
            .any(|e| matches!(e, Event::Fetching { flights } if *flights as u64 == c.planned))
    );
    let json: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    assert_eq!(json["counts"]["sent"], 300);
    assert_eq!(json["verification"]["violations"], 0);
    let text = r.text();
    assert!(text.contains(": OK\n"), "{text}");

    // Open loop: 200 requests/s for 1 s, the paper's uniform pairs, verified together with
    // the closed loop's flights.
    let mut open = LoadConfig::new(url.clone());
    open.mode = Mode::Open {
        rate: 200.0,
        max_in_flight: 1_000,
    };
    open.stop = Stop::Duration(Duration::from_secs(1));
    open.id_prefix = Some("open".into());
    let r2 = muse_load::run(&open, |_| {}).await.unwrap();
    let c2 = &r2.counts;
    assert_eq!(c2.sent, 200);
    assert_eq!(c2.errors, 0, "{:?}", c2.errors_by_kind);
    assert_eq!(c2.planned + c2.rejected, 200);
    assert!(c2.rejected_by_reason.contains_key("out_of_range"));
    assert!(
        r2.wall_s >= 0.99,
        "the schedule spreads 200 requests over a second"
    );
    let ol = r2.open_loop.unwrap();
    assert_eq!(ol.send_lag_ms.count, 200);
    assert_eq!(ol.waited_for_slot, 0);
    assert_eq!(r2.server.flights_before, 300);
    let reservations = r2.gauges.extents["muse_schedule_reservations"];
    assert!(reservations.max > 0.0, "{reservations:?}");
    let v2 = r2.verification.as_ref().unwrap();
    assert!(v2.ok(), "{:?}", v2.first_violations);
    assert_eq!(v2.flights as u64, c.planned + c2.planned);
    assert_eq!(v2.this_run as u64, c2.planned);

    // Paced, verified together with both runs before it.
    paced_run(&url, c.sent + c2.sent, c.planned + c2.planned).await;

    // Reusing the closed run's ids with other departures: every request is a 409 conflict,
    // counted as an error of that kind.
    let mut again = closed.clone();
    again.stop = Stop::Count(10);
    again.mode = Mode::Closed { clients: 2 };
    again.verify = false;
    let r3 = muse_load::run(&again, |_| {}).await.unwrap();
    assert_eq!(r3.counts.errors, 10);
    assert_eq!(r3.counts.errors_by_kind.get("409 conflict"), Some(&10));
    assert_eq!(r3.counts.answered, 10);
    assert_eq!(r3.latency_ms.count, 0);
    assert!(r3.verification.is_none() && r3.verified_ok());

    let _ = std::fs::remove_dir_all(&data);
}

/// A paced run against the service at `url`, which holds `held_before` flights of which
/// `planned_before` planned: the open-loop schedule of 500 requests/s served by 4 clients,
/// 300 requests, pairs within range, verified together with everything before it. (Another
/// seed than the closed run's: the same pairs and leads a few seconds later would mostly find
/// their slots taken.)
async fn paced_run(url: &str, held_before: u64, planned_before: u64) {
    let mut paced = LoadConfig::new(url);
    paced.seed = 2;
    paced.mode = Mode::Paced {
        rate: 500.0,
        clients: 4,
    };
    paced.stop = Stop::Count(300);
    paced.od = OdChoice::InRange;
    paced.lead = (Millis::from_mins(1), Millis::from_mins(120));
    paced.id_prefix = Some("paced".into());
    let r4 = muse_load::run(&paced, |_| {}).await.unwrap();
    let c4 = &r4.counts;
    assert_eq!(c4.sent, 300);
    assert_eq!(c4.answered, 300);
    assert_eq!(c4.errors, 0, "{:?}", c4.errors_by_kind);
    assert_eq!(c4.planned + c4.rejected, 300);
    assert_eq!(c4.unaccounted(), 0);
    assert_eq!(c4.rejected_by_reason.values().sum::<u64>(), c4.rejected);
    assert_eq!(c4.http_status.get("201"), Some(&c4.planned));
    assert!(
        c4.planned > 100,
        "in-range demand is mostly planned: {c4:?}"
    );
    assert_eq!(r4.latency_ms.count, 300);
    assert!(
        r4.wall_s >= 0.598,
        "the last of 300 is due 299/500 s after the start: {}",
        r4.wall_s
    );
    let ol4 = r4.open_loop.unwrap();
    assert_eq!(ol4.send_lag_ms.count, 300);
    assert_eq!(ol4.from_send_ms.count, 300);
    assert!((ol4.late_threshold_ms - 1.0).abs() < 1e-12);
    assert!(ol4.late <= 300 && ol4.waited_for_slot <= 300);
    assert!(ol4.from_send_ms.max_ms <= r4.latency_ms.max_ms);
    assert_eq!(r4.server.flights_before, held_before);
    let v4 = r4.verification.as_ref().unwrap();
    assert!(v4.ok(), "{:?}", v4.first_violations);
    assert_eq!(v4.flights as u64, planned_before + c4.planned);
    assert_eq!(v4.this_run as u64, c4.planned);
    let json: serde_json::Value = serde_json::from_str(&r4.to_json()).unwrap();
    assert_eq!(json["config"]["mode"], "paced");
    assert_eq!(json["config"]["clients"], 4);
    assert_eq!(json["config"]["rate"], 500.0);
    let text = r4.text();
    assert!(
        text.contains("paced at 500 requests/s (open-loop schedule) by 4 clients, 300 requests"),
        "{text}"
    );
    assert!(text.contains(": OK\n"), "{text}");
}

#[tokio::test]
async fn an_unreachable_service_is_a_clear_error() {
    // A port that was free a moment ago and nobody listens on now.
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    drop(listener);
    let mut config = LoadConfig::new(format!("http://{addr}"));
    config.timeout = Duration::from_secs(2);
    let err = muse_load::run(&config, |_| {}).await.unwrap_err();
    assert!(matches!(err, LoadError::Unreachable { .. }), "{err:?}");
    let text = err.to_string();
    assert!(
        text.starts_with(&format!("cannot reach the MUSE service at http://{addr}")),
        "{text}"
    );
    assert!(text.contains("muse serve"), "{text}");
}
