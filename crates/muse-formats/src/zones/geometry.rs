//! Geometry in zone files: positions, rings, polygons, multipolygons, circle radii, and the
//! assembly of a zone's areas and vertical bands into one or more [`Zone`]s.

use geo_types::{Coord, LineString, MultiPolygon, Polygon};
use muse_model::{LonLat, VerticalLimits, Zone, ZoneArea};
use serde_json::Value;

use super::properties::Common;
use super::{Ctx, show};
use crate::InputError;

const FOOT_M: f64 = 0.3048;
const NAUTICAL_MILE_M: f64 = 1_852.0;

/// One horizontal area of a zone, before polygons are merged.
pub(super) enum Part {
    Polygon(Polygon<f64>),
    Circle(LonLat, f64),
}

/// A `[lon, lat]` position (a third value, altitude, is ignored).
pub(super) fn parse_position(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
) -> Result<Coord<f64>, InputError> {
    let bad = || {
        ctx.err(
            field,
            format!("expected a position [longitude, latitude], got {}", show(v)),
        )
    };
    let items = v.as_array().ok_or_else(bad)?;
    if !(2..=3).contains(&items.len()) {
        return Err(bad());
    }
    let mut xy = [0.0; 2];
    for (k, slot) in xy.iter_mut().enumerate() {
        *slot = items[k].as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
            ctx.err(
                field,
                format!("coordinate {} is not a number", show(&items[k])),
            )
        })?;
    }
    if items.len() == 3 && !items[2].is_number() {
        return Err(ctx.err(
            field,
            format!("altitude {} is not a number", show(&items[2])),
        ));
    }
    let [lon, lat] = xy;
    if !(-180.0..=180.0).contains(&lon) {
        return Err(ctx.err(
            field,
            format!("longitude {lon} is out of range [-180, 180] (positions are [lon, lat])"),
        ));
    }
    if !(-90.0..=90.0).contains(&lat) {
        return Err(ctx.err(
            field,
            format!("latitude {lat} is out of range [-90, 90] (positions are [lon, lat])"),
        ));
    }
    Ok(Coord { x: lon, y: lat })
}

fn parse_ring(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<LineString<f64>, InputError> {
    let items = v.as_array().ok_or_else(|| {
        ctx.err(
            field,
            format!("expected a ring: an array of positions, got {}", show(v)),
        )
    })?;
    if items.len() < 4 {
        return Err(ctx.err(
            field,
            format!(
                "a polygon ring needs at least 4 positions (the last repeating the first), got {}",
                items.len()
            ),
        ));
    }
    let coords = items
        .iter()
        .enumerate()
        .map(|(i, p)| parse_position(ctx, p, &format!("{field}[{i}]")))
        .collect::<Result<Vec<_>, _>>()?;
    let (first, last) = (coords[0], coords[coords.len() - 1]);
    if first != last {
        return Err(ctx.err(
            field,
            format!(
                "the polygon ring is not closed: the first position [{}, {}] differs from the last [{}, {}]",
                first.x, first.y, last.x, last.y
            ),
        ));
    }
    Ok(LineString(coords))
}

/// A `GeoJSON` polygon: `[exterior, hole, …]`.
pub(super) fn parse_polygon(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
) -> Result<Polygon<f64>, InputError> {
    let rings = v.as_array().ok_or_else(|| {
        ctx.err(
            field,
            format!(
                "expected polygon coordinates [[[lon, lat], …]], got {}",
                show(v)
            ),
        )
    })?;
    if rings.is_empty() {
        return Err(ctx.err(field, "a polygon needs at least one ring"));
    }
    let mut rings = rings
        .iter()
        .enumerate()
        .map(|(i, r)| parse_ring(ctx, r, &format!("{field}[{i}]")))
        .collect::<Result<Vec<_>, _>>()?
        .into_iter();
    let exterior = rings.next().unwrap_or_else(|| LineString(Vec::new()));
    Ok(Polygon::new(exterior, rings.collect()))
}

/// `GeoJSON` multipolygon coordinates.
pub(super) fn parse_multipolygon(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
) -> Result<Vec<Polygon<f64>>, InputError> {
    let polys = v.as_array().ok_or_else(|| {
        ctx.err(
            field,
            format!(
                "expected multipolygon coordinates [[[[lon, lat], …]]], got {}",
                show(v)
            ),
        )
    })?;
    if polys.is_empty() {
        return Err(ctx.err(field, "a MultiPolygon needs at least one polygon"));
    }
    polys
        .iter()
        .enumerate()
        .map(|(i, p)| parse_polygon(ctx, p, &format!("{field}[{i}]")))
        .collect()
}

/// A circle radius in metres: a number (or numeric string) > 0, in `uom` (`M`, `FT`, `NM`).
pub(super) fn parse_radius(
    ctx: &Ctx<'_>,
    v: Option<&Value>,
    field: &str,
    uom: Option<(&Value, String)>,
) -> Result<f64, InputError> {
    let Some(v) = v else {
        return Err(ctx.err(field, "missing: a circle needs a radius"));
    };
    let r = match v {
        Value::Number(n) => n.as_f64(),
        Value::String(s) => s.trim().parse::<f64>().ok(),
        _ => None,
    };
    let r = r.ok_or_else(|| {
        ctx.err(
            field,
            format!("the circle radius must be a number, got {}", show(v)),
        )
    })?;
    if !r.is_finite() || r <= 0.0 {
        return Err(ctx.err(field, format!("the circle radius must be > 0, got {r}")));
    }
    let factor = match uom {
        None => 1.0,
        Some((u, uom_field)) => match u.as_str().map(str::trim) {
            Some(s) if s.eq_ignore_ascii_case("M") => 1.0,
            Some(s) if s.eq_ignore_ascii_case("FT") => FOOT_M,
            Some(s) if s.eq_ignore_ascii_case("NM") => NAUTICAL_MILE_M,
            _ => {
                return Err(ctx.err(
                    &uom_field,
                    format!("unknown unit {}: expected M, FT or NM", show(u)),
                ));
            }
        },
    };
    let metres = r * factor;
    if !metres.is_finite() {
        return Err(ctx.err(field, format!("the circle radius {r} is too large")));
    }
    Ok(metres)
}

/// Builds the zone(s) of one feature from its parts, each with its vertical band: the polygons
/// of one band form one area (bands in order of first appearance), each circle another; more
/// than one area gives one zone per area (`ID#1`, `ID#2`, …, explicit ids on the first). A
/// zone without parts (explicit elements only) has the band `bare`.
pub(super) fn assemble(
    ctx: &Ctx<'_>,
    id: String,
    common: Common,
    parts: Vec<(Part, VerticalLimits)>,
    bare: VerticalLimits,
    geometry_field: &str,
) -> Result<Vec<Zone>, InputError> {
    if parts.is_empty() && common.node_ids.is_empty() && common.edge_ids.is_empty() {
        return Err(ctx.err(
            geometry_field,
            "missing: a zone needs a geometry or explicit `nodes` / `edges` lists",
        ));
    }
    let mut polygons: Vec<(VerticalLimits, Vec<Polygon<f64>>)> = Vec::new();
    let mut circles = Vec::new();
    for (part, band) in parts {
        match part {
            Part::Polygon(p) => match polygons.iter_mut().find(|(b, _)| *b == band) {
                Some((_, group)) => group.push(p),
                None => polygons.push((band, vec![p])),
            },
            Part::Circle(centre, radius_m) => {
                circles.push((ZoneArea::Circle { centre, radius_m }, band));
            }
        }
    }
    let mut areas: Vec<(ZoneArea, VerticalLimits)> = polygons
        .into_iter()
        .map(|(band, group)| (ZoneArea::Polygons(MultiPolygon(group)), band))
        .chain(circles)
        .collect();
    let Common {
        name,
        restriction,
        node_ids,
        edge_ids,
        periods,
        announced,
        withdrawn,
    } = common;
    if areas.len() <= 1 {
        let (area, vertical) = areas.pop().map_or((None, bare), |(a, b)| (Some(a), b));
        return Ok(vec![Zone {
            id,
            name,
            restriction,
            area,
            node_ids,
            edge_ids,
            periods,
            announced,
            withdrawn,
            vertical,
        }]);
    }
    Ok(areas
        .into_iter()
        .enumerate()
        .map(|(k, (area, vertical))| Zone {
            id: format!("{id}#{}", k + 1),
            name: name.clone(),
            restriction: restriction.clone(),
            area: Some(area),
            node_ids: if k == 0 { node_ids.clone() } else { Vec::new() },
            edge_ids: if k == 0 { edge_ids.clone() } else { Vec::new() },
            periods: periods.clone(),
            announced,
            withdrawn,
            vertical,
        })
        .collect())
}
