//! Exact safe-interval A* (SIPP) with hovering, a battery limit, ground delay and battery
//! swaps at stations (multi-leg trips, SPEC §12).
//!
//! # States and labels
//!
//! A *state* is a node together with one of its safe intervals `[lo, hi]` (a maximal run of
//! instants at which the node is free, from [`Schedule::node_slot`]). A drone in a state may
//! hover anywhere inside the interval, so arriving earlier is never worse — *for the same
//! take-off time*. With a battery limit and ground delay, a later take-off can matter more
//! than an earlier arrival, so a state keeps every label that is not dominated.
//!
//! A *label* is a family of equivalent partial plans `{(a + x, t₀ + x) : 0 ≤ x ≤ σ}`:
//! arrival `a + x` with take-off `t₀ + x`. Sliding `x` means taking off later by `x` and
//! flying the same timing shifted, which ground delay makes possible near the origin. A point
//! label has `σ = 0`. Label `S` dominates label `N` in the same state when `N` arrives no
//! earlier, has been airborne no shorter, and cannot take off later:
//! `a_N ≥ a_S`, `a_N − t₀_N ≥ a_S − t₀_S` and `t₀_N + σ_N ≤ t₀_S + σ_S`. With `G_max = 0`
//! every label is a point with the requested take-off, and this is the classic SIPP rule
//! "keep the earliest arrival per state".
//!
//! # Successors
//!
//! From a label at node `u` (interval `[lo_u, hi_u]`) along edge `e` to `v` (traversal `w`),
//! the drone enters `e` at some `s` with `a ≤ s ≤ hi_u` (it hovers at `u` until then) at
//! which entry is allowed ([`Schedule::edge_free_run`]), arriving at `s + w` inside a safe
//! interval `J` of `v`. For departure `s`, the best member is the one that arrives at `u`
//! last, no later than `s`: take-off `t₀ + min(σ, s − a)`. So for each run of allowed entries
//! that lands in `J`, the successors are one slope-1 label (no hovering, later take-off) while
//! `s < a + σ`, and one point label for the first allowed `s ≥ a + σ`; later entries landing
//! in the same `J` are dominated. Every label is pruned by the battery: time airborne so far
//! plus the free-flow time still to fly must not exceed `T_max`.
//!
//! # Multi-leg trips
//!
//! With battery swaps a label also carries the first take-off of the trip, `f₀ + min(x, ρ)`
//! for member `x` (in the first leg `ρ = σ` and the first take-off is the leg's take-off), and
//! the legs begun. At a station other than the destination a drone may land: a *ground label*
//! free to take off from `a + x + S` with first take-off `f₀ + x` (`x ≤ ρ`; later landings
//! add nothing). Waiting on the ground is unlimited, so a take-off from the ground is a label
//! whose slack runs to the end of the station's safe interval; the ground label then moves on
//! to the next safe interval. The first leg may not land at the trip's origin (a leg joins two
//! different stations; landing back would only lift the ground-delay bound). The dominance
//! rule gains two conditions: no more legs, and a first take-off no earlier for every member
//! (`label.rs`).
//!
//! A label with a long slack (a take-off from the ground, or a wide ground-delay window) would
//! generate a successor for every free run of every corridor up to the end of its interval,
//! most of them never needed. Its members beyond half a battery are queued apart as a
//! *continuation* that expands only when its turn comes; it shares the state's dominance with
//! the label it came from.
//!
//! # Order and optimality
//!
//! Labels are expanded in order of `(a + h(v, a − t₀), −f₀, legs)` where `h` is the exact
//! remaining time on the empty graph: the free-flow time to the destination, or with swaps
//! the time of the best chain of legs given what the current leg has flown
//! ([`crate::heuristic::swaps`]). Both are exact costs of a relaxation, hence consistent: the
//! key never decreases along a successor, and where its first part stays equal the first
//! take-off does not move (sliding a member later costs as much in arrival as it gains in
//! take-off). So the first label popped at the destination lands earliest, among the earliest
//! landings it has the latest first take-off, and among those the fewest legs — exactly the
//! SPEC §6 (and §12) objective.

mod expand;
pub(crate) mod label;

use std::cmp::Reverse;

use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId, Plan, Stay};

use crate::heuristic::swaps::SwapTable;
use crate::schedule::{NodeSlot, Schedule};
use crate::time::Unbounded;
use label::{GROUND, Key, Label, LabelId, Labels, NO_EDGE};

pub use label::Scratch;

/// The remaining time still to fly, the search's heuristic.
#[derive(Clone, Copy)]
pub(crate) enum Remaining<'a> {
    /// Single legs: the free-flow time to the goal per node (`Millis::INF` if none).
    Single(&'a [Millis]),
    /// With battery swaps: the multi-leg tables of the destination.
    Swaps(&'a SwapTable),
}

impl Remaining<'_> {
    /// The most the current leg may have flown on reaching `v` and still finish.
    #[inline]
    fn max_used(self, v: NodeId, t_max: Millis) -> Millis {
        match self {
            Remaining::Single(h) => match h[v.index()] {
                Millis::INF => Millis::NEG_INF,
                h => t_max - h,
            },
            Remaining::Swaps(t) => t.max_used(v),
        }
    }

    /// The remaining time from `v` after `used` ms of the leg (`used ≤ max_used(v)`).
    #[inline]
    fn at(self, v: NodeId, used: Millis) -> Millis {
        match self {
            Remaining::Single(h) => h[v.index()],
            Remaining::Swaps(t) => t.remaining(v, used),
        }
    }

    /// The remaining time from the ground at station `v` (swaps only).
    #[inline]
    fn on_ground(self, v: NodeId) -> Millis {
        match self {
            Remaining::Single(_) => Millis::INF,
            Remaining::Swaps(t) => t.trip_from_ground(v),
        }
    }
}

/// Battery swaps as the search applies them (SPEC §12).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Swaps {
    /// Minimum time on the ground between legs.
    pub time: Millis,
    /// Most legs a trip may have.
    pub max_legs: u32,
    /// A leg may not land where it took off: the station the search's first leg takes off
    /// from (the trip's origin for a new trip), which the `no_return_legs`-th leg may not land
    /// at. Later legs never gain by landing back (waiting on the ground is better), so only
    /// that one leg needs the rule.
    pub no_return: NodeId,
    /// The leg the rule binds.
    pub no_return_legs: u32,
}

/// What a search needs besides the schedule.
#[derive(Clone, Copy)]
pub(crate) struct Problem<'a> {
    pub airspace: &'a Airspace,
    pub params: &'a FlightParams,
    /// The heuristic (it must match `swaps`: `Swaps` tables exactly when swaps are on).
    pub remaining: Remaining<'a>,
    /// Battery swaps, if the drone may land between legs.
    pub swaps: Option<Swaps>,
    /// The latest landing allowed (`Instant::INF`: none).
    pub deadline: Instant,
}

impl Problem<'_> {
    /// Members of a label beyond this slack are expanded lazily, as a continuation: half a
    /// battery, so that single legs with a ground delay of up to `T_max / 2` are never split.
    fn split(&self) -> Millis {
        Millis(self.params.max_flight.0 / 2).max(Millis(1))
    }
}

/// Where a search starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Start {
    /// On the ground at `origin`, taking off at any instant of `[earliest, latest]`.
    Ground {
        origin: NodeId,
        earliest: Instant,
        latest: Instant,
    },
    /// In the air: arriving at `node` at instant `at` (fixed), the current leg (the
    /// `legs`-th) having taken off at `takeoff` and the trip at `first` (SPEC §11: an airborne
    /// flight replanned from the first node it reaches).
    Airborne {
        node: NodeId,
        at: Instant,
        takeoff: Instant,
        first: Instant,
        legs: u32,
    },
    /// On the ground at station `node` between legs, free to take off from `at`, after
    /// `legs` legs of a trip that first took off at `first`.
    Landed {
        node: NodeId,
        at: Instant,
        first: Instant,
        legs: u32,
    },
}

/// Where a search may end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Goal {
    /// Landing at this station.
    Node(NodeId),
    /// Landing at any station: the earliest landing, ties to the lowest node index
    /// (SPEC §11 diversion).
    AnyStation,
}

/// Plans from `start` to `goal` against `schedule`: the earliest landing, then the latest
/// first take-off, then the fewest legs; `None` if no plan exists. `scratch.expanded` counts
/// the labels expanded. (Whether the goal is reachable or in range at all is the caller's
/// question: a search only finds out that nothing fits.)
pub(crate) fn search(
    p: Problem<'_>,
    schedule: &Schedule,
    start: Start,
    goal: Goal,
    scratch: &mut Scratch,
) -> Option<Plan> {
    let no_return_legs = p.swaps.map_or(0, |s| s.no_return_legs);
    scratch.reset(p.airspace.node_count(), p.deadline, no_return_legs);
    seed(p, schedule, start, scratch);
    let is_goal = |l: &Label| {
        !l.ground
            && match goal {
                Goal::Node(d) => l.node == d,
                Goal::AnyStation => p.airspace.is_station(l.node),
            }
    };
    let split = p.split();
    let mut found: Option<LabelId> = None;
    while let Some(Reverse((key, idx))) = scratch.heap.pop() {
        if scratch.is_dead(idx) {
            continue;
        }
        if key.landing > p.deadline {
            // Keys never decrease: nothing left can land in time.
            break;
        }
        let label = scratch.labels[idx];
        if let Some(best) = found {
            // Any station: other labels with the same key may land as early at a station
            // of lower index; past that key nothing can.
            if key.landing > scratch.labels[best].arrive {
                break;
            }
            if is_goal(&label) && label.arrive == key.landing {
                if label.node < scratch.labels[best].node {
                    found = Some(idx);
                }
                continue;
            }
        } else if is_goal(&label) {
            found = Some(idx);
            if matches!(goal, Goal::Node(_)) {
                break;
            }
            continue;
        }
        scratch.expanded += 1;
        if label.ground {
            expand::take_off(p, schedule, scratch, idx, &label);
            continue;
        }
        // Members from the instant the schedule stops changing on are only later copies of the
        // member there: no continuation past it (it would never end on an open interval).
        let cap = if label.slack > split && label.arrive + split <= schedule.quiet_from() {
            let later = label.later_members(split);
            let key = key_of(p, &later);
            scratch.push_continuation(idx, later, key);
            label.arrive + split - Millis(1)
        } else {
            Instant::INF
        };
        expand::fly(p, schedule, scratch, idx, &label, cap);
        // A leg that has not left the station it took off from gains nothing by landing
        // there again: the ground label it took off from stands for that landing already.
        let just_took_off = !label.parent.is_none() && scratch.labels[label.parent].ground;
        if !just_took_off {
            expand::land(p, scratch, idx, &label);
        }
    }
    found.map(|idx| reconstruct(schedule, &scratch.labels, idx))
}

/// The priority of an airborne label (see the module docs).
#[inline]
fn key_of(p: Problem<'_>, l: &Label) -> Key {
    let h = p.remaining.at(l.node, l.arrive - l.takeoff);
    Key {
        landing: l.arrive + h,
        first: Reverse(l.first),
        legs: l.legs,
    }
}

/// The priority of a ground label from which the trip takes `g` at the least.
#[inline]
fn ground_key(l: &Label, g: Millis) -> Key {
    Key {
        landing: l.arrive + g,
        first: Reverse(l.first),
        legs: l.legs,
    }
}

/// Queues the labels a search starts from.
fn seed(p: Problem<'_>, schedule: &Schedule, start: Start, scratch: &mut Scratch) {
    let t_max = p.params.max_flight;
    match start {
        // Take-off: any instant of [earliest, latest] at which the origin is free. Each safe
        // interval of the origin met gives one label whose members are the take-off instants.
        Start::Ground {
            origin,
            earliest,
            latest,
        } => {
            if p.remaining.max_used(origin, t_max) < Millis::ZERO {
                return;
            }
            let mut t = earliest;
            while t <= latest {
                match schedule.node_slot(origin, t) {
                    NodeSlot::Blocked { next_free } => t = next_free,
                    NodeSlot::Safe { lo, hi, next } => {
                        let slack = hi.min(latest) - t;
                        let root = root(origin, (lo, hi), (t, t, slack), (t, slack), 1);
                        scratch.push(root, key_of(p, &root));
                        t = next;
                    }
                }
            }
        }
        // In the air the arrival is fixed: one point label, if the node is free then.
        Start::Airborne {
            node,
            at,
            takeoff,
            first,
            legs,
        } => {
            if at - takeoff > p.remaining.max_used(node, t_max) {
                return;
            }
            if let NodeSlot::Safe { lo, hi, .. } = schedule.node_slot(node, at) {
                let root = root(
                    node,
                    (lo, hi),
                    (at, takeoff, Millis::ZERO),
                    (first, Millis::ZERO),
                    legs,
                );
                scratch.push(root, key_of(p, &root));
            }
        }
        Start::Landed {
            node,
            at,
            first,
            legs,
        } => {
            let g = p.remaining.on_ground(node);
            let more = p.swaps.is_some_and(|s| legs < s.max_legs);
            if g != Millis::INF && more {
                let label = Label {
                    ground: true,
                    lo: GROUND,
                    hi: Instant::INF,
                    ..root(
                        node,
                        (GROUND, Instant::INF),
                        (at, first, Millis::ZERO),
                        (first, Millis::ZERO),
                        legs,
                    )
                };
                scratch.push(label, ground_key(&label, g));
            }
        }
    }
}

/// A label with no parent: `interval` `(lo, hi)`, `timing` `(arrive, takeoff, slack)`,
/// `first` `(first, rho)`.
fn root(
    node: NodeId,
    interval: (Instant, Instant),
    timing: (Instant, Instant, Millis),
    first: (Instant, Millis),
    legs: u32,
) -> Label {
    Label {
        node,
        legs,
        ground: false,
        dead: false,
        lo: interval.0,
        hi: interval.1,
        arrive: timing.0,
        takeoff: timing.1,
        slack: timing.2,
        first: first.0,
        rho: first.1.min(timing.2),
        parent: LabelId::NONE,
        via: NO_EDGE,
        next_in_state: LabelId::NONE,
        alias: LabelId::NONE,
    }
}

/// Builds the plan of the earliest member of goal label `goal`. Within a leg every ancestor
/// contributes the member with the same leg take-off; across a swap, the landing member with
/// the same first take-off (the earliest such landing).
fn reconstruct(schedule: &Schedule, labels: &Labels, goal: LabelId) -> Plan {
    let first = labels[goal].first;
    let mut leg_takeoff = labels[goal].takeoff;
    let mut depart = labels[goal].arrive;
    let mut path = Vec::new();
    let mut idx = goal;
    loop {
        let l = &labels[idx];
        debug_assert!(!l.ground);
        let x = leg_takeoff - l.takeoff;
        debug_assert!((Millis::ZERO..=l.slack).contains(&x), "member {x} of {l:?}");
        let arrive = l.arrive + x;
        path.push(Stay {
            node: l.node,
            arrive,
            depart,
        });
        if l.parent.is_none() {
            break;
        }
        let parent = &labels[l.parent];
        if !parent.ground {
            depart = arrive - schedule.traversal(l.via);
            idx = l.parent;
            continue;
        }
        // `l` took off from the ground: back to the landing before it (none when the search
        // started on the ground).
        if parent.parent.is_none() {
            break;
        }
        let landed = &labels[parent.parent];
        let x = first - landed.first;
        debug_assert!(
            (Millis::ZERO..=landed.rho).contains(&x),
            "member {x} of {landed:?}"
        );
        leg_takeoff = landed.takeoff + x;
        depart = landed.arrive + x;
        idx = parent.parent;
    }
    path.reverse();
    Plan { path }
}
