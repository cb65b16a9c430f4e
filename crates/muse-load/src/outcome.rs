//! What became of one request: planned, rejected (with the reason) or an error of some kind,
//! read from the HTTP status and the answer's JSON.

use std::borrow::Cow;
use std::fmt;

use muse_model::RejectReason;
use serde::Deserialize;

/// Why a request did not get a planning answer.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ErrorKind {
    /// No connection could be made.
    Connect,
    /// No answer within the timeout.
    Timeout,
    /// Another transport failure (connection reset, malformed HTTP, …).
    Transport,
    /// An HTTP error answer: status and the API's error `code` (`?` when the body has none).
    Http {
        /// The status code (4xx or 5xx).
        status: u16,
        /// The API error code, e.g. `rate_limited`, `conflict`, `invalid_value`.
        code: String,
    },
    /// A success status whose body is not a planning answer.
    BadAnswer,
}

impl fmt::Display for ErrorKind {
    /// The key used in reports: `transport: connect`, `transport: timeout`, `transport:
    /// other`, `429 rate_limited`, `500 internal`, `bad answer`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::Connect => f.write_str("transport: connect"),
            ErrorKind::Timeout => f.write_str("transport: timeout"),
            ErrorKind::Transport => f.write_str("transport: other"),
            ErrorKind::Http { status, code } => write!(f, "{status} {code}"),
            ErrorKind::BadAnswer => f.write_str("bad answer"),
        }
    }
}

impl ErrorKind {
    /// Whether the request got no HTTP answer at all.
    pub fn is_transport(&self) -> bool {
        matches!(
            self,
            ErrorKind::Connect | ErrorKind::Timeout | ErrorKind::Transport
        )
    }
}

/// The outcome of one `POST /v1/flights`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Planned (`201`, `status: planned`).
    Planned,
    /// Rejected by the planner (`200`, `status: rejected`), for this reason.
    Rejected(RejectReason),
    /// No planning answer.
    Error(ErrorKind),
}

#[derive(Deserialize)]
struct Answer<'a> {
    #[serde(borrow)]
    status: Cow<'a, str>,
    #[serde(borrow)]
    reason: Option<Cow<'a, str>>,
}

#[derive(Deserialize)]
struct ErrorBody<'a> {
    #[serde(borrow)]
    error: ErrorCode<'a>,
}

#[derive(Deserialize)]
struct ErrorCode<'a> {
    #[serde(borrow)]
    code: Cow<'a, str>,
}

/// The outcome of an HTTP answer with `status` and `body`.
///
/// ```
/// use muse_load::outcome::{ErrorKind, Outcome, classify};
/// use muse_model::RejectReason;
/// assert_eq!(classify(201, br#"{"request":"a","status":"planned","reason":null}"#), Outcome::Planned);
/// assert_eq!(
///     classify(200, br#"{"status":"rejected","reason":"out_of_range"}"#),
///     Outcome::Rejected(RejectReason::OutOfRange)
/// );
/// assert_eq!(
///     classify(429, br#"{"error":{"status":429,"code":"rate_limited","message":"","field":null}}"#),
///     Outcome::Error(ErrorKind::Http { status: 429, code: "rate_limited".into() })
/// );
/// ```
pub fn classify(status: u16, body: &[u8]) -> Outcome {
    if (200..300).contains(&status) {
        let Ok(answer) = serde_json::from_slice::<Answer<'_>>(body) else {
            return Outcome::Error(ErrorKind::BadAnswer);
        };
        let reason = answer.reason.as_deref().and_then(RejectReason::parse);
        return match (answer.status.as_ref(), reason) {
            ("planned", _) => Outcome::Planned,
            ("rejected", Some(reason)) => Outcome::Rejected(reason),
            _ => Outcome::Error(ErrorKind::BadAnswer),
        };
    }
    let code = serde_json::from_slice::<ErrorBody<'_>>(body)
        .map_or_else(|_| "?".to_owned(), |b| b.error.code.into_owned());
    Outcome::Error(ErrorKind::Http { status, code })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers() {
        assert_eq!(
            classify(
                200,
                br#"{"status":"rejected","reason":"departure_in_past","path":null}"#
            ),
            Outcome::Rejected(RejectReason::DepartureInPast)
        );
        assert_eq!(
            classify(200, br#"{"status":"rejected","reason":"bored"}"#),
            Outcome::Error(ErrorKind::BadAnswer)
        );
        assert_eq!(
            classify(201, b"<html>"),
            Outcome::Error(ErrorKind::BadAnswer)
        );
        assert_eq!(
            classify(
                409,
                br#"{"error":{"status":409,"code":"conflict","message":"x","field":"id"}}"#
            ),
            Outcome::Error(ErrorKind::Http {
                status: 409,
                code: "conflict".into()
            })
        );
        assert_eq!(
            classify(502, b"Bad Gateway"),
            Outcome::Error(ErrorKind::Http {
                status: 502,
                code: "?".into()
            })
        );
    }

    #[test]
    fn report_keys() {
        let http = ErrorKind::Http {
            status: 500,
            code: "internal".into(),
        };
        assert_eq!(http.to_string(), "500 internal");
        assert!(!http.is_transport());
        assert_eq!(ErrorKind::Connect.to_string(), "transport: connect");
        assert!(ErrorKind::Timeout.is_transport());
    }
}
