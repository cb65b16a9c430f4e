//! A layered day end to end (docs/reference.md#layered-airspace, docs/reference.md): `muse simulate
//! --layers 4 --heading-rule sectors` writes every stay as a flat id and its layer, altitudes in
//! the flights GeoJSON, a `layer` column in `stays.csv` and one map panel per layer; `muse verify`
//! and `muse view` rebuild the layering from the summary (or the options) and check the day; and
//! one layer writes exactly what no `--layers` writes.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::run::{muse, read_json, said, stderr, stdout};

/// `muse simulate --count 300` (the default seed, 1) with `extra` options into a fresh
/// `DIR/NAME`.
fn simulate(name: &str, extra: &[&str]) -> PathBuf {
    let out = crate::support::scratch_dir(&format!("layers_{name}"));
    let mut args = vec!["simulate", "--count", "300", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = muse(&args);
    assert!(o.status.success(), "muse {args:?}: {}", said(&o));
    out
}

/// The lines of a plans file.
fn lines(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// A layered day: 4 layers, one quadrant of headings each.
fn layered_day(name: &str) -> PathBuf {
    simulate(name, &["--layers", "4", "--heading-rule", "sectors"])
}

#[test]
fn a_layered_day_writes_flat_nodes_with_their_layers_and_altitudes() {
    let out = layered_day("outputs");
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["world"]["layers"]["count"], 4, "{summary}");
    let stations: BTreeSet<String> = (1..=77).map(|i| format!("S{i:03}")).collect();
    let mut layers_flown = BTreeSet::new();
    let mut planned = 0;
    for line in lines(&out.join("plans.jsonl")) {
        let Some(path) = line["path"].as_array() else {
            continue;
        };
        planned += 1;
        for stay in path {
            let node = stay["node"].as_str().unwrap();
            assert!(stations.contains(node), "a flat station id: {stay}");
            let layer = stay["layer"].as_u64().expect("every stay gives its layer");
            assert!((1..=4).contains(&layer), "{stay}");
            layers_flown.insert(layer);
        }
        // Take-off and landing at layer 1.
        assert_eq!(path[0]["layer"], 1, "{line}");
        assert_eq!(path[path.len() - 1]["layer"], 1, "{line}");
    }
    assert!(planned > 50, "{planned} flights planned");
    assert_eq!(
        layers_flown,
        (1..=4).collect::<BTreeSet<u64>>(),
        "every layer is flown"
    );

    // The GeoJSON: the altitude of each stay's layer, its layers listed.
    let geo = read_json(&out.join("flights.geojson"));
    let features = geo["features"].as_array().unwrap();
    assert_eq!(features.len(), planned);
    let altitudes = [60.0, 69.144, 78.288, 87.432];
    let mut seen = BTreeSet::new();
    for f in features {
        let layers = f["properties"]["layers"].as_array().expect("`layers`");
        let coords = f["geometry"]["coordinates"].as_array().unwrap();
        assert_eq!(
            layers.len(),
            f["properties"]["nodes"].as_array().unwrap().len()
        );
        for c in coords {
            let c = c.as_array().unwrap();
            assert_eq!(c.len(), 4, "[lon, lat, altitude, t]: {c:?}");
            let alt = c[2].as_f64().unwrap();
            let k = altitudes
                .iter()
                .position(|&a| (a - alt).abs() < 1e-9)
                .unwrap_or_else(|| panic!("altitude {alt} is no layer's"));
            seen.insert(k);
        }
    }
    assert_eq!(seen.len(), 4, "every layer's altitude appears");

    // stays.csv: `layer` after `node`; flights.csv unchanged in shape.
    let stays = std::fs::read_to_string(out.join("stays.csv")).unwrap();
    assert!(
        stays.starts_with(
            "request,leg,stay,node,layer,arrive,arrive_day_s,depart,depart_day_s,hover_s\n"
        ),
        "{}",
        &stays[..200]
    );
    let flights = std::fs::read_to_string(out.join("flights.csv")).unwrap();
    assert!(!flights.contains('@'), "no layered id in flights.csv");

    // map.svg: one panel per layer, the vertical links not drawn as corridors.
    let map = std::fs::read_to_string(out.join("map.svg")).unwrap();
    assert_eq!(map.matches("<svg").count(), 5, "a page and four panels");
    for title in [
        "Layer 1 · 60 m",
        "Layer 2 · 69.144 m",
        "Layer 3 · 78.288 m",
        "Layer 4 · 87.432 m",
    ] {
        assert!(map.contains(title), "{title}");
    }
    assert!(map.contains("flights per corridor at each of 4 layers"));
}

#[test]
fn a_layered_day_verifies_with_its_summary_or_its_options() {
    let out = layered_day("verify");
    let plans = out.join("plans.jsonl");
    let plans_arg = plans.to_str().unwrap();
    let o = muse(&["verify", "--plans", plans_arg]);
    assert_eq!(o.status.code(), Some(0), "{}", said(&o));
    assert!(stdout(&o).starts_with("OK: 300 lines read"), "{}", said(&o));
    assert!(
        stdout(&o).contains("4 layers, heading rule sectors"),
        "{}",
        said(&o)
    );
    assert!(
        stderr(&o)
            .contains("4 layers from 60 m, 9.144 m apart, climbing at 5 m/s, heading rule sectors"),
        "{}",
        said(&o)
    );

    // An option given overrides the summary, and says so; the plans do not fit two layers.
    let o = muse(&["verify", "--plans", plans_arg, "--layers", "2"]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    let err = stderr(&o);
    assert!(err.contains("--layers 2 given: overrides"), "{err}");
    assert!(
        err.contains("field `path[") && err.contains("is out of range: give 1 to 2"),
        "{err}"
    );

    // Without the summary: flat by default, refused; the options rebuild the layering.
    let alone = crate::support::scratch_dir("layers_verify_alone");
    std::fs::create_dir_all(&alone).unwrap();
    let copy = alone.join("plans.jsonl");
    std::fs::copy(&plans, &copy).unwrap();
    let copy_arg = copy.to_str().unwrap();
    let o = muse(&["verify", "--plans", copy_arg]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains("line 1: field `path[0].layer`: layer 1, but the airspace is flat"),
        "{}",
        said(&o)
    );
    let o = muse(&[
        "verify",
        "--plans",
        copy_arg,
        "--layers",
        "4",
        "--heading-rule",
        "sectors",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", said(&o));

    // The same stays without the heading rule verify too (every direction at every layer);
    // flown all at layer 1, a climb becomes a stay repeated and corridors go against their
    // layer's heading: violations.
    let o = muse(&["verify", "--plans", copy_arg, "--layers", "4"]);
    assert_eq!(o.status.code(), Some(0), "{}", said(&o));
    let mut flattened = String::new();
    for mut line in lines(&copy) {
        if let Some(path) = line["path"].as_array_mut() {
            for stay in path {
                stay["layer"] = 1.into();
            }
        }
        flattened.push_str(&line.to_string());
        flattened.push('\n');
    }
    std::fs::write(&copy, flattened).unwrap();
    let o = muse(&[
        "verify",
        "--plans",
        copy_arg,
        "--layers",
        "4",
        "--heading-rule",
        "sectors",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", said(&o));
    assert!(stdout(&o).starts_with("FAILED: "), "{}", said(&o));

    // muse view draws it with the summary's layering.
    let page = out.join("again.html");
    let o = muse(&[
        "view",
        "--plans",
        plans_arg,
        "--out",
        page.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", said(&o));
    assert!(
        stdout(&o).contains("flights of 300 requests"),
        "{}",
        said(&o)
    );
}

#[test]
fn one_layer_writes_what_no_layers_writes() {
    let plain = simulate("plain", &[]);
    let one = simulate("one", &["--layers", "1"]);
    for file in [
        "plans.jsonl",
        "flights.geojson",
        "stays.csv",
        "flights.csv",
        "requests.csv",
        "map.svg",
    ] {
        let (a, b) = (
            std::fs::read(plain.join(file)).unwrap(),
            std::fs::read(one.join(file)).unwrap(),
        );
        assert!(a == b, "{file} differs between no --layers and --layers 1");
    }
    let summary = read_json(&one.join("summary.json"));
    assert!(summary["world"].get("layers").is_none(), "{summary}");
    let plans = std::fs::read_to_string(one.join("plans.jsonl")).unwrap();
    assert!(!plans.contains("\"layer\""));
}
