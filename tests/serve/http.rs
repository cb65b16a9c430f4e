//! The real `muse serve` binary as an operator runs it: tokens reloaded on `SIGHUP` (a
//! removed token refused, an added one accepted, a broken file keeping the tokens in force),
//! short tokens refused at start, timeout options checked, and the connection cap lowered to
//! what a small open-file limit allows, answering `503` above it instead of hanging.
//!
//! Every process is started here and killed by its pid; every wait is bounded.

use std::io::{BufRead as _, BufReader, Read as _, Write as _};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::support::scratch_dir;

/// A `muse serve` started here, with its stdout and stderr lines.
struct Served {
    child: Child,
    base: String,
    /// `(from stderr, line)` for every line after `listening on`.
    lines: mpsc::Receiver<(bool, String)>,
    /// The lines seen so far (stdout and stderr).
    seen: Vec<String>,
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Served {
    /// Starts `command` (a `muse serve` to be) and waits for its address.
    fn start(mut command: Command) -> Served {
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("muse serve starts");
        let (tx, lines) = mpsc::channel();
        for (is_err, stream) in [
            (
                false,
                Box::new(child.stdout.take().unwrap()) as Box<dyn std::io::Read + Send>,
            ),
            (true, Box::new(child.stderr.take().unwrap())),
        ] {
            let tx = tx.clone();
            std::thread::spawn(move || {
                for line in BufReader::new(stream).lines() {
                    let Ok(line) = line else { break };
                    if tx.send((is_err, line)).is_err() {
                        break;
                    }
                }
            });
        }
        let mut seen = Vec::new();
        let base = loop {
            let (_, line) = lines
                .recv_timeout(Duration::from_mins(1))
                .unwrap_or_else(|_| panic!("muse serve prints its address; printed {seen:#?}"));
            if let Some(addr) = line.strip_prefix("listening on ") {
                break addr.trim().to_owned();
            }
            seen.push(line);
        };
        Served {
            child,
            base,
            lines,
            seen,
        }
    }

    /// Waits (at most 10 s) for a line on stdout (`stderr` false) or stderr that contains
    /// every one of `parts`.
    fn wait_for(&mut self, stderr: bool, parts: &[&str]) -> String {
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let Ok((is_err, line)) = self.lines.recv_timeout(left) else {
                panic!("no line with {parts:?} within 10 s; seen {:#?}", self.seen);
            };
            self.seen.push(line.clone());
            if is_err == stderr && parts.iter().all(|p| line.contains(p)) {
                return line;
            }
        }
    }

    /// Sends SIGHUP to the process started here.
    fn hang_up(&self) {
        let status = Command::new("kill")
            .args(["-HUP", &self.child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(status.success());
    }
}

/// `muse serve` on an ephemeral loopback port with `extra` arguments.
fn serve(data: &Path, extra: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_muse"));
    command
        .args(["serve", "--listen", "127.0.0.1:0", "--data"])
        .arg(data)
        .args(extra);
    command
}

/// The status of `GET path` with an optional bearer token, over a fresh connection.
fn get(base: &str, path: &str, token: Option<&str>) -> u16 {
    let addr = base.strip_prefix("http://").expect("an http:// base");
    let mut s = TcpStream::connect(addr).expect("the service accepts connections");
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let auth = token.map_or(String::new(), |t| format!("Authorization: Bearer {t}\r\n"));
    // One write: a server refusing the connection may have closed it already; its answer is
    // read all the same.
    let _ = s.write_all(
        format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\n{auth}Connection: close\r\n\r\n")
            .as_bytes(),
    );
    let mut response = String::new();
    let _ = s.read_to_string(&mut response);
    response
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or_else(|| panic!("an HTTP answer, got {response:?}"))
}

fn tokens_file(entries: &[(&str, &str, &str)]) -> String {
    entries
        .iter()
        .map(|(token, operator, role)| {
            [
                "[[tokens]]\ntoken = \"",
                token,
                "\"\noperator = \"",
                operator,
                "\"\nrole = \"",
                role,
                "\"\n\n",
            ]
            .concat()
        })
        .collect()
}

const ALPHA: &str = "alpha-token-00000001";
const ALPHA_NEW: &str = "alpha-token-00000002";
const AUTHORITY: &str = "authority-token-0001";

#[test]
fn tokens_are_reloaded_on_sighup() {
    let dir = scratch_dir("serve-http-sighup");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tokens.toml");
    let file_name = file.display().to_string();
    std::fs::write(
        &file,
        tokens_file(&[
            (ALPHA, "alpha", "operator"),
            (AUTHORITY, "caas", "authority"),
        ]),
    )
    .unwrap();
    let mut server = Served::start(serve(&dir.join("data"), &["--tokens", &file_name]));
    let base = server.base.clone();
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA)), 200);
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA_NEW)), 401);

    // ALPHA removed, ALPHA_NEW added.
    std::fs::write(
        &file,
        tokens_file(&[
            (ALPHA_NEW, "alpha", "operator"),
            (AUTHORITY, "caas", "authority"),
        ]),
    )
    .unwrap();
    server.hang_up();
    let line = server.wait_for(false, &["tokens reloaded from", &file_name]);
    assert!(line.contains("2 token(s)"), "{line}");
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA)), 401);
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA_NEW)), 200);
    assert_eq!(get(&base, "/v1/flights", Some(AUTHORITY)), 200);

    // A file that does not parse: the error names it; the tokens in force stay.
    std::fs::write(&file, "[[tokens]]\ntoken = \"unterminated\n").unwrap();
    server.hang_up();
    let line = server.wait_for(true, &[&file_name, "keeping the 2 token(s) in force"]);
    println!("{line}");
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA_NEW)), 200);
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA)), 401);

    // A token under 16 characters: refused by entry, the tokens in force stay.
    std::fs::write(
        &file,
        tokens_file(&[
            (ALPHA, "alpha", "operator"),
            ("short-token", "bravo", "operator"),
        ]),
    )
    .unwrap();
    server.hang_up();
    let line = server.wait_for(
        true,
        &[&file_name, "tokens[1] (operator `bravo`)", "too short"],
    );
    println!("{line}");
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA_NEW)), 200);
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA)), 401);

    // A missing file: the same.
    std::fs::remove_file(&file).unwrap();
    server.hang_up();
    server.wait_for(true, &[&file_name, "keeping the 2 token(s) in force"]);
    assert_eq!(get(&base, "/v1/flights", Some(ALPHA_NEW)), 200);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The stderr and exit status of a `muse serve` expected to refuse to start.
fn refused(command: &mut Command) -> String {
    let out = command.output().expect("muse serve runs");
    assert!(!out.status.success(), "muse serve started");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn short_tokens_and_nonsense_limits_are_refused_at_start() {
    let dir = scratch_dir("serve-http-refused");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tokens.toml");
    std::fs::write(
        &file,
        tokens_file(&[
            (AUTHORITY, "caas", "authority"),
            ("fifteen-chars-x", "alpha", "operator"),
        ]),
    )
    .unwrap();
    let file_name = file.display().to_string();
    let data = dir.join("data");
    let e = refused(&mut serve(&data, &["--tokens", &file_name]));
    assert!(
        e.contains(&file_name)
            && e.contains("tokens[1] (operator `alpha`): field `token`: too short (15 characters; at least 16)"),
        "{e}"
    );
    for (option, value) in [
        ("--header-timeout-s", "0"),
        ("--header-timeout-s", "-1"),
        ("--body-timeout-s", "NaN"),
        ("--idle-timeout-s", "inf"),
        ("--idle-timeout-s", "soon"),
        ("--max-connections", "0"),
        ("--max-connections", "-5"),
        ("--max-connections", "1.5"),
    ] {
        let e = refused(&mut serve(&data, &[&format!("{option}={value}")]));
        assert!(e.contains(option), "{option} {value}: {e}");
        assert!(!e.contains("panicked"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Under an open-file limit of 256 (soft and hard), the cap is 256 less the 64 kept for
/// files: with 202 idle sockets open the service still answers, the sockets above the cap
/// and a new client get `503` at once, and once the idle sockets go it serves again.
#[test]
fn the_connection_cap_follows_the_open_file_limit() {
    let dir = scratch_dir("serve-http-nofile");
    let mut command = Command::new("sh");
    command
        .arg("-c")
        .arg("ulimit -n 256 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_muse"))
        .args(["serve", "--listen", "127.0.0.1:0", "--data"])
        .arg(dir.join("data"));
    let server = Served::start(command);
    let limits = server
        .seen
        .iter()
        .find(|l| l.trim_start().starts_with("http "))
        .cloned()
        .unwrap_or_default();
    assert!(
        limits.contains(
            "at most 192 connections (open-file limit 256, lowered from --max-connections 10000)"
        ),
        "{limits}"
    );
    let addr = server.base.strip_prefix("http://").unwrap().to_owned();
    let mut idle = Vec::new();
    for _ in 0..202 {
        idle.push(TcpStream::connect(&addr).expect("connects"));
    }
    // A new client is answered at once, never left hanging.
    let began = Instant::now();
    let status = get(&server.base, "/healthz", None);
    println!("with 202 idle sockets: {status} in {:?}", began.elapsed());
    assert_eq!(status, 503);
    assert!(began.elapsed() < Duration::from_secs(2));
    // The sockets above the cap were answered 503 and closed.
    let mut refused = 0;
    for s in &mut idle {
        s.set_nonblocking(true).unwrap();
        let mut buf = [0u8; 512];
        if s.read(&mut buf).is_ok_and(|n| n > 0) && buf.starts_with(b"HTTP/1.1 503") {
            refused += 1;
        }
    }
    println!("{refused} of 202 idle sockets answered 503");
    assert_eq!(refused, 10);
    drop(idle);
    let began = Instant::now();
    while get(&server.base, "/healthz", None) != 200 {
        assert!(began.elapsed() < Duration::from_secs(10), "served again");
        std::thread::sleep(Duration::from_millis(50));
    }
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}
