//! Lazy greedy by exact simulation: add the candidate that delivers the most, one pick at a
//! time, each judged by [`Siting::evaluate`] on the same seeded days.
//!
//! Every candidate is evaluated once against the existing pads (in parallel). After that, a
//! candidate's last measured gain is kept as its bound: a round re-evaluates the candidates
//! with the highest bounds, [`BATCH`] at a time (in parallel), until the best is one measured
//! in this round, and picks it (ties: the lower candidate index). This is exact greedy when a
//! pad's gain never grows as other pads are added (diminishing returns, as for coverage);
//! with traffic it may grow — a new pad can open corridors that make another more useful —
//! and then a pick can differ from exact greedy's. The batch is a constant, so the picks do
//! not depend on the number of threads.

use rayon::prelude::*;

use muse_sim::stats::MeanCi;

use crate::{Evaluation, Siting, SitingError};

/// How many stale candidates a round re-evaluates at once (in parallel).
pub const BATCH: usize = 8;

/// How many unmeasured candidates the first round evaluates at once (in parallel).
const FIRST_ROUND_BATCH: usize = 64;

/// One pick of the greedy.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    /// The candidate added (index into the candidates).
    pub candidate: usize,
    /// What it added: delivered requests per day over the set before it (paired over days).
    pub gain: MeanCi,
    /// The set with it, evaluated.
    pub after: Evaluation,
    /// Evaluations made so far, this pick's round included.
    pub evaluations: usize,
}

/// The picks of [`lazy_greedy`].
#[derive(Clone, Debug, PartialEq)]
pub struct GreedyRun {
    /// The existing pads alone, evaluated.
    pub base: Evaluation,
    /// The picks, in order.
    pub picks: Vec<Pick>,
    /// Evaluations made in all (the base included).
    pub evaluations: usize,
}

impl GreedyRun {
    /// The candidates picked, in order.
    pub fn added(&self) -> Vec<usize> {
        self.picks.iter().map(|p| p.candidate).collect()
    }
}

/// How far [`lazy_greedy`] is: evaluations done and picks made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Evaluations done.
    pub evaluations: usize,
    /// Picks made.
    pub picks: usize,
}

/// Adds `k` candidates by lazy greedy on delivered requests (see the [module
/// documentation](self)); `progress` is called after each batch of evaluations.
///
/// # Errors
/// `k` above the number of candidates, or a pad set that gives no airspace.
pub fn lazy_greedy(
    siting: &Siting,
    k: usize,
    mut progress: impl FnMut(Progress),
) -> Result<GreedyRun, SitingError> {
    let count = siting.candidates().len();
    if k > count {
        return Err(SitingError::TooFewCandidates {
            wanted: k,
            available: count,
        });
    }
    let base = siting.evaluate(&[])?;
    let mut evaluations = 1;
    let mut current = base.clone();
    let mut added: Vec<usize> = Vec::with_capacity(k);
    // Each open candidate's last measured gain and the round it was measured in.
    let mut bound: Vec<Option<(f64, usize)>> = vec![None; count];
    let mut open: Vec<bool> = vec![true; count];
    let mut picks = Vec::with_capacity(k);
    for round in 0..k {
        let mut fresh: Vec<Option<Evaluation>> = vec![None; count];
        loop {
            let order = by_bound(&bound, &open);
            let top = order[0];
            if bound[top].is_some_and(|(_, r)| r == round) {
                let after = fresh[top].take().expect("measured this round");
                picks.push(Pick {
                    candidate: top,
                    gain: after.gain_over(&current),
                    after: after.clone(),
                    evaluations,
                });
                current = after;
                added.push(top);
                open[top] = false;
                break;
            }
            // Unmeasured candidates (the first round) go FIRST_ROUND_BATCH at a time, so
            // that progress shows; they all come before any measured one, so this changes
            // nothing else.
            let limit = if bound[top].is_none() {
                FIRST_ROUND_BATCH
            } else {
                BATCH
            };
            let batch: Vec<usize> = order
                .iter()
                .take_while(|&&c| bound[c].is_none_or(|(_, r)| r != round))
                .take(limit)
                .copied()
                .collect();
            let measured: Vec<Result<Evaluation, SitingError>> = batch
                .par_iter()
                .map(|&c| {
                    let mut set = added.clone();
                    set.push(c);
                    siting.evaluate(&set)
                })
                .collect();
            for (&c, m) in batch.iter().zip(measured) {
                let m = m?;
                bound[c] = Some((m.mean_delivered() - current.mean_delivered(), round));
                fresh[c] = Some(m);
            }
            evaluations += batch.len();
            progress(Progress {
                evaluations,
                picks: picks.len(),
            });
        }
    }
    Ok(GreedyRun {
        base,
        picks,
        evaluations,
    })
}

/// The open candidates, highest bound first (unmeasured ones first of all), ties by index.
fn by_bound(bound: &[Option<(f64, usize)>], open: &[bool]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..bound.len()).filter(|&c| open[c]).collect();
    let key = |c: usize| bound[c].map_or(f64::INFINITY, |(g, _)| g);
    order.sort_by(|&a, &b| key(b).total_cmp(&key(a)).then(a.cmp(&b)));
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::example_input;

    /// Exact greedy: every open candidate evaluated at every pick.
    fn exact_greedy(siting: &Siting, k: usize) -> Vec<usize> {
        let mut added = Vec::new();
        for _ in 0..k {
            let best = (0..siting.candidates().len())
                .filter(|c| !added.contains(c))
                .map(|c| {
                    let mut set = added.clone();
                    set.push(c);
                    (siting.evaluate(&set).unwrap().mean_delivered(), c)
                })
                .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
                .unwrap();
            added.push(best.1);
        }
        added
    }

    #[test]
    fn the_first_pick_is_the_best_single_candidate_and_gains_add_up() {
        let siting = Siting::prepare(example_input()).unwrap();
        let run = lazy_greedy(&siting, 3, |_| {}).unwrap();
        assert_eq!(run.picks.len(), 3);
        assert_eq!(run.picks[0].candidate, exact_greedy(&siting, 1)[0]);
        // The gains add up to the last set's deliveries over the base.
        let total: f64 = run.picks.iter().map(|p| p.gain.mean).sum();
        let last = &run.picks[2].after;
        assert!((total - (last.mean_delivered() - run.base.mean_delivered())).abs() < 1e-9);
        assert_eq!(*last, siting.evaluate(&run.added()).unwrap());
        // Lazy: fewer evaluations than exact greedy's 1 + 5 + 4 + 3.
        assert!(run.evaluations <= 13, "{}", run.evaluations);
    }

    #[test]
    fn too_many_picks_are_refused() {
        let siting = Siting::prepare(example_input()).unwrap();
        assert!(matches!(
            lazy_greedy(&siting, 6, |_| {}),
            Err(SitingError::TooFewCandidates {
                wanted: 6,
                available: 5
            })
        ));
    }
}
