//! A layered day (docs/reference.md#layered-airspace: four layers, one heading sector each) in the
//! page `muse simulate` writes, driven in headless Chromium against its `plans.jsonl`: it opens
//! offline without errors, drawn from above (the flat stations only), and every layer shown draws
//! exactly the flights in the air (a climb does not end a leg); shown one layer alone, the page
//! draws exactly the flights at that layer (or crossing to or from it) by their stays; a zone whose
//! band covers the lower layers closes corridors there and none above; and the selected flight's
//! side view gives its altitude over time as its stays do, and a click on it moves the clock there.
//! Skipped with a notice when Chromium is not installed, unless `CI` is set.

use std::collections::BTreeSet;

use serde_json::Value;

use crate::support::cdp::{Page, browser_or_skip};
use crate::support::viewer::{
    Plan, assert_no_console_errors, eval_count, eval_i64, eval_string, local, open_offline,
    screenshots, simulate_with,
};

/// The layers' altitudes of the run in `out`, from its `summary.json` (`world.layers`).
fn altitudes(out: &std::path::Path) -> Vec<f64> {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let summary: Value = serde_json::from_str(&text).expect("summary.json is JSON");
    let l = &summary["world"]["layers"];
    let (count, base, spacing) = (
        l["count"].as_u64().expect("world.layers.count"),
        l["base_altitude_m"]
            .as_f64()
            .expect("world.layers.base_altitude_m"),
        l["spacing_m"].as_f64().expect("world.layers.spacing_m"),
    );
    (0..count).map(|k| base + k as f64 * spacing).collect()
}

/// The altitude at (fractional) layer `k`.
fn altitude(alts: &[f64], k: f64) -> f64 {
    let spacing = alts.get(1).map_or(0.0, |a| a - alts[0]);
    alts[0] + (k - 1.0) * spacing
}

/// The altitude the side view's legs give at `t` (straight between its points), if it spans `t`.
fn profile_altitude(legs: &[Vec<(i64, f64)>], t: i64) -> Option<f64> {
    legs.iter().find_map(|leg| {
        leg.windows(2).find_map(|w| {
            let ((ta, ma), (tb, mb)) = (w[0], w[1]);
            (ta <= t && t <= tb).then(|| {
                if tb == ta {
                    mb
                } else {
                    ma + (mb - ma) * (t - ta) as f64 / (tb - ta) as f64
                }
            })
        })
    })
}

#[test]
fn one_layer_alone_draws_its_flights_and_the_side_view_gives_each_altitude() {
    let Some(browser) = browser_or_skip("view_layers") else {
        return;
    };
    let out = crate::support::scratch_dir("view_layers");
    std::fs::create_dir_all(&out).expect("the scratch folder");
    // The CBD square from the ground to 75 m, 10:00–12:00: layers 1 (60 m) and 2 (69.1 m).
    let zones = out.join("low-cbd.json");
    std::fs::write(
        &zones,
        r#"{"type": "FeatureCollection", "features": [{"type": "Feature",
  "properties": {"identifier": "LOW-CBD", "name": "Downtown, low", "type": "PROHIBITED",
    "limitedApplicability": [{"schedule": [
      {"day": ["ANY"], "startTime": "10:00:00+08:00", "endTime": "12:00:00+08:00"}]}]},
  "geometry": {"type": "Polygon", "coordinates": [[[103.84, 1.27], [103.87, 1.27],
    [103.87, 1.30], [103.84, 1.30], [103.84, 1.27]]],
    "layer": {"upper": 75, "upperReference": "AGL", "uom": "m"}}}]}"#,
    )
    .expect("the zones file");
    let zones = zones.to_str().expect("a UTF-8 path");
    let args = [
        "--layers",
        "4",
        "--heading-rule",
        "sectors",
        "--count",
        "2000",
        "--zones",
        zones,
    ];
    let (plans, view) = simulate_with(&out.join("run"), &args);
    let alts = altitudes(&out.join("run"));
    let page = browser.new_page().expect("a new page");
    open_offline(&page, &view, "");
    assert_eq!(
        eval_i64(&page, "museView.scene.nodes.length"),
        77,
        "the flat stations only"
    );
    let sample = plans
        .iter()
        .find_map(|p| p.takeoff.as_deref())
        .expect("at least one planned flight");

    let t = assert_each_layer_alone(&page, &plans, sample);
    assert_the_low_zone_closes_the_lower_layers(&page, sample);
    assert_the_side_view(&page, &plans, &alts, t);
    assert_no_console_errors(&page);
}

/// At several instants, each layer shown alone draws exactly the flights at it or crossing to
/// or from it, by their stays; returns the busiest instant.
fn assert_each_layer_alone(page: &Page<'_>, plans: &[Plan], sample: &str) -> i64 {
    // Each layer alone, at several instants: exactly the flights at it or crossing to or from it.
    let mut layers_seen = BTreeSet::new();
    let mut busiest: Option<(i64, usize)> = None;
    for hh_mm in ["09:00", "10:30", "12:30", "15:00", "18:00"] {
        let t = local(sample, hh_mm);
        let all = eval_count(page, &format!("museView.setTime({t})"));
        let airborne = plans.iter().filter(|p| p.airborne_at(t)).count();
        assert_eq!(
            all as usize, airborne,
            "{hh_mm}: every layer, every flight in the air"
        );
        for k in 1..=4_u32 {
            let expected: BTreeSet<&str> = plans
                .iter()
                .filter(|p| p.airborne_at(t))
                .filter(|p| {
                    p.layer_at(t)
                        .is_some_and(|l| (l - f64::from(k)).abs() < 1.0)
                })
                .map(|p| p.request.as_str())
                .collect();
            let count = eval_count(page, &format!("museView.setLayer({k})"));
            let drawn: BTreeSet<String> = page
                .eval("museView.flightsDrawn().map(f => f.id)")
                .expect("flightsDrawn")
                .as_array()
                .expect("an array")
                .iter()
                .map(|v| v.as_str().expect("an id").to_owned())
                .collect();
            let drawn: BTreeSet<&str> = drawn.iter().map(String::as_str).collect();
            assert_eq!(drawn, expected, "{hh_mm}, layer {k} alone");
            assert_eq!(
                count as usize,
                expected.len(),
                "{hh_mm}, layer {k}: the count"
            );
            assert_eq!(
                eval_string(page, "document.getElementById('airborne').textContent"),
                format!("{all} in the air, {count} at layer {k} in view"),
                "{hh_mm}, layer {k}: the count shown"
            );
            if !expected.is_empty() {
                layers_seen.insert(k);
            }
            println!("{hh_mm} layer {k}: {count} of {all} airborne drawn");
        }
        assert_eq!(
            eval_count(page, "museView.setLayer(null)"),
            all,
            "{hh_mm}: every layer again"
        );
        if busiest.is_none_or(|(_, n)| all as usize > n) {
            busiest = Some((t, all as usize));
        }
    }
    assert!(
        layers_seen.len() >= 3,
        "flights at three layers or more at the instants checked: {layers_seen:?}"
    );

    busiest.expect("an instant checked").0
}

/// The low zone at 10:30: it closes corridors at layers 1 and 2, each flown there, and nothing
/// at layers 3 and 4.
fn assert_the_low_zone_closes_the_lower_layers(page: &Page<'_>, sample: &str) {
    eval_count(
        page,
        &format!("museView.setTime({})", local(sample, "10:30")),
    );
    for k in 1..=4_u32 {
        eval_count(page, &format!("museView.setLayer({k})"));
        let closed = page
            .eval("museView.closedCorridors()")
            .expect("closedCorridors");
        let closed: Vec<u64> = closed
            .as_array()
            .expect("an array")
            .iter()
            .map(|v| v.as_u64().expect("an index"))
            .collect();
        let flown_there = eval_count(
            page,
            &format!(
                "museView.closedCorridors().filter(e => museView.scene.layers.ways[{}][e] !== 0).length",
                k - 1
            ),
        );
        println!("10:30 layer {k}: corridors closed {closed:?}");
        if k <= 2 {
            assert!(
                !closed.is_empty(),
                "layer {k}: the low zone closes corridors"
            );
            assert_eq!(
                flown_there as usize,
                closed.len(),
                "layer {k}: only corridors flown there"
            );
        } else {
            assert!(closed.is_empty(), "layer {k} is above the zone: {closed:?}");
        }
    }
    eval_count(page, "museView.setLayer(null)");
}

/// The side view of a flight in the air at `t` that climbs above layer 1: its altitude as its
/// stays give it every 250 ms, the layer column of its table, and a click moving the clock.
fn assert_the_side_view(page: &Page<'_>, plans: &[Plan], alts: &[f64], t: i64) {
    // The side view of a flight that climbs above layer 1, while in the air.
    let flight: &Plan = plans
        .iter()
        .filter(|p| p.airborne_at(t))
        .max_by_key(|p| {
            let top = p.stays.iter().map(|s| s.1).max();
            let span = p.airborne.last().map_or(0, |l| l.1) - p.airborne.first().map_or(0, |l| l.0);
            (top, span)
        })
        .expect("a flight in the air at the busiest instant");
    let top = flight.stays.iter().map(|s| s.1).max().expect("stays");
    assert!(top >= 2, "{} climbs to layer {top}", flight.request);
    let id = serde_json::to_string(&flight.request).expect("a JSON string");
    page.eval(&format!("museView.select({id})"))
        .expect("select");
    eval_count(page, &format!("museView.setTime({t})"));
    let profile = page
        .eval("(() => { const p = museView.profile(); return p && { legs: p.legs, layers: p.layers }; })()")
        .expect("the side view");
    assert!(!profile.is_null(), "a side view for {}", flight.request);
    let legs: Vec<Vec<(i64, f64)>> = profile["legs"]
        .as_array()
        .expect("legs")
        .iter()
        .map(|leg| {
            leg.as_array()
                .expect("a leg")
                .iter()
                .map(|p| {
                    (
                        p[0].as_i64().expect("a time"),
                        p[1].as_f64().expect("metres"),
                    )
                })
                .collect()
        })
        .collect();
    assert_eq!(legs.len(), flight.airborne.len(), "one line per leg");
    let (from, to) = (
        flight.airborne[0].0,
        flight.airborne.last().expect("a leg").1,
    );
    let mut checked = 0;
    for t in (from..to).step_by(250) {
        if !flight.airborne_at(t) {
            continue;
        }
        let want = altitude(alts, flight.layer_at(t).expect("airborne"));
        let got = profile_altitude(&legs, t)
            .unwrap_or_else(|| panic!("the side view of {} misses {t}", flight.request));
        assert!(
            (got - want).abs() < 1e-6,
            "{} at {t}: the side view gives {got} m, its stays {want} m",
            flight.request
        );
        checked += 1;
    }
    println!(
        "{}: the side view agrees with its stays at {checked} instants (every 250 ms in the air), up to layer {top}",
        flight.request
    );
    let details = eval_string(page, "document.getElementById('details').textContent");
    assert!(
        details.contains("layer") && details.contains('→'),
        "the plan's table gives each stay's layer and the climbs: {details}"
    );

    // A click on the side view moves the clock to the instant under it (within a pixel).
    let target = from + (to - from) / 3;
    page.eval("document.getElementById('profile').scrollIntoView({block: 'center'})")
        .expect("the side view scrolled into view");
    page.screenshot(&screenshots().join("view-layers.png"))
        .expect("the screenshot");
    let at = page
        .eval(&format!(
            "(() => {{ const p = museView.profile(); return [p.xAt({target}), p.box[1] + p.box[3] / 2, p.box[2]]; }})()"
        ))
        .expect("where the instant is");
    let (x, y, width) = (
        at[0].as_f64().expect("x"),
        at[1].as_f64().expect("y"),
        at[2].as_f64().expect("width"),
    );
    page.click(x, y).expect("a click on the side view");
    let moved = eval_i64(page, "museView.time()");
    let per_px = (to - from) as f64 / (width - 66.0);
    assert!(
        ((moved - target) as f64).abs() <= per_px,
        "the click at {target} moved the clock to {moved} ({per_px:.0} ms per px)"
    );
    assert_eq!(
        page.eval("museView.selected()").expect("selected"),
        Value::String(flight.request.clone()),
        "the selection stays"
    );
}
