//! What a load run does: where, how hard, for how long and with what demand.

use std::time::Duration;

use muse_model::Millis;
use serde::Serialize;

use crate::demand::OdChoice;
use crate::error::LoadError;

/// How requests are issued.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mode {
    /// Open loop: request `i` is due at `t0 + i / rate` whatever the answers, and its latency
    /// runs from that due time (see [`crate::schedule`]).
    Open {
        /// Requests per second.
        rate: f64,
        /// Most requests in flight at once; a request due while this many are in flight
        /// waits for one to finish (and is counted as having waited).
        max_in_flight: usize,
    },
    /// Closed loop: `clients` tasks, each sending its next request as soon as the previous
    /// one is answered; latency runs from sending.
    Closed {
        /// Concurrent clients.
        clients: usize,
    },
    /// Paced: the open-loop schedule of `rate` requests per second (request `i` due at
    /// `t0 + i / rate`), served by `clients` concurrent clients, each with at most one request
    /// in flight. A request is taken by whichever client is free; one that falls due while
    /// every client is busy waits for the first to finish (and is counted as having waited).
    /// Latency runs from the due time, as in open loop, so the wait is charged to it (no
    /// coordinated omission); requests sent more than [`crate::schedule::PACED_LATE`] after
    /// their due time are counted as late.
    Paced {
        /// Requests per second, all clients together.
        rate: f64,
        /// Concurrent clients.
        clients: usize,
    },
}

/// When a run stops issuing requests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// After this many requests.
    Count(u64),
    /// After this long (requests already sent are still awaited).
    Duration(Duration),
}

/// The default cap on requests in flight in open loop.
pub const DEFAULT_MAX_IN_FLIGHT: usize = 10_000;

/// Everything a run needs.
#[derive(Clone, Debug)]
pub struct LoadConfig {
    /// The service's base URL, e.g. `http://127.0.0.1:8080`.
    pub url: String,
    /// Bearer token, if the service wants one.
    pub token: Option<String>,
    /// Open loop, closed loop or paced.
    pub mode: Mode,
    /// Count or duration.
    pub stop: Stop,
    /// Seed of the demand.
    pub seed: u64,
    /// Departures are the service's now at send time plus a uniform lead in this range
    /// (inclusive).
    pub lead: (Millis, Millis),
    /// Origin–destination rule.
    pub od: OdChoice,
    /// Id prefix; `None`: [`crate::demand::default_prefix`] of the seed and start time.
    pub id_prefix: Option<String>,
    /// Whether to fetch every planned flight at the end and verify them.
    pub verify: bool,
    /// Per-request timeout.
    pub timeout: Duration,
}

impl LoadConfig {
    /// A closed-loop run of 16 clients and 10,000 requests against `url`, seed 1, leads of 1
    /// to 1,440 minutes, uniform pairs, verified at the end, 30 s per-request timeout: the
    /// defaults of `muse load`.
    pub fn new(url: impl Into<String>) -> Self {
        LoadConfig {
            url: url.into(),
            token: None,
            mode: Mode::Closed { clients: 16 },
            stop: Stop::Count(10_000),
            seed: 1,
            lead: (Millis::from_mins(1), Millis::from_mins(1_440)),
            od: OdChoice::Uniform,
            id_prefix: None,
            verify: true,
            timeout: Duration::from_secs(30),
        }
    }

    /// Checks the options that need no server.
    pub fn check(&self) -> Result<(), LoadError> {
        match self.mode {
            Mode::Open {
                rate,
                max_in_flight,
            } => {
                check_rate(rate)?;
                if !(1..=1_000_000).contains(&max_in_flight) {
                    return Err(LoadError::Config(format!(
                        "the cap on requests in flight must be 1 to 1,000,000, got {max_in_flight}"
                    )));
                }
            }
            Mode::Closed { clients } => check_clients(clients)?,
            Mode::Paced { rate, clients } => {
                check_rate(rate)?;
                check_clients(clients)?;
            }
        }
        match self.stop {
            Stop::Count(0) => Err(LoadError::Config("--count must be at least 1".into())),
            Stop::Duration(d) if d.is_zero() => {
                Err(LoadError::Config("--duration must be positive".into()))
            }
            _ if self.timeout.is_zero() => {
                Err(LoadError::Config("the timeout must be positive".into()))
            }
            _ => Ok(()),
        }
    }

    /// The parameters as the report records them.
    pub fn summary(&self, id_prefix: &str) -> ConfigSummary {
        let (mode, rate, clients, max_in_flight) = match self.mode {
            Mode::Open {
                rate,
                max_in_flight,
            } => ("open", Some(rate), None, Some(max_in_flight)),
            Mode::Closed { clients } => ("closed", None, Some(clients), None),
            Mode::Paced { rate, clients } => ("paced", Some(rate), Some(clients), None),
        };
        let (count, duration_s) = match self.stop {
            Stop::Count(n) => (Some(n), None),
            Stop::Duration(d) => (None, Some(d.as_secs_f64())),
        };
        ConfigSummary {
            url: self.url.clone(),
            mode,
            rate,
            clients,
            max_in_flight,
            count,
            duration_s,
            seed: self.seed,
            lead_min: [
                self.lead.0.as_secs_f64() / 60.0,
                self.lead.1.as_secs_f64() / 60.0,
            ],
            od: self.od,
            id_prefix: id_prefix.to_owned(),
            verify: self.verify,
            timeout_s: self.timeout.as_secs_f64(),
            token: self.token.is_some(),
        }
    }
}

/// `--rate` is a positive, finite number of requests per second.
fn check_rate(rate: f64) -> Result<(), LoadError> {
    if rate.is_finite() && rate > 0.0 {
        Ok(())
    } else {
        Err(LoadError::Config(format!(
            "--rate must be a positive number of requests per second, got {rate}"
        )))
    }
}

/// `--clients` is 1 to 100,000.
fn check_clients(clients: usize) -> Result<(), LoadError> {
    if (1..=100_000).contains(&clients) {
        Ok(())
    } else {
        Err(LoadError::Config(format!(
            "--clients must be 1 to 100,000, got {clients}"
        )))
    }
}

/// The parameters of a run, as written to the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConfigSummary {
    /// The service's base URL.
    pub url: String,
    /// `open`, `closed` or `paced`.
    pub mode: &'static str,
    /// Open loop and paced: requests per second.
    pub rate: Option<f64>,
    /// Closed loop and paced: concurrent clients.
    pub clients: Option<usize>,
    /// Open loop: most requests in flight.
    pub max_in_flight: Option<usize>,
    /// Requests asked for (`--count`).
    pub count: Option<u64>,
    /// Duration asked for (`--duration`), s.
    pub duration_s: Option<f64>,
    /// Demand seed.
    pub seed: u64,
    /// Lead range `[A, B]`, minutes.
    pub lead_min: [f64; 2],
    /// Origin–destination rule.
    pub od: OdChoice,
    /// The prefix of this run's ids.
    pub id_prefix: String,
    /// Whether the flights were verified.
    pub verify: bool,
    /// Per-request timeout, s.
    pub timeout_s: f64,
    /// Whether a token was sent.
    pub token: bool,
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use super::*;

    #[test]
    fn defaults_and_checks() {
        let c = LoadConfig::new("http://127.0.0.1:8080");
        assert!(c.check().is_ok());
        let bad = |f: fn(&mut LoadConfig)| {
            let mut c = LoadConfig::new("http://x");
            f(&mut c);
            c.check().is_err()
        };
        assert!(bad(|c| c.stop = Stop::Count(0)));
        assert!(bad(|c| c.stop = Stop::Duration(Duration::ZERO)));
        assert!(bad(|c| c.mode = Mode::Closed { clients: 0 }));
        assert!(bad(|c| c.timeout = Duration::ZERO));
        assert!(bad(|c| c.mode = Mode::Open {
            rate: 0.0,
            max_in_flight: 10
        }));
        assert!(bad(|c| c.mode = Mode::Open {
            rate: 10.0,
            max_in_flight: 0
        }));
        assert!(!bad(|c| c.mode = Mode::Open {
            rate: 0.5,
            max_in_flight: 1
        }));
        assert!(bad(|c| c.mode = Mode::Paced {
            rate: f64::NAN,
            clients: 4
        }));
        assert!(bad(|c| c.mode = Mode::Paced {
            rate: 100.0,
            clients: 0
        }));
        assert!(bad(|c| c.mode = Mode::Paced {
            rate: 100.0,
            clients: 100_001
        }));
        assert!(!bad(|c| c.mode = Mode::Paced {
            rate: 2_000.0,
            clients: 1
        }));
    }

    #[test]
    fn summary_of_an_open_run() {
        let mut c = LoadConfig::new("http://x");
        c.mode = Mode::Open {
            rate: 2_000.0,
            max_in_flight: DEFAULT_MAX_IN_FLIGHT,
        };
        c.stop = Stop::Duration(Duration::from_secs(30));
        let s = c.summary("p");
        assert_eq!(
            (s.mode, s.rate, s.clients, s.duration_s, s.count),
            ("open", Some(2_000.0), None, Some(30.0), None)
        );
        assert_eq!(s.lead_min, [1.0, 1_440.0]);
    }

    #[test]
    fn summary_of_a_paced_run() {
        let mut c = LoadConfig::new("http://x");
        c.mode = Mode::Paced {
            rate: 2_000.0,
            clients: 16,
        };
        c.stop = Stop::Count(500);
        let s = c.summary("p");
        assert_eq!(
            (s.mode, s.rate, s.clients, s.max_in_flight, s.count),
            ("paced", Some(2_000.0), Some(16), None, Some(500))
        );
    }
}
