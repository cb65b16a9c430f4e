//! A standby's writes (see `crate::role`): `POST` and `DELETE` are sent on to the leader as
//! they came (path, query, `Authorization`, `Content-Type`, body), and the leader's answer is
//! the answer. The leader checks, plans and stores them once; the standby adds a loopback
//! round trip. Reads are the standby's own.
//!
//! If no service leads (a take-over under way) or the leader does not answer, the answer is
//! `503` `no_leader` with `Retry-After: 1` and, when one is known, the leader's address in
//! `X-Muse-Leader`: the write was not made by this service, and a retry with the same id, at
//! any service, is answered as the first answer was (ids are forever). A forwarded request that
//! reaches a standby (the lead moved meanwhile) is answered the same way, never sent on again.

use std::sync::Arc;
use std::time::Duration;

use axum::extract::{Request, State as AxumState};
use axum::http::{HeaderName, HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::{ApiError, App};
use crate::zones::body::MAX_ZONE_BODY;

/// The header that marks a request a standby sent on.
const FORWARDED: &str = "x-muse-forwarded";

/// The header that names the leader in a `no_leader` answer.
const LEADER: &str = "x-muse-leader";

/// How long a standby waits for the leader's answer.
const WAIT: Duration = Duration::from_secs(30);

/// The client a standby sends writes on with (kept-alive connections to the leader).
pub fn client() -> reqwest::Client {
    reqwest::Client::builder()
        .timeout(WAIT)
        .pool_max_idle_per_host(256)
        .build()
        .unwrap_or_default()
}

/// The `503` of a standby that could not have the leader answer (see the module docs).
fn no_leader(leader: Option<&str>, why: &str) -> Response {
    let mut e = ApiError::new(
        StatusCode::SERVICE_UNAVAILABLE,
        "no_leader",
        format!("{why}; nothing was done: retry with the same id (at any service)"),
    );
    e.retry_after_s = Some(1);
    let mut response = e.into_response();
    if let Some(value) = leader.and_then(|l| HeaderValue::from_str(l).ok()) {
        response
            .headers_mut()
            .insert(HeaderName::from_static(LEADER), value);
    }
    response
}

/// Sends a standby's writes to the leader (see the module docs); everything else, and every
/// request to the leader, goes on to its route.
pub(super) async fn to_leader(
    AxumState(app): AxumState<Arc<App>>,
    request: Request,
    next: Next,
) -> Response {
    let write = matches!(*request.method(), Method::POST | Method::DELETE);
    if !write || !app.state.role.is_standby() {
        return next.run(request).await;
    }
    let Some(leader) = app.state.role.leader() else {
        return no_leader(
            None,
            "this service is a standby and no service leads right now",
        );
    };
    if request.headers().contains_key(FORWARDED) {
        return no_leader(
            Some(&leader),
            "this service is a standby: the lead moved while the request was sent on",
        );
    }
    let (parts, body) = request.into_parts();
    let limit = app.max_body.max(MAX_ZONE_BODY);
    let Ok(body) = axum::body::to_bytes(body, limit).await else {
        return ApiError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "too_large",
            format!("the body is over {limit} bytes, or was not read whole"),
        )
        .closing()
        .into_response();
    };
    let path = parts.uri.path_and_query().map_or("/", |p| p.as_str());
    let mut sent = app
        .forwarder
        .request(parts.method.clone(), format!("{leader}{path}"))
        .header(FORWARDED, "1")
        .body(body);
    for name in [header::AUTHORIZATION, header::CONTENT_TYPE] {
        if let Some(v) = parts.headers.get(&name) {
            sent = sent.header(name, v.clone());
        }
    }
    let answer = match sent.send().await {
        Ok(a) => a,
        Err(e) => {
            return no_leader(
                Some(&leader),
                &format!("the leader at {leader} did not answer ({e})"),
            );
        }
    };
    let status = answer.status();
    let mut headers = axum::http::HeaderMap::new();
    for name in [header::CONTENT_TYPE, header::RETRY_AFTER, header::LOCATION] {
        if let Some(v) = answer.headers().get(&name) {
            headers.insert(name, v.clone());
        }
    }
    match answer.bytes().await {
        Ok(bytes) => (status, headers, bytes).into_response(),
        Err(e) => no_leader(
            Some(&leader),
            &format!("the leader at {leader} broke off its answer ({e})"),
        ),
    }
}
