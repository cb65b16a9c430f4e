//! The `muse` binary as a user runs it: its commands end to end (`commands`), multi-leg days
//! (`swaps`), sweeps sharded and merged (`sweep_shards`), the deployment scripts
//! (`deploy_scripts`), bad inputs refused (`bad_inputs`), outputs that never clobber
//! (`outputs`), parameters read from the summary beside the plans (`params_travel`) and every
//! example of docs/reference.md read by MUSE (`reference_examples`).

#[path = "../support/mod.rs"]
mod support;

mod bad_inputs;
mod commands;
mod deploy_scripts;
mod outputs;
mod params_travel;
mod reference_examples;
mod swaps;
mod sweep_shards;
