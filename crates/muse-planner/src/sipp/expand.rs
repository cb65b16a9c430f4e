//! The successors of a label: flying on along a corridor, landing for a battery swap, and
//! taking off again from the ground (see the module docs of [`super`]).

use muse_model::{Instant, Millis};

use super::label::{GROUND, Label, LabelId, NO_EDGE, Scratch};
use super::{Problem, ground_key, key_of};
use crate::schedule::{Dir, NodeSlot, Schedule};
use crate::time::Unbounded;

/// Flies on from airborne `label` along every corridor, entering no later than `cap`.
// The single-letter names follow the notation of the module docs (u, v, a, w, s).
#[allow(clippy::many_single_char_names)]
pub(super) fn fly(
    p: Problem<'_>,
    schedule: &Schedule,
    scratch: &mut Scratch,
    idx: LabelId,
    label: &Label,
    cap: Instant,
) {
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
                    let x = first - a;
                    // The member leaving at `first` (or the last one, hovering until then).
                    let (takeoff, slack, first_takeoff, rho) = if x < sigma {
                        let slack = last.min(a + sigma) - first;
                        let rho = (label.rho - x).clamp(Millis::ZERO, slack);
                        (t0 + x, slack, label.first + x.min(label.rho), rho)
                    } else {
                        (
                            t0 + sigma,
                            Millis::ZERO,
                            label.first + label.rho,
                            Millis::ZERO,
                        )
                    };
                    let child = Label {
                        node: v,
                        lo,
                        hi,
                        arrive: first + w,
                        takeoff,
                        slack,
                        first: first_takeoff,
                        rho,
                        parent: idx,
                        via: adj.edge,
                        next_in_state: LabelId::NONE,
                        alias: LabelId::NONE,
                        ..*label
                    };
                    scratch.push(child, key_of(p, &child));
                    // Later departures into this interval are dominated once the latest
                    // take-off is reached or the interval is used up: go on with the next one.
                    // (Progress: either `s` grows, or the next interval starts at `hi` and
                    // `node_slot` answers with it, a different state.)
                    s = if first + slack >= a + sigma || last == hi - w {
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

/// Lands airborne `label` for a battery swap, if it is at a station where it may (SPEC §12):
/// not the destination (reaching it ends the search), not where its leg took off (see
/// [`super::Swaps::no_return`]), and only if another leg is allowed.
pub(super) fn land(p: Problem<'_>, scratch: &mut Scratch, idx: LabelId, label: &Label) {
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
    // Members landing after `rho` take off first no later: only the earliest `rho` matter.
    let ready = label.arrive + swaps.time;
    let ground = Label {
        ground: true,
        lo: GROUND,
        hi: Instant::INF,
        arrive: ready,
        takeoff: label.first,
        slack: label.rho,
        parent: idx,
        via: NO_EDGE,
        next_in_state: LabelId::NONE,
        alias: LabelId::NONE,
        ..*label
    };
    scratch.push(ground, ground_key(&ground, g));
}

/// Takes off from ground `label`: a new leg whose members take off anywhere in the safe
/// interval of the station from the label's instant on; the ground label itself moves on to
/// the next safe interval, as a continuation.
pub(super) fn take_off(
    p: Problem<'_>,
    schedule: &Schedule,
    scratch: &mut Scratch,
    idx: LabelId,
    label: &Label,
) {
    let x = label.node;
    let r = label.arrive;
    let g = p.remaining.on_ground(x);
    let later = match schedule.node_slot(x, r) {
        NodeSlot::Blocked { next_free } => next_free,
        NodeSlot::Safe { lo, hi, next } => {
            let root = Label {
                ground: false,
                lo,
                hi,
                takeoff: r,
                slack: hi - r,
                rho: label.rho.min(hi - r),
                legs: label.legs + 1,
                parent: idx,
                via: NO_EDGE,
                next_in_state: LabelId::NONE,
                alias: LabelId::NONE,
                ..*label
            };
            scratch.push(root, key_of(p, &root));
            next
        }
    };
    if later < Instant::INF {
        let moved = label.on_ground_later(later - r);
        scratch.push_continuation(idx, moved, ground_key(&moved, g));
    }
}
