//! Batch planning (docs/reference.md#batch-planning): when the requests of a period are known
//! before it starts, plan them together, better than first come, first served (FCFS).
//!
//! The paper plans each request optimally against those before it; the whole day is NP-hard.
//! [`optimize`] starts from FCFS, tries priority orders ([`Order`]) and then improves the best
//! schedule by large-neighbourhood search: it takes the flights in a rejected request's way
//! out of the schedule, plans the request and those flights again in a new order with the
//! exact planner (`muse_planner`; no search is re-implemented here) and keeps the change
//! unless the [`Objective`] — most requests planned, then least total delay — got worse.
//! Every plan is made by the exact planner against every other plan, so every schedule is
//! valid (docs/reference.md#flight-model-and-separation and #no-fly-zones, #multi-leg-trips); the
//! result is never worse than FCFS; a seed and an iteration budget give the same schedule on every
//! machine.
//!
//! ```
//! use muse_airspace::closures::Closures;
//! use muse_model::{Airspace, FlightParams, Instant, NodeId, Request};
//! use muse_optimize::{Options, optimize};
//! use muse_planner::Planner;
//! // A and B, 1 km apart; no ground delay. `early` takes off from A at 0 s and lands at B at
//! // 120 s, just as `late` wants to take off from B: FCFS rejects `late`. Neither can move,
//! // so no schedule serves both; the optimiser keeps FCFS's count.
//! let air = Airspace::line(&[1_000.0]);
//! let planner = Planner::new(&air, FlightParams::default());
//! let r = |id: &str, o, d, t| Request { id: id.into(), origin: NodeId(o), destination: NodeId(d),
//!                                       departure: Instant(t), submitted: Instant(0) };
//! let requests = [r("early", 0, 1, 0), r("late", 1, 0, 120_000)];
//! let out = optimize(&planner, &Closures::none(&air), &requests, &Options::default(), |_| {});
//! assert_eq!((out.report.fcfs.planned, out.report.result.planned, out.report.alone), (1, 1, 2));
//! ```

#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod lns;
mod objective;
mod optimize;
mod order;
mod working;

pub use objective::Objective;
pub use optimize::{Optimized, Options, Report, optimize, optimize_on};
pub use order::Order;
