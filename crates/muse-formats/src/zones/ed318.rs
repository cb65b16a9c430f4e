//! The EUROCAE ED-318 `GeoJSON` profile: reading one feature, and writing zones.

use geo_types::{LineString, Polygon};
use muse_model::{DailyWindow, Millis, UtcOffset, VerticalLimits, Weekday, Zone, ZoneArea};
use serde::Serialize;
use serde_json::{Map, Value};

use super::geometry::{
    Part, assemble, parse_multipolygon, parse_polygon, parse_position, parse_radius,
};
use super::properties::parse_common;
use super::vertical::{agreeing, parse_layer, parse_properties_limits};
use super::{Ctx, expect_object, join, member, normalize, parse_identifier, round_degrees, show};
use crate::InputError;

/// Reads one ED-318 feature (usually one zone; see [`assemble`]).
pub(super) fn read_feature(file: &str, index: usize, v: &Value) -> Result<Vec<Zone>, InputError> {
    let mut ctx = Ctx::new(file, index);
    let feature = expect_object(&ctx, v, "", "a feature")?;
    if let Some(kind) = member(feature, "type")
        && kind.as_str() != Some("Feature")
    {
        return Err(ctx.err("type", format!("expected \"Feature\", got {}", show(kind))));
    }
    let Some(props_v) = member(feature, "properties") else {
        return Err(ctx.err(
            "properties",
            "missing: the zone's properties (identifier, name, …)",
        ));
    };
    let props = expect_object(&ctx, props_v, "properties", "`properties`")?;
    let id = match (member(props, "identifier"), member(feature, "id")) {
        (Some(v), _) => parse_identifier(&ctx, v, "identifier")?,
        (None, Some(v)) => parse_identifier(&ctx, v, "id")?,
        (None, None) => return Err(ctx.err("identifier", "missing: the zone's identifier")),
    };
    ctx.id = Some(id.clone());
    let common = parse_common(&ctx, props, &["restriction", "type"])?;
    // ED-269's `lowerLimit` / `upperLimit` in the properties: the band of every geometry
    // without a `layer` of its own (one that gives another is refused).
    let given = parse_properties_limits(&ctx, props)?;
    let mut parts = Vec::new();
    let geometry_v = member(feature, "geometry");
    if let Some(g) = geometry_v {
        let around = Around {
            feature,
            props,
            given,
        };
        let band = given.unwrap_or(VerticalLimits::WHOLE_SKY);
        geometry(&ctx, g, "geometry", &around, band, &mut parts)?;
    }
    // MUSE extension: the band of a zone with explicit elements only sits in its properties
    // (what `write_ed318` writes for such a zone).
    let bare = match (member(props, "layer"), geometry_v) {
        (None, _) => given.unwrap_or(VerticalLimits::WHOLE_SKY),
        (Some(layer), None) => agreeing(&ctx, parse_layer(&ctx, layer, "layer")?, given, "layer")?,
        (Some(_), Some(_)) => {
            return Err(ctx.err(
                "layer",
                "a zone with a geometry gives its vertical limits on the geometry \
                 (`geometry.layer`, ED-318); `properties.layer` is only for a zone with \
                 explicit `nodes` / `edges` and no geometry",
            ));
        }
    };
    assemble(&ctx, id, common, parts, bare, "geometry")
}

/// What a feature's geometries are read in: the feature, its properties, and the limits
/// its properties give.
struct Around<'a> {
    feature: &'a Map<String, Value>,
    props: &'a Map<String, Value>,
    given: Option<VerticalLimits>,
}

/// Reads a `GeoJSON` geometry (with the ED-318 circle extension) into `parts`, each with its
/// vertical band: the geometry's `layer`, else `band` (the enclosing collection's, else the
/// properties' limits, else the whole sky).
fn geometry(
    ctx: &Ctx<'_>,
    v: &Value,
    field: &str,
    around: &Around<'_>,
    band: VerticalLimits,
    parts: &mut Vec<(Part, VerticalLimits)>,
) -> Result<(), InputError> {
    let (feature, props) = (around.feature, around.props);
    let g = expect_object(ctx, v, field, "a geometry")?;
    let band = match member(g, "layer") {
        Some(layer) => {
            let layer_field = join(field, "layer");
            let layer = parse_layer(ctx, layer, &layer_field)?;
            agreeing(ctx, layer, around.given, &layer_field)?
        }
        None => band,
    };
    let kind_field = join(field, "type");
    let kind =
        member(g, "type").ok_or_else(|| ctx.err(&kind_field, "missing: the geometry type"))?;
    let coordinates = || {
        member(g, "coordinates").ok_or_else(|| {
            ctx.err(
                &join(field, "coordinates"),
                "missing: the geometry's coordinates",
            )
        })
    };
    let coord_field = join(field, "coordinates");
    match kind.as_str() {
        Some("Polygon") => parts.push((
            Part::Polygon(parse_polygon(ctx, coordinates()?, &coord_field)?),
            band,
        )),
        Some("MultiPolygon") => parts.extend(
            parse_multipolygon(ctx, coordinates()?, &coord_field)?
                .into_iter()
                .map(|p| (Part::Polygon(p), band)),
        ),
        Some("Point") => {
            let c = parse_position(ctx, coordinates()?, &coord_field)?;
            let (extent, extent_field) = [(g, join(field, "extent")), (feature, "extent".into()), (props, "extent".into())]
                .into_iter()
                .find_map(|(obj, f)| member(obj, "extent").map(|e| (e, f)))
                .ok_or_else(|| {
                    ctx.err(
                        &join(field, "extent"),
                        "missing: a Point zone needs an extent {\"subType\": \"Circle\", \"radius\": <metres>}",
                    )
                })?;
            let radius = circle_extent(ctx, extent, &extent_field)?;
            parts.push((
                Part::Circle(muse_model::LonLat::new(c.x, c.y), radius),
                band,
            ));
        }
        Some("GeometryCollection") => {
            let gf = join(field, "geometries");
            let items = member(g, "geometries")
                .and_then(Value::as_array)
                .ok_or_else(|| {
                    ctx.err(
                        &gf,
                        "missing: a GeometryCollection needs a `geometries` array",
                    )
                })?;
            for (i, item) in items.iter().enumerate() {
                geometry(ctx, item, &format!("{gf}[{i}]"), around, band, parts)?;
            }
        }
        _ => {
            return Err(ctx.err(
                &kind_field,
                format!(
                    "unsupported geometry type {}: expected Polygon, MultiPolygon, a Point with a \
                     circle extent, or a GeometryCollection of those",
                    show(kind)
                ),
            ));
        }
    }
    Ok(())
}

/// `{"subType": "Circle", "radius": r, "uom"?: "M" | "FT" | "NM"}` → metres.
fn circle_extent(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<f64, InputError> {
    let e = expect_object(ctx, v, field, "an extent")?;
    match member(e, "subType").and_then(Value::as_str) {
        Some(s) if s.eq_ignore_ascii_case("Circle") => {}
        _ => {
            return Err(ctx.err(
                &join(field, "subType"),
                format!(
                    "expected \"Circle\", got {}",
                    member(e, "subType").map_or_else(|| "nothing".into(), show)
                ),
            ));
        }
    }
    let uom = ["uom", "uomDimensions"]
        .into_iter()
        .find_map(|k| member(e, k).map(|u| (u, join(field, k))));
    parse_radius(ctx, member(e, "radius"), &join(field, "radius"), uom)
}

// ---------------------------------------------------------------------------------------------
// Writing.
// ---------------------------------------------------------------------------------------------

/// Writes zones as an ED-318 `GeoJSON` `FeatureCollection`: pretty-printed with a 2-space indent
/// (positions on one line), keys in a fixed order, a trailing newline, byte-identical for equal
/// input.
///
/// Per zone: `identifier`, `name` (as the ED-318 list `[{"text", "lang": "en"}]`, omitted when
/// empty), `type` (the zone's restriction), `variant: "COMMON"`, `limitedApplicability` (omitted
/// for a permanent zone), the MUSE extensions `announced` (omitted for a zone known from the
/// start), `withdrawn` (omitted unless the zone was withdrawn) and `nodes` / `edges` (omitted
/// when empty); the geometry is a `Polygon`, a
/// `MultiPolygon`, a `Point` with a circle `extent` (radius in metres), or `null` for a zone
/// with explicit elements only. A zone's vertical band, unless it is the whole sky, is the
/// geometry's ED-318 `layer` `{"upper", "upperReference", "lower", "lowerReference", "uom":
/// "m"}` (heights in metres, exact to the micrometre, an open side left out); for a zone
/// without geometry, the same `layer` in its properties (MUSE extension). Date-times are written in the offset of the period's first
/// daily window (UTC when it has none; `announced` and `withdrawn` in the offset of the zone's
/// first daily window, else UTC), clock times as `HH:MM:SS[.mmm]` with their offset, all seven
/// days as `["ANY"]`, and a daily window that ends the next day with `"overnight": true`.
///
/// What is written is each zone's [`normalize`]d form: coordinates rounded to 7 decimals of a
/// degree (about 1 cm, see [`COORDINATE_DECIMALS`](super::COORDINATE_DECIMALS)), days sorted,
/// a zone with an unbounded, unscheduled period written as permanent. Radii are written
/// exactly. ED-318's `country` and `zoneAuthority` are not written: MUSE does not model them.
///
/// [`read_zones`](super::read_zones) reads the output back to the normalized zones, and
/// writing those again gives the same bytes.
///
/// ```
/// use muse_formats::zones::{read_zones, write_ed318};
/// use muse_model::{DailyWindow, Metres, Millis, Period, UtcOffset, VerticalLimits, Weekday, Zone, ZoneArea};
/// use geo_types::polygon;
/// let cbd = Zone {
///     id: "CBD".into(),
///     name: "Downtown Core".into(),
///     restriction: "PROHIBITED".into(),
///     area: Some(ZoneArea::Polygons(polygon![
///         (x: 103.84, y: 1.27), (x: 103.86, y: 1.27), (x: 103.86, y: 1.29), (x: 103.84, y: 1.27)
///     ].into())),
///     node_ids: vec![],
///     announced: None, withdrawn: None,
///     // Up to 400 ft above ground.
///     vertical: VerticalLimits::agl(None, Some(Metres::from_ft(400.0).unwrap())),
///     edge_ids: vec![],
///     periods: vec![Period {
///         start: None,
///         end: None,
///         daily: vec![DailyWindow {
///             days: Weekday::ALL.to_vec(),
///             start: Millis::from_secs(10 * 3600),
///             end: Millis::from_secs(12 * 3600),
///             offset: UtcOffset::SINGAPORE,
///         }],
///     }],
/// };
/// let text = write_ed318(std::slice::from_ref(&cbd));
/// assert!(text.contains(r#""startTime": "10:00:00+08:00""#));
/// assert!(text.contains(r#""upper": 121.92,"#) && text.contains(r#""uom": "m""#));
/// assert_eq!(read_zones(&text, "cbd.geojson").unwrap(), vec![cbd]);
/// ```
pub fn write_ed318(zones: &[Zone]) -> String {
    let zones: Vec<Zone> = zones.iter().map(normalize).collect();
    let collection = CollectionOut {
        kind: "FeatureCollection",
        features: zones.iter().map(feature_out).collect(),
    };
    let pretty = serde_json::to_string_pretty(&collection)
        .expect("serializing plain structs with string keys cannot fail");
    compact_short_arrays(&pretty)
}

#[derive(Serialize)]
struct CollectionOut<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    features: Vec<FeatureOut<'a>>,
}

#[derive(Serialize)]
struct FeatureOut<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    properties: PropertiesOut<'a>,
    geometry: Option<GeometryOut>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct PropertiesOut<'a> {
    identifier: &'a str,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    name: Vec<TextOut<'a>>,
    #[serde(rename = "type")]
    zone_type: &'a str,
    variant: &'static str,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    limited_applicability: Vec<PeriodOut>,
    #[serde(skip_serializing_if = "Option::is_none")]
    announced: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    withdrawn: Option<String>,
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    nodes: &'a [String],
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    edges: &'a [String],
    /// The band of a zone without geometry (MUSE extension; otherwise on the geometry).
    #[serde(skip_serializing_if = "Option::is_none")]
    layer: Option<LayerOut>,
}

#[derive(Serialize)]
struct TextOut<'a> {
    text: &'a str,
    lang: &'static str,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct PeriodOut {
    #[serde(skip_serializing_if = "Option::is_none")]
    start_date_time: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    end_date_time: Option<String>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    schedule: Vec<DailyOut>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct DailyOut {
    day: Vec<&'static str>,
    start_time: String,
    end_time: String,
    /// A window ending the next day says so (the reader requires it).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    overnight: bool,
}

#[derive(Serialize)]
#[serde(tag = "type")]
enum GeometryOut {
    Polygon {
        coordinates: Vec<Vec<[f64; 2]>>,
        #[serde(skip_serializing_if = "Option::is_none")]
        layer: Option<LayerOut>,
    },
    MultiPolygon {
        coordinates: Vec<Vec<Vec<[f64; 2]>>>,
        #[serde(skip_serializing_if = "Option::is_none")]
        layer: Option<LayerOut>,
    },
    Point {
        coordinates: [f64; 2],
        extent: ExtentOut,
        #[serde(skip_serializing_if = "Option::is_none")]
        layer: Option<LayerOut>,
    },
}

/// An ED-318 vertical layer, the members in the standard's order; an open side is left out.
#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct LayerOut {
    #[serde(skip_serializing_if = "Option::is_none")]
    upper: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    upper_reference: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lower: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lower_reference: Option<&'static str>,
    uom: &'static str,
}

/// The `layer` of a band, `None` for the whole sky.
fn layer_out(band: &VerticalLimits) -> Option<LayerOut> {
    (!band.is_whole_sky()).then(|| LayerOut {
        upper: band.upper.map(|u| u.height.m()),
        upper_reference: band.upper.map(|u| u.reference.as_str()),
        lower: band.lower.map(|l| l.height.m()),
        lower_reference: band.lower.map(|l| l.reference.as_str()),
        uom: "m",
    })
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct ExtentOut {
    sub_type: &'static str,
    radius: f64,
}

fn feature_out(zone: &Zone) -> FeatureOut<'_> {
    let name = if zone.name.is_empty() {
        Vec::new()
    } else {
        vec![TextOut {
            text: &zone.name,
            lang: "en",
        }]
    };
    FeatureOut {
        kind: "Feature",
        properties: PropertiesOut {
            identifier: &zone.id,
            name,
            zone_type: &zone.restriction,
            variant: "COMMON",
            limited_applicability: zone.periods.iter().map(period_out).collect(),
            announced: zone.announced.map(|t| t.to_rfc3339(zone_offset(zone))),
            withdrawn: zone.withdrawn.map(|t| t.to_rfc3339(zone_offset(zone))),
            nodes: &zone.node_ids,
            edges: &zone.edge_ids,
            layer: if zone.area.is_none() {
                layer_out(&zone.vertical)
            } else {
                None
            },
        },
        geometry: zone
            .area
            .as_ref()
            .map(|area| geometry_out(area, &zone.vertical)),
    }
}

/// The offset date-times are written in: the first daily window's, else UTC.
fn zone_offset(zone: &Zone) -> UtcOffset {
    zone.periods
        .iter()
        .find_map(|p| p.daily.first())
        .map_or(UtcOffset(0), |d| d.offset)
}

fn period_out(p: &muse_model::Period) -> PeriodOut {
    let offset = p.daily.first().map_or(UtcOffset(0), |d| d.offset);
    PeriodOut {
        start_date_time: p.start.map(|t| t.to_rfc3339(offset)),
        end_date_time: p.end.map(|t| t.to_rfc3339(offset)),
        schedule: p.daily.iter().map(daily_out).collect(),
    }
}

fn daily_out(d: &DailyWindow) -> DailyOut {
    let all = Weekday::ALL.iter().all(|w| d.days.contains(w));
    DailyOut {
        day: if all {
            vec!["ANY"]
        } else {
            d.days.iter().map(|w| w.as_str()).collect()
        },
        start_time: clock(d.start, d.offset),
        end_time: clock(d.end, d.offset),
        overnight: d.end <= d.start,
    }
}

/// `HH:MM:SS[.mmm]` followed by the offset, e.g. `10:00:00+08:00`.
fn clock(t: Millis, offset: UtcOffset) -> String {
    let ms = t.0;
    let (h, m, s, frac) = (
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1_000 % 60,
        ms % 1_000,
    );
    if frac == 0 {
        format!("{h:02}:{m:02}:{s:02}{offset}")
    } else {
        format!("{h:02}:{m:02}:{s:02}.{frac:03}{offset}")
    }
}

fn ring_out(ring: &LineString<f64>) -> Vec<[f64; 2]> {
    ring.0
        .iter()
        .map(|c| [round_degrees(c.x), round_degrees(c.y)])
        .collect()
}

fn polygon_out(p: &Polygon<f64>) -> Vec<Vec<[f64; 2]>> {
    std::iter::once(p.exterior())
        .chain(p.interiors())
        .map(ring_out)
        .collect()
}

fn geometry_out(area: &ZoneArea, band: &VerticalLimits) -> GeometryOut {
    let layer = layer_out(band);
    match area {
        ZoneArea::Polygons(mp) if mp.0.len() == 1 => GeometryOut::Polygon {
            coordinates: polygon_out(&mp.0[0]),
            layer,
        },
        ZoneArea::Polygons(mp) => GeometryOut::MultiPolygon {
            coordinates: mp.0.iter().map(polygon_out).collect(),
            layer,
        },
        ZoneArea::Circle { centre, radius_m } => GeometryOut::Point {
            coordinates: [round_degrees(centre.lon), round_degrees(centre.lat)],
            extent: ExtentOut {
                sub_type: "Circle",
                radius: *radius_m,
            },
            layer,
        },
    }
}

/// Puts arrays of scalars (positions, day lists, short id lists) on one line when that line
/// stays within 100 columns. Works on `serde_json`'s pretty output, where an array of scalars
/// is an opening line ending in `[`, one scalar per line, and a closing `]` line.
fn compact_short_arrays(pretty: &str) -> String {
    const MAX_WIDTH: usize = 100;
    let lines: Vec<&str> = pretty.lines().collect();
    let mut out = String::with_capacity(pretty.len() + 1);
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line.ends_with('[') {
            let mut j = i + 1;
            let mut items = Vec::new();
            while let Some(next) = lines.get(j) {
                let t = next.trim();
                let t = t.strip_suffix(',').unwrap_or(t);
                if is_scalar(t) {
                    items.push(t);
                    j += 1;
                } else {
                    break;
                }
            }
            if let Some(close) = lines.get(j).map(|l| l.trim_start()) {
                let joined = items.join(", ");
                if !items.is_empty()
                    && close.starts_with(']')
                    && line.len() + joined.len() + close.len() <= MAX_WIDTH
                {
                    out.push_str(line);
                    out.push_str(&joined);
                    out.push_str(close);
                    out.push('\n');
                    i = j + 1;
                    continue;
                }
            }
        }
        out.push_str(line);
        out.push('\n');
        i += 1;
    }
    out
}

/// Whether a trimmed line of pretty JSON (without its trailing comma) is one scalar value.
fn is_scalar(t: &str) -> bool {
    (t.len() >= 2 && t.starts_with('"') && t.ends_with('"') && !t.contains("\": "))
        || matches!(t, "true" | "false" | "null")
        || (!t.is_empty()
            && t.bytes()
                .all(|b| b.is_ascii_digit() || b"+-.eE".contains(&b)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_text() {
        assert_eq!(
            clock(Millis(36_000_000), UtcOffset(28_800)),
            "10:00:00+08:00"
        );
        assert_eq!(clock(Millis(86_400_000), UtcOffset(0)), "24:00:00+00:00");
        assert_eq!(
            clock(Millis(36_001_005), UtcOffset(-19_800)),
            "10:00:01.005-05:30"
        );
    }

    #[test]
    fn compacts_positions_only() {
        let v = serde_json::json!({"a": [[1.5, 2.0], [3.0, -4.25]], "b": ["x", "y"], "c": []});
        let text = compact_short_arrays(&serde_json::to_string_pretty(&v).unwrap());
        assert!(
            text.contains("[\n    [1.5, 2.0],\n    [3.0, -4.25]\n  ]"),
            "{text}"
        );
        assert!(text.contains("\"b\": [\"x\", \"y\"]"), "{text}");
        let back: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, v);
    }
}
