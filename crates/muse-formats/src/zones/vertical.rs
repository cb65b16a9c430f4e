//! Vertical limits in zone files (docs/reference.md#layered-airspace): ED-318's `layer` on a
//! geometry and ED-269's `lowerLimit` / `upperLimit` on a volume (or in an ED-318 feature's
//! properties), read into a [`VerticalLimits`] band.
//!
//! - A height is a number (or a numeric string) ≥ 0, in metres or feet (`M`, `FT`, any case;
//!   1 ft = 0.3048 m exactly), kept to the micrometre. A missing or `null` side is open.
//! - A reference is `AGL`, `AMSL` or `WGS84` (any case; the aeronautical spellings `SFC` and
//!   `GND` are read as `AGL`, `MSL` as `AMSL`, `W84` as `WGS84`). MUSE flies over flat ground at
//!   sea level, so every reference measures the same heights; the reference is kept for display
//!   and writing. A height without a reference is `AGL`. Pressure altitudes (`STD`, flight
//!   levels) are refused.
//! - The lower limit may not be above the upper one.

use muse_model::{Metres, VerticalLimit, VerticalLimits, VerticalReference};
use serde_json::{Map, Value};

use super::{Ctx, expect_object, join, member, one_of, show};
use crate::InputError;

/// The member names of one format's vertical limits.
struct Keys {
    lower: &'static str,
    upper: &'static str,
    lower_reference: &'static str,
    upper_reference: &'static str,
    /// The unit's names (the first is the one the format defines).
    uom: &'static [&'static str],
    /// Whether the unit may be `NM` (ED-269's `uomDimensions` also gives a circle's radius):
    /// then only when no height is given.
    nautical_miles: bool,
}

/// ED-318 (`layer`).
const ED318: Keys = Keys {
    lower: "lower",
    upper: "upper",
    lower_reference: "lowerReference",
    upper_reference: "upperReference",
    uom: &["uom", "uomDimensions"],
    nautical_miles: false,
};

/// ED-269 (an airspace volume).
const ED269: Keys = Keys {
    lower: "lowerLimit",
    upper: "upperLimit",
    lower_reference: "lowerVerticalReference",
    upper_reference: "upperVerticalReference",
    uom: &["uomDimensions"],
    nautical_miles: true,
};

/// An ED-318 `layer` object at `field` (`{upper, upperReference, lower, lowerReference, uom}`).
pub(super) fn parse_layer(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
) -> Result<VerticalLimits, InputError> {
    let layer = expect_object(
        ctx,
        v,
        field,
        "a layer {\"upper\", \"upperReference\", \"lower\", \"lowerReference\", \"uom\"}",
    )?;
    parse_band(ctx, layer, field, &ED318)
}

/// The limits of an ED-269 airspace volume (the object at `field`).
pub(super) fn parse_volume_limits(
    ctx: &Ctx<'_>,
    volume: &Map<String, Value>,
    field: &str,
) -> Result<VerticalLimits, InputError> {
    parse_band(ctx, volume, field, &ED269)
}

/// ED-269's limits given in an ED-318 feature's `properties` (`lowerLimit`, `upperLimit`,
/// `uomDimensions`, `lowerVerticalReference`, `upperVerticalReference`): read exactly as
/// [`parse_volume_limits`] reads an ED-269 volume's, the band of the feature's geometries
/// that give no `layer`. `None` when neither limit is given (a unit or reference alone is
/// still checked).
pub(super) fn parse_properties_limits(
    ctx: &Ctx<'_>,
    props: &Map<String, Value>,
) -> Result<Option<VerticalLimits>, InputError> {
    let band = parse_volume_limits(ctx, props, "")?;
    let given = member(props, ED269.lower).is_some() || member(props, ED269.upper).is_some();
    Ok(given.then_some(band))
}

/// `layer`, the band an ED-318 `layer` at `field` gives, unless the feature's properties
/// give other limits (`given`, [`parse_properties_limits`]): a zone whose heights are said
/// twice, differently, is refused rather than one of them dropped.
pub(super) fn agreeing(
    ctx: &Ctx<'_>,
    layer: VerticalLimits,
    given: Option<VerticalLimits>,
    field: &str,
) -> Result<VerticalLimits, InputError> {
    match given {
        Some(limits) if limits != layer => Err(ctx.err(
            field,
            format!(
                "the layer ({layer}) contradicts the `lowerLimit` / `upperLimit` of the \
                 feature's properties ({limits}): give the zone's vertical limits once, or \
                 the same in both"
            ),
        )),
        _ => Ok(layer),
    }
}

#[derive(Clone, Copy)]
enum Unit {
    Metres,
    Feet,
    NauticalMiles,
}

fn parse_band(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    field: &str,
    keys: &Keys,
) -> Result<VerticalLimits, InputError> {
    let unit = match one_of(ctx, obj, keys.uom, field)? {
        None => (Unit::Metres, None),
        Some((key, u)) => (parse_unit(ctx, u, &join(field, key), keys)?, Some(key)),
    };
    let lower = parse_side(ctx, obj, field, keys.lower, keys.lower_reference, unit)?;
    let upper = parse_side(ctx, obj, field, keys.upper, keys.upper_reference, unit)?;
    if let (Some(l), Some(u)) = (lower, upper)
        && l.height > u.height
    {
        return Err(ctx.err(
            &join(field, keys.lower),
            format!(
                "the lower limit ({} m) is above the upper limit ({} m): a zone's band runs \
                 from its lower limit up to its upper limit",
                l.height, u.height
            ),
        ));
    }
    Ok(VerticalLimits { lower, upper })
}

fn parse_unit(ctx: &Ctx<'_>, u: &Value, field: &str, keys: &Keys) -> Result<Unit, InputError> {
    match u.as_str().map(str::trim) {
        Some(s) if s.eq_ignore_ascii_case("M") => Ok(Unit::Metres),
        Some(s) if s.eq_ignore_ascii_case("FT") => Ok(Unit::Feet),
        Some(s) if keys.nautical_miles && s.eq_ignore_ascii_case("NM") => Ok(Unit::NauticalMiles),
        _ => Err(ctx.err(
            field,
            format!(
                "unknown unit {}: expected M (metres) or FT (feet){}",
                show(u),
                if keys.nautical_miles {
                    ", or NM for a circle's radius in a volume without heights"
                } else {
                    ""
                }
            ),
        )),
    }
}

/// One side: its height (open when missing or `null`) and its reference.
fn parse_side(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    field: &str,
    key: &str,
    reference_key: &str,
    (unit, uom_key): (Unit, Option<&str>),
) -> Result<Option<VerticalLimit>, InputError> {
    // The reference is checked even for an open side: a misspelt one is a mistake anyway.
    let reference = match member(obj, reference_key) {
        None => VerticalReference::Agl,
        Some(r) => parse_reference(ctx, r, &join(field, reference_key))?,
    };
    let Some(v) = member(obj, key) else {
        return Ok(None);
    };
    let height_field = join(field, key);
    let x = match v {
        Value::Number(n) => n.as_f64(),
        Value::String(s) => s.trim().parse::<f64>().ok().filter(|x| x.is_finite()),
        _ => None,
    }
    .ok_or_else(|| {
        ctx.err(
            &height_field,
            format!(
                "a vertical limit must be a number ≥ 0 (or null for none), got {}",
                show(v)
            ),
        )
    })?;
    if x < 0.0 {
        return Err(ctx.err(
            &height_field,
            format!("a vertical limit must be ≥ 0, got {x}"),
        ));
    }
    let height = match unit {
        Unit::Metres => Metres::from_m(x),
        Unit::Feet => Metres::from_ft(x),
        Unit::NauticalMiles => {
            let uom_field = join(field, uom_key.unwrap_or("uomDimensions"));
            return Err(ctx.err(
                &uom_field,
                "heights in NM are not supported: give the volume's dimensions in M or FT",
            ));
        }
    }
    .map_err(|_| {
        ctx.err(
            &height_field,
            format!(
                "the vertical limit {x} is too large: at most {} m",
                Metres::MAX_M
            ),
        )
    })?;
    Ok(Some(VerticalLimit { height, reference }))
}

fn parse_reference(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<VerticalReference, InputError> {
    let s = v.as_str().map(str::trim).unwrap_or_default();
    let is = |names: &[&str]| names.iter().any(|n| s.eq_ignore_ascii_case(n));
    if is(&["AGL", "SFC", "GND"]) {
        Ok(VerticalReference::Agl)
    } else if is(&["AMSL", "MSL"]) {
        Ok(VerticalReference::Amsl)
    } else if is(&["WGS84", "W84"]) {
        Ok(VerticalReference::Wgs84)
    } else {
        Err(ctx.err(
            field,
            format!(
                "unknown vertical reference {}: expected AGL, AMSL or WGS84 (SFC, GND, MSL and \
                 W84 are read too; pressure altitudes, STD, are not supported)",
                show(v)
            ),
        ))
    }
}
