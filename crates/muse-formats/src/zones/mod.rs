//! No-fly zones: the EUROCAE ED-318 `GeoJSON` profile (native) and ED-269 JSON
//! (docs/reference.md#no-fly-zones).
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
//!   `PROHIBITED`, `REQ_AUTHORISATION`, …, see [`ZONE_TYPES`]): kept as text (MUSE closes
//!   the airspace whatever it says; `PROHIBITED` when neither is given);
//! - `properties.limitedApplicability` (or `applicability`): time periods, see below;
//! - `properties.announced`, `properties.withdrawn` (MUSE extensions,
//!   docs/reference.md#zones-announced-during-the-day): see below;
//! - `geometry`: `Polygon`, `MultiPolygon`, a `Point` with an `extent`
//!   `{"subType": "Circle", "radius": <metres>}` (the extent may sit on the geometry, the
//!   feature or the properties; an optional `uom` / `uomDimensions` of `M`, `FT` or `NM`
//!   converts the radius), or a `GeometryCollection` of those;
//! - `geometry.layer` (ED-318's vertical layer, on each geometry): `{"upper", "upperReference",
//!   "lower", "lowerReference", "uom"}`, the zone's vertical band (see below). A `layer` on a
//!   `GeometryCollection` is the band of its members that carry none. MUSE extension: a zone
//!   with explicit `nodes` / `edges` and no geometry gives its band as `properties.layer`
//!   (what [`write_ed318`] writes for it); with a geometry, `properties.layer` is an error.
//! - `properties.lowerLimit`, `properties.upperLimit` (ED-269's names, with `uomDimensions`,
//!   `lowerVerticalReference` and `upperVerticalReference`): read exactly as an ED-269
//!   volume's (below), the band of every geometry without a `layer` (or of a zone without
//!   geometry). A `layer` (on the geometry or in the properties) giving another band is an
//!   error: the file says two things.
//!
//! # ED-269 JSON
//!
//! An object with a `features` or `UASZoneList` array of zones (or a bare array). Per zone:
//! `identifier`, `name`, `restriction`, `applicability`, `announced`, `withdrawn` (see below) and
//! `geometry`: a list of volumes whose `horizontalProjection` is `{"type": "Polygon", "coordinates": [[[lon, lat], …]]}` or
//! `{"type": "Circle", "center": [lon, lat], "radius": r}`, `r` in the volume's
//! `uomDimensions` (`M` by default, or `FT`), and whose vertical band is `lowerLimit`,
//! `upperLimit` (in `uomDimensions`: `M` or `FT` when a limit is given),
//! `lowerVerticalReference`, `upperVerticalReference` (see below).
//!
//! # Shared rules
//!
//! - Positions are `[longitude, latitude]` in WGS84 degrees (a third value, altitude, is
//!   ignored). Rings have at least 4 positions and are closed (first = last).
//! - Vertical limits (docs/reference.md#layered-airspace) become the zone's
//!   [`VerticalLimits`](muse_model::VerticalLimits): heights are numbers (or numeric strings) ≥ 0
//!   in metres or feet (`M`, `FT`, any case, metres when no unit is given; 1 ft = 0.3048 m
//!   exactly), kept to the micrometre; a missing or `null` side is open, and a zone without limits
//!   covers the whole sky. References are `AGL`, `AMSL` or `WGS84` (any case; `SFC` and `GND` read
//!   as `AGL`, `MSL` as `AMSL`, `W84` as `WGS84`; `AGL` when not given): MUSE flies over flat
//!   ground at sea level, so all measure the same heights; the reference is kept to show and write.
//!   A height that is not a number, negative or beyond 10⁹ m, an unknown unit or reference
//!   (pressure altitudes, `STD`, are not supported), and a lower limit above the upper one are
//!   errors. MUSE flying one cruise altitude, a zone still closes what it covers whatever its band;
//!   with layers, only the layers in its band.
//! - A time period is `{startDateTime?, endDateTime?, schedule?}` (ED-269 also
//!   `permanent` and `dailyPeriod`). Date-times are RFC 3339 with an offset. A `schedule`
//!   entry is `{"day": ["ANY" | "MON" … "SUN"], "startTime": "10:00:00+08:00",
//!   "endTime": "12:00:00+08:00"}`: clock times `HH:MM[:SS[.mmm]]` **with** a UTC offset
//!   (`+08:00`, `Z`); a time without one is an error, since it would be ambiguous.
//!   `endTime` may be `24:00`. A window that runs past midnight (its end before its start)
//!   must say so with the MUSE extension `"overnight": true` in its entry; without it such an
//!   end is an error, and so is an end equal to the start. Daylight events (`startEvent`,
//!   `endEvent`) are not supported and are an error.
//! - The zone type (ED-318 `type` or `restriction`, ED-269 `restriction`) is one of
//!   [`ZONE_TYPES`]; any other is an error. [`read_zones_file`] refuses a file with no zone.
//! - A zone with no period, or with a period that has no bounds and no schedule (e.g. ED-269
//!   `permanent: "YES"`), is permanent.
//! - MUSE extension: `nodes: ["S001", …]` and `edges: ["S001-S002", …]` list airspace
//!   elements closed explicitly (the paper's `V_nfz` and `E_nfz`); a zone may have only these
//!   and no geometry. The ids are checked later, against an airspace.
//! - MUSE extension (docs/reference.md#zones-announced-during-the-day): `announced`, an RFC 3339
//!   date-time with an offset, is when the zone becomes known during the day; it binds flights from
//!   that instant on. Without it (or with `null`) the zone is known from the start. A value that is
//!   not such a date-time (no offset, finer than a millisecond, not a string) is an error on field
//!   `announced`.
//! - MUSE extension (docs/reference.md#zones-announced-during-the-day, written by the service's
//!   `GET /v1/zones`): `withdrawn`, an RFC 3339 date-time, is when an announced zone was withdrawn;
//!   from then on it binds nothing (it binds the stays and traversals that begin in `[announced,
//!   withdrawn)`). It needs `announced` and may not be before it; `null` means not withdrawn.
//! - A zone whose areas cannot be one [`ZoneArea`] with one vertical band (several circles,
//!   circles and polygons, e.g. an ED-269 zone with several volumes, or polygons at different
//!   heights, e.g. ED-318's "inverted wedding cake" of geometries with different `layer`s)
//!   becomes one zone per area, with ids `ID#1`, `ID#2`, …, each with its own band: all
//!   polygons of one band form one area. Explicit `nodes` / `edges` go with the first.
//!
//! The reader is split by concept into private modules: `time` (periods, daily windows,
//! date-times), `geometry` (positions, rings, polygons, circles, assembling a zone's areas),
//! `vertical` (vertical limits), `properties` (the fields every zone has), and one module per
//! format.
//!
//! Every problem is an [`InputError`] naming the file, the feature (index and id) and the
//! field, e.g. `limitedApplicability[0].schedule[1].startTime`, `geometry.coordinates[0]` or
//! `geometry[0].upperLimit`.

use std::collections::HashMap;
use std::path::Path;

use geo_types::Coord;
use muse_model::{Zone, ZoneArea};
use serde_json::{Map, Value};

use crate::{InputError, Location};

mod ed269;
mod ed318;
mod geometry;
mod properties;
mod time;
mod vertical;

pub use ed318::write_ed318;
pub use properties::ZONE_TYPES;

/// Decimals of degrees kept by [`write_ed318`] (and [`normalize`]): 7, about 1 cm.
pub const COORDINATE_DECIMALS: i32 = 7;

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

/// Reads a zone file from disk (see [`read_zones`]); errors name the path. A file holding no
/// zone is an error: a zone file given by a user that closes nothing is more likely the wrong
/// file than a wish for no zones (which `--zones none` says).
pub fn read_zones_file(path: &Path) -> Result<Vec<Zone>, InputError> {
    let text = crate::read_to_string(path)?;
    let file = path.display().to_string();
    let zones = read_zones(&text, &file)?;
    if zones.is_empty() {
        return Err(InputError::new(
            file,
            Location::Whole,
            None,
            "the file holds no zone (no features): give a file with at least one zone, or \
             `--zones none` for none",
        ));
    }
    Ok(zones)
}

/// The zones of several files read in order (`--zones a.json --zones b.json`), each zone id
/// once across them all: a zone id from two files (or one file given twice) would make two
/// zones of one name, which every output and the service tell apart by name only.
///
/// ```
/// use muse_formats::zones::ZoneFiles;
/// let dir = std::env::temp_dir().join(format!("muse-zone-files-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let zone = r#"{"type": "Feature", "properties": {"identifier": "X", "nodes": ["S001"]},
///                "geometry": null}"#;
/// let (a, b) = (dir.join("a.json"), dir.join("b.json"));
/// std::fs::write(&a, zone).unwrap();
/// std::fs::write(&b, zone).unwrap();
/// let mut files = ZoneFiles::default();
/// files.add(&a).unwrap();
/// let e = files.add(&b).unwrap_err().to_string();
/// assert!(e.contains("b.json: zone `X` is also in ") && e.contains("a.json"), "{e}");
/// assert_eq!(files.into_zones().len(), 1);
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
#[derive(Debug, Default)]
pub struct ZoneFiles {
    zones: Vec<Zone>,
    /// The file each zone id came from.
    files: HashMap<String, String>,
}

impl ZoneFiles {
    /// Reads the zone file `path` ([`read_zones_file`]) and adds its zones.
    ///
    /// # Errors
    /// Those of [`read_zones_file`]; a zone whose id an earlier file gave, naming the zone and
    /// both files (nothing of the file is added then).
    pub fn add(&mut self, path: &Path) -> Result<(), InputError> {
        let zones = read_zones_file(path)?;
        let file = path.display().to_string();
        if let Some((zone, first)) = zones
            .iter()
            .find_map(|z| self.files.get(&z.id).map(|first| (z, first)))
        {
            let twice = if *first == file {
                " (the file is given twice)"
            } else {
                ""
            };
            return Err(InputError::new(
                file.as_str(),
                Location::Whole,
                None,
                format!(
                    "zone `{}` is also in {first}{twice}: a zone id may be used once across \
                     the zone files; rename one of them or give each file once",
                    zone.id
                ),
            ));
        }
        for zone in &zones {
            self.files.insert(zone.id.clone(), file.clone());
        }
        self.zones.extend(zones);
        Ok(())
    }

    /// The zones of every file added, in order.
    pub fn into_zones(self) -> Vec<Zone> {
        self.zones
    }
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
///     node_ids: vec![], edge_ids: vec![], periods: vec![], announced: None, withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
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
    if zone.periods.iter().any(time::is_always) {
        zone.periods.clear();
    }
    zone
}

/// Rounds degrees to [`COORDINATE_DECIMALS`] decimals (idempotent).
pub(super) fn round_degrees(x: f64) -> f64 {
    let scale = 10_f64.powi(COORDINATE_DECIMALS);
    let r = (x * scale).round() / scale;
    if r == 0.0 { 0.0 } else { r }
}

fn round_coord(c: &mut Coord<f64>) {
    c.x = round_degrees(c.x);
    c.y = round_degrees(c.y);
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

#[cfg(test)]
#[allow(clippy::float_cmp)] // Exact values are the point of these tests.
mod tests;
