//! The search loop: seed the queue from the start, then pop labels in key order until the goal
//! is settled, expanding the others; finally rebuild the plan of the goal label.

use muse_model::{Instant, Millis, Plan, Stay};

use super::label::{Interval, Key, Label, LabelId};
use super::problem::{Goal, Problem, Start};
use super::scratch::{Labels, Scratch};
use crate::schedule::{NodeSlot, Schedule};
use crate::time::Unbounded;

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
    let mut search = Search {
        p,
        schedule,
        goal,
        split: p.split(),
        scratch,
        found: None,
    };
    search.seed(start);
    search.run()
}

/// One search under way: what it is asked, its memory, and the best goal label so far.
pub(super) struct Search<'s, 'p> {
    pub(super) p: Problem<'p>,
    pub(super) schedule: &'s Schedule,
    goal: Goal,
    /// Members of a label beyond this slack are expanded lazily ([`Problem::split`]).
    split: Millis,
    pub(super) scratch: &'s mut Scratch,
    /// The goal label to land with, once one is popped.
    found: Option<LabelId>,
}

/// What a label popped from the queue calls for.
enum Step {
    /// Expanding: generating its successors.
    Expand,
    /// Nothing more (it is a goal label, kept or not).
    Skip,
    /// Ending the search: nothing left in the queue can do better.
    Stop,
}

impl Search<'_, '_> {
    /// Pops labels in key order, settling or expanding each, until the search ends; then
    /// rebuilds the plan of the goal label found, if any.
    fn run(mut self) -> Option<Plan> {
        while let Some((key, idx)) = self.scratch.pop() {
            let label = self.scratch.labels[idx];
            match self.settle(key, idx, &label) {
                Step::Expand => self.expand(idx, &label),
                Step::Skip => {}
                Step::Stop => break,
            }
        }
        let found = self.found?;
        Some(reconstruct(self.schedule, &self.scratch.labels, found))
    }

    /// Queues the labels the search starts from.
    fn seed(&mut self, start: Start) {
        let t_max = self.p.params.max_flight;
        match start {
            // Take-off: any instant of [earliest, latest] at which the origin is free. Each
            // safe interval of the origin met gives one label whose members are the take-off
            // instants.
            Start::Ground {
                origin,
                earliest,
                latest,
            } => {
                if self.p.remaining.max_used(origin, t_max) < Millis::ZERO {
                    return;
                }
                let mut t = earliest;
                while t <= latest {
                    match self.schedule.node_slot(origin, t) {
                        NodeSlot::Blocked { next_free } => t = next_free,
                        NodeSlot::Safe { lo, hi, next } => {
                            let state = Interval { lo, hi };
                            let root = Label::take_offs(origin, state, t, hi.min(latest) - t);
                            self.push(root);
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
                if at - takeoff > self.p.remaining.max_used(node, t_max) {
                    return;
                }
                if let NodeSlot::Safe { lo, hi, .. } = self.schedule.node_slot(node, at) {
                    let state = Interval { lo, hi };
                    self.push(Label::in_flight(node, state, at, takeoff, first, legs));
                }
            }
            Start::Landed {
                node,
                at,
                first,
                legs,
            } => {
                let g = self.p.remaining.on_ground(node);
                let more = self.p.swaps.is_some_and(|s| legs < s.max_legs);
                if g != Millis::INF && more {
                    let label = Label::between_legs(node, at, first, legs);
                    self.scratch.push(label, Key::of(&label, g));
                }
            }
        }
    }

    /// Queues airborne label `label` with its key.
    #[inline]
    pub(super) fn push(&mut self, label: Label) {
        let key = self.p.key(&label);
        self.scratch.push(label, key);
    }

    /// What label `idx` (`label`, popped with `key`) calls for: the end of the search when no
    /// label left can land in time or better than the goal label found; remembering it when
    /// it is the first goal label (ending the search when the goal is one station), or a
    /// better one (any station: as early at a station of lower index); expanding it
    /// otherwise.
    fn settle(&mut self, key: Key, idx: LabelId, label: &Label) -> Step {
        if key.landing > self.p.deadline {
            // Keys never decrease: nothing left can land in time.
            return Step::Stop;
        }
        let Some(best) = self.found else {
            if !self.is_goal(label) {
                return Step::Expand;
            }
            self.found = Some(idx);
            return match self.goal {
                Goal::Node(_) => Step::Stop,
                Goal::AnyStation => Step::Skip,
            };
        };
        // Any station: other labels with the same key may land as early at a station of
        // lower index; past that key nothing can.
        let best = self.scratch.labels[best];
        if key.landing > best.arrive {
            return Step::Stop;
        }
        if self.is_goal(label) && label.arrive == key.landing {
            if label.node < best.node {
                self.found = Some(idx);
            }
            return Step::Skip;
        }
        Step::Expand
    }

    /// Whether `label` lands at the goal.
    #[inline]
    fn is_goal(&self, label: &Label) -> bool {
        !label.ground
            && match self.goal {
                Goal::Node(d) => label.node == d,
                Goal::AnyStation => self.p.airspace.is_station(label.node),
            }
    }

    /// Generates the successors of label `idx`: from the ground, the take-off; in the air,
    /// the flights on along every corridor (the members past the split queued apart as a
    /// continuation), and the landing for a battery swap.
    fn expand(&mut self, idx: LabelId, label: &Label) {
        self.scratch.expanded += 1;
        if label.ground {
            self.take_off(idx, label);
            return;
        }
        let cap = self.split_off_later_members(idx, label);
        self.fly(idx, label, cap);
        // A leg that has not left the station it took off from gains nothing by landing
        // there again: the ground label it took off from stands for that landing already.
        let parent = label.parent;
        let just_took_off = !parent.is_none() && self.scratch.labels[parent].ground;
        if !just_took_off {
            self.land(idx, label);
        }
    }

    /// Queues the members of airborne label `idx` beyond the split as a continuation, when
    /// it has any; returns the latest corridor entry the label itself is expanded to.
    fn split_off_later_members(&mut self, idx: LabelId, label: &Label) -> Instant {
        // Members from the instant the schedule stops changing on are only later copies of
        // the member there: no continuation past it (it would never end on an open interval).
        let split = self.split;
        if label.slack > split && label.arrive + split <= self.schedule.quiet_from() {
            let later = label.later_members(split);
            let key = self.p.key(&later);
            self.scratch.push_continuation(idx, later, key);
            label.arrive + split - Millis(1)
        } else {
            Instant::INF
        }
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
