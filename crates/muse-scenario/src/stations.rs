//! Choosing station car parks: seeded k-means over the candidates, then the real car park
//! nearest each centre.
//!
//! The rule, exactly (see also the [crate documentation](crate)):
//!
//! 1. Points: the candidates' SVY21 coordinates in metres, in the given order.
//! 2. **k-means++ initialisation** with a [`ChaCha8Rng`] seeded by
//!    [`SeedableRng::seed_from_u64`]. Uniform numbers in `[0, 1)` are made from the
//!    generator's raw `u64` output as `(x >> 11) · 2⁻⁵³`, so the choice depends only on the
//!    `ChaCha8` stream (which `rand_chacha` keeps stable), not on a sampling algorithm. The
//!    first centre is point `⌊u · n⌋`; each next centre is the first point whose running
//!    sum of squared distances to the nearest chosen centre exceeds `u · total`.
//! 3. **Lloyd iterations** until no point changes cluster (at most
//!    [`MAX_LLOYD_ITERATIONS`]): each point joins its nearest centre (ties: the lower centre
//!    index); each centre moves to the mean of its points (summed in point order); a centre
//!    whose cluster is empty stays where it is.
//! 4. **Snapping:** for centres in index order, the nearest candidate not yet taken (ties:
//!    the earlier candidate) becomes a station. Stations are therefore distinct real car
//!    parks.
//! 5. **Order:** north to south (SVY21 northing descending; ties by easting, then car park
//!    number). The scenario numbers them `S001`, `S002`, … in this order.

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

use crate::ScenarioError;
use crate::carparks::CarPark;

/// The cap on Lloyd iterations (the Singapore selection converges long before).
pub const MAX_LLOYD_ITERATIONS: usize = 1_000;

/// The outcome of [`kmeans`].
#[derive(Clone, Debug, PartialEq)]
pub struct KMeans {
    /// Final centres, in k-means++ pick order.
    pub centres: Vec<[f64; 2]>,
    /// For each point, the index of its centre.
    pub assignment: Vec<usize>,
    /// Number of Lloyd iterations run (the last one changed nothing, unless capped).
    pub iterations: usize,
    /// Sum of squared distances of the points to their centres.
    pub inertia: f64,
}

/// A uniform number in `[0, 1)` from the raw 64-bit output of `rng`.
pub(crate) fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

fn dist2(p: [f64; 2], q: [f64; 2]) -> f64 {
    let (dx, dy) = (p[0] - q[0], p[1] - q[1]);
    dx * dx + dy * dy
}

/// The index of the centre nearest `p` (ties: the lower index).
fn nearest(p: [f64; 2], centres: &[[f64; 2]]) -> usize {
    let mut best = (f64::INFINITY, 0);
    for (j, &c) in centres.iter().enumerate() {
        let d = dist2(p, c);
        if d < best.0 {
            best = (d, j);
        }
    }
    best.1
}

/// Seeded k-means (k-means++ initialisation, Lloyd iterations to convergence) of `points`
/// into `k` clusters; see the [module documentation](self) for the exact procedure.
/// `k` must be between 1 and the number of distinct points.
///
/// ```
/// use muse_scenario::stations::kmeans;
/// let pts = [[0.0, 0.0], [1.0, 0.0], [100.0, 0.0], [101.0, 0.0]];
/// let km = kmeans(&pts, 2, 7);
/// assert_eq!(km.assignment[0], km.assignment[1]);
/// assert_ne!(km.assignment[1], km.assignment[2]);
/// assert_eq!(km.inertia, 1.0);
/// ```
pub fn kmeans(points: &[[f64; 2]], k: usize, seed: u64) -> KMeans {
    kmeans_weighted(points, &vec![1.0; points.len()], k, seed)
}

/// [`kmeans`] of points that weigh differently (each weight finite and above 0): a point's
/// chance of becoming a k-means++ centre is its weight times its squared distance, and each
/// centre moves to the weighted mean of its points. With every weight 1 this is exactly
/// [`kmeans`] (the same arithmetic, bit for bit). `k` must be between 1 and the number of
/// distinct points.
///
/// ```
/// use muse_scenario::stations::kmeans_weighted;
/// // One cluster: the centre is pulled towards the heavy point.
/// let km = kmeans_weighted(&[[0.0, 0.0], [4.0, 0.0]], &[3.0, 1.0], 1, 1);
/// assert_eq!(km.centres, [[1.0, 0.0]]);
/// ```
pub fn kmeans_weighted(points: &[[f64; 2]], weights: &[f64], k: usize, seed: u64) -> KMeans {
    assert!(
        k >= 1 && k <= points.len(),
        "k = {k} must be in 1..={}",
        points.len()
    );
    assert_eq!(weights.len(), points.len(), "one weight per point");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = points.len();

    // k-means++ initialisation. The first centre is uniform over the points when they weigh
    // the same, else drawn by weight.
    let first = if weights.iter().all(|w| w.total_cmp(&1.0).is_eq()) {
        ((uniform(&mut rng) * n as f64) as usize).min(n - 1)
    } else {
        let total: f64 = weights.iter().sum();
        let target = uniform(&mut rng) * total;
        let mut acc = 0.0;
        weights
            .iter()
            .position(|&w| {
                acc += w;
                acc > target
            })
            .unwrap_or(n - 1)
    };
    let mut centres = vec![points[first]];
    let mut d2: Vec<f64> = points
        .iter()
        .zip(weights)
        .map(|(&p, &w)| w * dist2(p, points[first]))
        .collect();
    while centres.len() < k {
        let total: f64 = d2.iter().sum();
        let target = uniform(&mut rng) * total;
        let mut acc = 0.0;
        let mut pick = None;
        for (i, &w) in d2.iter().enumerate() {
            acc += w;
            if w > 0.0 && acc > target {
                pick = Some(i);
                break;
            }
        }
        // Rounding can leave `acc` just short of `target`: take the last eligible point.
        let pick = pick
            .or_else(|| d2.iter().rposition(|&w| w > 0.0))
            .expect("k is at most the number of distinct points");
        let c = points[pick];
        centres.push(c);
        for ((d, &p), &w) in d2.iter_mut().zip(points).zip(weights) {
            *d = d.min(w * dist2(p, c));
        }
    }

    // Lloyd iterations.
    let mut assignment: Vec<usize> = points.iter().map(|&p| nearest(p, &centres)).collect();
    let mut iterations = 0;
    while iterations < MAX_LLOYD_ITERATIONS {
        iterations += 1;
        let mut sums = vec![[0.0_f64; 2]; k];
        let mut mass = vec![0.0_f64; k];
        for ((&p, &a), &w) in points.iter().zip(&assignment).zip(weights) {
            sums[a][0] += w * p[0];
            sums[a][1] += w * p[1];
            mass[a] += w;
        }
        for ((c, s), &m) in centres.iter_mut().zip(&sums).zip(&mass) {
            if m > 0.0 {
                *c = [s[0] / m, s[1] / m];
            }
        }
        let next: Vec<usize> = points.iter().map(|&p| nearest(p, &centres)).collect();
        if next == assignment {
            break;
        }
        assignment = next;
    }
    let inertia = points
        .iter()
        .zip(&assignment)
        .zip(weights)
        .map(|((&p, &a), &w)| w * dist2(p, centres[a]))
        .sum();
    KMeans {
        centres,
        assignment,
        iterations,
        inertia,
    }
}

/// Chooses `k` distinct stations among `candidates` by the rule in the
/// [module documentation](self): seeded k-means, the nearest untaken car park to each
/// centre, ordered north to south.
///
/// ```
/// use muse_scenario::carparks::multi_storey_car_parks;
/// use muse_scenario::stations::select_stations;
/// let chosen = select_stations(&multi_storey_car_parks().unwrap(), 5, 1).unwrap();
/// assert_eq!(chosen.len(), 5);
/// assert!(chosen.windows(2).all(|w| w[0].svy21.northing >= w[1].svy21.northing));
/// ```
pub fn select_stations(
    candidates: &[CarPark],
    k: usize,
    seed: u64,
) -> Result<Vec<CarPark>, ScenarioError> {
    let points: Vec<[f64; 2]> = candidates
        .iter()
        .map(|c| [c.svy21.easting, c.svy21.northing])
        .collect();
    let mut distinct = points.clone();
    distinct.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    distinct.dedup();
    if k == 0 || k > distinct.len() {
        return Err(ScenarioError::TooFewCandidates {
            wanted: k,
            available: distinct.len(),
        });
    }
    let km = kmeans(&points, k, seed);
    let mut taken = vec![false; candidates.len()];
    let mut chosen = Vec::with_capacity(k);
    for &c in &km.centres {
        let mut best: Option<(f64, usize)> = None;
        for (i, &p) in points.iter().enumerate() {
            let d = dist2(p, c);
            if !taken[i] && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i));
            }
        }
        let (_, i) = best.expect("k is at most the number of candidates");
        taken[i] = true;
        chosen.push(candidates[i].clone());
    }
    chosen.sort_by(|a, b| {
        b.svy21
            .northing
            .total_cmp(&a.svy21.northing)
            .then(a.svy21.easting.total_cmp(&b.svy21.easting))
            .then(a.number.cmp(&b.number))
    });
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kmeans_is_deterministic_and_converges() {
        let pts: Vec<[f64; 2]> = (0..200)
            .map(|i| {
                let t = f64::from(i);
                [(t * 37.0) % 101.0, (t * 53.0) % 97.0]
            })
            .collect();
        let a = kmeans(&pts, 8, 3);
        let b = kmeans(&pts, 8, 3);
        assert_eq!(a, b);
        assert!(a.iterations < MAX_LLOYD_ITERATIONS);
        // Converged: every point is with its nearest centre.
        for (p, &c) in pts.iter().zip(&a.assignment) {
            assert_eq!(nearest(*p, &a.centres), c);
        }
        assert_ne!(kmeans(&pts, 8, 4).centres, a.centres, "the seed matters");
    }

    #[test]
    fn too_few_candidates() {
        let c = CarPark {
            number: "X".into(),
            address: String::new(),
            car_park_type: String::new(),
            svy21: muse_model::Svy21::new(1.0, 2.0),
        };
        let err = select_stations(&[c.clone(), c], 2, 0).unwrap_err();
        assert!(matches!(
            err,
            ScenarioError::TooFewCandidates {
                wanted: 2,
                available: 1
            }
        ));
    }
}
