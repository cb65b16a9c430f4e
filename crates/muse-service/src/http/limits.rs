//! What the server allows a client: the timeouts and the connection cap, their defaults, the
//! check of their bounds, and the cap the open-file limit leaves room for. The bounds are
//! those of the command line's options, in the one range table
//! ([`muse_formats::ranges::TIMEOUT_S`], [`muse_formats::ranges::MAX_CONNECTIONS`]), which
//! `muse serve` reads its options through.

use std::time::Duration;

use muse_formats::ranges::{MAX_CONNECTIONS, TIMEOUT_S};

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
    /// Checks that every timeout is within [`TIMEOUT_S`] (0.1 s to a day) and that at least
    /// one connection is allowed (no more is asked: [`connection_cap`] lowers a larger number
    /// to what the process can open); the error names the field.
    pub fn check(&self) -> Result<(), String> {
        for (name, t) in [
            ("header_timeout", self.header_timeout),
            ("body_timeout", self.body_timeout),
            ("idle_timeout", self.idle_timeout),
        ] {
            if !TIMEOUT_S.contains_duration(t) {
                return Err(format!(
                    "{name} must be between {} and {} seconds, got {}",
                    TIMEOUT_S.lo,
                    TIMEOUT_S.hi,
                    t.as_secs_f64()
                ));
            }
        }
        if self.max_connections < MAX_CONNECTIONS.lo {
            return Err(format!(
                "max_connections must be at least {}",
                MAX_CONNECTIONS.lo
            ));
        }
        Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_checked() {
        assert_eq!(Limits::default().check(), Ok(()));
        let zero = Limits {
            idle_timeout: Duration::ZERO,
            ..Limits::default()
        };
        assert!(zero.check().unwrap_err().starts_with("idle_timeout "));
        let none = Limits {
            max_connections: 0,
            ..Limits::default()
        };
        assert!(none.check().unwrap_err().starts_with("max_connections "));
    }

    #[test]
    fn the_cap_leaves_room_for_files() {
        let files = open_file_limit();
        let cap = connection_cap(usize::MAX);
        match files {
            Some(f) => assert_eq!(cap as u64, f.saturating_sub(FILE_RESERVE).max(1)),
            None => assert_eq!(cap, usize::MAX),
        }
        assert_eq!(connection_cap(3), 3.min(cap));
    }
}
