//! End-to-end tests of the `muse` binary: what a user sees for good and bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn muse(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .output()
        .expect("muse runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A fresh folder under the target directory for one test.
fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

#[test]
fn airspace_info_describes_the_default() {
    let o = muse(&["airspace", "info"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("77 (77 stations, 0 waypoints)"), "{out}");
    assert!(out.contains("SG-CBD-DOWNTOWN-CORE"), "{out}");
}

#[test]
fn airspace_build_check_passes_on_the_committed_files() {
    let root = env!("CARGO_MANIFEST_DIR");
    let dir = format!("{root}/scenarios/singapore-77");
    let o = muse(&["airspace", "build", "--check", "--out", &dir]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
}

#[test]
fn airspace_map_writes_an_svg() {
    let dir = scratch_dir("map");
    let out = dir.join("map.svg").display().to_string();
    let o = muse(&["airspace", "map", "--out", &out]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("S077") && svg.contains("Downtown Core"));
}

#[test]
fn bad_airspace_file_is_named_with_feature_and_field() {
    let dir = scratch_dir("bad_airspace");
    let air = write(
        &dir,
        "air.geojson",
        r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.81, 1.3]]}, "properties": {"from": "A", "to": "B"}}]}"#,
    );
    let o = muse(&["airspace", "info", "--airspace", &air]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("air.geojson: feature 1 (`A-B`): field `to`: unknown node id `B`"),
        "{err}"
    );
}

#[test]
fn bad_zone_file_is_named_with_feature_and_field() {
    let dir = scratch_dir("bad_zone");
    let zones = write(
        &dir,
        "z.geojson",
        r#"{"type": "FeatureCollection", "features": [{"type": "Feature",
  "geometry": {"type": "Polygon", "coordinates": [[[103.8, 1.3], [103.81, 1.3], [103.81, 1.31], [103.8, 1.31], [103.8, 1.3]]]},
  "properties": {"identifier": "Z1", "limitedApplicability": [{"schedule": [{"day": ["ANY"], "startTime": "10:00:00", "endTime": "12:00:00"}]}]}}]}"#,
    );
    let o = muse(&["airspace", "info", "--zones", &zones]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("z.geojson: feature 0 (`Z1`)") && err.contains("startTime"),
        "{err}"
    );
    assert!(err.contains("offset"), "{err}");
}
