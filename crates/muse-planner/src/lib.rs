//! The MUSE planner: exact, optimal, collision-free routing of one request at a time
//! against everything already planned.
//!
//! Its public surface is small: [`Planner`] (prepared once per airspace and parameters, then
//! queried: [`Planner::plan`] one request against a [`Schedule`], with a reusable
//! [`Scratch`]), [`plan_day`] (a list of requests first come, first served), [`Schedule`] (the
//! reservation table, the paper's *CurrentSchedule*), [`Live`] (the same planner and schedule
//! driven by a clock, for requests that arrive one at a time, with cancellation and zones
//! announced while it runs), and the outcome and error types ([`Outcome`] answers both
//! [`Planner::plan`] and [`Planner::resume`]). Inside, one module per concept: `time` (the
//! model's `Instant` and `Millis` throughout, and the planner's one infinity), `schedule`
//! (stays, traversals and zone closures, with safe-interval queries), `heuristic` (exact
//! free-flow times to each destination, computed once and shared), `sipp` (the safe-interval
//! A* search: hovering, battery, ground delay), `planner`, `online` and `replan` (what a newly
//! announced zone does to the flights it hits: replanned, diverted, cancelled or
//! contingency). The `plan_day` benchmark is in `benches/`.
//!
//! ```
//! use muse_airspace::closures::Closures;
//! use muse_model::{Airspace, Edge, FlightParams, Instant, LonLat, Millis, Node, NodeId, NodeKind, Request};
//! use muse_planner::{FlightId, Planner, Schedule, Scratch};
//!
//! let node = |id: &str, lon| Node {
//!     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3),
//! };
//! let airspace = Airspace::new(
//!     vec![node("A", 103.80), node("B", 103.81)],
//!     vec![Edge { id: "A-B".into(), from: NodeId(0), to: NodeId(1), length_m: 1_000.0 }],
//! ).unwrap();
//! // The paper's parameters, but drones may wait on the ground up to 10 minutes.
//! let params = FlightParams { max_ground_delay: Millis::from_mins(10), ..FlightParams::default() };
//! let planner = Planner::new(&airspace, params);
//! let mut schedule = Schedule::new(&airspace, &params, &Closures::none(&airspace));
//! let mut scratch = Scratch::new();
//! let r = |id: &str| Request { id: id.into(), origin: NodeId(0), destination: NodeId(1), departure: Instant(0), submitted: Instant(0) };
//!
//! let first = planner.plan(&schedule, &r("r1"), &mut scratch).result.unwrap();
//! assert_eq!(first.landing(), Instant(120_000)); // 1 km at 30 km/h
//! schedule.insert(&airspace, FlightId(0), &first);
//! // The second drone may not enter the corridor while the first is on it: it lands as early
//! // as possible, and waits for that on the ground rather than in the air.
//! let second = planner.plan(&schedule, &r("r2"), &mut scratch).result.unwrap();
//! assert_eq!(second.landing(), Instant(240_000));
//! assert_eq!(second.takeoff(), Instant(120_000));
//! ```
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod heuristic;
mod online;
mod planner;
mod replan;
mod schedule;
mod sipp;
mod time;

pub use online::{CancelError, FORGET_EVERY, Holding, Live, ZoneError};
pub use planner::{Landing, Outcome, Planner, Resume, plan_and_book, plan_day};
pub use replan::{Affected, Booking, Commitment, Fate, FateKind, breaks, committed_part};
pub use schedule::{FlightId, Schedule};
pub use sipp::Scratch;
