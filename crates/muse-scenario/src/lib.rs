//! muse-scenario
