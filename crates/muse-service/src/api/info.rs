//! What the service plans on and how it is doing: airspace, the API description, health and
//! metrics.

use std::sync::Arc;

use axum::extract::State as AxumState;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use muse_formats::params::ParamsRecord;
use serde::Serialize;

use super::error::json;
use super::{ApiError, App, Authed, OPENAPI};

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

pub(super) async fn airspace(AxumState(app): AxumState<Arc<App>>, Authed(_): Authed) -> Response {
    geojson(&app.airspace_geojson)
}

/// `GET /`: the live viewer page (HTML), or 404 when the service has none.
pub(super) async fn page(AxumState(app): AxumState<Arc<App>>) -> Response {
    match &app.page {
        Some(html) => (
            [(
                header::CONTENT_TYPE,
                HeaderValue::from_static("text/html; charset=utf-8"),
            )],
            html.clone(),
        )
            .into_response(),
        None => ApiError::new(
            StatusCode::NOT_FOUND,
            "not_found",
            "this service was started without a viewer page",
        )
        .into_response(),
    }
}

pub(super) async fn openapi() -> Response {
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
    /// `ok`, or `starting` while the store is being loaded (answered `503`).
    status: &'static str,
    now: String,
    /// Flights stored (every request answered, for the life of the store).
    flights: u64,
    /// Of those, the flights the live schedule holds (in memory).
    flights_held: usize,
    airspace: String,
    parameters: ParamsRecord,
    /// While starting: what has been loaded so far.
    #[serde(skip_serializing_if = "Option::is_none")]
    progress: Option<crate::state::Progress>,
    /// `leader` (plans and writes) or `standby` (follows the leader, forwards writes to it).
    role: &'static str,
    /// A standby's leader, as it advertised itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    leader: Option<String>,
    /// How far behind the leader a standby is.
    #[serde(skip_serializing_if = "Option::is_none")]
    behind: Option<crate::role::Behind>,
    /// Times this service took the lead from being a standby.
    takeovers: u64,
}

pub(super) async fn healthz(AxumState(app): AxumState<Arc<App>>) -> Response {
    let s = &app.state;
    let flights_held = s
        .index
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .len();
    let ready = s.phase.is_ready();
    json(
        if ready {
            StatusCode::OK
        } else {
            StatusCode::SERVICE_UNAVAILABLE
        },
        &Health {
            status: if ready { "ok" } else { "starting" },
            now: s.clock.now().to_rfc3339(s.world.offset),
            flights: s.metrics.flights_stored(),
            flights_held,
            airspace: s.world.label.clone(),
            progress: (!ready).then(|| s.phase.progress()),
            parameters: ParamsRecord::from(&s.world.params),
            role: if s.role.is_standby() {
                "standby"
            } else {
                "leader"
            },
            leader: s.role.leader(),
            behind: s.role.behind(crate::state::system_ms()),
            takeovers: s.role.takeovers(),
        },
    )
}

pub(super) async fn metrics(AxumState(app): AxumState<Arc<App>>) -> Response {
    (
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("text/plain; version=0.0.4"),
        )],
        {
            let mut out = app.state.metrics.render();
            app.state.role.render(&mut out, crate::state::system_ms());
            out
        },
    )
        .into_response()
}
