//! One tab driven over its flattened session: navigation, evaluation, waits, console and
//! network logs, screenshots.

use std::path::Path;
use std::time::{Duration, Instant};

use base64::Engine as _;
use serde_json::{Value, json};

use super::{Browser, POLL, TIMEOUT};

/// One tab, driven over its flattened session.
pub struct Page<'b> {
    /// The browser whose connection carries the session.
    pub(super) browser: &'b Browser,
    /// The session id.
    pub(super) session: String,
    /// Whether [`Page::offline`] was called: navigations keep the page offline.
    pub(super) offline: std::cell::Cell<bool>,
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
