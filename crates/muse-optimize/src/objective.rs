//! The objective of docs/reference.md#batch-planning: most requests planned, then least total
//! delay.

use std::cmp::Ordering;
use std::fmt;

use muse_model::{Millis, Plan, Request};

/// How good a schedule is (docs/reference.md#batch-planning), compared lexicographically: more
/// requests planned is better; with as many planned, less total delay is better. `Ord` puts the
/// better one greater.
///
/// ```
/// use muse_model::Millis;
/// use muse_optimize::Objective;
/// let fcfs = Objective { planned: 9, delay: Millis(60_000) };
/// let more = Objective { planned: 10, delay: Millis(600_000) };
/// let sooner = Objective { planned: 9, delay: Millis(30_000) };
/// assert!(more > fcfs && sooner > fcfs && more > sooner);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Objective {
    /// Requests planned.
    pub planned: usize,
    /// Total delay: the sum over planned requests of `landing − departure − free_flow`.
    pub delay: Millis,
}

impl Objective {
    /// The delay of one planned request: `landing − departure − free_flow`.
    pub fn delay_of(request: &Request, plan: &Plan, free_flow: Millis) -> Millis {
        plan.landing() - request.departure - free_flow
    }

    /// The objective with one more planned request of delay `delay`.
    #[must_use]
    pub fn with(self, delay: Millis) -> Self {
        Objective {
            planned: self.planned + 1,
            delay: self.delay + delay,
        }
    }

    /// The objective with one planned request of delay `delay` fewer.
    #[must_use]
    pub fn without(self, delay: Millis) -> Self {
        Objective {
            planned: self.planned - 1,
            delay: self.delay - delay,
        }
    }
}

impl Ord for Objective {
    fn cmp(&self, other: &Self) -> Ordering {
        self.planned
            .cmp(&other.planned)
            .then_with(|| other.delay.cmp(&self.delay))
    }
}

impl PartialOrd for Objective {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl fmt::Display for Objective {
    /// `5686 planned, total delay 822180.0 s`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} planned, total delay {:.1} s",
            self.planned,
            self.delay.as_secs_f64()
        )
    }
}
