//! `muse airspace build --pads` (docs/reference.md#airspace-from-pads): the airspace of any set of
//! pads. Built from all 1,115 Singapore car parks in SVY21 it is the built-in `singapore-all`, byte
//! for byte; on a few pads elsewhere (near Vienna, 48.2° N, 16.4° E) `muse simulate --airspace`
//! plans and verifies on it; exclusions and a maximum corridor length drop corridors; every bad
//! pads or exclusions file, or option, is refused with a clear message and no output.

use std::fmt::Write as _;
use std::path::Path;

use crate::run::{muse, said, stderr};
use crate::support::scratch_dir;

/// Seven made-up test positions near Vienna (not real pads).
pub(crate) const VIENNA: &str = "id,lon,lat,name
V1,16.3700,48.2080,test point 1
V2,16.3900,48.2150,test point 2
V3,16.4100,48.2000,test point 3
V4,16.3850,48.1900,test point 4
V5,16.3550,48.1950,test point 5
V6,16.4000,48.2250,test point 6
V7,16.3450,48.2150,test point 7
";

pub(crate) fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// CSV-quotes `s` when it needs it.
fn cell(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// `muse airspace build --pads PADS --out OUT` with the options `extra`.
fn build(pads: &str, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "airspace",
        "build",
        "--pads",
        pads,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    muse(&args)
}

#[test]
fn all_singapore_car_parks_in_svy21_are_the_built_in_singapore_all() {
    let dir = scratch_dir("pads-singapore-all");
    std::fs::create_dir_all(&dir).unwrap();
    // The pads: every multi-storey car park, at its position as the scenario rounds it.
    let mut csv = String::from("id,lon,lat,name\n");
    for n in muse_scenario::all_stations().unwrap().nodes {
        writeln!(
            csv,
            "{},{},{},{}",
            n.id,
            n.pos.lon,
            n.pos.lat,
            cell(&n.name)
        )
        .unwrap();
    }
    let pads = write(&dir, "car-parks.csv", &csv);
    let built = dir.join("built.geojson");
    let o = build(&pads, &built, &["--crs", "EPSG:3414"]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).contains("built 1115 pads into 3302 corridors in EPSG:3414"),
        "{}",
        said(&o)
    );
    let exported = dir.join("exported.geojson");
    let o = muse(&[
        "airspace",
        "export",
        "--scenario",
        "singapore-all",
        "--out",
        exported.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let (a, b) = (
        std::fs::read(&built).unwrap(),
        std::fs::read(&exported).unwrap(),
    );
    assert!(
        a == b,
        "the built file differs from the built-in singapore-all"
    );
    // The default plane, the UTM zone of Singapore (48 N), gives the same corridors here.
    let utm = dir.join("utm.geojson");
    let o = build(&pads, &utm, &[]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(std::fs::read(&utm).unwrap() == a, "UTM 48N and SVY21 agree");
}

#[test]
fn a_few_pads_near_vienna_build_plan_and_verify() {
    let dir = scratch_dir("pads-vienna");
    std::fs::create_dir_all(&dir).unwrap();
    let pads = write(&dir, "pads.csv", VIENNA);
    let air_path = dir.join("air.geojson");
    let air = air_path.to_str().unwrap();
    let o = build(&pads, &air_path, &[]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).contains("built 7 pads into 13 corridors in utm"),
        "{}",
        said(&o)
    );
    // The same pads, the same file, byte for byte; GeoJSON points give it too.
    let again = dir.join("again.geojson");
    let o = build(&pads, &again, &[]);
    assert!(o.status.success(), "{}", said(&o));
    assert_eq!(std::fs::read(air).unwrap(), std::fs::read(&again).unwrap());
    let mut points = String::from(r#"{"type": "FeatureCollection", "features": ["#);
    for (i, line) in VIENNA.lines().skip(1).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        write!(
            points,
            r#"{}{{"type": "Feature", "properties": {{"id": "{}", "name": "{}"}}, "geometry": {{"type": "Point", "coordinates": [{}, {}]}}}}"#,
            if i == 0 { "" } else { "," },
            f[0],
            f[3],
            f[1],
            f[2]
        )
        .unwrap();
    }
    points.push_str("]}");
    let geo = write(&dir, "pads.geojson", &points);
    let from_points = dir.join("points.geojson");
    let o = build(&geo, &from_points, &[]);
    assert!(o.status.success(), "{}", said(&o));
    assert_eq!(
        std::fs::read(air).unwrap(),
        std::fs::read(&from_points).unwrap()
    );
    // A day on it, planned and verified.
    let run = dir.join("run");
    let o = muse(&[
        "simulate",
        "--airspace",
        air,
        "--count",
        "300",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(said(&o).contains("verified      OK"), "{}", said(&o));
    let o = muse(&[
        "verify",
        "--plans",
        run.join("plans.jsonl").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
}

#[test]
fn exclusions_and_a_maximum_length_drop_corridors() {
    let dir = scratch_dir("pads-exclusions");
    std::fs::create_dir_all(&dir).unwrap();
    let pads = write(&dir, "pads.csv", VIENNA);
    let o = build(
        &pads,
        &dir.join("short.geojson"),
        &["--max-corridor-m", "3000"],
    );
    assert!(o.status.success(), "{}", said(&o));
    let corridors = |o: &std::process::Output| {
        let s = stderr(o);
        let at = s.find(" pads into ").unwrap() + 11;
        s[at..].split(' ').next().unwrap().parse::<usize>().unwrap()
    };
    let short = corridors(&o);
    assert!(short < 13, "{}", said(&o));
    // A box around the middle of V1–V2 (16.38, 48.2115): that corridor goes.
    let lake = write(
        &dir,
        "lake.geojson",
        r#"{"type": "Polygon", "coordinates": [[[16.378, 48.211], [16.382, 48.211], [16.382, 48.212], [16.378, 48.212], [16.378, 48.211]]]}"#,
    );
    let out = dir.join("lake.geojson.out");
    let o = build(&pads, &out, &["--exclude", &lake]);
    assert!(o.status.success(), "{}", said(&o));
    assert_eq!(corridors(&o), 12, "{}", said(&o));
    assert!(!std::fs::read_to_string(out).unwrap().contains("\"V1-V2\""));
    // A pad inside an exclusion.
    let v3 = write(
        &dir,
        "v3.geojson",
        r#"{"type": "Polygon", "coordinates": [[[16.40, 48.19], [16.42, 48.19], [16.42, 48.21], [16.40, 48.21], [16.40, 48.19]]]}"#,
    );
    let out = dir.join("v3.out");
    let o = build(&pads, &out, &["--exclude", &v3]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o)
            .contains("pads.csv: pad `V3` lies in polygon 0 (counted from 0) of the exclusions")
            && stderr(&o).contains("v3.geojson"),
        "{}",
        said(&o)
    );
    assert!(!out.exists(), "no output on an error");
}

#[test]
fn bad_pads_files_and_options_are_refused_with_no_output() {
    let dir = scratch_dir("pads-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let cases: [(&str, &str); 6] = [
        (
            "id,lon,lat\nA,16.3,48.2\nA,16.4,48.3\nC,16.5,48.25\n",
            "line 3: field `id`: duplicate pad id `A` (first on line 2)",
        ),
        (
            "id,lon,lat\nA,16.3,48.2\nB,16.4,148.3\nC,16.5,48.25\n",
            "line 3: field `lat`: 148.3 is outside −90 to 90",
        ),
        (
            "id,lon,lat\nA,16.3,48.2\nB,16.3,48.2\nC,16.5,48.25\n",
            "line 3: field `lon`: pad `B` is at the position of pad `A` (on line 2)",
        ),
        (
            "id,lon,lat\nA,16.3,48.2\nB,16.4,48.3\n",
            "2 pads: an airspace needs at least 3",
        ),
        (
            "id,lat\nA,48.2\n",
            "line 1: field `lon`: the header has no `lon` column",
        ),
        (
            "{\"type\": \"FeatureCollection\", \"features\": [{\"type\": \"Feature\", \"properties\": {\"id\": \"A\"}, \"geometry\": {\"type\": \"Polygon\", \"coordinates\": []}}]}",
            "feature 0 (`A`): field `geometry`: a pad is a GeoJSON `Point`",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let pads = write(&dir, &format!("bad{i}.csv"), text);
        let out = dir.join(format!("out{i}.geojson"));
        let o = build(&pads, &out, &[]);
        assert_eq!(o.status.code(), Some(2), "{}", said(&o));
        assert!(
            stderr(&o).contains(&format!("{pads}: {want}")),
            "{want}:\n{}",
            said(&o)
        );
        assert!(!out.exists(), "no output on an error");
    }
    let pads = write(&dir, "ok.csv", VIENNA);
    let out = dir.join("ok.geojson");
    for (args, want) in [
        (vec!["--crs", "EPSG:4326"], "--crs: unknown CRS `EPSG:4326`"),
        (
            vec!["--max-corridor-m", "0"],
            "must be a number of metres from 1 to 1000000",
        ),
        (vec!["--check"], "cannot be used with"),
    ] {
        let o = build(&pads, &out, &args);
        assert!(!o.status.success(), "{}", said(&o));
        assert!(stderr(&o).contains(want), "{want}:\n{}", said(&o));
    }
    let o = muse(&["airspace", "build", "--pads", &pads]);
    assert!(
        stderr(&o).contains("--pads needs --out FILE"),
        "{}",
        said(&o)
    );
    let o = muse(&["airspace", "build", "--crs", "utm"]);
    assert!(
        !o.status.success() && stderr(&o).contains("--pads"),
        "{}",
        said(&o)
    );
    // The pads file itself is never overwritten.
    let o = build(&pads, Path::new(&pads), &[]);
    assert!(!o.status.success(), "{}", said(&o));
    assert_eq!(std::fs::read_to_string(&pads).unwrap(), VIENNA);
}

#[test]
fn a_pads_file_that_is_not_utf8_names_the_line_of_its_first_bad_byte() {
    let dir = scratch_dir("pads-latin1");
    std::fs::create_dir_all(&dir).unwrap();
    // A file that is not UTF-8: the line of its first bad byte.
    let latin1 = dir.join("latin1.csv");
    std::fs::write(
        &latin1,
        b"id,lon,lat,name\nA,16.3,48.2,\nB,16.4,48.3,Caf\xe9\nC,16.5,48.25,\n",
    )
    .unwrap();
    let latin1 = latin1.to_str().unwrap();
    let o = build(latin1, &dir.join("l.geojson"), &[]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains(&format!(
            "{latin1}: line 3: byte 16 of the line, 0xE9, is not UTF-8"
        )),
        "{}",
        said(&o)
    );
}

#[test]
fn a_land_outline_is_carried_in_the_airspace_file_and_drawn() {
    let dir = scratch_dir("pads-land");
    std::fs::create_dir_all(&dir).unwrap();
    let pads = write(&dir, "vienna.csv", VIENNA);
    // A made-up outline around the test points.
    let land = write(
        &dir,
        "land.geojson",
        r#"{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[16.33, 48.18], [16.43, 48.18], [16.43, 48.24], [16.33, 48.24], [16.33, 48.18]]]}}"#,
    );
    let plain = dir.join("plain.geojson");
    let with_land = dir.join("with-land.geojson");
    assert!(build(&pads, &plain, &[]).status.success());
    let o = build(&pads, &with_land, &["--land", &land]);
    assert!(o.status.success(), "{}", said(&o));
    let text = std::fs::read_to_string(&with_land).unwrap();
    assert!(text.contains(r#""properties": {"kind": "land"}"#), "{text}");
    // The same graph: the plain file is the land file without its last feature.
    let plain_text = std::fs::read_to_string(&plain).unwrap();
    assert!(text.starts_with(plain_text.trim_end_matches("\n]}\n")));
    // Every command reads it; maps draw the land.
    let map = |air: &Path| {
        let out = dir.join("map.svg");
        let o = muse(&[
            "airspace",
            "map",
            "--airspace",
            air.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", said(&o));
        std::fs::read_to_string(out).unwrap()
    };
    // The coastline colour outlines the land.
    assert!(map(&with_land).contains("#7E98AD"), "the coastline");
    assert!(!map(&plain).contains("#7E98AD"));
    let o = muse(&[
        "simulate",
        "--airspace",
        with_land.to_str().unwrap(),
        "--count",
        "50",
        "--out",
        dir.join("sim").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    // A bad outline is refused with no output.
    let bad = write(
        &dir,
        "bad-land.geojson",
        r#"{"type": "Point", "coordinates": [16.3, 48.2]}"#,
    );
    let out = dir.join("refused.geojson");
    let o = build(&pads, &out, &["--land", &bad]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains("bad-land.geojson: feature 0: field `type`"),
        "{}",
        said(&o)
    );
    assert!(!out.exists());
}

#[test]
fn pads_across_the_180th_meridian_near_a_pole_or_too_far_apart_are_refused() {
    let dir = scratch_dir("pads-world");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("a.geojson");
    for (what, pads, message) in [
        (
            "across ±180° (Fiji)",
            "id,lon,lat\nF1,179.95,-17.0\nF2,-179.95,-17.05\nF3,179.9,-17.1\n",
            "the nodes lie on both sides of the ±180° meridian (`F2` at -179.95°, `F1` at \
             179.95°)",
        ),
        (
            "around the North Pole",
            "id,lon,lat\nP1,0,88.5\nP2,120,88.5\nP3,-120,88.5\n",
            "node `P1` is at latitude 88.5°: an airspace's nodes must lie between 84° S and 84° N",
        ),
        (
            "near the South Pole",
            "id,lon,lat\nQ1,10,-80\nQ2,11,-80.5\nQ3,10.5,-84.2\n",
            "node `Q3` is at latitude -84.2°",
        ),
        (
            "round the Arctic",
            "id,lon,lat\nR1,0,80\nR2,120,80\nR3,-120,80\n",
            "the nodes span 240° of longitude (`R3` at -120° to `R2` at 120°): they must lie \
             within 60°",
        ),
        (
            "a continent apart",
            "id,lon,lat\nA,0,10\nB,70,10\nC,35,20\n",
            "the nodes span 70° of longitude (`A` at 0° to `B` at 70°)",
        ),
    ] {
        let file = write(&dir, "pads.csv", pads);
        let o = build(&file, &out, &[]);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", said(&o));
        let err = stderr(&o);
        assert!(
            err.contains(&format!("building the airspace of {file}: {message}")),
            "{what}: {}",
            said(&o)
        );
        assert!(!out.exists(), "{what}: no output");
    }
    // Right up to the limits is built.
    let file = write(
        &dir,
        "edge.csv",
        "id,lon,lat\nE1,179.0,83.9\nE2,179.9,83.95\nE3,179.5,83.5\n",
    );
    let o = build(&file, &out, &[]);
    assert!(o.status.success(), "{}", said(&o));
}
