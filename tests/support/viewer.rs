//! What the tests of the page `muse simulate` writes share: running `muse simulate`, reading
//! its `plans.jsonl` as the oracle of what the page should show, and opening `view.html`
//! offline in the browser with a clean load.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use serde_json::Value;

use super::cdp::{Page, file_url};

/// One line of `plans.jsonl`, as far as the viewer shows it.
pub struct Plan {
    /// The request id.
    pub request: String,
    /// `planned`, `rejected`, `cancelled`, …
    pub status: String,
    /// Why it was rejected or cancelled, if it was.
    pub reason: Option<String>,
    /// Take-off and landing as written (RFC 3339), if planned.
    pub takeoff: Option<String>,
    /// See `takeoff`.
    pub landing: Option<String>,
    /// The airborne intervals `[takeoff, landing)` in epoch milliseconds: one per leg.
    pub airborne: Vec<(i64, i64)>,
    /// The nodes of its path, in order (a station repeated at a battery swap).
    pub path: Vec<String>,
    /// Its stays: node, layer (1 when flat), arrival and departure in epoch milliseconds.
    pub stays: Vec<(String, u32, i64, i64)>,
}

impl Plan {
    /// Whether the flight is in the air at `t` (epoch milliseconds).
    pub fn airborne_at(&self, t: i64) -> bool {
        self.airborne.iter().any(|&(from, to)| from <= t && t < to)
    }

    /// Its layer at `t`, from its stays (docs/reference.md#layered-airspace): the stay's layer
    /// while it is at a node, evenly between two layers while it crosses a vertical link (two stays
    /// in a row at one node), and the layer it flies at along a corridor. `None` before take-off or
    /// after landing.
    pub fn layer_at(&self, t: i64) -> Option<f64> {
        let i = self.stays.iter().rposition(|s| s.2 <= t)?;
        let (node, layer, _, depart) = &self.stays[i];
        let next = self.stays.get(i + 1);
        Some(match next {
            Some((n, k, arrive, _)) if t > *depart && n == node && k != layer => {
                f64::from(*layer)
                    + (f64::from(*k) - f64::from(*layer)) * (t - depart) as f64
                        / (arrive - depart) as f64
            }
            None if t > *depart => return None,
            _ => f64::from(*layer),
        })
    }
}

/// An RFC 3339 instant in epoch milliseconds.
pub fn epoch_ms(text: &str) -> i64 {
    text.parse::<jiff::Timestamp>()
        .unwrap_or_else(|e| panic!("`{text}` is not RFC 3339: {e}"))
        .as_millisecond()
}

/// A field that must be an RFC 3339 string.
fn instant(value: &Value, what: &str) -> i64 {
    epoch_ms(
        value
            .as_str()
            .unwrap_or_else(|| panic!("{what} is not a string: {value}")),
    )
}

/// Reads `plans.jsonl` (docs/reference.md, *Plans*).
pub fn read_plans(path: &Path) -> Vec<Plan> {
    let text = std::fs::read_to_string(path).expect("plans.jsonl is readable");
    text.lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let v: Value = serde_json::from_str(line).expect("each line of plans.jsonl is JSON");
            let request = v["request"].as_str().expect("a request id").to_owned();
            let takeoff = v["takeoff"].as_str().map(str::to_owned);
            let landing = v["landing"].as_str().map(str::to_owned);
            let airborne = match v["legs"].as_array() {
                Some(legs) if !legs.is_empty() => legs
                    .iter()
                    .map(|leg| {
                        (
                            instant(&leg["takeoff"], "a leg's takeoff"),
                            instant(&leg["landing"], "a leg's landing"),
                        )
                    })
                    .collect(),
                _ => match (&takeoff, &landing) {
                    (Some(up), Some(down)) => vec![(epoch_ms(up), epoch_ms(down))],
                    _ => Vec::new(),
                },
            };
            let stays: Vec<(String, u32, i64, i64)> =
                v["path"].as_array().map_or_else(Vec::new, |stays| {
                    stays
                        .iter()
                        .map(|s| {
                            (
                                s["node"].as_str().expect("a stay's node").to_owned(),
                                s["layer"]
                                    .as_u64()
                                    .map_or(1, |k| u32::try_from(k).expect("a layer fits in u32")),
                                instant(&s["arrive"], "a stay's arrival"),
                                instant(&s["depart"], "a stay's departure"),
                            )
                        })
                        .collect()
                });
            let path = stays.iter().map(|s| s.0.clone()).collect();
            Plan {
                request,
                status: v["status"].as_str().expect("a status").to_owned(),
                reason: v["reason"].as_str().map(str::to_owned),
                takeoff,
                landing,
                airborne,
                path,
                stays,
            }
        })
        .collect()
}

/// The `HH:MM:SS` of an RFC 3339 string (truncated to the second), as the page shows it.
pub fn clock(rfc3339: &str) -> &str {
    rfc3339
        .get(11..19)
        .unwrap_or_else(|| panic!("`{rfc3339}` is too short for RFC 3339"))
}

/// The local instant `HH:MM` on the day and at the offset of `sample` (an RFC 3339 string).
pub fn local(sample: &str, hh_mm: &str) -> i64 {
    let date = sample.get(..10).expect("an RFC 3339 date");
    let offset = sample
        .get(19..)
        .expect("an RFC 3339 time")
        .trim_start_matches(|c: char| c == '.' || c.is_ascii_digit());
    epoch_ms(&format!("{date}T{hh_mm}:00{offset}"))
}

/// Evaluates `expr`, which must give a whole number.
pub fn eval_count(page: &Page<'_>, expr: &str) -> u64 {
    let value = page.eval(expr).unwrap_or_else(|e| panic!("{e}"));
    value
        .as_u64()
        .unwrap_or_else(|| panic!("`{expr}` gave {value}, not a count"))
}

/// Evaluates `expr`, which must give a number (truncated to an integer).
pub fn eval_i64(page: &Page<'_>, expr: &str) -> i64 {
    let v = page.eval(expr).expect(expr);
    v.as_f64()
        .map_or_else(|| panic!("{expr} is not a number: {v}"), |v| v as i64)
}

/// Evaluates `expr`, which must give a string.
pub fn eval_string(page: &Page<'_>, expr: &str) -> String {
    let v = page.eval(expr).unwrap_or_else(|e| panic!("{e}"));
    v.as_str()
        .unwrap_or_else(|| panic!("`{expr}` gave {v}, not a string"))
        .to_owned()
}

/// Runs `muse simulate --out OUT` (the default scenario and demand) and returns the plans it
/// wrote and its `view.html`.
pub fn simulate(out: &Path) -> (Vec<Plan>, PathBuf) {
    simulate_with(out, &[])
}

/// Runs `muse simulate --out OUT` with the options `args` and returns the plans it wrote and
/// its `view.html`.
pub fn simulate_with(out: &Path, args: &[&str]) -> (Vec<Plan>, PathBuf) {
    let run = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(["simulate", "--out"])
        .arg(out)
        .args(args)
        .output()
        .expect("muse simulate runs");
    assert!(
        run.status.success(),
        "muse simulate failed ({}):\n{}{}",
        run.status,
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    let view = out.join("view.html");
    assert!(view.is_file(), "muse simulate wrote no {}", view.display());
    (read_plans(&out.join("plans.jsonl")), view)
}

/// Asserts that the page has logged no error so far.
pub fn assert_no_console_errors(page: &Page<'_>) {
    let errors = page.console_errors().expect("console errors");
    assert!(
        errors.is_empty(),
        "the viewer logged errors:\n{}",
        errors.join("\n")
    );
}

/// Opens `view` (with `fragment` after `#`, if not empty) offline, waits for
/// `museView.ready`, and asserts a clean load: no console errors, no request for anything
/// but `file://` and `data:` URLs. Returns the request count.
pub fn open_offline(page: &Page<'_>, view: &Path, fragment: &str) -> usize {
    page.offline().expect("offline emulation");
    let url = file_url(view).expect("an absolute UTF-8 path");
    let full = if fragment.is_empty() {
        url.clone()
    } else {
        format!("{url}#{fragment}")
    };
    page.goto(&full).expect("view.html loads");
    page.wait_for(
        "window.museView && window.museView.ready === true",
        Duration::from_mins(1),
    )
    .expect("the viewer gets ready");
    assert_no_console_errors(page);
    let requests = page.requests().expect("requests");
    let foreign: Vec<_> = requests
        .iter()
        .filter(|u| !u.starts_with("file://") && !u.starts_with("data:"))
        .collect();
    assert!(
        foreign.is_empty(),
        "the viewer asked the network for {foreign:?}"
    );
    assert!(
        requests.iter().any(|r| r == &url || r == &full),
        "the page's own request is missing: {requests:?}"
    );
    requests.len()
}

/// Where the browser tests save their screenshots (`target/screenshots/`; the README's
/// images of the viewer are copies of some of them: `scripts/viewer-images.sh`).
pub fn screenshots() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("target/screenshots")
}
