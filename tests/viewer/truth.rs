//! The viewer tells the truth, checked in headless Chromium against the `plans.jsonl` of the
//! day it shows: zoomed in, it still counts every drone in the air and says how many are in
//! view; a corridor tells how many flights used it and the load key's scale ends at the
//! busiest; a rejected request is found by its id in any case, with its reason, and a part of
//! an id lists the ids that contain it; the address follows the selection and the clock, and
//! the page follows the address; below 800 px the panel stacks under the map and fingers pan,
//! zoom and select. Each state is saved as a screenshot in `target/screenshots/`. Skipped
//! with a notice when Chromium is not installed, unless `CI` is set.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::time::Duration;

use serde_json::Value;

// The `muse serve` helpers are not used here.
use crate::support::cdp::{Browser, Page, browser_or_skip};
use crate::support::viewer::{
    Plan, assert_no_console_errors, clock, eval_count, eval_i64, eval_string, local, open_offline,
    screenshots, simulate,
};

/// A simulated day opened in a fresh page: the browser, the plans and the page's file.
struct Day {
    browser: Browser,
    plans: Vec<Plan>,
    view: PathBuf,
}

impl Day {
    /// Simulates the default day into a folder of its own, or `None` without Chromium.
    fn new(test: &str) -> Option<Day> {
        let browser = browser_or_skip(test)?;
        let (plans, view) = simulate(&crate::support::scratch_dir(test));
        Some(Day {
            browser,
            plans,
            view,
        })
    }

    /// The local instant `HH:MM` of the simulated day.
    fn at(&self, hh_mm: &str) -> i64 {
        let sample = self
            .plans
            .iter()
            .find_map(|p| p.takeoff.as_deref())
            .expect("a planned flight");
        local(sample, hh_mm)
    }

    /// The plans of the flights in the air at `t`.
    fn airborne(&self, t: i64) -> Vec<&Plan> {
        self.plans.iter().filter(|p| p.airborne_at(t)).collect()
    }
}

/// The centre of element `id` on the page, CSS px.
fn centre(page: &Page<'_>, id: &str) -> (f64, f64) {
    let r = page
        .eval(&format!(
            "(() => {{ const r = document.getElementById({id:?}).getBoundingClientRect(); \
             return [r.left + r.width / 2, r.top + r.height / 2]; }})()"
        ))
        .unwrap_or_else(|e| panic!("{e}"));
    (r[0].as_f64().expect("x"), r[1].as_f64().expect("y"))
}

/// The bounding box of the element `selector` matches: `[left, top, right, bottom]`.
fn rect(page: &Page<'_>, selector: &str) -> [f64; 4] {
    let r = page
        .eval(&format!(
            "(() => {{ const r = document.querySelector({selector:?}).getBoundingClientRect(); \
             return [r.left, r.top, r.right, r.bottom]; }})()"
        ))
        .unwrap_or_else(|e| panic!("{e}"));
    std::array::from_fn(|i| r[i].as_f64().expect("a number"))
}

/// The text of element `id`.
fn text(page: &Page<'_>, id: &str) -> String {
    eval_string(
        page,
        &format!("document.getElementById({id:?}).textContent"),
    )
}

#[test]
fn zoomed_in_the_page_counts_every_drone_in_the_air_and_those_in_view() {
    let Some(day) = Day::new("view_truth_zoom") else {
        return;
    };
    let page = day.browser.new_page().expect("a page");
    open_offline(&page, &day.view, "");
    let at = day.at("10:30");
    let n = day.airborne(at).len();
    assert!(n > 5, "a busy enough instant: {n} airborne");
    assert_eq!(
        eval_count(&page, &format!("museView.setTime({at})")),
        n as u64
    );
    // Zoom in about a drone with the wheel: it stays under the cursor, most others leave.
    let first = page.eval("museView.flightsDrawn()[0]").expect("a drone");
    let (x, y) = (
        first["x"].as_f64().expect("x"),
        first["y"].as_f64().expect("y"),
    );
    let before = page.eval("museView.scale()").expect("scale");
    for _ in 0..4 {
        page.wheel(x, y, -300.0).expect("a wheel turn");
    }
    page.wait_for(
        &format!("museView.scale() > 5 * {before} && museView.drawnCount() < {n}"),
        Duration::from_secs(10),
    )
    .expect("the wheel zooms in and drones leave the view");
    page.wait_for(
        "document.getElementById('airborne').textContent.endsWith(museView.drawnCount() + ' in view')",
        Duration::from_secs(5),
    )
    .expect("the count is redrawn");
    let m = eval_count(&page, "museView.drawnCount()") as usize;
    assert_eq!(eval_count(&page, "museView.airborneCount()") as usize, n);
    assert!(m >= 1 && m < n, "{m} in view of {n}");
    assert_eq!(
        text(&page, "airborne"),
        format!("{n} in the air, {m} in view")
    );
    let airborne: BTreeSet<&str> = day
        .airborne(at)
        .iter()
        .map(|p| p.request.as_str())
        .collect();
    let [left, top, right, bottom] = rect(&page, "#map");
    let drawn = page.eval("museView.flightsDrawn()").expect("drawn");
    for d in drawn.as_array().expect("an array") {
        let id = d["id"].as_str().expect("an id");
        let (x, y) = (d["x"].as_f64().expect("x"), d["y"].as_f64().expect("y"));
        assert!(airborne.contains(id), "{id} drawn but not airborne");
        assert!(
            (left..=right).contains(&x) && (top..=bottom).contains(&y),
            "{id} at ({x}, {y}) is counted in view but lies outside the map"
        );
    }
    page.screenshot(&screenshots().join("view-zoomed.png"))
        .expect("screenshot");
    println!("zoomed in: {n} in the air, {m} in view");
    assert_no_console_errors(&page);
}

#[test]
fn a_corridor_tells_its_flights_and_the_key_ends_at_the_busiest() {
    let Some(day) = Day::new("view_truth_corridors") else {
        return;
    };
    let page = day.browser.new_page().expect("a page");
    open_offline(&page, &day.view, "");
    // Flights per corridor by plans.jsonl: each hop between two different nodes of a path.
    let mut load: BTreeMap<(String, String), u64> = BTreeMap::new();
    for p in &day.plans {
        for hop in p.path.windows(2) {
            if hop[0] != hop[1] {
                let key = if hop[0] < hop[1] {
                    (hop[0].clone(), hop[1].clone())
                } else {
                    (hop[1].clone(), hop[0].clone())
                };
                *load.entry(key).or_default() += 1;
            }
        }
    }
    let max = *load.values().max().expect("flights");
    // Before the first take-off no drone hides a corridor from the mouse.
    eval_count(&page, "museView.setTime(museView.scene.t0)");
    let edges = page
        .eval(
            "museView.scene.edges.map(([a, b], i) => \
             [museView.scene.nodes[a].id, museView.scene.nodes[b].id, museView.corridor(i).text])",
        )
        .expect("edges");
    let mut busiest = None;
    for (i, e) in edges.as_array().expect("an array").iter().enumerate() {
        let (a, b) = (e[0].as_str().expect("a"), e[1].as_str().expect("b"));
        let key = if a < b { (a, b) } else { (b, a) };
        let n = load
            .get(&(key.0.to_owned(), key.1.to_owned()))
            .copied()
            .unwrap_or(0);
        let plural = if n == 1 { "" } else { "s" };
        assert_eq!(
            e[2].as_str().expect("a text"),
            format!("{a}–{b}: {n} flight{plural} in the whole day"),
            "corridor {i}"
        );
        if n == max {
            busiest = Some(i);
        }
    }
    let last_tick = eval_string(
        &page,
        "[...document.querySelectorAll('#load-key .key-ticks span')].pop().textContent",
    );
    assert_eq!(last_tick, max.to_string(), "the key ends at the busiest");
    let i = busiest.expect("a busiest corridor");
    let at = page
        .eval(&format!("museView.corridor({i})"))
        .expect("corridor");
    page.mouse_move(at["x"].as_f64().expect("x"), at["y"].as_f64().expect("y"))
        .expect("hover");
    page.wait_for(
        &format!(
            "!document.getElementById('tooltip').hidden && document.getElementById('tooltip').textContent === {}",
            at["text"]
        ),
        Duration::from_secs(5),
    )
    .expect("the tooltip on the busiest corridor");
    page.screenshot(&screenshots().join("view-corridor.png"))
        .expect("screenshot");
    println!("corridors: every count as plans.jsonl has it; the busiest has {max}");
    assert_no_console_errors(&page);
}

#[test]
fn a_rejected_request_is_found_case_aside_with_its_reason() {
    let Some(day) = Day::new("view_truth_find") else {
        return;
    };
    let page = day.browser.new_page().expect("a page");
    open_offline(&page, &day.view, "");
    let rejected = day
        .plans
        .iter()
        .find(|p| p.status == "rejected" && p.reason.as_deref() == Some("no_feasible_plan"))
        .expect("a request rejected for want of a feasible plan");
    let id = rejected.request.as_str();
    page.eval("document.getElementById('find').focus()")
        .expect("focus");
    page.insert_text(&id.to_uppercase()).expect("typing");
    // Suggestions while typing: ids containing the text, case aside, the id itself first.
    let listed: Vec<String> = serde_json::from_value(
        page.eval("[...document.querySelectorAll('#find-list button')].map((b) => b.textContent)")
            .expect("suggestions"),
    )
    .expect("strings");
    assert_eq!(listed.first().map(String::as_str), Some(id), "{listed:?}");
    let button = rect(&page, "#find-form button");
    page.click(
        f64::midpoint(button[0], button[2]),
        f64::midpoint(button[1], button[3]),
    )
    .expect("click on Show");
    page.wait_for(
        &format!("museView.selected() === {id:?}"),
        Duration::from_secs(5),
    )
    .expect("the rejected request is selected");
    let details = text(&page, "details");
    for want in [
        id,
        "rejected",
        "no_feasible_plan",
        "traffic and no-fly zones leave no plan",
    ] {
        assert!(details.contains(want), "#details lacks `{want}`: {details}");
    }
    page.screenshot(&screenshots().join("view-rejected.png"))
        .expect("screenshot");

    // Part of an id: the first ten ids containing it (those starting with it first, then the
    // shorter, then in order), and how many more.
    let part = "R12";
    let mut containing: Vec<&str> = day
        .plans
        .iter()
        .map(|p| p.request.as_str())
        .filter(|r| r.to_lowercase().contains(&part.to_lowercase()))
        .collect();
    containing.sort_by_key(|r| (!r.to_lowercase().starts_with("r12"), r.len(), *r));
    assert!(containing.len() > 10, "{containing:?}");
    page.eval(&format!(
        "(() => {{ const f = document.getElementById('find'); f.value = {part:?}; \
         f.dispatchEvent(new Event('input')); }})()"
    ))
    .expect("typing a part");
    let listed: Vec<String> = serde_json::from_value(
        page.eval("[...document.querySelectorAll('#find-list button')].map((b) => b.textContent)")
            .expect("suggestions"),
    )
    .expect("strings");
    assert_eq!(
        listed,
        containing[..10],
        "the first ten ids containing {part}"
    );
    let more = text(&page, "find-list");
    assert!(
        more.contains(&format!("and {} more", containing.len() - 10)),
        "{more}"
    );
    // An id nobody has.
    page.eval(
        "(() => { const f = document.getElementById('find'); f.value = 'zz-none'; \
         f.closest('form').requestSubmit(); })()",
    )
    .expect("a search");
    page.wait_for(
        "document.getElementById('find-message').textContent === 'No request zz-none, nor any id containing it.'",
        Duration::from_secs(5),
    )
    .expect("an unknown id is said to be unknown");
    println!(
        "found {id} (typed in capitals): rejected, no_feasible_plan; `{part}`: {} ids",
        containing.len()
    );
    assert_no_console_errors(&page);
}

#[test]
fn the_address_follows_the_selection_and_the_clock_both_ways() {
    let Some(day) = Day::new("view_truth_address") else {
        return;
    };
    let page = day.browser.new_page().expect("a page");
    open_offline(&page, &day.view, "");
    let t = day.at("10:30");
    let flying = day.airborne(t)[0].request.clone();
    eval_count(&page, &format!("museView.setTime({t})"));
    page.eval(&format!("museView.select({flying:?})"))
        .expect("select");
    page.wait_for(
        &format!("location.hash === '#t=10:30:00&f={flying}'"),
        Duration::from_secs(5),
    )
    .expect("the address follows the selection and the clock");

    // The address set by hand: the page follows, a rejected request included.
    let rejected = day
        .plans
        .iter()
        .find(|p| p.status == "rejected")
        .expect("a rejected request");
    let other = rejected.request.as_str();
    page.eval(&format!("location.hash = '#t=15:00:00&f={other}'"))
        .expect("set the address");
    page.wait_for(
        &format!("museView.selected() === {other:?} && document.getElementById('clock').textContent === '15:00:00'"),
        Duration::from_secs(5),
    )
    .expect("the page follows the address");
    assert!(text(&page, "details").contains("rejected"));

    // No time in the address: a flight not in the air then is shown from its take-off.
    let four = day.at("16:00");
    let later = day
        .plans
        .iter()
        .find(|p| p.airborne.first().is_some_and(|&(up, _)| up > four))
        .expect("a flight after 16:00");
    let takeoff = clock(later.takeoff.as_deref().expect("a take-off"));
    page.eval(&format!("location.hash = '#f={}'", later.request))
        .expect("set the address");
    page.wait_for(
        // The clock's text is drawn on the next frame, after the address changes: wait for both.
        &format!(
            "museView.selected() === {:?} && location.hash === '#t={takeoff}&f={}' \
             && document.getElementById('clock').textContent === '{takeoff}'",
            later.request, later.request
        ),
        Duration::from_secs(5),
    )
    .expect("the clock moves to the take-off and the address says so");
    assert_eq!(text(&page, "clock"), takeoff);
    page.screenshot(&screenshots().join("view-address.png"))
        .expect("screenshot");

    // A page opened at an address (the older `flight=` spelling too) starts there.
    let fresh = day.browser.new_page().expect("a page");
    open_offline(&fresh, &day.view, &format!("t=09:00&flight={flying}"));
    assert_eq!(eval_string(&fresh, "museView.selected()"), flying);
    assert_eq!(text(&fresh, "clock"), "09:00:00");
    fresh
        .wait_for(
            &format!("location.hash === '#t=09:00:00&f={flying}'"),
            Duration::from_secs(5),
        )
        .expect("the address is written back in full");
    println!(
        "address: select {flying} → written; set → followed ({other}, then {})",
        later.request
    );
    assert_no_console_errors(&page);
    assert_no_console_errors(&fresh);
}

#[test]
fn below_800_px_the_panel_stacks_under_the_map_and_fingers_pan_and_zoom() {
    let Some(day) = Day::new("view_truth_narrow") else {
        return;
    };
    let page = day.browser.new_page().expect("a page");
    page.set_viewport(600, 900, true)
        .expect("a 600 px touch screen");
    open_offline(&page, &day.view, "");
    let width = eval_i64(&page, "document.documentElement.clientWidth") as f64;
    let scroll = eval_i64(&page, "document.documentElement.scrollWidth") as f64;
    assert!((560.0..=600.0).contains(&width), "viewport {width}");
    assert!(scroll <= width, "horizontal overflow: {scroll} > {width}");
    let map = rect(&page, "#map-wrap");
    let controls = rect(&page, "footer");
    let panel = rect(&page, "aside");
    assert!(
        map[0].abs() < 1.0 && (map[2] - width).abs() < 1.0,
        "the map spans the width: {map:?}"
    );
    assert!(
        controls[1] >= map[3] - 1.0,
        "controls under the map: {controls:?} {map:?}"
    );
    assert!(
        panel[1] >= controls[3] - 1.0 && panel[0].abs() < 1.0 && (panel[2] - width).abs() < 1.0,
        "the panel under the controls, full width: {panel:?}"
    );
    let overflowing = eval_count(
        &page,
        "[...document.querySelectorAll('body *')].filter((e) => e.getBoundingClientRect().right > document.documentElement.clientWidth + 0.5).length",
    );
    assert_eq!(overflowing, 0, "elements past the right edge");

    // A tap selects the drone under the finger.
    let t = day.at("10:30");
    eval_count(&page, &format!("museView.setTime({t})"));
    let target = page
        .eval("museView.flightsDrawn().find((d) => d.y > 40 && d.x > 20 && d.x < 580)")
        .expect("a drone to tap");
    let (x, y) = (
        target["x"].as_f64().expect("x"),
        target["y"].as_f64().expect("y"),
    );
    page.touch("touchStart", &[(x + 3.0, y + 3.0)])
        .expect("touch");
    page.touch("touchEnd", &[]).expect("lift");
    page.wait_for(
        &format!("museView.selected() === {}", target["id"]),
        Duration::from_secs(5),
    )
    .expect("a tap selects");

    // Two fingers apart zoom in about their middle; one finger pans.
    let (cx, cy) = centre(&page, "map");
    let before = page.eval("museView.scale()").expect("scale");
    page.touch("touchStart", &[(cx - 40.0, cy), (cx + 40.0, cy)])
        .expect("two fingers");
    for step in 1..=4 {
        let d = 40.0 + 20.0 * f64::from(step);
        page.touch("touchMove", &[(cx - d, cy), (cx + d, cy)])
            .expect("pinch");
    }
    page.touch("touchEnd", &[]).expect("lift");
    let after = page.eval("museView.scale()").expect("scale");
    let ratio = after.as_f64().expect("a scale") / before.as_f64().expect("a scale");
    assert!(
        (ratio - 3.0).abs() < 0.05,
        "a pinch from 80 to 240 px zooms 3×: {ratio}"
    );
    let mid = |p: &Page<'_>| -> (f64, f64) {
        let c: Value = p.eval("museView.corridor(0)").expect("corridor");
        (c["x"].as_f64().expect("x"), c["y"].as_f64().expect("y"))
    };
    let (x0, y0) = mid(&page);
    page.touch("touchStart", &[(cx, cy)]).expect("one finger");
    for step in 1..=4 {
        let k = f64::from(step);
        page.touch("touchMove", &[(cx + 15.0 * k, cy + 10.0 * k)])
            .expect("pan");
    }
    page.touch("touchEnd", &[]).expect("lift");
    let (x1, y1) = mid(&page);
    assert!(
        (x1 - x0 - 60.0).abs() < 1.0 && (y1 - y0 - 40.0).abs() < 1.0,
        "one finger pans the map with it: ({x0}, {y0}) → ({x1}, {y1})"
    );
    page.eval("museView.resetView()").expect("reset");
    page.wait_for("museView.drawnCount() > 0", Duration::from_secs(5))
        .expect("drawn again");
    page.screenshot_full_page(&screenshots().join("view-narrow.png"))
        .expect("screenshot");
    println!("600 px: map, controls, panel stacked, no overflow; tap, pinch ×{ratio:.2}, pan");
    assert_no_console_errors(&page);
}

#[test]
fn an_optimised_day_shows_both_objectives_and_the_displaced() {
    let Some(browser) = browser_or_skip("view_truth_optimised") else {
        return;
    };
    let out = crate::support::scratch_dir("view_truth_optimised");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_muse"))
        .args([
            "simulate",
            "--od",
            "in-range",
            "--count",
            "1500",
            "--optimize",
        ])
        .args(["--iterations", "2000", "--out"])
        .arg(&out)
        .output()
        .expect("muse simulate runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let o = &summary["optimizer"];
    let page = browser.new_page().expect("a page");
    open_offline(&page, &out.join("view.html"), "");
    let text = eval_string(&page, "document.getElementById('summary').innerText");
    for (label, planned) in [
        ("planned by FCFS", &o["fcfs"]["planned"]),
        ("planned, optimised", &o["optimized"]["planned"]),
    ] {
        let line = text
            .lines()
            .skip_while(|l| l.trim() != label)
            .nth(1)
            .unwrap_or_else(|| panic!("no `{label}` in the summary:\n{text}"));
        assert!(
            line.starts_with(&format!("{planned}, delay ")),
            "{label}: {line}"
        );
    }
    let displaced = text
        .lines()
        .skip_while(|l| l.trim() != "displaced by the optimiser")
        .nth(1)
        .unwrap_or_default();
    assert_eq!(displaced.trim(), o["displaced"].to_string(), "{text}");
    page.screenshot(&screenshots().join("view-optimised-summary.png"))
        .expect("screenshot");
    assert_no_console_errors(&page);
}
