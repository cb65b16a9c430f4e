//! What the server allows a client: the timeouts and the connection cap, their defaults and
//! bounds, reading them from the command line, and the cap the open-file limit leaves room for.

use std::time::Duration;

/// Default [`Limits::header_timeout`].
pub const DEFAULT_HEADER_TIMEOUT: Duration = Duration::from_secs(10);
/// Default [`Limits::body_timeout`].
pub const DEFAULT_BODY_TIMEOUT: Duration = Duration::from_secs(30);
/// Default [`Limits::idle_timeout`].
pub const DEFAULT_IDLE_TIMEOUT: Duration = Duration::from_mins(1);
/// Default [`Limits::max_connections`] (before the open-file limit lowers it).
pub const DEFAULT_MAX_CONNECTIONS: usize = 10_000;
/// Open files kept back from the connection cap for everything else the process opens: the
/// store's log and lock, the listening socket, connections being refused.
pub const FILE_RESERVE: u64 = 64;
/// Shortest timeout accepted.
pub const MIN_TIMEOUT: Duration = Duration::from_millis(100);
/// Longest timeout accepted (a day).
pub const MAX_TIMEOUT: Duration = Duration::from_hours(24);

/// The limits of the HTTP server (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// From the first byte of a request to the end of its headers.
    pub header_timeout: Duration,
    /// From the end of the headers to the end of a body the API reads.
    pub body_timeout: Duration,
    /// Longest time a connection stays open with no request in progress.
    pub idle_timeout: Duration,
    /// Most connections served at once (lowered to [`connection_cap`]).
    pub max_connections: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            header_timeout: DEFAULT_HEADER_TIMEOUT,
            body_timeout: DEFAULT_BODY_TIMEOUT,
            idle_timeout: DEFAULT_IDLE_TIMEOUT,
            max_connections: DEFAULT_MAX_CONNECTIONS,
        }
    }
}

impl Limits {
    /// Checks that every timeout is within `MIN_TIMEOUT..=MAX_TIMEOUT` and that at
    /// least one connection is allowed; the error names the field.
    pub fn check(&self) -> Result<(), String> {
        for (name, t) in [
            ("header_timeout", self.header_timeout),
            ("body_timeout", self.body_timeout),
            ("idle_timeout", self.idle_timeout),
        ] {
            if !(MIN_TIMEOUT..=MAX_TIMEOUT).contains(&t) {
                return Err(format!(
                    "{name} must be between {} and {} seconds, got {}",
                    MIN_TIMEOUT.as_secs_f64(),
                    MAX_TIMEOUT.as_secs_f64(),
                    t.as_secs_f64()
                ));
            }
        }
        if self.max_connections == 0 {
            return Err("max_connections must be at least 1".into());
        }
        Ok(())
    }
}

/// Parses a timeout given in seconds (`"10"`, `"2.5"`) as the command line takes it: a
/// finite number within `MIN_TIMEOUT..=MAX_TIMEOUT` (0.1 s to a day).
pub fn parse_timeout(text: &str) -> Result<Duration, String> {
    let bad = || {
        format!(
            "must be a number of seconds from {} to {}",
            MIN_TIMEOUT.as_secs_f64(),
            MAX_TIMEOUT.as_secs_f64()
        )
    };
    let secs: f64 = text.trim().parse().map_err(|_| bad())?;
    if !secs.is_finite() {
        return Err(bad());
    }
    let t = Duration::try_from_secs_f64(secs).map_err(|_| bad())?;
    if (MIN_TIMEOUT..=MAX_TIMEOUT).contains(&t) {
        Ok(t)
    } else {
        Err(bad())
    }
}

/// The open-file limit of this process after raising its soft limit to the hard one (as far
/// as the system allows); `None` when there is no limit or it cannot be read.
pub fn open_file_limit() -> Option<u64> {
    #[cfg(unix)]
    {
        let raised = rlimit::increase_nofile_limit(u64::MAX).ok();
        let soft = raised.or_else(|| rlimit::Resource::NOFILE.get().ok().map(|(soft, _)| soft))?;
        (soft != rlimit::INFINITY).then_some(soft)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// How many connections the server takes at once when `requested` are asked for: at most
/// the open-file limit (raised first, see [`open_file_limit`]) less `FILE_RESERVE` (64 open
/// files kept for the store, the listening socket and refusals), and at least one.
pub fn connection_cap(requested: usize) -> usize {
    match open_file_limit() {
        Some(files) => {
            let room = usize::try_from(files.saturating_sub(FILE_RESERVE)).unwrap_or(usize::MAX);
            requested.min(room).max(1)
        }
        None => requested.max(1),
    }
}
