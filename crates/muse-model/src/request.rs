//! Delivery requests.

use crate::ids::NodeId;
use crate::time::Instant;

/// A delivery request: fly from `origin` to `destination`, taking off no earlier than
/// `departure`. Origin and destination are distinct stations (checked by the readers).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Request {
    /// Unique id as in files, e.g. `r000042`.
    pub id: String,
    /// Origin station.
    pub origin: NodeId,
    /// Destination station.
    pub destination: NodeId,
    /// Requested departure (earliest take-off).
    pub departure: Instant,
    /// When the request reaches the planner (SPEC §5): a booking made ahead of departure.
    /// Never later than `departure`; equal to it when the file gives no `submitted` column
    /// (the paper: every request planned at its departure).
    pub submitted: Instant,
}

/// Sorts requests into planning order, `(submitted, id)` (SPEC §5: first come, first served;
/// without bookings ahead, `submitted` is the departure and this is the paper's
/// `(departure, id)`).
///
/// ```
/// use muse_model::{request::sort_for_planning, Instant, NodeId, Request};
/// let r = |id: &str, t, s| Request {
///     id: id.into(), origin: NodeId(0), destination: NodeId(1), departure: Instant(t), submitted: Instant(s),
/// };
/// let mut v = vec![r("b", 5, 5), r("a", 5, 5), r("c", 1, 1), r("d", 9, 0)];
/// sort_for_planning(&mut v);
/// assert_eq!(v.iter().map(|r| r.id.as_str()).collect::<Vec<_>>(), ["d", "c", "a", "b"]);
/// ```
pub fn sort_for_planning(requests: &mut [Request]) {
    requests.sort_by(|a, b| a.submitted.cmp(&b.submitted).then_with(|| a.id.cmp(&b.id)));
}
