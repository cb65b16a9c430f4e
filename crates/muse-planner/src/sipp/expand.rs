//! The successors of a label: flying on along a corridor, landing for a battery swap, and
//! taking off again from the ground (see the module docs of [`super`]).

use muse_model::{Instant, Millis};

use super::label::{Hop, Interval, Key, Label, LabelId};
use super::search::Search;
use crate::schedule::{Dir, NodeSlot};
use crate::time::Unbounded;

impl Search<'_, '_> {
    /// Flies on from airborne label `idx` (`label`) along every corridor, entering no later
    /// than `cap`.
    // The single-letter names follow the notation of the module docs (u, v, a, w, s).
    #[allow(clippy::many_single_char_names)]
    pub(super) fn fly(&mut self, idx: LabelId, label: &Label, cap: Instant) {
        let (p, schedule) = (self.p, self.schedule);
        let t_max = p.params.max_flight;
        let u = label.node;
        let (a, t0, sigma) = (label.arrive, label.takeoff, label.slack);
        let used = a - t0;
        for adj in p.airspace.neighbours(u) {
            let v = adj.node;
            let max_used = p.remaining.max_used(v, t_max);
            let w = schedule.traversal(adj.edge);
            if used + w > max_used {
                continue;
            }
            let dir = Dir::of(adj.forward);
            let s_max = label.hi.min(t0 + sigma + max_used - w).min(cap);
            let mut s = a;
            while s <= s_max {
                let (first, run_end) = schedule.edge_free_run(adj.edge, dir, s);
                if first > s_max {
                    break;
                }
                match schedule.node_slot(v, first + w) {
                    NodeSlot::Blocked { next_free } if next_free >= Instant::INF => break,
                    NodeSlot::Blocked { next_free } => s = next_free - w,
                    NodeSlot::Safe { lo, hi, next } => {
                        let last = run_end.min(hi - w).min(s_max);
                        let hop = Hop {
                            via: adj.edge,
                            to: v,
                            arrive: first + w,
                            state: Interval { lo, hi },
                        };
                        let child = label.flown(idx, hop, first, last);
                        self.push(child);
                        // Later departures into this interval are dominated once the latest
                        // take-off is reached or the interval is used up: go on with the next
                        // one. (Progress: either `s` grows, or the next interval starts at
                        // `hi` and `node_slot` answers with it, a different state.)
                        s = if first + child.slack >= a + sigma || last == hi - w {
                            if next >= Instant::INF {
                                break; // no later interval
                            }
                            next - w
                        } else {
                            last + Millis(1)
                        };
                    }
                }
            }
        }
    }

    /// Lands airborne label `idx` (`label`) for a battery swap, if it is at a station where
    /// it may (docs/reference.md#multi-leg-trips): not the destination (reaching it ends the
    /// search), not where its leg took off (see `Swaps::no_return`), and only if another leg is
    /// allowed.
    pub(super) fn land(&mut self, idx: LabelId, label: &Label) {
        let p = self.p;
        let Some(swaps) = p.swaps else { return };
        let u = label.node;
        if label.legs >= swaps.max_legs
            || !p.airspace.is_station(u)
            || (label.legs == swaps.no_return_legs && u == swaps.no_return)
        {
            return;
        }
        let g = p.remaining.on_ground(u);
        if g == Millis::INF {
            return;
        }
        let ground = label.landed(idx, label.arrive + swaps.time);
        self.scratch.push(ground, Key::of(&ground, g));
    }

    /// Takes off from ground label `idx` (`label`): a new leg whose members take off
    /// anywhere in the safe interval of the station from the label's instant on; the ground
    /// label itself moves on to the next safe interval, as a continuation.
    pub(super) fn take_off(&mut self, idx: LabelId, label: &Label) {
        let x = label.node;
        let r = label.arrive;
        let g = self.p.remaining.on_ground(x);
        let later = match self.schedule.node_slot(x, r) {
            NodeSlot::Blocked { next_free } => next_free,
            NodeSlot::Safe { lo, hi, next } => {
                self.push(label.took_off(idx, Interval { lo, hi }));
                next
            }
        };
        if later < Instant::INF {
            let moved = label.on_ground_later(later - r);
            self.scratch
                .push_continuation(idx, moved, Key::of(&moved, g));
        }
    }
}
