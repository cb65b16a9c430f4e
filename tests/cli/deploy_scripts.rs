//! The cluster templates under `deploy/` run for real, as far as this machine allows: the
//! local script runs a sweep as separate shard processes and merges it, and the Slurm array
//! script runs as each array task would (its `SLURM_*` variables set, as `sbatch` does),
//! followed by the merge script. Both give the files of one machine, timing columns aside.
//! `submit.sh` runs with fake `sbatch` and `sinfo` commands first on the PATH: it refuses
//! jobs larger than any node, and prints reruns with the options it submitted with.
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

/// A folder of fake `sbatch` and (unless `sinfo` is `None`) `sinfo` commands, to put first on
/// PATH: `sbatch` logs its arguments to `sbatch.log` and answers job ids 101, 102, …;
/// `sinfo` prints `sinfo` (one node per line, `CPUS MEMORY_MB`) and logs its arguments.
fn fake_slurm(dir: &Path, sinfo: Option<&str>) -> String {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).expect("bin");
    let sbatch = format!(
        "#!/usr/bin/env bash\nlog={log}\nprintf '%s\\n' \"$*\" >>\"$log\"\necho $((100 + $(wc -l <\"$log\")))\n",
        log = dir.join("sbatch.log").display()
    );
    let mut scripts = vec![("sbatch", sbatch)];
    if let Some(nodes) = sinfo {
        scripts.push((
            "sinfo",
            format!(
                "#!/usr/bin/env bash\nprintf '%s\\n' \"$*\" >>{log}\nprintf '{nodes}'\n",
                log = dir.join("sinfo.log").display()
            ),
        ));
    }
    for (name, text) in scripts {
        let path = bin.join(name);
        std::fs::write(&path, text).expect("script");
        Command::new("chmod")
            .arg("+x")
            .arg(&path)
            .status()
            .expect("chmod");
    }
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

#[test]
fn submit_refuses_tasks_larger_than_any_node_and_prints_reruns_with_their_options() {
    let dir = crate::support::scratch_dir("deploy_submit");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let args = [&["3", "results", "--"], SWEEP].concat();
    // One node of 2 CPUs and 1,800 MB: the templates' 4 CPUs and 4 GB would wait forever.
    let path = fake_slurm(&dir, Some("2 1800\\n"));
    let (ok, text) = run(
        "deploy/slurm/submit.sh",
        &args,
        &dir,
        &[("PATH", path.clone())],
    );
    assert!(!ok, "{text}");
    assert!(
        text.contains(
            "submit.sh: the sweep's tasks ask for 4 CPUs (--cpus-per-task) and 4096 MB of \
             memory (--mem), but the largest node has 2 CPUs and 1800 MB (sinfo): they would \
             wait forever; set SWEEP_SBATCH_OPTS=\"--cpus-per-task=2 --mem=1800M\""
        ),
        "{text}"
    );
    assert!(
        !dir.join("sbatch.log").exists(),
        "nothing submitted: {text}"
    );
    // Enough CPUs, too much memory: the option to change is --mem.
    let env = [
        ("PATH", path.clone()),
        ("SWEEP_SBATCH_OPTS", "--cpus-per-task=2".to_owned()),
    ];
    let (ok, text) = run("deploy/slurm/submit.sh", &args, &dir, &env);
    assert!(!ok, "{text}");
    assert!(
        text.contains(
            "the sweep's tasks ask for 4096 MB of memory (--mem), but the largest node has \
             1800 MB (sinfo): they would wait forever; set SWEEP_SBATCH_OPTS=\"--cpus-per-task=2 \
             --mem=1800M\""
        ),
        "{text}"
    );
    // The merge job's defaults (1 CPU, 2 GB) are checked as well.
    let env = [
        ("PATH", path.clone()),
        (
            "SWEEP_SBATCH_OPTS",
            "-c 2 --mem 1G --partition=small".to_owned(),
        ),
    ];
    let (ok, text) = run("deploy/slurm/submit.sh", &args, &dir, &env);
    assert!(!ok, "{text}");
    assert!(
        text.contains(
            "the merge job asks for 2048 MB of memory (--mem), but the largest node has 1800 MB \
             (sinfo): it would wait forever; set MERGE_SBATCH_OPTS=\"--mem=1800M\""
        ),
        "{text}"
    );
    // The partition asked for is the one looked at.
    let sinfo_log = std::fs::read_to_string(dir.join("sinfo.log")).unwrap();
    assert!(sinfo_log.contains("-p small"), "{sinfo_log}");

    // Both fit: submitted, and the rerun and merge commands printed carry the options.
    let env = [
        ("PATH", path),
        ("SWEEP_SBATCH_OPTS", "--cpus-per-task=2 --mem=1G".to_owned()),
        ("MERGE_SBATCH_OPTS", "--mem=1000".to_owned()),
    ];
    let (ok, text) = run("deploy/slurm/submit.sh", &args, &dir, &env);
    assert!(ok, "{text}");
    let log = std::fs::read_to_string(dir.join("sbatch.log")).unwrap();
    assert_eq!(log.lines().count(), 2, "{log}");
    let rerun = text
        .lines()
        .find(|l| l.starts_with("rerun task(s) K:"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        rerun.contains("sbatch --array=K --cpus-per-task=2 --mem=1G --output="),
        "{rerun}"
    );
    let merge = text
        .lines()
        .find(|l| l.starts_with("then merge:"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        merge.contains("sbatch --dependency=afterok:RERUN_JOB_ID --mem=1000 --output="),
        "{merge}"
    );

    // Without sinfo (not a Slurm login node, or another scheduler's): no check.
    let _ = std::fs::remove_file(dir.join("sbatch.log"));
    let path = fake_slurm(&dir.join("no-sinfo"), None);
    let (ok, text) = run("deploy/slurm/submit.sh", &args, &dir, &[("PATH", path)]);
    assert!(ok, "{text}");
}

/// The three services of `deploy/service/compose.yaml` are started with command lines
/// `muse serve` takes (every option known, every value in range: with `--help` last, `muse`
/// parses them all, then prints the help and succeeds), each with its own advertised address,
/// on one store; and the example tokens file is one `muse serve --tokens` reads. (Running the
/// file needs a Docker engine; see `deploy/README.md`.)
#[test]
fn the_compose_file_starts_three_services_with_command_lines_muse_takes() {
    let text = std::fs::read_to_string(root().join("deploy/service/compose.yaml")).unwrap();
    let mut stores = std::collections::BTreeSet::new();
    let mut advertised = std::collections::BTreeSet::new();
    for line in text.lines().map(str::trim) {
        let Some(array) = line.strip_prefix("command: ") else {
            continue;
        };
        let args: Vec<String> = serde_json::from_str(array).expect("a JSON array of words");
        if args.first().map(String::as_str) != Some("serve") {
            continue;
        }
        let at = |option: &str| {
            let k = args.iter().position(|a| a == option).unwrap();
            args[k + 1].clone()
        };
        stores.insert(at("--store"));
        advertised.insert(at("--advertise"));
        let out = Command::new(env!("CARGO_BIN_EXE_muse"))
            .args(&args)
            .arg("--help")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(
        (stores.len(), advertised.len()),
        (1, 3),
        "{stores:?} {advertised:?}"
    );
    let tokens = root().join("deploy/service/tokens.example.toml");
    let data = std::env::temp_dir().join(format!("muse-compose-tokens-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(["serve", "--check-store", "--data"])
        .arg(&data)
        .arg("--tokens")
        .arg(&tokens)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&data);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
