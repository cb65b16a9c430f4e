//! The browser tests' CDP client (`support::cdp`) against a tiny local page: console
//! errors and uncaught exceptions are collected, `eval` returns values and reports exceptions,
//! a click reaches a button, a screenshot is a PNG, and `offline` takes the page offline.
//! Skipped with a notice when Chromium is not installed, unless `CI` is set.

use std::time::Duration;

use serde_json::json;

// The `muse serve` helpers are not used here.
use crate::support::cdp::{browser_or_skip, file_url};

/// A button that says when it is clicked, one `console.error` and one uncaught exception.
const PAGE: &str = r#"<!doctype html>
<html><head><meta charset="utf-8"><title>cdp selftest</title>
<style>
  body { margin: 0; }
  #b { position: absolute; left: 100px; top: 120px; width: 200px; height: 80px; }
</style></head>
<body>
<button id="b" onclick="this.textContent = 'clicked'">click me</button>
<script>
  window.answer = 6 * 7;
  console.error("boom", 7);
  setTimeout(() => { throw new Error("kaboom"); }, 0);
</script>
</body></html>
"#;

#[test]
fn the_cdp_client_drives_a_local_page() {
    let Some(browser) = browser_or_skip("cdp_selftest") else {
        return;
    };
    let dir = crate::support::scratch_dir("cdp_selftest");
    std::fs::create_dir_all(&dir).expect("the scratch folder is created");
    let html = dir.join("page with space.html");
    std::fs::write(&html, PAGE).expect("the page is written");
    let url = file_url(&html).expect("an absolute UTF-8 path");
    assert!(url.ends_with("/page%20with%20space.html"), "{url}");

    let page = browser.new_page().expect("a new page");
    page.offline().expect("offline emulation");
    page.goto(&url).expect("the local page loads offline");

    assert_eq!(page.eval("navigator.onLine").expect("eval"), json!(false));
    assert_eq!(page.eval("answer + 1").expect("eval"), json!(43));
    assert_eq!(
        page.eval("new Promise(r => setTimeout(() => r({ok: [1, 'two']}), 10))")
            .expect("a promise is awaited"),
        json!({"ok": [1, "two"]})
    );
    assert_eq!(page.eval("undefined").expect("eval"), json!(null));
    let thrown = page.eval("nope.nothing").expect_err("a ReferenceError");
    assert!(thrown.contains("ReferenceError"), "{thrown}");

    page.wait_for("window.answer === 42", Duration::from_secs(5))
        .expect("an expression that is already true");
    let late = page
        .wait_for("window.never", Duration::from_millis(200))
        .expect_err("a value that never comes");
    assert!(late.contains("window.never"), "{late}");

    let errors = page.console_errors().expect("console errors");
    assert!(
        errors.iter().any(|e| e == "console.error: boom 7"),
        "{errors:?}"
    );
    // The exception is thrown from a timer; give it the moment it needs.
    page.wait_for(
        "new Promise(r => setTimeout(() => r(true), 50))",
        Duration::from_secs(5),
    )
    .expect("a timer fires");
    let errors = page.console_errors().expect("console errors");
    assert!(
        errors
            .iter()
            .any(|e| e.starts_with("uncaught:") && e.contains("kaboom")),
        "{errors:?}"
    );

    let centre = page
        .eval("(() => { const r = b.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; })()")
        .expect("the button's centre");
    let (x, y) = (
        centre[0].as_f64().expect("x"),
        centre[1].as_f64().expect("y"),
    );
    assert_eq!((x, y), (200.0, 160.0));
    page.click(x, y).expect("a click");
    page.wait_for("b.textContent === 'clicked'", Duration::from_secs(5))
        .expect("the button sees the click");

    let shot = dir.join("shots").join("page.png");
    page.screenshot(&shot).expect("a screenshot");
    let png = std::fs::read(&shot).expect("the screenshot is written");
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");

    let requests = page.requests().expect("requests");
    assert_eq!(requests, [url], "the page's only request is its own file");
}
