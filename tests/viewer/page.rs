//! The viewer that `muse simulate` writes, driven in headless Chromium: `view.html` opens from
//! `file://` on a machine with networking disabled, with no console errors and no request for
//! anything but itself and `data:` URLs; at several instants of the day it draws exactly the
//! flights airborne then according to `plans.jsonl`; and a click on a drone selects it and
//! shows its plan. Skipped with a notice when Chromium is not installed, unless `CI` is set.

use std::collections::BTreeSet;
use std::path::Path;
use std::time::Duration;

// The `muse serve` helpers are not used here.
use crate::support::cdp::{Page, browser_or_skip};
use crate::support::viewer::{
    Plan, assert_no_console_errors, clock, eval_count, eval_i64, local, open_offline, screenshots,
    simulate,
};

/// A drone the page has drawn.
struct Drawn {
    /// Its flight id.
    id: String,
    /// Its centre in CSS pixels from the viewport's top left.
    x: f64,
    /// See `x`.
    y: f64,
    /// Whether the topmost element at its centre is the canvas (no panel covers it).
    on_canvas: bool,
}

/// `museView.flightsDrawn()`, with what lies on top of each drone.
fn drawn(page: &Page<'_>) -> Vec<Drawn> {
    let value = page
        .eval(
            "museView.flightsDrawn().map(f => {
                const top = document.elementFromPoint(f.x, f.y);
                return {id: f.id, x: f.x, y: f.y, canvas: !!top && top.tagName === 'CANVAS'};
            })",
        )
        .unwrap_or_else(|e| panic!("{e}"));
    value
        .as_array()
        .unwrap_or_else(|| panic!("flightsDrawn() is not an array: {value}"))
        .iter()
        .map(|f| Drawn {
            id: f["id"]
                .as_str()
                .unwrap_or_else(|| panic!("a drawn flight without a string id: {f}"))
                .to_owned(),
            x: f["x"].as_f64().unwrap_or_else(|| panic!("no x: {f}")),
            y: f["y"].as_f64().unwrap_or_else(|| panic!("no y: {f}")),
            on_canvas: f["canvas"] == true,
        })
        .collect()
}

/// The drone easiest to click: inside the viewport, on the canvas if any is, and farthest
/// from its nearest neighbour.
fn easiest_to_click(drones: &[Drawn], width: f64, height: f64) -> &Drawn {
    let inside =
        |d: &&Drawn| d.x >= 10.0 && d.y >= 10.0 && d.x <= width - 10.0 && d.y <= height - 10.0;
    let any_on_canvas = drones.iter().filter(inside).any(|d| d.on_canvas);
    let isolation = |d: &Drawn| {
        drones
            .iter()
            .filter(|o| !std::ptr::eq(*o, d))
            .map(|o| (o.x - d.x).hypot(o.y - d.y))
            .fold(f64::INFINITY, f64::min)
    };
    drones
        .iter()
        .filter(inside)
        .filter(|d| d.on_canvas || !any_on_canvas)
        .max_by(|a, b| isolation(a).total_cmp(&isolation(b)))
        .expect("a drawn drone inside the viewport")
}

/// Sets the clock to `t` and asserts that the page draws exactly the flights airborne then
/// (by `setTime`'s count, `drawnCount()` and `flightsDrawn()`); returns how many.
fn assert_draws_the_airborne(page: &Page<'_>, plans: &[Plan], t: i64, label: &str) -> usize {
    let expected: BTreeSet<&str> = plans
        .iter()
        .filter(|p| p.airborne_at(t))
        .map(|p| p.request.as_str())
        .collect();
    let set = eval_count(page, &format!("museView.setTime({t})"));
    let count = eval_count(page, "museView.drawnCount()");
    let airborne = eval_count(page, "museView.airborneCount()");
    let shown = page
        .eval("document.getElementById('airborne').textContent")
        .expect("#airborne");
    let clock_ms = page.eval("museView.time()").expect("museView.time()");
    let ids: BTreeSet<String> = drawn(page).into_iter().map(|d| d.id).collect();
    println!(
        "{label} ({t}): {} airborne per plans.jsonl; setTime gave {set}, drawnCount {count}, \
         flightsDrawn {}",
        expected.len(),
        ids.len()
    );
    assert_eq!(
        clock_ms.as_f64(),
        Some(t as f64),
        "the clock after setTime at {label}"
    );
    assert_eq!(set as usize, expected.len(), "setTime's count at {label}");
    assert_eq!(count as usize, expected.len(), "drawnCount at {label}");
    assert_eq!(
        airborne as usize,
        expected.len(),
        "airborneCount at {label}"
    );
    let n = expected.len();
    assert_eq!(
        shown,
        format!("{n} in the air, {n} in view"),
        "the count shown at {label}, the whole airspace in view"
    );
    let ids: BTreeSet<&str> = ids.iter().map(String::as_str).collect();
    assert_eq!(ids, expected, "the flights drawn at {label}");
    expected.len()
}

/// At clock `t`, clicks the drone easiest to click and asserts that it is selected and that
/// `#details` shows its id, take-off and landing; screenshots before and after the click.
fn assert_click_selects(page: &Page<'_>, plans: &[Plan], t: i64, screenshots: &Path) {
    eval_count(page, &format!("museView.setTime({t})"));
    let size = page
        .eval("[innerWidth, innerHeight]")
        .expect("the viewport's size");
    let (width, height) = (
        size[0].as_f64().expect("a width"),
        size[1].as_f64().expect("a height"),
    );
    let drones = drawn(page);
    let target = easiest_to_click(&drones, width, height);
    let plan = plans
        .iter()
        .find(|p| p.request == target.id)
        .unwrap_or_else(|| panic!("the drawn flight `{}` is not in plans.jsonl", target.id));
    let (takeoff, landing) = (
        clock(plan.takeoff.as_deref().expect("a planned take-off")),
        clock(plan.landing.as_deref().expect("a planned landing")),
    );
    page.screenshot(&screenshots.join("view-simulate-before-click.png"))
        .expect("the screenshot before the click");
    page.click(target.x, target.y).expect("the click");
    let id = serde_json::to_string(&target.id).expect("a JSON string");
    if let Err(e) = page.wait_for(
        &format!("museView.selected() === {id}"),
        Duration::from_secs(5),
    ) {
        panic!(
            "clicking `{}` at ({:.1}, {:.1}) did not select it: {e}",
            target.id, target.x, target.y
        );
    }
    let details = page
        .eval("document.querySelector('#details').textContent")
        .expect("#details");
    page.screenshot(&screenshots.join("view-simulate.png"))
        .expect("the screenshot after the click");
    let details = details
        .as_str()
        .unwrap_or_else(|| panic!("no #details element: {details}"));
    for shown in [target.id.as_str(), takeoff, landing] {
        assert!(
            details.contains(shown),
            "#details lacks `{shown}` (flight {}, take-off {takeoff}, landing {landing}):\n{details}",
            target.id
        );
    }
    println!(
        "clicked {} at ({:.1}, {:.1}) at {t}: selected; #details shows take-off {takeoff} and \
         landing {landing}; screenshots in {}",
        target.id,
        target.x,
        target.y,
        screenshots.display()
    );
}

#[test]
fn the_simulated_day_plays_offline_and_a_click_shows_a_plan() {
    let Some(browser) = browser_or_skip("view_browser") else {
        return;
    };
    let (plans, view) = simulate(&crate::support::scratch_dir("view_browser"));
    let page = browser.new_page().expect("a new page");
    let requests = open_offline(&page, &view, "");

    // The scenario's day and offset, from the first planned take-off.
    let first = plans
        .iter()
        .find_map(|p| p.takeoff.as_deref())
        .expect("at least one planned flight");
    println!(
        "{} plans, {} planned, the first take-off {first}; {requests} requests, all file:// \
         or data:, with networking off and no console errors",
        plans.len(),
        plans.iter().filter(|p| p.takeoff.is_some()).count(),
    );
    // 10:30 is inside the CBD no-fly zone's 10:00–12:00 window.
    let mut busiest: Option<(i64, usize)> = None;
    for hh_mm in ["09:00", "10:30", "15:00"] {
        let t = local(first, hh_mm);
        let n = assert_draws_the_airborne(&page, &plans, t, hh_mm);
        if n > 0 && busiest.is_none_or(|(_, most)| n > most) {
            busiest = Some((t, n));
        }
    }
    let (t, _) = busiest.expect("a flight airborne at one of the instants checked");
    assert_click_selects(&page, &plans, t, &screenshots());
    assert_plays(&page, &plans);
    assert_no_console_errors(&page);
}

/// A real click on the play button runs the clock (300× by default), and the drones drawn
/// then are still exactly the airborne ones; a second click pauses it.
fn assert_plays(page: &Page<'_>, plans: &[Plan]) {
    let button = page
        .eval("(() => { const r = document.getElementById('play').getBoundingClientRect(); return [r.left + r.width / 2, r.top + r.height / 2]; })()")
        .expect("the play button's place");
    let (x, y) = (
        button[0].as_f64().expect("x"),
        button[1].as_f64().expect("y"),
    );
    let before = eval_i64(page, "museView.time()");
    page.click(x, y).expect("click on play");
    page.wait_for(
        &format!("museView.time() > {before} + 60000"),
        Duration::from_secs(20),
    )
    .expect("the clock runs: more than a minute of the day within 20 s at 300×");
    page.click(x, y).expect("click on pause");
    let paused = eval_i64(page, "museView.time()");
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(eval_i64(page, "museView.time()"), paused, "paused");
    let drawn = eval_i64(page, "museView.drawnCount()");
    let airborne = plans.iter().filter(|p| p.airborne_at(paused)).count();
    assert_eq!(drawn, airborne as i64, "after playing, at {paused}");
    println!(
        "play: the clock ran from {before} to {paused} (epoch ms); {drawn} drones drawn, \
         {airborne} airborne"
    );
}
