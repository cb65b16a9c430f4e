//! Time inside the planner: the model's integer milliseconds, [`Instant`] for points in time
//! and [`Millis`] for durations, from the schedule through the search, and one infinity for
//! both.
//!
//! Both are `#[repr(transparent)]` newtypes over `i64` with inlined arithmetic, so typing the
//! planner costs nothing at run time: the labels, the heap keys and the reservation lists hold
//! the same words as before.

use muse_model::{Instant, Millis};

/// The planner's one infinity, ms: beyond any instant or duration MUSE handles (±1.4 × 10¹⁵
/// years), with headroom so that adding durations to it cannot overflow.
const INFINITY_MS: i64 = i64::MAX / 4;

/// The unbounded values of a time type, both at the one infinity.
pub(crate) trait Unbounded {
    /// Beyond every value MUSE handles: for an instant "never" (an interval that does not
    /// end), for a duration "unreachable" (no remaining time at all).
    const INF: Self;
    /// Before every value MUSE handles: for an instant "always" (an interval that has no
    /// start), for a duration "no room at all".
    const NEG_INF: Self;
}

impl Unbounded for Instant {
    const INF: Instant = Instant(INFINITY_MS);
    const NEG_INF: Instant = Instant(-INFINITY_MS);
}

impl Unbounded for Millis {
    const INF: Millis = Millis(INFINITY_MS);
    const NEG_INF: Millis = Millis(-INFINITY_MS);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn infinity_has_headroom_and_is_one_value() {
        assert_eq!(Instant::INF.0, Millis::INF.0);
        assert_eq!(Instant::NEG_INF.0, -Instant::INF.0);
        // A day's worth of durations added to it stays far from overflow.
        let big = Millis(1_000_000_000_000);
        assert!((Instant::INF + big + big).0 > Instant::INF.0);
        assert!((Instant::NEG_INF - big - big).0 < Instant::NEG_INF.0);
        assert_eq!(std::mem::size_of::<Instant>(), std::mem::size_of::<i64>());
    }
}
