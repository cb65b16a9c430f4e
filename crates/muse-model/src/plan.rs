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

/// A planned flight: its stays from origin to destination (SPEC §3).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Plan {
    /// The stays, origin first.
    pub path: Vec<Stay>,
}

impl Plan {
    /// Take-off instant (arrival at the first stay).
    pub fn takeoff(&self) -> Instant {
        self.path.first().map_or(Instant(0), |s| s.arrive)
    }

    /// Landing instant (departure from the last stay).
    pub fn landing(&self) -> Instant {
        self.path.last().map_or(Instant(0), |s| s.depart)
    }

    /// Airborne time, landing minus take-off.
    pub fn airborne(&self) -> Millis {
        self.landing() - self.takeoff()
    }
}

/// Why a request was rejected (SPEC §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RejectReason {
    /// Even the free-flow path, ignoring traffic and zones, exceeds the battery limit.
    OutOfRange,
    /// No path in the graph joins origin and destination.
    Unreachable,
    /// Traffic and/or zones make every path infeasible.
    NoFeasiblePlan,
    /// The requested departure is earlier than the service clock's now (SPEC §10; only the
    /// online planner gives it).
    DepartureInPast,
}

impl RejectReason {
    /// All reasons, in report order.
    pub const ALL: [RejectReason; 4] = [
        RejectReason::OutOfRange,
        RejectReason::Unreachable,
        RejectReason::NoFeasiblePlan,
        RejectReason::DepartureInPast,
    ];

    /// The reasons a plan of SPEC §6 can be refused for, whatever the clock: the ones a batch
    /// run (a day planned in advance) reports.
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
