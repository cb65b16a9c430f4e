//! Every example of the user reference, `docs/reference.md`, given to MUSE the way a user
//! would give it: a requests example to `muse plan --requests`, a zones example to `--zones`,
//! a plans example to `muse verify --plans`, a request body to a running `muse serve`. The
//! examples MUSE writes but never reads (`summary.json`, `flights.geojson`, the service's
//! answers) must have exactly the members of a real output made here.
//!
//! # How examples are tagged
//!
//! An example is a fenced code block whose info string is `LANG KIND [OPTION ...]`:
//!
//! - `LANG` is the block's language for the reader (`csv`, `json`, `jsonl`, `geojson`,
//!   `toml`); GitHub highlights by it and ignores the rest;
//! - `KIND` says what the example is and so how it is checked (the table below);
//! - the words after it are command-line options the example goes with (the zones a plans
//!   file was made with, the `muse simulate` options of a summary), passed as they are to the
//!   command that checks it, in the repository root (no quoting: an option holds no space).
//!
//! A block in `sh` or `text` (or with no language) is prose and is not read. Any other block
//! must name a known kind in its own language: a block of data without a kind, an unknown
//! kind and a kind in the wrong language fail every test here, so an example cannot go
//! unchecked by mistake; and at least [`MIN_EXAMPLES`] examples, every kind at least once,
//! must be found.
//!
//! | kind | language | checked by |
//! |---|---|---|
//! | `airspace` | geojson | `muse airspace info --airspace FILE` exits 0 |
//! | `pads` | csv, geojson | `muse airspace build --pads FILE --out A.geojson` exits 0 |
//! | `zones` | json, geojson | `muse airspace info --zones FILE` exits 0 (the zones resolved on the default airspace) |
//! | `requests` | csv | `muse plan --requests FILE` exits 0 |
//! | `plans` | jsonl | `muse verify --plans FILE` exits 0: read, and every rule holds |
//! | `study` | toml | `muse sweep --study FILE --dry-run` exits 0 |
//! | `summary` | json | the members of `summary.json` of `muse simulate OPTIONS` |
//! | `flights` | geojson | the members of `flights.geojson` of `muse simulate OPTIONS` |
//! | `flights-table`, `stays-table` | csv | the header `muse plan` writes in `flights.csv` and `stays.csv`, and as many cells in every row |
//! | `tokens` | toml | `muse_service::Tokens::parse` |
//! | `shard` | json | `muse_sim::experiment::ShardFile::read` |
//! | `sweep-runs`, `sweep-summary`, `lead-runs`, `lead-summary` | csv | the header `muse sweep` writes, and as many cells in every row |
//! | `flight-request`, `zone-announcement` | json | posted to a real `muse serve`: `201` |
//! | `flight`, `flight-list`, `healthz`, `error`, `zone-announced`, `zone-withdrawn`, `closures` | json | the members of the real service's answers in that session |
//!
//! "The members" of a JSON document are the paths of all its object keys (`features[].properties.request`),
//! array elements taken together: an example must have exactly those of the real output, so
//! that it neither invents a field nor leaves one out. Values are not compared.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::Command;

use muse_sim::experiment::{lead, sweep};
use serde_json::Value;

use crate::support::{scratch_dir, start};

/// The reference, relative to the repository root.
const REFERENCE: &str = "docs/reference.md";

/// Fewest examples the reference must hold: a parser that finds none fails.
const MIN_EXAMPLES: usize = 25;

/// The service's clock in the session (the examples' day, before their departures).
const CLOCK: &str = "2026-01-05T07:00:00+08:00";

/// What an example is, and so how it is checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Airspace,
    Pads,
    Zones,
    Requests,
    Plans,
    Study,
    Summary,
    Flights,
    FlightsTable,
    StaysTable,
    Tokens,
    Shard,
    SweepRuns,
    SweepSummary,
    LeadRuns,
    LeadSummary,
    FlightRequest,
    ZoneAnnouncement,
    Flight,
    FlightList,
    Healthz,
    Error,
    ZoneAnnounced,
    ZoneWithdrawn,
    Closures,
    Customers,
}

impl Kind {
    const ALL: [Kind; 26] = [
        Kind::Airspace,
        Kind::Pads,
        Kind::Customers,
        Kind::Zones,
        Kind::Requests,
        Kind::Plans,
        Kind::Study,
        Kind::Summary,
        Kind::Flights,
        Kind::FlightsTable,
        Kind::StaysTable,
        Kind::Tokens,
        Kind::Shard,
        Kind::SweepRuns,
        Kind::SweepSummary,
        Kind::LeadRuns,
        Kind::LeadSummary,
        Kind::FlightRequest,
        Kind::ZoneAnnouncement,
        Kind::Flight,
        Kind::FlightList,
        Kind::Healthz,
        Kind::Error,
        Kind::ZoneAnnounced,
        Kind::ZoneWithdrawn,
        Kind::Closures,
    ];

    /// The kind's name in an info string, and the languages its examples may be written in.
    fn spelling(self) -> (&'static str, &'static [&'static str]) {
        const JSON: &[&str] = &["json"];
        const CSV: &[&str] = &["csv"];
        match self {
            Kind::Airspace => ("airspace", &["geojson"]),
            Kind::Pads => ("pads", &["csv", "geojson"]),
            Kind::Customers => ("customers", CSV),
            Kind::Zones => ("zones", &["json", "geojson"]),
            Kind::Requests => ("requests", CSV),
            Kind::Plans => ("plans", &["jsonl"]),
            Kind::Study => ("study", &["toml"]),
            Kind::Summary => ("summary", JSON),
            Kind::Flights => ("flights", &["geojson"]),
            Kind::FlightsTable => ("flights-table", CSV),
            Kind::StaysTable => ("stays-table", CSV),
            Kind::Tokens => ("tokens", &["toml"]),
            Kind::Shard => ("shard", JSON),
            Kind::SweepRuns => ("sweep-runs", CSV),
            Kind::SweepSummary => ("sweep-summary", CSV),
            Kind::LeadRuns => ("lead-runs", CSV),
            Kind::LeadSummary => ("lead-summary", CSV),
            Kind::FlightRequest => ("flight-request", JSON),
            Kind::ZoneAnnouncement => ("zone-announcement", JSON),
            Kind::Flight => ("flight", JSON),
            Kind::FlightList => ("flight-list", JSON),
            Kind::Healthz => ("healthz", JSON),
            Kind::Error => ("error", JSON),
            Kind::ZoneAnnounced => ("zone-announced", JSON),
            Kind::ZoneWithdrawn => ("zone-withdrawn", JSON),
            Kind::Closures => ("closures", JSON),
        }
    }

    fn name(self) -> &'static str {
        self.spelling().0
    }

    fn parse(name: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether the kind is checked against a running `muse serve`.
    fn served(self) -> bool {
        matches!(
            self,
            Kind::FlightRequest
                | Kind::ZoneAnnouncement
                | Kind::Flight
                | Kind::FlightList
                | Kind::Healthz
                | Kind::Error
                | Kind::ZoneAnnounced
                | Kind::ZoneWithdrawn
                | Kind::Closures
        )
    }

    /// Whether examples of the kind may carry command-line options.
    fn takes_options(self) -> bool {
        matches!(
            self,
            Kind::Airspace
                | Kind::Zones
                | Kind::Requests
                | Kind::Plans
                | Kind::Summary
                | Kind::Flights
        )
    }
}

/// The languages of blocks that are prose, never read.
const PROSE: [&str; 3] = ["", "sh", "text"];

/// One example of the reference.
#[derive(Clone, Debug)]
struct Example {
    /// The line of its opening fence (1-based).
    line: usize,
    kind: Kind,
    /// Command-line options it goes with.
    options: Vec<String>,
    text: String,
}

impl Example {
    /// `docs/reference.md:LINE (KIND)`, for messages.
    fn at(&self) -> String {
        format!("{REFERENCE}:{} ({})", self.line, self.kind.name())
    }
}

/// The examples of a reference's text; an error names the first block that is not a known
/// kind of example in its own language, or a fence left open.
fn examples(text: &str) -> Result<Vec<Example>, String> {
    let mut out = Vec::new();
    let mut open: Option<(usize, Tag, String)> = None;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let Some(info) = line.strip_prefix("```") else {
            if let Some((_, _, body)) = &mut open {
                body.push_str(line);
                body.push('\n');
            }
            continue;
        };
        match open.take() {
            Some((start, tag, body)) => {
                if !info.trim().is_empty() {
                    return Err(format!(
                        "{REFERENCE}:{line_no}: a fence opens inside the block of line {start}"
                    ));
                }
                if let Some((kind, options)) = tag {
                    out.push(Example {
                        line: start,
                        kind,
                        options,
                        text: body,
                    });
                }
            }
            None => open = Some((line_no, tag(info, line_no)?, String::new())),
        }
    }
    if let Some((start, _, _)) = open {
        return Err(format!("{REFERENCE}:{start}: the block is never closed"));
    }
    Ok(out)
}

/// What an opening fence's info string says: `None` for prose, else the kind and options.
type Tag = Option<(Kind, Vec<String>)>;

/// The [`Tag`] of an opening fence's info string, or why it is not a known one.
fn tag(info: &str, line_no: usize) -> Result<Tag, String> {
    let mut words = info.split_whitespace();
    let lang = words.next().unwrap_or("");
    let kind = words.next();
    let options: Vec<String> = words.map(str::to_owned).collect();
    if PROSE.contains(&lang) {
        return match kind {
            None => Ok(None),
            Some(k) => Err(format!(
                "{REFERENCE}:{line_no}: a `{lang}` block is prose and has no kind, yet says `{k}`"
            )),
        };
    }
    let Some(name) = kind else {
        return Err(format!(
            "{REFERENCE}:{line_no}: a `{lang}` example names no kind: tag it (`{lang} KIND`, see \
             tests/reference_examples.rs), or make it `text`"
        ));
    };
    let Some(kind) = Kind::parse(name) else {
        return Err(format!(
            "{REFERENCE}:{line_no}: unknown kind `{name}`; the kinds are {}",
            Kind::ALL.map(Kind::name).join(", ")
        ));
    };
    if !kind.spelling().1.contains(&lang) {
        return Err(format!(
            "{REFERENCE}:{line_no}: a `{name}` example is written in {}, not `{lang}`",
            kind.spelling().1.join(" or ")
        ));
    }
    if !options.is_empty() && !kind.takes_options() {
        return Err(format!(
            "{REFERENCE}:{line_no}: a `{name}` example takes no options, yet says {options:?}"
        ));
    }
    Ok(Some((kind, options)))
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The reference's examples (the test fails here if one is not a known kind).
fn reference_examples() -> Vec<Example> {
    let text = std::fs::read_to_string(root().join(REFERENCE)).expect("docs/reference.md");
    examples(&text).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs `muse` in the repository root; its stdout if it exits 0, else what it said.
fn muse(args: &[String]) -> Result<String, String> {
    let out = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("muse runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!(
            "`muse {}` exited with {}:\n{stdout}{}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// The paths of every object key of a JSON document, array elements taken together.
fn members(v: &Value) -> BTreeSet<String> {
    fn walk(v: &Value, path: &str, out: &mut BTreeSet<String>) {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    let p = format!("{path}.{k}");
                    out.insert(p.clone());
                    walk(x, &p, out);
                }
            }
            Value::Array(items) => {
                for x in items {
                    walk(x, &format!("{path}[]"), out);
                }
            }
            _ => {}
        }
    }
    let mut out = BTreeSet::new();
    walk(v, "", &mut out);
    out
}

/// Whether an example has exactly the members of the real documents of its kind.
fn same_members(example: &Example, real: &[Value]) -> Result<(), String> {
    if real.is_empty() {
        return Err(format!("{}: no real output to compare with", example.at()));
    }
    let mine = members(&parse_json(example)?);
    let theirs: BTreeSet<String> = real.iter().flat_map(members).collect();
    let invented: Vec<&String> = mine.difference(&theirs).collect();
    let missing: Vec<&String> = theirs.difference(&mine).collect();
    if invented.is_empty() && missing.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{}: the example's members differ from a real one's: not in the real output \
             {invented:?}; missing from the example {missing:?}",
            example.at()
        ))
    }
}

fn parse_json(example: &Example) -> Result<Value, String> {
    serde_json::from_str(&example.text).map_err(|e| format!("{}: not JSON: {e}", example.at()))
}

/// Where one test run writes: the examples as files, and the outputs of the commands.
struct Scratch {
    dir: PathBuf,
    /// `muse simulate` outputs by their options: the folder each was written to.
    simulated: HashMap<Vec<String>, PathBuf>,
}

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = scratch_dir(name);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        Scratch {
            dir,
            simulated: HashMap::new(),
        }
    }

    /// Writes an example to a file of its own, named after its line; returns its path.
    fn file(&self, example: &Example, extension: &str) -> String {
        let path = self
            .dir
            .join(format!("example-{}.{extension}", example.line));
        std::fs::write(&path, &example.text).expect("example written");
        path.display().to_string()
    }

    /// The output folder of `muse simulate OPTIONS`, run once per set of options.
    fn simulate(&mut self, options: &[String]) -> Result<PathBuf, String> {
        if let Some(dir) = self.simulated.get(options) {
            return Ok(dir.clone());
        }
        let out = self.dir.join(format!("simulate-{}", self.simulated.len()));
        let mut args = vec!["simulate".to_owned()];
        args.extend(options.iter().cloned());
        args.extend(["--out".to_owned(), out.display().to_string()]);
        muse(&args)?;
        self.simulated.insert(options.to_vec(), out.clone());
        Ok(out)
    }

    /// The real file `name` of `muse simulate` with the example's options, as JSON.
    fn simulated(&mut self, example: &Example, name: &str) -> Result<Value, String> {
        let dir = self.simulate(&example.options)?;
        let text = std::fs::read_to_string(dir.join(name)).map_err(|e| format!("{name}: {e}"))?;
        serde_json::from_str(&text).map_err(|e| format!("{name}: {e}"))
    }
}

/// `muse ARGS FILE OPTIONS` must exit 0.
fn run_on(
    scratch: &Scratch,
    example: &Example,
    args: &[&str],
    extension: &str,
) -> Result<(), String> {
    let mut all: Vec<String> = args.iter().map(|&a| a.to_owned()).collect();
    all.push(scratch.file(example, extension));
    all.extend(example.options.iter().cloned());
    muse(&all)
        .map(drop)
        .map_err(|e| format!("{}: {e}", example.at()))
}

/// A CSV example must have `header` as its first line and as many cells in every row.
fn csv_with_header(example: &Example, header: &str) -> Result<(), String> {
    let first = example.text.lines().next().unwrap_or_default();
    if first != header.trim_end() {
        return Err(format!(
            "{}: the header is not the one muse writes:\n  example: {first}\n  muse:    {}",
            example.at(),
            header.trim_end()
        ));
    }
    let mut reader = csv::Reader::from_reader(example.text.as_bytes());
    let width = reader.headers().map_err(|e| e.to_string())?.len();
    for (i, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("{}: {e}", example.at()))?;
        if record.len() != width {
            return Err(format!(
                "{}: row {} has {} cells",
                example.at(),
                i + 1,
                record.len()
            ));
        }
    }
    Ok(())
}

/// The header of a CSV file of these columns.
fn header<T>(columns: &[muse_sim::experiment::Column<'_, T>]) -> String {
    let names: Vec<&str> = columns.iter().map(|c| c.name).collect();
    names.join(",")
}

/// The header of a summary file.
fn summary_header<R>(spec: &muse_sim::experiment::SummarySpec<R>) -> String {
    muse_sim::experiment::summary_csv(spec, &[]).expect("an empty summary is written")
}

/// Checks one example that needs no service.
fn check(scratch: &mut Scratch, example: &Example) -> Result<(), String> {
    match example.kind {
        Kind::Airspace => run_on(
            scratch,
            example,
            &["airspace", "info", "--airspace"],
            "geojson",
        ),
        Kind::Pads => {
            let out = scratch.dir.join(format!("pads-{}.geojson", example.line));
            let out = out.display().to_string();
            run_on(
                scratch,
                example,
                &["airspace", "build", "--out", &out, "--pads"],
                "txt",
            )
        }
        Kind::Customers => muse_formats::customers::read_customers(&example.text, &example.at())
            .map(|_| ())
            .map_err(|e| e.to_string()),
        Kind::Zones => run_on(scratch, example, &["airspace", "info", "--zones"], "json"),
        Kind::Requests => {
            let out = scratch.dir.join(format!("plan-{}", example.line));
            let out = out.display().to_string();
            run_on(
                scratch,
                example,
                &["plan", "--out", &out, "--requests"],
                "csv",
            )
        }
        Kind::Plans => run_on(scratch, example, &["verify", "--plans"], "jsonl"),
        Kind::Study => {
            let out = scratch.dir.join(format!("study-{}", example.line));
            let out = out.display().to_string();
            run_on(
                scratch,
                example,
                &["sweep", "--dry-run", "--out", &out, "--study"],
                "toml",
            )
        }
        Kind::Summary => {
            let real = scratch.simulated(example, "summary.json")?;
            same_members(example, &[real])
        }
        Kind::Flights => {
            let real = scratch.simulated(example, "flights.geojson")?;
            same_members(example, &[real])
        }
        Kind::Tokens => muse_service::Tokens::parse(&example.text, "example")
            .map(drop)
            .map_err(|e| format!("{}: {e}", example.at())),
        Kind::Shard => {
            use muse_sim::experiment::ShardFile;
            let runs =
                ShardFile::<muse_sim::experiment::sweep::RunRecord>::read(&example.text, "example");
            let leads =
                ShardFile::<muse_sim::experiment::lead::LeadRecord>::read(&example.text, "example");
            match (runs, leads) {
                (Ok(_), _) | (_, Ok(_)) => Ok(()),
                (Err(e), _) => Err(format!("{}: {e}", example.at())),
            }
        }
        Kind::FlightsTable => csv_with_header(
            example,
            &muse_formats::flights_csv::FLIGHTS_COLUMNS.join(","),
        ),
        Kind::StaysTable => {
            csv_with_header(example, &muse_formats::stays_csv::STAYS_COLUMNS.join(","))
        }
        Kind::SweepRuns => csv_with_header(example, &header(&sweep::columns())),
        Kind::SweepSummary => csv_with_header(example, &summary_header(&sweep::summary())),
        Kind::LeadRuns => csv_with_header(example, &header(&lead::columns())),
        Kind::LeadSummary => csv_with_header(example, &summary_header(&lead::summary())),
        served => Err(format!(
            "{}: `{}` is checked by the service",
            example.at(),
            served.name()
        )),
    }
}

/// Checks every example that needs no service; the failures, one per example.
fn check_all(scratch: &mut Scratch, examples: &[Example]) -> Vec<String> {
    examples
        .iter()
        .filter(|e| !e.kind.served())
        .filter_map(|e| check(scratch, e).err())
        .collect()
}

#[test]
fn every_example_is_tagged_and_enough_are_found() {
    let examples = reference_examples();
    assert!(
        examples.len() >= MIN_EXAMPLES,
        "only {} examples found in {REFERENCE} (at least {MIN_EXAMPLES} expected)",
        examples.len()
    );
    let missing: Vec<&str> = Kind::ALL
        .into_iter()
        .filter(|k| !examples.iter().any(|e| e.kind == *k))
        .map(Kind::name)
        .collect();
    assert!(
        missing.is_empty(),
        "no example of {missing:?} in {REFERENCE}"
    );
}

#[test]
fn the_tags_are_checked() {
    let block = |info: &str| format!("text\n```{info}\n{{}}\n```\n");
    let refused = |info: &str| examples(&block(info)).unwrap_err();
    assert!(refused("json zonez").contains("unknown kind `zonez`"));
    assert!(refused("json").contains("names no kind"));
    assert!(refused("csv zones").contains("not `csv`"));
    assert!(refused("yaml zones").contains("not `yaml`"));
    assert!(refused("toml tokens --x").contains("takes no options"));
    assert!(refused("text zones").contains("prose"));
    assert!(
        examples("```json zones\n{}\n")
            .unwrap_err()
            .contains("never closed")
    );
    let found = examples(&block("jsonl plans --battery-swap-s 300")).unwrap();
    assert_eq!(
        (found[0].line, found[0].kind, found[0].options.clone()),
        (
            2,
            Kind::Plans,
            vec!["--battery-swap-s".into(), "300".into()]
        )
    );
    assert!(examples(&block("sh")).unwrap().is_empty());
}

#[test]
fn every_example_outside_the_service_is_read_by_muse() {
    let examples = reference_examples();
    let mut scratch = Scratch::new("reference-examples");
    let failures = check_all(&mut scratch, &examples);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn a_broken_example_fails() {
    let examples = reference_examples();
    let first = |kind: Kind| {
        examples
            .iter()
            .find(|e| e.kind == kind)
            .cloned()
            .unwrap_or_else(|| panic!("an example of {kind:?}"))
    };
    let mut broken = Vec::new();
    let mut break_one = |kind: Kind, from: &str, to: &str| {
        let mut e = first(kind);
        let text = e.text.replacen(from, to, 1);
        assert_ne!(text, e.text, "{}: `{from}` is not in the example", e.at());
        e.text = text;
        broken.push(e);
    };
    // An unknown station, a polygon ring left open, a field no plan has, a member no summary
    // has, a column muse does not write.
    break_one(Kind::Requests, "S040", "S999");
    break_one(Kind::Zones, "[103.84, 1.27]]]", "[103.84, 1.28]]]");
    break_one(Kind::Plans, "\"expanded\"", "\"bogus\":1,\"expanded\"");
    break_one(Kind::Summary, "\"requests\"", "\"bogus\": 1, \"requests\"");
    break_one(Kind::SweepRuns, "variant,", "variants,");
    let mut scratch = Scratch::new("reference-examples-broken");
    let failures = check_all(&mut scratch, &broken);
    assert_eq!(
        failures.len(),
        broken.len(),
        "every broken example fails: {failures:#?}"
    );
}

/// Sends a request to the service; its status and JSON answer.
async fn send(
    http: &reqwest::Client,
    method: reqwest::Method,
    url: String,
    body: Option<&str>,
) -> (u16, Value) {
    let mut r = http.request(method, url);
    if let Some(b) = body {
        r = r
            .header("content-type", "application/json")
            .body(b.to_owned());
    }
    let r = r.send().await.expect("the service answers");
    let code = r.status().as_u16();
    (code, r.json().await.expect("a JSON answer"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_service_takes_the_requests_and_answers_as_the_examples_show() {
    let examples = reference_examples();
    let of = |kind: Kind| examples.iter().filter(move |e| e.kind == kind);
    let data = scratch_dir("reference-examples-serve");
    let server = start(&data, &["--clock", CLOCK]);
    let base = server.base.clone();
    let http = reqwest::Client::new();
    let mut session = Session::default();
    let url = |path: &str| format!("{base}{path}");
    for e in of(Kind::FlightRequest) {
        let answer = send(
            &http,
            reqwest::Method::POST,
            url("/v1/flights"),
            Some(&e.text),
        )
        .await;
        session.expect(e, 201, answer, Kind::Flight);
    }
    for (path, kind) in [
        ("/v1/flights", Kind::FlightList),
        ("/healthz", Kind::Healthz),
    ] {
        let (code, answer) = send(&http, reqwest::Method::GET, url(path), None).await;
        assert_eq!(code, 200, "{path}: {answer}");
        session.real.entry(kind).or_default().push(answer);
    }
    let unknown = r#"{"id": "x", "origin": "S012", "destination": "S999", "departure": "2026-01-05T08:00:00+08:00"}"#;
    let (code, answer) = send(
        &http,
        reqwest::Method::POST,
        url("/v1/flights"),
        Some(unknown),
    )
    .await;
    assert_eq!(code, 422, "{answer}");
    session.real.entry(Kind::Error).or_default().push(answer);
    for e in of(Kind::ZoneAnnouncement) {
        let (code, answer) = send(
            &http,
            reqwest::Method::POST,
            url("/v1/zones"),
            Some(&e.text),
        )
        .await;
        let id = answer["zone"].as_str().map(str::to_owned);
        session.expect(e, 201, (code, answer), Kind::ZoneAnnounced);
        if let Some(id) = id {
            let withdrawn = send(
                &http,
                reqwest::Method::DELETE,
                url(&format!("/v1/zones/{id}")),
                None,
            )
            .await;
            session.expect(e, 200, withdrawn, Kind::ZoneWithdrawn);
        }
    }
    // What the zones close, the one known from the start and those announced above.
    let (code, answer) = send(&http, reqwest::Method::GET, url("/v1/closures"), None).await;
    assert_eq!(code, 200, "/v1/closures: {answer}");
    session.real.entry(Kind::Closures).or_default().push(answer);
    for e in examples.iter().filter(|e| e.kind.served()) {
        if !matches!(e.kind, Kind::FlightRequest | Kind::ZoneAnnouncement) {
            let real = session.real.get(&e.kind).map_or(&[][..], Vec::as_slice);
            if let Err(message) = same_members(e, real) {
                session.failures.push(message);
            }
        }
    }
    drop(server);
    assert!(
        session.failures.is_empty(),
        "{}",
        session.failures.join("\n\n")
    );
}

/// What a session with the service gave: its answers by kind, and what went wrong.
#[derive(Default)]
struct Session {
    real: HashMap<Kind, Vec<Value>>,
    failures: Vec<String>,
}

impl Session {
    /// Keeps `answer` as a real `kind` if its status is `want`, else notes the failure.
    fn expect(&mut self, example: &Example, want: u16, (got, answer): (u16, Value), kind: Kind) {
        if got == want {
            self.real.entry(kind).or_default().push(answer);
        } else {
            self.failures.push(format!(
                "{}: answered {got}, not {want}: {answer}",
                example.at()
            ));
        }
    }
}
