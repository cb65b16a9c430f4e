//! Why a siting problem cannot be set up or evaluated.

use muse_airspace::builder::BuildError;
use muse_airspace::closures::ClosureError;
use muse_airspace::plane::PlaneError;
use muse_sim::demand::DemandError;

/// Errors of siting.
#[derive(Debug, thiserror::Error)]
pub enum SitingError {
    /// No candidate pads to choose from.
    #[error("there are no candidate pads to choose from")]
    NoCandidates,
    /// More pads asked for than there are candidates.
    #[error("cannot add {wanted} pads: there are {available} candidates")]
    TooFewCandidates {
        /// Pads asked for.
        wanted: usize,
        /// Candidates available.
        available: usize,
    },
    /// A candidate has the id of an existing pad or of an earlier candidate.
    #[error("candidate pad `{0}` has the id of an existing pad or of another candidate")]
    DuplicateId(String),
    /// A candidate stands where an existing pad (or another candidate) is.
    #[error("candidate pad `{id}` stands where pad `{other}` is: it would add nothing")]
    SamePosition {
        /// The candidate.
        id: String,
        /// The pad already there.
        other: String,
    },
    /// A first round given to the greedy is not whole.
    #[error("the first round given is not whole: {0}")]
    FirstRound(String),
    /// No seeded day to plan.
    #[error("siting needs at least one seeded day of demand")]
    NoDays,
    /// A zone is announced or withdrawn during the day: siting plans days whose zones are known
    /// from the start.
    #[error(
        "zone `{0}` is announced or withdrawn during the day: siting plans days whose zones \
         are known from the start; give it without `announced` and `withdrawn`"
    )]
    ZoneDuringDay(String),
    /// The demand could not be drawn.
    #[error(transparent)]
    Demand(#[from] DemandError),
    /// A pad set gives no airspace.
    #[error("building the airspace: {0}")]
    Build(#[from] BuildError),
    /// A position the airspace's plane cannot project.
    #[error(transparent)]
    Plane(#[from] PlaneError),
    /// A zone could not be resolved on a rebuilt airspace.
    #[error(transparent)]
    Zones(#[from] ClosureError),
}
