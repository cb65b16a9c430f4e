//! The cluster templates under `deploy/` run for real, as far as this machine allows: the
//! local script runs a sweep as separate shard processes and merges it, and the Slurm array
//! script runs as each array task would (its `SLURM_*` variables set, as `sbatch` does),
//! followed by the merge script. Both give the files of one machine, timing columns aside.
//! (Kubernetes and Docker need a cluster and an engine; see `deploy/README.md`.)

use std::path::{Path, PathBuf};
use std::process::Command;

// Only the scratch folder and the CSV comparison are used here.

/// A small sweep: 2 variants × 2 counts × 3 repetitions = 12 runs.
const SWEEP: &[&str] = &[
    "--counts", "100,250", "--reps", "3", "--vary", "zones", "--od", "in-range",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `script` with `args` in `dir` with `MUSE` set to the binary under test, and `env`.
fn run(script: &str, args: &[&str], dir: &Path, env: &[(&str, String)]) -> (bool, String) {
    let out = Command::new("bash")
        .arg(root().join(script))
        .args(args)
        .current_dir(dir)
        .env("MUSE", env!("CARGO_BIN_EXE_muse"))
        .envs(env.iter().map(|(k, v)| (*k, v.as_str())))
        .output()
        .expect("bash runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// The unsharded sweep, written to `dir/whole`.
fn whole(dir: &Path) {
    let out = Command::new(env!("CARGO_BIN_EXE_muse"))
        .arg("sweep")
        .args(SWEEP)
        .args(["--out", "whole"])
        .current_dir(dir)
        .output()
        .expect("muse runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_local_script_runs_shards_as_processes_and_merges_them() {
    let dir = crate::support::scratch_dir("deploy_local");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    whole(&dir);
    let args = [&["4", "2", "sharded", "--"], SWEEP].concat();
    let (ok, text) = run(
        "deploy/local/shards.sh",
        &args,
        &dir,
        &[("THREADS", "1".into())],
    );
    assert!(ok, "shards.sh failed:\n{text}");
    assert!(text.contains("merged 4 shards, 12 runs"), "{text}");
    for k in 0..4 {
        assert!(text.contains(&format!("shard {k}/4: ")), "{text}");
    }
    for file in ["sweep.csv", "sweep_summary.csv"] {
        crate::support::csv::same_untimed(&dir.join("whole"), &dir.join("sharded/merged"), file);
    }
    // A shard that fails stops the run before the merge, with a non-zero exit.
    let bad = [&["2", "1", "bad", "--"], SWEEP, &["--reps", "0"]].concat();
    let (ok, text) = run("deploy/local/shards.sh", &bad, &dir, &[]);
    assert!(!ok, "a failing shard must fail the script:\n{text}");
    assert!(text.contains("not merging"), "{text}");
    assert!(!dir.join("bad/merged").exists(), "no merge after a failure");
}

#[test]
fn the_slurm_scripts_run_each_array_task_and_merge() {
    let dir = crate::support::scratch_dir("deploy_slurm");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    whole(&dir);
    let n = 3;
    for k in 0..n {
        // What sbatch --array=0-2 sets in task k.
        let env = [
            ("SLURM_ARRAY_JOB_ID", "4242".to_owned()),
            ("SLURM_ARRAY_TASK_ID", k.to_string()),
            ("SLURM_ARRAY_TASK_COUNT", n.to_string()),
            ("SLURM_ARRAY_TASK_MIN", "0".to_owned()),
            ("SLURM_ARRAY_TASK_MAX", (n - 1).to_string()),
            ("SLURM_CPUS_PER_TASK", "1".to_owned()),
        ];
        let args = [&["results", "--"], SWEEP].concat();
        let (ok, text) = run("deploy/slurm/sweep.sbatch", &args, &dir, &env);
        assert!(ok, "task {k} failed:\n{text}");
        assert!(text.contains(&format!("shard {k}/{n}")), "{text}");
    }
    // A rerun of one task without SHARDS cannot know N: refused.
    let rerun = [
        ("SLURM_ARRAY_TASK_ID", "1".to_owned()),
        ("SLURM_ARRAY_TASK_COUNT", "1".to_owned()),
        ("SLURM_ARRAY_TASK_MIN", "1".to_owned()),
        ("SLURM_ARRAY_TASK_MAX", "1".to_owned()),
    ];
    let args = [&["results", "--"], SWEEP].concat();
    let (ok, text) = run("deploy/slurm/sweep.sbatch", &args, &dir, &rerun);
    assert!(!ok && text.contains("set SHARDS=N"), "{text}");

    let (ok, text) = run("deploy/slurm/merge.sbatch", &["results"], &dir, &[]);
    assert!(ok, "merge.sbatch failed:\n{text}");
    for file in ["sweep.csv", "sweep_summary.csv"] {
        crate::support::csv::same_untimed(&dir.join("whole"), &dir.join("results/merged"), file);
    }
}
