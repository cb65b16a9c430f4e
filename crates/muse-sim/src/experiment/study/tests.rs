use super::*;

/// A few options of `muse sweep`, in the shapes a study knows.
fn sweep_options() -> Vec<OptionShape> {
    let shape = |long: &str, takes, path| OptionShape {
        long: long.to_owned(),
        takes,
        path,
    };
    vec![
        shape("counts", Takes::Value, false),
        shape("reps", Takes::Value, false),
        shape("vary", Takes::Repeated, false),
        shape("swap-min", Takes::Value, false),
        shape("zones", Takes::Repeated, true),
        shape("headway-s", Takes::Value, false),
        shape("quick", Takes::Flag, false),
    ]
}

/// A fresh folder under the temporary directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("muse-sim-study-{}-{name}", std::process::id()));
        std::fs::create_dir_all(dir.join("studies")).unwrap();
        Scratch(dir)
    }

    /// Writes `text` as `studies/NAME.toml` and loads it for `command`.
    fn load(&self, name: &str, command: &str, text: &str) -> Result<Study, StudyError> {
        let path = self.0.join("studies").join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        Study::load(&path, command, &sweep_options())
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn options_become_the_command_line_they_stand_for() {
    let scratch = Scratch::new("args");
    let study = scratch
        .load(
            "s",
            "sweep",
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
    let root = &scratch.0;
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
    assert_eq!(study.line_of("reps"), Some(7));
    assert_eq!(study.line_of("seed"), None);
    assert_eq!(study.default_out(), Path::new("out/s"));
    let reference = study.reference();
    assert_eq!(reference.title, "A study");
    assert!(reference.file.ends_with("studies/s.toml"), "{reference:?}");
}

#[test]
fn flags_are_booleans() {
    let scratch = Scratch::new("flags");
    let read = |body: &str| scratch.load("s", "sweep", &format!("title = \"t\"\n[sweep]\n{body}"));
    assert_eq!(
        read("quick = true\nreps = 1").unwrap().args,
        ["--quick", "--reps", "1"]
    );
    assert_eq!(read("quick = false").unwrap().args, Vec::<String>::new());
    let e = read("quick = 1").unwrap_err().to_string();
    assert!(
        e.ends_with("s.toml:3: `quick`: expected true or false"),
        "{e}"
    );
}

#[test]
fn errors_name_the_file_line_and_key() {
    let scratch = Scratch::new("errors");
    for (text, expected) in [
        (
            "title = \"t\"\n[sweep]\ncounts = [1]\nrepz = 3\n",
            "bad.toml:4: `repz`: not an option of `muse sweep` (see `muse sweep --help`)",
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
            "title = \"t\"\n[sweep]\ncounts = { a = 1 }\n",
            "bad.toml:3: `counts`: a table is not an option value",
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
        let e = scratch.load("bad", "sweep", text).unwrap_err().to_string();
        let e = e
            .split_once("studies/")
            .map_or(e.clone(), |(_, rest)| rest.to_owned());
        assert!(
            e.starts_with(expected),
            "{text:?}:\n  got      {e}\n  expected {expected}"
        );
    }
    let missing = Study::load(&scratch.0.join("nowhere.toml"), "sweep", &[]).unwrap_err();
    assert!(
        missing.to_string().starts_with("reading the study ")
            && missing.to_string().contains("nowhere.toml"),
        "{missing}"
    );
}

#[test]
fn a_bench_study_reads_its_own_table() {
    let scratch = Scratch::new("bench");
    let path = scratch.0.join("b.toml");
    std::fs::write(
        &path,
        "title = \"t\"\n[sweep]\nreps = 1\n[bench]\nrequests = [5000, 10000]\nseed = 2\n",
    )
    .unwrap();
    let options = ["requests", "seed"].map(|long| OptionShape {
        long: long.to_owned(),
        takes: Takes::Value,
        path: false,
    });
    let study = Study::load(&path, "bench", &options).unwrap();
    assert_eq!(study.args, ["--requests", "5000,10000", "--seed", "2"]);
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
