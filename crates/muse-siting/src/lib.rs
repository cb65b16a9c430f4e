//! MUSE siting (docs/reference.md#airspace-from-pads): which candidate pads to add to an airspace
//! so that the most requests are delivered, judged by planning whole days exactly on the rebuilt
//! airspace.
//!
//! Coverage models (maximum coverage, k-means of demand) place pads where customers are and
//! never check that the corridors can carry the traffic. Here every candidate set is judged by
//! what it delivers: the airspace is rebuilt from the pads by the rule of
//! docs/reference.md#airspace-from-pads, the same seeded days of demand between customers are
//! mapped to their nearest pads in reach and planned exactly (docs/reference.md#planning, and
//! #multi-leg-trips with battery swaps), and the planned requests are counted.
//!
//! - [`problem`]: the prepared problem ([`Siting`]): pads, candidates, customers, the seeded
//!   days, and each customer's pads in reach, computed once;
//! - [`evaluate`](mod@evaluate): one pad set's deliveries, day by day ([`Evaluation`]);
//! - [`greedy`]: lazy greedy by exact simulation, pick by pick with the marginal gain and its
//!   confidence interval;
//! - [`baselines`]: the coverage models it is compared with: maximum coverage and k-means;
//! - [`shard`]: the greedy's first round cut into shards, each a file (`shard.json`), and the
//!   files merged back.
//!
//! ```
//! use muse_siting::{Siting, SitingInput};
//! # let input = muse_siting::problem::example_input();
//! let siting = Siting::prepare(input).unwrap();
//! let none = siting.evaluate(&[]).unwrap();
//! let run = muse_siting::greedy::lazy_greedy(&siting, 1, |_| {}).unwrap();
//! // The first pick adds what its evaluation says, over the same days.
//! assert_eq!(run.base, none);
//! assert!(run.picks[0].after.mean_delivered() >= none.mean_delivered());
//! ```
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod baselines;
pub mod error;
pub mod evaluate;
pub mod greedy;
pub mod problem;
pub mod shard;

pub use error::SitingError;
pub use evaluate::Evaluation;
pub use problem::{Siting, SitingInput};
