//! The HTTP API (JSON, versioned under `/v1`): routes, input checks and answers.
//!
//! | method and path | what |
//! |---|---|
//! | `POST /v1/flights` | plan a request: `201` planned, `200` rejected, `409` id taken |
//! | `GET /v1/flights` | the caller's flights (every flight for an authority), filtered |
//! | `GET /v1/flights/{id}` | one flight |
//! | `DELETE /v1/flights/{id}` | cancel before take-off (`409` after) |
//! | `GET /v1/airspace` | the airspace, SPEC §2 GeoJSON |
//! | `GET /v1/zones` | the no-fly zones, ED-318 GeoJSON |
//! | `GET /v1/openapi.json` | this API as `OpenAPI` 3.1 |
//! | `GET /healthz` | liveness and a few numbers |
//! | `GET /metrics` | Prometheus metrics |
//!
//! Every error is `{"error": {"status", "code", "message", "field"}}`; `field` names the
//! offending input field when there is one.
//!
//! The handlers are grouped by concept: `error` (the error answer and JSON bodies),
//! `caller` (who calls: token and rate limit), `flights` (the flight routes and their
//! input checks) and `info` (airspace, zones, the API description, health and metrics).

mod caller;
mod error;
mod flights;
mod info;

use std::sync::Arc;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::response::IntoResponse;
use axum::routing::get;
use tokio::sync::mpsc;
use tower_http::catch_panic::CatchPanicLayer;

use crate::auth::{RateLimiter, Tokens};
use crate::engine::Command;
use crate::state::State;

pub use caller::Authed;
pub use error::ApiError;
use flights::{cancel, create, list, read};
use info::{airspace, healthz, metrics, openapi, zones};

/// The `OpenAPI` description of this API.
pub const OPENAPI: &str = include_str!("openapi.json");

/// Every route, as `(method, path)`: the router serves exactly these (checked against the
/// `OpenAPI` document by a test).
pub const ROUTES: &[(&str, &str)] = &[
    ("post", "/v1/flights"),
    ("get", "/v1/flights"),
    ("get", "/v1/flights/{id}"),
    ("delete", "/v1/flights/{id}"),
    ("get", "/v1/airspace"),
    ("get", "/v1/zones"),
    ("get", "/v1/openapi.json"),
    ("get", "/healthz"),
    ("get", "/metrics"),
];

/// Longest client id accepted.
pub const MAX_ID_LEN: usize = 128;

/// What the handlers share.
#[derive(Debug)]
pub struct App {
    /// The state shared with the planner task.
    pub state: Arc<State>,
    /// Who may call.
    pub tokens: Tokens,
    /// Requests per token.
    pub limiter: RateLimiter,
    /// The planner task's queue.
    pub commands: mpsc::Sender<Command>,
    /// `GET /v1/airspace`, rendered once.
    pub airspace_geojson: String,
    /// `GET /v1/zones`, rendered once.
    pub zones_geojson: String,
    /// Largest request body, bytes.
    pub max_body: usize,
}

/// The router of the API over `app`.
pub fn router(app: Arc<App>) -> Router {
    let max_body = app.max_body;
    Router::new()
        .route("/v1/flights", get(list).post(create))
        .route("/v1/flights/{id}", get(read).delete(cancel))
        .route("/v1/airspace", get(airspace))
        .route("/v1/zones", get(zones))
        .route("/v1/openapi.json", get(openapi))
        .route("/healthz", get(healthz))
        .route("/metrics", get(metrics))
        .fallback(not_found)
        .layer(DefaultBodyLimit::max(max_body))
        .layer(CatchPanicLayer::custom(|_| {
            ApiError::new(
                StatusCode::INTERNAL_SERVER_ERROR,
                "internal",
                "internal error while handling the request; the schedule is unchanged",
            )
            .into_response()
        }))
        .with_state(app)
}

async fn not_found() -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        "not_found",
        "no such route; see /v1/openapi.json",
    )
}
