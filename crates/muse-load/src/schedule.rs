//! The open-loop schedule: request `i` is due at `t0 + i / rate`, whatever happened to the
//! requests before it.
//!
//! Measuring each latency from its request's due time, not from when it was actually sent,
//! is what keeps an open-loop run free of *coordinated omission*: when the server (or the
//! load generator itself) stalls, the requests that should have gone out during the stall
//! are charged the stall, as a real population of independent clients would experience it.
//!
//! Open loop ([`crate::Mode::Open`]) sends each request at its due time from the async
//! timer; paced runs ([`crate::Mode::Paced`]) release the same due times from a thread of
//! their own ([`pace`]) to a fixed number of clients.

use std::time::{Duration, Instant};

use crate::config::Stop;

/// Requests due at a fixed rate from a start instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OpenSchedule {
    /// Requests per second (finite, positive).
    rate: f64,
}

impl OpenSchedule {
    /// A schedule of `rate` requests per second; `None` unless `rate` is finite and positive.
    pub fn new(rate: f64) -> Option<Self> {
        (rate.is_finite() && rate > 0.0).then_some(OpenSchedule { rate })
    }

    /// The rate, requests per second.
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// When request `i` (0-based) is due, after the start: `i / rate`, to the nanosecond
    /// (rounded to nearest).
    ///
    /// ```
    /// use std::time::Duration;
    /// use muse_load::schedule::OpenSchedule;
    /// let s = OpenSchedule::new(2_000.0).unwrap();
    /// assert_eq!(s.due(0), Duration::ZERO);
    /// assert_eq!(s.due(1), Duration::from_micros(500));
    /// assert_eq!(s.due(2_000), Duration::from_secs(1));
    /// ```
    pub fn due(&self, i: u64) -> Duration {
        // Whole seconds exactly, the remainder in floating point: exact for integer rates
        // and never drifting over long runs.
        let per_second = self.rate;
        let whole = (i as f64 / per_second).floor();
        let rest = i as f64 - whole * per_second;
        let nanos = (rest * 1e9 / per_second).round();
        Duration::from_secs(whole as u64) + Duration::from_nanos(nanos as u64)
    }

    /// How many requests are due strictly before `d` after the start: the count of an
    /// open-loop run of duration `d`.
    ///
    /// ```
    /// use std::time::Duration;
    /// use muse_load::schedule::OpenSchedule;
    /// let s = OpenSchedule::new(2_000.0).unwrap();
    /// assert_eq!(s.count_within(Duration::from_secs(30)), 60_000);
    /// ```
    pub fn count_within(&self, d: Duration) -> u64 {
        // First guess from floating point, then corrected against `due` itself so that the
        // two definitions can never disagree.
        let mut n = (d.as_secs_f64() * self.rate).ceil().max(0.0) as u64;
        while n > 0 && self.due(n - 1) >= d {
            n -= 1;
        }
        while self.due(n) < d {
            n += 1;
        }
        n
    }

    /// How many requests a run stopping at `stop` sends: `n` for [`Stop::Count`]`(n)`, and
    /// [`OpenSchedule::count_within`] the duration for [`Stop::Duration`] (every request due
    /// before the end is sent, however late).
    ///
    /// ```
    /// use std::time::Duration;
    /// use muse_load::Stop;
    /// use muse_load::schedule::OpenSchedule;
    /// let s = OpenSchedule::new(500.0).unwrap();
    /// assert_eq!(s.count_of(Stop::Count(7)), 7);
    /// assert_eq!(s.count_of(Stop::Duration(Duration::from_secs(2))), 1_000);
    /// ```
    pub fn count_of(&self, stop: Stop) -> u64 {
        match stop {
            Stop::Count(n) => n,
            Stop::Duration(d) => self.count_within(d),
        }
    }
}

/// Whether a request sent `lag` after its due time counts as late (and so as one the
/// generator could not send on time) in open loop: more than this. (The async timer that
/// open loop sleeps on has millisecond granularity.)
pub const LATE: Duration = Duration::from_millis(10);

/// Whether a request sent `lag` after its due time counts as late in a paced run: more than
/// this. Its due times come from [`pace`], precise to tens of microseconds, so a request is
/// late by more than this only when every client was busy or the machine stalled.
pub const PACED_LATE: Duration = Duration::from_millis(1);

/// Releases requests `0..total` of `schedule`, request `i` at `t0 + schedule.due(i)`, by
/// calling `release(i, due)` then (or at once if that time has passed); stops early when
/// `release` returns `false` (the receiver is gone). Returns how many `release` accepted.
///
/// This blocks the calling thread in `std::thread::sleep` between due times and is meant
/// for a thread of its own: an operating-system sleep wakes within tens of microseconds of
/// its deadline, where the async timer rounds to the millisecond.
///
/// ```
/// use std::time::{Duration, Instant};
/// use muse_load::schedule::{OpenSchedule, pace};
/// let s = OpenSchedule::new(10_000.0).unwrap();
/// let t0 = Instant::now();
/// let mut released = Vec::new();
/// assert_eq!(pace(s, t0, 5, |i, due| { released.push((i, due)); true }), 5);
/// assert_eq!(released[4], (4, t0 + Duration::from_micros(400)));
/// assert!(t0.elapsed() >= Duration::from_micros(400));
/// ```
pub fn pace(
    schedule: OpenSchedule,
    t0: Instant,
    total: u64,
    mut release: impl FnMut(u64, Instant) -> bool,
) -> u64 {
    for i in 0..total {
        let due = t0 + schedule.due(i);
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        }
        if !release(i, due) {
            return i;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_non_positive_or_non_finite_rates() {
        assert!(OpenSchedule::new(0.0).is_none());
        assert!(OpenSchedule::new(-1.0).is_none());
        assert!(OpenSchedule::new(f64::NAN).is_none());
        assert!(OpenSchedule::new(f64::INFINITY).is_none());
        assert!(OpenSchedule::new(0.5).is_some());
    }

    #[test]
    fn due_times_are_evenly_spaced_and_exact_at_whole_seconds() {
        let s = OpenSchedule::new(3.0).unwrap();
        assert_eq!(s.due(0), Duration::ZERO);
        assert_eq!(s.due(1), Duration::from_nanos(333_333_333));
        assert_eq!(s.due(2), Duration::from_nanos(666_666_667));
        assert_eq!(s.due(3), Duration::from_secs(1));
        // No drift after a day at 3/s: still on the whole second.
        assert_eq!(s.due(3 * 86_400), Duration::from_hours(24));
        let slow = OpenSchedule::new(0.5).unwrap();
        assert_eq!(slow.due(1), Duration::from_secs(2));
        assert_eq!(slow.due(3), Duration::from_secs(6));
        // Strictly increasing at a high rate.
        let fast = OpenSchedule::new(123_457.0).unwrap();
        for i in 0..10_000 {
            assert!(fast.due(i + 1) > fast.due(i));
        }
    }

    #[test]
    fn the_count_of_a_duration_is_what_is_due_before_it() {
        let s = OpenSchedule::new(2_000.0).unwrap();
        assert_eq!(s.count_within(Duration::ZERO), 0);
        assert_eq!(s.count_within(Duration::from_nanos(1)), 1);
        assert_eq!(s.count_within(Duration::from_micros(500)), 1);
        assert_eq!(s.count_within(Duration::from_nanos(500_001)), 2);
        assert_eq!(s.count_within(Duration::from_secs(1)), 2_000);
        for rate in [0.5, 3.0, 7.25, 1_000.0, 2_000.0] {
            let s = OpenSchedule::new(rate).unwrap();
            for ms in [0, 1, 999, 1_000, 1_001, 30_000] {
                let d = Duration::from_millis(ms);
                let n = s.count_within(d);
                assert!(n == 0 || s.due(n - 1) < d, "rate {rate}, {ms} ms");
                assert!(s.due(n) >= d, "rate {rate}, {ms} ms");
            }
        }
    }

    #[test]
    fn the_count_of_a_stop() {
        let s = OpenSchedule::new(2_000.0).unwrap();
        assert_eq!(s.count_of(Stop::Count(3)), 3);
        assert_eq!(s.count_of(Stop::Duration(Duration::from_secs(30))), 60_000);
        assert_eq!(
            s.count_of(Stop::Duration(Duration::from_millis(1))),
            s.count_within(Duration::from_millis(1))
        );
    }

    #[test]
    fn pacing_releases_each_request_in_order_never_before_its_due_time() {
        let s = OpenSchedule::new(1_000.0).unwrap();
        let t0 = Instant::now();
        let mut released = Vec::new();
        let n = pace(s, t0, 20, |i, due| {
            released.push((i, due, Instant::now()));
            true
        });
        assert_eq!(n, 20);
        assert_eq!(released.len(), 20);
        for (k, &(i, due, at)) in released.iter().enumerate() {
            assert_eq!(i, k as u64);
            assert_eq!(due, t0 + s.due(i));
            assert!(at >= due, "request {i} released before its due time");
        }
        assert!(t0.elapsed() >= Duration::from_millis(19));
    }

    #[test]
    fn pacing_catches_up_at_once_and_stops_when_told() {
        let s = OpenSchedule::new(1_000.0).unwrap();
        // Started a second ago: everything is overdue and released without sleeping.
        let t0 = Instant::now().checked_sub(Duration::from_secs(1)).unwrap();
        let start = Instant::now();
        let mut count = 0;
        assert_eq!(
            pace(s, t0, 500, |_, _| {
                count += 1;
                true
            }),
            500
        );
        assert_eq!(count, 500);
        assert!(start.elapsed() < Duration::from_millis(500));
        // The receiver gone after three: the fourth is not released.
        let mut seen = Vec::new();
        let n = pace(s, t0, 10, |i, _| {
            seen.push(i);
            i < 3
        });
        assert_eq!((n, seen), (3, vec![0, 1, 2, 3]));
    }
}
