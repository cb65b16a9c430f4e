//! The search's reusable memory: its labels, the states they are in (with dominance applied
//! as labels arrive) and the queue.

use std::cmp::Reverse;
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

/// Reusable per-thread search memory: after the first few requests, planning allocates
/// nothing.
#[derive(Debug, Default)]
pub struct Scratch {
    pub(super) labels: Labels,
    heap: BinaryHeap<Reverse<(Key, LabelId)>>,
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
        while let Some(Reverse((key, idx))) = self.heap.pop() {
            if !self.is_dead(idx) {
                return Some((key, idx));
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
