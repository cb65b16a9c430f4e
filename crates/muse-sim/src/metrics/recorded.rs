//! What a `summary.json` records of the world a run was planned on, and reading a summary's
//! world and parameters back: `muse verify` and `muse view` take them from the summary beside
//! the plans, so that a day is checked with the parameters it was made with.
//!
//! A summary written before the `world` member existed is read too: its parameters are used,
//! and it records no world ([`Recorded::world`] is `None`).

use serde::{Deserialize, Serialize};

use muse_formats::params::ParamsRecord;

/// The world a run was planned on, as a summary records it (`world`): where the airspace came
/// from and which zone files were read. Exactly one of `scenario`, `airspace` and `synthetic`
/// is set.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldRecord {
    /// The built-in scenario (`singapore-77`, `singapore-all`), when the airspace is one.
    pub scenario: Option<String>,
    /// The airspace file, as an absolute path, when the airspace is read from one.
    pub airspace: Option<String>,
    /// The synthetic airspace, when the airspace is one.
    pub synthetic: Option<SyntheticRecord>,
    /// The zone files read, as absolute paths, in order: empty for no zones (`--zones none`);
    /// `None` for the airspace's own zones (a built-in scenario's; none for a file or a
    /// synthetic airspace).
    pub zones: Option<Vec<String>>,
    /// The layering (docs/reference.md#layered-airspace), when there is more than one layer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<LayersRecord>,
}

/// A layered airspace, as a summary records it (docs/reference.md#layered-airspace).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayersRecord {
    /// Number of cruise layers.
    pub count: u32,
    /// Altitude of layer 1, metres.
    pub base_altitude_m: f64,
    /// Spacing between layers, metres.
    pub spacing_m: f64,
    /// Vertical speed, metres per second.
    pub climb_mps: f64,
    /// Time to cross one vertical link, ms.
    pub climb_ms: i64,
    /// `none` or `sectors`.
    pub heading_rule: String,
}

impl LayersRecord {
    /// The record of `layers`.
    pub fn of(layers: &muse_model::Layers) -> Self {
        LayersRecord {
            count: layers.count,
            base_altitude_m: layers.base.m(),
            spacing_m: layers.spacing.m(),
            climb_mps: f64::from(layers.climb_mm_per_s) / 1e3,
            climb_ms: layers.climb_time().0,
            heading_rule: layers.heading_rule.name().to_owned(),
        }
    }
}

/// A synthetic airspace, as a summary records it: what `--synthetic` and its options say.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyntheticRecord {
    /// `grid` or `geometric`.
    pub layout: String,
    /// Number of nodes.
    pub nodes: usize,
    /// Grid spacing, or mean nearest-neighbour distance, metres.
    pub spacing_m: f64,
    /// The fraction of nodes that are stations.
    pub station_share: f64,
    /// Seed of the points and of the choice of stations.
    pub seed: u64,
}

/// The world and parameters read back from a summary.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct Recorded {
    /// The flight parameters.
    pub parameters: ParamsRecord,
    /// The world; `None` in a summary written before summaries recorded it.
    #[serde(default)]
    pub world: Option<WorldRecord>,
}

/// Reads the world and parameters of a summary's text; the error names `file`, the line and
/// the member (`parameters.speed_kmh`, say). Other members of the summary are not read.
///
/// ```
/// use muse_sim::metrics::recorded::read_recorded;
/// let text = r#"{"requests": 1, "parameters": {"speed_kmh": 40.0, "max_flight_min": 20.0,
///   "node_separation_s": 5.0, "edge_rule": "exclusive", "headway_s": null,
///   "max_ground_delay_s": 0.0, "battery_swap_s": 300.0}}"#;
/// let r = read_recorded(text, "summary.json").unwrap();
/// assert_eq!((r.parameters.speed_kmh, r.parameters.battery_swap_s), (40.0, Some(300.0)));
/// assert!(r.world.is_none(), "an older summary: no world recorded");
/// let e = read_recorded(&text.replace("40.0", "\"fast\""), "s.json").unwrap_err();
/// assert!(e.starts_with("s.json: line 1: field `parameters.speed_kmh`: "), "{e}");
/// ```
pub fn read_recorded(text: &str, file: &str) -> Result<Recorded, String> {
    let mut de = serde_json::Deserializer::from_str(text);
    let read: Result<Recorded, _> = serde_path_to_error::deserialize(&mut de);
    read.map_err(|e| {
        let field = e.path().to_string();
        let inner = e.into_inner();
        let line = inner.line();
        // serde_json's message ends with its own " at line L column C": the line is given first.
        let message = inner.to_string();
        let message = message
            .rsplit_once(" at line ")
            .map_or(message.as_str(), |(m, _)| m)
            .to_owned();
        if field == "." {
            format!("{file}: line {line}: not a MUSE summary: {message}")
        } else {
            format!("{file}: line {line}: field `{field}`: {message}")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{Provenance, Summary};
    use muse_model::{BatterySwap, EdgeRule, FlightParams, Millis};
    use std::time::Duration;

    #[test]
    fn a_summary_reads_back_its_world_and_parameters() {
        let params = FlightParams {
            edge_rule: EdgeRule::Headway(Millis::from_secs(3)),
            battery_swap: Some(BatterySwap {
                time: Millis::from_secs(300),
                max_legs: Some(3),
            }),
            max_trip: Some(Millis::from_mins(60)),
            ..FlightParams::default()
        };
        let world = WorldRecord {
            scenario: None,
            airspace: None,
            synthetic: Some(SyntheticRecord {
                layout: "grid".into(),
                nodes: 100,
                spacing_m: 1_500.0,
                station_share: 0.1,
                seed: 7,
            }),
            zones: Some(vec!["/data/zones.geojson".into()]),
            layers: None,
        };
        let s = Summary::compute([], &params, Duration::ZERO, Provenance::default())
            .with_world(world.clone());
        let r = read_recorded(&s.to_json(), "summary.json").unwrap();
        assert_eq!(r.parameters, s.parameters);
        assert_eq!(r.world, Some(world));
    }

    #[test]
    fn errors_name_the_file_line_and_member() {
        let s = Summary::compute(
            [],
            &FlightParams::default(),
            Duration::ZERO,
            Provenance::default(),
        )
        .with_world(WorldRecord::default());
        let text = s.to_json();
        for (from, to, needle) in [
            (
                "\"edge_rule\": \"exclusive\"",
                "\"edge_rule\": 3",
                "field `parameters.edge_rule`: invalid type: integer `3`, expected a string",
            ),
            (
                "\"scenario\": null",
                "\"scenario\": null, \"planet\": \"mars\"",
                "field `world.planet`: unknown field `planet`",
            ),
            ("\"parameters\"", "\"params\"", "missing field `parameters`"),
        ] {
            let e = read_recorded(&text.replace(from, to), "out/summary.json").unwrap_err();
            assert!(
                e.starts_with("out/summary.json: line ") && e.contains(needle),
                "{e}"
            );
        }
        let e = read_recorded("[1, 2]", "s.json").unwrap_err();
        assert!(e.starts_with("s.json: line 1: "), "{e}");
    }
}
