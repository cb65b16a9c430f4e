//! What a lever is: a `--vary` value of the paper's sweep, the settings it compares, and the
//! option (if any) that lists them.

use muse_model::{FlightParams, Millis, Zone};

use crate::experiment::sweep::variant::Variant;

/// The most values of a list option that multiplies a sweep's runs (`--swap-min`, `--leads`,
/// `--tau-s`).
pub const MAX_LIST: usize = 100;

/// What every lever starts from: the sweep's base flight parameters and zones.
#[derive(Clone, Copy, Debug)]
pub struct Base<'a> {
    /// The flight parameters given (the defaults: the paper's).
    pub params: FlightParams,
    /// The zones in force.
    pub zones: &'a [Zone],
    /// How the zones are named in legends: `CBD zone` for a built-in scenario's, `no zone`,
    /// or the zone ids.
    pub zone_label: &'a str,
}

/// A lever's own option: a list of the settings it compares, e.g. `--tau-s 2,5,10`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Setting {
    /// The option's long name without `--`, e.g. `tau-s`.
    pub name: &'static str,
    /// Its value's placeholder in `--help`, e.g. `S,...`.
    pub value_name: &'static str,
    /// Its help text (saying its default).
    pub help: &'static str,
    /// Its value when not given.
    pub default: &'static str,
}

/// Why a lever's settings are refused; the message names the option or `--vary` value.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct LeverError(pub String);

/// A policy the paper's sweep compares on the same seeds (`muse sweep --vary NAME`).
///
/// A lever turns one variant into several, one per setting it compares; levers given together
/// combine into the cartesian product of their settings. To add one, write a file beside the
/// others implementing this trait and add it to the list in `levers/mod.rs`.
pub trait Lever: Sync {
    /// Its `--vary` value, e.g. `tau`.
    fn name(&self) -> &'static str;

    /// What it compares, for `--help` (one sentence).
    fn help(&self) -> &'static str;

    /// Its own option, if it has one.
    fn setting(&self) -> Option<Setting> {
        None
    }

    /// The settings it compares applied to `current`: each one's label (joined to the
    /// variant's name in legends) and variant. `value` is its option's text, or its default.
    fn apply(
        &self,
        base: &Base<'_>,
        current: &Variant,
        value: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError>;
}

/// Parses a comma-separated list of durations for the option `option` (e.g. `--swap-min`):
/// at most [`MAX_LIST`] numbers of `unit`s (`minutes`, `seconds`; `scale` seconds each),
/// each from 0 to `max`.
///
/// ```
/// use muse_model::Millis;
/// use muse_sim::experiment::sweep::levers::durations;
/// assert_eq!(durations("--tau-s", "2, 0.5", "seconds", 1.0, 3600.0).unwrap(),
///            vec![Millis::from_secs(2), Millis(500)]);
/// assert_eq!(durations("--tau-s", "2,,5", "seconds", 1.0, 3600.0).unwrap_err().to_string(),
///            "--tau-s `2,,5`: expected at most 100 comma-separated seconds, each from 0 to 3600");
/// ```
pub fn durations(
    option: &str,
    text: &str,
    unit: &str,
    scale: f64,
    max: f64,
) -> Result<Vec<Millis>, LeverError> {
    list(
        option,
        text,
        &format!("{unit}, each from 0 to {max}"),
        |x| {
            let v: f64 = x.parse().ok()?;
            if !(0.0..=max).contains(&v) {
                return None;
            }
            Millis::from_secs_f64(v * scale).ok()
        },
    )
}

/// The values of a comma-separated list option: at most [`MAX_LIST`] of them, each read by
/// `parse` (trimmed; `None` refuses it); else an error saying `option `text`: expected at
/// most 100 comma-separated {expected}`.
pub fn list<T>(
    option: &str,
    text: &str,
    expected: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Vec<T>, LeverError> {
    let bad = || {
        LeverError(format!(
            "{option} `{text}`: expected at most {MAX_LIST} comma-separated {expected}"
        ))
    };
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() > MAX_LIST {
        return Err(bad());
    }
    parts
        .into_iter()
        .map(|x| parse(x.trim()).ok_or_else(bad))
        .collect()
}

/// `current` with the flight parameters `params`.
pub fn with_params(current: &Variant, params: FlightParams) -> Variant {
    Variant {
        params,
        ..current.clone()
    }
}
