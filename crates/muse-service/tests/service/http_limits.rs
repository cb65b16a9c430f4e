//! The HTTP server's limits, against a real service on an ephemeral loopback port: timeouts
//! for slow headers, slow bodies and idle connections, the connection cap, declared bodies
//! over the limit, the media type of writes, and the `Host` check of open mode.
//!
//! Requests are written by hand over TCP (as a misbehaving client would), so that what the
//! server does with partial requests is seen byte for byte. Every wait is bounded; no test
//! draws random numbers.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use muse_model::{Airspace, FlightParams, Millis, UtcOffset};
use muse_service::{Clock, Limits, Options, ServiceWorld, Tokens, start};
use serde_json::{Value, json};
use tokio::io::{AsyncReadExt as _, AsyncWriteExt as _};
use tokio::net::TcpStream;

/// Two stations 1 km apart.
fn airspace() -> Airspace {
    Airspace::line(&[1_000.0])
}

/// A running service.
struct Service {
    addr: SocketAddr,
    data: PathBuf,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    server: Option<tokio::task::JoinHandle<Result<(), muse_service::ServeError>>>,
}

impl Service {
    async fn start(name: &str, configure: impl FnOnce(&mut Options)) -> Service {
        let data = std::env::temp_dir().join(format!("muse-http-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&data);
        let mut options = Options::new(data.clone());
        configure(&mut options);
        let world = ServiceWorld::new(
            "two stations".into(),
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
        let addr = running.addr;
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let server = tokio::spawn(running.serve_until(async {
            let _ = stopped.await;
        }));
        Service {
            addr,
            data,
            stop: Some(stop),
            server: Some(server),
        }
    }

    /// Stops the service and waits (at most `within`) for it to finish.
    async fn stop_within(mut self, within: Duration) -> Duration {
        let began = Instant::now();
        let _ = self.stop.take().unwrap().send(());
        tokio::time::timeout(within, self.server.take().unwrap())
            .await
            .expect("the service stops in time")
            .unwrap()
            .unwrap();
        began.elapsed()
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        let _ = std::fs::remove_dir_all(&self.data);
    }
}

/// Short timeouts, so that the tests wait seconds, not minutes.
fn short(header: u64, body: u64, idle: u64) -> Limits {
    Limits {
        header_timeout: Duration::from_secs(header),
        body_timeout: Duration::from_secs(body),
        idle_timeout: Duration::from_secs(idle),
        ..Limits::default()
    }
}

/// What a raw exchange got: everything read until the server closed the connection (or
/// `wait` passed), whether it closed it, and when the first byte or the close came.
struct Got {
    text: String,
    closed: bool,
    after: Duration,
}

impl Got {
    fn status(&self) -> u16 {
        self.text
            .split(' ')
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap_or(0)
    }

    fn body(&self) -> Value {
        let body = self.text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
        serde_json::from_str(body).unwrap_or(Value::Null)
    }

    fn header(&self, name: &str) -> Option<String> {
        let head = self.text.split_once("\r\n\r\n").map_or("", |(h, _)| h);
        head.lines().skip(1).find_map(|line| {
            let (n, v) = line.split_once(':')?;
            n.eq_ignore_ascii_case(name).then(|| v.trim().to_owned())
        })
    }
}

/// Reads from `stream` until the server closes it or `wait` passes.
async fn read_all(stream: &mut TcpStream, wait: Duration) -> Got {
    let began = Instant::now();
    let mut bytes = Vec::new();
    let mut buf = [0u8; 4096];
    let mut closed = false;
    let deadline = tokio::time::Instant::now() + wait;
    loop {
        match tokio::time::timeout_at(deadline, stream.read(&mut buf)).await {
            Ok(Ok(0) | Err(_)) => {
                closed = true;
                break;
            }
            Ok(Ok(n)) => bytes.extend_from_slice(&buf[..n]),
            Err(_) => break,
        }
    }
    Got {
        text: String::from_utf8_lossy(&bytes).into_owned(),
        closed,
        after: began.elapsed(),
    }
}

/// Sends `request` on a new connection and reads until the server closes it or `wait`
/// passes.
async fn exchange(addr: SocketAddr, request: &str, wait: Duration) -> Got {
    let mut stream = TcpStream::connect(addr).await.unwrap();
    stream.write_all(request.as_bytes()).await.unwrap();
    read_all(&mut stream, wait).await
}

/// A complete request that closes its connection after the answer.
fn request(method: &str, path: &str, host: &str, headers: &str, body: &str) -> String {
    format!(
        "{method} {path} HTTP/1.1\r\nHost: {host}\r\n{headers}Content-Length: {}\r\n\
         Connection: close\r\n\r\n{body}",
        body.len()
    )
}

fn departure_in(secs: i64) -> String {
    (Clock::system().now() + Millis::from_secs(secs)).to_rfc3339(UtcOffset::SINGAPORE)
}

fn new_flight(id: &str) -> String {
    json!({"id": id, "origin": "A", "destination": "B", "departure": departure_in(600)}).to_string()
}

/// How many flights the service holds (open mode).
async fn flights(addr: SocketAddr) -> usize {
    let got = exchange(
        addr,
        &request("GET", "/v1/flights", "127.0.0.1", "", ""),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 200, "{}", got.text);
    got.body()["flights"].as_array().unwrap().len()
}

/// Raises this process's open-file limit (soft to hard) and says how many idle sockets the
/// test can hold: each costs two descriptors here (client and server side).
fn idle_sockets_affordable(wanted: usize) -> usize {
    let soft = rlimit::increase_nofile_limit(u64::MAX).expect("the open-file limit is readable");
    let room = usize::try_from(soft.saturating_sub(256) / 2).unwrap_or(usize::MAX);
    if room < wanted {
        println!("open-file limit {soft}: holding {room} idle sockets instead of {wanted}");
    }
    wanted.min(room)
}

/// 2,000 idle sockets and a few slow-header clients: another client is still answered at
/// once, the slow clients are cut at the header timeout, the idle sockets at the idle
/// timeout (and not before), and the service still stops promptly.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_and_slow_clients_do_not_starve_the_others() {
    const HEADER: Duration = Duration::from_secs(1);
    const IDLE: Duration = Duration::from_secs(3);
    let idle_count = idle_sockets_affordable(2_000);
    let s = Service::start("idle", |o| o.http = short(1, 5, 3)).await;
    let addr = s.addr;

    // The idle sockets: each task reports how long after its connect the server closed it.
    let mut idle = Vec::with_capacity(idle_count);
    for _ in 0..idle_count {
        let mut stream = TcpStream::connect(addr).await.unwrap();
        let opened = Instant::now();
        idle.push(tokio::spawn(async move {
            let mut buf = [0u8; 16];
            let r = tokio::time::timeout(IDLE + Duration::from_secs(20), stream.read(&mut buf))
                .await
                .expect("the server closes an idle socket");
            assert!(matches!(r, Ok(0) | Err(_)), "an idle socket got {r:?}");
            opened.elapsed()
        }));
    }

    // Slow-header clients: a byte every 200 ms, never the end of the headers.
    let mut slow = Vec::new();
    for k in 0..8 {
        slow.push(tokio::spawn(async move {
            let mut stream = TcpStream::connect(addr).await.unwrap();
            let partial = format!("GET /healthz?slow={k} HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ");
            let began = Instant::now();
            for byte in partial.bytes().chain(std::iter::repeat(b'z')).take(200) {
                if stream.write_all(&[byte]).await.is_err() {
                    break;
                }
                let mut buf = [0u8; 64];
                match tokio::time::timeout(Duration::from_millis(200), stream.read(&mut buf)).await
                {
                    Ok(Ok(0) | Err(_)) => return began.elapsed(),
                    Ok(Ok(n)) => panic!("a slow client got an answer: {:?}", &buf[..n]),
                    Err(_) => {}
                }
            }
            panic!("a slow-header client was not disconnected within 40 s");
        }));
    }

    // Another client is answered promptly meanwhile.
    for _ in 0..3 {
        let got = exchange(
            addr,
            &request("GET", "/healthz", "127.0.0.1", "", ""),
            Duration::from_secs(5),
        )
        .await;
        assert_eq!(got.status(), 200, "{}", got.text);
        println!(
            "answered in {:?} beside {idle_count} idle sockets",
            got.after
        );
        assert!(
            got.after < Duration::from_secs(2),
            "answered in {:?}",
            got.after
        );
    }

    for task in slow {
        let cut = task.await.unwrap();
        println!("slow-header client cut after {cut:?}");
        assert!(
            cut >= HEADER && cut < HEADER + Duration::from_secs(3),
            "slow-header client cut after {cut:?} (header timeout {HEADER:?})"
        );
    }
    let mut cut = Vec::with_capacity(idle.len());
    for task in idle {
        cut.push(task.await.unwrap());
    }
    let (first, last) = (
        cut.iter().min().copied().unwrap_or_default(),
        cut.iter().max().copied().unwrap_or_default(),
    );
    println!("{} idle sockets cut after {first:?} to {last:?}", cut.len());
    // The server's clock for a socket starts when it accepts it, a moment after the connect.
    assert!(
        first + Duration::from_millis(250) >= IDLE,
        "an idle socket was cut after {first:?}"
    );
    assert!(last < IDLE + Duration::from_secs(10), "{last:?}");

    // A client still gets in afterwards, and the service stops promptly.
    let got = exchange(
        addr,
        &request("GET", "/healthz", "localhost", "", ""),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 200);
    let stop = s.stop_within(Duration::from_secs(10)).await;
    println!("stopped in {stop:?}");
}

/// A graceful stop does not wait for idle or slow clients.
#[tokio::test]
async fn a_stop_does_not_wait_for_idle_or_slow_clients() {
    let s = Service::start("stop", |o| o.http = short(30, 30, 60)).await;
    let mut idle = TcpStream::connect(s.addr).await.unwrap();
    let mut slow = TcpStream::connect(s.addr).await.unwrap();
    slow.write_all(b"GET /healthz HTTP/1.1\r\nHo")
        .await
        .unwrap();
    // A kept-alive connection after one answer.
    let mut kept = TcpStream::connect(s.addr).await.unwrap();
    kept.write_all(b"GET /healthz HTTP/1.1\r\nHost: localhost\r\n\r\n")
        .await
        .unwrap();
    let mut buf = [0u8; 2048];
    assert!(kept.read(&mut buf).await.unwrap() > 0);
    tokio::time::sleep(Duration::from_millis(100)).await;
    let stopped = s.stop_within(Duration::from_secs(5)).await;
    println!("stopped in {stopped:?}");
    for stream in [&mut idle, &mut slow, &mut kept] {
        let got = read_all(stream, Duration::from_secs(5)).await;
        assert!(got.closed, "{}", got.text);
    }
}

/// Above the cap a connection is answered `503` at once and closed; below it again, served.
#[tokio::test]
async fn connections_above_the_cap_are_answered_503() {
    let s = Service::start("cap", |o| {
        o.http = Limits {
            max_connections: 3,
            ..short(10, 10, 30)
        };
    })
    .await;
    let mut held = Vec::new();
    for _ in 0..3 {
        held.push(TcpStream::connect(s.addr).await.unwrap());
    }
    // The held connections are accepted before the next one (the backlog is in order).
    let got = exchange(
        s.addr,
        &request("GET", "/healthz", "127.0.0.1", "", ""),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 503, "{}", got.text);
    assert_eq!(got.header("retry-after").as_deref(), Some("1"));
    assert_eq!(got.header("connection").as_deref(), Some("close"));
    assert_eq!(got.body()["error"]["code"], "too_many_connections");
    assert!(
        got.closed && got.after < Duration::from_secs(2),
        "{:?}",
        got.after
    );
    // One held connection goes: a new one is served again.
    drop(held.pop());
    let began = Instant::now();
    loop {
        let got = exchange(
            s.addr,
            &request("GET", "/healthz", "127.0.0.1", "", ""),
            Duration::from_secs(5),
        )
        .await;
        if got.status() == 200 {
            break;
        }
        assert_eq!(got.status(), 503, "{}", got.text);
        assert!(
            began.elapsed() < Duration::from_secs(5),
            "a freed slot is not reused"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// A declared `Content-Length` over the limit is refused at once, on a route that reads a
/// body and on one that does not, and the connection is closed.
#[tokio::test]
async fn a_declared_body_over_the_limit_is_refused_at_once() {
    let s = Service::start("length", |o| o.http = short(10, 30, 60)).await;
    let json = "Content-Type: application/json\r\n";
    for (method, path, headers) in [
        ("POST", "/v1/flights", json),
        ("GET", "/healthz", ""),
        ("GET", "/v1/flights", ""),
        ("POST", "/v1/zones", json),
    ] {
        let got = exchange(
            s.addr,
            &format!(
                "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\n{headers}\
                 Content-Length: 1000000000000\r\n\r\n{{\"id\""
            ),
            Duration::from_secs(5),
        )
        .await;
        println!("{method} {path}: {} after {:?}", got.status(), got.after);
        assert_eq!(got.status(), 413, "{method} {path}: {}", got.text);
        assert_eq!(got.body()["error"]["code"], "body_too_large");
        assert_eq!(got.body()["error"]["field"], "Content-Length");
        assert!(
            got.closed && got.after < Duration::from_secs(2),
            "{method} {path}: closed {} after {:?}",
            got.closed,
            got.after
        );
    }
    // Just over the flights limit (16 KiB by default) is refused too; a zone may be larger.
    let got = exchange(
        s.addr,
        "POST /v1/flights HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n\
         Content-Length: 16385\r\n\r\n",
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 413);
    assert_eq!(flights(s.addr).await, 0);
}

/// A body that does not arrive within the body timeout is answered `408` and the connection
/// closed.
#[tokio::test]
async fn a_slow_body_is_answered_408() {
    let s = Service::start("body", |o| o.http = short(10, 1, 60)).await;
    let mut stream = TcpStream::connect(s.addr).await.unwrap();
    stream
        .write_all(
            b"POST /v1/flights HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n\
              Content-Length: 200\r\n\r\n{\"id\": ",
        )
        .await
        .unwrap();
    let got = read_all(&mut stream, Duration::from_secs(10)).await;
    println!("408 after {:?}", got.after);
    assert_eq!(got.status(), 408, "{}", got.text);
    assert_eq!(got.body()["error"]["code"], "body_timeout");
    assert_eq!(got.header("connection").as_deref(), Some("close"));
    assert!(got.closed);
    assert!(got.after >= Duration::from_millis(900) && got.after < Duration::from_secs(4));
    assert_eq!(flights(s.addr).await, 0);
}

/// Writes need a JSON media type: a form or `text/plain` POST (what a web page may send to
/// any site without asking) is refused `415` and books nothing.
#[tokio::test]
async fn writes_need_a_json_media_type() {
    let s = Service::start("media", |o| o.http = short(10, 30, 60)).await;
    let body = new_flight("m1");
    for headers in [
        "Content-Type: text/plain\r\n",
        "Content-Type: application/x-www-form-urlencoded\r\n",
        "Content-Type: multipart/form-data; boundary=x\r\n",
        "",
    ] {
        let got = exchange(
            s.addr,
            &request("POST", "/v1/flights", "127.0.0.1", headers, &body),
            Duration::from_secs(5),
        )
        .await;
        assert_eq!(got.status(), 415, "{headers:?}: {}", got.text);
        let e = &got.body()["error"];
        assert_eq!(e["code"], "unsupported_media_type");
        assert_eq!(e["field"], "Content-Type");
        assert_eq!(e["status"], 415);
    }
    assert_eq!(flights(s.addr).await, 0, "nothing booked");
    let got = exchange(
        s.addr,
        &request(
            "POST",
            "/v1/flights",
            "127.0.0.1",
            "Content-Type: Application/JSON; charset=utf-8\r\n",
            &body,
        ),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 201, "{}", got.text);
    // Zones: JSON or GeoJSON.
    let zone = |id: &str| {
        json!({
            "type": "Feature",
            "properties": {
                "identifier": id,
                "name": [{"text": "test zone", "lang": "en"}],
                "type": "PROHIBITED",
                "nodes": ["B"],
                "limitedApplicability": [{
                    "startDateTime": departure_in(7_200),
                    "endDateTime": departure_in(10_800),
                }],
            },
            "geometry": null,
        })
        .to_string()
    };
    let post_zone = |headers: &'static str, body: String| {
        let addr = s.addr;
        async move {
            exchange(
                addr,
                &request("POST", "/v1/zones", "127.0.0.1", headers, &body),
                Duration::from_secs(5),
            )
            .await
        }
    };
    let got = post_zone("Content-Type: text/plain\r\n", zone("Z0")).await;
    assert_eq!(got.status(), 415, "{}", got.text);
    let got = post_zone("Content-Type: application/geo+json\r\n", zone("Z1")).await;
    assert_eq!(got.status(), 201, "{}", got.text);
    let got = post_zone("Content-Type: application/json\r\n", zone("Z2")).await;
    assert_eq!(got.status(), 201, "{}", got.text);
    let got = exchange(
        s.addr,
        &request("GET", "/v1/zones", "127.0.0.1", "", ""),
        Duration::from_secs(5),
    )
    .await;
    let zones = got.body();
    let ids: Vec<&str> = zones["features"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|f| f["properties"]["identifier"].as_str())
        .collect();
    assert!(!ids.contains(&"Z0") && ids.contains(&"Z1"), "{ids:?}");
}

/// Open mode answers only requests addressed to a loopback name; with tokens, any name.
#[tokio::test]
async fn open_mode_answers_only_loopback_hosts() {
    let s = Service::start("host", |o| o.http = short(10, 30, 60)).await;
    let port = s.addr.port();
    for host in [
        "evil.example".to_owned(),
        format!("evil.example:{port}"),
        format!("192.168.1.20:{port}"),
        "localhost.evil.example".to_owned(),
    ] {
        let got = exchange(
            s.addr,
            &request("GET", "/v1/flights", &host, "", ""),
            Duration::from_secs(5),
        )
        .await;
        assert_eq!(got.status(), 403, "{host}: {}", got.text);
        let e = &got.body()["error"];
        assert_eq!(e["code"], "host_not_allowed");
        assert_eq!(e["field"], "Host");
        let message = e["message"].as_str().unwrap();
        assert!(
            message.contains("DNS rebinding") && message.contains("--tokens"),
            "{message}"
        );
    }
    // A web page's cross-site POST, through a name of its own: refused, nothing booked.
    let got = exchange(
        s.addr,
        &request(
            "POST",
            "/v1/flights",
            &format!("rebound.example:{port}"),
            "Content-Type: application/json\r\n",
            &new_flight("x1"),
        ),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 403, "{}", got.text);
    // No Host at all (HTTP/1.0): refused; health and metrics are not exempt.
    for path in ["/healthz", "/metrics", "/v1/flights"] {
        let got = exchange(
            s.addr,
            &format!("GET {path} HTTP/1.0\r\n\r\n"),
            Duration::from_secs(5),
        )
        .await;
        assert_eq!(got.status(), 403, "{path}: {}", got.text);
    }
    assert_eq!(flights(s.addr).await, 0);
    for host in [
        "localhost".to_owned(),
        format!("localhost:{port}"),
        format!("viewer.localhost:{port}"),
        format!("127.0.0.1:{port}"),
        "127.0.0.2".to_owned(),
        format!("[::1]:{port}"),
    ] {
        let got = exchange(
            s.addr,
            &request("GET", "/healthz", &host, "", ""),
            Duration::from_secs(5),
        )
        .await;
        assert_eq!(got.status(), 200, "{host}: {}", got.text);
    }

    // With tokens, the token is the protection: any name is served.
    let tokens =
        "[[tokens]]\ntoken = \"host-test-token-0001\"\noperator = \"a\"\nrole = \"operator\"\n";
    let t = Service::start("host-tokens", |o| {
        o.http = short(10, 30, 60);
        o.tokens = Tokens::parse(tokens, "tokens.toml").unwrap();
    })
    .await;
    let got = exchange(
        t.addr,
        &request(
            "GET",
            "/v1/flights",
            "planner.example.com",
            "Authorization: Bearer host-test-token-0001\r\n",
            "",
        ),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 200, "{}", got.text);
}

/// An event stream is a request in progress: the idle timeout never cuts it, even when no
/// byte flows for longer than the timeout.
#[tokio::test]
async fn an_event_stream_outlives_the_idle_timeout() {
    let s = Service::start("events", |o| o.http = short(1, 1, 1)).await;
    let mut stream = TcpStream::connect(s.addr).await.unwrap();
    stream
        .write_all(b"GET /v1/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        .await
        .unwrap();
    let head = read_all(&mut stream, Duration::from_millis(500)).await;
    assert_eq!(head.status(), 200, "{}", head.text);
    assert!(!head.closed);
    // Three idle timeouts with no byte on the stream (keep-alive comments come every 15 s).
    let quiet = read_all(&mut stream, Duration::from_secs(3)).await;
    assert!(!quiet.closed, "the stream was cut: {}", quiet.text);
    // An event still arrives on it.
    let got = exchange(
        s.addr,
        &request(
            "POST",
            "/v1/flights",
            "127.0.0.1",
            "Content-Type: application/json\r\n",
            &new_flight("e1"),
        ),
        Duration::from_secs(5),
    )
    .await;
    assert_eq!(got.status(), 201, "{}", got.text);
    let event = read_all(&mut stream, Duration::from_millis(1_500)).await;
    assert!(event.text.contains("event: planned"), "{}", event.text);
    // A stop ends the stream.
    let _ = s.stop_within(Duration::from_secs(5)).await;
    let end = read_all(&mut stream, Duration::from_secs(5)).await;
    assert!(end.closed);
}

/// An answer the client stops reading is cut once its writes have made no progress for the
/// idle timeout; a client that keeps reading gets all of it, however long it takes.
#[tokio::test]
async fn an_answer_the_client_stops_reading_is_cut() {
    const PAGE: usize = 16 << 20;
    let s = Service::start("stall", |o| {
        o.http = short(1, 1, 1);
        o.page = Some("x".repeat(PAGE));
    })
    .await;
    let get_page = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    // A slow but steady reader gets the whole page, though it takes longer than the idle
    // timeout.
    let mut reader = TcpStream::connect(s.addr).await.unwrap();
    reader.write_all(get_page.as_bytes()).await.unwrap();
    let began = Instant::now();
    let mut total = 0;
    let mut buf = vec![0u8; 64 * 1024];
    while total < PAGE {
        let n = tokio::time::timeout(Duration::from_secs(10), reader.read(&mut buf))
            .await
            .expect("the page keeps coming")
            .unwrap();
        assert!(n > 0, "cut after {total} bytes");
        total += n;
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    println!("a steady reader took {:?} for the page", began.elapsed());
    assert!(began.elapsed() > Duration::from_millis(1_500));
    // A client with a small receive buffer that stops reading.
    let socket = tokio::net::TcpSocket::new_v4().unwrap();
    socket.set_recv_buffer_size(4096).unwrap();
    let mut stalled = socket.connect(s.addr).await.unwrap();
    stalled.write_all(get_page.as_bytes()).await.unwrap();
    tokio::time::sleep(Duration::from_secs(3)).await;
    let got = read_all(&mut stalled, Duration::from_secs(20)).await;
    println!(
        "a stalled client read {} bytes before the cut",
        got.text.len()
    );
    assert!(got.closed, "the stalled answer was not cut");
    assert!(got.text.len() < PAGE, "the whole page arrived");
}
