//! The optimiser of docs/reference.md#batch-planning: first come, first served, then priority
//! orders, then large-neighbourhood search, keeping the best schedule found and never a worse one.

use std::time::{Duration, Instant as WallInstant};

use muse_airspace::closures::Closures;
use muse_model::{Instant, Millis, Plan, RejectReason, Request};
use muse_planner::{FlightId, Outcome, Planner, Schedule, Scratch};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::lns::{Step, in_the_way, pick, size, step};
use crate::objective::Objective;
use crate::order::Order;
use crate::working::Working;

/// How hard to try.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Steps of large-neighbourhood search: the reproducible budget
    /// (docs/reference.md#batch-planning).
    pub iterations: u64,
    /// Stop early after this much wall time, if given (then the result depends on the
    /// machine's speed: not reproducible).
    pub time_budget: Option<Duration>,
    /// Seed of every random choice.
    pub seed: u64,
    /// Random orders tried besides the fixed ones.
    pub restarts: u32,
    /// Most flights taken out in one step.
    pub neighbourhood: usize,
    /// Simulated annealing: the chance, at the first step, that a step which makes the
    /// schedule worse is kept anyway, falling linearly to 0 at the last; `0` keeps only
    /// steps that leave it no worse. The best schedule seen is returned either way.
    pub anneal: f64,
}

impl Default for Options {
    /// 10,000 steps, no time budget, seed 1, 4 random orders, neighbourhoods of up to 8, no
    /// annealing.
    fn default() -> Self {
        Options {
            iterations: 10_000,
            time_budget: None,
            seed: 1,
            restarts: 4,
            neighbourhood: 8,
            anneal: 0.0,
        }
    }
}

/// What the optimiser did (docs/reference.md#batch-planning's report).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Report {
    /// First come, first served: the starting point.
    pub fcfs: Objective,
    /// The schedule returned: never worse than `fcfs`.
    pub result: Objective,
    /// Requests that can fly alone (on the empty schedule, with the zones): no schedule
    /// plans more.
    pub alone: usize,
    /// The order whose schedule the search started from (`arrival` is FCFS).
    pub start: &'static str,
    /// Orders tried, each with its objective.
    pub orders: Vec<(&'static str, Objective)>,
    /// Steps of large-neighbourhood search done.
    pub iterations: u64,
    /// Of which improved the objective.
    pub improved: u64,
    /// Whether the time budget ended the search before the iteration budget.
    pub timed_out: bool,
    /// Wall time, first come first served included.
    pub elapsed: Duration,
    /// Labels expanded by every search.
    pub expanded: u64,
    /// Requests served by first come, first served but rejected by the result (indices).
    pub displaced: Vec<usize>,
}

impl Report {
    /// Steps per second of wall time (`0` if none).
    pub fn iterations_per_s(&self) -> f64 {
        let s = self.elapsed.as_secs_f64();
        if s > 0.0 {
            self.iterations as f64 / s
        } else {
            0.0
        }
    }
}

/// The optimised schedule: one outcome per request, in the order given, and the report.
#[derive(Debug)]
pub struct Optimized {
    /// The answer to each request: its plan, or why it has none.
    pub outcomes: Vec<Outcome>,
    /// What the optimiser did.
    pub report: Report,
}

/// Plans `requests` (in planning order `(submitted, id)`, docs/reference.md#requests) as a batch
/// against `closures`: first come, first served, then the priority orders and `options.restarts`
/// random ones, then `options.iterations` steps of large-neighbourhood search from the best of
/// them, keeping only steps that leave the objective no worse. The result is never worse than first
/// come, first served, and with no time budget the same inputs give the same schedule on every
/// machine. `progress` is called with the steps done.
///
/// ```
/// use muse_airspace::closures::Closures;
/// use muse_model::{Airspace, FlightParams, Instant, NodeId, Request};
/// use muse_optimize::{Options, optimize};
/// use muse_planner::Planner;
/// // A - B - C, 1 km each (2 minutes at 30 km/h), no ground delay. The trip A → C is over
/// // the A-B corridor and at B when the trip B → A wants to leave B for A: whatever the
/// // order, one of them cannot fly, and the optimiser returns FCFS's schedule or as good.
/// let air = Airspace::line(&[1_000.0, 1_000.0]);
/// let planner = Planner::new(&air, FlightParams::default());
/// let r = |id: &str, o, d, t| Request { id: id.into(), origin: NodeId(o), destination: NodeId(d),
///                                       departure: Instant(t), submitted: Instant(0) };
/// let requests = [r("long", 0, 2, 0), r("short", 1, 0, 60_000)];
/// let out = optimize(&planner, &Closures::none(&air), &requests, &Options::default(), |_| {});
/// assert_eq!((out.report.fcfs.planned, out.report.result.planned, out.report.alone), (1, 1, 2));
/// assert_eq!(out.outcomes.len(), 2);
/// ```
pub fn optimize(
    planner: &Planner<'_>,
    closures: &Closures,
    requests: &[Request],
    options: &Options,
    progress: impl FnMut(u64),
) -> Optimized {
    let base = planner.schedule(closures);
    let ids: Vec<FlightId> = (0..requests.len()).map(FlightId::from).collect();
    optimize_on(planner, &base, requests, &ids, options, progress)
}

/// [`optimize`] on top of `base`, a schedule whose flights (booked before the batch) stay as
/// they are: the batch's requests are planned around them, request `i` as flight `ids[i]`
/// (ids `base` does not use). First come, first served is then the batch in the order given
/// on top of `base`, and "can fly alone" means with `base`'s flights and no other of the
/// batch. A service answering the requests that arrive together does this.
///
/// # Panics
/// If `ids` is not as long as `requests`.
pub fn optimize_on(
    planner: &Planner<'_>,
    base: &Schedule,
    requests: &[Request],
    ids: &[FlightId],
    options: &Options,
    progress: impl FnMut(u64),
) -> Optimized {
    assert_eq!(ids.len(), requests.len(), "one flight id per request");
    let started = WallInstant::now();
    let (alone, free_flow) = plans_alone(planner, base, requests);
    let alternatives: Vec<usize> = requests.iter().map(|r| planner.alternatives(r)).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let first = best_order(
        planner,
        base,
        (requests, ids),
        (&free_flow, &alternatives),
        options.restarts,
        &mut rng,
    );
    let mut working = first.working;
    let mut by_departure: Vec<usize> = (0..requests.len()).collect();
    by_departure.sort_by_key(|&i| (requests[i].departure, i));
    let search = Search {
        requests,
        by_departure,
        free_flow: &free_flow,
        alone: &alone,
        options,
        started,
    };
    let done = search.run(&mut working, &mut rng, progress);
    let outcomes = answers(&working, &free_flow);
    let displaced = (0..requests.len())
        .filter(|&i| first.fcfs_planned[i] && working.plan(i).is_none())
        .collect();
    let result = working.objective();
    debug_assert!(result >= first.tried[0].1);
    Optimized {
        outcomes,
        report: Report {
            fcfs: first.tried[0].1,
            result,
            alone: alone.iter().filter(|p| p.is_some()).count(),
            start: first.start.name(),
            orders: first.tried,
            iterations: done.iterations,
            improved: done.improved,
            timed_out: done.timed_out,
            elapsed: started.elapsed(),
            expanded: first.expanded + working.expanded,
            displaced,
        },
    }
}

/// The schedules of the priority orders, the best kept.
struct FirstSchedules<'a> {
    /// The best schedule.
    working: Working<'a>,
    /// The order that made it.
    start: Order,
    /// Every order tried (first come, first served first), with its objective.
    tried: Vec<(&'static str, Objective)>,
    /// Which requests first come, first served planned.
    fcfs_planned: Vec<bool>,
    /// Labels expanded by the orders other than the best.
    expanded: u64,
}

/// Plans the batch in arrival order (first come, first served), the fixed priority orders
/// and `restarts` random ones, and keeps the best (the first of equals).
fn best_order<'a>(
    planner: &'a Planner<'a>,
    base: &Schedule,
    (requests, ids): (&'a [Request], &'a [FlightId]),
    (free_flow, alternatives): (&'a [Option<Millis>], &[usize]),
    restarts: u32,
    rng: &mut ChaCha8Rng,
) -> FirstSchedules<'a> {
    let mut orders = vec![
        Order::Arrival,
        Order::EarliestDeparture,
        Order::ShortestFirst,
        Order::LongestFirst,
        Order::FewestAlternatives,
    ];
    for _ in 0..restarts {
        orders.push(Order::Random(rng.random()));
    }
    let mut tried = Vec::with_capacity(orders.len());
    let mut best: Option<(Working<'a>, Order)> = None;
    let mut fcfs_planned = Vec::new();
    let mut expanded = 0;
    for order in orders {
        let mut w = Working::new(planner, base.clone(), requests, ids, free_flow);
        for i in order.ranked(requests, free_flow, alternatives) {
            w.try_plan(i);
        }
        if order == Order::Arrival {
            fcfs_planned = w.plans().iter().map(Option::is_some).collect();
        }
        tried.push((order.name(), w.objective()));
        match &best {
            Some((b, _)) if w.objective() <= b.objective() => expanded += w.expanded,
            _ => {
                if let Some((old, _)) = best.take() {
                    expanded += old.expanded;
                }
                best = Some((w, order));
            }
        }
    }
    let (working, start) = best.expect("the arrival order is always tried");
    FirstSchedules {
        working,
        start,
        tried,
        fcfs_planned,
        expanded,
    }
}

/// The large-neighbourhood search over one batch.
struct Search<'a> {
    requests: &'a [Request],
    /// Every request's index, by departure (then index).
    by_departure: Vec<usize>,
    free_flow: &'a [Option<Millis>],
    alone: &'a [Option<Plan>],
    options: &'a Options,
    started: WallInstant,
}

/// What a search did.
struct Done {
    iterations: u64,
    improved: u64,
    timed_out: bool,
}

impl Search<'_> {
    /// Runs the steps of the budget on `working` ([`Search::one_step`]), keeping the best
    /// schedule seen.
    fn run(
        &self,
        working: &mut Working<'_>,
        rng: &mut ChaCha8Rng,
        mut progress: impl FnMut(u64),
    ) -> Done {
        let mut done = Done {
            iterations: 0,
            improved: 0,
            timed_out: false,
        };
        let mut waiting: Vec<usize> = unplanned(working, self.alone);
        let mut best = working.objective();
        let mut snapshot: Option<Vec<Option<Plan>>> = None;
        let budget = self.options.iterations;
        while done.iterations < budget {
            if self
                .options
                .time_budget
                .is_some_and(|budget| self.started.elapsed() >= budget)
            {
                done.timed_out = true;
                break;
            }
            let chance = self.options.anneal * (1.0 - done.iterations as f64 / budget as f64);
            let keep_worse = chance > 0.0 && rng.random_bool(chance.min(1.0));
            if keep_worse && working.objective() == best && snapshot.is_none() {
                snapshot = Some(working.plans().to_vec());
            }
            done.iterations += 1;
            let Some(outcome) = self.one_step(working, &waiting, keep_worse, rng) else {
                break;
            };
            match outcome {
                Step::Better => {
                    done.improved += 1;
                    waiting = unplanned(working, self.alone);
                }
                Step::Same | Step::Worse => waiting = unplanned(working, self.alone),
                Step::Undone => {}
            }
            if done.iterations.is_multiple_of(FILL_EVERY) && fill(working, &waiting) > 0 {
                waiting = unplanned(working, self.alone);
            }
            if working.objective() > best {
                best = working.objective();
                snapshot = None;
            }
            progress(done.iterations);
        }
        if let Some(plans) = snapshot.filter(|_| working.objective() < best) {
            working.restore(plans);
        }
        done
    }

    /// One step on `working`: a waiting request (one that can fly alone but holds no plan)
    /// and the flights in its way, or, once none waits, a delayed flight and the flights in
    /// its way. `None` when no request waits and none is delayed: nothing is left to do.
    fn one_step(
        &self,
        working: &mut Working<'_>,
        waiting: &[usize],
        keep_worse: bool,
        rng: &mut ChaCha8Rng,
    ) -> Option<Step> {
        let k = size(self.options.neighbourhood, rng);
        if waiting.is_empty() {
            let target = delayed(working, self.requests, self.free_flow, rng)?;
            let path = working
                .plan(target)
                .expect("a delayed request is planned")
                .clone();
            let mut out = pick(self.in_the_way(working, target, &path), k - 1, rng);
            out.push(target);
            let extras = self.extras(working, &out, k);
            return Some(step(working, target, &out, &extras, keep_worse, rng));
        }
        let target = self.choose(waiting, rng);
        let path = self.alone[target]
            .as_ref()
            .expect("a waiting request can fly alone");
        let out = pick(self.in_the_way(working, target, path), k, rng);
        let extras = self.extras(working, &out, k);
        Some(step(working, target, &out, &extras, keep_worse, rng))
    }

    /// A waiting request: half the time any, else the shorter trip of two drawn (short trips
    /// hold the corridors least, so they are the cheapest to fit).
    fn choose(&self, waiting: &[usize], rng: &mut ChaCha8Rng) -> usize {
        let a = waiting[rng.random_range(0..waiting.len())];
        if rng.random_range(0..2) == 0 {
            return a;
        }
        let b = waiting[rng.random_range(0..waiting.len())];
        if self.free_flow[b] < self.free_flow[a] {
            b
        } else {
            a
        }
    }

    /// Up to `most` waiting requests that depart while the flights `out` fly (from the
    /// earliest take-off less the longest trip to the latest landing), shortest trip first:
    /// they may fit where those flights were.
    fn extras(&self, working: &Working<'_>, out: &[usize], most: usize) -> Vec<usize> {
        let plans = out.iter().filter_map(|&i| working.plan(i));
        let (mut from, mut to) = (None::<Instant>, None::<Instant>);
        for p in plans {
            from = Some(from.map_or(p.takeoff(), |f| f.min(p.takeoff())));
            to = Some(to.map_or(p.landing(), |t| t.max(p.landing())));
        }
        let (Some(from), Some(to)) = (from, to) else {
            return Vec::new();
        };
        let from = from - working.params().max_flight;
        let by = &self.by_departure;
        let start = by.partition_point(|&i| self.requests[i].departure < from);
        let mut found: Vec<usize> = by[start..]
            .iter()
            .take_while(|&&i| self.requests[i].departure <= to)
            .filter(|&&i| self.alone[i].is_some() && working.plan(i).is_none())
            .take(EXTRAS_SCANNED)
            .copied()
            .collect();
        found.sort_by_key(|&i| (self.free_flow[i], i));
        found.truncate(most);
        found
    }

    /// The flights in the way of `target` flying `path`, within the time it could still be
    /// at each node (its ground delay and its battery's slack).
    fn in_the_way(&self, working: &Working<'_>, target: usize, path: &Plan) -> Vec<usize> {
        let params = working.params();
        let slack = slack(params.max_flight, self.free_flow[target]) + params.max_ground_delay;
        in_the_way(working, target, path, slack, params.node_separation)
    }
}

/// The most waiting requests looked at for a step's extras.
const EXTRAS_SCANNED: usize = 64;

/// Steps between two tries of every waiting request ([`fill`]).
const FILL_EVERY: u64 = 1_000;

/// Tries to plan each of `waiting` (in order) as the schedule stands: steps move flights, and
/// a request that did not fit before may fit now. Returns how many were planned.
fn fill(working: &mut Working<'_>, waiting: &[usize]) -> usize {
    waiting.iter().filter(|&&i| working.try_plan(i)).count()
}

/// Each request's answer in `working`: its plan, or the reason its last search gave.
fn answers(working: &Working<'_>, free_flow: &[Option<Millis>]) -> Vec<Outcome> {
    (0..free_flow.len())
        .map(|i| {
            let (labels, reason) = working.last_search(i);
            Outcome {
                result: working
                    .plan(i)
                    .cloned()
                    .ok_or(reason.unwrap_or(RejectReason::NoFeasiblePlan)),
                free_flow: free_flow[i],
                expanded: labels,
            }
        })
        .collect()
}

/// Each request's plan on `base` (its zones and flights, none of the batch), if it can fly
/// at all, and its free-flow time as the planner gives it (with battery swaps, the swaps'
/// time included).
fn plans_alone(
    planner: &Planner<'_>,
    base: &Schedule,
    requests: &[Request],
) -> (Vec<Option<Plan>>, Vec<Option<Millis>>) {
    let mut scratch = Scratch::new();
    requests
        .iter()
        .map(|r| {
            let out = planner.plan(base, r, &mut scratch);
            (out.result.ok(), out.free_flow)
        })
        .unzip()
}

/// The requests that could fly alone but hold no plan, in index order.
fn unplanned(working: &Working<'_>, alone: &[Option<Plan>]) -> Vec<usize> {
    (0..alone.len())
        .filter(|&i| alone[i].is_some() && working.plan(i).is_none())
        .collect()
}

/// A planned request with some delay, drawn at random; `None` if none is delayed.
fn delayed(
    working: &Working<'_>,
    requests: &[Request],
    free_flow: &[Option<Millis>],
    rng: &mut ChaCha8Rng,
) -> Option<usize> {
    let late: Vec<usize> = (0..requests.len())
        .filter(|&i| {
            working.plan(i).is_some_and(|p| {
                free_flow[i].is_some_and(|f| Objective::delay_of(&requests[i], p, f) > Millis::ZERO)
            })
        })
        .collect();
    (!late.is_empty()).then(|| late[rng.random_range(0..late.len())])
}

/// How much later than its free-flow time a flight may still land: the battery's slack.
fn slack(max_flight: Millis, free_flow: Option<Millis>) -> Millis {
    free_flow.map_or(Millis::ZERO, |f| (max_flight - f).max(Millis::ZERO))
}
