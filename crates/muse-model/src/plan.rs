//! Plans: what the planner returns for a request.

use std::fmt;

use crate::ids::NodeId;
use crate::time::{Instant, Millis};

/// One stay of a plan: the drone is at `node` from `arrive` to `depart` (hovering if they
/// differ). The first stay starts at take-off, the last ends at landing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stay {
    /// Where.
    pub node: NodeId,
    /// Arrival (take-off for the first stay).
    pub arrive: Instant,
    /// Departure (landing for the last stay, where `depart == arrive`).
    pub depart: Instant,
}

/// A planned flight: its stays from origin to destination
/// (docs/reference.md#flight-model-and-separation).
///
/// A multi-leg trip (docs/reference.md#multi-leg-trips: battery swaps at stations) lists the stays
/// of all its legs in order. Where one leg lands and the next takes off, two consecutive stays are
/// at the same station: the landing `(X, l, l)` and the next take-off `(X, t, d)`, with the swap
/// time `t − l` spent on the ground, outside the airspace. Consecutive stays of one leg are always
/// at different nodes (edges join distinct nodes), so the legs are read off the path alone.
///
/// ```
/// use muse_model::{Instant, NodeId, Plan, Stay};
/// let stay = |n, a, d| Stay { node: NodeId(n), arrive: Instant(a), depart: Instant(d) };
/// // S0 → S1, swap at S1 for 5 minutes, S1 → S2.
/// let plan = Plan { path: vec![stay(0, 0, 0), stay(1, 600_000, 600_000),
///                              stay(1, 900_000, 900_000), stay(2, 1_500_000, 1_500_000)] };
/// assert_eq!(plan.leg_count(), 2);
/// assert_eq!(plan.legs().map(|l| l.len()).collect::<Vec<_>>(), [2, 2]);
/// assert_eq!(plan.hops().count(), 2);
/// assert_eq!((plan.takeoff(), plan.landing()), (Instant(0), Instant(1_500_000)));
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Plan {
    /// The stays, origin first (every leg's, in order).
    pub path: Vec<Stay>,
}

impl Plan {
    /// Take-off instant (arrival at the first stay; the first leg's take-off).
    pub fn takeoff(&self) -> Instant {
        self.path.first().map_or(Instant(0), |s| s.arrive)
    }

    /// Landing instant (departure from the last stay; the last leg's landing).
    pub fn landing(&self) -> Instant {
        self.path.last().map_or(Instant(0), |s| s.depart)
    }

    /// Landing minus take-off: for a multi-leg trip, the whole trip, time on the ground
    /// between legs included.
    pub fn airborne(&self) -> Millis {
        self.landing() - self.takeoff()
    }

    /// The legs: maximal runs of stays whose consecutive nodes differ (one for a plan without
    /// battery swaps; none for an empty plan).
    pub fn legs(&self) -> impl Iterator<Item = &[Stay]> + '_ {
        self.path.chunk_by(|a, b| a.node != b.node)
    }

    /// How many legs the plan has.
    pub fn leg_count(&self) -> usize {
        self.legs().count()
    }

    /// The traversals: consecutive stays of the same leg, `(from, to)`; the drone leaves
    /// `from.node` at `from.depart` and reaches `to.node` at `to.arrive`.
    pub fn hops(&self) -> impl Iterator<Item = (&Stay, &Stay)> + '_ {
        self.path
            .windows(2)
            .filter(|w| w[0].node != w[1].node)
            .map(|w| (&w[0], &w[1]))
    }
}

/// What became of an accepted flight that a zone announced later would break
/// (docs/reference.md#zones-announced-during-the-day).
///
/// ```
/// use muse_model::plan::{Fate, FateKind};
/// use muse_model::Plan;
/// assert_eq!(Fate::Cancelled.kind().as_str(), "cancelled");
/// assert!(Fate::Replanned(Plan::default()).plan().is_some());
/// assert_eq!(FateKind::parse("diverted"), Some(FateKind::Diverted));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Fate {
    /// A new plan to its destination.
    Replanned(Plan),
    /// Airborne, and its destination could not be reached: a plan to the station where it can
    /// land earliest.
    Diverted(Plan),
    /// Not taken off, and no plan exists: cancelled (reason `zone_announced`).
    Cancelled,
    /// Airborne, and no station can be reached: the committed part (ending with the arrival
    /// at the node it reaches at or after the announcement), which stays reserved.
    Contingency(Plan),
}

impl Fate {
    /// The flight's plan after replanning, if it still lands somewhere.
    pub fn plan(&self) -> Option<&Plan> {
        match self {
            Fate::Replanned(p) | Fate::Diverted(p) => Some(p),
            Fate::Cancelled | Fate::Contingency(_) => None,
        }
    }

    /// Which fate, without its plan.
    pub fn kind(&self) -> FateKind {
        match self {
            Fate::Replanned(_) => FateKind::Replanned,
            Fate::Diverted(_) => FateKind::Diverted,
            Fate::Cancelled => FateKind::Cancelled,
            Fate::Contingency(_) => FateKind::Contingency,
        }
    }
}

/// The kind of a [`Fate`]: the status a replanned flight is reported with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FateKind {
    /// See [`Fate::Replanned`].
    Replanned,
    /// See [`Fate::Diverted`].
    Diverted,
    /// See [`Fate::Cancelled`].
    Cancelled,
    /// See [`Fate::Contingency`].
    Contingency,
}

impl FateKind {
    /// All kinds, in report order.
    pub const ALL: [FateKind; 4] = [
        FateKind::Replanned,
        FateKind::Diverted,
        FateKind::Cancelled,
        FateKind::Contingency,
    ];

    /// The status spelling used in files and answers.
    pub const fn as_str(self) -> &'static str {
        match self {
            FateKind::Replanned => "replanned",
            FateKind::Diverted => "diverted",
            FateKind::Cancelled => "cancelled",
            FateKind::Contingency => "contingency",
        }
    }

    /// Parses the status spelling.
    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.as_str() == text)
    }
}

/// What one zone announcement did to one flight (docs/reference.md#zones-announced-during-the-day):
/// the record every layer keeps of it — the planner's replanning, the simulator's replay, a plans
/// file's `changes` and the service's store. The plan it left the flight with, if any, is the
/// [`Fate`] kept beside the last change.
///
/// ```
/// use muse_model::Instant;
/// use muse_model::plan::{Change, Fate, FateKind};
/// let c = Change::new("Z1", Instant(36_000_000), true, &Fate::Cancelled);
/// assert_eq!((c.zone.as_str(), c.outcome), ("Z1", FateKind::Cancelled));
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Change {
    /// The id of the zone announced.
    pub zone: String,
    /// When it was announced.
    pub announced: Instant,
    /// Whether the flight had taken off then.
    pub airborne: bool,
    /// What the announcement made of the flight.
    pub outcome: FateKind,
}

impl Change {
    /// The change `zone`, announced at `announced`, made of a flight (`airborne`: it had
    /// taken off then) whose fate is now `fate`.
    pub fn new(zone: &str, announced: Instant, airborne: bool, fate: &Fate) -> Self {
        Change {
            zone: zone.to_owned(),
            announced,
            airborne,
            outcome: fate.kind(),
        }
    }
}

/// The reason a flight cancelled by a zone announcement is given
/// (docs/reference.md#zones-announced-during-the-day).
pub const ZONE_ANNOUNCED: &str = "zone_announced";

/// The reason given for a flight its operator cancelled before take-off (the service,
/// docs/reference.md#the-planning-service
///): it then holds no plan.
pub const CANCELLED_BY_OPERATOR: &str = "cancelled_by_operator";

/// Why a request was rejected (docs/reference.md#planning).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RejectReason {
    /// Even the free-flow path, ignoring traffic and zones, exceeds the battery limit.
    OutOfRange,
    /// No path in the graph joins origin and destination.
    Unreachable,
    /// Traffic and/or zones make every path infeasible.
    NoFeasiblePlan,
    /// The requested departure is earlier than the service clock's now
    /// (docs/reference.md#the-planning-service; only the online planner gives it).
    DepartureInPast,
    /// Demand from customers (docs/reference.md#airspace-from-pads): a customer has no pad within
    /// the last mile, or both share one, so the request was never planned; counted apart from the
    /// planner's reasons.
    Unserved,
}

impl RejectReason {
    /// All reasons, in report order.
    pub const ALL: [RejectReason; 5] = [
        RejectReason::OutOfRange,
        RejectReason::Unreachable,
        RejectReason::NoFeasiblePlan,
        RejectReason::DepartureInPast,
        RejectReason::Unserved,
    ];

    /// The reasons the planning service gives (docs/reference.md#the-planning-service): the
    /// planner's and `departure_in_past`.
    pub const SERVICE: [RejectReason; 4] = [
        RejectReason::OutOfRange,
        RejectReason::Unreachable,
        RejectReason::NoFeasiblePlan,
        RejectReason::DepartureInPast,
    ];

    /// The reasons a plan of docs/reference.md#planning can be refused for, whatever the clock: the
    /// ones a batch run (a day planned in advance) reports.
    pub const PLANNING: [RejectReason; 3] = [
        RejectReason::OutOfRange,
        RejectReason::Unreachable,
        RejectReason::NoFeasiblePlan,
    ];

    /// The spelling used in files.
    pub const fn as_str(self) -> &'static str {
        match self {
            RejectReason::OutOfRange => "out_of_range",
            RejectReason::Unreachable => "unreachable",
            RejectReason::NoFeasiblePlan => "no_feasible_plan",
            RejectReason::DepartureInPast => "departure_in_past",
            RejectReason::Unserved => "unserved",
        }
    }

    /// Parses the file spelling.
    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|r| r.as_str() == text)
    }
}

impl fmt::Display for RejectReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}
