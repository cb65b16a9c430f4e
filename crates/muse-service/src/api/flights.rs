//! The flight routes: plan, list, read and cancel, with their input checks.

use std::sync::Arc;
use std::time::Instant as WallInstant;

use axum::extract::rejection::QueryRejection;
use axum::extract::{Path, Query, State as AxumState};
use axum::http::StatusCode;
use axum::response::Response;
use muse_model::{Instant, NodeId, NodeKind, Request};
use serde::{Deserialize, Serialize};
use tokio::sync::oneshot;

use crate::engine::{CancelReply, Command, PlanReply};
use crate::flights::{FlightEntry, ListQuery, Status};
use crate::metrics::PlanOutcome;

use super::error::json;
use super::guard::JsonBody;
use super::{ApiError, App, Authed, read_store};
use crate::flights::{ID_RULE, valid_id};

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
    if !valid_id(&body.id) {
        return Err(ApiError::invalid(
            "id",
            format!("must be {ID_RULE}, got {:?}", body.id),
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
        submitted: departure,
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

pub(super) async fn create(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    JsonBody(body): JsonBody<false>,
) -> Result<Response, ApiError> {
    let started = WallInstant::now();
    let checked = body
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
pub(super) struct ListParams {
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

pub(super) async fn list(
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
        .map(|s| {
            Status::parse(s).ok_or_else(|| {
                ApiError::invalid(
                    "status",
                    format!(
                        "`{s}` is not one of {}",
                        Status::ALL.map(|s| format!("`{}`", s.as_str())).join(", ")
                    ),
                )
            })
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
    let (entries, more) = read_store(&app, move |app| {
        app.state.reader.list(&app.state.world.airspace, &query)
    })
    .await?;
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

pub(super) async fn read(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    Path(id): Path<String>,
) -> Result<Response, ApiError> {
    let held = app
        .state
        .index
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .get(&id)
        .cloned();
    let entry = if let Some(e) = held {
        Some(e)
    } else {
        let wanted = id.clone();
        read_store(&app, move |app| {
            app.state.reader.flight(&app.state.world.airspace, &wanted)
        })
        .await?
        .map(Arc::new)
    };
    let entry = entry
        .filter(|e| caller.may_read(&e.operator))
        .ok_or_else(|| ApiError::not_found(&format!("flight `{id}`")))?;
    Ok(flight_json(&app, StatusCode::OK, &entry))
}

pub(super) async fn cancel(
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
        CancelReply::NotPlanned => Err(ApiError::new(
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
