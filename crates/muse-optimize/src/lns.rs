//! Large-neighbourhood search (after Shaw, and MAPF-LNS): take a few flights out of the
//! schedule, plan a request that could not fly together with them again in a new order with
//! the exact planner, and keep the result unless the objective got worse.
//!
//! The neighbourhood of a request is the flights in its way: those that stay at a node of the
//! plan it would fly alone, within the time it could be there (its free-flow instant, up to
//! the ground delay and the battery's slack later, widened by the node separation).

use muse_model::{Millis, Plan};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::order::shuffle;
use crate::working::Working;

/// What one step tried and whether it was kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// The objective improved.
    Better,
    /// As good as before (kept: it moves the search along a plateau).
    Same,
    /// Worse, and kept all the same (simulated annealing).
    Worse,
    /// Worse: undone.
    Undone,
}

/// The flights in the way of request `target`, whose plan alone is `alone`: every planned
/// request with a stay at a node of `alone` in `[arrive − tau, depart + slack + tau]`,
/// nearest in time first (how far its stay begins from the instant `alone` reaches the
/// node), without `target`.
pub(crate) fn in_the_way(
    working: &Working<'_>,
    target: usize,
    alone: &Plan,
    slack: Millis,
    tau: Millis,
) -> Vec<usize> {
    let mut found: Vec<(Millis, usize)> = Vec::new();
    for s in &alone.path {
        let (lo, hi) = (s.arrive - tau, s.depart + slack + tau);
        for v in working.visits(s.node.index()) {
            if v.arrive <= hi && v.depart >= lo {
                let gap = if v.arrive >= s.arrive {
                    v.arrive - s.arrive
                } else {
                    s.arrive - v.arrive
                };
                found.push((gap, v.request as usize));
            }
        }
    }
    // Each flight once, at its nearest stay: by flight then gap, the first of each flight.
    found.sort_unstable_by_key(|&(gap, i)| (i, gap));
    found.dedup_by_key(|&mut (_, i)| i);
    found.retain(|&(_, i)| i != target);
    found.sort_unstable();
    found.into_iter().map(|(_, i)| i).collect()
}

/// One step: takes `out` (planned requests) out of the schedule, plans `first` (not
/// planned, or among `out`), then the rest of `out` in a random order, then `extras`
/// (requests holding no plan, in the order given) where they now fit, and keeps the result
/// unless the objective is worse and `keep_worse` is false, in which case everything is put
/// back as it was.
pub(crate) fn step(
    working: &mut Working<'_>,
    first: usize,
    out: &[usize],
    extras: &[usize],
    keep_worse: bool,
    rng: &mut ChaCha8Rng,
) -> Step {
    let before = working.objective();
    let mut saved: Vec<(usize, Plan)> = Vec::with_capacity(out.len() + 1);
    for &i in out {
        saved.push((i, working.take_out(i)));
    }
    let mut order: Vec<usize> = out.iter().copied().filter(|&i| i != first).collect();
    shuffle(&mut order, rng);
    let mut tried = Vec::with_capacity(order.len() + extras.len() + 1);
    tried.push(first);
    tried.extend(order);
    tried.extend(extras.iter().copied().filter(|&i| i != first));
    for &i in &tried {
        working.try_plan(i);
    }
    let after = working.objective();
    if after > before {
        return Step::Better;
    }
    if after == before {
        return Step::Same;
    }
    if keep_worse {
        return Step::Worse;
    }
    for &i in &tried {
        if working.plan(i).is_some() {
            working.take_out(i);
        }
    }
    for (i, plan) in saved {
        working.book(i, plan);
    }
    debug_assert_eq!(working.objective(), before);
    Step::Undone
}

/// Up to `most` of `candidates` (nearest first): the nearest, or, one time in four, a random
/// draw of them, so that the search does not keep trying the same few.
pub(crate) fn pick(mut candidates: Vec<usize>, most: usize, rng: &mut ChaCha8Rng) -> Vec<usize> {
    if candidates.len() > most {
        if rng.random_range(0..4) == 0 {
            shuffle(&mut candidates, rng);
        }
        candidates.truncate(most);
    }
    candidates
}

/// A random size of neighbourhood, from 1 to `most`.
pub(crate) fn size(most: usize, rng: &mut ChaCha8Rng) -> usize {
    rng.random_range(1..=most.max(1))
}
