//! MUSE export: planned flights written in the languages of other tools of the field.
//!
//! - [`bluesky`]: a day of flights as a BlueSky scenario (`.scn`), to fly MUSE's plans under
//!   BlueSky's drone dynamics and conflict detection;
//! - [`f3548`]: each flight as an ASTM F3548-21 operational intent, the form in which a UAS
//!   service supplier (USS) shares flights.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

pub mod bluesky;
pub mod f3548;
