//! A sweep run whole and as three shards in separate processes (`--shard K/3`), merged with
//! `muse sweep merge`: the CSVs are identical, timing columns aside. Merge refuses shards of
//! another sweep, a missing shard and a shard given twice, each with a clear message and a
//! non-zero exit.

use std::path::Path;
use std::process::{Command, Output};

// Only the scratch folder is used here.
#[allow(dead_code)]
mod support;

const SWEEP: &[&str] = &[
    "sweep", "--counts", "100,250", "--reps", "3", "--vary", "zones",
];

fn muse(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("muse runs")
}

fn ok(args: &[&str], dir: &Path) {
    let out = muse(args, dir);
    assert!(
        out.status.success(),
        "muse {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The CSV at `path` without its timing columns (`planner_ms…`).
fn untimed(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).expect("a CSV");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].starts_with("planner_ms"))
        .collect();
    assert!(
        keep.len() < header.len(),
        "{} has timing columns",
        path.display()
    );
    std::iter::once(header.join(","))
        .chain(lines.map(str::to_owned))
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| cells[i].to_owned()).collect()
        })
        .collect()
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
    let dir = support::scratch_dir("sweep_shards");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    ok(&[SWEEP, &["--out", "whole"]].concat(), &dir);
    for k in 0..3 {
        let shard = format!("{k}/3");
        let out = format!("s{k}");
        ok(&[SWEEP, &["--shard", &shard, "--out", &out]].concat(), &dir);
    }
    ok(
        &["sweep", "merge", "s2", "s0", "s1", "--out", "merged"],
        &dir,
    );
    for file in ["sweep.csv", "sweep_summary.csv"] {
        let whole = untimed(&dir.join("whole").join(file));
        let merged = untimed(&dir.join("merged").join(file));
        assert_eq!(whole.len(), merged.len(), "{file}: rows");
        assert_eq!(
            whole, merged,
            "{file}: merged differs from the unsharded run"
        );
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
}
