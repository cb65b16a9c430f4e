//! A value a run's summary recorded, replaced by the option when the command line gives it:
//! `muse verify`, `muse view` and the exports read the world and parameters of the run
//! behind a plans file from its `summary.json`, and each option the user gives overrides
//! the summary's value. One concept for the flight parameters (`recorded.rs`) and the
//! layering (`layers.rs`), each override said in the notes printed on standard error.

use std::path::PathBuf;

use clap::ArgMatches;
use clap::parser::ValueSource;
use muse_sim::metrics::recorded::Recorded;

/// A summary read: its path (as given, for messages) and what it records.
pub struct Summary {
    /// Its path.
    pub path: PathBuf,
    /// Its world and parameters.
    pub recorded: Recorded,
}

/// Whether the option with clap id `id` was given on the command line.
pub fn given(matches: &ArgMatches, id: &str) -> bool {
    matches.value_source(id) == Some(ValueSource::CommandLine)
}

/// Options whose values a summary records, each named by its clap id.
pub trait Overridable: Clone {
    /// The value of option `id`, as the command line would write it.
    fn value(&self, id: &str) -> String;

    /// Sets option `id` to its value in `from`.
    fn set(&mut self, from: &Self, id: &str);
}

/// The values `summary` records (`recorded`), each option of `ids` the command line gives
/// (`matches`) replaced by its value in `cli`; each said in `notes`: `--speed-kmh 40 given:
/// overrides summary.json's 30`, or `… given: as in summary.json` when the values agree.
pub fn overridden<T: Overridable>(
    recorded: &T,
    cli: &T,
    ids: &[&str],
    matches: &ArgMatches,
    summary: &Summary,
    notes: &mut Vec<String>,
) -> T {
    let name = summary.path.display();
    let mut merged = recorded.clone();
    for &id in ids {
        if !given(matches, id) {
            continue;
        }
        let (theirs, mine) = (recorded.value(id), cli.value(id));
        let option = format!("--{} {mine}", id.replace('_', "-"));
        notes.push(if theirs == mine {
            format!("{option} given: as in {name}")
        } else {
            format!("{option} given: overrides {name}'s {theirs}")
        });
        merged.set(cli, id);
    }
    merged
}
