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

use muse_sim::experiment::Shard;
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
    progress: impl FnMut(Progress),
) -> Result<GreedyRun, SitingError> {
    lazy_greedy_from(siting, k, None, progress)
}

/// The first round: the existing pads evaluated, and each candidate of `shard` (candidate
/// `c` when `c mod N = K`) evaluated with them, in parallel; `progress` is called with the
/// evaluations done. The rounds after it need every candidate's first evaluation: merge the
/// shards' and give them to [`lazy_greedy_from`].
///
/// # Errors
/// A pad set that gives no airspace.
pub fn first_round(
    siting: &Siting,
    shard: Shard,
    mut progress: impl FnMut(usize),
) -> Result<FirstRound, SitingError> {
    let base = siting.evaluate(&[])?;
    let mine: Vec<usize> = (0..siting.candidates().len())
        .filter(|&c| shard.takes(c))
        .collect();
    let mut evaluations = Vec::with_capacity(mine.len());
    for chunk in mine.chunks(FIRST_ROUND_BATCH) {
        let measured: Vec<Result<Evaluation, SitingError>> =
            chunk.par_iter().map(|&c| siting.evaluate(&[c])).collect();
        for (&c, m) in chunk.iter().zip(measured) {
            evaluations.push((c, m?));
        }
        progress(evaluations.len() + 1);
    }
    Ok(FirstRound { base, evaluations })
}

/// The existing pads and candidates evaluated with them alone: the greedy's first round, or
/// a shard of it ([`first_round`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FirstRound {
    /// The existing pads alone.
    pub base: Evaluation,
    /// `(candidate, the existing pads with it)`.
    pub evaluations: Vec<(usize, Evaluation)>,
}

/// [`lazy_greedy`], its first round given (every candidate once, e.g. merged from shards) or
/// evaluated here (`None`).
///
/// # Errors
/// `k` above the number of candidates; a first round that does not give every candidate
/// once, or whose days differ in number; a pad set that gives no airspace.
pub fn lazy_greedy_from(
    siting: &Siting,
    k: usize,
    first: Option<FirstRound>,
    mut progress: impl FnMut(Progress),
) -> Result<GreedyRun, SitingError> {
    let count = siting.candidates().len();
    if k > count {
        return Err(SitingError::TooFewCandidates {
            wanted: k,
            available: count,
        });
    }
    // Each open candidate's last measured gain and the round it was measured in.
    let mut bound: Vec<Option<(f64, usize)>> = vec![None; count];
    let mut fresh: Vec<Option<Evaluation>> = vec![None; count];
    let (base, mut evaluations) = match first {
        None => (siting.evaluate(&[])?, 1),
        Some(first) => {
            let days = siting.day_count();
            let given = first.evaluations.len();
            for (c, e) in first.evaluations {
                if c >= count || fresh[c].is_some() || e.delivered.len() != days {
                    return Err(SitingError::FirstRound(format!(
                        "candidate {c} is out of range, given twice, or judged on other days"
                    )));
                }
                bound[c] = Some((e.mean_delivered() - first.base.mean_delivered(), 0));
                fresh[c] = Some(e);
            }
            if given != count || first.base.delivered.len() != days {
                return Err(SitingError::FirstRound(format!(
                    "{given} of the {count} candidates are evaluated"
                )));
            }
            (first.base, given + 1)
        }
    };
    let mut current = base.clone();
    let mut added: Vec<usize> = Vec::with_capacity(k);
    let mut open: Vec<bool> = vec![true; count];
    let mut picks = Vec::with_capacity(k);
    for round in 0..k {
        if round > 0 {
            fresh = vec![None; count];
        }
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
    fn a_first_round_merged_from_shards_picks_as_one_run_does() {
        let siting = Siting::prepare(example_input()).unwrap();
        let whole = lazy_greedy(&siting, 3, |_| {}).unwrap();
        let shards: Vec<FirstRound> = (0..3)
            .map(|index| first_round(&siting, Shard { index, of: 3 }, |_| {}).unwrap())
            .collect();
        let mut merged = FirstRound {
            base: shards[0].base.clone(),
            evaluations: Vec::new(),
        };
        for s in shards {
            assert_eq!(s.base, merged.base);
            merged.evaluations.extend(s.evaluations);
        }
        let again = lazy_greedy_from(&siting, 3, Some(merged.clone()), |_| {}).unwrap();
        assert_eq!(again, whole);
        // A first round that misses a candidate is refused.
        merged.evaluations.pop();
        assert!(matches!(
            lazy_greedy_from(&siting, 3, Some(merged), |_| {}),
            Err(SitingError::FirstRound(_))
        ));
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
