//! How close flights come in metres (docs/reference.md#metric-separation): the closest approach
//! of any two flights and how many pairs come closer than given distances, exactly in
//! continuous time, for any set of plans (flat, layered, multi-leg, changed by zones).
//!
//! Each flight is flown exactly as planned ([`track`]): at its node during a stay, in a straight
//! line at constant pace between two stays, on the ground between legs. Two flights are closer
//! than `d` when at some instant both are airborne, less than `d` apart horizontally and less
//! than `V` apart vertically (the rule of metric separation, with `D = d`). Pairs of pieces are
//! found by a sweep over time with a grid (`sweep`) and compared exactly (`pair`).
//!
//! ```
//! use muse_model::{Airspace, Instant, NodeId, Plan, Request, Stay};
//! use muse_verify::Flight;
//! use muse_verify::approach::{Positions, report};
//!
//! // Two stations 1 km apart, 120 s per corridor; one flight each way, the second taking off
//! // 60 s after the first: they meet halfway, at the same place and instant.
//! let air = Airspace::line(&[1000.0]);
//! let plane = [[0.0, 0.0], [1000.0, 0.0]];
//! let positions = Positions::new(&air, &plane);
//! let stay = |n, t| Stay { node: NodeId(n), arrive: Instant(t), depart: Instant(t) };
//! let east = Plan { path: vec![stay(0, 0), stay(1, 120_000)] };
//! let west = Plan { path: vec![stay(1, 0), stay(0, 120_000)] };
//! let request = |id: &str, o, d| Request {
//!     id: id.into(),
//!     origin: NodeId(o),
//!     destination: NodeId(d),
//!     departure: Instant(0),
//!     submitted: Instant(0),
//! };
//! let (r1, r2) = (request("east", 0, 1), request("west", 1, 0));
//! let flights = [Flight::new("east", &r1, &east), Flight::new("west", &r2, &west)];
//! let r = report(&positions, &flights, &[10.0, 30.0], 9.144);
//! let closest = r.closest.unwrap();
//! assert!(closest.distance_m < 1e-9 && (closest.at_ms - 60_000.0).abs() < 1e-6);
//! assert_eq!(r.under, vec![(10.0, 1), (30.0, 1)]);
//! ```

pub mod pair;
mod sweep;
pub mod track;

use std::collections::HashMap;

use muse_model::{NodeId, Separation};

pub use track::Positions;

use crate::Flight;

/// The distances every report counts pairs under, metres.
pub const REPORTED_M: [f64; 3] = [10.0, 20.0, 30.0];

/// The farthest the closest approach is looked for, metres: flights never closer than this
/// have no closest approach reported.
pub const FARTHEST_M: f64 = 5_000.0;

/// The closest approach of two flights.
#[derive(Clone, Debug, PartialEq)]
pub struct Approach {
    /// The two flights (indices in the list given), the first the lower.
    pub flights: (usize, usize),
    /// Their horizontal distance, metres.
    pub distance_m: f64,
    /// The instant, milliseconds since the Unix epoch (not rounded).
    pub at_ms: f64,
    /// The node nearest to the first flight then.
    pub near: NodeId,
}

/// How close the flights come (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The closest approach of any two flights (`None`: never two airborne within
    /// [`FARTHEST_M`] of each other, closer than `V` vertically).
    pub closest: Option<Approach>,
    /// For each distance asked for, in the order asked, the pairs of flights closer than it.
    pub under: Vec<(f64, usize)>,
    /// The vertical separation `V` the report was made with, metres.
    pub vertical_m: f64,
}

/// How close `flights` come, flown over `positions`: the closest approach, and the pairs
/// closer than each of `distances` (metres), with vertical separation `vertical_m`.
#[must_use]
pub fn report(
    positions: &Positions,
    flights: &[Flight<'_>],
    distances: &[f64],
    vertical_m: f64,
) -> Report {
    let origin = time_origin(flights);
    let pieces = all_pieces(positions, flights, origin);
    let widest = distances.iter().copied().fold(REPORTED_M[2], f64::max);
    let mut r = widest;
    loop {
        let mut pairs: HashMap<(u32, u32), f64> = HashMap::new();
        let mut best: Option<(f64, f64, usize, usize)> = None;
        sweep::near_pairs(
            &pieces,
            r,
            vertical_m - Separation::VERTICAL_TOLERANCE_M,
            |i, j, d, t| {
                let (a, b) = (pieces[i].flight, pieces[j].flight);
                let key = (a.min(b), a.max(b));
                let e = pairs.entry(key).or_insert(d);
                *e = e.min(d);
                let better = best
                    .is_none_or(|(bd, bt, bi, bj)| (d, t, i.min(j), i.max(j)) < (bd, bt, bi, bj));
                if better {
                    best = Some((d, t, i.min(j), i.max(j)));
                }
            },
        );
        if best.is_some() || r >= FARTHEST_M {
            let closest = best.map(|(d, t, i, j)| approach(positions, &pieces, origin, d, t, i, j));
            let under = distances
                .iter()
                .map(|&x| (x, pairs.values().filter(|&&d| d < x).count()))
                .collect();
            return Report {
                closest,
                under,
                vertical_m,
            };
        }
        r = (r * 4.0).min(FARTHEST_M);
    }
}

/// Every pair of `flights` that comes closer than `distance` metres horizontally while
/// within `vertical_m` vertically, flown over `positions` (the pairs breaking metric separation
/// with `D = distance`), each with its closest approach, in the order of their flights.
#[must_use]
pub fn closer_than(
    positions: &Positions,
    flights: &[Flight<'_>],
    distance: f64,
    vertical_m: f64,
) -> Vec<Approach> {
    let origin = time_origin(flights);
    let pieces = all_pieces(positions, flights, origin);
    let mut pairs: HashMap<(u32, u32), (f64, f64, usize, usize)> = HashMap::new();
    let within = vertical_m - Separation::VERTICAL_TOLERANCE_M;
    sweep::near_pairs(&pieces, distance, within, |i, j, d, t| {
        if d >= distance {
            return;
        }
        let (a, b) = (pieces[i].flight, pieces[j].flight);
        let candidate = (d, t, i.min(j), i.max(j));
        pairs
            .entry((a.min(b), a.max(b)))
            .and_modify(|e| {
                if candidate < *e {
                    *e = candidate;
                }
            })
            .or_insert(candidate);
    });
    let mut out: Vec<Approach> = pairs
        .into_values()
        .map(|(d, t, i, j)| approach(positions, &pieces, origin, d, t, i, j))
        .collect();
    out.sort_by_key(|a| a.flights);
    out
}

/// The instant every piece's time is counted from: the first take-off.
fn time_origin(flights: &[Flight<'_>]) -> i64 {
    flights
        .iter()
        .filter_map(|f| f.plan.path.first())
        .map(|s| s.arrive.0)
        .min()
        .unwrap_or(0)
}

/// The pieces of every flight, by their start.
fn all_pieces(positions: &Positions, flights: &[Flight<'_>], origin: i64) -> Vec<track::Piece> {
    let mut pieces = Vec::new();
    for (k, f) in flights.iter().enumerate() {
        track::pieces(positions, f.plan, k as u32, origin, &mut pieces);
    }
    pieces.sort_by(|a, b| a.t0.total_cmp(&b.t0));
    pieces
}

/// The approach of pieces `i` and `j`, `d` apart at `t` seconds after `origin`.
fn approach(
    positions: &Positions,
    pieces: &[track::Piece],
    origin: i64,
    d: f64,
    t: f64,
    i: usize,
    j: usize,
) -> Approach {
    let (pi, pj) = (&pieces[i], &pieces[j]);
    let (first, second) = if pi.flight <= pj.flight {
        (pi, pj)
    } else {
        (pj, pi)
    };
    let at = first.at(t);
    let near = [first.from, first.to]
        .into_iter()
        .min_by(|&m, &n| dist2(positions.at(m), at).total_cmp(&dist2(positions.at(n), at)))
        .unwrap_or(first.from);
    Approach {
        flights: (first.flight as usize, second.flight as usize),
        distance_m: d,
        at_ms: origin as f64 + t * 1000.0,
        near,
    }
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

#[cfg(test)]
#[allow(clippy::many_single_char_names)]
mod tests {
    use super::track::Piece;
    use super::*;

    /// Random flights of straight pieces in a 600 m square about the origin over a few minutes, at three
    /// altitudes, each flight's pieces one after the other.
    fn random_pieces(seed: u64, flights: u32) -> Vec<Piece> {
        let mut x = seed;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut out = Vec::new();
        for f in 0..flights {
            let mut t = next() * 200.0;
            let mut p = [next() * 600.0 - 300.0, next() * 600.0 - 300.0, 60.0];
            for _ in 0..5 {
                let d = 1.0 + next() * 60.0;
                let q = if next() < 0.3 {
                    p
                } else {
                    [
                        next() * 600.0 - 300.0,
                        next() * 600.0 - 300.0,
                        60.0 + (next() * 3.0).floor() * 9.144,
                    ]
                };
                out.push(Piece {
                    flight: f,
                    t0: t,
                    t1: t + d,
                    p0: p,
                    p1: q,
                    from: NodeId(0),
                    to: NodeId(0),
                });
                t += d;
                p = q;
            }
        }
        out.sort_by(|a, b| a.t0.total_cmp(&b.t0));
        out
    }

    #[test]
    fn the_sweep_finds_every_pair_all_pairs_find() {
        let mut found = 0;
        for seed in 1..=40_u64 {
            let pieces = random_pieces(0x39_1000 + seed, 30);
            let r = 30.0;
            let mut swept: HashMap<(u32, u32), f64> = HashMap::new();
            sweep::near_pairs(&pieces, r, 9.144, |i, j, d, _| {
                let (a, b) = (pieces[i].flight, pieces[j].flight);
                let e = swept.entry((a.min(b), a.max(b))).or_insert(d);
                *e = e.min(d);
            });
            let mut all: HashMap<(u32, u32), f64> = HashMap::new();
            for (i, a) in pieces.iter().enumerate() {
                for b in &pieces[i + 1..] {
                    if a.flight == b.flight {
                        continue;
                    }
                    if let Some((d, _)) =
                        pair::closest(a, b, f64::NEG_INFINITY, f64::INFINITY, 9.144)
                        && d < r
                    {
                        let key = (a.flight.min(b.flight), a.flight.max(b.flight));
                        let e = all.entry(key).or_insert(d);
                        *e = e.min(d);
                    }
                }
            }
            assert_eq!(
                swept.keys().collect::<std::collections::BTreeSet<_>>(),
                all.keys().collect::<std::collections::BTreeSet<_>>(),
                "seed {seed}"
            );
            for (k, d) in &all {
                assert!(
                    (swept[k] - d).abs() < 1e-9,
                    "seed {seed} {k:?}: {} {d}",
                    swept[k]
                );
            }
            found += all.len();
        }
        assert!(
            found > 100,
            "only {found} close pairs in all: the test checks too little"
        );
    }
}
