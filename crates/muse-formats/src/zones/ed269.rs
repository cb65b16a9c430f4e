//! EUROCAE ED-269 JSON: reading one zone of a `features` / `UASZoneList` array.

use muse_model::{LonLat, VerticalLimits, Zone};
use serde_json::{Map, Value};

use super::geometry::{
    Part, assemble, parse_multipolygon, parse_polygon, parse_position, parse_radius,
};
use super::properties::parse_common;
use super::vertical::parse_volume_limits;
use super::{Ctx, expect_object, join, list_of, member, parse_identifier, show};
use crate::InputError;

/// Reads one ED-269 zone (usually one [`Zone`]; see [`assemble`]).
pub(super) fn read_zone(file: &str, index: usize, v: &Value) -> Result<Vec<Zone>, InputError> {
    let mut ctx = Ctx::new(file, index);
    let obj = expect_object(&ctx, v, "", "a zone")?;
    let id = match member(obj, "identifier") {
        Some(v) => parse_identifier(&ctx, v, "identifier")?,
        None => return Err(ctx.err("identifier", "missing: the zone's identifier")),
    };
    ctx.id = Some(id.clone());
    let common = parse_common(&ctx, obj, &["restriction"])?;
    let mut parts = Vec::new();
    if let Some(g) = member(obj, "geometry") {
        for (i, volume) in list_of(g).iter().enumerate() {
            let field = if g.is_array() {
                format!("geometry[{i}]")
            } else {
                "geometry".to_owned()
            };
            parts.push(volume_part(&ctx, volume, &field)?);
        }
    }
    let parts = parts.into_iter().flatten().collect();
    assemble(
        &ctx,
        id,
        common,
        parts,
        VerticalLimits::WHOLE_SKY,
        "geometry",
    )
}

/// One airspace volume: its `horizontalProjection`, each part with the volume's vertical
/// limits.
fn volume_part(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
) -> Result<Vec<(Part, VerticalLimits)>, InputError> {
    let volume = expect_object(ctx, v, field, "an airspace volume")?;
    let parts = projection_parts(ctx, volume, field)?;
    let band = parse_volume_limits(ctx, volume, field)?;
    Ok(parts.into_iter().map(|part| (part, band)).collect())
}

/// The parts of a volume's `horizontalProjection`.
fn projection_parts(
    ctx: &Ctx<'_>,
    volume: &Map<String, Value>,
    field: &str,
) -> Result<Vec<Part>, InputError> {
    let hp_field = join(field, "horizontalProjection");
    let hp_v = member(volume, "horizontalProjection")
        .ok_or_else(|| ctx.err(&hp_field, "missing: the volume's horizontal projection"))?;
    let hp = expect_object(ctx, hp_v, &hp_field, "`horizontalProjection`")?;
    let kind_field = join(&hp_field, "type");
    let kind =
        member(hp, "type").ok_or_else(|| ctx.err(&kind_field, "missing: Polygon or Circle"))?;
    let coord_field = join(&hp_field, "coordinates");
    let coordinates = || {
        member(hp, "coordinates")
            .ok_or_else(|| ctx.err(&coord_field, "missing: the polygon's coordinates"))
    };
    match kind.as_str() {
        Some("Polygon") => Ok(vec![Part::Polygon(parse_polygon(
            ctx,
            coordinates()?,
            &coord_field,
        )?)]),
        Some("MultiPolygon") => Ok(parse_multipolygon(ctx, coordinates()?, &coord_field)?
            .into_iter()
            .map(Part::Polygon)
            .collect()),
        Some("Circle") => {
            let (key, centre) = ["center", "centre"]
                .into_iter()
                .find_map(|k| member(hp, k).map(|c| (k, c)))
                .ok_or_else(|| {
                    ctx.err(
                        &join(&hp_field, "center"),
                        "missing: the circle's center [lon, lat]",
                    )
                })?;
            let c = parse_position(ctx, centre, &join(&hp_field, key))?;
            let uom = member(volume, "uomDimensions").map(|u| (u, join(field, "uomDimensions")));
            let radius = parse_radius(ctx, member(hp, "radius"), &join(&hp_field, "radius"), uom)?;
            Ok(vec![Part::Circle(LonLat::new(c.x, c.y), radius)])
        }
        _ => Err(ctx.err(
            &kind_field,
            format!(
                "unsupported horizontal projection type {}: expected Polygon or Circle",
                show(kind)
            ),
        )),
    }
}
