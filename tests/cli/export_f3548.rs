//! `muse export f3548`: a small plans file exported at B = 10 m matches its golden file
//! (`crates/muse-export/testdata/f3548/`), a layered day exports its climbs as volumes
//! spanning both layers, and bad inputs — a buffer out of range, a missing or bad plans file,
//! an output that is an input — are refused with exit 2, naming what is wrong, before
//! anything is written.

use std::path::{Path, PathBuf};

use crate::run::{muse, said, stderr, stdout};

/// The golden inputs and outputs.
fn testdata(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates/muse-export/testdata/f3548")
        .join(name)
        .display()
        .to_string()
}

/// A fresh folder under the target directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("export_f3548_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `args`, asserts exit code 2 and that stderr says every one of `needles`.
fn refused(args: &[&str], needles: &[&str]) {
    let o = muse(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: `{needle}` not in: {err}");
    }
    assert!(!err.contains("panicked"), "{args:?}: {err}");
}

#[test]
fn a_small_day_exports_as_its_golden_file() {
    let dir = scratch("golden");
    let out = dir.join("intents.json");
    let (plans, air) = (testdata("plans.jsonl"), testdata("air.geojson"));
    let o = muse(&[
        "export",
        "f3548",
        "--plans",
        &plans,
        "--airspace",
        &air,
        "--buffer-m",
        "10",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    // Three flights fly (r2 is rejected). r3 waits at A until r1 has left A–B, so they never
    // share a corridor, but r3's wait at A meets r1's volume for A–B (which holds A for the
    // whole traversal); r4 leaves B for W while r1 flies W–C: their corridors' volumes meet
    // at W. r3 has landed before r4 takes off.
    assert!(
        stdout(&o).contains(
            "3 operational intents (7 volumes) of 4 requests; 2 of 3 flights' pairs intersect \
             in 4-D at buffer 10 m"
        ),
        "{}",
        said(&o)
    );
    let golden = std::fs::read_to_string(testdata("intents_b10.expected.json")).unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(
        written == golden,
        "{} differs from testdata's intents_b10.expected.json; if the change is meant, \
         write it there with: muse export f3548 --plans {plans} --airspace {air} \
         --buffer-m 10 --out crates/muse-export/testdata/f3548/intents_b10.expected.json",
        out.display()
    );
}

#[test]
fn a_layered_day_climbs_in_volumes_that_span_both_layers() {
    let dir = scratch("layered");
    let out = dir.join("intents.json");
    let o = muse(&[
        "export",
        "f3548",
        "--plans",
        &testdata("layered.jsonl"),
        "--airspace",
        &testdata("air.geojson"),
        "--layers",
        "2",
        "--buffer-m",
        "0",
        "--vertical-buffer-m",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", said(&o));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let mut bands = Vec::new();
    for entry in doc["operational_intents"].as_array().unwrap() {
        for v in entry["operational_intent"]["details"]["volumes"]
            .as_array()
            .unwrap()
        {
            let band = (
                v["volume"]["altitude_lower"]["value"].as_f64().unwrap(),
                v["volume"]["altitude_upper"]["value"].as_f64().unwrap(),
                v["volume"].get("outline_circle").is_some(),
            );
            if v["volume"]["outline_circle"]["radius"]["value"].is_number() {
                assert_eq!(v["volume"]["outline_circle"]["radius"]["value"], 0.01);
            }
            if !bands.contains(&band) {
                bands.push(band);
            }
        }
    }
    bands.sort_by(|a, b| a.partial_cmp(b).unwrap());
    // Corridors at 60 m and 69.144 m ± 1 m; climbs (circles) from the bottom of the first to
    // the top of the second.
    assert_eq!(
        bands,
        [
            (59.0, 61.0, false),
            (59.0, 70.144, true),
            (68.144, 70.144, false)
        ]
    );
}

#[test]
fn a_buffer_out_of_range_is_refused() {
    let dir = scratch("range");
    let out = dir.join("intents.json");
    let out = out.to_str().unwrap();
    let plans = testdata("plans.jsonl");
    for bad in ["-1", "1000.5", "NaN", "ten"] {
        refused(
            &[
                "export",
                "f3548",
                "--plans",
                &plans,
                "--buffer-m",
                bad,
                "--out",
                out,
            ],
            &["--buffer-m", "from 0 to 1000"],
        );
    }
    refused(
        &[
            "export",
            "f3548",
            "--plans",
            &plans,
            "--buffer-m",
            "10",
            "--vertical-buffer-m",
            "0",
            "--out",
            out,
        ],
        &["--vertical-buffer-m", "from 0.01 to 1000"],
    );
    refused(
        &["export", "f3548", "--plans", &plans, "--out", out],
        &["--buffer-m"],
    );
    assert!(!Path::new(out).exists());
}

#[test]
fn bad_plans_and_options_are_refused_naming_them() {
    let dir = scratch("bad");
    let out = dir.join("intents.json");
    let out = out.to_str().unwrap();
    let air = testdata("air.geojson");
    let missing = dir.join("missing.jsonl");
    refused(
        &[
            "export",
            "f3548",
            "--plans",
            missing.to_str().unwrap(),
            "--airspace",
            &air,
            "--buffer-m",
            "10",
            "--out",
            out,
        ],
        &["missing.jsonl"],
    );
    let text = std::fs::read_to_string(testdata("plans.jsonl")).unwrap();
    let broken = dir.join("broken.jsonl");
    let first = text.lines().next().unwrap();
    std::fs::write(
        &broken,
        format!("{first}\n{{\"request\": \"r9\", \"status\": 3}}\n"),
    )
    .unwrap();
    refused(
        &[
            "export",
            "f3548",
            "--plans",
            broken.to_str().unwrap(),
            "--airspace",
            &air,
            "--buffer-m",
            "10",
            "--out",
            out,
        ],
        &["broken.jsonl", "line 2"],
    );
    let plans = testdata("plans.jsonl");
    let with = |option: &str, value: &str, needle: &str| {
        refused(
            &[
                "export",
                "f3548",
                "--plans",
                &plans,
                "--airspace",
                &air,
                "--buffer-m",
                "10",
                option,
                value,
                "--out",
                out,
            ],
            &[option, needle],
        );
    };
    with(
        "--uss-base-url",
        "https://uss.example.com/",
        "not end with /",
    );
    with("--shared-at", "tomorrow", "tomorrow");
    // Shared after the day: every intent would end in the past.
    with(
        "--shared-at",
        "2026-01-06T00:00:00Z",
        "ends before it is shared",
    );
    assert!(!Path::new(out).exists());
}

#[test]
fn the_output_never_clobbers_an_input() {
    let dir = scratch("clobber");
    let plans = dir.join("plans.jsonl");
    std::fs::copy(testdata("plans.jsonl"), &plans).unwrap();
    let before = std::fs::read(&plans).unwrap();
    let plans = plans.to_str().unwrap();
    let air = testdata("air.geojson");
    refused(
        &[
            "export",
            "f3548",
            "--plans",
            plans,
            "--airspace",
            &air,
            "--buffer-m",
            "10",
            "--out",
            plans,
        ],
        &["--out", "--plans"],
    );
    refused(
        &[
            "export",
            "f3548",
            "--plans",
            plans,
            "--airspace",
            &air,
            "--buffer-m",
            "10",
            "--out",
            &air,
        ],
        &["--out", "--airspace"],
    );
    assert_eq!(std::fs::read(plans).unwrap(), before);
}
