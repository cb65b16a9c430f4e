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

use std::sync::Arc;
use std::time::Instant as WallInstant;

use axum::Router;
use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, QueryRejection};
use axum::extract::{DefaultBodyLimit, FromRequestParts, Path, Query, State as AxumState};
use axum::http::{HeaderValue, StatusCode, header, request::Parts};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use muse_model::{Instant, NodeId, NodeKind, Request};
use serde::{Deserialize, Serialize};
use tokio::sync::{mpsc, oneshot};
use tower_http::catch_panic::CatchPanicLayer;

use crate::auth::{Caller, RateLimiter, Tokens};
use crate::engine::{CancelReply, Command, PlanReply};
use crate::flights::{FlightEntry, ListQuery, Status};
use crate::metrics::PlanOutcome;
use crate::state::State;

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

/// An error answer.
#[derive(Debug)]
pub struct ApiError {
    status: StatusCode,
    code: &'static str,
    message: String,
    field: Option<String>,
    retry_after_s: Option<u64>,
}

#[derive(Serialize)]
struct ErrorBody<'a> {
    error: ErrorInner<'a>,
}

#[derive(Serialize)]
struct ErrorInner<'a> {
    status: u16,
    code: &'a str,
    message: &'a str,
    field: Option<&'a str>,
}

impl ApiError {
    fn new(status: StatusCode, code: &'static str, message: impl Into<String>) -> Self {
        ApiError {
            status,
            code,
            message: message.into(),
            field: None,
            retry_after_s: None,
        }
    }

    fn field(mut self, field: impl Into<String>) -> Self {
        self.field = Some(field.into());
        self
    }

    fn invalid(field: &str, message: impl Into<String>) -> Self {
        ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, "invalid_value", message).field(field)
    }

    fn not_found(what: &str) -> Self {
        ApiError::new(StatusCode::NOT_FOUND, "not_found", format!("no {what}"))
    }

    fn unavailable() -> Self {
        ApiError::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "unavailable",
            "the planner is not running (the service is stopping); retry with the same id",
        )
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let body = ErrorBody {
            error: ErrorInner {
                status: self.status.as_u16(),
                code: self.code,
                message: &self.message,
                field: self.field.as_deref(),
            },
        };
        let mut response = json(self.status, &body);
        if let Some(s) = self.retry_after_s {
            response
                .headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(s));
        }
        response
    }
}

/// A JSON answer.
fn json<T: Serialize>(status: StatusCode, body: &T) -> Response {
    // Our bodies are plain data: serialising cannot fail.
    let bytes = serde_json::to_vec(body).unwrap_or_default();
    (
        status,
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/json"),
        )],
        bytes,
    )
        .into_response()
}

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

/// The body of `POST /v1/flights`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct NewFlight {
    id: String,
    origin: String,
    destination: String,
    departure: String,
}

/// Parses a JSON body, naming the field at fault.
fn parse_body<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Result<T, ApiError> {
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let mut err = ApiError::new(
            StatusCode::BAD_REQUEST,
            "malformed",
            format!("the body is not a valid request: {}", e.inner()),
        );
        if path != "." {
            err = err.field(path);
        }
        err
    })?;
    de.end().map_err(|e| {
        ApiError::new(
            StatusCode::BAD_REQUEST,
            "malformed",
            format!("the body is not a valid request: {e}"),
        )
    })?;
    Ok(value)
}

/// Checks a new flight's fields against the airspace and the clock.
fn validate(app: &App, body: NewFlight) -> Result<Request, ApiError> {
    let world = &app.state.world;
    let ok_id = !body.id.is_empty()
        && body.id.len() <= MAX_ID_LEN
        && body
            .id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"._~:-".contains(&b));
    if !ok_id {
        return Err(ApiError::invalid(
            "id",
            format!(
                "must be 1 to {MAX_ID_LEN} characters of letters, digits and `._~:-`, got {:?}",
                body.id
            ),
        ));
    }
    let station = |field: &str, id: &str| -> Result<NodeId, ApiError> {
        let n = world
            .airspace
            .node_id(id)
            .ok_or_else(|| ApiError::invalid(field, format!("unknown station `{id}`")))?;
        if world.airspace.node(n).kind != NodeKind::Station {
            return Err(ApiError::invalid(
                field,
                format!("`{id}` is a waypoint, not a station"),
            ));
        }
        Ok(n)
    };
    let origin = station("origin", &body.origin)?;
    let destination = station("destination", &body.destination)?;
    if origin == destination {
        return Err(ApiError::invalid(
            "destination",
            "must differ from the origin",
        ));
    }
    let departure = Instant::parse_rfc3339(&body.departure)
        .map_err(|e| ApiError::invalid("departure", e.to_string()))?;
    let now = app.state.clock.now();
    if departure - now > world.booking_horizon {
        return Err(ApiError::invalid(
            "departure",
            format!(
                "more than {} days ahead of now ({}): bookings open {} days ahead",
                world.booking_horizon.0 / 86_400_000,
                now.to_rfc3339(world.offset),
                world.booking_horizon.0 / 86_400_000
            ),
        ));
    }
    if departure + world.params.max_ground_delay + world.params.max_flight > world.calendar_end {
        return Err(ApiError::invalid(
            "departure",
            "beyond the zone calendar this service resolved at start; restart it to plan further ahead",
        ));
    }
    Ok(Request {
        id: body.id,
        origin,
        destination,
        departure,
    })
}

fn flight_json(app: &App, status: StatusCode, entry: &FlightEntry) -> Response {
    let w = &app.state.world;
    json(status, &entry.view(&w.airspace, w.offset))
}

/// The status code of an answer about a new request: 201 when a plan was made.
fn answer_status(entry: &FlightEntry) -> StatusCode {
    if entry.result.is_ok() {
        StatusCode::CREATED
    } else {
        StatusCode::OK
    }
}

async fn create(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let started = WallInstant::now();
    let checked = body
        .map_err(|r| ApiError::new(r.status(), "body", r.body_text()))
        .and_then(|b| parse_body::<NewFlight>(&b))
        .and_then(|b| validate(&app, b));
    let request = match checked {
        Ok(r) => r,
        Err(e) => {
            app.state.metrics.count_plan(PlanOutcome::Invalid);
            return Err(e);
        }
    };
    let (tx, rx) = oneshot::channel();
    app.commands
        .send(Command::Plan {
            caller,
            request,
            reply: tx,
        })
        .await
        .map_err(|_| ApiError::unavailable())?;
    let reply = rx.await.map_err(|_| ApiError::unavailable())?;
    app.state.metrics.request_latency.observe(started.elapsed());
    match reply {
        PlanReply::New(e) | PlanReply::Repeat(e) => Ok(flight_json(&app, answer_status(&e), &e)),
        PlanReply::Conflict => Err(ApiError::new(
            StatusCode::CONFLICT,
            "conflict",
            "this id is already used by another request; a retry must repeat the same origin, \
             destination and departure",
        )
        .field("id")),
        PlanReply::Failed(m) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            m,
        )),
    }
}

/// Query of `GET /v1/flights`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ListParams {
    status: Option<String>,
    from: Option<String>,
    to: Option<String>,
    operator: Option<String>,
    after: Option<u64>,
    limit: Option<usize>,
}

#[derive(Serialize)]
struct FlightList {
    flights: Vec<crate::flights::FlightView>,
    /// The `after` of the next page, when `limit` cut this one short.
    next_after: Option<u64>,
}

async fn list(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    params: Result<Query<ListParams>, QueryRejection>,
) -> Result<Response, ApiError> {
    let Query(p) = params.map_err(|r| {
        ApiError::new(
            StatusCode::BAD_REQUEST,
            "malformed",
            format!("bad query: {}", r.body_text()),
        )
    })?;
    let time = |field: &str, v: &Option<String>| -> Result<Option<Instant>, ApiError> {
        v.as_deref()
            .map(|t| Instant::parse_rfc3339(t).map_err(|e| ApiError::invalid(field, e.to_string())))
            .transpose()
    };
    let status = p
        .status
        .as_deref()
        .map(|s| match s {
            "planned" => Ok(Status::Planned),
            "rejected" => Ok(Status::Rejected),
            "cancelled" => Ok(Status::Cancelled),
            other => Err(ApiError::invalid(
                "status",
                format!("`{other}` is not `planned`, `rejected` or `cancelled`"),
            )),
        })
        .transpose()?;
    let operator = match (p.operator, caller.role) {
        (Some(op), crate::auth::Role::Authority) => Some(op),
        (Some(op), crate::auth::Role::Operator) if op == caller.operator => Some(op),
        (Some(_), crate::auth::Role::Operator) => {
            return Err(ApiError::new(
                StatusCode::FORBIDDEN,
                "forbidden",
                "an operator may list only its own flights",
            )
            .field("operator"));
        }
        (None, crate::auth::Role::Authority) => None,
        (None, crate::auth::Role::Operator) => Some(caller.operator.clone()),
    };
    let query = ListQuery {
        operator,
        status,
        from: time("from", &p.from)?,
        to: time("to", &p.to)?,
        after: p.after,
        limit: p.limit,
    };
    let (entries, more) = app
        .state
        .index
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .list(&query);
    let w = &app.state.world;
    let body = FlightList {
        next_after: if more {
            entries.last().map(|e| e.seq)
        } else {
            None
        },
        flights: entries
            .iter()
            .map(|e| e.view(&w.airspace, w.offset))
            .collect(),
    };
    Ok(json(StatusCode::OK, &body))
}

async fn read(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    Path(id): Path<String>,
) -> Result<Response, ApiError> {
    let entry = app
        .state
        .index
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .get(&id)
        .filter(|e| caller.may_read(&e.operator))
        .cloned()
        .ok_or_else(|| ApiError::not_found(&format!("flight `{id}`")))?;
    Ok(flight_json(&app, StatusCode::OK, &entry))
}

async fn cancel(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    Path(id): Path<String>,
) -> Result<Response, ApiError> {
    let (tx, rx) = oneshot::channel();
    app.commands
        .send(Command::Cancel {
            caller,
            id: id.clone(),
            reply: tx,
        })
        .await
        .map_err(|_| ApiError::unavailable())?;
    let offset = app.state.world.offset;
    match rx.await.map_err(|_| ApiError::unavailable())? {
        CancelReply::Done(e) | CancelReply::Already(e) => Ok(flight_json(&app, StatusCode::OK, &e)),
        CancelReply::NotFound => Err(ApiError::not_found(&format!("flight `{id}`"))),
        CancelReply::TookOff(e) => Err(ApiError::new(
            StatusCode::CONFLICT,
            "committed",
            format!(
                "flight `{id}` took off at {}; it is committed and cannot be cancelled",
                e.span().0.to_rfc3339(offset)
            ),
        )),
        CancelReply::NotPlanned(_) => Err(ApiError::new(
            StatusCode::CONFLICT,
            "not_planned",
            format!("flight `{id}` was rejected; there is nothing to cancel"),
        )),
        CancelReply::Failed(m) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            m,
        )),
    }
}

fn geojson(text: &str) -> Response {
    (
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/geo+json"),
        )],
        text.to_owned(),
    )
        .into_response()
}

async fn airspace(AxumState(app): AxumState<Arc<App>>, Authed(_): Authed) -> Response {
    geojson(&app.airspace_geojson)
}

async fn zones(AxumState(app): AxumState<Arc<App>>, Authed(_): Authed) -> Response {
    geojson(&app.zones_geojson)
}

async fn openapi() -> Response {
    (
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/json"),
        )],
        OPENAPI,
    )
        .into_response()
}

#[derive(Serialize)]
struct Health {
    status: &'static str,
    now: String,
    flights: usize,
    airspace: String,
    parameters: Parameters,
    /// Seconds a flight stays in memory after it ends (`--retain-hours`).
    retain_s: f64,
}

/// The flight parameters planned with (SPEC §3), as `muse plan` takes them.
#[derive(Serialize)]
struct Parameters {
    speed_kmh: f64,
    max_flight_min: f64,
    node_separation_s: f64,
    edge_rule: &'static str,
    headway_s: Option<f64>,
    max_ground_delay_s: f64,
}

async fn healthz(AxumState(app): AxumState<Arc<App>>) -> Response {
    let s = &app.state;
    let flights = s
        .index
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .len();
    json(
        StatusCode::OK,
        &Health {
            status: "ok",
            now: s.clock.now().to_rfc3339(s.world.offset),
            flights,
            airspace: s.world.label.clone(),
            retain_s: s.retain.as_secs_f64(),
            parameters: {
                let p = &s.world.params;
                Parameters {
                    speed_kmh: p.speed.kmh(),
                    max_flight_min: p.max_flight.as_secs_f64() / 60.0,
                    node_separation_s: p.node_separation.as_secs_f64(),
                    edge_rule: p.edge_rule.name(),
                    headway_s: match p.edge_rule {
                        muse_model::EdgeRule::Headway(h) => Some(h.as_secs_f64()),
                        muse_model::EdgeRule::Exclusive => None,
                    },
                    max_ground_delay_s: p.max_ground_delay.as_secs_f64(),
                }
            },
        },
    )
}

async fn metrics(AxumState(app): AxumState<Arc<App>>) -> Response {
    (
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("text/plain; version=0.0.4"),
        )],
        app.state.metrics.render(),
    )
        .into_response()
}

async fn not_found() -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        "not_found",
        "no such route; see /v1/openapi.json",
    )
}
