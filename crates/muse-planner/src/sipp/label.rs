//! Labels: families of partial plans (see the module docs of [`super`]), how they are made,
//! their priority and their dominance.

use muse_model::{EdgeId, Instant, Millis, NodeId};

use crate::time::Unbounded;

/// The index of a label in a search's labels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct LabelId(pub(super) u32);

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

/// The `lo` of the ground state of a station (docs/reference.md#multi-leg-trips: on the ground
/// between legs). Not a time: the key of that state, below every safe interval's `lo` (which is at
/// least `Instant::NEG_INF`).
pub(super) const GROUND: Instant = Instant(i64::MIN);

/// A safe interval `[lo, hi]` of a node: with the node, the state a label is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Interval {
    pub lo: Instant,
    pub hi: Instant,
}

/// A move along a corridor: the edge flown, the node reached, the arrival there and the safe
/// interval of the node it arrives in.
#[derive(Clone, Copy, Debug)]
pub(super) struct Hop {
    pub via: EdgeId,
    pub to: NodeId,
    pub arrive: Instant,
    pub state: Interval,
}

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
    /// The state of every ground label.
    const ON_GROUND: Interval = Interval {
        lo: GROUND,
        hi: Instant::INF,
    };

    /// A search's first label on the ground: take-offs from `origin` at `from + x` for
    /// `x ∈ [0, slack]`, into its safe interval `state`, each the first take-off of the trip.
    pub fn take_offs(origin: NodeId, state: Interval, from: Instant, slack: Millis) -> Label {
        Label {
            node: origin,
            legs: 1,
            ground: false,
            dead: false,
            lo: state.lo,
            hi: state.hi,
            arrive: from,
            takeoff: from,
            slack,
            first: from,
            rho: slack,
            parent: LabelId::NONE,
            via: NO_EDGE,
            next_in_state: LabelId::NONE,
            alias: LabelId::NONE,
        }
    }

    /// A search's first label in the air: one member, arriving at `node` at `at` in its safe
    /// interval `state`, its leg (the `legs`-th) having taken off at `leg_takeoff` and the
    /// trip at `first`.
    pub fn in_flight(
        node: NodeId,
        state: Interval,
        at: Instant,
        leg_takeoff: Instant,
        first: Instant,
        legs: u32,
    ) -> Label {
        Label {
            takeoff: leg_takeoff,
            slack: Millis::ZERO,
            first,
            rho: Millis::ZERO,
            legs,
            ..Label::take_offs(node, state, at, Millis::ZERO)
        }
    }

    /// A search's first label between legs: one member, on the ground at station `node`,
    /// free to take off from `ready`, after `legs` legs of a trip that first took off at
    /// `first`.
    pub fn between_legs(node: NodeId, ready: Instant, first: Instant, legs: u32) -> Label {
        Label {
            ground: true,
            ..Label::in_flight(node, Label::ON_GROUND, ready, first, first, legs)
        }
    }

    /// The successor of airborne label `self` (whose id is `parent`) that enters the corridor
    /// of `hop` at `s`: the member arriving at `s` (or, when every member arrives earlier,
    /// the last one, hovering until then), and with it, while there are later members, those
    /// entering by `last` without hovering.
    pub fn flown(&self, parent: LabelId, hop: Hop, s: Instant, last: Instant) -> Label {
        debug_assert!(!self.ground && s >= self.arrive && last >= s);
        let x = s - self.arrive;
        let (takeoff, slack, first, rho) = if x < self.slack {
            let slack = last.min(self.arrive + self.slack) - s;
            let rho = (self.rho - x).clamp(Millis::ZERO, slack);
            (self.takeoff + x, slack, self.first + x.min(self.rho), rho)
        } else {
            let none = Millis::ZERO;
            (self.takeoff + self.slack, none, self.first + self.rho, none)
        };
        Label {
            node: hop.to,
            legs: self.legs,
            ground: false,
            dead: false,
            lo: hop.state.lo,
            hi: hop.state.hi,
            arrive: hop.arrive,
            takeoff,
            slack,
            first,
            rho,
            parent,
            via: hop.via,
            next_in_state: LabelId::NONE,
            alias: LabelId::NONE,
        }
    }

    /// Airborne label `self` (whose id is `parent`) landed at its node for a battery swap,
    /// free to take off again from `ready + x`. Only its members up to `rho` matter: later
    /// landings take off first no later.
    pub fn landed(&self, parent: LabelId, ready: Instant) -> Label {
        debug_assert!(!self.ground);
        Label {
            ground: true,
            lo: Label::ON_GROUND.lo,
            hi: Label::ON_GROUND.hi,
            arrive: ready,
            takeoff: self.first,
            slack: self.rho,
            parent,
            via: NO_EDGE,
            next_in_state: LabelId::NONE,
            alias: LabelId::NONE,
            ..*self
        }
    }

    /// Ground label `self` (whose id is `parent`) taking off on its next leg into the safe
    /// interval `state` of its station, which holds its instant: a member for every instant
    /// from there to the end of the interval.
    pub fn took_off(&self, parent: LabelId, state: Interval) -> Label {
        debug_assert!(self.ground && state.lo <= self.arrive && self.arrive <= state.hi);
        let slack = state.hi - self.arrive;
        Label {
            ground: false,
            lo: state.lo,
            hi: state.hi,
            takeoff: self.arrive,
            slack,
            rho: self.rho.min(slack),
            legs: self.legs + 1,
            parent,
            via: NO_EDGE,
            next_in_state: LabelId::NONE,
            alias: LabelId::NONE,
            ..*self
        }
    }

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

/// The priority of a label (see the module docs of [`super`]): the earliest landing it can
/// lead to first, then the latest first take-off, then the fewest legs ([`Key::rank`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Key {
    /// The earliest landing the label can lead to: its arrival plus the remaining time.
    pub landing: Instant,
    /// The label's first take-off.
    pub first: Instant,
    /// The legs begun.
    pub legs: u32,
}

impl Key {
    /// The priority of label `l` from which at least `remaining` is still to fly.
    #[inline]
    pub fn of(l: &Label, remaining: Millis) -> Key {
        Key {
            landing: l.arrive + remaining,
            first: l.first,
            legs: l.legs,
        }
    }

    /// The key as plain integers, smallest first: landing, then the first take-off negated
    /// (later first), then legs. The queue compares these on every sift, where plain integers
    /// compare fastest.
    #[inline]
    pub fn rank(self) -> (i64, i64, u32) {
        (self.landing.0, -self.first.0, self.legs)
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
pub(super) fn dominates(s: &Label, n: &Label, r: u32) -> bool {
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

    /// Member `x` of a label: its arrival, its leg's take-off and its first take-off, in ms.
    fn member(l: &Label, x: i64) -> (i64, i64, i64) {
        let x = Millis(x);
        (
            (l.arrive + x).0,
            (l.takeoff + x).0,
            (l.first + x.min(l.rho)).0,
        )
    }

    /// `(arrive, takeoff, slack, first, rho)` in ms.
    fn timing(l: &Label) -> (i64, i64, i64, i64, i64) {
        (l.arrive.0, l.takeoff.0, l.slack.0, l.first.0, l.rho.0)
    }

    #[test]
    fn a_flown_label_holds_the_members_that_leave_at_its_entries() {
        let w = 10;
        let hop = |s: i64| Hop {
            via: EdgeId(5),
            to: NodeId(1),
            arrive: Instant(s + w),
            state: Interval {
                lo: Instant(0),
                hi: Instant(1_000),
            },
        };
        let mut checked = 0;
        for (slack, rho) in [(0, 0), (3, 1), (5, 5), (6, 2)] {
            let l = label(10, 4, slack, 2, rho, 2);
            for s in 10..20 {
                for last in s..22 {
                    let c = l.flown(LabelId(7), hop(s), Instant(s), Instant(last));
                    assert_eq!(
                        (c.node, c.legs, c.parent, c.via, c.ground),
                        (NodeId(1), 2, LabelId(7), EdgeId(5), false)
                    );
                    // Every member leaves in [s, last] without hovering, unless the
                    // parent's members all arrived before `s`.
                    let expected = if s - 10 < slack {
                        last.min(10 + slack) - s
                    } else {
                        0
                    };
                    assert_eq!(c.slack.0, expected, "{l:?} s {s} last {last}");
                    for y in 0..=c.slack.0 {
                        // The parent's member that arrives last by the departure `s + y`.
                        let x = (s + y - 10).min(slack);
                        let (_, takeoff, first) = member(&l, x);
                        assert_eq!(
                            member(&c, y),
                            (s + y + w, takeoff, first),
                            "{l:?} s {s} last {last} member {y}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 500);
    }

    #[test]
    fn first_labels_are_the_starts_they_name() {
        let state = Interval {
            lo: Instant(-5),
            hi: Instant(50),
        };
        let g = Label::take_offs(NodeId(3), state, Instant(10), Millis(4));
        assert_eq!(timing(&g), (10, 10, 4, 10, 4));
        assert_eq!(
            (g.node, g.legs, g.ground, g.lo, g.hi),
            (NodeId(3), 1, false, state.lo, state.hi)
        );
        assert!(g.parent.is_none() && g.alias.is_none() && g.via == NO_EDGE);
        let a = Label::in_flight(NodeId(3), state, Instant(30), Instant(12), Instant(8), 2);
        assert_eq!(timing(&a), (30, 12, 0, 8, 0));
        assert_eq!((a.legs, a.ground), (2, false));
        let b = Label::between_legs(NodeId(3), Instant(30), Instant(8), 2);
        assert_eq!(timing(&b), (30, 8, 0, 8, 0));
        assert_eq!(
            (b.legs, b.ground, b.lo, b.hi),
            (2, true, GROUND, Instant::INF)
        );
    }

    #[test]
    fn landing_and_taking_off_keep_each_members_first_take_off() {
        let l = label(10, 4, 6, 2, 3, 1);
        // Ready 15 after landing: members up to `rho` (later landings take off first no later).
        let g = l.landed(LabelId(3), Instant(25));
        assert_eq!(timing(&g), (25, 2, 3, 2, 3));
        assert_eq!(
            (g.ground, g.lo, g.parent, g.legs),
            (true, GROUND, LabelId(3), 1)
        );
        let up = g.took_off(
            LabelId(4),
            Interval {
                lo: Instant(20),
                hi: Instant(27),
            },
        );
        // Take-offs from 25 to the end of the interval, 27; the first take-off slides with
        // them up to `rho`.
        assert_eq!(timing(&up), (25, 25, 2, 2, 2));
        assert_eq!(
            (up.ground, up.lo, up.legs, up.parent),
            (false, Instant(20), 2, LabelId(4))
        );
    }
}
