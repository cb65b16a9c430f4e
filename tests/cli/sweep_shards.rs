//! A sweep run whole and as three shards in separate processes (`--shard K/3`), merged with
//! `muse sweep merge`: the CSVs are identical, timing columns aside — for a sweep of variants
//! and for an announcement-lead sweep, from the command line and from a study file. Merge
//! refuses shards of another sweep, a missing shard and a shard given twice, each with a clear
//! message and a non-zero exit. The committed paper study reproduces its published results.

use std::path::Path;
use std::process::{Command, Output};

// Only the scratch folder is used here.

const SWEEP: &[&str] = &[
    "sweep", "--counts", "100,250", "--reps", "3", "--vary", "zones",
];

/// Runs muse in `dir`; prints its output (seen with `--nocapture`).
fn muse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("muse runs")
}

/// Runs muse in `dir`, expects success and returns its standard output.
fn ok(args: &[&str], dir: &Path) -> String {
    let out = muse(args, dir);
    assert!(
        out.status.success(),
        "muse {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `sweep` as shards `0/n` … `n-1/n` in separate processes, into `{prefix}K` in `dir`.
fn shards(sweep: &[&str], n: usize, prefix: &str, dir: &Path) {
    for k in 0..n {
        let (shard, out) = (format!("{k}/{n}"), format!("{prefix}{k}"));
        ok(&[sweep, &["--shard", &shard, "--out", &out]].concat(), dir);
    }
}

fn refused(args: &[&str], dir: &Path, needle: &str) {
    let out = muse(args, dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "muse {args:?} should fail");
    assert!(
        err.contains(needle),
        "muse {args:?}: expected `{needle}` in:\n{err}"
    );
}

#[test]
fn three_shards_merge_into_the_files_of_one_machine() {
    let dir = crate::support::scratch_dir("sweep_shards");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    ok(&[SWEEP, &["--out", "whole"]].concat(), &dir);
    shards(SWEEP, 3, "s", &dir);
    ok(
        &["sweep", "merge", "s2", "s0", "s1", "--out", "merged"],
        &dir,
    );
    for file in ["sweep.csv", "sweep_summary.csv"] {
        crate::support::csv::same_untimed(&dir.join("whole"), &dir.join("merged"), file);
    }
    for plot in [
        "sweep_runtime.svg",
        "sweep_success.svg",
        "sweep_air_delay.svg",
    ] {
        assert!(dir.join("merged").join(plot).is_file(), "{plot} written");
    }
    println!(
        "12 runs: unsharded and 3 shards merged give the same sweep.csv and sweep_summary.csv"
    );

    refused(
        &["sweep", "merge", "s0", "s2", "--out", "m"],
        &dir,
        "missing shard(s) 1/3",
    );
    refused(
        &["sweep", "merge", "s0", "s1", "s1", "s2", "--out", "m"],
        &dir,
        "shard 1/3 is given twice",
    );
    let other = [
        "sweep", "--counts", "100,250", "--reps", "4", "--vary", "zones",
    ];
    ok(
        &[&other[..], &["--shard", "1/3", "--out", "t1"]].concat(),
        &dir,
    );
    refused(
        &["sweep", "merge", "s0", "t1", "s2", "--out", "m"],
        &dir,
        "shards of different sweeps",
    );
    refused(
        &["sweep", "merge", "nowhere", "--out", "m"],
        &dir,
        "did not finish",
    );
    refused(&[SWEEP, &["--shard", "3/3"]].concat(), &dir, "expected K/N");
    // `--count` (one day's requests elsewhere) is not a sweep's: it would be ignored.
    refused(
        &[SWEEP, &["--count", "5"]].concat(),
        &dir,
        "a sweep's request counts are --counts",
    );
}

/// A small announcement-lead sweep: 2 leads + known + never announced × 2 counts × 2 reps.
const LEAD_SWEEP: &[&str] = &[
    "sweep",
    "--vary",
    "announce-lead",
    "--counts",
    "200,400",
    "--reps",
    "2",
    "--leads",
    "0,60",
    "--od",
    "in-range",
];

#[test]
fn an_announcement_lead_sweep_shards_and_merges_too() {
    let dir = crate::support::scratch_dir("sweep_shards_lead");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    ok(&[LEAD_SWEEP, &["--out", "whole"]].concat(), &dir);
    shards(LEAD_SWEEP, 3, "s", &dir);
    let merged = ok(
        &["sweep", "merge", "s1", "s2", "s0", "--out", "merged"],
        &dir,
    );
    assert!(merged.contains("merged 3 shards, 16 runs"), "{merged}");
    for file in ["announce_lead.csv", "announce_lead_summary.csv"] {
        crate::support::csv::same_untimed(&dir.join("whole"), &dir.join("merged"), file);
    }
    for plot in [
        "announce_lead_success.svg",
        "announce_lead_outcomes.svg",
        "announce_lead_extra_delay.svg",
    ] {
        assert!(dir.join("merged").join(plot).is_file(), "{plot} written");
    }
    refused(
        &["sweep", "merge", "s0", "s1", "--out", "m"],
        &dir,
        "missing shard(s) 2/3",
    );
    println!("16 announcement-lead runs: unsharded and 3 shards merged give the same CSVs");
}

/// A small study: CBD against the stadium zone (a file beside it, found from `studies/`) ×
/// ground delay, 2 counts × 2 repetitions.
const SMALL_STUDY: &str = r#"title = "A small study"
results = "../published"

[sweep]
counts = [150, 300]
reps = 2
vary = ["zones", "ground-delay"]
zones = ["../stadium.geojson"]
od = "in-range"
"#;

/// The small study's sweep written as a command line.
const SMALL_FLAGS: &[&str] = &[
    "sweep",
    "--counts",
    "150,300",
    "--reps",
    "2",
    "--vary",
    "zones",
    "--vary",
    "ground-delay",
    "--zones",
    "stadium.geojson",
    "--od",
    "in-range",
];

/// A scratch folder with the small study in `studies/` and its zone file.
fn small_study(name: &str) -> std::path::PathBuf {
    let dir = crate::support::scratch_dir(name);
    std::fs::create_dir_all(dir.join("studies")).expect("scratch dir");
    let zones = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/singapore-77");
    std::fs::copy(
        zones.join("stadium_zone.geojson"),
        dir.join("stadium.geojson"),
    )
    .expect("zone file");
    std::fs::write(dir.join("studies/small.toml"), SMALL_STUDY).expect("study");
    dir
}

#[test]
fn a_study_runs_whole_or_in_shards_and_is_checked_against_its_results() {
    let dir = small_study("sweep_shards_study");
    let study = ["sweep", "--study", "studies/small.toml"];
    let dry = ok(&[&study[..], &["--dry-run"]].concat(), &dir);
    let dry_flags = ok(&[SMALL_FLAGS, &["--dry-run"]].concat(), &dir);
    let id = |text: &str| {
        text.lines()
            .find(|l| l.starts_with("sweep "))
            .map(str::to_owned)
    };
    assert_eq!(
        id(&dry),
        id(&dry_flags),
        "the study is the sweep of its flags:\n{dry}\n{dry_flags}"
    );
    assert!(
        dry.contains("sweep ") && dry.contains(": 16 runs, 3600 requests"),
        "{dry}"
    );

    // No published results yet: the run says so; then it is the published one.
    let first = ok(&[&study[..], &["--out", "published"]].concat(), &dir);
    assert!(
        first.contains("wrote the study's published results"),
        "{first}"
    );
    let again = ok(&study, &dir);
    assert!(
        again.contains("reproduces the published published/sweep_summary.csv exactly"),
        "{again}"
    );
    assert!(
        dir.join("out/small/sweep.csv").is_file(),
        "default --out is out/STUDY"
    );
    ok(&[SMALL_FLAGS, &["--out", "by-flags"]].concat(), &dir);
    crate::support::csv::same_untimed(&dir.join("published"), &dir.join("by-flags"), "sweep.csv");

    shards(&[&study[..], &["--threads", "1"]].concat(), 2, "t", &dir);
    let merged = ok(&["sweep", "merge", "t0", "t1", "--out", "merged"], &dir);
    assert!(
        merged.contains("(study studies/small.toml: A small study)"),
        "{merged}"
    );
    assert!(merged.contains("reproduces the published"), "{merged}");
    crate::support::csv::same_untimed(&dir.join("published"), &dir.join("merged"), "sweep.csv");

    // A published table that does not match is reported, with a non-zero exit.
    let summary = dir.join("published/sweep_summary.csv");
    let text = std::fs::read_to_string(&summary).expect("summary");
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    lines[1] = lines[1].replacen(",2,", ",3,", 1);
    std::fs::write(&summary, lines.join("\n") + "\n").expect("edited summary");
    refused(
        &["sweep", "merge", "t0", "t1", "--out", "merged"],
        &dir,
        "differs from the published published/sweep_summary.csv: 1 of 8 rows differ; first at line 2, column runs: published 3, now 2",
    );

    // Beside a study only how it is run.
    refused(
        &[&study[..], &["--reps", "5"]].concat(),
        &dir,
        "--reps is set by the study studies/small.toml",
    );
}

#[test]
fn the_paper_study_reproduces_its_published_results() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = crate::support::scratch_dir("paper_study");
    let printed = ok(
        &[
            "sweep",
            "--study",
            "studies/paper.toml",
            "--out",
            out.to_str().expect("a UTF-8 path"),
        ],
        root,
    );
    assert!(
        printed.contains("reproduces the published docs/results/paper/sweep_summary.csv exactly"),
        "{printed}"
    );
}

#[test]
fn a_shard_killed_with_sigkill_leaves_no_file_and_is_simply_rerun() {
    use std::os::unix::process::ExitStatusExt as _;
    let dir = crate::support::scratch_dir("sweep_shards_kill");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    // Days of 3,000 requests with battery swaps and no deadline take seconds each to plan:
    // shard 0 is certainly still running when it is killed.
    let sweep = [
        "sweep",
        "--counts",
        "3000",
        "--reps",
        "2",
        "--vary",
        "battery-swap",
        "--swap-min",
        "5",
        "--threads",
        "1",
    ];
    let mut child = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(sweep)
        .args(["--shard", "0/2", "--out", "k0"])
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("muse starts");
    std::thread::sleep(std::time::Duration::from_millis(300));
    child.kill().expect("SIGKILL");
    let status = child.wait().expect("reaped");
    assert_eq!(
        status.signal(),
        Some(9),
        "the shard ended before the kill ({status}): make its sweep bigger"
    );
    let left: Vec<_> = std::fs::read_dir(dir.join("k0"))
        .map(|d| d.map(|e| e.expect("entry").file_name()).collect())
        .unwrap_or_default();
    assert!(left.is_empty(), "a killed shard left {left:?}");
    refused(
        &["sweep", "merge", "k0", "--out", "m"],
        &dir,
        "did not finish",
    );
    // Rerun: the same shard writes its file, and the merge takes it.
    ok(
        &[&sweep[..], &["--shard", "0/2", "--out", "k0"]].concat(),
        &dir,
    );
    ok(
        &[&sweep[..], &["--shard", "1/2", "--out", "k1"]].concat(),
        &dir,
    );
    let merged = ok(&["sweep", "merge", "k0", "k1", "--out", "m"], &dir);
    assert!(merged.contains("merged 2 shards, 4 runs"), "{merged}");
}
