use super::*;

use crate::cli::bench::BenchArgs;
use crate::cli::sweep::SweepArgs;

fn sweep_cmd() -> Command {
    SweepArgs::augment_args(Command::new("sweep"))
}

/// Writes `text` as `studies/NAME.toml` in a fresh folder and loads it for `sweep`.
fn load_text(name: &str, text: &str) -> anyhow::Result<Study> {
    let dir = std::env::temp_dir().join(format!("muse-study-{}-{name}", std::process::id()));
    std::fs::create_dir_all(dir.join("studies")).unwrap();
    let path = dir.join("studies").join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let out = load(&path, &sweep_cmd());
    std::fs::remove_dir_all(&dir).unwrap();
    out
}

/// The error of loading `text`, with the temporary folder cut off.
fn error(text: &str) -> String {
    let e = load_text("bad", text).unwrap_err().to_string();
    e.split_once("studies/")
        .map_or(e.clone(), |(_, rest)| rest.to_owned())
}

#[test]
fn the_shapes_of_the_sweep_options() {
    let shapes = shapes(&sweep_cmd());
    let shape = |long: &str| shapes.iter().find(|s| s.long == long).cloned();
    assert_eq!(shape("vary").map(|s| s.takes), Some(Takes::Repeated));
    assert_eq!(shape("dry-run").map(|s| s.takes), Some(Takes::Flag));
    assert_eq!(shape("counts").map(|s| s.takes), Some(Takes::Value));
    assert_eq!(shape("swap-min").map(|s| s.takes), Some(Takes::Value));
    assert!(shape("zones").is_some_and(|s| s.path && s.takes == Takes::Repeated));
    assert!(shape("count").is_none(), "hidden");
}

#[test]
fn a_study_parses_into_the_command_it_stands_for() {
    let study = load_text(
        "s",
        "title = \"A study\"\n[sweep]\ncounts = [100, 250]\nreps = 3\nvary = [\"battery-swap\"]\nswap-min = [2, 0.5]\n",
    )
    .unwrap();
    let args: SweepArgs = parse(&study, "sweep", &["--out".into(), "o".into()]).unwrap();
    assert_eq!((args.reps, args.counts.as_str()), (3, "100,250"));
    assert_eq!(args.levers.given(), [("swap-min", "2,0.5".to_owned())]);
    assert_eq!(args.out, PathBuf::from("o"));
}

#[test]
fn values_the_command_refuses_are_reported_at_their_line() {
    for (text, expected) in [
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
            "title = \"t\"\n[sweep]\nrepz = 5\n",
            "bad.toml:3: `repz`: not an option of `muse sweep` (see `muse sweep --help`)",
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
fn given_beside_a_study_only_how_it_is_run() {
    let dir = std::env::temp_dir().join(format!("muse-study-beside-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("s.toml");
    std::fs::write(&path, "title = \"t\"\n[sweep]\nreps = 2\n").unwrap();
    let study = load(&path, &sweep_cmd()).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let shown = path.display().to_string();
    let matches = |argv: &[&str]| sweep_cmd().try_get_matches_from(argv).unwrap();
    let ok = matches(&[
        "sweep",
        "--study",
        &shown,
        "--shard",
        "1/2",
        "--out",
        "o",
        "--threads",
        "1",
    ]);
    refuse_overrides(&study, &sweep_cmd(), &ok).unwrap();
    assert_eq!(out(&study, &ok, Path::new("o")), PathBuf::from("o"));
    let default = matches(&["sweep", "--study", &shown]);
    assert_eq!(
        out(&study, &default, Path::new("out/sweep")),
        PathBuf::from("out/s")
    );
    let e = refuse_overrides(
        &study,
        &sweep_cmd(),
        &matches(&[
            "sweep",
            "--study",
            &shown,
            "--reps",
            "5",
            "--od",
            "in-range",
            "--swap-min",
            "3",
        ]),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with(&format!(
            "--reps, --swap-min, --od are set by the study {shown}"
        )),
        "{e}"
    );
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
            let study = load(&path, &BenchArgs::augment_args(Command::new("bench"))).unwrap();
            parse::<BenchArgs>(&study, "bench", &extra).unwrap();
        } else {
            let study = load(&path, &sweep_cmd()).unwrap();
            parse::<SweepArgs>(&study, "sweep", &extra).unwrap();
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
