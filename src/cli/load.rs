//! `muse load`: an HTTP load generator for `muse serve` (the work is in `muse-load`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use muse_load::{Event, LoadConfig, Mode, OdChoice, Stop};
use muse_model::Millis;

use super::output;
use super::ranges;

/// Origin–destination rule on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum OdArg {
    /// Uniform over distinct station pairs (the paper).
    Uniform,
    /// Only pairs whose free-flow time on the empty graph fits the battery.
    InRange,
}

/// Arguments of `muse load`.
#[derive(Debug, Args)]
pub struct LoadArgs {
    /// The service's base URL.
    #[arg(long, value_name = "URL", default_value = "http://127.0.0.1:8080")]
    url: String,
    /// Bearer token (an authority's token lets the final verification see every flight).
    #[arg(long, value_name = "TOKEN")]
    token: Option<String>,
    /// Open loop: send this many requests per second, whatever the answers (latency counts
    /// from each request's due time), from 0.01 to 1000000. With --clients: paced, see there.
    #[arg(long, value_name = "R", allow_negative_numbers = true, value_parser = ranges::load_rate)]
    rate: Option<f64>,
    /// Closed loop: this many concurrent clients, each sending as soon as answered
    /// (default 16 without --rate). With --rate: paced, these N clients together follow the
    /// open-loop schedule of R requests/s, each request taken by whichever client is free (it
    /// waits while all are busy; latency still counts from its due time). From 1 to 100000.
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = ranges::clients)]
    clients: Option<usize>,
    /// Run for this long, seconds, from 1 to 86400.
    #[arg(long, value_name = "SECONDS", conflicts_with = "count", allow_negative_numbers = true, value_parser = ranges::duration_s)]
    duration: Option<f64>,
    /// Send this many requests, from 1 to 10000000 (default 10000 without --duration).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = ranges::load_count)]
    count: Option<u64>,
    /// Seed of the demand, a whole number from 0 to 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = ranges::seed)]
    seed: u64,
    /// Each departure is the service's now at send time plus a uniform lead in [A, B]
    /// minutes, each from 0 to 43200 (30 days).
    #[arg(long, value_name = "A:B", default_value = "1:1440", allow_hyphen_values = true, value_parser = parse_lead)]
    lead_min: (Millis, Millis),
    /// Origin–destination rule.
    #[arg(long, value_enum, default_value_t = OdArg::Uniform)]
    od: OdArg,
    /// Report file (JSON; `-`: standard output, the summary then on stderr).
    #[arg(long, value_name = "FILE", default_value = "load.json")]
    out: PathBuf,
    /// Do not fetch and verify the planned flights at the end.
    #[arg(long)]
    no_verify: bool,
    /// Prefix of this run's flight ids (default: from the seed and the start time, so that
    /// runs against one service never reuse ids).
    #[arg(long, value_name = "PREFIX")]
    id_prefix: Option<String>,
    /// Open loop: most requests in flight at once (a request due beyond it waits and is
    /// counted), from 1 to 1000000. Paced runs have --clients in flight at most.
    #[arg(long, value_name = "N", default_value_t = muse_load::config::DEFAULT_MAX_IN_FLIGHT, requires = "rate", conflicts_with = "clients", allow_negative_numbers = true, value_parser = ranges::max_in_flight)]
    max_in_flight: usize,
    /// Per-request timeout, seconds, from 0.1 to 86400.
    #[arg(long, value_name = "SECONDS", default_value_t = 30.0, allow_negative_numbers = true, value_parser = ranges::timeout_s)]
    timeout: f64,
}

impl LoadArgs {
    fn config(&self) -> anyhow::Result<LoadConfig> {
        let mut c = LoadConfig::new(self.url.clone());
        c.token.clone_from(&self.token);
        c.mode = match (self.rate, self.clients) {
            (Some(rate), Some(clients)) => Mode::Paced { rate, clients },
            (Some(rate), None) => Mode::Open {
                rate,
                max_in_flight: self.max_in_flight,
            },
            (None, clients) => Mode::Closed {
                clients: clients.unwrap_or(16),
            },
        };
        c.stop = match (self.duration, self.count) {
            (Some(d), _) => Stop::Duration(seconds("--duration", d)?),
            (None, Some(n)) => Stop::Count(n),
            (None, None) => Stop::Count(10_000),
        };
        c.seed = self.seed;
        c.lead = self.lead_min;
        c.od = match self.od {
            OdArg::Uniform => OdChoice::Uniform,
            OdArg::InRange => OdChoice::InRange,
        };
        c.id_prefix.clone_from(&self.id_prefix);
        c.verify = !self.no_verify;
        c.timeout = seconds("--timeout", self.timeout)?;
        Ok(c)
    }
}

fn seconds(name: &str, s: f64) -> anyhow::Result<Duration> {
    Duration::try_from_secs_f64(s)
        .ok()
        .filter(|d| !d.is_zero())
        .with_context(|| format!("{name} must be a positive number of seconds, got {s}"))
}

/// `--lead-min A:B` (or `A`): minutes from 0 to [`ranges::MAX_LEAD_MIN`], `A <= B`.
fn parse_lead(text: &str) -> Result<(Millis, Millis), String> {
    let (a, b) = text.split_once(':').unwrap_or((text, text));
    let minutes = |v: &str| -> Result<Millis, String> {
        let m = ranges::lead_min(v).map_err(|e| format!("`{}`: {e}", v.trim()))?;
        Millis::from_secs_f64(m * 60.0).map_err(|e| e.to_string())
    };
    let (a, b) = (minutes(a)?, minutes(b)?);
    if b < a {
        return Err(format!(
            "A:B must have A <= B, got {text}: a lead of at least A and at most B minutes"
        ));
    }
    Ok((a, b))
}

/// Runs `muse load`; exits 1 if the verifier finds a violation, 2 if the service cannot be
/// reached or the options are wrong.
pub fn run(args: &LoadArgs) -> anyhow::Result<ExitCode> {
    let config = args.config()?;
    let out = output::file("--out", &args.out, &output::Inputs::new())?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let mut progress = Progress::default();
    let report = runtime.block_on(muse_load::run(&config, |e| progress.on(e)));
    progress.clear();
    let report = report?;
    out.write(&report.to_json())?;
    output::say(out.is_stdout(), report.text().trim_end());
    output::say(out.is_stdout(), format_args!("  wrote         {out}"));
    Ok(if report.verified_ok() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// Progress bars, shown once a phase has lasted a second.
#[derive(Default)]
struct Progress {
    phase: Option<(u8, Instant)>,
    bar: Option<ProgressBar>,
}

impl Progress {
    fn on(&mut self, event: &Event) {
        let (phase, len, pos, message, template) = match *event {
            Event::Load {
                elapsed,
                completed,
                planned,
                errors,
                stop,
                ..
            } => {
                let message = format!("load: {planned} planned, {errors} errors");
                match stop {
                    Stop::Count(n) => (
                        0,
                        n,
                        completed,
                        message,
                        "{msg} [{bar:40}] {pos}/{len} ({elapsed}, ETA {eta})",
                    ),
                    Stop::Duration(d) => (
                        0,
                        d.as_secs().max(1),
                        elapsed.as_secs(),
                        format!("{message}, {completed} answered"),
                        "{msg} [{bar:40}] {pos}/{len} s",
                    ),
                }
            }
            Event::Fetching { flights } => (
                1,
                0,
                flights as u64,
                "fetching planned flights".to_owned(),
                "{msg}: {pos}",
            ),
            Event::Verifying { flights } => {
                (2, 0, 0, format!("verifying {flights} flights"), "{msg}")
            }
        };
        if self.phase.is_none_or(|(p, _)| p != phase) {
            self.clear();
            self.phase = Some((phase, Instant::now()));
        }
        if self.bar.is_none()
            && self
                .phase
                .is_some_and(|(_, t)| t.elapsed() > Duration::from_secs(1))
        {
            let bar = if len > 0 {
                ProgressBar::new(len)
            } else {
                ProgressBar::no_length()
            };
            bar.set_style(
                ProgressStyle::with_template(template)
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            self.bar = Some(bar);
        }
        if let Some(bar) = &self.bar {
            bar.set_message(message);
            bar.set_position(pos);
        }
    }

    fn clear(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        load: LoadArgs,
    }

    fn mode(args: &[&str]) -> Result<Mode, String> {
        let cli = Cli::try_parse_from(std::iter::once("load").chain(args.iter().copied()))
            .map_err(|e| e.to_string())?;
        Ok(cli.load.config().map_err(|e| e.to_string())?.mode)
    }

    #[test]
    fn rate_and_clients_choose_the_mode() {
        assert_eq!(mode(&[]).unwrap(), Mode::Closed { clients: 16 });
        assert_eq!(
            mode(&["--clients", "4"]).unwrap(),
            Mode::Closed { clients: 4 }
        );
        assert_eq!(
            mode(&["--rate", "500"]).unwrap(),
            Mode::Open {
                rate: 500.0,
                max_in_flight: muse_load::config::DEFAULT_MAX_IN_FLIGHT
            }
        );
        assert_eq!(
            mode(&["--rate", "500", "--max-in-flight", "7"]).unwrap(),
            Mode::Open {
                rate: 500.0,
                max_in_flight: 7
            }
        );
        assert_eq!(
            mode(&["--rate", "2000", "--clients", "256"]).unwrap(),
            Mode::Paced {
                rate: 2_000.0,
                clients: 256
            }
        );
        assert!(mode(&["--max-in-flight", "7"]).is_err(), "needs --rate");
        assert!(
            mode(&["--rate", "1", "--clients", "2", "--max-in-flight", "7"]).is_err(),
            "paced runs have no cap of their own"
        );
    }

    #[test]
    fn lead_ranges() {
        assert_eq!(
            parse_lead("1:1440").unwrap(),
            (Millis::from_mins(1), Millis::from_mins(1_440))
        );
        assert_eq!(
            parse_lead("0.5").unwrap(),
            (Millis::from_secs(30), Millis::from_secs(30))
        );
        for bad in ["a:2", "-1:2", "1:NaN", "0:43201"] {
            assert!(
                parse_lead(bad)
                    .unwrap_err()
                    .ends_with("must be a number of minutes from 0 to 43200"),
                "{bad}"
            );
        }
        assert!(parse_lead("5:1").unwrap_err().contains("A <= B"));
    }
}
