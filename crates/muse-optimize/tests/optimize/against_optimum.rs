//! The optimiser against the true optimum of small batches (`optimum`: every valid schedule,
//! not only those planned in some order): the optimum is never beaten (or the optimum or the
//! optimiser would be wrong), its schedule passes the independent verifier, and the report
//! says how often, and after how many steps, the optimiser reaches it.

use std::time::Instant;

use muse_optimize::{Objective, Options, optimize};
use muse_planner::Planner;
use muse_verify::{Flight, verify};

use crate::instances::{Instance, instance};
use crate::optimum::optimum;
use crate::orders::best_over_orders;

/// The step budgets tried, smallest first.
const BUDGETS: [u64; 5] = [0, 10, 100, 500, 2_000];

/// Most search nodes expanded for one optimum.
const CAP: usize = 5_000;

/// First come, first served's objective on `inst`, the optimiser's after each of the
/// budgets, and its wall time with the largest.
fn optimised(inst: &Instance, seed: u64) -> (Objective, Vec<Objective>, f64) {
    let planner = Planner::new(&inst.airspace, inst.params);
    let (mut fcfs, mut elapsed) = (Objective::default(), 0.0);
    let got = BUDGETS
        .iter()
        .map(|&iterations| {
            let options = Options {
                iterations,
                seed,
                ..Options::default()
            };
            let report =
                optimize(&planner, &inst.closures(), &inst.requests, &options, |_| {}).report;
            (fcfs, elapsed) = (report.fcfs, report.elapsed.as_secs_f64());
            report.result
        })
        .collect();
    (fcfs, got, elapsed)
}

/// The objectives after each budget, as `0: 7/41, 10: …` (planned / total delay in s).
fn steps(got: &[Objective]) -> String {
    BUDGETS
        .iter()
        .zip(got)
        .map(|(b, o)| format!("{b}: {}/{:.0}", o.planned, o.delay.as_secs_f64()))
        .collect::<Vec<_>>()
        .join(", ")
}

#[test]
fn the_optimiser_against_the_true_optimum_of_small_batches() {
    let seeds = 0..40_u64;
    println!("seeds {seeds:?}, 5 to 8 requests, budgets {BUDGETS:?} steps, cap {CAP} nodes");
    let mut reached = [0_usize; BUDGETS.len()];
    let mut count_reached = [0_usize; BUDGETS.len()];
    let mut fcfs_reached = 0;
    let (mut solved, mut expanded, mut search_s, mut optimiser_s) = (0, Vec::new(), 0.0, 0.0);
    for seed in seeds.clone() {
        let inst = instance(seed, 5 + (seed as usize % 4), false);
        let context = format!("seed {seed}, {} requests", inst.requests.len());
        let clock = Instant::now();
        let best = optimum(&inst, CAP);
        search_s += clock.elapsed().as_secs_f64();
        let (fcfs, got, took) = optimised(&inst, seed);
        optimiser_s += took;
        let best = match best {
            Ok(best) => best,
            Err(bound) => {
                // Not proven: still, nothing beats the bound.
                assert!(got.iter().all(|o| *o <= bound), "{context}: beyond {bound}");
                println!(
                    "{context}: not proven; no schedule beats {bound}; {}",
                    steps(&got)
                );
                continue;
            }
        };
        solved += 1;
        fcfs_reached += usize::from(fcfs == best.objective);
        expanded.push(best.expanded);
        let flights: Vec<Flight<'_>> = inst
            .requests
            .iter()
            .zip(&best.plans)
            .filter_map(|(r, p)| p.as_ref().map(|p| Flight::new(&r.id, r, p)))
            .collect();
        let violations = verify(&inst.airspace, &inst.closures(), &inst.params, &flights);
        assert!(
            violations.is_empty(),
            "{context}: the optimum {violations:#?}"
        );
        for (b, o) in got.iter().enumerate() {
            assert!(
                *o <= best.objective,
                "{context}: {o} beats {}",
                best.objective
            );
            reached[b] += usize::from(*o == best.objective);
            count_reached[b] += usize::from(o.planned == best.objective.planned);
        }
        let missed = got[BUDGETS.len() - 1] < best.objective;
        let orders = if missed {
            // Is the optimum one order away, or does it need a plan the planner never gives?
            let planner = Planner::new(&inst.airspace, inst.params);
            let by_order = best_over_orders(&inst, &planner);
            assert!(by_order <= best.objective, "{context}: {by_order}");
            format!("; the best over every order: {by_order}")
        } else {
            String::new()
        };
        println!(
            "{context}: optimum {} ({} nodes); {}{orders}",
            best.objective,
            best.expanded,
            steps(&got)
        );
    }
    expanded.sort_unstable();
    println!(
        "optimum proven on {solved} of {} batches (search {search_s:.2} s; nodes median {}, \
         max {}); the optimiser's {} steps took {optimiser_s:.2} s in all",
        seeds.end,
        expanded.get(expanded.len() / 2).unwrap_or(&0),
        expanded.last().unwrap_or(&0),
        BUDGETS[BUDGETS.len() - 1]
    );
    println!("first come, first served is optimal on {fcfs_reached} of {solved}");
    for (b, iterations) in BUDGETS.iter().enumerate() {
        println!(
            "{iterations:>5} steps: the optimum reached on {} of {solved}, its count on {}",
            reached[b], count_reached[b]
        );
    }
    assert!(solved * 10 >= 40 * 9, "proven on only {solved} of 40");
    assert!(
        count_reached[BUDGETS.len() - 1] * 10 >= solved * 9,
        "the optimum count reached on too few"
    );
}
