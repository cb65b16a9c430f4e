//! `--vary layers`: the airspace flown at each number of cruise layers of `--layer-counts`
//! (docs/reference.md#layered-airspace), the layers' other values the defaults (60 m, 9.144 m
//! apart, 5 m/s).

use muse_model::Layers;

use super::lever::{Base, Lever, LeverError, Setting, list};
use crate::experiment::sweep::variant::Variant;

/// One variant per number of layers.
pub struct LayerCounts;

impl Lever for LayerCounts {
    fn name(&self) -> &'static str {
        "layers"
    }

    fn help(&self) -> &'static str {
        "The airspace flown at each number of cruise layers of --layer-counts (docs/reference.md#layered-airspace)"
    }

    fn setting(&self) -> Option<Setting> {
        Some(Setting {
            name: "layer-counts",
            value_name: "L,...",
            help: "With --vary layers: the numbers of layers compared, each a whole number from \
                   1 to 64 (default 1,2,4,8)",
            default: "1,2,4,8",
        })
    }

    fn apply(
        &self,
        _: &Base<'_>,
        current: &Variant,
        value: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let counts = list(
            "--layer-counts",
            value,
            &format!("whole numbers of layers, each from 1 to {}", Layers::MAX_COUNT),
            |t| {
                t.parse::<u32>()
                    .ok()
                    .filter(|n| (1..=Layers::MAX_COUNT).contains(n))
            },
        )?;
        Ok(counts
            .into_iter()
            .map(|count| {
                let label = if count == 1 {
                    "1 layer".to_owned()
                } else {
                    format!("{count} layers")
                };
                let layers = Layers {
                    count,
                    ..current.layers
                };
                (
                    label,
                    Variant {
                        layers,
                        ..current.clone()
                    },
                )
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::day::Planning;
    use muse_model::FlightParams;

    #[test]
    fn one_variant_per_count_and_bad_counts_are_named() {
        let base = Base {
            params: FlightParams::default(),
            zones: &[],
            zone_label: "no zone",
        };
        let current = Variant {
            name: String::new(),
            zones: Vec::new(),
            params: FlightParams::default(),
            planning: Planning::FirstComeFirstServed,
            layers: Layers::default(),
        };
        let got = LayerCounts.apply(&base, &current, "1, 4").unwrap();
        let names: Vec<&str> = got.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["1 layer", "4 layers"]);
        assert_eq!(got[1].1.layers.count, 4);
        for bad in ["0", "65", "2,,4", "x"] {
            let e = LayerCounts.apply(&base, &current, bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--layer-counts `{bad}`")), "{e}");
        }
    }
}
