//! The zone routes (docs/reference.md#zones-announced-during-the-day): announce and withdraw (the
//! authority only), list, and what each zone closes. Only the HTTP face of zones is here, beside
//! every other route: reading a body, the zones known and deciding an announcement or a withdrawal
//! are in [`crate::zones`].

use std::sync::Arc;

use axum::extract::{Path, State as AxumState};
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use tokio::sync::oneshot;

use crate::auth::{Caller, Role};
use crate::engine::Command;
use crate::flights::FlightView;
use crate::zones::body::parse_feature;
use crate::zones::book::AnnouncedZone;
use crate::zones::decide::{AnnounceReply, WithdrawReply};

use super::error::json;
use super::guard::JsonBody;
use super::{ApiError, App, Authed};

fn authority_only(caller: &Caller) -> Result<(), ApiError> {
    if caller.role == Role::Authority {
        Ok(())
    } else {
        Err(ApiError::new(
            StatusCode::FORBIDDEN,
            "forbidden",
            "only the authority may announce or withdraw zones",
        ))
    }
}

/// The answer to `POST /v1/zones`.
#[derive(Serialize)]
struct AnnouncementBody {
    zone: String,
    announced: String,
    affected: Vec<AffectedBody>,
}

/// One flight an announcement changed.
#[derive(Serialize)]
struct AffectedBody {
    flight: String,
    operator: String,
    airborne: bool,
    outcome: &'static str,
    plan: FlightView,
}

pub(super) async fn announce(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    JsonBody(body): JsonBody<true>,
) -> Result<Response, ApiError> {
    authority_only(&caller)?;
    let body = body?;
    let zone = parse_feature(&body).map_err(|e| {
        let mut err = ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, "invalid_zone", e.message);
        if let Some(f) = e.field {
            err = err.field(f);
        }
        err
    })?;
    let id = zone.id.clone();
    let (tx, rx) = oneshot::channel();
    app.commands
        .send(Command::Announce { zone, reply: tx })
        .await
        .map_err(|_| ApiError::unavailable())?;
    let w = &app.state.world;
    match rx.await.map_err(|_| ApiError::unavailable())? {
        AnnounceReply::Done(a) => {
            let affected = a
                .affected
                .iter()
                .map(|e| AffectedBody {
                    flight: e.request.id.clone(),
                    operator: e.operator.clone(),
                    airborne: e.changes.last().is_some_and(|c| c.airborne),
                    outcome: e.status().as_str(),
                    plan: e.view(&w.airspace, w.offset),
                })
                .collect();
            let body = AnnouncementBody {
                zone: a.zone,
                announced: a.announced.to_rfc3339(w.offset),
                affected,
            };
            Ok(json(StatusCode::CREATED, &body))
        }
        AnnounceReply::Taken => Err(ApiError::new(
            StatusCode::CONFLICT,
            "conflict",
            format!(
                "zone id `{id}` is taken by a zone known from the start or announced before \
                 (withdrawn or not); ids are never reused"
            ),
        )
        .field("identifier")),
        AnnounceReply::Invalid { field, message } => {
            let mut err = ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, "invalid_zone", message);
            if let Some(f) = field {
                err = err.field(f);
            }
            Err(err)
        }
        AnnounceReply::Failed(m) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            m,
        )),
    }
}

/// The answer to `DELETE /v1/zones/{id}`.
#[derive(Serialize)]
struct ZoneBody {
    zone: String,
    announced: String,
    withdrawn: Option<String>,
    affected: usize,
}

fn zone_json(app: &App, zone: &AnnouncedZone) -> Response {
    let offset = app.state.world.offset;
    json(
        StatusCode::OK,
        &ZoneBody {
            zone: zone.id.clone(),
            announced: zone.announced.to_rfc3339(offset),
            withdrawn: zone.withdrawn.map(|t| t.to_rfc3339(offset)),
            affected: zone.affected,
        },
    )
}

pub(super) async fn withdraw(
    AxumState(app): AxumState<Arc<App>>,
    Authed(caller): Authed,
    Path(id): Path<String>,
) -> Result<Response, ApiError> {
    authority_only(&caller)?;
    let (tx, rx) = oneshot::channel();
    app.commands
        .send(Command::Withdraw {
            id: id.clone(),
            reply: tx,
        })
        .await
        .map_err(|_| ApiError::unavailable())?;
    match rx.await.map_err(|_| ApiError::unavailable())? {
        WithdrawReply::Done(z) | WithdrawReply::Already(z) => Ok(zone_json(&app, &z)),
        WithdrawReply::Base => Err(ApiError::new(
            StatusCode::CONFLICT,
            "known_from_start",
            format!("zone `{id}` is known from the start, cannot be withdrawn"),
        )),
        WithdrawReply::Unknown => Err(ApiError::not_found(&format!("zone `{id}`"))),
        WithdrawReply::Failed(m) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            m,
        )),
    }
}

pub(super) async fn list(AxumState(app): AxumState<Arc<App>>, Authed(_): Authed) -> Response {
    let text = app
        .state
        .zones
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .geojson()
        .to_owned();
    (
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/geo+json"),
        )],
        text,
    )
        .into_response()
}

/// The answer to `GET /v1/closures`.
#[derive(Serialize)]
struct ClosuresBody {
    zones: Vec<ZoneClosureBody>,
}

/// What one zone closes while it is active. In a layered airspace
/// (docs/reference.md#layered-airspace) nodes and corridors are the flat ones, closed at each of
/// `layers` where they are flown, and the vertical links it closes are listed apart.
#[derive(Serialize)]
struct ZoneClosureBody {
    zone: String,
    nodes: Vec<String>,
    corridors: Vec<CorridorBody>,
    #[serde(skip_serializing_if = "Option::is_none")]
    layers: Option<Vec<u32>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vertical_links: Option<Vec<VerticalLinkBody>>,
}

/// A vertical link of a layered airspace: at `node`, between `layer` and the one above.
#[derive(Serialize)]
struct VerticalLinkBody {
    node: String,
    layer: u32,
}

/// A corridor, by its id and its end nodes.
#[derive(Serialize)]
struct CorridorBody {
    id: String,
    from: String,
    to: String,
}

/// What zone `zone` closes, `nodes` and `edges` of `airspace`, as `GET /v1/closures` gives
/// it: in a layered airspace, by flat node and corridor, in flat order, with the layers and
/// the vertical links apart.
fn zone_closure(
    airspace: &muse_model::Airspace,
    zone: &str,
    nodes: &[muse_model::NodeId],
    edges: &[muse_model::EdgeId],
) -> ZoneClosureBody {
    use muse_model::EdgeKind;
    let flat = airspace.flat();
    let mut flat_nodes: Vec<muse_model::NodeId> =
        nodes.iter().map(|&n| airspace.flat_node(n)).collect();
    let mut flat_edges: Vec<muse_model::EdgeId> = edges
        .iter()
        .filter_map(|&e| airspace.flat_edge(e))
        .collect();
    flat_nodes.sort_unstable();
    flat_nodes.dedup();
    flat_edges.sort_unstable();
    flat_edges.dedup();
    let id = |n: muse_model::NodeId| flat.node(n).id.clone();
    let (layers, vertical_links) = if airspace.layers().is_some() {
        let mut layers: Vec<u32> = nodes.iter().map(|&n| airspace.node_layer(n)).collect();
        let mut vertical = Vec::new();
        for &e in edges {
            match airspace.edge_kind(e) {
                EdgeKind::Corridor { layer, .. } => layers.push(layer),
                EdgeKind::Vertical { layer, .. } => vertical.push(VerticalLinkBody {
                    node: id(airspace.flat_node(airspace.edge(e).from)),
                    layer,
                }),
            }
        }
        layers.sort_unstable();
        layers.dedup();
        (Some(layers), Some(vertical))
    } else {
        (None, None)
    };
    ZoneClosureBody {
        zone: zone.to_owned(),
        nodes: flat_nodes.into_iter().map(id).collect(),
        corridors: flat_edges
            .into_iter()
            .map(|e| {
                let edge = flat.edge(e);
                CorridorBody {
                    id: edge.id.clone(),
                    from: id(edge.from),
                    to: id(edge.to),
                }
            })
            .collect(),
        layers,
        vertical_links,
    }
}

/// `GET /v1/closures`: the nodes and corridors each zone of `GET /v1/zones` closes while it is
/// active, worked out as the planner does (the live viewer draws them).
pub(super) async fn closures(
    AxumState(app): AxumState<Arc<App>>,
    Authed(_): Authed,
) -> Result<Response, ApiError> {
    let airspace = &app.state.world.airspace;
    let zones: Vec<muse_model::Zone> = app
        .state
        .zones
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .all()
        .cloned()
        .collect();
    let mut body = ClosuresBody {
        zones: Vec::with_capacity(zones.len()),
    };
    for zone in &zones {
        // Every zone here was resolved on this airspace when it was loaded or announced.
        let (nodes, edges) =
            muse_airspace::closures::closed_elements(airspace, zone).map_err(|e| {
                ApiError::new(
                    StatusCode::INTERNAL_SERVER_ERROR,
                    "internal",
                    format!("zone `{}`: {e}", zone.id),
                )
            })?;
        body.zones
            .push(zone_closure(airspace, &zone.id, &nodes, &edges));
    }
    Ok(json(StatusCode::OK, &body))
}
