//! A small synchronous client of CDP, the debugging protocol of Chrome, for the browser tests.
//!
//! [`Browser::launch`] starts headless Chromium on a fresh profile and connects one WebSocket
//! to its browser endpoint; [`Browser::new_page`] opens a tab and attaches to it with a
//! flattened session, so every page's commands and events travel over that one socket, tagged
//! with the page's session id. Replies are matched to commands by id; events that arrive in
//! the meantime are kept in a per-session log, never dropped, so a page's console errors and
//! network requests can be read back at any time. Every wait has a deadline (and the socket a
//! matching read timeout), so a wedged browser fails the test with a message naming what was
//! awaited instead of hanging it.
//!
//! Launching the browser is here; the socket is in `connection.rs`, a tab in `page.rs`.

use std::cell::{RefCell, RefMut};
use std::fmt::Write as _;
use std::io::{BufRead as _, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use serde_json::json;

mod connection;
mod page;

use connection::Connection;
pub use page::Page;

/// How long a command's reply or a page load may take.
pub const TIMEOUT: Duration = Duration::from_mins(1);

/// How long Chromium may take to print the address of its CDP endpoint.
const LAUNCH_TIMEOUT: Duration = Duration::from_secs(30);

/// How long a closed browser may take to exit before it is killed.
const EXIT_GRACE: Duration = Duration::from_secs(5);

/// How often [`Page::wait_for`] evaluates its expression.
const POLL: Duration = Duration::from_millis(50);

/// What the error says when no browser is found.
const INSTALL_HINT: &str = "install it with `apt-get install chromium`, or set MUSE_CHROMIUM to \
                            a Chromium or Chrome executable";

/// The Chromium executable: `$MUSE_CHROMIUM` if set, else `/usr/bin/chromium`, else
/// `chromium` on `PATH`.
pub fn chromium() -> Result<PathBuf, String> {
    if let Some(path) = std::env::var_os("MUSE_CHROMIUM") {
        let path = PathBuf::from(path);
        return if path.is_file() {
            Ok(path)
        } else {
            Err(format!(
                "MUSE_CHROMIUM={} is not a file; {INSTALL_HINT}",
                path.display()
            ))
        };
    }
    let usual = Path::new("/usr/bin/chromium");
    if usual.is_file() {
        return Ok(usual.to_owned());
    }
    std::env::var_os("PATH")
        .iter()
        .flat_map(std::env::split_paths)
        .map(|dir| dir.join("chromium"))
        .find(|path| path.is_file())
        .ok_or_else(|| {
            format!(
                "Chromium not found (looked at $MUSE_CHROMIUM, /usr/bin/chromium and `chromium` \
                 on PATH); {INSTALL_HINT}"
            )
        })
}

/// Launches the browser for the test `test`. When Chromium is not installed, prints a notice
/// and returns `None` (the test skips itself) unless the environment variable `CI` is set, in
/// which case it panics: CI installs Chromium, so a missing one there is a failure. Panics if
/// an installed Chromium fails to start.
pub fn browser_or_skip(test: &str) -> Option<Browser> {
    if let Err(why) = chromium() {
        assert!(
            std::env::var_os("CI").is_none(),
            "{test}: {why} (CI is set, so a missing browser fails the test)"
        );
        // Straight to stderr, past the test harness's capture, so the skip is visible.
        let _ = std::io::Write::write_all(
            &mut std::io::stderr(),
            format!("\nSKIPPED {test}: {why}\n").as_bytes(),
        );
        return None;
    }
    Some(Browser::launch().unwrap_or_else(|e| panic!("{test}: {e}")))
}

/// A `file://` URL for an absolute path, percent-encoding every byte that is not plain.
pub fn file_url(path: &Path) -> Result<String, String> {
    let text = path
        .to_str()
        .ok_or_else(|| format!("{} is not UTF-8", path.display()))?;
    if !path.is_absolute() {
        return Err(format!("{text} is not an absolute path"));
    }
    let mut url = String::from("file://");
    for byte in text.bytes() {
        if byte.is_ascii_alphanumeric() || b"/-._~".contains(&byte) {
            url.push(char::from(byte));
        } else {
            let _ = write!(url, "%{byte:02X}");
        }
    }
    Ok(url)
}

/// A headless Chromium and the WebSocket to its browser endpoint. Dropping it closes the
/// browser (killing it if it does not exit promptly) and removes its profile folder.
pub struct Browser {
    /// The connection (declared before `process`, so it is closed first).
    conn: RefCell<Connection>,
    /// The Chromium process and its profile folder.
    process: Process,
}

impl Browser {
    /// Starts [`chromium`] headless on a fresh profile folder, reads the address of the CDP
    /// endpoint it prints on stderr and connects to it.
    pub fn launch() -> Result<Self, String> {
        let exe = chromium()?;
        let profile = fresh_profile()?;
        let child = Command::new(&exe)
            .args([
                "--headless=new",
                "--no-sandbox",
                "--remote-debugging-port=0",
                "--no-first-run",
                "--no-default-browser-check",
                "--disable-gpu",
                "--window-size=1400,900",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("about:blank")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("starting {}: {e}", exe.display()))?;
        // From here on, a failure kills the process and removes the profile.
        let mut process = Process {
            child,
            profile,
            closing: false,
        };
        let endpoint = process.devtools_endpoint(&exe)?;
        let conn = Connection::open(&endpoint)?;
        Ok(Self {
            conn: RefCell::new(conn),
            process,
        })
    }

    /// Opens a tab on `about:blank`, attaches to it with a flattened session and enables the
    /// `Page`, `Runtime`, `Log` and `Network` domains on it.
    pub fn new_page(&self) -> Result<Page<'_>, String> {
        let mut conn = self.conn()?;
        let created = conn.command(None, "Target.createTarget", json!({"url": "about:blank"}))?;
        let target = created["targetId"]
            .as_str()
            .ok_or("Target.createTarget replied without a targetId")?
            .to_owned();
        let attached = conn.command(
            None,
            "Target.attachToTarget",
            json!({"targetId": target, "flatten": true}),
        )?;
        let session = attached["sessionId"]
            .as_str()
            .ok_or("Target.attachToTarget replied without a sessionId")?
            .to_owned();
        for domain in ["Page", "Runtime", "Log", "Network"] {
            conn.command(Some(&session), &format!("{domain}.enable"), json!({}))?;
        }
        drop(conn);
        Ok(Page {
            browser: self,
            session,
            offline: std::cell::Cell::new(false),
        })
    }

    /// The connection, borrowed for one exchange.
    fn conn(&self) -> Result<RefMut<'_, Connection>, String> {
        self.conn
            .try_borrow_mut()
            .map_err(|_| "the DevTools connection is already in use".to_owned())
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // Ask politely (the browser then takes its helper processes down with it); the
        // process's own drop kills it if it does not exit in time.
        let closed = self
            .conn
            .get_mut()
            .send(None, "Browser.close", json!({}))
            .is_ok();
        self.process.closing = closed;
    }
}

/// The Chromium process and its profile folder; dropping it ends the one and removes the
/// other.
struct Process {
    /// The process (the Debian `chromium` wrapper `exec`s the browser, so this is the browser).
    child: Child,
    /// The `--user-data-dir` folder.
    profile: PathBuf,
    /// Whether the browser was asked to close, so is worth waiting for.
    closing: bool,
}

impl Process {
    /// Reads stderr until the `DevTools listening on ws://…` line and returns the address; a
    /// thread keeps draining stderr afterwards so the browser never blocks on a full pipe.
    fn devtools_endpoint(&mut self, exe: &Path) -> Result<String, String> {
        let stderr = self
            .child
            .stderr
            .take()
            .ok_or("Chromium's stderr is not piped")?;
        let (lines_tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                // Once the address is found nobody listens; keep reading regardless.
                let _ = lines_tx.send(line);
            }
        });
        let deadline = Instant::now() + LAUNCH_TIMEOUT;
        let mut said = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match lines.recv_timeout(left) {
                Ok(line) => {
                    if let Some(address) = line.strip_prefix("DevTools listening on ") {
                        return Ok(address.trim().to_owned());
                    }
                    said.push(line);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    return Err(format!(
                        "timed out after {} s waiting for {} to print `DevTools listening on`; \
                         it said:\n{}",
                        LAUNCH_TIMEOUT.as_secs(),
                        exe.display(),
                        said.join("\n")
                    ));
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = self
                        .child
                        .wait()
                        .map_or_else(|e| e.to_string(), |s| s.to_string());
                    return Err(format!(
                        "{} exited ({status}) before printing its DevTools address; it said:\n{}",
                        exe.display(),
                        said.join("\n")
                    ));
                }
            }
        }
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        if self.closing {
            let deadline = Instant::now() + EXIT_GRACE;
            while Instant::now() < deadline && matches!(self.child.try_wait(), Ok(None)) {
                std::thread::sleep(POLL);
            }
        }
        // Harmless if it has exited already.
        let _ = self.child.kill();
        let _ = self.child.wait();
        // A helper process may still be writing its last files; try again briefly.
        for _ in 0..10 {
            if std::fs::remove_dir_all(&self.profile).is_ok() || !self.profile.exists() {
                break;
            }
            std::thread::sleep(POLL);
        }
    }
}

/// An empty folder for a browser profile, unique to this process and launch.
fn fresh_profile() -> Result<PathBuf, String> {
    static LAUNCHES: AtomicU64 = AtomicU64::new(0);
    let n = LAUNCHES.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("muse-cdp-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)
        .map_err(|e| format!("creating the profile folder {}: {e}", dir.display()))?;
    Ok(dir)
}
