//! Delivery requests.

use crate::ids::NodeId;
use crate::time::Instant;

/// Longest request id accepted, in a requests file as by the service's API (also the longest
/// id of a zone announced to the service).
pub const MAX_ID_LEN: usize = 128;

/// The rule [`valid_id`] checks, for messages and documentation.
pub const ID_RULE: &str = "1 to 128 characters among the ASCII letters and digits and `._~:-`";

/// Whether `b` may appear in an id: an ASCII letter or digit, or one of `._~:-` (the
/// characters a URL path segment carries as they are; `#` is left for the service's store).
pub fn is_id_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b"._~:-".contains(&b)
}

/// Whether `id` is a valid request id ([`ID_RULE`]): the same rule for the requests CSV and
/// the service's `POST /v1/flights`, so that any request of a file can also be sent to the
/// service (its id names the flight in `/v1/flights/{id}`).
///
/// ```
/// use muse_model::request::valid_id;
/// assert!(valid_id("r-000042") && valid_id("a.b~c:d_e"));
/// assert!(!valid_id("") && !valid_id("a b") && !valid_id("a#2") && !valid_id("a,b"));
/// assert!(!valid_id("caf\u{e9}") && !valid_id("\"q\"") && !valid_id(&"x".repeat(129)));
/// ```
pub fn valid_id(id: &str) -> bool {
    !id.is_empty() && id.len() <= MAX_ID_LEN && id.bytes().all(is_id_byte)
}

/// The instants MUSE plans requests at: a request departs, and is submitted, from
/// 1000-01-01T00:00:00Z up to (not including) 9000-01-01T00:00:00Z, the years 1000 to 8999 in
/// UTC ([`PLANNED_RULE`] in words). Timestamps of other years are read, but a request of
/// them is not planned: the zones' calendars are worked out a day and a trip either side of
/// the requests, and these years leave room for that.
///
/// ```
/// use muse_model::Instant;
/// use muse_model::request::PLANNED;
/// let t = |s: &str| Instant::parse_rfc3339(s).unwrap();
/// assert_eq!(PLANNED, t("1000-01-01T00:00:00Z")..t("9000-01-01T00:00:00Z"));
/// assert!(PLANNED.contains(&t("8999-12-31T23:59:59.999Z")));
/// assert!(!PLANNED.contains(&t("9999-12-31T23:59:59Z")));
/// ```
pub const PLANNED: std::ops::Range<Instant> =
    Instant(-30_610_224_000_000)..Instant(221_845_392_000_000);

/// The years [`PLANNED`] holds, for messages and documentation.
pub const PLANNED_RULE: &str = "from 1000-01-01T00:00:00Z up to 9000-01-01T00:00:00Z (the years \
                                1000 to 8999, UTC)";

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
    /// When the request reaches the planner (docs/reference.md#requests): a booking made ahead of
    /// departure. Never later than `departure`; equal to it when the file gives no `submitted`
    /// column (the paper: every request planned at its departure).
    pub submitted: Instant,
}

/// Sorts requests into planning order, `(submitted, id)` (docs/reference.md#requests: first come,
/// first served; without bookings ahead, `submitted` is the departure and this is the paper's
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn id_rule_states_the_length() {
        assert!(ID_RULE.starts_with(&format!("1 to {MAX_ID_LEN} characters")));
        assert!(valid_id(&"x".repeat(MAX_ID_LEN)));
        assert!(!valid_id(&"x".repeat(MAX_ID_LEN + 1)));
    }
}
