//! Exact safe-interval A* (SIPP) with hovering, a battery limit and ground delay.
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
//! # Order and optimality
//!
//! Labels are expanded in order of `(a + h(v), −t₀)` where `h` is the exact free-flow time to
//! the destination (consistent). The key never decreases along a successor, so the first label
//! popped at the destination lands earliest, and among the earliest landings it has the
//! latest take-off — exactly the SPEC §6 objective.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use muse_model::{Airspace, EdgeId, FlightParams, Instant, NodeId, Plan, RejectReason, Stay};

use crate::heuristic::UNREACHABLE;
use crate::schedule::{NodeSlot, Schedule};

const NONE: u32 = u32::MAX;

/// One label (see the module docs).
#[derive(Clone, Copy, Debug)]
struct Label {
    node: u32,
    /// The safe interval of the state.
    lo: i64,
    hi: i64,
    /// Earliest member: arrival and take-off; `slack` = σ.
    arrive: i64,
    takeoff: i64,
    slack: i64,
    /// Parent label and the edge flown from it (`NONE` at the origin).
    parent: u32,
    via: u32,
    /// Next label of the same state (linked list), or `NONE`.
    next_in_state: u32,
    dead: bool,
}

/// Reusable per-thread search memory: after the first few requests, planning allocates
/// nothing.
#[derive(Debug, Default)]
pub struct Scratch {
    labels: Vec<Label>,
    heap: BinaryHeap<Reverse<(i64, i64, u32)>>,
    /// Per node: the states met in this search, as `(lo, first label)`.
    states: Vec<Vec<(i64, u32)>>,
    touched: Vec<u32>,
    /// Labels expanded by the last search.
    pub expanded: u64,
}

impl Scratch {
    /// Empty scratch space; it grows to fit the airspace on first use.
    pub fn new() -> Self {
        Scratch::default()
    }

    fn reset(&mut self, node_count: usize) {
        self.labels.clear();
        self.heap.clear();
        if self.states.len() < node_count {
            self.states.resize_with(node_count, Vec::new);
        }
        for &n in &self.touched {
            self.states[n as usize].clear();
        }
        self.touched.clear();
        self.expanded = 0;
    }

    /// Adds a label unless an existing label of its state dominates it; marks the labels it
    /// dominates dead; queues it with key `(arrive + h, −takeoff)`.
    fn push(&mut self, label: Label, h: i64) {
        let node = label.node as usize;
        let slot = self.states[node].iter().position(|&(lo, _)| lo == label.lo);
        let idx = self.labels.len() as u32;
        let mut label = label;
        if let Some(k) = slot {
            let head = self.states[node][k].1;
            let mut i = head;
            while i != NONE {
                let s = &self.labels[i as usize];
                if !s.dead && dominates(s, &label) {
                    return;
                }
                i = s.next_in_state;
            }
            let mut i = head;
            while i != NONE {
                let s = &mut self.labels[i as usize];
                if !s.dead && dominates(&label, s) {
                    s.dead = true;
                }
                i = s.next_in_state;
            }
            label.next_in_state = head;
            self.states[node][k].1 = idx;
        } else {
            if self.states[node].is_empty() {
                self.touched.push(label.node);
            }
            self.states[node].push((label.lo, idx));
        }
        self.labels.push(label);
        self.heap
            .push(Reverse((label.arrive + h, -label.takeoff, idx)));
    }
}

/// Whether `s` dominates `n` (same state assumed).
#[inline]
fn dominates(s: &Label, n: &Label) -> bool {
    n.arrive >= s.arrive
        && n.arrive - n.takeoff >= s.arrive - s.takeoff
        && n.takeoff + n.slack <= s.takeoff + s.slack
}

/// What a search needs besides the schedule.
#[derive(Clone, Copy)]
pub(crate) struct Problem<'a> {
    pub airspace: &'a Airspace,
    pub params: &'a FlightParams,
    /// Free-flow time to the goal per node (`UNREACHABLE` if none).
    pub h: &'a [i64],
}

/// Where a search starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Start {
    /// On the ground at `origin`, taking off at any instant of `[earliest, latest]`.
    Ground {
        origin: NodeId,
        earliest: i64,
        latest: i64,
    },
    /// In the air: arriving at `node` at instant `at` (fixed), having taken off at `takeoff`
    /// (SPEC §11: an airborne flight replanned from the first node it reaches).
    Airborne { node: NodeId, at: i64, takeoff: i64 },
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
/// take-off, or the reason no plan exists. `scratch.expanded` counts the labels expanded.
///
/// Reasons: `Unreachable` when no path leads from the start to the goal; `OutOfRange` when
/// even the free-flow path exceeds the battery left (on the ground: `T_max`); otherwise
/// `NoFeasiblePlan`.
pub(crate) fn search(
    p: Problem<'_>,
    schedule: &Schedule,
    start: Start,
    goal: Goal,
    scratch: &mut Scratch,
) -> Result<Plan, RejectReason> {
    let t_max = p.params.max_flight.0;
    scratch.reset(p.airspace.node_count());
    let (first, spent) = match start {
        Start::Ground { origin, .. } => (origin, 0),
        Start::Airborne { node, at, takeoff } => (node, at - takeoff),
    };
    let h_first = p.h[first.index()];
    if h_first == UNREACHABLE {
        return Err(RejectReason::Unreachable);
    }
    if spent + h_first > t_max {
        return Err(RejectReason::OutOfRange);
    }

    match start {
        // Take-off: any instant of [earliest, latest] at which the origin is free. Each safe
        // interval of the origin met gives one label whose members are the take-off instants.
        Start::Ground {
            origin,
            earliest,
            latest,
        } => {
            let mut t = earliest;
            while t <= latest {
                match schedule.node_slot(origin, t) {
                    NodeSlot::Blocked { next_free } => t = next_free,
                    NodeSlot::Safe { lo, hi, next } => {
                        scratch.push(root(origin, lo, hi, t, t, hi.min(latest) - t), h_first);
                        t = next;
                    }
                }
            }
        }
        // In the air the arrival is fixed: one point label, if the node is free then.
        Start::Airborne { node, at, takeoff } => {
            if let NodeSlot::Safe { lo, hi, .. } = schedule.node_slot(node, at) {
                scratch.push(root(node, lo, hi, at, takeoff, 0), h_first);
            }
        }
    }

    let is_goal = |n: u32| match goal {
        Goal::Node(d) => n == d.0,
        Goal::AnyStation => p.airspace.is_station(NodeId(n)),
    };
    let mut found: Option<u32> = None;
    while let Some(Reverse((key, _, idx))) = scratch.heap.pop() {
        let label = scratch.labels[idx as usize];
        if label.dead {
            continue;
        }
        if let Some(best) = found {
            // Any station: other labels with the same key may land as early at a station
            // of lower index; past that key nothing can.
            if key > scratch.labels[best as usize].arrive {
                break;
            }
            if is_goal(label.node) && label.arrive == key {
                if label.node < scratch.labels[best as usize].node {
                    found = Some(idx);
                }
                continue;
            }
        } else if is_goal(label.node) {
            found = Some(idx);
            if matches!(goal, Goal::Node(_)) {
                break;
            }
            continue;
        }
        scratch.expanded += 1;
        expand(p, schedule, scratch, idx, &label);
    }
    match found {
        Some(idx) => Ok(reconstruct(schedule, &scratch.labels, idx)),
        None => Err(RejectReason::NoFeasiblePlan),
    }
}

/// A label with no parent: a take-off (or the start of an airborne replan).
fn root(node: NodeId, lo: i64, hi: i64, arrive: i64, takeoff: i64, slack: i64) -> Label {
    Label {
        node: node.0,
        lo,
        hi,
        arrive,
        takeoff,
        slack,
        parent: NONE,
        via: NONE,
        next_in_state: NONE,
        dead: false,
    }
}

/// Generates the successors of `label` (see the module docs).
// The single-letter names follow the notation of the module docs (u, v, a, w, s).
#[allow(clippy::many_single_char_names)]
fn expand(
    problem: Problem<'_>,
    schedule: &Schedule,
    scratch: &mut Scratch,
    idx: u32,
    label: &Label,
) {
    let t_max = problem.params.max_flight.0;
    let u = NodeId(label.node);
    let (a, t0, sigma) = (label.arrive, label.takeoff, label.slack);
    let airborne = a - t0;
    for adj in problem.airspace.neighbours(u) {
        let v = adj.node;
        let hv = problem.h[v.index()];
        if hv == UNREACHABLE {
            continue;
        }
        let w = schedule.traversal_ms(adj.edge);
        if airborne + w + hv > t_max {
            continue;
        }
        let dir = usize::from(!adj.forward);
        let s_max = label.hi.min(t0 + sigma + t_max - w - hv);
        let mut s = a;
        while s <= s_max {
            let (first, run_end) = schedule.edge_free_run(adj.edge, dir, s);
            if first > s_max {
                break;
            }
            match schedule.node_slot(v, first + w) {
                NodeSlot::Blocked { next_free } => s = next_free - w,
                NodeSlot::Safe { lo, hi, next } => {
                    let last = run_end.min(hi - w).min(s_max);
                    let (takeoff, slack) = if first - a < sigma {
                        (t0 + first - a, last.min(a + sigma) - first)
                    } else {
                        (t0 + sigma, 0)
                    };
                    let child = Label {
                        node: v.0,
                        lo,
                        hi,
                        arrive: first + w,
                        takeoff,
                        slack,
                        parent: idx,
                        via: adj.edge.0,
                        next_in_state: NONE,
                        dead: false,
                    };
                    scratch.push(child, hv);
                    // Later departures into this interval are dominated once the latest
                    // take-off is reached or the interval is used up: go on with the next one.
                    // (Progress: either `s` grows, or the next interval starts at `hi` and
                    // `node_slot` answers with it, a different state.)
                    s = if first + slack >= a + sigma || last == hi - w {
                        next - w
                    } else {
                        last + 1
                    };
                }
            }
        }
    }
}

/// Builds the plan of the earliest member of goal label `goal`: every ancestor contributes
/// the member with the same take-off.
fn reconstruct(schedule: &Schedule, labels: &[Label], goal: u32) -> Plan {
    let takeoff = labels[goal as usize].takeoff;
    let mut path = Vec::new();
    let mut idx = goal;
    let mut depart = labels[goal as usize].arrive;
    loop {
        let l = &labels[idx as usize];
        let arrive = l.arrive + (takeoff - l.takeoff);
        debug_assert!((0..=l.slack).contains(&(takeoff - l.takeoff)));
        path.push(Stay {
            node: NodeId(l.node),
            arrive: Instant(arrive),
            depart: Instant(depart),
        });
        if l.parent == NONE {
            break;
        }
        depart = arrive - schedule.traversal_ms(EdgeId(l.via));
        idx = l.parent;
    }
    path.reverse();
    Plan { path }
}
