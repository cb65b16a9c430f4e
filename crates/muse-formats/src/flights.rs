//! Planned flights as GeoJSON, for QGIS and kepler.gl.
//!
//! One `LineString` feature per planned flight. Its vertices are the stays of the plan in
//! order — two vertices at the same position when the drone hovers (arrival, then departure)
//! — and each position is `[lon, lat, 0, t]` with `t` the instant in Unix seconds (with
//! milliseconds): the layout kepler.gl's Trips layer animates, and that QGIS reads as a
//! measure. The same instants are in the `times` property as RFC 3339 text. Properties:
//! `request`, `origin`, `destination`, `takeoff`, `landing`, `airborne_s`, `air_delay_s`,
//! `ground_delay_s`, `nodes`, `times`.

use std::fmt::Write as _;

use muse_model::{Airspace, Millis, Plan, UtcOffset};
use serde_json::{Value, json};

/// A planned flight to draw.
#[derive(Clone, Copy, Debug)]
pub struct FlightFeature<'a> {
    /// Request id.
    pub request: &'a str,
    /// The plan.
    pub plan: &'a Plan,
    /// Requested departure.
    pub requested_departure: muse_model::Instant,
    /// Free-flow time, for the air delay.
    pub free_flow: Option<Millis>,
}

/// Writes the flights as a GeoJSON FeatureCollection, one feature per line.
///
/// ```
/// use muse_formats::flights::{write_flights, FlightFeature};
/// use muse_model::{Instant, NodeId, Plan, Stay, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.81, 1.3]]}, "properties": {"from": "A", "to": "B"}}]}"#, "a").unwrap();
/// let plan = Plan { path: vec![
///     Stay { node: NodeId(0), arrive: Instant(0), depart: Instant(5_000) },
///     Stay { node: NodeId(1), arrive: Instant(139_000), depart: Instant(139_000) },
/// ] };
/// let f = FlightFeature { request: "r1", plan: &plan, requested_departure: Instant(0), free_flow: None };
/// let text = write_flights(&[f], &air, UtcOffset::SINGAPORE);
/// assert!(text.contains(r#""coordinates":[[103.8,1.3,0,0.0],[103.8,1.3,0,5.0],[103.81,1.3,0,139.0]]"#));
/// ```
pub fn write_flights(
    flights: &[FlightFeature<'_>],
    airspace: &Airspace,
    offset: UtcOffset,
) -> String {
    let mut out = String::from("{\"type\": \"FeatureCollection\", \"features\": [\n");
    for (i, f) in flights.iter().enumerate() {
        let mut coords = Vec::with_capacity(f.plan.path.len() * 2);
        let mut times = Vec::with_capacity(f.plan.path.len() * 2);
        let mut nodes = Vec::with_capacity(f.plan.path.len());
        for stay in &f.plan.path {
            let node = airspace.node(stay.node);
            nodes.push(Value::String(node.id.clone()));
            let mut instants = vec![stay.arrive];
            if stay.depart > stay.arrive {
                instants.push(stay.depart);
            }
            for t in instants {
                coords.push(json!([node.pos.lon, node.pos.lat, 0, t.0 as f64 / 1e3]));
                times.push(Value::String(t.to_rfc3339(offset)));
            }
        }
        let p = f.plan;
        let feature = json!({
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": coords},
            "properties": {
                "request": f.request,
                "origin": nodes.first().cloned().unwrap_or(Value::Null),
                "destination": nodes.last().cloned().unwrap_or(Value::Null),
                "takeoff": p.takeoff().to_rfc3339(offset),
                "landing": p.landing().to_rfc3339(offset),
                "airborne_s": p.airborne().as_secs_f64(),
                "air_delay_s": f.free_flow.map(|ff| (p.airborne() - ff).as_secs_f64()),
                "ground_delay_s": (p.takeoff() - f.requested_departure).as_secs_f64(),
                "nodes": nodes,
                "times": times,
            }
        });
        if i > 0 {
            out.push_str(",\n");
        }
        let _ = write!(out, "{feature}");
    }
    out.push_str("\n]}\n");
    out
}
