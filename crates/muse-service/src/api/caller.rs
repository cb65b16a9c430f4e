//! Who calls a `/v1` route: the bearer token and the rate limit.

use std::sync::Arc;

use axum::extract::FromRequestParts;
use axum::http::{StatusCode, header, request::Parts};

use crate::auth::Caller;

use super::{ApiError, App};

/// The authenticated, rate-limited caller of a `/v1` route.
pub struct Authed(pub Caller);

impl FromRequestParts<Arc<App>> for Authed {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, app: &Arc<App>) -> Result<Self, ApiError> {
        let header = parts
            .headers
            .get(header::AUTHORIZATION)
            .and_then(|v| v.to_str().ok());
        let Some((key, caller)) = app.tokens.caller(header) else {
            app.state.metrics.count_unauthorized();
            return Err(ApiError::new(
                StatusCode::UNAUTHORIZED,
                "unauthorized",
                if header.is_some() {
                    "unknown token"
                } else {
                    "an `Authorization: Bearer <token>` header is required"
                },
            ));
        };
        if let Err(wait) = app.limiter.check(&key) {
            app.state.metrics.count_rate_limited();
            let mut e = ApiError::new(
                StatusCode::TOO_MANY_REQUESTS,
                "rate_limited",
                "too many requests for this token; retry later",
            );
            e.retry_after_s = Some(wait.ceil().max(1.0) as u64);
            return Err(e);
        }
        Ok(Authed(caller))
    }
}
