//! Planned flights as GeoJSON, for QGIS and kepler.gl.
//!
//! One `LineString` feature per planned flight — per leg for a multi-leg trip
//! (docs/reference.md#multi-leg-trips), so that a map shows where the drone lands for a battery
//! swap. Its vertices are the stays of the plan (or leg) in order — two vertices at the same
//! position when the drone hovers (arrival, then departure) — and each position is `[lon, lat, 0,
//! t]` with `t` the instant in Unix seconds (with milliseconds): the layout kepler.gl's Trips layer
//! animates, and that QGIS reads as a measure. The same instants are in the `times` property as RFC
//! 3339 text. Properties: `request`, `origin`, `destination`, `takeoff`, `landing`, `airborne_s`,
//! `air_delay_s`, `ground_delay_s` (all of the trip as a whole: first take-off, last landing, the
//! time on the ground between legs included), `nodes` and `times` (the feature's own vertices). A
//! leg of a multi-leg trip adds `leg` (1 for the first) and `legs` (how many the trip has); a
//! single-leg flight has neither.
//!
//! In a layered airspace (docs/reference.md#layered-airspace) the third coordinate is the stay's
//! altitude in metres, `h_k` of its layer (a climb is two positions at the same place, one above
//! the other), the `nodes` are flat ids, and `layers` gives each node's layer. A flat airspace's
//! positions keep `0` there, and its features have no `layers`.

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

/// Writes the flights as a GeoJSON FeatureCollection, one feature per line (per leg for a
/// multi-leg trip).
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
    let mut first = true;
    for f in flights {
        for feature in features(f, airspace, offset) {
            if !first {
                out.push_str(",\n");
            }
            first = false;
            let _ = write!(out, "{feature}");
        }
    }
    out.push_str("\n]}\n");
    out
}

/// The features of one flight: one per leg (none for an empty plan).
fn features(f: &FlightFeature<'_>, airspace: &Airspace, offset: UtcOffset) -> Vec<Value> {
    let p = f.plan;
    let count = p.leg_count();
    let end = |stay: Option<&muse_model::Stay>| {
        stay.map_or(Value::Null, |s| {
            Value::String(airspace.flat().node(airspace.flat_node(s.node)).id.clone())
        })
    };
    let (origin, destination) = (end(p.path.first()), end(p.path.last()));
    p.legs()
        .enumerate()
        .map(|(k, leg)| {
            let mut coords = Vec::with_capacity(leg.len() * 2);
            let mut times = Vec::with_capacity(leg.len() * 2);
            let mut nodes = Vec::with_capacity(leg.len());
            let mut layers = Vec::with_capacity(leg.len());
            for stay in leg {
                let node = airspace.node(stay.node);
                let flat = airspace.flat().node(airspace.flat_node(stay.node));
                nodes.push(Value::String(flat.id.clone()));
                let k = airspace.node_layer(stay.node);
                layers.push(json!(k));
                let altitude = airspace
                    .layers()
                    .map_or_else(|| json!(0), |l| json!(l.altitude(k).m()));
                let mut instants = vec![stay.arrive];
                if stay.depart > stay.arrive {
                    instants.push(stay.depart);
                }
                for t in instants {
                    coords.push(json!([
                        node.pos.lon,
                        node.pos.lat,
                        altitude,
                        t.0 as f64 / 1e3
                    ]));
                    times.push(Value::String(t.to_rfc3339(offset)));
                }
            }
            let mut properties = json!({
                "request": f.request,
                "origin": origin,
                "destination": destination,
                "takeoff": p.takeoff().to_rfc3339(offset),
                "landing": p.landing().to_rfc3339(offset),
                "airborne_s": p.airborne().as_secs_f64(),
                "air_delay_s": f.free_flow.map(|ff| (p.airborne() - ff).as_secs_f64()),
                "ground_delay_s": (p.takeoff() - f.requested_departure).as_secs_f64(),
                "nodes": nodes,
                "times": times,
            });
            if airspace.layers().is_some() {
                properties["layers"] = Value::Array(layers);
            }
            if count > 1 {
                properties["leg"] = json!(k + 1);
                properties["legs"] = json!(count);
            }
            json!({
                "type": "Feature",
                "geometry": {"type": "LineString", "coordinates": coords},
                "properties": properties,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use muse_model::Instant;
    use muse_model::testing::plan;

    use super::*;
    use crate::airspace_geojson::read_airspace;

    fn air() -> Airspace {
        read_airspace(
            r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8089, 1.3]}, "properties": {"id": "B", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8178, 1.3]}, "properties": {"id": "C", "kind": "station"}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.8089, 1.3]]}, "properties": {"from": "A", "to": "B", "length_m": 1000}},
  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8089, 1.3], [103.8178, 1.3]]}, "properties": {"from": "B", "to": "C", "length_m": 1000}}]}"#,
            "a",
        )
        .unwrap()
    }

    #[test]
    fn single_leg_golden() {
        let plan = plan(&[
            (0, 1_000, 3_500),
            (1, 123_500, 123_500),
            (2, 243_500, 243_500),
        ]);
        let f = FlightFeature {
            request: "r1",
            plan: &plan,
            requested_departure: Instant(0),
            free_flow: Some(Millis(240_000)),
        };
        let text = write_flights(&[f, f], &air(), UtcOffset::SINGAPORE);
        assert_eq!(
            text,
            include_str!("../testdata/flights/single_leg.geojson"),
            "as before multi-leg trips"
        );
    }

    #[test]
    fn one_feature_per_leg() {
        // A -> B, on the ground at B from 121 s to 421 s, B -> C.
        let plan = plan(&[
            (0, 1_000, 1_000),
            (1, 121_000, 121_000),
            (1, 421_000, 423_000),
            (2, 543_000, 543_000),
        ]);
        let f = FlightFeature {
            request: "r1",
            plan: &plan,
            requested_departure: Instant(0),
            free_flow: Some(Millis(240_000)),
        };
        let text = write_flights(&[f], &air(), UtcOffset::SINGAPORE);
        let doc: Value = serde_json::from_str(&text).unwrap();
        let features = doc["features"].as_array().unwrap();
        assert_eq!(features.len(), 2);
        let coords = |i: usize| features[i]["geometry"]["coordinates"].clone();
        assert_eq!(
            coords(0),
            json!([[103.8, 1.3, 0, 1.0], [103.8089, 1.3, 0, 121.0]])
        );
        assert_eq!(
            coords(1),
            json!([
                [103.8089, 1.3, 0, 421.0],
                [103.8089, 1.3, 0, 423.0],
                [103.8178, 1.3, 0, 543.0]
            ])
        );
        let props = |i: usize| features[i]["properties"].clone();
        assert_eq!(
            (props(0)["leg"].clone(), props(0)["legs"].clone()),
            (json!(1), json!(2))
        );
        assert_eq!(
            (props(1)["leg"].clone(), props(1)["legs"].clone()),
            (json!(2), json!(2))
        );
        assert_eq!(props(1)["nodes"], json!(["B", "C"]));
        assert_eq!(props(1)["times"][0], json!("1970-01-01T08:07:01.000+08:00"));
        // The trip as a whole.
        for i in 0..2 {
            assert_eq!(props(i)["origin"], json!("A"));
            assert_eq!(props(i)["destination"], json!("C"));
            assert_eq!(props(i)["takeoff"], json!("1970-01-01T08:00:01.000+08:00"));
            assert_eq!(props(i)["landing"], json!("1970-01-01T08:09:03.000+08:00"));
            assert_eq!(props(i)["airborne_s"], json!(542.0));
            assert_eq!(props(i)["air_delay_s"], json!(302.0));
            assert_eq!(props(i)["ground_delay_s"], json!(1.0));
        }
    }

    #[test]
    fn layered_positions_carry_the_altitude() {
        let layers = muse_model::Layers {
            count: 2,
            ..muse_model::Layers::default()
        };
        let air = air().layered(&layers).unwrap();
        // A at layer 1, up to A@2 (node 3), along to B@2 (node 4), down to B (node 1).
        let climbing = plan(&[
            (0, 0, 0),
            (3, 1_829, 1_829),
            (4, 121_829, 122_829),
            (1, 124_658, 124_658),
        ]);
        let f = FlightFeature {
            request: "r1",
            plan: &climbing,
            requested_departure: Instant(0),
            free_flow: Some(Millis(120_000)),
        };
        let doc: Value =
            serde_json::from_str(&write_flights(&[f], &air, UtcOffset::SINGAPORE)).unwrap();
        let feature = &doc["features"][0];
        assert_eq!(
            feature["geometry"]["coordinates"],
            json!([
                [103.8, 1.3, 60.0, 0.0],
                [103.8, 1.3, 69.144, 1.829],
                [103.8089, 1.3, 69.144, 121.829],
                [103.8089, 1.3, 69.144, 122.829],
                [103.8089, 1.3, 60.0, 124.658]
            ])
        );
        let props = &feature["properties"];
        assert_eq!(props["nodes"], json!(["A", "A", "B", "B"]));
        assert_eq!(props["layers"], json!([1, 2, 2, 1]));
        assert_eq!(
            (&props["origin"], &props["destination"]),
            (&json!("A"), &json!("B"))
        );
        // Flat: no `layers`, altitude 0 (the golden file of `single_leg_golden`).
        let flat_plan = plan(&[(0, 0, 0), (1, 120_000, 120_000)]);
        let f = FlightFeature {
            plan: &flat_plan,
            ..f
        };
        let flat = write_flights(&[f], air.flat(), UtcOffset::SINGAPORE);
        assert!(
            !flat.contains("layers") && flat.contains("[103.8,1.3,0,0.0]"),
            "{flat}"
        );
    }
}
