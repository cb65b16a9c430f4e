//! The regulator's question (issue 9): how much warning before a temporary no-fly zone
//! becomes active keeps the cost of announcing it low?
//!
//! An announcement-lead sweep plans the same demand once per lead `L`: each zone to announce
//! is announced (docs/reference.md#zones-announced-during-the-day) at the start of its first active
//! window on the day minus `L`, and the day is [replayed](crate::replay). Every lead plans the same
//! days of the grid, so the differences between leads are the lead's effect, not sampling noise.
//! Two reference cases run on the same seeds: the zones known from the start ([`LeadCase::Known`],
//! the limit of a long lead) and, optionally, never announced at all ([`LeadCase::NoZone`]). Zones
//! known from the start (`base` zones) apply in every case.
//!
//! - [`Lead`]: the kind, with its [`LeadSpec`] (leads, zones, the day);
//! - [`LeadWorld`]: the zones resolved once, and one planned day per case;
//! - [`LeadRecord`]: what one run measured (success rate, affected, replanned, diverted,
//!   cancelled, contingency, extra delay, …), a row of `announce_lead.csv`;
//! - `announce_lead_summary.csv` ([`summary`]), the table and three plots against the lead.

mod case;
mod kind;
mod plots;
mod record;
mod report;
mod world;

pub use case::{LeadCase, LeadError};
pub use kind::{Lead, LeadSpec};
pub use record::{LeadRecord, columns};
pub use report::{SUMMARY_FILE, summary};
pub use world::{LeadWorld, ScenarioDay, first_window_start};

#[cfg(test)]
mod tests;
