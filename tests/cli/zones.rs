//! Zone files that are legal one by one but say something else together, or do nothing: the
//! same zone id in two files is refused naming both files; a zone announced after its last
//! window ended, or one that closes nothing on the airspace (or at the layers' heights), is
//! read with a warning on standard error naming it.

use std::path::Path;

use crate::run::{muse, said, stderr};
use crate::support::scratch_dir;

/// A zone file of one feature `id` with the given properties (after the identifier) and a
/// 2 km square around the stadium, lon 103.865–103.885, lat 1.295–1.315.
fn zone(id: &str, props: &str) -> String {
    format!(
        r#"{{"type": "FeatureCollection", "features": [{{"type": "Feature",
  "properties": {{"identifier": "{id}"{props}}},
  "geometry": {{"type": "Polygon", "coordinates": [[[103.865, 1.295], [103.885, 1.295],
    [103.885, 1.315], [103.865, 1.315], [103.865, 1.295]]]}}}}]}}"#
    )
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// `muse airspace info` on the default airspace with `args`.
fn info(args: &[&str]) -> std::process::Output {
    let all: Vec<&str> = ["airspace", "info"]
        .into_iter()
        .chain(args.iter().copied())
        .collect();
    muse(&all)
}

#[test]
fn the_same_zone_id_in_two_files_is_refused_naming_both() {
    let dir = scratch_dir("zones-same-id");
    std::fs::create_dir_all(&dir).unwrap();
    let a = write(&dir, "a.geojson", &zone("X", ""));
    let b = write(&dir, "b.geojson", &zone("X", r#", "name": "another X""#));
    let c = write(&dir, "c.geojson", &zone("Y", ""));
    let out = dir.join("out").display().to_string();
    for args in [
        vec!["airspace", "info", "--zones", &a, "--zones", &b],
        vec![
            "airspace", "info", "--zones", &c, "--zones", &a, "--zones", &b,
        ],
        vec![
            "simulate", "--count", "10", "--zones", &a, "--zones", &b, "--out", &out,
        ],
    ] {
        let o = muse(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", said(&o));
        let err = stderr(&o);
        assert!(
            err.contains(&format!("{b}: zone `X` is also in {a}")),
            "{args:?}: {}",
            said(&o)
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    // The same file twice is the same mistake.
    let o = info(&["--zones", &a, "--zones", &a]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(stderr(&o).contains("zone `X` is also in"), "{}", said(&o));
    // Distinct ids in two files are read, without a word.
    let o = info(&["--zones", &a, "--zones", &c]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(!stderr(&o).contains("warning"), "{}", said(&o));
}

#[test]
fn a_zone_announced_after_its_last_window_is_read_with_a_warning() {
    let dir = scratch_dir("zones-announced-late");
    std::fs::create_dir_all(&dir).unwrap();
    // Closed 10:00-12:00 on 5 January, announced at 14:00: it binds nothing, ever.
    let late = write(
        &dir,
        "late.geojson",
        &zone(
            "LATE",
            r#", "limitedApplicability": [{"startDateTime": "2026-01-05T10:00:00+08:00",
                "endDateTime": "2026-01-05T12:00:00+08:00"}],
               "announced": "2026-01-05T14:00:00+08:00""#,
        ),
    );
    // Daily 10:00-12:00 within 5 January only, announced at 12:00 (the end is excluded).
    let daily = write(
        &dir,
        "daily.geojson",
        &zone(
            "DAILY",
            r#", "limitedApplicability": [{"startDateTime": "2026-01-05T00:00:00+08:00",
                "endDateTime": "2026-01-06T00:00:00+08:00", "schedule": [{"day": ["ANY"],
                "startTime": "10:00:00+08:00", "endTime": "12:00:00+08:00"}]}],
               "announced": "2026-01-05T12:00:00+08:00""#,
        ),
    );
    for (file, id, ended) in [
        (&late, "LATE", "2026-01-05T12:00:00.000+08:00"),
        (&daily, "DAILY", "2026-01-05T12:00:00.000+08:00"),
    ] {
        let out = dir.join(id).display().to_string();
        let o = muse(&["simulate", "--count", "10", "--zones", file, "--out", &out]);
        assert!(o.status.success(), "{id}: {}", said(&o));
        let err = stderr(&o);
        assert!(
            err.contains(&format!(
                "warning: zone `{id}` is announced at 2026-01-05T1"
            )) && err.contains(&format!(
                "when its last window has already ended ({ended}): it closes nothing"
            )),
            "{id}: {}",
            said(&o)
        );
    }
    // Announced while it is closed, or before: no warning.
    for announced in ["2026-01-05T11:00:00+08:00", "2026-01-05T09:00:00+08:00"] {
        let text = std::fs::read_to_string(&late)
            .unwrap()
            .replace("2026-01-05T14:00:00+08:00", announced);
        let file = write(&dir, "in-time.geojson", &text);
        let o = info(&["--zones", &file]);
        assert!(o.status.success(), "{}", said(&o));
        assert!(!stderr(&o).contains("warning"), "{announced}: {}", said(&o));
    }
    // A daily zone without an end always has a window to come.
    let text = std::fs::read_to_string(&daily)
        .unwrap()
        .replace(r#""endDateTime": "2026-01-06T00:00:00+08:00", "#, "");
    let file = write(&dir, "every-day.geojson", &text);
    let o = info(&["--zones", &file]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(!stderr(&o).contains("warning"), "{}", said(&o));
}

#[test]
fn a_zone_that_closes_nothing_is_read_with_a_warning() {
    let dir = scratch_dir("zones-close-nothing");
    std::fs::create_dir_all(&dir).unwrap();
    // A square in the Gulf of Guinea, far from every Singapore station and corridor.
    let far = write(
        &dir,
        "far.geojson",
        &zone("FAR", "")
            .replace("103.8", "0.0")
            .replace("1.3", "0.3")
            .replace("1.2", "0.2"),
    );
    let near = write(&dir, "near.geojson", &zone("NEAR", ""));
    let o = info(&["--zones", &near, "--zones", &far]);
    assert!(o.status.success(), "{}", said(&o));
    let err = stderr(&o);
    assert!(
        err.contains("warning: zone `FAR` closes nothing on the airspace"),
        "{}",
        said(&o)
    );
    assert!(!err.contains("`NEAR`"), "{}", said(&o));
    // Planning says so too.
    let out = dir.join("out").display().to_string();
    let o = muse(&["simulate", "--count", "10", "--zones", &far, "--out", &out]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).contains("warning: zone `FAR` closes nothing"),
        "{}",
        said(&o)
    );

    // From 500 m up it covers stations and corridors, but no layer flies that high.
    let high = write(
        &dir,
        "high.geojson",
        &zone("HIGH", r#", "lowerLimit": 500"#),
    );
    let o = info(&["--zones", &high]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(!stderr(&o).contains("warning"), "flat: {}", said(&o));
    let o = info(&["--zones", &high, "--layers", "3"]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).contains(
            "warning: zone `HIGH` closes nothing on the airspace at its heights (from 500 m AGL up)"
        ),
        "{}",
        said(&o)
    );
}
