use super::*;

use crate::cli::bench::BenchArgs;
use crate::cli::sweep::SweepArgs;

fn sweep_cmd() -> Command {
    SweepArgs::augment_args(Command::new("sweep"))
}

/// Writes `text` as `name` in a fresh folder under the target dir and loads it for `sweep`.
fn load(name: &str, text: &str) -> anyhow::Result<Study> {
    let dir = std::env::temp_dir().join(format!("muse-study-{}-{name}", std::process::id()));
    std::fs::create_dir_all(dir.join("studies")).unwrap();
    let path = dir.join("studies").join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let out = Study::load(&path, &sweep_cmd());
    std::fs::remove_dir_all(&dir).unwrap();
    out
}

/// The error of loading `text`, with the temporary folder cut off.
fn error(text: &str) -> String {
    let e = load("bad", text).unwrap_err().to_string();
    e.split_once("studies/")
        .map_or(e.clone(), |(_, rest)| rest.to_owned())
}

#[test]
fn options_become_the_command_line_they_stand_for() {
    let study = load(
        "s",
        r#"
title = "A study"
results = "../docs/results/x"

[sweep]
counts = [100, 250]
reps = 3
vary = ["zones", "edge-rule"]
swap-min = [2, 0.5]
zones = ["../scenarios/cbd.geojson", "none", "/abs/z.json"]
headway-s = 5.5
"#,
    )
    .unwrap();
    assert_eq!(study.title, "A study");
    let dir = study.path.parent().unwrap();
    let root = dir.parent().unwrap();
    assert_eq!(study.results, Some(root.join("docs/results/x")));
    let cbd = root.join("scenarios/cbd.geojson").display().to_string();
    // Keys in order; a list of a repeatable option repeats it, any other list is joined.
    assert_eq!(
        study.args,
        [
            "--counts",
            "100,250",
            "--headway-s",
            "5.5",
            "--reps",
            "3",
            "--swap-min",
            "2,0.5",
            "--vary",
            "zones",
            "--vary",
            "edge-rule",
            "--zones",
            &cbd,
            "--zones",
            "none",
            "--zones",
            "/abs/z.json",
        ]
    );
    assert_eq!(
        study.command_line("sweep", &["--out".into(), "o".into()])[..3],
        ["sweep", "--counts", "100,250"]
    );
    let args: SweepArgs = study.parse("sweep", &["--out".into(), "o".into()]).unwrap();
    assert_eq!((args.reps, args.counts.as_str()), (3, "100,250"));
    assert_eq!(args.out, PathBuf::from("o"));
}

#[test]
fn flags_are_booleans() {
    let cmd = Command::new("x")
        .arg(
            clap::Arg::new("quick")
                .long("quick")
                .action(ArgAction::SetTrue),
        )
        .arg(clap::Arg::new("n").long("n"));
    let dir = std::env::temp_dir().join(format!("muse-study-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("s.toml");
    let read = |body: &str| {
        std::fs::write(&path, format!("title = \"t\"\n[sweep]\n{body}")).unwrap();
        Study::load(&path, &cmd.clone().name("sweep"))
    };
    assert_eq!(
        read("quick = true\nn = 1").unwrap().args,
        ["--n", "1", "--quick"]
    );
    assert_eq!(read("quick = false").unwrap().args, Vec::<String>::new());
    let e = read("quick = 1").unwrap_err().to_string();
    assert!(
        e.ends_with("s.toml:3: `quick`: expected true or false"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn errors_name_the_file_line_and_key() {
    for (text, expected) in [
        (
            "title = \"t\"\n[sweep]\ncounts = [1]\nrepz = 3\n",
            "bad.toml:4: `repz`: not an option of `muse sweep` (see `muse sweep --help`)",
        ),
        (
            "title = \"t\"\n\n[sweep]\nreps = \"x\"\n",
            "bad.toml:4: `reps`: invalid value 'x' for '--reps <REPS>': must be a whole number of repetitions from 1 to 10000",
        ),
        (
            "title = \"t\"\n[sweep]\nvary = [\"zones\", \"nope\"]\n",
            "bad.toml:3: `vary`: invalid value 'nope' for '--vary <VARY>'",
        ),
        (
            "title = \"t\"\n[sweep]\ncount = 5\n",
            "bad.toml:3: `count`: not an option of `muse sweep` (see `muse sweep --help`)",
        ),
        (
            "title = \"t\"\n[sweep]\nout = \"x\"\n",
            "bad.toml:3: `out`: how a study is run is not part of it: give --out on the command line",
        ),
        (
            "title = \"t\"\n[sweep]\nshard = \"0/2\"\n",
            "bad.toml:3: `shard`: how a study is run is not part of it: give --shard on the command line",
        ),
        (
            "title = \"t\"\n[sweep]\ndry-run = true\n",
            "bad.toml:3: `dry-run`: how a study is run is not part of it: give --dry-run on the command line",
        ),
        (
            "title = \"t\"\n[sweep]\ncounts = [[1]]\n",
            "bad.toml:3: `counts`: a list inside a list is not an option value",
        ),
        (
            "title = \"t\"\n[sweep]\ncounts = [1, 2\n",
            "bad.toml:3: unclosed array, expected `]`",
        ),
        ("[sweep]\nreps = 2\n", "bad.toml:1: missing field `title`"),
        (
            "title = \"t\"\ncolour = 1\n[sweep]\n",
            "bad.toml:2: unknown field `colour`, expected one of `title`, `description`, `results`, `sweep`, `bench`",
        ),
        (
            "title = \"t\"\n[bench]\nseed = 2\n",
            "bad.toml: no [sweep] table: this study is for `muse bench`: run `muse bench --study",
        ),
        (
            "title = \"t\"\n",
            "bad.toml: no [sweep] table: a study for `muse sweep` sets its options in [sweep]",
        ),
    ] {
        let e = error(text);
        assert!(
            e.starts_with(expected),
            "{text:?}:\n  got      {e}\n  expected {expected}"
        );
    }
}

#[test]
fn a_bench_study_reads_its_own_table() {
    let dir = std::env::temp_dir().join(format!("muse-study-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("b.toml");
    std::fs::write(
        &path,
        "title = \"t\"\n[sweep]\nreps = 1\n[bench]\nrequests = [5000, 10000]\nseed = 2\n",
    )
    .unwrap();
    let study = Study::load(&path, &BenchArgs::augment_args(Command::new("bench"))).unwrap();
    assert_eq!(study.args, ["--requests", "5000,10000", "--seed", "2"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn given_beside_a_study_only_how_it_is_run() {
    let study = Study {
        path: "s.toml".into(),
        title: "t".into(),
        results: None,
        args: vec![],
    };
    let matches = |argv: &[&str]| sweep_cmd().try_get_matches_from(argv).unwrap();
    let ok = matches(&[
        "sweep",
        "--study",
        "s.toml",
        "--shard",
        "1/2",
        "--out",
        "o",
        "--threads",
        "1",
    ]);
    study.refuse_overrides(&sweep_cmd(), &ok).unwrap();
    assert_eq!(study.out(&ok, Path::new("o")), PathBuf::from("o"));
    let default = matches(&["sweep", "--study", "s.toml"]);
    assert_eq!(
        study.out(&default, Path::new("out/sweep")),
        PathBuf::from("out/s")
    );
    let e = study
        .refuse_overrides(
            &sweep_cmd(),
            &matches(&[
                "sweep", "--study", "s.toml", "--reps", "5", "--od", "in-range",
            ]),
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("--reps, --od are set by the study s.toml"),
        "{e}"
    );
}

#[test]
fn paths_are_normalized_lexically() {
    assert_eq!(
        normalize(Path::new("studies/../scenarios/a.json")),
        PathBuf::from("scenarios/a.json")
    );
    assert_eq!(normalize(Path::new("./a/./b")), PathBuf::from("a/b"));
    assert_eq!(normalize(Path::new("../a")), PathBuf::from("../a"));
    assert_eq!(normalize(Path::new("a/..")), PathBuf::from("."));
    assert_eq!(normalize(Path::new("/x/../y")), PathBuf::from("/y"));
}

#[test]
fn published_results_are_compared_without_the_times() {
    let a = "variant,count,success,planner_ms_mean\nv,1,0.5,2.0\nv,2,0.4,3.0\n";
    assert_eq!(first_difference(a, a, sweep_time_column), None);
    let retimed = "variant,count,success,planner_ms_mean\nv,1,0.5,9.0\nv,2,0.4,1.0\n";
    assert_eq!(first_difference(a, retimed, sweep_time_column), None);
    let other = "variant,count,success,planner_ms_mean\nv,1,0.5,2.0\nv,2,0.3,3.0\n";
    assert_eq!(
        first_difference(a, other, sweep_time_column).unwrap(),
        "1 of 2 rows differ; first at line 3, column success: published 0.4, now 0.3"
    );
    let short = "variant,count,success,planner_ms_mean\nv,1,0.5,2.0\n";
    assert_eq!(
        first_difference(a, short, sweep_time_column).unwrap(),
        "2 rows published, 1 now"
    );
    let wider = "variant,count,success,planner_ms_mean,legs\nv,1,0.5,2.0,1\nv,2,0.4,3.0,1\n";
    assert_eq!(
        first_difference(a, wider, sweep_time_column).unwrap(),
        "the columns differ (only published: none; only now: legs)"
    );
    // A quoted name with a comma is one cell.
    let quoted = "variant,count\n\"zones A,B\",1\n";
    assert_eq!(first_difference(quoted, quoted, sweep_time_column), None);
}

#[test]
fn every_committed_study_reads_and_parses() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension() != Some("toml".as_ref()) {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let extra = ["--out".to_owned(), "o".to_owned()];
        if text.contains("\n[bench]") {
            let cmd = BenchArgs::augment_args(Command::new("bench"));
            let study = Study::load(&path, &cmd).unwrap();
            study.parse::<BenchArgs>("bench", &extra).unwrap();
        } else {
            let study = Study::load(&path, &sweep_cmd()).unwrap();
            study.parse::<SweepArgs>("sweep", &extra).unwrap();
            let results = study.results.expect("a committed study names its results");
            assert!(
                results.is_dir(),
                "{}: {}",
                path.display(),
                results.display()
            );
        }
        seen += 1;
    }
    assert!(seen >= 9, "{seen} studies in {}", dir.display());
}
