//! The search's reusable memory: its labels, the states they are in (with dominance applied
//! as labels arrive) and the queue.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::ops::{Index, IndexMut};

use muse_model::{Instant, NodeId};

use super::label::{Key, Label, LabelId, dominates};

/// A state met in a search: a node's safe interval (or its ground) and its labels, as a
/// list linked through `Label::next_in_state`.
#[derive(Clone, Copy, Debug)]
struct State {
    lo: Instant,
    head: LabelId,
    tail: LabelId,
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

/// A queued label with its key. The queue is a max-heap: the greater entry is the one whose
/// key ranks first ([`Key::rank`]), then the older label (the lower id).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Queued {
    key: Key,
    label: LabelId,
}

impl Queued {
    /// The order of entries, smallest first, as plain integers.
    #[inline]
    fn rank(&self) -> (i64, i64, u32, u32) {
        let (landing, later_first, legs) = self.key.rank();
        (landing, later_first, legs, self.label.0)
    }
}

impl Ord for Queued {
    #[inline]
    fn cmp(&self, other: &Self) -> Ordering {
        other.rank().cmp(&self.rank())
    }
}

impl PartialOrd for Queued {
    #[inline]
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }

    #[inline]
    fn lt(&self, other: &Self) -> bool {
        other.rank() < self.rank()
    }

    #[inline]
    fn le(&self, other: &Self) -> bool {
        other.rank() <= self.rank()
    }

    #[inline]
    fn gt(&self, other: &Self) -> bool {
        other.rank() > self.rank()
    }

    #[inline]
    fn ge(&self, other: &Self) -> bool {
        other.rank() >= self.rank()
    }
}

/// Reusable per-thread search memory: after the first few requests, planning allocates
/// nothing.
#[derive(Debug, Default)]
pub struct Scratch {
    pub(super) labels: Labels,
    heap: BinaryHeap<Queued>,
    /// Per node: the states met in this search, sorted by `lo`.
    states: Vec<Vec<State>>,
    touched: Vec<NodeId>,
    /// Labels whose key passes this are never queued (the search's deadline).
    deadline: Instant,
    /// The leg that may not land where it took off (`Swaps::no_return_legs`).
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

    /// The next label in key order that is not dominated, with its key.
    #[inline]
    pub(super) fn pop(&mut self) -> Option<(Key, LabelId)> {
        while let Some(Queued { key, label }) = self.heap.pop() {
            if !self.is_dead(label) {
                return Some((key, label));
            }
        }
        None
    }

    /// Whether label `idx` (or, for a continuation, the label it belongs to) is dominated.
    fn is_dead(&self, idx: LabelId) -> bool {
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
        self.heap.push(Queued { key, label: idx });
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
        self.heap.push(Queued { key, label: idx });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_queue_pops_the_earliest_landing_then_the_latest_first_take_off_then_fewest_legs() {
        // Every combination of a few values, queued in a scrambled order.
        let mut entries = Vec::new();
        for landing in [5, -3, 9] {
            for first in [2, 0, -7] {
                for legs in [2, 1] {
                    let label = LabelId(entries.len() as u32 * 7 % 19);
                    let key = Key {
                        landing: Instant(landing),
                        first: Instant(first),
                        legs,
                    };
                    entries.push(Queued { key, label });
                }
            }
        }
        // Two entries with the same key: the older label first.
        entries.push(Queued {
            key: entries[4].key,
            label: LabelId(100),
        });
        let mut heap: BinaryHeap<Queued> = entries.iter().copied().collect();
        let mut popped = Vec::new();
        while let Some(q) = heap.pop() {
            popped.push(q);
        }
        let mut want = entries.clone();
        want.sort_by_key(|q| {
            (
                q.key.landing,
                std::cmp::Reverse(q.key.first),
                q.key.legs,
                q.label,
            )
        });
        assert_eq!(popped, want);
        assert_eq!(popped[0].key.landing, Instant(-3));
        assert_eq!(popped[0].key.first, Instant(2));
        assert_eq!(popped[0].key.legs, 1);
    }
}
