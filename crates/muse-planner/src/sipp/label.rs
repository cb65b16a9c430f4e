//! Labels, their dominance, and the search's reusable memory.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::{Index, IndexMut};

use muse_model::{EdgeId, Instant, Millis, NodeId};

/// The index of a label in a search's [`Scratch`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct LabelId(u32);

impl LabelId {
    /// No label: the parent of a search's first labels and of a take-off's, the end of a
    /// state's list, the owner of a label that is not a continuation.
    pub const NONE: LabelId = LabelId(u32::MAX);

    /// Whether this is [`LabelId::NONE`].
    #[inline]
    pub fn is_none(self) -> bool {
        self == LabelId::NONE
    }
}

/// The edge of a label that was not flown to (a search's first labels, landings and
/// take-offs).
pub(super) const NO_EDGE: EdgeId = EdgeId(u32::MAX);

/// The `lo` of the ground state of a station (SPEC §12: on the ground between legs). Not a
/// time: the key of that state, below every safe interval's `lo` (which is at least
/// `Instant::NEG_INF`).
pub(super) const GROUND: Instant = Instant(i64::MIN);

/// One label (see the module docs of [`super`]): a family of partial plans with members
/// `x ∈ [0, slack]`: arrival `arrive + x`, current leg's take-off `takeoff + x`, first
/// take-off `first + min(x, rho)`, `legs` legs begun. A ground label (`ground`) is a drone on
/// the ground at a station between legs, free to take off from `arrive + x`; its `takeoff`
/// is `first` and its `slack` is `rho`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Label {
    pub node: NodeId,
    pub legs: u32,
    pub ground: bool,
    pub dead: bool,
    /// The safe interval of the state (`GROUND` for a ground label).
    pub lo: Instant,
    pub hi: Instant,
    pub arrive: Instant,
    pub takeoff: Instant,
    pub slack: Millis,
    pub first: Instant,
    pub rho: Millis,
    /// Parent label (`NONE` at the start of the search and after a take-off) and the edge
    /// flown from it (`NO_EDGE` when none was).
    pub parent: LabelId,
    pub via: EdgeId,
    /// Next label of the same state (linked list), or `NONE`.
    pub next_in_state: LabelId,
    /// For a *continuation* (the later members of a label, queued apart so that their
    /// successors are generated lazily): the label held in the state list whose death is
    /// theirs. `NONE` for a label in the state list.
    pub alias: LabelId,
}

impl Label {
    /// The members `x ≥ dx` of an airborne label, as a label of their own.
    pub fn later_members(&self, dx: Millis) -> Label {
        debug_assert!(!self.ground && dx > Millis::ZERO && dx <= self.slack);
        Label {
            arrive: self.arrive + dx,
            takeoff: self.takeoff + dx,
            slack: self.slack - dx,
            first: self.first + dx.min(self.rho),
            rho: (self.rho - dx).max(Millis::ZERO),
            ..*self
        }
    }

    /// A ground label's members from `dt` later on: free to take off from `arrive + dt`.
    pub fn on_ground_later(&self, dt: Millis) -> Label {
        debug_assert!(self.ground && dt > Millis::ZERO);
        let first = self.first + dt.min(self.rho);
        let rho = (self.rho - dt).max(Millis::ZERO);
        Label {
            arrive: self.arrive + dt,
            takeoff: first,
            slack: rho,
            first,
            rho,
            ..*self
        }
    }
}

/// A state met in a search: a node's safe interval (or its ground) and its labels, as a
/// list linked through [`Label::next_in_state`].
#[derive(Clone, Copy, Debug)]
struct State {
    lo: Instant,
    head: LabelId,
    tail: LabelId,
}

/// The priority of a label, smallest first (see the module docs of [`super`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Key {
    /// The earliest landing the label can lead to: its arrival plus the remaining time.
    pub landing: Instant,
    /// Then the latest first take-off.
    pub first: Reverse<Instant>,
    /// Then the fewest legs.
    pub legs: u32,
}

/// A search's labels, indexed by [`LabelId`].
#[derive(Debug, Default)]
pub(super) struct Labels(Vec<Label>);

impl Labels {
    /// The id the next label pushed will have.
    #[inline]
    fn next_id(&self) -> LabelId {
        LabelId(self.0.len() as u32)
    }
}

impl Index<LabelId> for Labels {
    type Output = Label;

    #[inline]
    fn index(&self, id: LabelId) -> &Label {
        &self.0[id.0 as usize]
    }
}

impl IndexMut<LabelId> for Labels {
    #[inline]
    fn index_mut(&mut self, id: LabelId) -> &mut Label {
        &mut self.0[id.0 as usize]
    }
}

/// Reusable per-thread search memory: after the first few requests, planning allocates
/// nothing.
#[derive(Debug, Default)]
pub struct Scratch {
    pub(super) labels: Labels,
    pub(super) heap: BinaryHeap<Reverse<(Key, LabelId)>>,
    /// Per node: the states met in this search, sorted by `lo`.
    states: Vec<Vec<State>>,
    touched: Vec<NodeId>,
    /// Labels whose key passes this are never queued (the search's deadline).
    pub(super) deadline: Instant,
    /// The leg that may not land where it took off ([`super::Swaps::no_return_legs`]).
    no_return_legs: u32,
    /// Labels expanded by the last search.
    pub(crate) expanded: u64,
}

impl Scratch {
    /// Empty scratch space; it grows to fit the airspace on first use.
    pub fn new() -> Self {
        Scratch::default()
    }

    pub(super) fn reset(&mut self, node_count: usize, deadline: Instant, no_return_legs: u32) {
        self.deadline = deadline;
        self.no_return_legs = no_return_legs;
        self.labels.0.clear();
        self.heap.clear();
        if self.states.len() < node_count {
            self.states.resize_with(node_count, Vec::new);
        }
        for &n in &self.touched {
            self.states[n.index()].clear();
        }
        self.touched.clear();
        self.expanded = 0;
    }

    /// Whether label `idx` (or, for a continuation, the label it belongs to) is dominated.
    pub(super) fn is_dead(&self, idx: LabelId) -> bool {
        let l = &self.labels[idx];
        l.dead || (!l.alias.is_none() && self.labels[l.alias].dead)
    }

    /// Adds a label unless an existing label of its state dominates it; marks the labels it
    /// dominates dead; queues it with `key`.
    ///
    /// A state's labels are listed oldest first: labels are pushed in roughly increasing key
    /// order, so an older label is the likelier to dominate a new one, and is met first.
    pub(super) fn push(&mut self, label: Label, key: Key) {
        if key.landing > self.deadline {
            return;
        }
        let node = label.node.index();
        let states = &mut self.states[node];
        // States are kept sorted by `lo`; new ones usually go last.
        let k = states.partition_point(|s| s.lo < label.lo);
        let idx = self.labels.next_id();
        if states.get(k).is_some_and(|s| s.lo == label.lo) {
            if self.dominated_in(node, k, &label) {
                return;
            }
            let tail = std::mem::replace(&mut self.states[node][k].tail, idx);
            if tail.is_none() {
                self.states[node][k].head = idx;
            } else {
                self.labels[tail].next_in_state = idx;
            }
        } else {
            if states.is_empty() {
                self.touched.push(label.node);
            }
            states.insert(
                k,
                State {
                    lo: label.lo,
                    head: idx,
                    tail: idx,
                },
            );
        }
        self.labels.0.push(Label {
            next_in_state: LabelId::NONE,
            ..label
        });
        self.heap.push(Reverse((key, idx)));
    }

    /// Whether a label of state `k` of `node` dominates `label`; marks dead those `label`
    /// dominates and unlinks every dead label met, so that lists stay short.
    fn dominated_in(&mut self, node: usize, k: usize, label: &Label) -> bool {
        let r = self.no_return_legs;
        let mut prev = LabelId::NONE;
        let mut i = self.states[node][k].head;
        let mut dominated = false;
        while !i.is_none() {
            let s = &mut self.labels[i];
            let next = s.next_in_state;
            if !s.dead && !dominated && dominates(s, label, r) {
                dominated = true;
            } else if !s.dead && !dominated && dominates(label, s, r) {
                s.dead = true;
            }
            if s.dead {
                // Unlink: a dead label never dominates again (its continuations check its
                // flag, not the list).
                if prev.is_none() {
                    self.states[node][k].head = next;
                } else {
                    self.labels[prev].next_in_state = next;
                }
            } else {
                prev = i;
            }
            i = next;
        }
        self.states[node][k].tail = prev;
        dominated
    }

    /// Queues the continuation `label` of label `of` (not in any state list: `of` stands for
    /// it in dominance).
    pub(super) fn push_continuation(&mut self, of: LabelId, label: Label, key: Key) {
        if key.landing > self.deadline {
            return;
        }
        let idx = self.labels.next_id();
        let owner = self.labels[of].alias;
        self.labels.0.push(Label {
            alias: if owner.is_none() { of } else { owner },
            next_in_state: LabelId::NONE,
            ..label
        });
        self.heap.push(Reverse((key, idx)));
    }
}

/// Whether `s` dominates `n` (same state assumed): every member of `n` is matched by a member
/// of `s` that is there no later, has flown its leg no longer, took off first no earlier and
/// has begun no more legs (hovering, or waiting on the ground, closes the gap in arrival).
/// `r` is the leg that may not land where it took off: an airborne label of that leg never
/// dominates one of a later leg, which may. A ground label is past that rule whatever its
/// count (the leg it counts has landed; the next is free to land anywhere).
///
/// For member `x` of `n` the best member of `s` is `y = min(σ_s, a_n − a_s + x)`; it exists
/// and is no worse in arrival and battery for every `x` exactly when the first three
/// conditions hold, and no worse in first take-off when [`first_no_earlier`] holds.
#[inline]
fn dominates(s: &Label, n: &Label, r: u32) -> bool {
    n.arrive >= s.arrive
        && n.arrive - n.takeoff >= s.arrive - s.takeoff
        && n.takeoff + n.slack <= s.takeoff + s.slack
        && s.legs <= n.legs
        && (s.ground || s.legs != r || n.legs == r)
        && first_no_earlier(s, n)
}

/// `s.first + min(ρ_s, a_n − a_s + x) ≥ n.first + min(x, ρ_n)` for every `x ∈ [0, σ_n]`:
/// both sides are concave and piecewise linear in `x`, so the difference is smallest at an end
/// of the range or at a kink.
#[inline]
fn first_no_earlier(s: &Label, n: &Label) -> bool {
    let gap = n.arrive - s.arrive;
    let ok = |x: Millis| s.first + s.rho.min(gap + x) >= n.first + x.min(n.rho);
    ok(Millis::ZERO) && ok(n.slack) && ok(n.rho) && ok((s.rho - gap).clamp(Millis::ZERO, n.slack))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn label(arrive: i64, takeoff: i64, slack: i64, first: i64, rho: i64, legs: u32) -> Label {
        Label {
            node: NodeId(0),
            legs,
            ground: false,
            dead: false,
            lo: Instant(0),
            hi: Instant(1_000),
            arrive: Instant(arrive),
            takeoff: Instant(takeoff),
            slack: Millis(slack),
            first: Instant(first),
            rho: Millis(rho),
            parent: LabelId::NONE,
            via: NO_EDGE,
            next_in_state: LabelId::NONE,
            alias: LabelId::NONE,
        }
    }

    /// Brute force over whole members: every member of `n` has a member of `s` no worse.
    fn dominates_by_members(s: &Label, n: &Label) -> bool {
        (0..=n.slack.0).map(Millis).all(|x| {
            (0..=s.slack.0).map(Millis).any(|y| {
                s.arrive + y <= n.arrive + x
                    && s.takeoff + y >= n.takeoff + x
                    && s.first + y.min(s.rho) >= n.first + x.min(n.rho)
            })
        })
    }

    #[test]
    fn dominance_matches_members_on_small_families() {
        let mut checked = 0;
        for a in 0..3 {
            for t in -2..1 {
                for slack in 0..3 {
                    for f in -2..1 {
                        for rho in 0..=slack {
                            let s = label(1, -1, 2, -1, 1, 2);
                            let n = label(a, t, slack, f, rho, 2);
                            assert_eq!(dominates(&s, &n, 1), dominates_by_members(&s, &n), "{n:?}");
                            assert_eq!(dominates(&n, &s, 1), dominates_by_members(&n, &s), "{n:?}");
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 100);
    }

    #[test]
    fn the_leg_that_may_not_land_back_never_dominates_a_later_one() {
        let s = label(0, 0, 5, 0, 5, 1);
        let n = label(3, 0, 0, 0, 0, 2);
        assert!(!dominates(&s, &n, 1));
        assert!(dominates(&label(0, 0, 5, 0, 5, 2), &n, 1));
        assert!(dominates(&s, &n, 0), "no leg is bound by the rule");
        let on_ground = |l: Label| Label { ground: true, ..l };
        assert!(
            dominates(&on_ground(s), &on_ground(n), 1),
            "on the ground after the bound leg, the rule is behind"
        );
    }

    #[test]
    fn later_members_and_later_on_the_ground() {
        let l = label(10, 4, 6, 2, 3, 1);
        let m = l.later_members(Millis(4));
        assert_eq!(
            (m.arrive.0, m.takeoff.0, m.slack.0, m.first.0, m.rho.0),
            (14, 8, 2, 5, 0)
        );
        let g = Label {
            ground: true,
            ..label(10, 2, 3, 2, 3, 2)
        };
        let h = g.on_ground_later(Millis(2));
        assert_eq!(
            (h.arrive.0, h.takeoff.0, h.slack.0, h.first.0, h.rho.0),
            (12, 4, 1, 4, 1)
        );
    }
}
