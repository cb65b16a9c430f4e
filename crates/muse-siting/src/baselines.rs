//! The coverage models siting by simulation is compared with, for the same number of pads:
//!
//! - [`max_coverage`]: greedy maximum coverage (the range-limited facility location of the
//!   literature, with the last mile as the range): each pick is the candidate that puts the
//!   most customer weight not yet in reach of a pad within reach (ties: the lower index);
//! - [`kmeans_sites`]: k-means of demand: weighted k-means (k-means++ seeded, Lloyd to
//!   convergence, [`kmeans_weighted`]) of the customers no existing pad reaches — of all
//!   customers when fewer than `k` distinct such points remain — in the airspace's plane, each
//!   centre then taken by the nearest candidate not yet taken (ties: the lower index). When
//!   even all customers stand at fewer than `k` distinct positions, there are that many
//!   centres, and the centres take their next nearest candidates in turn until `k` are taken.
//!
//! Neither looks at traffic; both sets are then judged like any other, by
//! [`Siting::evaluate`].

use muse_model::{Node, NodeKind};
use muse_scenario::stations::kmeans_weighted;

use crate::{Siting, SitingError};

/// The first `k` picks of greedy maximum coverage, in order (see the [module
/// documentation](self)).
///
/// ```
/// # let siting = muse_siting::Siting::prepare(muse_siting::problem::example_input()).unwrap();
/// let picks = muse_siting::baselines::max_coverage(&siting, 2);
/// assert_eq!(picks.len(), 2);
/// assert_ne!(picks[0], picks[1]);
/// ```
pub fn max_coverage(siting: &Siting, k: usize) -> Vec<usize> {
    let existing = siting.input().existing.len();
    let count = siting.candidates().len();
    let weights: Vec<f64> = siting.input().customers.iter().map(|c| c.weight).collect();
    let mut covered: Vec<bool> = siting
        .reach()
        .iter()
        .map(|near| near.iter().any(|&(p, _)| p < existing))
        .collect();
    let mut reaches: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (customer, near) in siting.reach().iter().enumerate() {
        for &(p, _) in near {
            if p >= existing {
                reaches[p - existing].push(customer);
            }
        }
    }
    let mut open = vec![true; count];
    let mut picks = Vec::with_capacity(k.min(count));
    for _ in 0..k.min(count) {
        let gain = |c: usize| -> f64 {
            reaches[c]
                .iter()
                .filter(|&&u| !covered[u])
                .map(|&u| weights[u])
                .sum()
        };
        let best = (0..count)
            .filter(|&c| open[c])
            .map(|c| (gain(c), c))
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
            .expect("an open candidate");
        open[best.1] = false;
        for &u in &reaches[best.1] {
            covered[u] = true;
        }
        picks.push(best.1);
    }
    picks
}

/// The `k` candidates k-means of demand places (see the [module documentation](self)), in the
/// order of the k-means++ centres; `seed` seeds the k-means++ draw.
///
/// # Errors
/// `k` above the number of candidates, or a position the airspace's plane cannot project.
pub fn kmeans_sites(siting: &Siting, k: usize, seed: u64) -> Result<Vec<usize>, SitingError> {
    let input = siting.input();
    let count = siting.candidates().len();
    if k == 0 || k > count {
        return Err(SitingError::TooFewCandidates {
            wanted: k,
            available: count,
        });
    }
    let node = |id: &str, pos| Node {
        id: id.to_owned(),
        kind: NodeKind::Station,
        name: String::new(),
        pos,
    };
    let nodes: Vec<Node> = input
        .customers
        .iter()
        .map(|c| node(&c.id, c.pos))
        .chain(input.candidates.iter().cloned())
        .collect();
    let plane = input.build.plane.project(&nodes)?;
    let xy: Vec<[f64; 2]> = plane.iter().map(|p| [p.x, p.y]).collect();
    let (customers_xy, candidates_xy) = xy.split_at(input.customers.len());
    let existing = input.existing.len();
    let uncovered: Vec<usize> = (0..input.customers.len())
        .filter(|&u| !siting.reach()[u].iter().any(|&(p, _)| p < existing))
        .collect();
    let distinct = |set: &[usize]| {
        let mut d: Vec<[f64; 2]> = set.iter().map(|&u| customers_xy[u]).collect();
        d.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
        d.dedup();
        d.len()
    };
    let everyone: Vec<usize> = (0..input.customers.len()).collect();
    let clustered = if distinct(&uncovered) >= k {
        uncovered
    } else {
        everyone
    };
    let points: Vec<[f64; 2]> = clustered.iter().map(|&u| customers_xy[u]).collect();
    let weights: Vec<f64> = clustered
        .iter()
        .map(|&u| input.customers[u].weight)
        .collect();
    // Fewer distinct positions than k: that many centres, the other pads beside them.
    let km = kmeans_weighted(&points, &weights, k.min(distinct(&clustered)), seed);
    let mut taken = vec![false; count];
    let mut picks = Vec::with_capacity(k);
    for c in km.centres.iter().cycle().take(k) {
        let best = (0..count)
            .filter(|&i| !taken[i])
            .map(|i| {
                let (dx, dy) = (candidates_xy[i][0] - c[0], candidates_xy[i][1] - c[1]);
                (dx * dx + dy * dy, i)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .expect("k is at most the number of candidates");
        taken[best.1] = true;
        picks.push(best.1);
    }
    Ok(picks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::example_input;

    #[test]
    fn max_coverage_takes_the_most_uncovered_weight_first() {
        let siting = Siting::prepare(example_input()).unwrap();
        let picks = max_coverage(&siting, 5);
        let mut sorted = picks.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, [0, 1, 2, 3, 4]);
        // The first pick covers at least as much new weight as any other single candidate.
        let existing = siting.input().existing.len();
        let new_weight = |c: usize| {
            siting
                .reach()
                .iter()
                .filter(|near| {
                    !near.iter().any(|&(p, _)| p < existing)
                        && near.iter().any(|&(p, _)| p == existing + c)
                })
                .count()
        };
        assert!((0..5).all(|c| new_weight(picks[0]) >= new_weight(c)));
    }

    #[test]
    fn kmeans_sites_are_distinct_and_seeded() {
        let siting = Siting::prepare(example_input()).unwrap();
        for k in 1..=5 {
            let picks = kmeans_sites(&siting, k, 1).unwrap();
            let mut sorted = picks.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), k);
            assert_eq!(picks, kmeans_sites(&siting, k, 1).unwrap());
        }
        assert!(kmeans_sites(&siting, 6, 1).is_err());
    }

    #[test]
    fn customers_at_fewer_positions_than_pads_still_give_k_pads() {
        let mut input = example_input();
        let here = input.customers[0].pos;
        for c in &mut input.customers {
            c.pos = here;
        }
        // Two positions in all.
        input.customers[1].pos = muse_model::LonLat::new(103.9, 1.4);
        let siting = Siting::prepare(input).unwrap();
        let picks = kmeans_sites(&siting, 4, 1).unwrap();
        let mut sorted = picks.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), 4);
    }
}
