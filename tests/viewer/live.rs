//! The live viewer of `muse serve`, driven in headless Chromium against the real binary on an
//! ephemeral loopback port: the page at `/` loads with no console error, follows the events
//! stream, and a flight planned over plain HTTP (as with `curl`) appears on it — in the list
//! of events, and drawn on the map while it is airborne, where a click shows its plan; a zone
//! announced live appears with its windows dated and draws, while active, exactly the
//! corridors the planner closes for it; a request rejected over HTTP is found by its id with
//! its reason. With tokens, an operator's page shows its own flights only and the
//! authority's every flight. Skipped with a notice when Chromium is not installed, unless
//! `CI` is set.

use std::collections::BTreeSet;
use std::io::{Read as _, Write as _};
use std::net::TcpStream;
use std::path::Path;
use std::time::Duration;

use serde_json::Value;

use crate::support::cdp::{Page, browser_or_skip};

/// The service's clock starts here (and runs at real speed).
const CLOCK: &str = "2026-01-05T09:00:00+08:00";

/// `POST path` with a JSON body over a fresh HTTP/1.1 connection, as `curl` would; returns the
/// status and the body as JSON.
fn post(base: &str, path: &str, token: Option<&str>, body: &str) -> (u16, Value) {
    let addr = base.strip_prefix("http://").expect("an http:// base");
    let mut s = TcpStream::connect(addr).expect("the service accepts connections");
    s.set_read_timeout(Some(Duration::from_secs(30)))
        .expect("timeout");
    let auth = token.map_or(String::new(), |t| format!("Authorization: Bearer {t}\r\n"));
    write!(
        s,
        "POST {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n{auth}Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .expect("request sent");
    let mut response = String::new();
    s.read_to_string(&mut response).expect("response read");
    let (head, body) = response.split_once("\r\n\r\n").expect("HTTP response");
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .expect("a status code");
    // Small bodies may come chunked: take the JSON object inside.
    let json = &body[body.find('{').expect("a JSON body")..=body.rfind('}').expect("a JSON body")];
    (status, serde_json::from_str(json).expect("JSON body"))
}

/// Plans flight `id` from `origin` to `destination`, departing `after_s` seconds after the
/// service's clock started; returns the plan.
fn plan(base: &str, token: Option<&str>, id: &str, od: (&str, &str), after_s: i64) -> Value {
    let start = CLOCK.parse::<jiff::Timestamp>().expect("RFC 3339");
    let departure = start + jiff::SignedDuration::from_secs(after_s);
    let body = format!(
        r#"{{"id": "{id}", "origin": "{}", "destination": "{}", "departure": "{departure}"}}"#,
        od.0, od.1
    );
    let (status, plan) = post(base, "/v1/flights", token, &body);
    assert_eq!(status, 201, "{id} is planned: {plan}");
    plan
}

fn epoch_ms(v: &Value) -> i64 {
    v.as_str()
        .expect("an RFC 3339 string")
        .parse::<jiff::Timestamp>()
        .expect("RFC 3339")
        .as_millisecond()
}

/// Opens the live page at `url` and waits until it is connected to the events stream.
fn open_live(page: &Page<'_>, url: &str) {
    page.goto(url).expect("the live page loads");
    page.wait_for(
        "window.museView && museView.ready && museView.live && museView.connected === true",
        Duration::from_secs(20),
    )
    .expect("the live page connects to the events stream");
}

/// Waits until flight `id` is on the page, and checks it is listed among the latest events.
fn wait_for_flight(page: &Page<'_>, id: &str) {
    page.wait_for(
        &format!("museView.scene.byId.has({id:?})"),
        Duration::from_secs(20),
    )
    .unwrap_or_else(|e| panic!("{id} never appeared on the live page: {e}"));
    let events = page
        .eval("document.getElementById('events').textContent")
        .expect("events list");
    assert!(
        events.as_str().is_some_and(|t| t.contains(id)),
        "{id} not in the events list: {events}"
    );
}

/// Stops following the clock, sets it inside `plan`'s flight and clicks the drone drawn for
/// it; returns the number of drones drawn then.
fn click_flight(page: &Page<'_>, plan: &Value) -> i64 {
    let id = plan["request"].as_str().expect("request id");
    let t = epoch_ms(&plan["takeoff"]) + 1_000;
    page.eval("museView.follow(false)").expect("follow off");
    let drawn = page
        .eval(&format!("museView.setTime({t})"))
        .expect("setTime")
        .as_i64()
        .expect("a count");
    let at = page.eval("museView.flightsDrawn()").expect("flightsDrawn");
    let me = at
        .as_array()
        .expect("an array")
        .iter()
        .find(|d| d["id"] == id)
        .unwrap_or_else(|| panic!("{id} is not drawn at its take-off + 1 s: {at}"));
    page.click(me["x"].as_f64().expect("x"), me["y"].as_f64().expect("y"))
        .expect("click");
    let selected = page.eval("museView.selected()").expect("selected");
    assert_eq!(selected, id, "the click selects {id}");
    let details = page
        .eval("document.getElementById('details').textContent")
        .expect("details");
    let details = details.as_str().expect("text");
    let hhmmss = |v: &Value| v.as_str().expect("a time")[11..19].to_owned();
    for want in [
        id.to_owned(),
        hhmmss(&plan["takeoff"]),
        hhmmss(&plan["landing"]),
    ] {
        assert!(
            details.contains(&want),
            "the plan shown lacks {want}: {details}"
        );
    }
    drawn
}

/// The stadium zone file as a body for `POST /v1/zones` (the service sets the announcement
/// instant itself).
fn stadium_announcement() -> String {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/singapore-77/stadium_zone.geojson");
    let mut zone: Value =
        serde_json::from_str(&std::fs::read_to_string(file).expect("the stadium zone file"))
            .expect("GeoJSON");
    for f in zone["features"].as_array_mut().expect("features") {
        f["properties"]
            .as_object_mut()
            .expect("properties")
            .remove("announced");
    }
    zone.to_string()
}

/// Announces the stadium zone (15:00–18:00 on the service's day) with `POST /v1/zones` and
/// waits for the page to draw it: not active before 15:00, active at 15:30.
fn announce_zone_and_see_it(page: &Page<'_>, base: &str) {
    let (status, answer) = post(base, "/v1/zones", None, &stadium_announcement());
    assert_eq!(status, 201, "the zone is announced: {answer}");
    let id = "SG-NATIONAL-STADIUM-EVENT";
    page.wait_for(
        &format!("museView.scene.zones.some((z) => z.id === {id:?})"),
        Duration::from_secs(25),
    )
    .expect("the announced zone reaches the live page");
    let state = |hh_mm: &str| {
        let t = format!("2026-01-05T{hh_mm}:00+08:00")
            .parse::<jiff::Timestamp>()
            .expect("RFC 3339")
            .as_millisecond();
        page.eval(&format!("museView.setTime({t}), museView.zoneAt({id:?})"))
            .expect("zone state")
    };
    assert_eq!(state("08:30"), "unannounced", "before its announcement");
    assert_eq!(state("14:30"), "idle", "announced, not active yet");
    assert_eq!(
        closed_corridors(page),
        BTreeSet::new(),
        "nothing closed at 14:30"
    );
    assert_eq!(state("15:30"), "active");
    // The corridors the planner closes for it, worked out here from the zone file.
    let airspace = &muse_scenario::by_name("singapore-77")
        .expect("the default scenario")
        .airspace;
    let zone = muse_scenario::stadium_zone().expect("the stadium zone");
    let (nodes, edges) =
        muse_airspace::closures::closed_elements(airspace, &zone).expect("its closures");
    let expected: BTreeSet<(String, String)> = edges
        .iter()
        .map(|&e| {
            let edge = airspace.edge(e);
            ordered(&airspace.node(edge.from).id, &airspace.node(edge.to).id)
        })
        .collect();
    assert!(!expected.is_empty(), "the stadium zone closes corridors");
    page.wait_for(
        &format!("museView.closedCorridors().length === {}", expected.len()),
        Duration::from_secs(10),
    )
    .expect("the announced zone's corridors are drawn closed");
    assert_eq!(closed_corridors(page), expected, "drawn closed at 15:30");
    let closed_nodes = page
        .eval("museView.closedNodes().map((i) => museView.scene.nodes[i].id)")
        .expect("closed nodes");
    let expected_nodes: Vec<&str> = nodes
        .iter()
        .map(|&n| airspace.node(n).id.as_str())
        .collect();
    assert_eq!(
        closed_nodes,
        serde_json::json!(expected_nodes),
        "nodes drawn closed"
    );
    // The zones' windows within the day shown, dated: the CBD's of this day only.
    let zones = page
        .eval("document.getElementById('zones').textContent")
        .expect("zones");
    let zones = zones.as_str().expect("text");
    assert!(
        zones.contains("active Mon 5 Jan 10:00–12:00"),
        "the CBD's window of this day, dated: {zones}"
    );
    assert_eq!(
        zones.matches("Jan 10:00").count(),
        1,
        "one CBD window: {zones}"
    );
    assert!(
        zones.contains("active Mon 5 Jan 15:00–18:00; announced Mon 5 Jan 09:0"),
        "the stadium's window, dated, and its announcement: {zones}"
    );
}

/// `(a, b)` in order.
fn ordered(a: &str, b: &str) -> (String, String) {
    if a < b {
        (a.to_owned(), b.to_owned())
    } else {
        (b.to_owned(), a.to_owned())
    }
}

/// The corridors the page draws closed, by their end nodes' ids.
fn closed_corridors(page: &Page<'_>) -> BTreeSet<(String, String)> {
    let pairs = page
        .eval(
            "museView.closedCorridors().map((i) => museView.scene.edges[i]\
             .map((n) => museView.scene.nodes[n].id))",
        )
        .expect("closed corridors");
    pairs
        .as_array()
        .expect("an array")
        .iter()
        .map(|p| ordered(p[0].as_str().expect("id"), p[1].as_str().expect("id")))
        .collect()
}

/// A request the service rejects (out of range), posted over HTTP, is found on the page by
/// its id typed in capitals, with its reason (it makes no event: the page asks the service).
fn find_a_rejected_request(page: &Page<'_>, base: &str) {
    let body = r#"{"id": "far1", "origin": "S001", "destination": "S077", "departure": "2026-01-05T10:00:00+08:00"}"#;
    let (status, answer) = post(base, "/v1/flights", None, body);
    assert_eq!(
        (status, answer["reason"].as_str()),
        (200, Some("out_of_range")),
        "{answer}"
    );
    page.eval(
        "(() => { const f = document.getElementById('find'); f.value = 'FAR1'; \
         f.closest('form').requestSubmit(); })()",
    )
    .expect("a search");
    page.wait_for("museView.selected() === 'far1'", Duration::from_secs(10))
        .expect("the rejected request is found");
    let details = page
        .eval("document.getElementById('details').textContent")
        .expect("details");
    let details = details.as_str().expect("text");
    for want in ["far1", "rejected", "out_of_range", "battery"] {
        assert!(details.contains(want), "#details lacks {want}: {details}");
    }
}

fn no_console_errors(page: &Page<'_>) {
    let errors = page.console_errors().expect("console");
    assert!(errors.is_empty(), "console errors: {errors:?}");
}

#[test]
fn live_page_shows_a_flight_planned_over_http() {
    let Some(browser) = browser_or_skip("live_page_shows_a_flight_planned_over_http") else {
        return;
    };
    let data = crate::support::scratch_dir("view-live-open");
    let server = crate::support::start(&data, &["--clock", CLOCK]);
    let page = browser.new_page().expect("a page");
    open_live(&page, &format!("{}/", server.base));
    let p = plan(&server.base, None, "live1", ("S012", "S040"), 60);
    wait_for_flight(&page, "live1");
    assert_eq!(click_flight(&page, &p), 1, "only live1 is in the air then");
    announce_zone_and_see_it(&page, &server.base);
    find_a_rejected_request(&page, &server.base);
    // A flight across the stadium zone while it is active goes round it.
    let p2 = plan(
        &server.base,
        None,
        "live2",
        ("S070", "S071"),
        6 * 3600 + 20 * 60,
    );
    wait_for_flight(&page, "live2");
    click_flight(&page, &p2);
    no_console_errors(&page);
    let shots = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/screenshots");
    page.screenshot(&shots.join("view-live.png"))
        .expect("screenshot");
    println!(
        "live page: live1 planned over HTTP appeared, drawn and selectable; screenshot in {}",
        shots.display()
    );
    server.kill();
}

#[test]
fn live_page_shows_an_operator_its_own_flights_and_the_authority_all() {
    let Some(browser) = browser_or_skip("live_page_shows_an_operator_its_own_flights") else {
        return;
    };
    let data = crate::support::scratch_dir("view-live-tokens");
    std::fs::create_dir_all(&data).expect("data dir");
    let tokens = data.with_extension("toml");
    std::fs::write(
        &tokens,
        "[[tokens]]\ntoken = \"alpha-secret-0001\"\noperator = \"alpha\"\nrole = \"operator\"\n\n\
         [[tokens]]\ntoken = \"bravo-secret-0002\"\noperator = \"bravo\"\nrole = \"operator\"\n\n\
         [[tokens]]\ntoken = \"authority-secret-0003\"\noperator = \"caas\"\nrole = \"authority\"\n",
    )
    .expect("tokens file");
    let server = crate::support::start(
        &data,
        &[
            "--clock",
            CLOCK,
            "--tokens",
            tokens.to_str().expect("UTF-8 path"),
        ],
    );
    let alpha = browser.new_page().expect("a page");
    open_live(&alpha, &format!("{}/?token=alpha-secret-0001", server.base));
    let authority = browser.new_page().expect("a page");
    open_live(
        &authority,
        &format!("{}/?token=authority-secret-0003", server.base),
    );

    plan(
        &server.base,
        Some("bravo-secret-0002"),
        "b1",
        ("S012", "S040"),
        60,
    );
    plan(
        &server.base,
        Some("alpha-secret-0001"),
        "a1",
        ("S001", "S002"),
        60,
    );
    wait_for_flight(&alpha, "a1");
    wait_for_flight(&authority, "a1");
    wait_for_flight(&authority, "b1");
    let alpha_has_b1 = alpha.eval("museView.scene.byId.has('b1')").expect("eval");
    assert_eq!(
        alpha_has_b1, false,
        "an operator never sees another's flight"
    );
    let count = |p: &Page<'_>| p.eval("museView.scene.flights.length").expect("eval");
    assert_eq!(count(&alpha), 1);
    assert_eq!(count(&authority), 2);

    // Without a token the page says how to pass one.
    let anonymous = browser.new_page().expect("a page");
    anonymous
        .goto(&format!("{}/", server.base))
        .expect("the page loads");
    anonymous
        .wait_for(
            "document.getElementById('status').textContent.includes('token')",
            Duration::from_secs(20),
        )
        .expect("the page asks for a token");
    for p in [&alpha, &authority] {
        no_console_errors(p);
    }
    server.kill();
}

/// `muse serve --layers 4 --heading-rule sectors`: the live page draws a flight planned over
/// HTTP from above, at each of its stays at the layer the service's answer gives, and reads
/// what the CBD zone closes per layer from `GET /v1/closures` (flat ids and the layers).
#[test]
fn live_page_follows_a_layered_service() {
    let Some(browser) = browser_or_skip("live_page_follows_a_layered_service") else {
        return;
    };
    let data = crate::support::scratch_dir("view-live-layers");
    let layered = [
        "--clock",
        CLOCK,
        "--layers",
        "4",
        "--heading-rule",
        "sectors",
    ];
    let server = crate::support::start(&data, &layered);
    let page = browser.new_page().expect("a page");
    open_live(&page, &format!("{}/", server.base));
    let p = plan(&server.base, None, "up1", ("S012", "S040"), 60);
    wait_for_flight(&page, "up1");
    page.eval("museView.follow(false)").expect("follow off");
    let stays = p["path"].as_array().expect("the plan's stays");
    let top = stays
        .iter()
        .map(|s| s["layer"].as_u64().expect("a layered stay gives its layer"))
        .max()
        .expect("stays");
    for s in stays {
        let t = epoch_ms(&s["arrive"]);
        let layer = page
            .eval(&format!("museView.setTime({t}), museView.layerOf('up1')"))
            .expect("layerOf");
        assert_eq!(
            layer.as_f64(),
            s["layer"].as_f64(),
            "up1 at {} on arriving at {}",
            s["arrive"],
            s["node"]
        );
    }
    // What each zone closes per layer, as the planner works it out on the layered airspace:
    // the CBD zone from the page's own scene, the stadium's from `GET /v1/closures` once it is
    // announced.
    let scenario = muse_scenario::by_name("singapore-77").expect("the default scenario");
    let airspace = scenario
        .airspace
        .layered(&muse_model::Layers {
            count: 4,
            heading_rule: muse_model::HeadingRule::Sectors,
            ..muse_model::Layers::default()
        })
        .expect("four layers");
    let stadium = muse_scenario::stadium_zone().expect("the stadium zone");
    let (status, answer) = post(&server.base, "/v1/zones", None, &stadium_announcement());
    assert_eq!(status, 201, "the zone is announced: {answer}");
    page.wait_for(
        &format!(
            "museView.scene.zones.some((z) => z.id === {:?} && z.layers)",
            stadium.id
        ),
        Duration::from_secs(25),
    )
    .expect("the announced zone reaches the page with its layers");
    let cbd = &scenario.zones[0];
    for (zone, hh_mm) in [(cbd, "10:30"), (&stadium, "15:30")] {
        assert_closes_per_layer(&page, &airspace, zone, hh_mm);
    }
    no_console_errors(&page);
    println!(
        "layered live page: up1 climbs to layer {top}, its layer right at each of its {} stays",
        stays.len(),
    );
    server.kill();
}

/// The corridors `zone` closes at each of the four layers of `airspace`, by their flat end
/// nodes' ids, as the planner works them out.
fn closed_per_layer(
    airspace: &muse_model::Airspace,
    zone: &muse_model::Zone,
) -> Vec<BTreeSet<(String, String)>> {
    let (_, edges) =
        muse_airspace::closures::closed_elements(airspace, zone).expect("its closures");
    let id = |n| airspace.flat().node(airspace.flat_node(n)).id.clone();
    (1..=4)
        .map(|k| {
            edges
                .iter()
                .filter(|&&e| {
                    matches!(airspace.edge_kind(e), muse_model::EdgeKind::Corridor { layer, .. } if layer == k)
                })
                .map(|&e| ordered(&id(airspace.edge(e).from), &id(airspace.edge(e).to)))
                .collect()
        })
        .collect()
}

/// At `hh_mm` on the service's day, each layer shown alone draws closed exactly the corridors
/// `zone` closes there, and every layer those it closes at any.
fn assert_closes_per_layer(
    page: &Page<'_>,
    airspace: &muse_model::Airspace,
    zone: &muse_model::Zone,
    hh_mm: &str,
) {
    let t = format!("2026-01-05T{hh_mm}:00+08:00")
        .parse::<jiff::Timestamp>()
        .expect("RFC 3339")
        .as_millisecond();
    page.eval(&format!("museView.setTime({t})"))
        .expect("the time");
    let expected = closed_per_layer(airspace, zone);
    let mut shown = Vec::new();
    for (k, want) in (1..=4).zip(&expected) {
        page.eval(&format!("museView.setLayer({k})"))
            .expect("one layer");
        let closed = closed_corridors(page);
        assert_eq!(&closed, want, "{} at {hh_mm}, layer {k}", zone.id);
        shown.push(closed.len());
    }
    page.eval("museView.setLayer(null)").expect("every layer");
    let any: BTreeSet<_> = expected.iter().flatten().cloned().collect();
    assert!(!any.is_empty(), "{} closes corridors", zone.id);
    assert_eq!(
        closed_corridors(page),
        any,
        "{} at {hh_mm}, every layer",
        zone.id
    );
    println!(
        "{} at {hh_mm}: corridors closed per layer {shown:?}, {} at any",
        zone.id,
        any.len()
    );
}
