//! The properties every zone has, whatever the format: name, restriction, time periods,
//! announcement and withdrawal instants and the explicit node and edge lists.

use muse_model::{Instant, Period};
use serde_json::{Map, Value};

use super::time::{parse_date_time, parse_periods};
use super::{Ctx, member, show};
use crate::InputError;

/// The zone types read (ED-318 `type`, ED-269 `restriction`; `REQ_AUTHORIZATION` is read as
/// written too). MUSE closes what a zone covers whatever its type; an unknown type is refused
/// all the same, as it is more likely a typo than a type MUSE should ignore.
pub const ZONE_TYPES: [&str; 6] = [
    "PROHIBITED",
    "REQ_AUTHORISATION",
    "REQ_AUTHORIZATION",
    "CONDITIONAL",
    "NO_RESTRICTION",
    "USPACE",
];

/// The fields every zone has, whatever the format.
pub(super) struct Common {
    pub(super) name: String,
    pub(super) restriction: String,
    pub(super) node_ids: Vec<String>,
    pub(super) edge_ids: Vec<String>,
    pub(super) periods: Vec<Period>,
    pub(super) announced: Option<Instant>,
    pub(super) withdrawn: Option<Instant>,
}

/// Reads name, restriction (the first of `restriction_keys` present), periods, the
/// announcement and withdrawal instants and the explicit node and edge lists from a zone
/// object (ED-318 `properties` or an ED-269 zone).
pub(super) fn parse_common(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    restriction_keys: &[&str],
) -> Result<Common, InputError> {
    let name = match member(obj, "name") {
        None => String::new(),
        Some(v) => parse_name(ctx, v)?,
    };
    let mut restriction = None;
    for &key in restriction_keys {
        if let Some(v) = member(obj, key) {
            let s = v.as_str().ok_or_else(|| {
                ctx.err(
                    key,
                    format!("the restriction must be a string, got {}", show(v)),
                )
            })?;
            if !ZONE_TYPES.contains(&s) {
                return Err(ctx.err(
                    key,
                    format!(
                        "unknown zone type {}: expected one of {}",
                        show(v),
                        ZONE_TYPES.join(", ")
                    ),
                ));
            }
            restriction = Some(s.to_owned());
            break;
        }
    }
    let announced = parse_date_time(ctx, obj, "announced", "")?;
    let withdrawn = parse_date_time(ctx, obj, "withdrawn", "")?;
    if let Some(w) = withdrawn {
        // Only an announced zone can be withdrawn
        // (docs/reference.md#zones-announced-during-the-day), and not before it was announced.
        match announced {
            None => {
                return Err(ctx.err(
                    "withdrawn",
                    "a zone known from the start cannot be withdrawn: `withdrawn` needs \
                     `announced`",
                ));
            }
            Some(n) if w < n => {
                return Err(ctx.err(
                    "withdrawn",
                    format!(
                        "withdrawn at {} before it was announced ({}): must be at or after \
                         `announced`",
                        w.to_rfc3339(muse_model::UtcOffset(0)),
                        n.to_rfc3339(muse_model::UtcOffset(0))
                    ),
                ));
            }
            Some(_) => {}
        }
    }
    Ok(Common {
        name,
        restriction: restriction.unwrap_or_else(|| "PROHIBITED".to_owned()),
        node_ids: parse_id_list(ctx, obj, "nodes")?,
        edge_ids: parse_id_list(ctx, obj, "edges")?,
        periods: parse_periods(ctx, obj)?,
        announced,
        withdrawn,
    })
}

fn parse_name(ctx: &Ctx<'_>, v: &Value) -> Result<String, InputError> {
    let text_of = |item: &Value| -> Option<String> {
        match item {
            Value::String(s) => Some(s.clone()),
            Value::Object(o) => o.get("text").and_then(Value::as_str).map(str::to_owned),
            _ => None,
        }
    };
    match v {
        Value::Array(items) if items.is_empty() => Some(String::new()),
        Value::Array(items) => items.iter().find_map(text_of),
        other => text_of(other),
    }
    .ok_or_else(|| {
        ctx.err(
            "name",
            format!(
                "expected a string or a list of {{\"text\", \"lang\"}}, got {}",
                show(v)
            ),
        )
    })
}

fn parse_id_list(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    key: &str,
) -> Result<Vec<String>, InputError> {
    let Some(v) = member(obj, key) else {
        return Ok(Vec::new());
    };
    let items = v.as_array().ok_or_else(|| {
        ctx.err(
            key,
            format!("expected an array of {key} ids, got {}", show(v)),
        )
    })?;
    items
        .iter()
        .enumerate()
        .map(|(i, item)| match item.as_str() {
            Some(s) if !s.trim().is_empty() => Ok(s.to_owned()),
            _ => Err(ctx.err(
                &format!("{key}[{i}]"),
                format!("expected a non-empty id string, got {}", show(item)),
            )),
        })
        .collect()
}
