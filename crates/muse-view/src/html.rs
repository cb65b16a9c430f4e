//! The page: the template of `web/index.html` with the style, the script and the scene
//! inlined, so that the file opens with no network at all.

use crate::Scene;

const TEMPLATE: &str = include_str!("../web/index.html");
const STYLE: &str = include_str!("../web/style.css");
/// Decoding and querying a scene (no DOM; `web/test` runs it under node).
const MODEL: &str = include_str!("../web/src/model.js");
/// Decoding the live feed (no DOM either).
const FEED: &str = include_str!("../web/src/feed.js");
/// The map's colours and the load key's values (no DOM either).
const PALETTE: &str = include_str!("../web/src/palette.js");
/// The page's core: state, view, clock, selection, address.
const VIEWER: &str = include_str!("../web/src/viewer.js");
/// Drawing the map.
const DRAW: &str = include_str!("../web/src/draw.js");
/// The side view of a layered airspace: the selected flight's altitude over time.
const PROFILE: &str = include_str!("../web/src/profile.js");
/// The side panel: the day, the zones, the search, the flight.
const PANELS: &str = include_str!("../web/src/panels.js");
/// Mouse, touch, wheel and keys.
const INPUT: &str = include_str!("../web/src/input.js");
/// `window.museView` and the start.
const START: &str = include_str!("../web/src/start.js");
/// The live feed (`muse serve`).
const LIVE: &str = include_str!("../web/src/live.js");

/// The self-contained page of `scene`: a day to play.
///
/// ```
/// use muse_model::{Airspace, Instant, UtcOffset};
/// use muse_view::{SceneInput, page, scene};
/// let airspace = Airspace::line(&[1_000.0]);
/// let s = scene(&SceneInput::new(&airspace, UtcOffset(0), (Instant(0), Instant(1)))).unwrap();
/// let html = page(&s);
/// assert!(!html.contains("<script src") && !html.contains("http://") && !html.contains("https://"));
/// ```
pub fn page(scene: &Scene) -> String {
    render(scene)
}

/// The live page of `muse serve`: the map layers of `scene` (its flights are ignored); the
/// page fetches flights from the service's API and follows its events stream.
pub fn live_page(scene: &Scene) -> String {
    let live = Scene {
        flights: Vec::new(),
        unflown: Vec::new(),
        reasons: Vec::new(),
        live: true,
        ..scene.clone()
    };
    render(&live)
}

fn render(scene: &Scene) -> String {
    // Serializing plain structs of numbers and strings cannot fail; `<` is escaped so that
    // no string in the data can close the script element.
    let json = serde_json::to_string(scene)
        .expect("a scene always serializes")
        .replace('<', "\\u003c");
    let script = format!(
        "(() => {{\n'use strict';\n{}\n{}\n{}\n{VIEWER}\n{DRAW}\n{PROFILE}\n{PANELS}\n{INPUT}\n{START}\n{LIVE}\n}})();\n",
        plain_script(MODEL),
        plain_script(FEED),
        plain_script(PALETTE)
    );
    let mut out = String::with_capacity(TEMPLATE.len() + STYLE.len() + script.len() + json.len());
    let mut rest = TEMPLATE;
    for (marker, text) in [
        ("/*STYLE*/", STYLE),
        ("/*SCENE*/", json.as_str()),
        ("/*SCRIPT*/", script.as_str()),
    ] {
        let (head, tail) = rest
            .split_once(marker)
            .expect("web/index.html holds each marker once, in this order");
        out.push_str(head);
        out.push_str(text);
        rest = tail;
    }
    out.push_str(rest);
    out
}

/// A module (`model.js`, `feed.js`, `palette.js`) as plain script: its `import` lines and
/// `export` keywords (at the start of a line) dropped, since the page inlines every file into
/// one script, one scope.
fn plain_script(module: &str) -> String {
    module
        .lines()
        .filter(|l| !l.starts_with("import "))
        .map(|l| l.strip_prefix("export ").unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markers_are_filled_and_data_cannot_close_the_script() {
        let airspace = muse_model::Airspace::line(&[1_000.0]);
        let mut input = crate::SceneInput::new(
            &airspace,
            muse_model::UtcOffset(0),
            (muse_model::Instant(0), muse_model::Instant(1)),
        );
        input.title = "</script><b>".into();
        let html = page(&crate::scene(&input).unwrap());
        for marker in ["/*STYLE*/", "/*SCENE*/", "/*SCRIPT*/"] {
            assert!(!html.contains(marker), "{marker} left");
        }
        assert!(!html.contains("</script><b>"));
        assert!(html.contains("\\u003c/script>\\u003cb>"));
        assert!(!html.contains("\nexport "), "exports dropped");
        assert!(!html.contains("\nimport "), "imports dropped");
        assert_eq!(
            html.matches("<script").count(),
            2,
            "the scene and the script"
        );
    }

    #[test]
    fn the_live_page_has_no_flights_and_says_it_is_live() {
        let airspace = muse_model::Airspace::line(&[1_000.0]);
        let input = crate::SceneInput::new(
            &airspace,
            muse_model::UtcOffset(0),
            (muse_model::Instant(0), muse_model::Instant(1)),
        );
        let html = live_page(&crate::scene(&input).unwrap());
        assert!(html.contains("\"live\":true") && html.contains("\"flights\":[]"));
    }
}
