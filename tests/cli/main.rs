//! The `muse` binary as a user runs it: its commands end to end (`commands`), the day an
//! airspace file carries (`airspace_day`), zones' heights in
//! `muse airspace info` (`airspace_info`), multi-leg days
//! (`swaps`), sweeps sharded and merged (`sweep_shards`), the deployment scripts
//! (`deploy_scripts`), bad inputs refused (`bad_inputs`), outputs that never clobber
//! (`outputs`), batch planning (`optimize`), parameters read from the summary beside the plans (`params_travel`), layered
//! airspace's outputs and their verification (`layers`), airspaces built from pads (`pads`),
//! plans exported as BlueSky scenarios (`export_bluesky`) and as ASTM F3548-21 operational
//! intents (`export_f3548`), every example of docs/reference.md read by MUSE
//! (`reference_examples`), zone files together and zones that do nothing (`zones`), and
//! every relative link of the README and docs/ resolving
//! (`docs_links`).

/// What this area's tests share (tests/support): `muse serve` on a loopback port, scratch
/// folders; [`csv`] compares the CSV files of sweeps.
#[path = "../support"]
mod support {
    pub mod csv;
    mod serve;
    pub use serve::{scratch_dir, start};
}

mod airspace_day;
mod airspace_info;
mod bad_inputs;
mod commands;
mod customers;
mod deploy_scripts;
mod docs_links;
mod export_bluesky;
mod export_f3548;
mod layers;
mod optimize;
mod outputs;
mod pads;
mod params_travel;
mod reference_examples;
mod run;
mod siting;
mod swaps;
mod sweep_shards;
mod zones;
