//! Study files: a sweep or a benchmark written down in TOML, so that `muse sweep --study FILE`
//! (or `muse bench --study FILE`) reruns exactly the runs behind a published table.
//!
//! A study names what it reproduces and, in a table named after the command, the command's
//! options by their long names, without the leading `--`:
//!
//! ```toml
//! title = "The paper's experiment"
//! results = "../docs/results/paper"   # where its published files are (optional)
//!
//! [sweep]
//! scenario = "singapore-77"
//! counts = "1000:10000:1000"   # or a list: [3000, 6000, 9000]
//! reps = 100
//! vary = ["zones"]             # options given several times take a list
//! swap-min = [2, 5, 10]        # a list for a comma-separated option is joined with commas
//! ```
//!
//! Paths (zone, airspace files) are read relative to the study file. A study holds what
//! decides the runs; how they are run — `--shard`, `--out`, `--threads` — is given on the
//! command line, and any other option given there beside `--study` is refused, so that a
//! study always means the same runs. Unknown keys, values of the wrong type and options that
//! do not parse are reported with the study's file name, line and key.

use std::ffi::OsString;
use std::path::{Component, Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;
use clap::parser::ValueSource;
use clap::{ArgAction, ArgMatches, Args, Command, FromArgMatches};
use muse_sim::shard::StudyRef;
use serde::Deserialize;
use toml::Spanned;

/// Options that say how a study is run, never what it is (clap ids): allowed beside
/// `--study`, refused inside a study file.
const HOW_TO_RUN: [&str; 5] = ["study", "shard", "out", "threads", "dry_run"];

/// A study file, read.
#[derive(Debug, Clone)]
pub struct Study {
    /// The file.
    pub path: PathBuf,
    /// What it reproduces.
    pub title: String,
    /// Where its published results are (relative to the working directory), if it says.
    pub results: Option<PathBuf>,
    /// The command's options it sets, as command-line arguments (`--reps`, `100`, …).
    pub args: Vec<String>,
}

/// The file's shape: `title`, optional `description` and `results`, and one table of
/// options per command it may be run with.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyToml {
    title: String,
    #[serde(default)]
    #[allow(dead_code)] // read for the reader of the file; checked to be text
    description: Option<String>,
    #[serde(default)]
    results: Option<String>,
    #[serde(default)]
    sweep: Option<Options>,
    #[serde(default)]
    bench: Option<Options>,
}

/// A command's options in a study: key → value, each with its place in the file.
type Options = std::collections::BTreeMap<String, Spanned<toml::Value>>;

impl Study {
    /// Reads the study at `path` for the command `name` (`sweep` or `bench`) whose options
    /// are `T`, and refuses the options given beside it on the command line other than how it
    /// is run (`matches`: the command's own).
    pub fn open<T: Args>(
        path: &Path,
        name: &'static str,
        matches: &ArgMatches,
    ) -> anyhow::Result<Study> {
        let cmd = T::augment_args(Command::new(name));
        let study = Study::load(path, &cmd)?;
        study.refuse_overrides(&cmd, matches)?;
        println!("study {}: {}", path.display(), study.title);
        Ok(study)
    }

    /// Reads the study at `path` for the command `command` (`sweep` or `bench`), whose
    /// options are those of `cmd`.
    pub fn load(path: &Path, cmd: &Command) -> anyhow::Result<Study> {
        let name = path.display().to_string();
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading the study {name}"))?;
        let file: StudyToml = toml::from_str(&text).map_err(|e| located(&name, &text, &e))?;
        let command = cmd.get_name();
        let table = match command {
            "sweep" => file.sweep.as_ref(),
            "bench" => file.bench.as_ref(),
            other => anyhow::bail!("no study is run by `muse {other}`"),
        };
        let Some(table) = table else {
            let has = [
                ("sweep", file.sweep.is_some()),
                ("bench", file.bench.is_some()),
            ]
            .into_iter()
            .find_map(|(c, present)| present.then_some(c));
            anyhow::bail!(
                "{name}: no [{command}] table: {}",
                has.map_or_else(
                    || format!("a study for `muse {command}` sets its options in [{command}]"),
                    |c| format!("this study is for `muse {c}`: run `muse {c} --study {name}`")
                )
            );
        };
        let dir = path.parent().unwrap_or(Path::new(""));
        let line_of_key = |key: &str| table.get(key).map(|v| line_of(&text, v.span().start));
        let mut args = Vec::new();
        for (key, value) in table {
            let at = |msg: String| {
                let line = line_of(&text, value.span().start);
                anyhow::anyhow!("{name}:{line}: `{key}`: {msg}")
            };
            let value = value.get_ref();
            if HOW_TO_RUN.contains(&key.replace('-', "_").as_str()) {
                return Err(at(format!(
                    "how a study is run is not part of it: give --{key} on the command line"
                )));
            }
            let Some(arg) = cmd
                .get_arguments()
                .find(|a| a.get_long() == Some(key.as_str()) && !a.is_hide_set())
            else {
                return Err(at(format!(
                    "not an option of `muse {command}` (see `muse {command} --help`)"
                )));
            };
            option_args(arg, &format!("--{key}"), value, dir, &mut args).map_err(at)?;
        }
        // Parse once here so that a value clap refuses is reported at its line.
        let mut argv = vec![command.to_owned()];
        argv.extend(args.iter().cloned());
        if let Err(e) = cmd.clone().try_get_matches_from(&argv) {
            let key = match e.get(clap::error::ContextKind::InvalidArg) {
                Some(clap::error::ContextValue::String(s)) => s
                    .trim_start_matches('-')
                    .split([' ', '='])
                    .next()
                    .map(str::to_owned),
                _ => None,
            };
            let at = key
                .as_deref()
                .and_then(|k| Some(format!("{}: `{k}`", line_of_key(k)?)))
                .unwrap_or_else(|| format!("[{command}]"));
            let message = e.to_string();
            let first = message.lines().next().unwrap_or_default();
            anyhow::bail!("{name}:{at}: {}", first.trim_start_matches("error: "));
        }
        Ok(Study {
            path: path.to_owned(),
            title: file.title,
            results: file.results.map(|r| normalize(&dir.join(r))),
            args,
        })
    }

    /// Refuses options of `cmd` given on the command line beside `--study` other than how it
    /// is run (`matches`: the command's own).
    pub fn refuse_overrides(&self, cmd: &Command, matches: &ArgMatches) -> anyhow::Result<()> {
        let given: Vec<String> = cmd
            .get_arguments()
            .map(|a| a.get_id().as_str())
            .filter(|id| !HOW_TO_RUN.contains(id))
            .filter(|id| matches.value_source(id) == Some(ValueSource::CommandLine))
            .map(|id| format!("--{}", id.replace('_', "-")))
            .collect();
        if !given.is_empty() {
            anyhow::bail!(
                "{} {} set by the study {}: edit the study (or run without --study); beside --study give only --shard, --out, --threads and --dry-run",
                given.join(", "),
                if given.len() == 1 { "is" } else { "are" },
                self.path.display()
            );
        }
        Ok(())
    }

    /// The output folder: `given` if `--out` is on the command line, else `out/STUDY` (the
    /// study file's name without `.toml`).
    pub fn out(&self, matches: &ArgMatches, given: &Path) -> PathBuf {
        if matches.value_source("out") == Some(ValueSource::CommandLine) {
            return given.to_owned();
        }
        let stem = self.path.file_stem().unwrap_or("study".as_ref());
        Path::new("out").join(stem)
    }

    /// The command line the study stands for, with `extra` (how it is run) appended:
    /// `[command, --option, value, …, extra…]`.
    pub fn command_line(&self, command: &str, extra: &[String]) -> Vec<String> {
        std::iter::once(command.to_owned())
            .chain(self.args.iter().cloned())
            .chain(extra.iter().cloned())
            .collect()
    }

    /// The command's arguments `T` the study stands for, with `extra` appended.
    pub fn parse<T: Args + FromArgMatches>(
        &self,
        command: &'static str,
        extra: &[String],
    ) -> anyhow::Result<T> {
        let argv: Vec<OsString> = self
            .command_line(command, extra)
            .into_iter()
            .map(OsString::from)
            .collect();
        let matches = T::augment_args(Command::new(command))
            .try_get_matches_from(argv)
            .with_context(|| format!("the study {}", self.path.display()))?;
        T::from_arg_matches(&matches).with_context(|| format!("the study {}", self.path.display()))
    }
}

/// Whether a sweep's CSV column holds a measured time (`planner_ms…`), which no two runs
/// share; every other column is exact.
pub fn sweep_time_column(name: &str) -> bool {
    name.starts_with("planner_ms")
}

/// After a study's run has written `file` into `out`, compares it with the study's published
/// one, the columns `measured` on this machine (times, memory) aside, and prints the verdict:
/// exit 0 when it is the same (or there is nothing to compare), 1 when it differs.
pub fn report_reproduction(
    study: Option<&StudyRef>,
    out: &Path,
    file: &str,
    measured: fn(&str) -> bool,
) -> anyhow::Result<ExitCode> {
    let Some(results) = study.and_then(|s| s.results.as_deref()) else {
        return Ok(ExitCode::SUCCESS);
    };
    let published = Path::new(results).join(file);
    let written = out.join(file);
    if !published.is_file() {
        println!(
            "no published {} to compare with (the study names {results})",
            published.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    if std::fs::canonicalize(&published)? == std::fs::canonicalize(&written)? {
        println!("wrote the study's published results ({results})");
        return Ok(ExitCode::SUCCESS);
    }
    let read =
        |p: &Path| std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()));
    match first_difference(&read(&published)?, &read(&written)?, measured) {
        None => {
            println!(
                "reproduces the published {} exactly (but for what this machine measures: times, memory)",
                published.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Some(diff) => {
            eprintln!(
                "error: {} differs from the published {}: {diff}",
                written.display(),
                published.display()
            );
            Ok(ExitCode::from(1))
        }
    }
}

/// The first difference between two CSV texts with a header, the `measured` columns aside;
/// `None` when they are the same.
fn first_difference(published: &str, written: &str, measured: fn(&str) -> bool) -> Option<String> {
    let table = |text: &str| -> Option<Vec<Vec<String>>> {
        csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(text.as_bytes())
            .records()
            .map(|r| Some(r.ok()?.iter().map(str::to_owned).collect()))
            .collect()
    };
    let (Some(a), Some(b)) = (table(published), table(written)) else {
        return Some("a file is not CSV".into());
    };
    let (Some(head_a), Some(head_b)) = (a.first(), b.first()) else {
        return Some("a file is empty".into());
    };
    if head_a != head_b {
        let only = |x: &[String], y: &[String]| {
            let names: Vec<&str> = x
                .iter()
                .filter(|c| !y.contains(c))
                .map(String::as_str)
                .collect();
            if names.is_empty() {
                "none".to_owned()
            } else {
                names.join(", ")
            }
        };
        return Some(format!(
            "the columns differ (only published: {}; only now: {})",
            only(head_a, head_b),
            only(head_b, head_a)
        ));
    }
    let keep: Vec<usize> = (0..head_a.len())
        .filter(|&i| !measured(&head_a[i]))
        .collect();
    if a.len() != b.len() {
        return Some(format!(
            "{} rows published, {} now",
            a.len() - 1,
            b.len() - 1
        ));
    }
    let differing: Vec<usize> = (1..a.len())
        .filter(|&r| keep.iter().any(|&i| a[r].get(i) != b[r].get(i)))
        .collect();
    let &first = differing.first()?;
    let col = keep
        .iter()
        .copied()
        .find(|&i| a[first].get(i) != b[first].get(i))
        .unwrap_or(0);
    Some(format!(
        "{} of {} rows differ; first at line {}, column {}: published {}, now {}",
        differing.len(),
        a.len() - 1,
        first + 1,
        head_a[col],
        a[first].get(col).map_or("", String::as_str),
        b[first].get(col).map_or("", String::as_str)
    ))
}

/// Appends the command-line arguments of option `arg` (written `flag`) set to `value` in a
/// study whose folder is `dir`.
fn option_args(
    arg: &clap::Arg,
    flag: &str,
    value: &toml::Value,
    dir: &Path,
    args: &mut Vec<String>,
) -> Result<(), String> {
    let is_path = arg.get_value_parser().type_id() == std::any::TypeId::of::<PathBuf>();
    match (arg.get_action(), value) {
        (ArgAction::SetTrue, toml::Value::Boolean(on)) => {
            if *on {
                args.push(flag.to_owned());
            }
        }
        (ArgAction::SetTrue, _) => return Err("expected true or false".into()),
        // An option given several times: once per item.
        (ArgAction::Append, toml::Value::Array(items)) => {
            for item in items {
                args.push(flag.to_owned());
                args.push(scalar(item, is_path, dir)?);
            }
        }
        // Any other option: a comma-separated list.
        (_, toml::Value::Array(items)) => {
            let parts: Vec<String> = items
                .iter()
                .map(|i| scalar(i, is_path, dir))
                .collect::<Result<_, _>>()?;
            args.push(flag.to_owned());
            args.push(parts.join(","));
        }
        (_, v) => {
            args.push(flag.to_owned());
            args.push(scalar(v, is_path, dir)?);
        }
    }
    Ok(())
}

/// A study error from `toml` as `file:line: message`.
fn located(name: &str, text: &str, e: &toml::de::Error) -> anyhow::Error {
    let line = e.span().map_or(1, |s| line_of(text, s.start));
    anyhow::anyhow!("{name}:{line}: {}", e.message())
}

/// One value of an option as it would be typed: text as is (paths relative to the study's
/// folder `dir`), numbers and booleans as TOML writes them.
fn scalar(v: &toml::Value, is_path: bool, dir: &Path) -> Result<String, String> {
    Ok(match v {
        toml::Value::String(s) if is_path && s != "none" && Path::new(s).is_relative() => {
            normalize(&dir.join(s)).display().to_string()
        }
        toml::Value::String(s) => s.clone(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => f.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        toml::Value::Datetime(d) => d.to_string(),
        toml::Value::Array(_) => return Err("a list inside a list is not an option value".into()),
        toml::Value::Table(_) => return Err("a table is not an option value".into()),
    })
}

/// `a/b/../c` as `a/c`, lexically (a study's paths are joined to its folder).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

/// The 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

#[cfg(test)]
mod tests;
