//! How the zones to announce become known in one run of an announcement-lead sweep, and why
//! such a sweep is refused.

use muse_airspace::closures::ClosureError;
use muse_model::Millis;
use muse_planner::ZoneError;

use crate::demand::DemandError;

/// How the zones to announce become known in one run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LeadCase {
    /// Announced `lead` before the start of the zone's first active window.
    Announced {
        /// Warning between announcement and the first window's start (at least zero).
        lead: Millis,
    },
    /// Known from the start, like a base zone: the reference a long lead tends to.
    Known,
    /// Never announced: the day without the zones (base zones still apply).
    NoZone,
}

impl LeadCase {
    /// `announced`, `known` or `none`, as in the CSV files.
    pub fn kind(self) -> &'static str {
        match self {
            LeadCase::Announced { .. } => "announced",
            LeadCase::Known => "known",
            LeadCase::NoZone => "none",
        }
    }

    /// The lead in minutes, if the zones are announced.
    ///
    /// ```
    /// use muse_model::Millis;
    /// use muse_sim::experiment::lead::LeadCase;
    /// assert_eq!(LeadCase::Announced { lead: Millis::from_secs(90) }.lead_min(), Some(1.5));
    /// assert_eq!(LeadCase::Known.lead_min(), None);
    /// ```
    pub fn lead_min(self) -> Option<f64> {
        match self {
            LeadCase::Announced { lead } => Some(lead.as_secs_f64() / 60.0),
            LeadCase::Known | LeadCase::NoZone => None,
        }
    }

    /// A short label for tables and legends: the lead in minutes, `known` or `none`.
    ///
    /// ```
    /// use muse_model::Millis;
    /// use muse_sim::experiment::lead::LeadCase;
    /// assert_eq!(LeadCase::Announced { lead: Millis::from_mins(15) }.label(), "15");
    /// assert_eq!(LeadCase::NoZone.label(), "none");
    /// ```
    pub fn label(self) -> String {
        self.lead_min()
            .map_or_else(|| self.kind().to_owned(), |m| m.to_string())
    }
}

/// Errors of an announcement-lead sweep.
#[derive(Debug, thiserror::Error)]
pub enum LeadError {
    /// No zone to announce was given.
    #[error("no zone to announce")]
    NothingToAnnounce,
    /// A zone to announce has no active window beginning on the day.
    #[error(
        "zone `{zone}` has no active window starting between {from} and {to}, so it has no first window to announce ahead of"
    )]
    NoWindow {
        /// The zone's id.
        zone: String,
        /// The day's start, RFC 3339.
        from: String,
        /// The day's end, RFC 3339.
        to: String,
    },
    /// A lead is negative.
    #[error("lead {0}: a lead must be >= 0")]
    NegativeLead(Millis),
    /// A zone could not be resolved against the airspace.
    #[error(transparent)]
    Zones(#[from] ClosureError),
    /// Two zones to announce share an id.
    #[error(transparent)]
    Announced(#[from] ZoneError),
    /// Demand could not be generated.
    #[error(transparent)]
    Demand(#[from] DemandError),
}
