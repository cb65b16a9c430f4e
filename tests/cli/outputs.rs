//! Outputs never clobber (docs/reference.md#outputs): an output that is a device, a FIFO or
//! a symbolic link is refused, and so is one that is an input of the run or another output
//! of it; `-` is standard output for a single file and refused for a folder; a folder is
//! written whole, so that a rerun never mixes files of two runs and a killed run leaves
//! nothing that looks whole. Each case exits 2, names what is wrong and leaves nothing
//! behind.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `muse` in `dir`.
fn muse(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("muse runs")
}

/// Runs `muse` in `dir` and expects success; its stdout.
fn ok(dir: &Path, args: &[&str]) -> String {
    let o = muse(dir, args);
    assert!(
        o.status.success(),
        "muse {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs `muse` in `dir` and expects exit 2 with `message` on stderr.
fn refused(dir: &Path, args: &[&str], message: &str) {
    let o = muse(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "muse {args:?}: {err}");
    assert!(err.contains(message), "muse {args:?}: {err}");
}

/// A fresh folder under the target directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("outputs_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// The names in `dir`, sorted (hidden ones too).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("a folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_device_is_refused_and_left_alone() {
    use std::os::unix::fs::FileTypeExt as _;
    let dir = scratch("device");
    for dev in ["/dev/null", "/dev/full"] {
        refused(
            &dir,
            &["demand", "--count", "5", "--out", dev],
            &format!("--out {dev} is a character device; give a regular file path"),
        );
        refused(
            &dir,
            &["simulate", "--count", "5", "--out", dev],
            &format!("--out {dev} is a character device; give a folder path"),
        );
        let t = std::fs::symlink_metadata(dev).expect("device").file_type();
        assert!(t.is_char_device(), "{dev} is still a device");
    }
    assert!(names(&dir).is_empty(), "left {:?}", names(&dir));
}

#[test]
fn a_fifo_is_refused_and_left_alone() {
    use std::os::unix::fs::FileTypeExt as _;
    let dir = scratch("fifo");
    let made = Command::new("mkfifo")
        .arg("pipe")
        .current_dir(&dir)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    refused(
        &dir,
        &["demand", "--count", "5", "--out", "pipe"],
        "--out pipe is a FIFO (named pipe); give a regular file path",
    );
    refused(
        &dir,
        &["view", "--plans", "nowhere.jsonl", "--out", "pipe"],
        "--out pipe is a FIFO",
    );
    refused(
        &dir,
        &["plan", "--requests", "r.csv", "--out", "pipe"],
        "--out pipe is a FIFO (named pipe); give a folder path",
    );
    let t = std::fs::symlink_metadata(dir.join("pipe")).expect("fifo");
    assert!(t.file_type().is_fifo(), "still a FIFO");
    assert_eq!(names(&dir), ["pipe"]);
}

#[test]
fn a_symbolic_link_is_refused_not_followed() {
    let dir = scratch("symlink");
    std::fs::write(dir.join("mine.csv"), "my data").expect("file");
    std::os::unix::fs::symlink("mine.csv", dir.join("link.csv")).expect("link");
    std::os::unix::fs::symlink("nowhere.csv", dir.join("dangling.csv")).expect("link");
    std::fs::create_dir(dir.join("mine")).expect("folder");
    std::os::unix::fs::symlink("mine", dir.join("linked")).expect("link");
    for link in ["link.csv", "dangling.csv"] {
        refused(
            &dir,
            &["demand", "--count", "5", "--out", link],
            &format!("--out {link} is a symbolic link; give a regular file path"),
        );
    }
    refused(
        &dir,
        &[
            "airspace",
            "export",
            "--out",
            "x.geojson",
            "--zones-out",
            "link.csv",
        ],
        "--zones-out link.csv is a symbolic link",
    );
    refused(
        &dir,
        &["simulate", "--count", "5", "--out", "linked"],
        "--out linked is a symbolic link; give a folder path",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("mine.csv")).expect("file"),
        "my data"
    );
    for link in ["link.csv", "dangling.csv", "linked"] {
        let m = std::fs::symlink_metadata(dir.join(link)).expect("link");
        assert!(m.is_symlink(), "{link} is still a link");
    }
    assert!(names(&dir.join("mine")).is_empty());
    assert_eq!(
        names(&dir),
        ["dangling.csv", "link.csv", "linked", "mine", "mine.csv"]
    );
}

#[test]
fn an_output_never_replaces_an_input() {
    let dir = scratch("input");
    ok(&dir, &["simulate", "--count", "40", "--out", "day"]);
    let plans = std::fs::read_to_string(dir.join("day/plans.jsonl")).expect("plans");
    let summary = std::fs::read_to_string(dir.join("day/summary.json")).expect("summary");
    refused(
        &dir,
        &[
            "view",
            "--plans",
            "day/plans.jsonl",
            "--out",
            "day/plans.jsonl",
        ],
        "--out day/plans.jsonl is the input --plans day/plans.jsonl",
    );
    // The summary read from beside the plans is an input too.
    refused(
        &dir,
        &[
            "view",
            "--plans",
            "day/plans.jsonl",
            "--out",
            "day/summary.json",
        ],
        "--out day/summary.json is the input the summary beside --plans",
    );
    // A run's folder is replaced whole: it may not hold the run's input.
    refused(
        &dir,
        &["plan", "--requests", "day/requests.csv", "--out", "day"],
        "--out day holds the input --requests day/requests.csv",
    );
    refused(
        &dir,
        &[
            "simulate",
            "--requests",
            "./day/requests.csv",
            "--out",
            "day",
        ],
        "--out day holds the input --requests ./day/requests.csv",
    );
    // Merging a shard into its own folder would remove the shard.
    ok(
        &dir,
        &[
            "sweep", "--counts", "5", "--reps", "1", "--shard", "0/1", "--out", "s0",
        ],
    );
    refused(
        &dir,
        &["sweep", "merge", "s0", "--out", "s0"],
        "--out s0 holds the input the shard s0/shard.json",
    );
    assert_eq!(names(&dir.join("s0")), ["shard.json"]);
    ok(&dir, &["airspace", "export", "--out", "a.geojson"]);
    refused(
        &dir,
        &[
            "demand",
            "--count",
            "5",
            "--airspace",
            "a.geojson",
            "--out",
            "a.geojson",
        ],
        "--out a.geojson is the input --airspace a.geojson",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("day/plans.jsonl")).expect("plans"),
        plans
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("day/summary.json")).expect("summary"),
        summary
    );
    assert_eq!(
        names(&dir.join("day")),
        [
            "flights.csv",
            "flights.geojson",
            "map.svg",
            "plans.jsonl",
            "requests.csv",
            "stays.csv",
            "summary.json",
            "view.html"
        ]
    );
    assert_eq!(names(&dir), ["a.geojson", "day", "s0"]);
}

#[test]
fn two_outputs_of_one_run_never_name_the_same_file() {
    let dir = scratch("same");
    refused(
        &dir,
        &[
            "airspace",
            "export",
            "--out",
            "x.geojson",
            "--zones-out",
            "x.geojson",
        ],
        "--out and --zones-out both name x.geojson",
    );
    refused(
        &dir,
        &[
            "airspace",
            "export",
            "--out",
            "./x.geojson",
            "--zones-out",
            "x.geojson",
        ],
        "--out and --zones-out both name ./x.geojson",
    );
    refused(
        &dir,
        &["airspace", "export", "--out", "-", "--zones-out", "-"],
        "--out and --zones-out both name standard output",
    );
    assert!(names(&dir).is_empty(), "left {:?}", names(&dir));
    ok(
        &dir,
        &[
            "airspace",
            "export",
            "--out",
            "x.geojson",
            "--zones-out",
            "z.geojson",
        ],
    );
    refused(
        &dir,
        &[
            "airspace",
            "export",
            "--out",
            "x.geojson",
            "--zones-out",
            "x.geojson",
        ],
        "--out and --zones-out both name x.geojson",
    );
    let airspace = std::fs::read_to_string(dir.join("x.geojson")).expect("airspace");
    assert!(airspace.contains("\"S077\""), "the airspace, not the zones");
    assert_eq!(names(&dir), ["x.geojson", "z.geojson"]);
}

#[test]
fn a_dash_is_standard_output_for_one_file_only() {
    let dir = scratch("stdout");
    let o = muse(
        &dir,
        &["demand", "--count", "5", "--seed", "3", "--out", "-"],
    );
    assert!(o.status.success());
    let csv = String::from_utf8_lossy(&o.stdout);
    assert!(
        csv.starts_with("id,origin,destination,departure\n"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 6, "{csv}");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("to standard output"), "{err}");

    let o = muse(&dir, &["airspace", "export", "--out", "-"]);
    assert!(o.status.success());
    let geojson: serde_json::Value = serde_json::from_slice(&o.stdout).expect("GeoJSON alone");
    assert_eq!(geojson["type"], "FeatureCollection");

    ok(&dir, &["simulate", "--count", "20", "--out", "day"]);
    let o = muse(&dir, &["view", "--plans", "day/plans.jsonl", "--out", "-"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("<!doctype html>"));

    for command in [
        &["simulate", "--count", "5", "--out", "-"][..],
        &["plan", "--requests", "day/requests.csv", "--out", "-"],
        &["sweep", "--counts", "5", "--reps", "1", "--out", "-"],
        &["bench", "--requests", "10", "--out", "-"],
        &["airspace", "build", "--out", "-"],
    ] {
        refused(
            &dir,
            command,
            "standard output takes a single file; give a folder path",
        );
    }
    assert_eq!(names(&dir), ["day"], "no file named -");
}

/// A file output's folder is checked before any work, naming the option: a path ending in
/// `/` (a folder's path) and a missing folder are refused for every command that writes one
/// file, and `muse airspace build --out DIR` checks its folder before building.
#[test]
fn a_file_outputs_folder_is_checked_before_the_work() {
    let dir = scratch("file_folder");
    ok(&dir, &["simulate", "--count", "20", "--out", "day"]);
    let pads = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/pads.csv");
    let plans = "day/plans.jsonl";
    let commands: [&[&str]; 8] = [
        &["demand", "--count", "5"],
        &["view", "--plans", plans],
        &["airspace", "map"],
        &["airspace", "export"],
        &["airspace", "build", "--pads", pads],
        &["export", "bluesky", "--plans", plans],
        &["export", "f3548", "--plans", plans, "--buffer-m", "10"],
        &["load", "--url", "http://127.0.0.1:9", "--count", "5"],
    ];
    for command in commands {
        let run = |out: &str, message: &str| {
            let mut args = command.to_vec();
            args.extend_from_slice(&["--out", out]);
            refused(&dir, &args, message);
        };
        run(
            "nodir/",
            "--out nodir/ ends with /, a folder's path: give the path of the file to write",
        );
        run(
            "nodir/x.out",
            "--out nodir/x.out: its folder nodir does not exist: make it first, or give another \
             path",
        );
    }
    refused(
        &dir,
        &[
            "airspace",
            "export",
            "--out",
            "x.geojson",
            "--zones-out",
            "nodir/",
        ],
        "--zones-out nodir/ ends with /",
    );
    std::fs::write(dir.join("afile"), "mine\n").expect("a file");
    refused(
        &dir,
        &["airspace", "build", "--out", "afile"],
        "--out afile is a regular file; give a folder path",
    );
    refused(
        &dir,
        &["airspace", "build", "--out", "afile/sub"],
        "--out afile/sub: ",
    );
    assert_eq!(names(&dir), ["afile", "day"]);
}

#[test]
fn a_folder_never_holds_files_of_two_runs() {
    let dir = scratch("two_runs");
    ok(
        &dir,
        &[
            "demand",
            "--count",
            "30",
            "--seed",
            "2",
            "--out",
            "seed2.csv",
        ],
    );
    ok(
        &dir,
        &["simulate", "--count", "30", "--seed", "1", "--out", "day"],
    );
    ok(
        &dir,
        &[
            "sweep",
            "--counts",
            "5",
            "--reps",
            "1",
            "--out",
            "day/sweep",
        ],
    );
    // Planning other requests into the folder: only this run's files remain (no view.html
    // of seed 1 beside seed 2's plans); the folder of the sweep inside is kept.
    ok(&dir, &["plan", "--requests", "seed2.csv", "--out", "day"]);
    assert_eq!(
        names(&dir.join("day")),
        [
            "flights.csv",
            "plans.jsonl",
            "stays.csv",
            "summary.json",
            "sweep"
        ]
    );
    let summary = std::fs::read_to_string(dir.join("day/summary.json")).expect("summary");
    assert!(summary.contains("seed2.csv"), "{summary}");
    assert!(dir.join("day/sweep/sweep_summary.csv").is_file());
    ok(
        &dir,
        &["simulate", "--count", "30", "--seed", "2", "--out", "day"],
    );
    let summary = std::fs::read_to_string(dir.join("day/summary.json")).expect("summary");
    assert!(summary.contains("\"seed\": 2"), "{summary}");
    assert_eq!(
        names(&dir.join("day")).len(),
        9,
        "{:?}",
        names(&dir.join("day"))
    );
    assert_eq!(names(&dir), ["day", "seed2.csv"], "nothing left beside it");

    // A folder that is not an earlier run's is refused and left as it is.
    std::fs::create_dir(dir.join("mine")).expect("folder");
    std::fs::write(dir.join("mine/notes.txt"), "my notes").expect("file");
    std::fs::write(dir.join("mine/plans.jsonl"), "my plans").expect("file");
    refused(
        &dir,
        &["simulate", "--count", "5", "--out", "mine"],
        "--out mine holds notes.txt (a regular file), which no muse run writes",
    );
    assert_eq!(names(&dir.join("mine")), ["notes.txt", "plans.jsonl"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("mine/plans.jsonl")).expect("file"),
        "my plans"
    );
    assert_eq!(names(&dir), ["day", "mine", "seed2.csv"]);
}

#[test]
fn a_killed_run_leaves_nothing_that_looks_whole() {
    use std::os::unix::process::ExitStatusExt as _;
    let dir = scratch("killed");
    // A day of 300,000 requests takes far longer to plan than the wait below.
    let (mut child, temp) =
        started_folder_run(&dir, &["simulate", "--count", "300000", "--out", "day"]);
    child.kill().expect("SIGKILL");
    let status = child.wait().expect("reaped");
    assert_eq!(status.signal(), Some(9), "ended before the kill: {status}");
    // Nothing at the output path; only the temporary folder, named as such.
    assert_eq!(names(&dir), [temp]);
    // A rerun writes the folder whole and removes what the killed run left.
    ok(&dir, &["simulate", "--count", "20", "--out", "day"]);
    assert_eq!(names(&dir), ["day"]);
    assert!(dir.join("day/summary.json").is_file());
}

/// `muse ARGS` (its last argument the output folder) started in `dir`, once its temporary
/// folder exists and 200 ms more have passed; with the temporary folder's name. Its standard
/// error is piped, its standard output dropped.
fn started_folder_run(dir: &Path, args: &[&str]) -> (std::process::Child, String) {
    let child = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("muse starts");
    let out = args[args.len() - 1];
    let temp = format!(".{out}.partial-{}", child.id());
    let started = std::time::Instant::now();
    while !dir.join(&temp).is_dir() {
        assert!(
            started.elapsed().as_secs() < 10,
            "no {temp} after 10 s: {:?}",
            names(dir)
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    (child, temp)
}

/// A run interrupted by SIGTERM or SIGINT (Ctrl-C) removes its temporary folder and exits
/// with the conventional 128 + the signal's number: 143 and 130.
#[test]
fn an_interrupted_run_removes_its_temporary_folder() {
    let dir = scratch("interrupted");
    // Days of 300,000 requests (50 of them for the sweep) take far longer than the wait below.
    let runs: [(&[&str], &str, i32); 3] = [
        (
            &["simulate", "--count", "300000", "--out", "day"],
            "TERM",
            143,
        ),
        (
            &["simulate", "--count", "300000", "--out", "day"],
            "INT",
            130,
        ),
        (
            &[
                "sweep", "--counts", "300000", "--reps", "50", "--out", "sweep",
            ],
            "TERM",
            143,
        ),
    ];
    for (args, signal, code) in runs {
        let (child, _) = started_folder_run(&dir, args);
        let sent = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(sent.success());
        let ended = child.wait_with_output().expect("reaped");
        let err = String::from_utf8_lossy(&ended.stderr);
        assert_eq!(
            ended.status.code(),
            Some(code),
            "{args:?} SIG{signal}: {err}"
        );
        assert!(
            err.contains(&format!("interrupted by SIG{signal}")),
            "{err}"
        );
        assert_eq!(names(&dir), Vec::<String>::new(), "{args:?} SIG{signal}");
    }
}

/// `muse verify … | head`: a reader that goes away before the report is written closes the
/// pipe; verify stops quietly (no panic) and its exit code still says what it found.
#[test]
fn verify_into_a_closed_pipe_stops_quietly_with_its_verdict() {
    use std::process::{Command, Stdio};
    let dir = crate::support::scratch_dir("verify-closed-pipe");
    std::fs::create_dir_all(&dir).unwrap();
    let sim = dir.join("sim");
    let o = crate::run::muse(&["simulate", "--count", "300", "--out", sim.to_str().unwrap()]);
    assert!(o.status.success(), "{}", crate::run::said(&o));
    // Every flight twice, under another id: each meets its copy, hundreds of violations.
    let plans = std::fs::read_to_string(sim.join("plans.jsonl")).unwrap();
    let twice = plans.clone() + &plans.replace("\"request\":\"r", "\"request\":\"copy-r");
    let doubled = dir.join("doubled.jsonl");
    std::fs::write(&doubled, twice).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(["verify", "--plans", doubled.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader is gone before the report is written
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(1), "{err}");
}
