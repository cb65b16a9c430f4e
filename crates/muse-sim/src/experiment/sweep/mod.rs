//! The paper's experiment as a [`Kind`](crate::experiment::Kind): request counts ×
//! repetitions × scenario variants, every variant on the same days of demand, so that
//! differences between variants are the policy's effect, not sampling noise.
//!
//! - [`Sweep`]: the kind, its variants prepared once (zones resolved, planners built);
//! - [`levers`]: the policies `--vary` compares, one file each, and their variants;
//! - [`RunRecord`]: what one run measured, a row of `sweep.csv`;
//! - `sweep_summary.csv`, the table and the plots (runtime, success rate, air delay).

mod airspaces;
mod kind;
pub mod levers;
mod record;
mod report;
mod variant;

pub use airspaces::Airspaces;
pub use kind::{Sweep, SweepError};
pub use record::{Approach, LayerUse, RunRecord, approach_columns, columns, layer_columns};
pub use report::{SUMMARY_FILE, layer_metrics, summary};
pub use variant::Variant;
