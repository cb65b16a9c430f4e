//! Study files: an experiment written down in TOML, so that `muse sweep --study FILE` (or
//! `muse bench --study FILE`) reruns exactly the runs behind a published table, and the
//! comparison of a rerun with the published file.
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
//! decides the runs; how they are run (`--shard`, `--out`, `--threads`, `--dry-run`) is
//! given on the command line. [`Study::load`] knows a command's options only by their
//! [`OptionShape`]s: it reads no command line, so it is tested without one.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use super::shard::StudyRef;

/// Options that say how a study is run, never what it is: refused inside a study file.
pub const HOW_TO_RUN: [&str; 5] = ["study", "shard", "out", "threads", "dry-run"];

/// How a command's option takes its value, as far as a study needs to know.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OptionShape {
    /// Its long name without `--`, e.g. `reps`.
    pub long: String,
    /// How it is given.
    pub takes: Takes,
    /// Whether its values are paths (read relative to the study file).
    pub path: bool,
}

/// What an option takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Takes {
    /// Nothing: a flag, `true` or `false` in a study.
    Flag,
    /// One value, or several given once joined with commas (a list in a study).
    Value,
    /// One value per occurrence: a list in a study gives the option once per item.
    Repeated,
}

/// A study file, read.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// The file.
    pub path: PathBuf,
    /// What it reproduces.
    pub title: String,
    /// Where its published results are (relative to the working directory), if it says.
    pub results: Option<PathBuf>,
    /// The command's options it sets, as command-line arguments (`--reps`, `100`, …), keys in
    /// alphabetical order.
    pub args: Vec<String>,
    /// The line of each key of the command's table.
    lines: BTreeMap<String, usize>,
}

/// Why a study is refused: the message names the file, and the line and key when there is
/// one.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The file cannot be read.
    #[error("reading the study {file}: {source}")]
    Read {
        /// The file.
        file: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The file is not a study: bad TOML, an unknown or missing field.
    #[error("{file}:{line}: {message}")]
    Toml {
        /// The file.
        file: String,
        /// The line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// An option of the command's table is refused.
    #[error("{file}:{line}: `{key}`: {message}")]
    Key {
        /// The file.
        file: String,
        /// The line.
        line: usize,
        /// The option.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// The file has no table for the command.
    #[error("{file}: no [{command}] table: {hint}")]
    NoTable {
        /// The file.
        file: String,
        /// The command.
        command: String,
        /// What to do.
        hint: String,
    },
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
type Options = BTreeMap<String, Spanned<toml::Value>>;

impl Study {
    /// Reads the study at `path` for the command `command` (`sweep` or `bench`), whose
    /// options are `options` (hidden ones left out).
    pub fn load(path: &Path, command: &str, options: &[OptionShape]) -> Result<Study, StudyError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| StudyError::Read {
            file: file.clone(),
            source,
        })?;
        let parsed: StudyToml = toml::from_str(&text).map_err(|e| StudyError::Toml {
            file: file.clone(),
            line: e.span().map_or(1, |s| line_of(&text, s.start)),
            message: e.message().to_owned(),
        })?;
        let table = match command {
            "sweep" => parsed.sweep.as_ref(),
            "bench" => parsed.bench.as_ref(),
            _ => None,
        };
        let Some(table) = table else {
            let has = [
                ("sweep", parsed.sweep.is_some()),
                ("bench", parsed.bench.is_some()),
            ]
            .into_iter()
            .find_map(|(c, present)| present.then_some(c));
            return Err(StudyError::NoTable {
                hint: has.map_or_else(
                    || format!("a study for `muse {command}` sets its options in [{command}]"),
                    |c| format!("this study is for `muse {c}`: run `muse {c} --study {file}`"),
                ),
                file,
                command: command.to_owned(),
            });
        };
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut args = Vec::new();
        let mut lines = BTreeMap::new();
        for (key, value) in table {
            let line = line_of(&text, value.span().start);
            lines.insert(key.clone(), line);
            let at = |message: String| StudyError::Key {
                file: file.clone(),
                line,
                key: key.clone(),
                message,
            };
            if HOW_TO_RUN.contains(&key.as_str()) {
                return Err(at(format!(
                    "how a study is run is not part of it: give --{key} on the command line"
                )));
            }
            let Some(option) = options.iter().find(|o| o.long == *key) else {
                return Err(at(format!(
                    "not an option of `muse {command}` (see `muse {command} --help`)"
                )));
            };
            option_args(option, value.get_ref(), dir, &mut args).map_err(at)?;
        }
        Ok(Study {
            path: path.to_owned(),
            title: parsed.title,
            results: parsed.results.map(|r| normalize(&dir.join(r))),
            args,
            lines,
        })
    }

    /// The line of the option `key` in the study's table.
    pub fn line_of(&self, key: &str) -> Option<usize> {
        self.lines.get(key).copied()
    }

    /// The default output folder: `out/STUDY` (the study file's name without `.toml`).
    pub fn default_out(&self) -> PathBuf {
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

    /// How the shards of a study name it.
    pub fn reference(&self) -> StudyRef {
        StudyRef {
            file: self.path.display().to_string(),
            title: self.title.clone(),
            results: self.results.as_ref().map(|r| r.display().to_string()),
        }
    }
}

/// Appends the command-line arguments of `option` set to `value` in a study whose folder is
/// `dir`.
fn option_args(
    option: &OptionShape,
    value: &toml::Value,
    dir: &Path,
    args: &mut Vec<String>,
) -> Result<(), String> {
    let flag = format!("--{}", option.long);
    match (option.takes, value) {
        (Takes::Flag, toml::Value::Boolean(on)) => {
            if *on {
                args.push(flag);
            }
        }
        (Takes::Flag, _) => return Err("expected true or false".into()),
        // An option given several times: once per item.
        (Takes::Repeated, toml::Value::Array(items)) => {
            for item in items {
                args.push(flag.clone());
                args.push(scalar(item, option.path, dir)?);
            }
        }
        // Any other option: a comma-separated list.
        (_, toml::Value::Array(items)) => {
            let parts: Vec<String> = items
                .iter()
                .map(|i| scalar(i, option.path, dir))
                .collect::<Result<_, _>>()?;
            args.push(flag);
            args.push(parts.join(","));
        }
        (_, v) => {
            args.push(flag);
            args.push(scalar(v, option.path, dir)?);
        }
    }
    Ok(())
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
