//! The levers of `muse sweep --vary` on the command line: the `--vary` values (every lever of
//! [`muse_sim::experiment::sweep::levers`], and `announce-lead`) and each lever's own option
//! (`--swap-min`, …), made from the levers themselves, so that a new lever needs no change
//! here.

use clap::builder::{PossibleValue, PossibleValuesParser};
use clap::{Arg, ArgMatches, Args, Command, FromArgMatches};
use muse_sim::experiment::sweep::levers::LEVERS;

/// The `--vary` value that is its own sweep rather than a lever.
pub const ANNOUNCE_LEAD: &str = "announce-lead";

/// The `--vary` values: every lever, then `announce-lead`.
pub fn vary_values() -> PossibleValuesParser {
    let levers = LEVERS
        .iter()
        .map(|l| PossibleValue::new(l.name()).help(l.help()));
    PossibleValuesParser::new(levers.chain(std::iter::once(
        PossibleValue::new(ANNOUNCE_LEAD).help(
            "How much warning before a zone's first active window it is announced (`--leads`, \
             `--announce-zones`); replays each day \
             (docs/reference.md#zones-announced-during-the-day) with bookings made 0–120 min \
             ahead unless `--booking-lead-min` says otherwise. Not combinable with other \
             `--vary` values",
        ),
    )))
}

/// The levers' own options given on the command line: (option name, text).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LeverArgs(Vec<(&'static str, String)>);

impl LeverArgs {
    /// The options given, by name, in the levers' order.
    pub fn given(&self) -> &[(&'static str, String)] {
        &self.0
    }
}

impl FromArgMatches for LeverArgs {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut given = Vec::new();
        for s in LEVERS.iter().filter_map(|l| l.setting()) {
            if let Ok(Some(v)) = matches.try_get_one::<String>(s.name) {
                given.push((s.name, v.clone()));
            }
        }
        Ok(LeverArgs(given))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for LeverArgs {
    fn augment_args(cmd: Command) -> Command {
        LEVERS
            .iter()
            .filter_map(|l| l.setting())
            .fold(cmd, |cmd, s| {
                cmd.arg(
                    Arg::new(s.name)
                        .long(s.name)
                        .value_name(s.value_name)
                        .help(s.help)
                        .allow_hyphen_values(true),
                )
            })
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// Refuses a lever's option given without its lever among `vary`.
pub fn check_given(levers: &LeverArgs, vary: &[String]) -> anyhow::Result<()> {
    for (name, _) in levers.given() {
        let Some(lever) = LEVERS
            .iter()
            .find(|l| l.setting().is_some_and(|s| s.name == *name))
        else {
            continue;
        };
        if !vary.iter().any(|v| v == lever.name()) {
            anyhow::bail!("--{name} applies only with --vary {}", lever.name());
        }
    }
    Ok(())
}
