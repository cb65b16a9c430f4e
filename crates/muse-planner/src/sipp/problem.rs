//! What a search is asked: the heuristic, the battery swaps, the deadline, where it starts
//! and where it may end.

use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId};

use super::label::{Key, Label};
use crate::heuristic::swaps::SwapTable;
use crate::time::Unbounded;

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
    pub fn max_used(self, v: NodeId, t_max: Millis) -> Millis {
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
    pub fn at(self, v: NodeId, used: Millis) -> Millis {
        match self {
            Remaining::Single(h) => h[v.index()],
            Remaining::Swaps(t) => t.remaining(v, used),
        }
    }

    /// The remaining time from the ground at station `v` (swaps only).
    #[inline]
    pub fn on_ground(self, v: NodeId) -> Millis {
        match self {
            Remaining::Single(_) => Millis::INF,
            Remaining::Swaps(t) => t.trip_from_ground(v),
        }
    }
}

/// Battery swaps as the search applies them (docs/reference.md#multi-leg-trips).
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
    pub(super) fn split(&self) -> Millis {
        Millis(self.params.max_flight.0 / 2).max(Millis(1))
    }

    /// The priority of airborne label `l`.
    #[inline]
    pub(super) fn key(&self, l: &Label) -> Key {
        Key::of(l, self.remaining.at(l.node, l.arrive - l.takeoff))
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
    /// `legs`-th) having taken off at `takeoff` and the trip at `first`
    /// (docs/reference.md#zones-announced-during-the-day: an airborne flight replanned from the
    /// first node it reaches).
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
    /// (docs/reference.md#zones-announced-during-the-day diversion).
    AnyStation,
}
