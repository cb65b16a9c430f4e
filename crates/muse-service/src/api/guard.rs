//! What every request passes before its route: in open mode the `Host` must be a loopback
//! name (DNS-rebinding protection), and a declared body larger than the route takes is
//! refused at once. And the reader of the JSON bodies the writes take: media type, limit,
//! timeout.

use std::net::{Ipv4Addr, Ipv6Addr};
use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::{FromRequest, Request, State as AxumState};
use axum::http::{HeaderMap, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::http::BodyDeadline;
use crate::metrics::PlanOutcome;

use super::{ApiError, App};
use crate::zones::body::MAX_ZONE_BODY;

/// The largest body the route at `path` takes, bytes.
pub(super) fn body_limit(max_body: usize, path: &str) -> usize {
    if path == "/v1/zones" {
        MAX_ZONE_BODY.max(max_body)
    } else {
        max_body
    }
}

/// Refuses, before any route runs, a request whose `Host` is not a loopback name when the
/// service is open, and one whose declared `Content-Length` exceeds what its route takes.
pub(super) async fn gate(
    AxumState(app): AxumState<Arc<App>>,
    request: Request,
    next: Next,
) -> Response {
    if app.tokens.is_open()
        && let Err(e) = check_host(&request)
    {
        return e.into_response();
    }
    let limit = body_limit(app.max_body, request.uri().path());
    if let Some(declared) = declared_length(request.headers())
        && declared > limit as u64
    {
        if request.method() == Method::POST && request.uri().path() == "/v1/flights" {
            // A flight request all the same, as when the body is read and found too long.
            app.state.metrics.count_plan(PlanOutcome::Invalid);
        }
        return ApiError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "body_too_large",
            format!(
                "the declared body of {declared} bytes is larger than this route takes \
                 ({limit} bytes)"
            ),
        )
        .field("Content-Length")
        .closing()
        .into_response();
    }
    next.run(request).await
}

/// The `Content-Length` a request declares, if it declares one that reads as a number.
fn declared_length(headers: &HeaderMap) -> Option<u64> {
    headers
        .get(header::CONTENT_LENGTH)?
        .to_str()
        .ok()?
        .trim()
        .parse()
        .ok()
}

/// In open mode, the request must name this machine by a loopback name: a web page elsewhere
/// can make a browser send requests to a loopback port (through a name of its own that
/// resolves to 127.0.0.1: DNS rebinding), but not with a loopback `Host`.
fn check_host(request: &Request) -> Result<(), ApiError> {
    let refuse = |what: String| {
        ApiError::new(
            StatusCode::FORBIDDEN,
            "host_not_allowed",
            format!(
                "{what}: an open service (started without --tokens) answers only requests \
                 addressed to a loopback name (localhost, *.localhost, 127.0.0.0/8, [::1], any \
                 port), which protects it from web pages that reach it through a name of \
                 their own (DNS rebinding). Use http://127.0.0.1:PORT/ or http://localhost:PORT/, \
                 or start the service with --tokens FILE to serve other names"
            ),
        )
        .field("Host")
    };
    if let Some(authority) = request.uri().authority()
        && !is_loopback_host(authority.as_str())
    {
        return Err(refuse(format!("the request is addressed to `{authority}`")));
    }
    match request.headers().get(header::HOST) {
        None if request.uri().authority().is_none() => {
            Err(refuse("the request has no Host header".into()))
        }
        None => Ok(()),
        Some(host) => match host.to_str() {
            Ok(host) if is_loopback_host(host) => Ok(()),
            Ok(host) => Err(refuse(format!("Host `{host}` is not a loopback name"))),
            Err(_) => Err(refuse("the Host header is not text".into())),
        },
    }
}

/// Whether `host` (a `Host` header: a name or address, with or without `:port`) names this
/// machine's loopback interface: `localhost`, a name under `.localhost`, an address in
/// 127.0.0.0/8, or `[::1]`.
pub(super) fn is_loopback_host(host: &str) -> bool {
    let port_ok = |port: &str| {
        !port.is_empty() && port.len() <= 5 && port.bytes().all(|b| b.is_ascii_digit())
    };
    if let Some(rest) = host.strip_prefix('[') {
        let Some((address, after)) = rest.split_once(']') else {
            return false;
        };
        let port_fine = after.is_empty() || after.strip_prefix(':').is_some_and(port_ok);
        return port_fine && address.parse::<Ipv6Addr>().is_ok_and(|a| a.is_loopback());
    }
    let name = match host.rsplit_once(':') {
        Some((name, port)) if port_ok(port) => name,
        Some(_) => return false,
        None => host,
    };
    if let Ok(address) = name.parse::<Ipv4Addr>() {
        return address.is_loopback();
    }
    let name = name.to_ascii_lowercase();
    if name == "localhost" {
        return true;
    }
    name.strip_suffix(".localhost").is_some_and(|sub| {
        !sub.is_empty()
            && sub.split('.').all(|label| {
                !label.is_empty()
                    && label
                        .bytes()
                        .all(|b| b.is_ascii_alphanumeric() || b == b'-')
            })
    })
}

/// A JSON body, read after its media type is checked: `Content-Type: application/json`
/// (parameters such as `; charset=utf-8` allowed), or also `application/geo+json` when
/// `GEO`. `Err` holds the answer to give instead: `415` for another media type, `413` over
/// the route's limit, `408` when the body did not arrive before its deadline (the connection
/// is then closed), `400` for a body that could not be read.
///
/// The error is handed to the handler rather than rejected, so that the handler decides
/// which check comes first (the caller's role before the body, for zones).
pub(super) struct JsonBody<const GEO: bool>(pub(super) Result<Bytes, ApiError>);

impl<const GEO: bool> FromRequest<Arc<App>> for JsonBody<GEO> {
    type Rejection = std::convert::Infallible;

    async fn from_request(request: Request, app: &Arc<App>) -> Result<Self, Self::Rejection> {
        if let Err(e) = check_media_type(request.headers(), GEO) {
            return Ok(JsonBody(Err(e)));
        }
        let deadline = request.extensions().get::<BodyDeadline>().copied();
        let read = async {
            Bytes::from_request(request, app).await.map_err(|r| {
                let e = ApiError::new(r.status(), "body", r.body_text());
                if r.status() == StatusCode::PAYLOAD_TOO_LARGE {
                    e.closing()
                } else {
                    e
                }
            })
        };
        let body = match deadline {
            None => read.await,
            Some(d) => tokio::time::timeout_at(d.at, read)
                .await
                .unwrap_or_else(|_| {
                    Err(ApiError::new(
                        StatusCode::REQUEST_TIMEOUT,
                        "body_timeout",
                        format!(
                            "the request body did not arrive within {} s of its headers",
                            d.after.as_secs_f64()
                        ),
                    )
                    .closing())
                }),
        };
        Ok(JsonBody(body))
    }
}

/// `415` unless the body is declared JSON (or GeoJSON when `geo`).
fn check_media_type(headers: &HeaderMap, geo: bool) -> Result<(), ApiError> {
    let expected = if geo {
        "`Content-Type: application/json` or `application/geo+json`"
    } else {
        "`Content-Type: application/json`"
    };
    let unsupported = |what: String| {
        ApiError::new(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "unsupported_media_type",
            format!("{what}: the body must be JSON, sent with {expected}"),
        )
        .field("Content-Type")
    };
    let Some(value) = headers.get(header::CONTENT_TYPE) else {
        return Err(unsupported("no Content-Type header".into()));
    };
    let text = value.to_str().unwrap_or_default();
    let essence = text.split(';').next().unwrap_or_default().trim();
    let json = essence.eq_ignore_ascii_case("application/json")
        || (geo && essence.eq_ignore_ascii_case("application/geo+json"));
    if json {
        Ok(())
    } else {
        Err(unsupported(format!("Content-Type `{text}`")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_hosts() {
        for ok in [
            "localhost",
            "LOCALHOST:8080",
            "viewer.localhost",
            "a.b-c.localhost:1",
            "127.0.0.1",
            "127.0.0.1:8080",
            "127.255.0.9:65535",
            "[::1]",
            "[::1]:8080",
        ] {
            assert!(is_loopback_host(ok), "{ok}");
        }
        for bad in [
            "",
            "example.com",
            "example.com:8080",
            "localhost.example.com",
            "evil-localhost",
            ".localhost",
            "a..localhost",
            "localhost:",
            "localhost:http",
            "localhost:123456",
            "128.0.0.1",
            "10.0.0.1:8080",
            "0.0.0.0",
            "127.1",
            "[::2]",
            "[::1",
            "[::1]x",
            "[::ffff:127.0.0.1]",
            "::1",
        ] {
            assert!(!is_loopback_host(bad), "{bad}");
        }
    }

    #[test]
    fn media_types() {
        let with = |v: &str| {
            let mut h = HeaderMap::new();
            h.insert(header::CONTENT_TYPE, v.parse().unwrap());
            h
        };
        assert!(check_media_type(&with("application/json"), false).is_ok());
        assert!(check_media_type(&with("Application/JSON; charset=utf-8"), false).is_ok());
        assert!(check_media_type(&with("application/geo+json"), true).is_ok());
        assert!(check_media_type(&with("application/geo+json"), false).is_err());
        assert!(check_media_type(&with("text/plain"), true).is_err());
        assert!(check_media_type(&with("application/x-www-form-urlencoded"), false).is_err());
        assert!(check_media_type(&with("multipart/form-data; boundary=x"), false).is_err());
        assert!(check_media_type(&with("application/jsonx"), false).is_err());
        assert!(check_media_type(&HeaderMap::new(), false).is_err());
    }
}
