//! The open-loop schedule: request `i` is due at `t0 + i / rate`, whatever happened to the
//! requests before it.
//!
//! Measuring each latency from its request's due time, not from when it was actually sent,
//! is what keeps an open-loop run free of *coordinated omission*: when the server (or the
//! load generator itself) stalls, the requests that should have gone out during the stall
//! are charged the stall, as a real population of independent clients would experience it.

use std::time::Duration;

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
}

/// Whether a request sent `lag` after its due time counts as late (and so as one the
/// generator could not send on time): more than this.
pub const LATE: Duration = Duration::from_millis(10);

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
        assert_eq!(s.due(3 * 86_400), Duration::from_secs(86_400));
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
}
