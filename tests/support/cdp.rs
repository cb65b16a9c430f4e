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

use std::cell::{RefCell, RefMut};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::{BufRead as _, BufReader, ErrorKind};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use base64::Engine as _;
use serde_json::{Value, json};
use tungstenite::{Message, WebSocket};

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

/// The WebSocket to the browser endpoint, with the events received so far.
struct Connection {
    /// The socket.
    socket: WebSocket<TcpStream>,
    /// The id of the next command.
    next_id: u64,
    /// Every event received, by session id (`""` for the browser's own), in arrival order.
    events: HashMap<String, Vec<Value>>,
}

impl Connection {
    /// Connects to a `ws://127.0.0.1:PORT/devtools/browser/…` endpoint.
    fn open(endpoint: &str) -> Result<Self, String> {
        let authority = endpoint
            .strip_prefix("ws://")
            .and_then(|rest| rest.split('/').next())
            .ok_or_else(|| format!("unexpected DevTools address {endpoint}"))?;
        let stream = TcpStream::connect(authority)
            .map_err(|e| format!("connecting to DevTools at {endpoint}: {e}"))?;
        stream
            .set_read_timeout(Some(TIMEOUT))
            .and_then(|()| stream.set_write_timeout(Some(TIMEOUT)))
            .map_err(|e| format!("setting socket timeouts: {e}"))?;
        let (socket, _) = tungstenite::client(endpoint, stream)
            .map_err(|e| format!("WebSocket handshake with {endpoint}: {e}"))?;
        Ok(Self {
            socket,
            next_id: 1,
            events: HashMap::new(),
        })
    }

    /// Sends a command without waiting for its reply; returns its id.
    fn send(&mut self, session: Option<&str>, method: &str, params: Value) -> Result<u64, String> {
        let id = self.next_id;
        self.next_id += 1;
        let mut message = serde_json::Map::new();
        message.insert("id".into(), id.into());
        message.insert("method".into(), method.into());
        message.insert("params".into(), params);
        if let Some(session) = session {
            message.insert("sessionId".into(), session.into());
        }
        let message = Value::Object(message);
        self.socket
            .send(Message::text(message.to_string()))
            .map_err(|e| format!("sending {method}: {e}"))?;
        Ok(id)
    }

    /// Sends a command and waits for its reply; returns its `result`, or the protocol's error.
    fn command(
        &mut self,
        session: Option<&str>,
        method: &str,
        params: Value,
    ) -> Result<Value, String> {
        let id = self.send(session, method, params)?;
        let deadline = Instant::now() + TIMEOUT;
        let what = format!("the reply to {method}");
        loop {
            let Some(mut reply) = self.receive(deadline, &what)? else {
                continue;
            };
            // A different id is a late reply to a command that timed out: ignore it.
            if reply["id"].as_u64() != Some(id) {
                continue;
            }
            if let Some(error) = reply.get("error") {
                return Err(format!("{method} failed: {error}"));
            }
            return Ok(reply["result"].take());
        }
    }

    /// How many events `session` has received so far.
    fn event_count(&self, session: &str) -> usize {
        self.events.get(session).map_or(0, Vec::len)
    }

    /// The events `session` has received so far.
    fn events(&self, session: &str) -> &[Value] {
        self.events.get(session).map_or(&[], Vec::as_slice)
    }

    /// Waits until `session` has an event at index `from` or later for which `matches` holds
    /// (given the method and params), and returns its index.
    fn wait_event(
        &mut self,
        session: &str,
        from: usize,
        deadline: Instant,
        what: &str,
        matches: impl Fn(&str, &Value) -> bool,
    ) -> Result<usize, String> {
        let mut seen = from;
        loop {
            let events = self.events(session);
            if let Some(offset) = events
                .get(seen..)
                .unwrap_or_default()
                .iter()
                .position(|e| matches(e["method"].as_str().unwrap_or(""), &e["params"]))
            {
                return Ok(seen + offset);
            }
            seen = seen.max(events.len());
            self.receive(deadline, what)?;
        }
    }

    /// Reads one message before `deadline`: records an event and returns `None`, or returns a
    /// reply. The error names `what` was being awaited.
    fn receive(&mut self, deadline: Instant, what: &str) -> Result<Option<Value>, String> {
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(format!("timed out waiting for {what}"));
            }
            self.socket
                .get_mut()
                .set_read_timeout(Some(left))
                .map_err(|e| format!("setting the read timeout: {e}"))?;
            let text = match self.socket.read() {
                Ok(Message::Text(text)) => text,
                Ok(Message::Close(frame)) => {
                    return Err(format!(
                        "the browser closed the connection ({frame:?}) while we waited for {what}"
                    ));
                }
                // Pings are answered by tungstenite itself; nothing else is expected.
                Ok(_) => continue,
                Err(tungstenite::Error::Io(e))
                    if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) =>
                {
                    continue;
                }
                Err(e) => return Err(format!("reading from the browser, awaiting {what}: {e}")),
            };
            let message: Value = serde_json::from_str(text.as_str())
                .map_err(|e| format!("a DevTools message is not JSON ({e}): {text}"))?;
            if message.get("id").is_some() {
                return Ok(Some(message));
            }
            let session = message["sessionId"].as_str().unwrap_or("").to_owned();
            self.events.entry(session).or_default().push(message);
            return Ok(None);
        }
    }
}

/// One tab, driven over its flattened session.
pub struct Page<'b> {
    /// The browser whose connection carries the session.
    browser: &'b Browser,
    /// The session id.
    session: String,
    /// Whether [`Page::offline`] was called: navigations keep the page offline.
    offline: std::cell::Cell<bool>,
}

impl Page<'_> {
    /// Sends a command on this page's session and waits for its result.
    fn command(&self, method: &str, params: Value) -> Result<Value, String> {
        self.browser
            .conn()?
            .command(Some(&self.session), method, params)
    }

    /// Navigates to `url` and waits for its `load` event.
    pub fn goto(&self, url: &str) -> Result<(), String> {
        let deadline = Instant::now() + TIMEOUT;
        let mut conn = self.browser.conn()?;
        let from = conn.event_count(&self.session);
        let navigated = conn.command(Some(&self.session), "Page.navigate", json!({"url": url}))?;
        if let Some(error) = navigated["errorText"].as_str() {
            return Err(format!("navigating to {url}: {error}"));
        }
        // The load event of this document, not a late one of the previous: after the main
        // frame commits the navigation's loader.
        let committed = match navigated["loaderId"].as_str() {
            Some(loader) => {
                let what = format!("{url} to commit (Page.frameNavigated)");
                let index = conn.wait_event(&self.session, from, deadline, &what, |m, p| {
                    m == "Page.frameNavigated"
                        && p["frame"]["loaderId"] == loader
                        && p["frame"].get("parentId").is_none()
                })?;
                index + 1
            }
            None => from,
        };
        let what = format!("{url} to load (Page.loadEventFired)");
        conn.wait_event(&self.session, committed, deadline, &what, |m, _| {
            m == "Page.loadEventFired"
        })?;
        drop(conn);
        // Some Chromium versions (148) start the new document's renderer online again, though
        // requests stay refused: tell it again.
        if self.offline.get() {
            self.offline()?;
        }
        Ok(())
    }

    /// Emulates a machine with networking disabled (call before [`Page::goto`]).
    pub fn offline(&self) -> Result<(), String> {
        self.offline.set(true);
        self.command(
            "Network.emulateNetworkConditions",
            json!({
                "offline": true,
                "latency": 0,
                "downloadThroughput": -1,
                "uploadThroughput": -1,
            }),
        )?;
        Ok(())
    }

    /// Evaluates a JavaScript expression in the page, awaiting it if it is a promise, and
    /// returns its value as JSON (`undefined`, and numbers JSON cannot hold, come back as
    /// `null`). An exception is an error carrying its text.
    pub fn eval(&self, expr: &str) -> Result<Value, String> {
        self.evaluate(expr)?
            .map_err(|exception| format!("`{expr}` threw: {exception}"))
    }

    /// [`Page::eval`], with the protocol's failures outside and the script's exception inside.
    fn evaluate(&self, expr: &str) -> Result<Result<Value, String>, String> {
        let mut reply = self
            .command(
                "Runtime.evaluate",
                json!({"expression": expr, "returnByValue": true, "awaitPromise": true}),
            )
            .map_err(|e| format!("evaluating `{expr}`: {e}"))?;
        if let Some(details) = reply.get("exceptionDetails") {
            return Ok(Err(exception_text(details)));
        }
        Ok(Ok(reply["result"]["value"].take()))
    }

    /// Evaluates `expr` every 50 ms until it is truthy (an exception counts as not yet), and
    /// returns that value; fails after `timeout`, naming the expression and its last outcome.
    pub fn wait_for(&self, expr: &str, timeout: Duration) -> Result<Value, String> {
        let deadline = Instant::now() + timeout;
        loop {
            let outcome = self.evaluate(expr)?;
            if let Ok(value) = &outcome
                && truthy(value)
            {
                return outcome;
            }
            if Instant::now() >= deadline {
                let last = match outcome {
                    Ok(value) => format!("it was {value}"),
                    Err(exception) => format!("it threw {exception}"),
                };
                return Err(format!(
                    "timed out after {:.1} s waiting for `{expr}`; {last}",
                    timeout.as_secs_f64()
                ));
            }
            std::thread::sleep(POLL);
        }
    }

    /// Clicks the left mouse button at `(x, y)` in CSS pixels from the viewport's top left.
    pub fn click(&self, x: f64, y: f64) -> Result<(), String> {
        self.command(
            "Input.dispatchMouseEvent",
            json!({"type": "mouseMoved", "x": x, "y": y, "button": "none"}),
        )?;
        for kind in ["mousePressed", "mouseReleased"] {
            self.command(
                "Input.dispatchMouseEvent",
                json!({"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1}),
            )?;
        }
        Ok(())
    }

    /// Moves the mouse to `(x, y)` (CSS pixels from the viewport's top left), no button down.
    pub fn mouse_move(&self, x: f64, y: f64) -> Result<(), String> {
        self.command(
            "Input.dispatchMouseEvent",
            json!({"type": "mouseMoved", "x": x, "y": y, "button": "none"}),
        )
        .map(drop)
    }

    /// Turns the mouse wheel at `(x, y)` by `delta_y` CSS pixels (negative: away from the
    /// user, which zooms a map in).
    pub fn wheel(&self, x: f64, y: f64, delta_y: f64) -> Result<(), String> {
        self.command(
            "Input.dispatchMouseEvent",
            json!({"type": "mouseWheel", "x": x, "y": y, "deltaX": 0, "deltaY": delta_y}),
        )
        .map(drop)
    }

    /// Types `text` into the focused element, as an input method would.
    pub fn insert_text(&self, text: &str) -> Result<(), String> {
        self.command("Input.insertText", json!({"text": text}))
            .map(drop)
    }

    /// Emulates a viewport of `width` × `height` CSS pixels (at one device pixel per CSS
    /// pixel) and, with `touch`, a touch screen; reload the page for media queries to apply
    /// to its first layout.
    pub fn set_viewport(&self, width: u32, height: u32, touch: bool) -> Result<(), String> {
        self.command(
            "Emulation.setDeviceMetricsOverride",
            json!({"width": width, "height": height, "deviceScaleFactor": 1, "mobile": false}),
        )?;
        self.command(
            "Emulation.setTouchEmulationEnabled",
            json!({"enabled": touch, "maxTouchPoints": 5}),
        )
        .map(drop)
    }

    /// Sends one touch event (`touchStart`, `touchMove`, `touchEnd`) with the fingers at
    /// `points` (CSS pixels; the n-th point is finger n). `touchEnd` lifts every finger.
    pub fn touch(&self, kind: &str, points: &[(f64, f64)]) -> Result<(), String> {
        let points: Vec<Value> = points
            .iter()
            .enumerate()
            .map(|(id, &(x, y))| json!({"x": x, "y": y, "id": id}))
            .collect();
        self.command(
            "Input.dispatchTouchEvent",
            json!({"type": kind, "touchPoints": points}),
        )
        .map(drop)
    }

    /// Saves a PNG screenshot of the whole page, beyond the viewport when it scrolls (the
    /// page is laid out as tall as its content then, so with no vertical scroll bar: the
    /// viewport's whole width is taken).
    pub fn screenshot_full_page(&self, path: &Path) -> Result<(), String> {
        let metrics = self.command("Page.getLayoutMetrics", json!({}))?;
        let height = metrics["cssContentSize"]["height"]
            .as_f64()
            .ok_or("no content height")?;
        let width = self
            .eval("window.innerWidth")?
            .as_f64()
            .ok_or("no viewport width")?;
        self.capture(
            path,
            json!({"format": "png", "captureBeyondViewport": true,
                   "clip": {"x": 0, "y": 0, "width": width, "height": height, "scale": 1}}),
        )
    }

    /// Saves a PNG screenshot of the viewport to `path`, creating its folder.
    pub fn screenshot(&self, path: &Path) -> Result<(), String> {
        self.capture(path, json!({"format": "png"}))
    }

    /// `Page.captureScreenshot` with `params`, written to `path`.
    fn capture(&self, path: &Path, params: Value) -> Result<(), String> {
        let shot = self.command("Page.captureScreenshot", params)?;
        let data = shot["data"]
            .as_str()
            .ok_or("Page.captureScreenshot replied without data")?;
        let png = base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| format!("the screenshot is not base64: {e}"))?;
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("creating {}: {e}", parent.display()))?;
        }
        std::fs::write(path, png).map_err(|e| format!("writing {}: {e}", path.display()))
    }

    /// The page's errors so far: `console.error` and failed `console.assert` calls, uncaught
    /// exceptions, and the browser's own error entries (such as failed loads).
    pub fn console_errors(&self) -> Result<Vec<String>, String> {
        self.settle()?;
        let conn = self.browser.conn()?;
        Ok(conn
            .events(&self.session)
            .iter()
            .filter_map(|e| {
                let p = &e["params"];
                match e["method"].as_str()? {
                    "Runtime.consoleAPICalled" => {
                        let kind = p["type"].as_str()?;
                        matches!(kind, "error" | "assert")
                            .then(|| format!("console.{kind}: {}", console_text(p)))
                    }
                    "Runtime.exceptionThrown" => Some(format!(
                        "uncaught: {}",
                        exception_text(&p["exceptionDetails"])
                    )),
                    "Log.entryAdded" => (p["entry"]["level"] == "error").then(|| {
                        let entry = &p["entry"];
                        let source = entry["source"].as_str().unwrap_or("log");
                        let text = entry["text"].as_str().unwrap_or("");
                        match entry["url"].as_str() {
                            Some(url) if !url.is_empty() => format!("{source}: {text} ({url})"),
                            _ => format!("{source}: {text}"),
                        }
                    }),
                    _ => None,
                }
            })
            .collect())
    }

    /// The URL of every request the page has made so far, the document's own included.
    pub fn requests(&self) -> Result<Vec<String>, String> {
        self.settle()?;
        let conn = self.browser.conn()?;
        Ok(conn
            .events(&self.session)
            .iter()
            .filter(|e| e["method"] == "Network.requestWillBeSent")
            .filter_map(|e| e["params"]["request"]["url"].as_str().map(str::to_owned))
            .collect())
    }

    /// A round trip through the page's main thread, so the events it sent before are in.
    fn settle(&self) -> Result<(), String> {
        self.eval("0").map(drop)
    }
}

/// The text of a `Runtime.ExceptionDetails`: the exception's description (message and
/// stack) when there is one, else the details' text, with where it was thrown.
fn exception_text(details: &Value) -> String {
    let text = details["exception"]["description"]
        .as_str()
        .or_else(|| details["text"].as_str())
        .unwrap_or("an exception");
    match details["url"].as_str() {
        Some(url) if !url.is_empty() => format!(
            "{text} ({url}:{}:{})",
            details["lineNumber"].as_u64().map_or(0, |l| l + 1),
            details["columnNumber"].as_u64().map_or(0, |c| c + 1)
        ),
        _ => text.to_owned(),
    }
}

/// A console call's arguments, space-separated like the console shows them.
fn console_text(params: &Value) -> String {
    params["args"]
        .as_array()
        .map(|args| {
            args.iter()
                .map(|arg| match &arg["value"] {
                    Value::String(s) => s.clone(),
                    Value::Null => arg["description"]
                        .as_str()
                        .or_else(|| arg["unserializableValue"].as_str())
                        .or_else(|| arg["subtype"].as_str())
                        .or_else(|| arg["type"].as_str())
                        .unwrap_or("?")
                        .to_owned(),
                    value => value.to_string(),
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_default()
}

/// JavaScript's truthiness, for the values JSON can carry.
fn truthy(value: &Value) -> bool {
    match value {
        Value::Null => false,
        Value::Bool(b) => *b,
        Value::Number(n) => n.as_f64().is_some_and(|x| x != 0.0),
        Value::String(s) => !s.is_empty(),
        Value::Array(_) | Value::Object(_) => true,
    }
}
