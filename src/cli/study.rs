//! `--study FILE` on the command line: a study (read by [`muse_sim::experiment::Study`])
//! checked against the command's options, the options given beside it refused but for how it
//! is run, and turned into the command's arguments.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::parser::ValueSource;
use clap::{ArgAction, ArgMatches, Args, Command, FromArgMatches};
use muse_sim::experiment::{HOW_TO_RUN, OptionShape, Study, Takes};

/// The options of `cmd` as a study knows them (hidden ones left out).
pub fn shapes(cmd: &Command) -> Vec<OptionShape> {
    cmd.get_arguments()
        .filter(|a| !a.is_hide_set())
        .filter_map(|a| {
            Some(OptionShape {
                long: a.get_long()?.to_owned(),
                takes: match a.get_action() {
                    ArgAction::SetTrue => Takes::Flag,
                    ArgAction::Append => Takes::Repeated,
                    _ => Takes::Value,
                },
                path: a.get_value_parser().type_id() == std::any::TypeId::of::<PathBuf>(),
            })
        })
        .collect()
}

/// Reads the study at `path` for the command `cmd`, and parses its options once, so that a
/// value the command refuses is reported at its line.
pub fn load(path: &Path, cmd: &Command) -> anyhow::Result<Study> {
    let command = cmd.get_name();
    let study = Study::load(path, command, &shapes(cmd))?;
    let mut argv = vec![command.to_owned()];
    argv.extend(study.args.iter().cloned());
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
            .and_then(|k| Some(format!("{}: `{k}`", study.line_of(k)?)))
            .unwrap_or_else(|| format!("[{command}]"));
        let message = e.to_string();
        let first = message.lines().next().unwrap_or_default();
        anyhow::bail!(
            "{}:{at}: {}",
            path.display(),
            first.trim_start_matches("error: ")
        );
    }
    Ok(study)
}

/// Reads the study at `path` for the command `name` whose options are `T`, and refuses the
/// options given beside it on the command line other than how it is run (`matches`: the
/// command's own).
pub fn open<T: Args>(
    path: &Path,
    name: &'static str,
    matches: &ArgMatches,
) -> anyhow::Result<Study> {
    let cmd = T::augment_args(Command::new(name));
    let study = load(path, &cmd)?;
    refuse_overrides(&study, &cmd, matches)?;
    println!("study {}: {}", path.display(), study.title);
    Ok(study)
}

/// Refuses options of `cmd` given on the command line beside `--study` other than how it is
/// run (`matches`: the command's own).
pub fn refuse_overrides(study: &Study, cmd: &Command, matches: &ArgMatches) -> anyhow::Result<()> {
    let given: Vec<String> = cmd
        .get_arguments()
        .filter(|a| !HOW_TO_RUN.contains(&a.get_long().unwrap_or_default()))
        .map(|a| a.get_id().as_str())
        .filter(|id| matches.value_source(id) == Some(ValueSource::CommandLine))
        .map(|id| format!("--{}", id.replace('_', "-")))
        .collect();
    if !given.is_empty() {
        anyhow::bail!(
            "{} {} set by the study {}: edit the study (or run without --study); beside --study give only --shard, --out, --threads and --dry-run",
            given.join(", "),
            if given.len() == 1 { "is" } else { "are" },
            study.path.display()
        );
    }
    Ok(())
}

/// The output folder: `given` if `--out` is on the command line, else `out/STUDY`.
pub fn out(study: &Study, matches: &ArgMatches, given: &Path) -> PathBuf {
    if matches.value_source("out") == Some(ValueSource::CommandLine) {
        return given.to_owned();
    }
    study.default_out()
}

/// The command's arguments `T` the study stands for, with `extra` appended.
pub fn parse<T: Args + FromArgMatches>(
    study: &Study,
    command: &'static str,
    extra: &[String],
) -> anyhow::Result<T> {
    let argv: Vec<OsString> = study
        .command_line(command, extra)
        .into_iter()
        .map(OsString::from)
        .collect();
    let matches = T::augment_args(Command::new(command))
        .try_get_matches_from(argv)
        .with_context(|| format!("the study {}", study.path.display()))?;
    T::from_arg_matches(&matches).with_context(|| format!("the study {}", study.path.display()))
}

#[cfg(test)]
mod tests;
