//! No-fly zones: the EUROCAE ED-318 `GeoJSON` profile (native) and ED-269 JSON (SPEC §4).
//!
//! [`read_zones`] detects the format and returns [`Zone`]s; [`write_ed318`] writes them back
//! in the ED-318 `GeoJSON` profile.
//!
//! # ED-318 (`GeoJSON` profile)
//!
//! A `FeatureCollection` (a single `Feature`, or a bare JSON array of features, is accepted
//! too). Per feature:
//!
//! - `properties.identifier` (falling back to the feature's `id`): the zone id, unique in the file;
//! - `properties.name`: a string or the ED-318 list of `{"text", "lang"}` (the first text is used);
//! - `properties.restriction` or, as in ED-318 proper, `properties.type` (the zone type:
//!   `PROHIBITED`, `REQ_AUTHORIZATION`, …): kept as text (MUSE closes the airspace whatever
//!   it says; `PROHIBITED` when neither is given);
//! - `properties.limitedApplicability` (or `applicability`): time periods, see below;
//! - `geometry`: `Polygon`, `MultiPolygon`, a `Point` with an `extent`
//!   `{"subType": "Circle", "radius": <metres>}` (the extent may sit on the geometry, the
//!   feature or the properties; an optional `uom` / `uomDimensions` of `M`, `FT` or `NM`
//!   converts the radius), or a `GeometryCollection` of those.
//!
//! # ED-269 JSON
//!
//! An object with a `features` or `UASZoneList` array of zones (or a bare array). Per zone:
//! `identifier`, `name`, `restriction`, `applicability` and `geometry`: a list of volumes
//! whose `horizontalProjection` is `{"type": "Polygon", "coordinates": [[[lon, lat], …]]}` or
//! `{"type": "Circle", "center": [lon, lat], "radius": r}`, `r` in the volume's
//! `uomDimensions` (`M` by default, or `FT`).
//!
//! # Shared rules
//!
//! - Positions are `[longitude, latitude]` in WGS84 degrees (a third value, altitude, is
//!   ignored). Rings have at least 4 positions and are closed (first = last).
//! - Vertical limits (`lowerLimit`, `upperLimit`, `layer`, …) are read past and ignored:
//!   MUSE flies at one cruise altitude and every zone closes the airspace it covers.
//! - A time period is `{startDateTime?, endDateTime?, schedule?}` (ED-269 also
//!   `permanent` and `dailyPeriod`). Date-times are RFC 3339 with an offset. A `schedule`
//!   entry is `{"day": ["ANY" | "MON" … "SUN"], "startTime": "10:00:00+08:00",
//!   "endTime": "12:00:00+08:00"}`: clock times `HH:MM[:SS[.mmm]]` **with** a UTC offset
//!   (`+08:00`, `Z`); a time without one is an error, since it would be ambiguous.
//!   `endTime` may be `24:00`; an end at or before the start runs past midnight. Daylight
//!   events (`startEvent`, `endEvent`) are not supported and are an error.
//! - A zone with no period, or with a period that has no bounds and no schedule (e.g. ED-269
//!   `permanent: "YES"`), is permanent.
//! - MUSE extension: `nodes: ["S001", …]` and `edges: ["S001-S002", …]` list airspace
//!   elements closed explicitly (the paper's `V_nfz` and `E_nfz`); a zone may have only these
//!   and no geometry. The ids are checked later, against an airspace.
//! - A zone whose areas cannot be one [`ZoneArea`] (several circles, or circles and polygons,
//!   e.g. an ED-269 zone with several volumes) becomes one zone per area, with ids
//!   `ID#1`, `ID#2`, … (all polygons of a zone form one area).
//!
//! Every problem is an [`InputError`] naming the file, the feature (index and id) and the
//! field, e.g. `limitedApplicability[0].schedule[1].startTime` or `geometry.coordinates[0]`.

use std::collections::HashMap;
use std::path::Path;

use geo_types::{Coord, LineString, MultiPolygon, Polygon};
use muse_model::time::parse_clock;
use muse_model::{
    DailyWindow, Instant, LonLat, Millis, Period, UtcOffset, Weekday, Zone, ZoneArea,
};
use serde_json::{Map, Value};

use crate::{InputError, Location};

mod ed269;
mod ed318;

pub use ed318::write_ed318;

/// Decimals of degrees kept by [`write_ed318`] (and [`normalize`]): 7, about 1 cm.
pub const COORDINATE_DECIMALS: i32 = 7;

const DAY_MS: i64 = 86_400_000;
const FOOT_M: f64 = 0.3048;
const NAUTICAL_MILE_M: f64 = 1_852.0;

/// Reads zones from the text of a file in the ED-318 `GeoJSON` profile or ED-269 JSON,
/// detected from the top-level shape. `file` names the file in errors.
///
/// The zones come back in the canonical form of [`normalize`] (except for coordinates,
/// which are kept as written).
///
/// ```
/// use muse_formats::zones::read_zones;
/// let text = r#"{"type": "FeatureCollection", "features": [{
///   "type": "Feature",
///   "properties": {"identifier": "CBD", "name": "Downtown Core", "type": "PROHIBITED",
///     "limitedApplicability": [{"schedule": [
///       {"day": ["ANY"], "startTime": "10:00:00+08:00", "endTime": "12:00:00+08:00"}]}]},
///   "geometry": {"type": "Polygon", "coordinates": [[[103.84, 1.27], [103.86, 1.27],
///     [103.86, 1.29], [103.84, 1.29], [103.84, 1.27]]]}}]}"#;
/// let zones = read_zones(text, "cbd.geojson").unwrap();
/// assert_eq!(zones[0].id, "CBD");
/// assert_eq!(zones[0].periods[0].daily[0].days.len(), 7);
///
/// let err = read_zones("not json", "x.json").unwrap_err();
/// assert!(err.message.contains("not valid JSON"));
/// ```
pub fn read_zones(text: &str, file: &str) -> Result<Vec<Zone>, InputError> {
    let whole = |message: String| InputError::new(file, Location::Whole, None, message);
    let root: Value =
        serde_json::from_str(text).map_err(|e| whole(format!("not valid JSON: {e}")))?;
    let (format, items): (Format, &[Value]) = match &root {
        Value::Array(items) => (Format::guess(items), items),
        Value::Object(obj) => top_level(&root, obj).map_err(whole)?,
        _ => {
            return Err(whole(
                "expected an ED-318 FeatureCollection or an ED-269 object with `features` \
                 or `UASZoneList`"
                    .into(),
            ));
        }
    };
    let mut zones = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (index, item) in items.iter().enumerate() {
        let parsed = match format {
            Format::Ed318 => ed318::read_feature(file, index, item)?,
            Format::Ed269 => ed269::read_zone(file, index, item)?,
        };
        for zone in parsed {
            if let Some(first) = seen.insert(zone.id.clone(), index) {
                return Err(InputError::new(
                    file,
                    Location::Feature {
                        index,
                        id: Some(zone.id.clone()),
                    },
                    Some("identifier"),
                    format!(
                        "duplicate zone identifier `{}` (first used by feature {first})",
                        zone.id
                    ),
                ));
            }
            zones.push(zone);
        }
    }
    Ok(zones)
}

/// Reads a zone file from disk (see [`read_zones`]); errors name the path.
pub fn read_zones_file(path: &Path) -> Result<Vec<Zone>, InputError> {
    let text = crate::read_to_string(path)?;
    read_zones(&text, &path.display().to_string())
}

/// The canonical form of a zone, the form [`write_ed318`] writes: coordinates rounded to
/// [`COORDINATE_DECIMALS`] decimals, the days of each daily window sorted and without
/// repeats, and no periods at all when one of them is unbounded with no daily windows (such a
/// zone is permanent). [`read_zones`] returns zones in this form except for the rounding.
///
/// For valid zones, `read_zones(&write_ed318(zones))` equals `zones` normalized.
///
/// ```
/// use muse_formats::zones::normalize;
/// use muse_model::{LonLat, Zone, ZoneArea};
/// let zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: "PROHIBITED".into(),
///     area: Some(ZoneArea::Circle { centre: LonLat::new(103.812_345_678, 1.3), radius_m: 50.0 }),
///     node_ids: vec![], edge_ids: vec![], periods: vec![], announced: None,
/// };
/// let Some(ZoneArea::Circle { centre, .. }) = normalize(&zone).area else { unreachable!() };
/// assert_eq!(centre.lon, 103.812_345_7);
/// ```
pub fn normalize(zone: &Zone) -> Zone {
    let mut zone = zone.clone();
    match &mut zone.area {
        Some(ZoneArea::Polygons(mp)) => {
            for poly in &mut mp.0 {
                poly.exterior_mut(|ring| ring.0.iter_mut().for_each(round_coord));
                poly.interiors_mut(|rings| {
                    for ring in rings {
                        ring.0.iter_mut().for_each(round_coord);
                    }
                });
            }
        }
        Some(ZoneArea::Circle { centre, .. }) => {
            centre.lon = round_degrees(centre.lon);
            centre.lat = round_degrees(centre.lat);
        }
        None => {}
    }
    for period in &mut zone.periods {
        for daily in &mut period.daily {
            daily.days.sort_unstable();
            daily.days.dedup();
        }
    }
    if zone.periods.iter().any(is_always) {
        zone.periods.clear();
    }
    zone
}

/// Rounds degrees to [`COORDINATE_DECIMALS`] decimals (idempotent).
pub(crate) fn round_degrees(x: f64) -> f64 {
    let scale = 10_f64.powi(COORDINATE_DECIMALS);
    let r = (x * scale).round() / scale;
    if r == 0.0 { 0.0 } else { r }
}

fn round_coord(c: &mut Coord<f64>) {
    c.x = round_degrees(c.x);
    c.y = round_degrees(c.y);
}

fn is_always(p: &Period) -> bool {
    p.start.is_none() && p.end.is_none() && p.daily.is_empty()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ed318,
    Ed269,
}

impl Format {
    /// Guesses the format of a list of zones from its first object.
    fn guess(items: &[Value]) -> Format {
        let first = items.iter().find_map(Value::as_object);
        match first {
            Some(obj)
                if obj.contains_key("properties")
                    || obj.get("type").and_then(Value::as_str) == Some("Feature") =>
            {
                Format::Ed318
            }
            Some(obj)
                if obj.contains_key("applicability")
                    || obj.contains_key("restriction")
                    || obj.get("geometry").is_some_and(Value::is_array) =>
            {
                Format::Ed269
            }
            _ => Format::Ed318,
        }
    }
}

/// The format and the list of zones of a top-level object (`root` is `obj` as a value).
fn top_level<'v>(
    root: &'v Value,
    obj: &'v Map<String, Value>,
) -> Result<(Format, &'v [Value]), String> {
    let kind = obj.get("type").and_then(Value::as_str);
    if kind == Some("Feature") {
        return Ok((Format::Ed318, std::slice::from_ref(root)));
    }
    let list = |key: &str| -> Result<Option<&'v [Value]>, String> {
        match obj.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::Array(items)) => Ok(Some(items.as_slice())),
            Some(_) => Err(format!("`{key}` must be an array")),
        }
    };
    if let Some(items) = list("UASZoneList")? {
        return Ok((Format::Ed269, items));
    }
    match list("features")? {
        Some(items) if kind == Some("FeatureCollection") => Ok((Format::Ed318, items)),
        Some(items) => Ok((Format::guess(items), items)),
        None if kind == Some("FeatureCollection") => {
            Err("the FeatureCollection has no `features` array".into())
        }
        None => Err(
            "expected an ED-318 FeatureCollection or an ED-269 object with `features` \
                     or `UASZoneList`"
                .into(),
        ),
    }
}

// ---------------------------------------------------------------------------------------------
// Shared parsing.
// ---------------------------------------------------------------------------------------------

/// Where errors point: the file and the feature.
pub(crate) struct Ctx<'a> {
    file: &'a str,
    index: usize,
    id: Option<String>,
}

impl<'a> Ctx<'a> {
    pub(crate) fn new(file: &'a str, index: usize) -> Self {
        Ctx {
            file,
            index,
            id: None,
        }
    }

    pub(crate) fn err(&self, field: &str, message: impl Into<String>) -> InputError {
        InputError::new(
            self.file,
            Location::Feature {
                index: self.index,
                id: self.id.clone(),
            },
            (!field.is_empty()).then_some(field),
            message,
        )
    }
}

/// `prefix.key`, or `key` at the top.
pub(crate) fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_owned()
    } else {
        format!("{prefix}.{key}")
    }
}

/// A member that is present and not `null`.
pub(crate) fn member<'v>(obj: &'v Map<String, Value>, key: &str) -> Option<&'v Value> {
    obj.get(key).filter(|v| !v.is_null())
}

/// The one of `keys` that is present (an error if several are).
pub(crate) fn one_of<'v, 'k>(
    ctx: &Ctx<'_>,
    obj: &'v Map<String, Value>,
    keys: &[&'k str],
    prefix: &str,
) -> Result<Option<(&'k str, &'v Value)>, InputError> {
    let mut found: Option<(&'k str, &'v Value)> = None;
    for &key in keys {
        if let Some(v) = member(obj, key) {
            if let Some((first, _)) = found {
                return Err(ctx.err(
                    &join(prefix, key),
                    format!("both `{first}` and `{key}` are given; use one"),
                ));
            }
            found = Some((key, v));
        }
    }
    Ok(found)
}

/// The elements of an array, or the value itself when a single object stands for a list.
pub(crate) fn list_of(v: &Value) -> &[Value] {
    match v {
        Value::Array(items) => items,
        other => std::slice::from_ref(other),
    }
}

/// A short rendering of a JSON value for messages.
pub(crate) fn show(v: &Value) -> String {
    let s = v.to_string();
    if s.chars().count() > 60 {
        format!("{}…", s.chars().take(60).collect::<String>())
    } else {
        s
    }
}

pub(crate) fn expect_object<'v>(
    ctx: &Ctx<'_>,
    v: &'v Value,
    field: &str,
    what: &str,
) -> Result<&'v Map<String, Value>, InputError> {
    v.as_object().ok_or_else(|| {
        ctx.err(
            field,
            format!("{what} must be a JSON object, got {}", show(v)),
        )
    })
}

/// A zone identifier: a non-empty string (or an integer).
pub(crate) fn parse_identifier(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
) -> Result<String, InputError> {
    match v {
        Value::String(s) if !s.trim().is_empty() => Ok(s.clone()),
        Value::Number(n) if n.is_i64() || n.is_u64() => Ok(n.to_string()),
        _ => Err(ctx.err(
            field,
            format!(
                "a zone identifier must be a non-empty string, got {}",
                show(v)
            ),
        )),
    }
}

/// The fields every zone has, whatever the format.
pub(crate) struct Common {
    pub(crate) name: String,
    pub(crate) restriction: String,
    pub(crate) node_ids: Vec<String>,
    pub(crate) edge_ids: Vec<String>,
    pub(crate) periods: Vec<Period>,
    pub(crate) announced: Option<Instant>,
}

/// Reads name, restriction (the first of `restriction_keys` present), periods and the explicit
/// node and edge lists from a zone object (ED-318 `properties` or an ED-269 zone).
pub(crate) fn parse_common(
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
            restriction = Some(s.to_owned());
            break;
        }
    }
    Ok(Common {
        name,
        restriction: restriction.unwrap_or_else(|| "PROHIBITED".to_owned()),
        node_ids: parse_id_list(ctx, obj, "nodes")?,
        edge_ids: parse_id_list(ctx, obj, "edges")?,
        periods: parse_periods(ctx, obj)?,
        announced: parse_date_time(ctx, obj, "announced", "")?,
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

/// `limitedApplicability` (ED-318) or `applicability` (ED-269).
fn parse_periods(ctx: &Ctx<'_>, obj: &Map<String, Value>) -> Result<Vec<Period>, InputError> {
    let Some((key, v)) = one_of(ctx, obj, &["limitedApplicability", "applicability"], "")? else {
        return Ok(Vec::new());
    };
    let mut periods = Vec::new();
    for (i, item) in list_of(v).iter().enumerate() {
        let field = format!("{key}[{i}]");
        periods.push(parse_period(ctx, item, &field)?);
    }
    if periods.iter().any(is_always) {
        periods.clear();
    }
    Ok(periods)
}

fn parse_period(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<Period, InputError> {
    let obj = expect_object(ctx, v, field, "a time period")?;
    if let Some(p) = member(obj, "permanent") {
        let ok = match p {
            Value::Bool(_) => true,
            Value::String(s) => s.eq_ignore_ascii_case("YES") || s.eq_ignore_ascii_case("NO"),
            _ => false,
        };
        if !ok {
            return Err(ctx.err(
                &join(field, "permanent"),
                format!("expected \"YES\" or \"NO\", got {}", show(p)),
            ));
        }
    }
    let start = parse_date_time(ctx, obj, "startDateTime", field)?;
    let end = parse_date_time(ctx, obj, "endDateTime", field)?;
    if let (Some(s), Some(e)) = (start, end)
        && e <= s
    {
        return Err(ctx.err(
            &join(field, "endDateTime"),
            "endDateTime must be after startDateTime",
        ));
    }
    let mut daily = Vec::new();
    if let Some((key, v)) = one_of(ctx, obj, &["schedule", "dailyPeriod"], field)? {
        let items = list_of(v);
        if items.is_empty() {
            return Err(ctx.err(
                &join(field, key),
                "an empty schedule never applies; omit it instead",
            ));
        }
        for (j, item) in items.iter().enumerate() {
            daily.push(parse_daily(
                ctx,
                item,
                &format!("{}[{j}]", join(field, key)),
            )?);
        }
    }
    Ok(Period { start, end, daily })
}

fn parse_date_time(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    key: &str,
    prefix: &str,
) -> Result<Option<Instant>, InputError> {
    let Some(v) = member(obj, key) else {
        return Ok(None);
    };
    let field = join(prefix, key);
    let s = v.as_str().ok_or_else(|| {
        ctx.err(
            &field,
            format!("expected an RFC 3339 date-time string, got {}", show(v)),
        )
    })?;
    Instant::parse_rfc3339(s)
        .map(Some)
        .map_err(|e| ctx.err(&field, e.to_string()))
}

fn parse_daily(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<DailyWindow, InputError> {
    let obj = expect_object(ctx, v, field, "a schedule entry")?;
    for key in ["startEvent", "endEvent"] {
        if member(obj, key).is_some() {
            return Err(ctx.err(
                &join(field, key),
                "daylight events (SR, SS, BMCT, EECT) are not supported; give startTime and \
                 endTime with a UTC offset",
            ));
        }
    }
    let Some((day_key, days_v)) = one_of(ctx, obj, &["day", "days"], field)? else {
        return Err(ctx.err(
            &join(field, "day"),
            "missing: list the days, e.g. [\"ANY\"]",
        ));
    };
    let day_field = join(field, day_key);
    let day_items = list_of(days_v);
    if day_items.is_empty() {
        return Err(ctx.err(&day_field, "no days given; use [\"ANY\"] for every day"));
    }
    let mut days = Vec::new();
    for (k, d) in day_items.iter().enumerate() {
        let name = d.as_str().unwrap_or_default();
        if name.trim().eq_ignore_ascii_case("ANY") {
            days.extend(Weekday::ALL);
        } else if let Some(day) = Weekday::ALL
            .into_iter()
            .find(|w| w.as_str().eq_ignore_ascii_case(name.trim()))
        {
            days.push(day);
        } else {
            return Err(ctx.err(
                &format!("{day_field}[{k}]"),
                format!(
                    "unknown day {}: expected ANY, MON, TUE, WED, THU, FRI, SAT or SUN",
                    show(d)
                ),
            ));
        }
    }
    days.sort_unstable();
    days.dedup();
    let (start, offset) = parse_clock_with_offset(ctx, obj, "startTime", field)?;
    let (end, end_offset) = parse_clock_with_offset(ctx, obj, "endTime", field)?;
    if start.0 >= DAY_MS {
        return Err(ctx.err(
            &join(field, "startTime"),
            "a schedule cannot start at 24:00; use 00:00",
        ));
    }
    let end = if end_offset == offset {
        end
    } else {
        // Same instant of day, stated in the start time's offset.
        let shifted = (end.0 + i64::from(offset.0 - end_offset.0) * 1_000).rem_euclid(DAY_MS);
        Millis(if shifted == 0 { DAY_MS } else { shifted })
    };
    Ok(DailyWindow {
        days,
        start,
        end,
        offset,
    })
}

fn parse_clock_with_offset(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    key: &str,
    prefix: &str,
) -> Result<(Millis, UtcOffset), InputError> {
    let field = join(prefix, key);
    let Some(v) = member(obj, key) else {
        return Err(ctx.err(
            &field,
            format!("missing: a schedule entry needs `{key}`, e.g. \"10:00:00+08:00\""),
        ));
    };
    let text = v
        .as_str()
        .ok_or_else(|| {
            ctx.err(
                &field,
                format!(
                    "expected a time such as \"10:00:00+08:00\", got {}",
                    show(v)
                ),
            )
        })?
        .trim();
    let Some(split) = text.find(['+', '-', 'Z', 'z']) else {
        return Err(ctx.err(
            &field,
            format!(
                "`{text}` has no UTC offset: daily schedule times must state one, e.g. \
                 \"{text}+08:00\" or \"{text}Z\""
            ),
        ));
    };
    let clock = parse_clock(&text[..split]).map_err(|e| ctx.err(&field, e.to_string()))?;
    let offset = UtcOffset::parse(&text[split..]).map_err(|e| ctx.err(&field, e.to_string()))?;
    Ok((clock, offset))
}

// ---------------------------------------------------------------------------------------------
// Geometry.
// ---------------------------------------------------------------------------------------------

/// One horizontal area of a zone, before polygons are merged.
pub(crate) enum Part {
    Polygon(Polygon<f64>),
    Circle(LonLat, f64),
}

/// A `[lon, lat]` position (a third value, altitude, is ignored).
pub(crate) fn parse_position(
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
pub(crate) fn parse_polygon(
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
pub(crate) fn parse_multipolygon(
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
pub(crate) fn parse_radius(
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

/// Builds the zone(s) of one feature: all polygons form one area, each circle another; more
/// than one area gives one zone per area (`ID#1`, `ID#2`, …, explicit ids on the first).
pub(crate) fn assemble(
    ctx: &Ctx<'_>,
    id: String,
    common: Common,
    parts: Vec<Part>,
    geometry_field: &str,
) -> Result<Vec<Zone>, InputError> {
    if parts.is_empty() && common.node_ids.is_empty() && common.edge_ids.is_empty() {
        return Err(ctx.err(
            geometry_field,
            "missing: a zone needs a geometry or explicit `nodes` / `edges` lists",
        ));
    }
    let mut polygons = Vec::new();
    let mut areas = Vec::new();
    for part in parts {
        match part {
            Part::Polygon(p) => polygons.push(p),
            Part::Circle(centre, radius_m) => areas.push(ZoneArea::Circle { centre, radius_m }),
        }
    }
    if !polygons.is_empty() {
        areas.insert(0, ZoneArea::Polygons(MultiPolygon(polygons)));
    }
    let Common {
        name,
        restriction,
        node_ids,
        edge_ids,
        periods,
        announced,
    } = common;
    if areas.len() <= 1 {
        return Ok(vec![Zone {
            id,
            name,
            restriction,
            area: areas.pop(),
            node_ids,
            edge_ids,
            periods,
            announced,
        }]);
    }
    Ok(areas
        .into_iter()
        .enumerate()
        .map(|(k, area)| Zone {
            id: format!("{id}#{}", k + 1),
            name: name.clone(),
            restriction: restriction.clone(),
            area: Some(area),
            node_ids: if k == 0 { node_ids.clone() } else { Vec::new() },
            edge_ids: if k == 0 { edge_ids.clone() } else { Vec::new() },
            periods: periods.clone(),
            announced,
        })
        .collect())
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // Exact values are the point of these tests.
mod tests;
