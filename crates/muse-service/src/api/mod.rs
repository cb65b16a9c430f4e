//! The HTTP API (JSON, versioned under `/v1`): routes, input checks and answers.
//!
//! | method and path | what |
//! |---|---|
//! | `POST /v1/flights` | plan a request: `201` planned, `200` rejected, `409` id taken |
//! | `GET /v1/flights` | the caller's flights (every flight for an authority), filtered |
//! | `GET /v1/flights/{id}` | one flight |
//! | `DELETE /v1/flights/{id}` | cancel before take-off (`409` after) |
//! | `GET /v1/airspace` | the airspace, docs/reference.md#airspace GeoJSON |
//! | `GET /v1/zones` | the no-fly zones, ED-318 GeoJSON, announced ones included |
//! | `POST /v1/zones` | announce a zone now (authority): `201` with every flight it changed |
//! | `DELETE /v1/zones/{id}` | withdraw an announced zone (authority); replans nothing |
//! | `GET /v1/closures` | the nodes and corridors each zone closes while active |
//! | `GET /v1/events` | the caller's flights' changes, server-sent events, resumable |
//! | `GET /v1/openapi.json` | this API as `OpenAPI` 3.1 |
//! | `GET /healthz` | liveness and a few numbers |
//! | `GET /metrics` | Prometheus metrics |
//!
//! Every error is `{"error": {"status", "code", "message", "field"}}`; `field` names the
//! offending input field (or header) when there is one.
//!
//! Before any route: in open mode (no tokens) a request whose `Host` is not a loopback name
//! (`localhost`, `*.localhost`, 127.0.0.0/8, `[::1]`) is refused `403` (`host_not_allowed`:
//! DNS-rebinding protection; no route is exempt), and a declared `Content-Length` above what
//! the route takes is refused `413` at once, closing the connection. The writes with a body
//! (`POST /v1/flights`, `POST /v1/zones`) need `Content-Type: application/json` (zones also
//! take `application/geo+json`), else `415` (`unsupported_media_type`); a body that has not
//! arrived within the body timeout is `408` (see [`crate::http`]).
//!
//! The handlers are grouped by concept: `error` (the error answer and JSON bodies),
//! `caller` (who calls: token and rate limit), `flights` (the flight routes and their
//! input checks), `zones` (the zone routes: announce, withdraw, list, closures;
//! docs/reference.md#zones-announced-during-the-day; the zones themselves, reading a body and
//! deciding, are in [`crate::zones`]), [`events`] (the event stream) and `info` (airspace, the API
//! description, health and metrics).
//!
//! Zones: `POST /v1/zones` takes one ED-318 feature (or a `FeatureCollection` of one)
//! without `announced`: the service announces it at its clock's now. `422` names the field
//! at fault (a body giving `announced` is refused on `properties.announced`), `409` means
//! the id is taken (by a zone known from the start or announced before, withdrawn or not),
//! `403` that the caller is not the authority. `DELETE /v1/zones/{id}` answers `200` with
//! the zone and its withdrawal instant, again `200` with the same for a zone withdrawn
//! before (idempotent), `409` for a zone known from the start and `404` for an unknown id.

mod caller;
mod error;
mod events;
mod flights;
mod forward;
mod guard;
mod info;
mod zones;

use std::sync::Arc;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::response::IntoResponse;
use axum::routing::{delete, get};
use tokio::sync::{mpsc, watch};
use tower_http::catch_panic::CatchPanicLayer;

use crate::auth::{RateLimiter, Tokens};
use crate::engine::Command;
use crate::state::State;

pub use caller::Authed;
pub use error::ApiError;
use flights::{cancel, create, list, read};
use info::{airspace, healthz, metrics, openapi, page};

/// The `OpenAPI` description of this API.
pub const OPENAPI: &str = include_str!("openapi.json");

/// Every route, as `(method, path)`: the router serves exactly these (checked against the
/// `OpenAPI` document by a test).
pub const ROUTES: &[(&str, &str)] = &[
    ("get", "/"),
    ("post", "/v1/flights"),
    ("get", "/v1/flights"),
    ("get", "/v1/flights/{id}"),
    ("delete", "/v1/flights/{id}"),
    ("get", "/v1/airspace"),
    ("get", "/v1/zones"),
    ("post", "/v1/zones"),
    ("delete", "/v1/zones/{id}"),
    ("get", "/v1/closures"),
    ("get", "/v1/events"),
    ("get", "/v1/openapi.json"),
    ("get", "/healthz"),
    ("get", "/metrics"),
];

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
    /// `GET /`: the live viewer page, if the service was given one.
    pub page: Option<String>,
    /// Largest request body, bytes (zone bodies: [`MAX_ZONE_BODY`](crate::zones::body::MAX_ZONE_BODY)).
    pub max_body: usize,
    /// Set when the service stops: event streams end then.
    pub stopping: watch::Sender<bool>,
    /// The client a standby sends writes to the leader with.
    pub forwarder: reqwest::Client,
}

/// The client a standby sends writes to the leader with (for [`App::forwarder`]).
pub fn forwarder() -> reqwest::Client {
    forward::client()
}

/// The router of the API over `app`.
pub fn router(app: Arc<App>) -> Router {
    let max_body = app.max_body;
    Router::new()
        .route("/", get(page))
        .route("/v1/flights", get(list).post(create))
        .route("/v1/flights/{id}", get(read).delete(cancel))
        .route("/v1/airspace", get(airspace))
        .route(
            "/v1/zones",
            get(zones::list)
                .post(zones::announce)
                .layer(DefaultBodyLimit::max(guard::body_limit(
                    max_body,
                    "/v1/zones",
                ))),
        )
        .route("/v1/zones/{id}", delete(zones::withdraw))
        .route("/v1/closures", get(zones::closures))
        .route("/v1/events", get(events::stream))
        .route("/v1/openapi.json", get(openapi))
        .route("/healthz", get(healthz))
        .route("/metrics", get(metrics))
        .fallback(not_found)
        .layer(axum::middleware::from_fn_with_state(
            Arc::clone(&app),
            forward::to_leader,
        ))
        .layer(axum::middleware::from_fn_with_state(
            Arc::clone(&app),
            until_ready,
        ))
        .layer(DefaultBodyLimit::max(max_body))
        .layer(axum::middleware::from_fn_with_state(
            Arc::clone(&app),
            guard::gate,
        ))
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

/// While the store is being loaded, every route but `/healthz`, `/metrics` and the API
/// description answers `503` (`starting`, retry in a second): nothing is decided on a
/// schedule that is not whole yet.
async fn until_ready(
    axum::extract::State(app): axum::extract::State<Arc<App>>,
    request: axum::extract::Request,
    next: axum::middleware::Next,
) -> axum::response::Response {
    let always = matches!(
        request.uri().path(),
        "/healthz" | "/metrics" | "/v1/openapi.json"
    );
    if always || app.state.phase.is_ready() {
        return next.run(request).await;
    }
    let p = app.state.phase.progress();
    let mut e = ApiError::new(
        StatusCode::SERVICE_UNAVAILABLE,
        "starting",
        format!(
            "the service is starting: {} of {} flights still ahead loaded{}; see /healthz",
            p.flights_loaded,
            p.flights_to_load,
            if p.imported_records > 0 {
                format!(
                    ", {} records of an earlier version's log converted",
                    p.imported_records
                )
            } else {
                String::new()
            }
        ),
    );
    e.retry_after_s = Some(1);
    e.into_response()
}

/// Runs `read` of the store off the async workers (the store's reads block: a database
/// round trip), mapping a failed read to its `500`.
pub(super) async fn read_store<T: Send + 'static>(
    app: &Arc<App>,
    read: impl FnOnce(&App) -> Result<T, crate::store::StoreError> + Send + 'static,
) -> Result<T, ApiError> {
    let app = Arc::clone(app);
    tokio::task::spawn_blocking(move || read(&app))
        .await
        .map_err(|_| {
            ApiError::new(
                StatusCode::INTERNAL_SERVER_ERROR,
                "internal",
                "the read of the store failed",
            )
        })?
        .map_err(|e| ApiError::store(&e))
}

async fn not_found() -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        "not_found",
        "no such route; see /v1/openapi.json",
    )
}
