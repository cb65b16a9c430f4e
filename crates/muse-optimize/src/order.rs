//! Priority orders: a batch planned one request at a time, each against those before it, in
//! an order other than arrival.

use muse_model::{Millis, Request};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// An order in which to plan a batch one request at a time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// The planning order given, `(submitted, id)`: first come, first served
    /// (docs/reference.md#requests).
    Arrival,
    /// Earliest departure first.
    EarliestDeparture,
    /// Shortest free-flow trip first: short trips hold the airspace least.
    ShortestFirst,
    /// Longest free-flow trip first: long trips hold the most corridors at once.
    LongestFirst,
    /// Fewest alternatives first: requests with the fewest corridors their flight could use
    /// within its battery ([`Planner::alternatives`](muse_planner::Planner::alternatives))
    /// have the fewest ways around the others, so they are planned before.
    FewestAlternatives,
    /// A random order drawn from a seed.
    Random(u64),
}

impl Order {
    /// The name written in reports: `arrival`, `earliest-departure`, `shortest-first`,
    /// `longest-first`, `fewest-alternatives`, `random`.
    pub fn name(self) -> &'static str {
        match self {
            Order::Arrival => "arrival",
            Order::EarliestDeparture => "earliest-departure",
            Order::ShortestFirst => "shortest-first",
            Order::LongestFirst => "longest-first",
            Order::FewestAlternatives => "fewest-alternatives",
            Order::Random(_) => "random",
        }
    }

    /// The indices of `requests` in this order; ties keep the planning order. Requests with
    /// no free-flow time (they cannot fly) come last in the trip-length orders; requests with
    /// no alternative at all, last in `FewestAlternatives`.
    ///
    /// ```
    /// use muse_model::{Instant, Millis, NodeId, Request};
    /// use muse_optimize::Order;
    /// let r = |t| Request { id: String::new(), origin: NodeId(0), destination: NodeId(1),
    ///                       departure: Instant(t), submitted: Instant(0) };
    /// let requests = [r(50), r(10), r(30)];
    /// let free_flow = [Some(Millis(5)), Some(Millis(9)), None];
    /// let alternatives = [7, 3, 0];
    /// let ranked = |o: Order| o.ranked(&requests, &free_flow, &alternatives);
    /// assert_eq!(ranked(Order::EarliestDeparture), [1, 2, 0]);
    /// assert_eq!(ranked(Order::ShortestFirst), [0, 1, 2]);
    /// assert_eq!(ranked(Order::LongestFirst), [1, 0, 2]);
    /// assert_eq!(ranked(Order::FewestAlternatives), [1, 0, 2]);
    /// ```
    pub fn ranked(
        self,
        requests: &[Request],
        free_flow: &[Option<Millis>],
        alternatives: &[usize],
    ) -> Vec<usize> {
        let mut order: Vec<usize> = (0..requests.len()).collect();
        let unknown = |i: usize| free_flow[i].is_none();
        match self {
            Order::Arrival => {}
            Order::EarliestDeparture => order.sort_by_key(|&i| requests[i].departure),
            Order::ShortestFirst => order.sort_by_key(|&i| (unknown(i), free_flow[i])),
            Order::LongestFirst => {
                order.sort_by_key(|&i| (unknown(i), std::cmp::Reverse(free_flow[i])));
            }
            Order::FewestAlternatives => {
                order.sort_by_key(|&i| (alternatives[i] == 0, alternatives[i]));
            }
            Order::Random(seed) => shuffle(&mut order, &mut ChaCha8Rng::seed_from_u64(seed)),
        }
        order
    }
}

/// Shuffles `items` (Fisher–Yates) with draws from `rng`: the same seed gives the same order
/// on every machine.
pub(crate) fn shuffle<T>(items: &mut [T], rng: &mut ChaCha8Rng) {
    for i in (1..items.len()).rev() {
        let j = rng.random_range(0..=i);
        items.swap(i, j);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_seeded_shuffle_is_a_permutation_and_repeats() {
        let mut a: Vec<u32> = (0..100).collect();
        let mut b = a.clone();
        shuffle(&mut a, &mut ChaCha8Rng::seed_from_u64(7));
        shuffle(&mut b, &mut ChaCha8Rng::seed_from_u64(7));
        assert_eq!(a, b);
        assert_ne!(a, (0..100).collect::<Vec<_>>());
        a.sort_unstable();
        assert_eq!(a, (0..100).collect::<Vec<_>>());
    }
}
