//! The store's promises, tried on the `muse serve` binary as an operator would meet them
//! (docs/reference.md#the-planning-service): ids are forever, across any age, SIGKILL and restart;
//! damage to the database between restarts is refused or named, never served as data.

use std::io::{BufRead as _, BufReader, Read as _};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use muse_model::{Instant, UtcOffset};
use serde_json::{Value, json};

use crate::support::scratch_dir;

/// Tokens of two operators (16 characters or more).
const TOKENS: &str = r#"
[[tokens]]
token = "alpha-token-000000"
operator = "alpha"
role = "operator"

[[tokens]]
token = "beta-token-0000000"
operator = "beta"
role = "operator"
"#;

/// A `muse serve` process, running or refused.
struct Proc {
    child: Child,
    base: Option<String>,
    stderr: std::sync::Arc<std::sync::Mutex<String>>,
}

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Proc {
    /// Starts `muse serve` on `data` with the service clock at `clock`; waits until it
    /// listens (ready) or exits.
    fn start(data: &Path, clock: Instant, extra: &[&str]) -> Proc {
        let mut child = Command::new(env!("CARGO_BIN_EXE_muse"))
            .args(["serve", "--listen", "127.0.0.1:0", "--clock"])
            .arg(clock.to_rfc3339(UtcOffset::SINGAPORE))
            .args(extra)
            .arg("--data")
            .arg(data)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("muse serve starts");
        let stderr = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
        let mut pipe = child.stderr.take().expect("piped stderr");
        let sink = std::sync::Arc::clone(&stderr);
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = pipe.read_to_string(&mut text);
            sink.lock().unwrap().push_str(&text);
        });
        let mut lines = BufReader::new(child.stdout.take().expect("piped stdout")).lines();
        let mut base = None;
        for line in lines.by_ref() {
            let line = line.expect("readable stdout");
            if let Some(addr) = line.strip_prefix("listening on ") {
                base = Some(addr.trim().to_owned());
                break;
            }
        }
        std::thread::spawn(move || for _ in lines {});
        Proc {
            child,
            base,
            stderr,
        }
    }

    fn base(&self) -> &str {
        self.base
            .as_deref()
            .unwrap_or_else(|| panic!("muse serve did not start: {}", self.stderr.lock().unwrap()))
    }

    /// Waits for a refused start to exit; returns its exit code and what it said.
    fn refused(mut self) -> (Option<i32>, String) {
        assert!(self.base.is_none(), "muse serve started on a damaged store");
        let status = self.child.wait().expect("exits");
        // Let the stderr reader finish.
        std::thread::sleep(Duration::from_millis(100));
        (status.code(), self.stderr.lock().unwrap().clone())
    }

    /// SIGKILL.
    fn kill(mut self) {
        self.child.kill().expect("SIGKILL");
        self.child.wait().expect("reaped");
    }

    /// SIGTERM, then waits for the clean stop (the store is checkpointed and closed).
    fn stop(mut self) {
        let pid = self.child.id().to_string();
        let sent = Command::new("kill")
            .args(["-TERM", &pid])
            .status()
            .expect("kill runs");
        assert!(sent.success());
        for _ in 0..200 {
            if let Some(status) = self.child.try_wait().expect("waits") {
                assert!(status.success(), "a clean stop: {status}");
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        panic!("muse serve did not stop on SIGTERM");
    }
}

async fn send(
    method: reqwest::Method,
    url: String,
    token: Option<&str>,
    body: Option<&Value>,
) -> (u16, Value) {
    let mut r = reqwest::Client::new().request(method, url);
    if let Some(t) = token {
        r = r.bearer_auth(t);
    }
    if let Some(b) = body {
        r = r
            .header("content-type", "application/json")
            .body(b.to_string());
    }
    let response = r.send().await.expect("server answers");
    let code = response.status().as_u16();
    (code, response.json().await.expect("JSON answer"))
}

async fn post(base: &str, token: Option<&str>, body: &Value) -> (u16, Value) {
    send(
        reqwest::Method::POST,
        format!("{base}/v1/flights"),
        token,
        Some(body),
    )
    .await
}

async fn get(base: &str, path: &str, token: Option<&str>) -> (u16, Value) {
    send(reqwest::Method::GET, format!("{base}{path}"), token, None).await
}

/// Two stations joined by a corridor (a short flight that is planned).
async fn neighbours(base: &str, token: Option<&str>) -> (String, String) {
    let text = reqwest::Client::new()
        .get(format!("{base}/v1/airspace"))
        .bearer_auth(token.unwrap_or("none"))
        .send()
        .await
        .unwrap()
        .text()
        .await
        .unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    let edge = v["features"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["geometry"]["type"] == "LineString")
        .unwrap();
    let p = &edge["properties"];
    (
        p["from"].as_str().unwrap().to_owned(),
        p["to"].as_str().unwrap().to_owned(),
    )
}

fn now() -> Instant {
    let ms = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_millis() as i64;
    // Whole seconds: the clock given on the command line.
    Instant(ms - ms % 1_000)
}

fn flight(id: &str, from: &str, to: &str, departure: Instant) -> Value {
    json!({"id": id, "origin": from, "destination": to,
           "departure": departure.to_rfc3339(UtcOffset::SINGAPORE)})
}

const DAY: i64 = 86_400_000;

/// An id re-sent long after its flight ended (what the earlier store forgot after its 24 h
/// retention), by the same operator and by another, then SIGKILL and restart: the service
/// starts, and the id still names the first flight, stored once.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_id_names_its_first_flight_forever() {
    let data = scratch_dir("serve-ids-forever");
    std::fs::create_dir_all(&data).unwrap();
    let tokens = data.with_extension("tokens.toml");
    std::fs::write(&tokens, TOKENS).unwrap();
    let tokens = tokens.to_str().unwrap();
    let (alpha, beta) = (Some("alpha-token-000000"), Some("beta-token-0000000"));
    let t0 = now();

    let s = Proc::start(&data, t0, &["--tokens", tokens]);
    let (from, to) = neighbours(s.base(), alpha).await;
    let first_body = flight("reused", &from, &to, t0 + muse_model::Millis(600_000));
    let (code, first) = post(s.base(), alpha, &first_body).await;
    assert_eq!(code, 201, "{first}");
    s.kill();

    // Two days later the flight has long ended and left memory.
    let later = t0 + muse_model::Millis(2 * DAY);
    let s = Proc::start(&data, later, &["--tokens", tokens]);
    let base = s.base().to_owned();
    // The same request again: the first answer, nothing new.
    let (code, again) = post(&base, alpha, &first_body).await;
    assert_eq!((code, &again), (201, &first));
    // The same id with other content, from its operator or another: a conflict.
    let other = flight("reused", &from, &to, later + muse_model::Millis(600_000));
    for token in [alpha, beta] {
        let (code, v) = post(&base, token, &other).await;
        assert_eq!(code, 409, "{v}");
        assert_eq!(v["error"]["field"], "id");
    }
    let (code, v) = post(&base, beta, &first_body).await;
    assert_eq!(code, 409, "another operator's retry is a conflict too: {v}");
    s.kill();

    let s = Proc::start(&data, later, &["--tokens", tokens]);
    let (code, stored) = get(s.base(), "/v1/flights/reused", alpha).await;
    assert_eq!((code, &stored), (200, &first));
    // Another operator cannot see it.
    assert_eq!(get(s.base(), "/v1/flights/reused", beta).await.0, 404);
    let (_, listed) = get(s.base(), "/v1/flights", alpha).await;
    assert_eq!(listed["flights"].as_array().unwrap().len(), 1, "{listed}");
    s.stop();
    // Stored once, as anyone can see in the database.
    let db = rusqlite::Connection::open(data.join("muse.db")).unwrap();
    let rows: i64 = db
        .query_row(
            "SELECT count(*) FROM flights WHERE id = 'reused'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    assert_eq!(rows, 1);
}

/// Runs `muse serve --check-store` on `data`; returns its exit code and what it printed.
fn check_store(data: &Path) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(["serve", "--check-store", "--data"])
        .arg(data)
        .output()
        .expect("muse serve --check-store runs");
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code(), text)
}

/// Copies a data folder (the store only; the lock is per process).
fn copy(from: &Path, to: &Path) {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
    }
}

/// Changes one digit of every occurrence of `needle` in `file` (a plan's text: the row, and
/// any stale copy SQLite left in free space when it split a page).
fn flip_digit_of(file: &Path, needle: &str) {
    let mut bytes = std::fs::read(file).unwrap();
    let at: Vec<usize> = bytes
        .windows(needle.len())
        .enumerate()
        .filter(|(_, w)| *w == needle.as_bytes())
        .map(|(i, _)| i)
        .collect();
    assert!(!at.is_empty(), "{needle} is not in {}", file.display());
    for start in at {
        let i = start + needle.len() - 2;
        bytes[i] = if bytes[i] == b'9' { b'8' } else { bytes[i] + 1 };
    }
    std::fs::write(file, bytes).unwrap();
}

/// The plan's first stay as the store writes it: `["S012",1767571200000,`.
fn first_stay_text(answer: &Value) -> String {
    let stay = &answer["path"][0];
    let arrive = Instant::parse_rfc3339(stay["arrive"].as_str().unwrap()).unwrap();
    format!("[\"{}\",{},", stay["node"].as_str().unwrap(), arrive.0)
}

/// Damage between restarts: a flipped byte in a flight the schedule still holds, a flipped
/// byte in a flight that has ended, the database cut short. The service refuses to start
/// naming the damage, or starts with every acknowledged flight intact and names the damaged
/// one when it is read; it never serves a changed flight.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn damage_is_refused_or_named_never_served() {
    let data = scratch_dir("serve-damage");
    let t0 = now();
    let s = Proc::start(&data, t0, &[]);
    let base = s.base().to_owned();
    let (from, to) = neighbours(&base, None).await;
    let mut acked = Vec::new();
    // One flight that will have ended at the restart, one still ahead, and some others.
    let (_, ended) = post(
        &base,
        None,
        &flight("ended", &from, &to, t0 + muse_model::Millis(300_000)),
    )
    .await;
    let (_, ahead) = post(
        &base,
        None,
        &flight("ahead", &from, &to, t0 + muse_model::Millis(2 * DAY)),
    )
    .await;
    assert_eq!(
        (ended["status"].as_str(), ahead["status"].as_str()),
        (Some("planned"), Some("planned"))
    );
    acked.push(ended.clone());
    acked.push(ahead.clone());
    for k in 0..200 {
        let dep = t0 + muse_model::Millis(600_000 + 97_000 * k);
        let (code, v) = post(&base, None, &flight(&format!("f{k}"), &to, &from, dep)).await;
        assert!(code == 200 || code == 201, "{v}");
        acked.push(v);
    }
    s.stop();
    let restart = t0 + muse_model::Millis(DAY);
    let db_of = |d: &Path| d.join("muse.db");

    // Intact: every acknowledged flight as answered.
    let s = Proc::start(&data, restart, &[]);
    for want in &acked {
        let id = want["request"].as_str().unwrap();
        let (code, got) = get(s.base(), &format!("/v1/flights/{id}"), None).await;
        assert_eq!((code, &got), (200, want), "{id}");
    }
    s.stop();

    // A flipped byte in a flight still ahead: the start reads it, and refuses.
    let d = scratch_dir("serve-damage-ahead");
    copy(&data, &d);
    flip_digit_of(&db_of(&d), &first_stay_text(&ahead));
    let (code, said) = Proc::start(&d, restart, &[]).refused();
    assert_ne!(code, Some(0));
    assert!(
        said.contains("is damaged") && said.contains("id \"ahead\"") && said.contains("checksum"),
        "{said}"
    );

    // A flipped byte in a flight that ended, among the last flights written: the start checks
    // those whole, and refuses.
    let d = scratch_dir("serve-damage-ended");
    copy(&data, &d);
    flip_digit_of(&db_of(&d), &first_stay_text(&ended));
    let (code, said) = Proc::start(&d, restart, &[]).refused();
    assert_ne!(code, Some(0));
    assert!(
        said.contains("is damaged") && said.contains("id \"ended\"") && said.contains("checksum"),
        "{said}"
    );
    // Older than what the start checks (here: nothing beyond what it loads), it is not read
    // at start (the start's time does not grow with the days served); reading it names the
    // damage, never the data.
    let s = Proc::start(&d, restart, &["--check-recent", "0"]);
    let (code, v) = get(s.base(), "/v1/flights/ended", None).await;
    assert_eq!(code, 500, "{v}");
    let message = v["error"]["message"].as_str().unwrap();
    assert!(
        message.contains("id \"ended\"") && message.contains("checksum"),
        "{message}"
    );
    // The listing that meets it fails the same way rather than leave it out.
    let (code, _) = get(s.base(), "/v1/flights?limit=500", None).await;
    assert_eq!(code, 500);
    for want in &acked[1..] {
        let id = want["request"].as_str().unwrap();
        let (code, got) = get(s.base(), &format!("/v1/flights/{id}"), None).await;
        assert_eq!((code, &got), (200, want), "{id}");
    }
    s.kill();

    // `muse serve --check-store` reads every row: it finds the damage a start does not read,
    // and passes the intact store.
    let (code, said) = check_store(&d);
    assert_eq!(code, Some(2), "{said}");
    assert!(
        said.contains("is damaged") && said.contains("id \"ended\"") && said.contains("checksum"),
        "{said}"
    );
    let (code, said) = check_store(&data);
    assert_eq!(code, Some(0), "{said}");
    assert!(said.contains("whole — 202 flights"), "{said}");

    // The database cut short after a checkpoint (the clean stop checkpointed it).
    let d = scratch_dir("serve-damage-cut");
    copy(&data, &d);
    let db = db_of(&d);
    let len = std::fs::metadata(&db).unwrap().len();
    let f = std::fs::OpenOptions::new().write(true).open(&db).unwrap();
    f.set_len(len - len / 3).unwrap();
    drop(f);
    let (code, said) = Proc::start(&d, restart, &[]).refused();
    assert_ne!(code, Some(0));
    assert!(said.contains("cut short"), "{said}");
}

/// The offset of the WAL's last frame of its current generation (the frames whose salts are
/// the header's): after a SIGKILL with nothing in flight, the commit frame of the last
/// acknowledged transaction.
fn last_frame_of(wal: &[u8]) -> usize {
    let page = u32::from_be_bytes(wal[8..12].try_into().unwrap()) as usize;
    let frame = 24 + page;
    let mut at = 32;
    while at + 2 * frame <= wal.len() && wal[at + frame + 8..at + frame + 16] == wal[16..24] {
        at += frame;
    }
    at
}

/// SIGKILL, then one byte flipped in the last acknowledged transaction of the WAL: from the
/// WAL alone a write torn by the crash, but it was answered, so the start refuses, naming
/// the WAL's frame; the same folder undamaged starts with every answer intact.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flip_in_the_last_acknowledged_transaction_is_refused() {
    let data = scratch_dir("serve-wal-flip");
    let t0 = now();
    let s = Proc::start(&data, t0, &[]);
    let base = s.base().to_owned();
    let (from, to) = neighbours(&base, None).await;
    let mut acked = Vec::new();
    for k in 0..40 {
        let dep = t0 + muse_model::Millis(600_000 + 97_000 * k);
        let (code, v) = post(&base, None, &flight(&format!("w{k}"), &from, &to, dep)).await;
        assert!(code == 200 || code == 201, "{v}");
        acked.push(v);
    }
    s.kill();
    let d = scratch_dir("serve-wal-flip-damaged");
    copy(&data, &d);
    let wal = d.join("muse.db-wal");
    let mut bytes = std::fs::read(&wal).unwrap();
    let at = last_frame_of(&bytes) + 24 + 100;
    bytes[at] ^= 0x5a;
    std::fs::write(&wal, bytes).unwrap();
    let (code, said) = Proc::start(&d, t0, &[]).refused();
    assert_ne!(code, Some(0));
    assert!(
        said.contains("is damaged")
            && said.contains("acknowledged")
            && said.contains("fails its checksum"),
        "{said}"
    );
    let s = Proc::start(&data, t0, &[]);
    for want in &acked {
        let id = want["request"].as_str().unwrap();
        let (code, got) = get(s.base(), &format!("/v1/flights/{id}"), None).await;
        assert_eq!((code, &got), (200, want), "{id}");
    }
    s.stop();
}

/// A store records the layering it was written with (docs/reference.md#layered-airspace): a start
/// with another one is refused and names both; the same one starts; a flat store keeps its meta as
/// before layers.
#[test]
fn a_store_refuses_another_layering() {
    let d = scratch_dir("store-layers");
    let clock = now();
    let four = ["--layers", "4", "--heading-rule", "sectors"];
    Proc::start(&d, clock, &four).stop();
    let (code, said) = Proc::start(&d, clock, &[]).refused();
    assert_eq!(code, Some(2), "{said}");
    assert!(
        said.contains("layers 4 from 60 m, 9.144 m apart")
            && said.contains("heading rule sectors")
            && said.contains("layers (none)"),
        "{said}"
    );
    let (code, said) = Proc::start(&d, clock, &["--layers", "2"]).refused();
    assert_eq!(code, Some(2), "{said}");
    assert!(said.contains("layers 2 from 60 m"), "{said}");
    Proc::start(&d, clock, &four).stop();

    let flat = scratch_dir("store-flat");
    Proc::start(&flat, clock, &[]).stop();
    let (code, said) = Proc::start(&flat, clock, &["--layers", "2"]).refused();
    assert_eq!(code, Some(2), "{said}");
    assert!(said.contains("layers (not recorded)"), "{said}");
    Proc::start(&flat, clock, &["--layers", "1"]).stop();
}
