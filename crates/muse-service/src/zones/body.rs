//! How a `POST /v1/zones` body becomes a zone to announce: one ED-318 feature, or a
//! `FeatureCollection` of exactly one, without `announced` (the service sets it).

use muse_formats::zones::read_zones;
use serde_json::Value;

use super::book::NewZone;
use crate::flights::{ID_RULE, valid_id};

/// Largest `POST /v1/zones` body, bytes (zones may carry long polygons; only the authority
/// may send one).
pub const MAX_ZONE_BODY: usize = 1 << 20;

/// Why a body is not a zone to announce: the field at fault (as `muse_formats` names it) and
/// what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BodyError {
    /// The field, when one is to blame.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl BodyError {
    fn new(field: Option<&str>, message: impl Into<String>) -> Self {
        BodyError {
            field: field.map(str::to_owned),
            message: message.into(),
        }
    }
}

/// Reads a `POST /v1/zones` body: one ED-318 feature, or a `FeatureCollection` of exactly
/// one, without `announced`.
pub fn parse_feature(body: &[u8]) -> Result<NewZone, BodyError> {
    let root: Value = serde_json::from_slice(body)
        .map_err(|e| BodyError::new(None, format!("the body is not valid JSON: {e}")))?;
    let feature = match root.get("type").and_then(Value::as_str) {
        Some("Feature") => root,
        Some("FeatureCollection") => match root.get("features").and_then(Value::as_array) {
            Some(features) if features.len() == 1 => features[0].clone(),
            Some(features) => {
                return Err(BodyError::new(
                    Some("features"),
                    format!(
                        "one zone per announcement: the FeatureCollection must hold exactly one \
                         feature, not {}",
                        features.len()
                    ),
                ));
            }
            None => {
                return Err(BodyError::new(
                    Some("features"),
                    "the FeatureCollection has no `features` array",
                ));
            }
        },
        _ => {
            return Err(BodyError::new(
                Some("type"),
                "expected an ED-318 zone: a GeoJSON Feature (or a FeatureCollection of one)",
            ));
        }
    };
    if feature
        .get("properties")
        .and_then(|p| p.get("announced"))
        .is_some()
    {
        return Err(BodyError::new(
            Some("properties.announced"),
            "the service sets the announcement instant itself (its clock's now when the zone \
             is taken into account); leave `announced` out",
        ));
    }
    let text = feature.to_string();
    let zones = read_zones(&text, "the zone").map_err(|e| {
        BodyError::new(
            e.field.as_deref(),
            format!("not a valid ED-318 zone: {}", e.message),
        )
    })?;
    let Some(first) = zones.first() else {
        return Err(BodyError::new(None, "the feature holds no zone"));
    };
    let id = if zones.len() == 1 {
        first.id.clone()
    } else {
        first
            .id
            .rsplit_once('#')
            .map_or_else(|| first.id.clone(), |(id, _)| id.to_owned())
    };
    if !valid_id(&id) {
        return Err(BodyError::new(
            Some("identifier"),
            format!(
                "an announced zone's identifier must be {ID_RULE} (it names the zone in \
                 /v1/zones/{{id}}), got {id:?}"
            ),
        ));
    }
    Ok(NewZone {
        id,
        feature: text,
        zones,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::zones::book::tests::ZONE;

    #[test]
    fn a_feature_is_read_and_an_announcement_instant_refused() {
        let body = br#"{"type": "Feature", "properties": {"identifier": "Z", "nodes": ["B"]}, "geometry": null}"#;
        let zone = parse_feature(body).unwrap();
        assert_eq!(
            (zone.id.as_str(), zone.zones[0].node_ids.as_slice()),
            ("Z", &["B".to_owned()][..])
        );
        let e = parse_feature(
            br#"{"type": "Feature", "properties": {"identifier": "Z", "nodes": ["B"],
            "announced": "2026-01-05T14:00:00+08:00"}}"#,
        )
        .unwrap_err();
        assert_eq!(e.field.as_deref(), Some("properties.announced"));
    }

    #[test]
    fn bodies_are_read_or_refused_with_the_field_at_fault() {
        let zone = parse_feature(ZONE.as_bytes()).unwrap();
        assert_eq!(zone.id, "EVT");
        assert_eq!(zone.zones.len(), 2);
        let field = |body: &str| parse_feature(body.as_bytes()).unwrap_err().field;
        assert_eq!(field("nope"), None);
        assert_eq!(field(r#"{"type": "Point"}"#).as_deref(), Some("type"));
        assert_eq!(
            field(r#"{"type": "FeatureCollection", "features": []}"#).as_deref(),
            Some("features")
        );
        assert_eq!(
            field(r#"{"type": "Feature", "properties": {"identifier": "Z", "nodes": "B"}}"#)
                .as_deref(),
            Some("nodes")
        );
        assert_eq!(
            field(r#"{"type": "Feature", "properties": {"identifier": "a b", "nodes": ["B"]}}"#)
                .as_deref(),
            Some("identifier")
        );
    }
}
