//! Labels, their dominance, and the search's reusable memory.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// "No label" in parent, edge and list links.
pub(super) const NONE: u32 = u32::MAX;

/// The `lo` of the ground state of a station (SPEC §12: on the ground between legs), below
/// every safe interval's `lo`.
pub(super) const GROUND: i64 = i64::MIN;

/// One label (see the module docs of [`super`]): a family of partial plans with members
/// `x ∈ [0, slack]`: arrival `arrive + x`, current leg's take-off `takeoff + x`, first
/// take-off `first + min(x, rho)`, `legs` legs begun. A ground label (`ground`) is a drone on
/// the ground at a station between legs, free to take off from `arrive + x`; its `takeoff`
/// is `first` and its `slack` is `rho`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Label {
    pub node: u32,
    pub legs: u32,
    pub ground: bool,
    pub dead: bool,
    /// The safe interval of the state (`GROUND` for a ground label).
    pub lo: i64,
    pub hi: i64,
    pub arrive: i64,
    pub takeoff: i64,
    pub slack: i64,
    pub first: i64,
    pub rho: i64,
    /// Parent label and the edge flown from it (`NONE` at the start of the search and after
    /// a take-off).
    pub parent: u32,
    pub via: u32,
    /// Next label of the same state (linked list), or `NONE`.
    pub next_in_state: u32,
    /// For a *continuation* (the later members of a label, queued apart so that their
    /// successors are generated lazily): the label held in the state list whose death is
    /// theirs. `NONE` for a label in the state list.
    pub alias: u32,
}

impl Label {
    /// The members `x ≥ dx` of an airborne label, as a label of their own.
    pub fn later_members(&self, dx: i64) -> Label {
        debug_assert!(!self.ground && dx > 0 && dx <= self.slack);
        Label {
            arrive: self.arrive + dx,
            takeoff: self.takeoff + dx,
            slack: self.slack - dx,
            first: self.first + dx.min(self.rho),
            rho: (self.rho - dx).max(0),
            ..*self
        }
    }

    /// A ground label's members from `dt` later on: free to take off from `arrive + dt`.
    pub fn on_ground_later(&self, dt: i64) -> Label {
        debug_assert!(self.ground && dt > 0);
        let first = self.first + dt.min(self.rho);
        let rho = (self.rho - dt).max(0);
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
    lo: i64,
    head: u32,
    tail: u32,
}

/// The priority of a label: `(arrival + remaining, −first take-off, legs)`, smallest first.
pub(super) type Key = (i64, i64, u32);

/// Reusable per-thread search memory: after the first few requests, planning allocates
/// nothing.
#[derive(Debug, Default)]
pub struct Scratch {
    pub(super) labels: Vec<Label>,
    pub(super) heap: BinaryHeap<Reverse<(Key, u32)>>,
    /// Per node: the states met in this search, sorted by `lo`.
    states: Vec<Vec<State>>,
    touched: Vec<u32>,
    /// Labels whose key passes this are never queued (the search's deadline).
    pub(super) deadline: i64,
    /// The leg that may not land where it took off ([`super::Swaps::no_return_legs`]).
    no_return_legs: u32,
    /// Labels expanded by the last search.
    pub expanded: u64,
}

impl Scratch {
    /// Empty scratch space; it grows to fit the airspace on first use.
    pub fn new() -> Self {
        Scratch::default()
    }

    pub(super) fn reset(&mut self, node_count: usize, deadline: i64, no_return_legs: u32) {
        self.deadline = deadline;
        self.no_return_legs = no_return_legs;
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

    /// Whether label `idx` (or, for a continuation, the label it belongs to) is dominated.
    pub(super) fn is_dead(&self, idx: u32) -> bool {
        let l = &self.labels[idx as usize];
        l.dead || (l.alias != NONE && self.labels[l.alias as usize].dead)
    }

    /// Adds a label unless an existing label of its state dominates it; marks the labels it
    /// dominates dead; queues it with `key`.
    ///
    /// A state's labels are listed oldest first: labels are pushed in roughly increasing key
    /// order, so an older label is the likelier to dominate a new one, and is met first.
    pub(super) fn push(&mut self, label: Label, key: Key) {
        if key.0 > self.deadline {
            return;
        }
        let node = label.node as usize;
        let states = &mut self.states[node];
        // States are kept sorted by `lo`; new ones usually go last.
        let k = states.partition_point(|s| s.lo < label.lo);
        let idx = self.labels.len() as u32;
        if states.get(k).is_some_and(|s| s.lo == label.lo) {
            if self.dominated_in(node, k, &label) {
                return;
            }
            let tail = std::mem::replace(&mut self.states[node][k].tail, idx);
            if tail == NONE {
                self.states[node][k].head = idx;
            } else {
                self.labels[tail as usize].next_in_state = idx;
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
        self.labels.push(Label {
            next_in_state: NONE,
            ..label
        });
        self.heap.push(Reverse((key, idx)));
    }

    /// Whether a label of state `k` of `node` dominates `label`; marks dead those `label`
    /// dominates and unlinks every dead label met, so that lists stay short.
    fn dominated_in(&mut self, node: usize, k: usize, label: &Label) -> bool {
        let r = self.no_return_legs;
        let mut prev = NONE;
        let mut i = self.states[node][k].head;
        let mut dominated = false;
        while i != NONE {
            let s = &mut self.labels[i as usize];
            let next = s.next_in_state;
            if !s.dead && !dominated && dominates(s, label, r) {
                dominated = true;
            } else if !s.dead && !dominated && dominates(label, s, r) {
                s.dead = true;
            }
            if s.dead {
                // Unlink: a dead label never dominates again (its continuations check its
                // flag, not the list).
                if prev == NONE {
                    self.states[node][k].head = next;
                } else {
                    self.labels[prev as usize].next_in_state = next;
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
    pub(super) fn push_continuation(&mut self, of: u32, label: Label, key: Key) {
        if key.0 > self.deadline {
            return;
        }
        let idx = self.labels.len() as u32;
        let owner = self.labels[of as usize].alias;
        self.labels.push(Label {
            alias: if owner == NONE { of } else { owner },
            next_in_state: NONE,
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
    let ok = |x: i64| s.first + s.rho.min(gap + x) >= n.first + x.min(n.rho);
    ok(0) && ok(n.slack) && ok(n.rho) && ok((s.rho - gap).clamp(0, n.slack))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn label(arrive: i64, takeoff: i64, slack: i64, first: i64, rho: i64, legs: u32) -> Label {
        Label {
            node: 0,
            legs,
            ground: false,
            dead: false,
            lo: 0,
            hi: 1_000,
            arrive,
            takeoff,
            slack,
            first,
            rho,
            parent: NONE,
            via: NONE,
            next_in_state: NONE,
            alias: NONE,
        }
    }

    /// Brute force over whole members: every member of `n` has a member of `s` no worse.
    fn dominates_by_members(s: &Label, n: &Label) -> bool {
        (0..=n.slack).all(|x| {
            (0..=s.slack).any(|y| {
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
        let m = l.later_members(4);
        assert_eq!(
            (m.arrive, m.takeoff, m.slack, m.first, m.rho),
            (14, 8, 2, 5, 0)
        );
        let g = Label {
            ground: true,
            ..label(10, 2, 3, 2, 3, 2)
        };
        let h = g.on_ground_later(2);
        assert_eq!(
            (h.arrive, h.takeoff, h.slack, h.first, h.rho),
            (12, 4, 1, 4, 1)
        );
    }
}
